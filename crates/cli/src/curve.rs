//! `vibroatlas curve`: a bifurcation followed in a plane of two parameters A
//! and B. At each value of B (from the start to `--to` in `--steps` steps) the
//! orbit is continued in A across a window around the predicted crossing (the
//! secant of the last two points), and the bifurcation of the requested kind
//! is located to 1e-9 in A by `continue`'s test functions (with exact
//! Jacobians). This is natural continuation in B with relocation in A: it ends
//! where the curve turns back in B (a fold of the curve), leaves the window,
//! or where no orbit is found; it does not solve the extended system by
//! pseudo-arclength. A second bifurcation of another kind located within the
//! tolerance of the curve point is recorded as a codimension-two point.

use crate::args::{CurveArgs, KindArg};
use crate::common::{check_period, labels_json, parse_assignment, setup};
use crate::out::outln;
use anyhow::{anyhow, bail, Result};
use serde_json::{json, Value};
use solver::continuation::{follow, Branch};
use solver::{orbit_of_cell, Bifurcation, System};

/// Points of the continuation in A across the search window: an even number,
/// so that the predicted value (the window's centre) is not a grid point (a
/// bifurcation exactly on a grid point is neutral there, not a crossing).
const WINDOW_POINTS: usize = 40;
/// Two bifurcations closer than this in A form a codimension-two point.
const CODIM2_TOL: f64 = 1e-3;

/// Runs the command.
pub fn run(a: CurveArgs) -> Result<()> {
    let s = setup(&a.sim)?;
    check_period(a.n)?;
    let kind = match a.kind {
        KindArg::Pd => Bifurcation::PeriodDoubling,
        KindArg::Sn => Bifurcation::SaddleNode,
        KindArg::Pf => Bifurcation::Pitchfork,
        KindArg::Ns => Bifurcation::NeimarkSacker,
        KindArg::Grazing => Bifurcation::Grazing,
    };
    let (pa, pb) = a.free.split_once(',').ok_or_else(|| anyhow!("--free: expected A,B, got '{}'", a.free))?;
    let (pa, pb) = (pa.trim().to_string(), pb.trim().to_string());
    for p in [&pa, &pb] {
        s.scene.check_parameter(p, "--free")?;
    }
    let start = a.start.split(',').map(|t| parse_assignment(t, "--start")).collect::<Result<Vec<_>>>()?;
    let value = |name: &str| {
        start.iter().find(|(n, _)| n == name).map(|x| x.1).ok_or_else(|| anyhow!("--start: give {name}=VALUE"))
    };
    let (a0, b0) = (value(&pa)?, value(&pb)?);
    if a.steps == 0 || a.steps > 10_000 {
        bail!("--steps: expected 1 to 10000, got {}", a.steps);
    }
    if !(a.window > 0.0 && a.window.is_finite() && a.to.is_finite()) {
        bail!("--window, --to: expected finite numbers, the window > 0");
    }
    let system = |va: f64, vb: f64| -> Option<System> {
        let mut over = s.overrides.clone();
        over.retain(|(k, _)| *k != pa && *k != pb);
        over.push((pa.clone(), va));
        over.push((pb.clone(), vb));
        System::new(s.scene.evaluate(&over).ok()?).ok()
    };
    let mut points: Vec<(f64, f64, Value)> = Vec::new();
    let mut codim2: Vec<Value> = Vec::new();
    let mut ended = None;
    for k in 0..=a.steps {
        let vb = b0 + (a.to - b0) * k as f64 / a.steps as f64;
        let guess = match points.len() {
            0 => a0,
            1 => points[0].0,
            n => 2.0 * points[n - 1].0 - points[n - 2].0,
        };
        match locate(&s, &system, kind, guess, a.window, vb, a.n) {
            Ok((va, labels, others)) => {
                for other in others.iter().filter(|o| (o.1 - va).abs() <= CODIM2_TOL) {
                    codim2
                        .push(json!({"kind": format!("{}-{}", kind.name(), other.0), pa.clone(): va, pb.clone(): vb}));
                }
                points.push((va, vb, labels));
            }
            Err(why) => {
                ended = Some(format!("at {pb} = {vb}: {why}"));
                break;
            }
        }
    }
    if let Some(out) = &a.output {
        store::check_output(out, &[&a.sim.scene], false)?;
        let curve = store::Curve {
            kind: kind.name().to_string(),
            free: [pa.clone(), pb.clone()],
            points: points.iter().map(|p| (p.0, p.1)).collect(),
            codim2: codim2
                .iter()
                .map(|c| {
                    (
                        c["kind"].as_str().unwrap_or_default().to_string(),
                        c[&pa].as_f64().unwrap_or(f64::NAN),
                        c[&pb].as_f64().unwrap_or(f64::NAN),
                    )
                })
                .collect(),
            ended: ended.clone().unwrap_or_else(|| format!("reached {pb} = {}", a.to)),
        };
        store::write_curve(out, &curve, &crate::plan::command_line(), s.scene.source())?;
    }
    let list: Vec<Value> =
        points.iter().map(|(va, vb, labels)| json!({pa.clone(): va, pb.clone(): vb, "labels": labels})).collect();
    if a.json {
        let out = json!({
            "kind": kind.name(),
            "free": [pa, pb],
            "points": list,
            "codim2": codim2,
            "ended": ended.clone().unwrap_or_else(|| format!("reached {pb} = {}", a.to)),
        });
        outln!("{}", serde_json::to_string(&out)?);
    } else {
        outln!("{} curve in ({pa}, {pb}): {} points", kind.name(), points.len());
        for (va, vb, labels) in &points {
            outln!("  {pa} = {va:.9}  {pb} = {vb:.9}  {labels}");
        }
        for c in &codim2 {
            outln!("codim-2   {c}");
        }
        outln!("ended: {}", ended.unwrap_or_else(|| format!("reached {pb} = {}", a.to)));
    }
    Ok(())
}

