//! `vibroatlas curve` (one bifurcation followed in a plane of two parameters,
//! [`solver::curve`]) and `vibroatlas curves` (curves seeded from a stored
//! map, [`grid::curves`]): parsing, and the JSON, text and files they write.

use crate::args::{CurveArgs, CurvesArgs, KindArg};
use crate::common::{check_period, labels_json, parse_assignment, setup, system_with, Setup};
use crate::out::outln;
use anyhow::{anyhow, bail, Result};
use serde_json::{json, Value};
use solver::curve::{Curve, CurvePoint, Tracing};
use solver::Bifurcation;

/// Runs `curve`.
pub fn run(a: CurveArgs) -> Result<()> {
    let s = setup(&a.sim)?;
    check_period(a.n)?;
    let kind = solver_kind(a.kind);
    let names: Vec<&str> = a.free.split(',').map(str::trim).collect();
    let [pa, pb] = names[..] else { bail!("--free: expected A,B (two parameters), got '{}'", a.free) };
    if pa == pb {
        bail!("--free: expected two different parameters, got '{}' twice", pa);
    }
    let (pa, pb) = (pa.to_string(), pb.to_string());
    for p in [&pa, &pb] {
        s.scene.check_parameter(p, "--free")?;
    }
    let start = a.start.split(',').map(|t| parse_assignment(t, "--start")).collect::<Result<Vec<_>>>()?;
    if let Some((other, _)) = start.iter().find(|(n, _)| *n != pa && *n != pb) {
        bail!("--start: gives the free parameters {pa} and {pb} only, got {other} (fix others with --set)");
    }
    let value = |name: &str| {
        start.iter().find(|(n, _)| n == name).map(|x| x.1).ok_or_else(|| anyhow!("--start: give {name}=VALUE"))
    };
    let (a0, b0) = (value(&pa)?, value(&pb)?);
    if a.steps == 0 || a.steps > 10_000 {
        bail!("--steps: expected 1 to 10000, got {}", a.steps);
    }
    if !(a.window > 0.0 && a.window.is_finite()) {
        bail!("--window: expected a finite number > 0, got {}", a.window);
    }
    if !a.to.is_finite() {
        bail!("--to: expected a finite number, got {}", a.to);
    }
    // The start and the end in B must make valid scenes (ranges of the parameters).
    system_with(&s, &[(pa.as_str(), a0), (pb.as_str(), b0)]).map_err(|e| anyhow!("--start: {e}"))?;
    system_with(&s, &[(pa.as_str(), a0), (pb.as_str(), a.to)]).map_err(|e| anyhow!("--to: {e}"))?;
    let a_bounds = match &a.bounds {
        Some(text) => parse_range(text, &pa)?,
        None => [f64::NEG_INFINITY, f64::INFINITY],
    };
    if a0 < a_bounds[0] || a0 > a_bounds[1] {
        bail!("--bounds: the start {pa} = {a0} is outside {}:{}", a_bounds[0], a_bounds[1]);
    }
    let step = (a.to - b0).abs() / a.steps as f64;
    let tracing = Tracing {
        kind,
        acc: s.accuracy,
        n: a.n,
        scale: [a.window, if step > 0.0 { step } else { a.window }],
        bounds: [a_bounds, [b0.min(a.to), b0.max(a.to)]],
        max_points: 10 * a.steps + 1,
    };
    let plane = |va: f64, vb: f64| system_with(&s, &[(pa.as_str(), va), (pb.as_str(), vb)]).ok();
    let curve = match tracing.locate(&plane, a0, b0, solver::curve::Start::Fresh) {
        Ok(first) => tracing.follow(&plane, first, a.to),
        Err(why) => {
            Curve { kind, points: Vec::new(), codim2: Vec::new(), ended: Some(format!("at {pb} = {b0}: {why}")) }
        }
    };
    let ended = curve.ended.clone().unwrap_or_else(|| format!("reached {pb} = {}", a.to));
    let stored = stored(&curve, [&pa, &pb], &ended);
    if let Some(out) = &a.output {
        store::check_output(out, &[&a.sim.scene], false)?;
        store::write_curves(out, std::slice::from_ref(&stored), &crate::plan::command_line(), s.scene.source())?;
    }
    let sides: Vec<Value> = curve.points.iter().map(|p| sides_json(&tracing, &plane, p)).collect();
    if a.json {
        let points: Vec<Value> = curve
            .points
            .iter()
            .zip(&sides)
            .map(|(p, l)| json!({pa.clone(): p.a, pb.clone(): p.b, "labels": l}))
            .collect();
        let codim2: Vec<Value> =
            curve.codim2.iter().map(|c| json!({"kind": c.kind, pa.clone(): c.a, pb.clone(): c.b})).collect();
        let out = json!({"kind": kind.name(), "free": [pa, pb], "points": points, "codim2": codim2, "ended": ended});
        outln!("{}", serde_json::to_string(&out)?);
    } else {
        outln!("{} curve in ({pa}, {pb}): {} points", kind.name(), curve.points.len());
        for (p, l) in curve.points.iter().zip(&sides) {
            outln!("  {pa} = {:.9}  {pb} = {:.9}  {l}", p.a, p.b);
        }
        for c in &curve.codim2 {
            outln!("codim-2   {} at {pa} = {:.9}, {pb} = {:.9}", c.kind, c.a, c.b);
        }
        outln!("ended: {ended}");
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

/// The labels either side of a curve point, as `{"below": {...}, "above": {...}}`.
fn sides_json(tracing: &Tracing, plane: &solver::curve::Plane2, p: &CurvePoint) -> Value {
    let one = |side: Option<(Vec<solver::MassLabel>, Option<solver::Symmetry>)>| match side {
        None => Value::Null,
        Some((labels, symmetry)) => {
            let mut l = labels_json(&labels);
            if let Some(sym) = symmetry {
                l["symmetry"] = sym.name().into();
            }
            l
        }
    };
    let sides = tracing.sides(plane, p);
    json!({"below": one(sides.below), "above": one(sides.above)})
}

/// A curve as stored in files.
fn stored(c: &Curve, free: [&str; 2], ended: &str) -> store::Curve {
    store::Curve {
        kind: c.kind.name().to_string(),
        free: free.map(str::to_string),
        points: c.points.iter().map(|p| (p.a, p.b)).collect(),
        codim2: c.codim2.iter().map(|x| (x.kind.clone(), x.a, x.b)).collect(),
        ended: ended.to_string(),
    }
}

/// The bifurcation of `kind` as a solver kind.
fn solver_kind(kind: KindArg) -> Bifurcation {
    match kind {
        KindArg::Pd => Bifurcation::PeriodDoubling,
        KindArg::Sn => Bifurcation::SaddleNode,
        KindArg::Pf => Bifurcation::Pitchfork,
        KindArg::Ns => Bifurcation::NeimarkSacker,
        KindArg::Grazing => Bifurcation::Grazing,
    }
}

/// Runs `curves`.
pub fn run_curves(a: CurvesArgs) -> Result<()> {
    let clock = std::time::Instant::now();
    if a.output.is_none() && !a.into {
        bail!("-o: give the curve file to write, or --into to store the curves in the atlas");
    }
    if a.max == 0 || a.max > 100_000 {
        bail!("--max: expected 1 to 100000 curves, got {}", a.max);
    }
    if let Some(out) = &a.output {
        store::check_output(out, &[&a.file], false)?;
    }
    let loaded = store::read(&a.file)?;
    // Before the search: an atlas that cannot be rewritten is refused now.
    if a.into {
        store::check_writable(&a.file)?;
    }
    let atlas = &loaded.atlas;
    let m = &atlas.meta;
    let sweeps = match a.sweep {
        Some(s) => vec![s.kind()],
        None => m.sweeps.clone(),
    };
    if let Some(missing) = sweeps.iter().find(|s| atlas.map(**s).is_none()) {
        bail!("--sweep: the file has no {} sweep", missing.name());
    }
    let s = stored_setup(m, &a.file)?;
    let setup = crate::common::cell_setup(&s, 0)?;
    let seeding = grid::curves::Seeding {
        kinds: a.kinds.iter().map(|&k| solver_kind(k)).collect(),
        sweeps,
        max: a.max,
        threads: crate::plan::threads(a.threads)?,
    };
    if m.plane.x.count < 2 {
        bail!("{}: curves need at least two columns", a.file.display());
    }
    // Progress on standard error only (a bar or `progress:` lines), never in --json's stdout.
    let bar = std::sync::OnceLock::new();
    let report = |t: grid::curves::Tally| bar.get_or_init(|| crate::progress::Seeds::new(t.total)).report(t);
    let found = grid::curves::find(&setup, atlas, &seeding, &report);
    if let Some(b) = bar.get() {
        b.finish();
    }
    let found = found?;
    let (x, y) = (&m.plane.x.name, &m.plane.y.name);
    let curves: Vec<store::Curve> = found
        .curves
        .iter()
        .map(|c| stored(c, [x, y], c.ended.as_deref().unwrap_or("reached the plane's edges")))
        .collect();
    let command = crate::plan::command_line();
    if let Some(out) = &a.output {
        store::write_curves(out, &curves, &command, &m.scene_toml)?;
    }
    if a.into {
        store::add_curves(&a.file, &curves, &command)?;
    }
    let codim2: usize = curves.iter().map(|c| c.codim2.len()).sum();
    let secs = clock.elapsed().as_secs_f64();
    if a.json {
        let list: Vec<Value> = curves
            .iter()
            .map(|c| json!({"kind": c.kind, "points": c.points.len(), "codim2": c.codim2.len(), "ended": c.ended}))
            .collect();
        outln!("{}", serde_json::to_string(&json!({"curves": list, "seeds": found.seeds, "seconds": secs}))?);
    } else {
        outln!("{} curves ({codim2} codimension-two points) from {} seeds in {secs:.1} s", curves.len(), found.seeds);
        for c in &curves {
            outln!("  {:<8} {:>4} points  {}", c.kind, c.points.len(), c.ended);
        }
        for out in a.output.iter().chain(a.into.then_some(&a.file)) {
            outln!("wrote {}", out.display());
        }
    }
    Ok(())
}

/// The simulation set-up a stored atlas was computed with.
fn stored_setup(m: &grid::Meta, file: &std::path::Path) -> Result<Setup> {
    let scene = scene::Scene::parse(&m.scene_toml).map_err(|e| anyhow!("{}: stored scene: {e}", file.display()))?;
    let preset = solver::Preset::parse(&m.preset).unwrap_or(solver::Preset::Standard);
    let mut accuracy = solver::Accuracy::preset(preset);
    for (k, v) in &m.accuracy {
        accuracy.set(k, *v)?;
    }
    Ok(Setup {
        scene,
        overrides: m.overrides.clone(),
        accuracy,
        accuracy_overrides: m.accuracy.clone(),
        preset,
        method: solver::Method::Exact,
    })
}
