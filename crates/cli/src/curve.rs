//! `vibroatlas curve` (one bifurcation followed in a plane of two parameters,
//! [`solver::curve`]) and `vibroatlas curves` (curves seeded from a stored
//! map, [`grid::curves`]): parsing, and the JSON, text and files they write.

use crate::args::{CurveArgs, CurvesArgs};
use crate::common::{command_line, sim};
use crate::common::{parse_assignment, parse_state};
use crate::out::outln;
use anyhow::{anyhow, bail, Result};
use engine::CurveRequest;
use scene::Named;

/// Runs `curve`.
pub fn run(a: CurveArgs) -> Result<()> {
    let names: Vec<&str> = a.free.split(',').map(str::trim).collect();
    let [pa, pb] = names[..] else { bail!("--free: expected A,B (two parameters), got '{}'", a.free) };
    let bounds = match &a.bounds {
        Some(text) => Some(parse_range(text, pa)?),
        None => None,
    };
    let r = CurveRequest {
        sim: sim(&a.sim)?,
        kind: a.kind,
        free: [pa.to_string(), pb.to_string()],
        start: a.start.split(',').map(|t| parse_assignment(t, "--start")).collect::<Result<Vec<_>>>()?,
        to: a.to,
        steps: a.steps,
        window: a.window,
        bounds,
        n: a.n,
        state: a.state.as_deref().map(parse_state).transpose()?,
        output: a.output.clone(),
        command: command_line(),
    };
    let t = engine::curve(&r, &engine::Quiet)?;
    if a.json {
        outln!("{}", serde_json::to_string(&t.to_json())?);
    } else {
        let [pa, pb] = &t.free;
        outln!("{} curve in ({pa}, {pb}): {} points", t.curve.kind.name(), t.curve.points.len());
        for (p, l) in t.curve.points.iter().zip(&t.sides) {
            outln!("  {pa} = {:.9}  {pb} = {:.9}  {}", p.a, p.b, serde_json::to_value(l)?);
        }
        for c in &t.curve.codim2 {
            outln!("codim-2   {} at {pa} = {:.9}, {pb} = {:.9}", c.kind, c.a, c.b);
        }
        outln!("ended: {}", t.ended);
    }
    Ok(())
}

/// `LO:HI` of `--bounds NAME=LO:HI` for parameter `name`.
fn parse_range(text: &str, name: &str) -> Result<[f64; 2]> {
    let bad = || anyhow!("--bounds: expected {name}=LO:HI, got '{text}'");
    let (n, range) = text.split_once('=').ok_or_else(bad)?;
    if n.trim() != name {
        bail!("--bounds: bounds the located parameter {name}, got '{}'", n.trim());
    }
    let (lo, hi) = range.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (lo.trim().parse().map_err(|_| bad())?, hi.trim().parse().map_err(|_| bad())?);
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        bail!("--bounds: expected finite LO < HI, got '{text}'");
    }
    Ok([lo, hi])
}

/// Runs `curves`.
pub fn run_curves(a: CurvesArgs) -> Result<()> {
    let r = engine::CurvesRequest {
        file: a.file.clone(),
        kinds: a.kinds.clone(),
        sweep: a.sweep,
        max: a.max,
        output: a.output.clone(),
        into: a.into,
        threads: engine::threads(a.threads)?,
        command: command_line(),
    };
    // Progress on standard error only (a bar or `progress:` lines), never in --json's stdout.
    let bar = std::sync::OnceLock::new();
    let report = |t: grid::curves::Tally| bar.get_or_init(|| crate::progress::Seeds::new(t.total)).report(t);
    let found = engine::curves(&r, &report);
    if let Some(b) = bar.get() {
        b.finish();
    }
    let found = found?;
    if a.json {
        outln!("{}", serde_json::to_string(&found.to_json())?);
    } else {
        let codim2: usize = found.curves.iter().map(|c| c.codim2.len()).sum();
        let (n, seeds, secs) = (found.curves.len(), found.seeds, found.secs);
        outln!("{n} curves ({codim2} codimension-two points) from {seeds} seeds in {secs:.1} s");
        for c in &found.curves {
            outln!("  {:<8} {:>4} points  {}", c.kind, c.points.len(), c.ended);
        }
        for out in a.output.iter().chain(a.into.then_some(&a.file)) {
            outln!("wrote {}", out.display());
        }
    }
    Ok(())
}