/// Locates the bifurcation of `kind` nearest to `guess` in A at B = `vb`:
/// the orbit found at the window's upper end, continued down across it (and,
/// failing that, from the lower end up). Returns A, the labels of fresh cells
/// a quarter of the window below and above it, and the other bifurcations
/// located in the window (kind, A).
#[allow(clippy::type_complexity)]
fn locate(
    s: &crate::common::Setup,
    system: &dyn Fn(f64, f64) -> Option<System>,
    kind: Bifurcation,
    guess: f64,
    window: f64,
    vb: f64,
    n: Option<usize>,
) -> Result<(f64, Value, Vec<(&'static str, f64)>), String> {
    let family = |va: f64| system(va, vb);
    for (from, to) in [(guess + window, guess - window), (guess - window, guess + window)] {
        let Some(sys) = family(from) else { continue };
        let Ok(orbit) = orbit_of_cell(&sys, &s.accuracy, &sys.model.initial_state(), n) else { continue };
        let values: Vec<f64> =
            (0..WINDOW_POINTS).map(|i| from + (to - from) * i as f64 / (WINDOW_POINTS - 1) as f64).collect();
        let branch: Branch = follow(&family, &s.accuracy, &values, orbit);
        let best = branch
            .bifurcations
            .iter()
            .filter(|b| b.kind == kind)
            .min_by(|x, y| (x.value - guess).abs().total_cmp(&(y.value - guess).abs()));
        if let Some(b) = best {
            // The motion a map shows on each side: a fresh cell (from the
            // scene's initial state) a quarter of the window away.
            let side = |offset: f64| -> Value {
                let Some(sys) = family(b.value + offset) else { return Value::Null };
                let cell = solver::run_cell(&sys, &s.accuracy, solver::Method::Exact, &sys.model.initial_state());
                let mut l = labels_json(&cell.labels);
                if let Some(sym) = cell.symmetry {
                    l["symmetry"] = sym.name().into();
                }
                l
            };
            let others =
                branch.bifurcations.iter().filter(|o| o.kind != kind).map(|o| (o.kind.name(), o.value)).collect();
            return Ok((b.value, json!({"below": side(-window / 4.0), "above": side(window / 4.0)}), others));
        }
    }
    Err(format!("no {} within {guess} ± {window}", kind.name()))
}
