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
    let kind = solver_kind(a.kind);
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
    let tracer = Tracer { s: &s, pa: &pa, pb: &pb, window: a.window, n: a.n };
    let traced = tracer.trace(kind, a0, b0, a.to, a.steps);
    let (points, codim2, ended) = (traced.points, traced.codim2, traced.ended);
    if let Some(out) = &a.output {
        store::check_output(out, &[&a.sim.scene], false)?;
        let curve = store::Curve {
            kind: kind.name().to_string(),
            free: [pa.clone(), pb.clone()],
            points: points.iter().map(|p| (p.0, p.1)).collect(),
            codim2: codim2.clone(),
            ended: ended.clone().unwrap_or_else(|| format!("reached {pb} = {}", a.to)),
        };
        store::write_curves(out, &[curve], &crate::plan::command_line(), s.scene.source())?;
    }
    let list: Vec<Value> =
        points.iter().map(|(va, vb, labels)| json!({pa.clone(): va, pb.clone(): vb, "labels": labels})).collect();
    if a.json {
        let out = json!({
            "kind": kind.name(),
            "free": [pa, pb],
            "points": list,
            "codim2": codim2.iter().map(|c| json!({"kind": c.0, pa.clone(): c.1, pb.clone(): c.2})).collect::<Vec<_>>(),
            "ended": ended.clone().unwrap_or_else(|| format!("reached {pb} = {}", a.to)),
        });
        outln!("{}", serde_json::to_string(&out)?);
    } else {
        outln!("{} curve in ({pa}, {pb}): {} points", kind.name(), points.len());
        for (va, vb, labels) in &points {
            outln!("  {pa} = {va:.9}  {pb} = {vb:.9}  {labels}");
        }
        for (k, va, vb) in &codim2 {
            outln!("codim-2   {k} at {pa} = {va:.9}, {pb} = {vb:.9}");
        }
        outln!("ended: {}", ended.unwrap_or_else(|| format!("reached {pb} = {}", a.to)));
    }
    Ok(())
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

/// `vibroatlas curves`: seeds where neighbouring cells of a row carry
/// different periodic labels (first labelled mass), from the top row down,
/// locates a bifurcation of the requested kinds between them (the window is
/// one cell), and follows it row by row up and down to the plane's edges (a
/// window of two cells); a seed within 1.5 cells of a curve already found is
/// skipped (duplicates merged), and a curve of a single point dropped.
/// Deterministic.
pub fn run_curves(a: crate::args::CurvesArgs) -> Result<()> {
    let clock = std::time::Instant::now();
    store::check_output(&a.output, &[&a.file], false)?;
    let loaded = store::read(&a.file)?;
    let atlas = &loaded.atlas;
    let m = &atlas.meta;
    let (x, y) = (&m.plane.x, &m.plane.y);
    if x.count < 2 {
        bail!("{}: curves need at least two columns", a.file.display());
    }
    let sweep = a.sweep.map_or(m.sweeps[0], |s| s.kind());
    let cells = &atlas.map(sweep).ok_or_else(|| anyhow!("--sweep: the file has no {} sweep", sweep.name()))?.cells;
    let scene = scene::Scene::parse(&m.scene_toml).map_err(|e| anyhow!("{}: stored scene: {e}", a.file.display()))?;
    let preset = solver::Preset::parse(&m.preset).unwrap_or(solver::Preset::Standard);
    let mut accuracy = solver::Accuracy::preset(preset);
    for (k, v) in &m.accuracy {
        accuracy.set(k, *v)?;
    }
    let s = crate::common::Setup {
        scene,
        overrides: m.overrides.clone(),
        accuracy,
        accuracy_overrides: m.accuracy.clone(),
        preset,
        method: solver::Method::Exact,
    };
    let dx = (x.stop - x.start) / (x.count - 1) as f64;
    let dy = if y.count > 1 { (y.stop - y.start) / (y.count - 1) as f64 } else { 1.0 };
    // The curve may move more than a cell from one row to the next.
    let tracer = Tracer { s: &s, pa: &x.name, pb: &y.name, window: 2.0 * dx, n: None };
    let periodic = |i: usize| cells[i].as_ref().filter(|c| c.class == solver::Class::Periodic);
    let mut curves: Vec<store::Curve> = Vec::new();
    let mut seeds = 0;
    // From the top row down: the clean boundaries of large clearances first.
    'rows: for iy in (0..y.count).rev() {
        for ix in 0..x.count - 1 {
            let i = iy * x.count + ix;
            let (Some(c1), Some(c2)) = (periodic(i), periodic(i + 1)) else { continue };
            if c1.labels[0] == c2.labels[0] {
                continue;
            }
            let (mid, vb) = (x.value(ix) + dx / 2.0, y.value(iy));
            let near = curves
                .iter()
                .flat_map(|c| &c.points)
                .any(|p| (p.0 - mid).abs() <= 1.5 * dx && (p.1 - vb).abs() <= 1.5 * dy);
            if near {
                continue;
            }
            seeds += 1;
            // The kind located nearest to the boundary.
            let found = a
                .kinds
                .iter()
                .filter_map(|&k| {
                    let kind = solver_kind(k);
                    locate(&s, &|va, vb| tracer.system(va, vb), kind, mid, dx, vb, None).ok().map(|f| (kind, f.0))
                })
                .min_by(|p, q| (p.1 - mid).abs().total_cmp(&(q.1 - mid).abs()));
            let Some((kind, va)) = found else { continue };
            let up = tracer.trace(kind, va, vb, y.stop, y.count - 1 - iy);
            let down = tracer.trace(kind, va, vb, y.start, iy);
            let mut points: Vec<(f64, f64)> = down.points.iter().skip(1).rev().map(|p| (p.0, p.1)).collect();
            points.extend(up.points.iter().map(|p| (p.0, p.1)));
            let mut codim2 = down.codim2.clone();
            codim2.extend(up.codim2.iter().cloned());
            // A curve reached again from another seed is a duplicate.
            let same = |c: &store::Curve| {
                c.kind == kind.name()
                    && points
                        .iter()
                        .filter(|p| c.points.iter().any(|q| (p.0 - q.0).abs() <= 1e-6 && p.1 == q.1))
                        .count()
                        * 2
                        > points.len()
            };
            if points.len() < 2 || curves.iter().any(same) {
                continue;
            }
            let ended = [down.ended, up.ended].into_iter().flatten().collect::<Vec<_>>().join("; ");
            curves.push(store::Curve {
                kind: kind.name().to_string(),
                free: [x.name.clone(), y.name.clone()],
                points,
                codim2,
                ended: if ended.is_empty() { "reached the plane's edges".into() } else { ended },
            });
            if curves.len() >= a.max {
                break 'rows;
            }
        }
    }
    store::write_curves(&a.output, &curves, &crate::plan::command_line(), &m.scene_toml)?;
    let codim2: usize = curves.iter().map(|c| c.codim2.len()).sum();
    let secs = clock.elapsed().as_secs_f64();
    if a.json {
        let list: Vec<Value> = curves
            .iter()
            .map(|c| json!({"kind": c.kind, "points": c.points.len(), "codim2": c.codim2.len(), "ended": c.ended}))
            .collect();
        outln!("{}", serde_json::to_string(&json!({"curves": list, "seeds": seeds, "seconds": secs}))?);
    } else {
        outln!("{} curves ({codim2} codimension-two points) from {seeds} seeds in {secs:.1} s", curves.len());
        for c in &curves {
            outln!("  {:<8} {:>4} points  {}", c.kind, c.points.len(), c.ended);
        }
        outln!("wrote {}", a.output.display());
    }
    Ok(())
}

/// A curve as traced: points `(A, B, labels either side)`, codimension-two
/// points `(kinds, A, B)`, and why it stopped early (`None`: it reached the end).
pub struct Traced {
    /// Points along the curve.
    pub points: Vec<(f64, f64, Value)>,
    /// Codimension-two points.
    pub codim2: Vec<(String, f64, f64)>,
    /// Why the curve stopped before the end.
    pub ended: Option<String>,
}

/// Follows bifurcations in the plane of parameters A (located) and B (stepped).
pub struct Tracer<'a> {
    /// The validated set-up (scene, overrides, accuracy).
    pub s: &'a crate::common::Setup,
    /// Parameter A.
    pub pa: &'a str,
    /// Parameter B.
    pub pb: &'a str,
    /// Half-width of the search in A.
    pub window: f64,
    /// Period of the orbit (default: the cell's).
    pub n: Option<usize>,
}

impl Tracer<'_> {
    /// The system at A = `va`, B = `vb`.
    fn system(&self, va: f64, vb: f64) -> Option<System> {
        crate::common::system_with(self.s, &[(self.pa, va), (self.pb, vb)]).ok()
    }

    /// The curve of `kind` from (a0, b0) to B = `to` in `steps` steps.
    pub fn trace(&self, kind: Bifurcation, a0: f64, b0: f64, to: f64, steps: usize) -> Traced {
        let mut t = Traced { points: Vec::new(), codim2: Vec::new(), ended: None };
        for k in 0..=steps {
            let vb = if steps == 0 { b0 } else { b0 + (to - b0) * k as f64 / steps as f64 };
            let guess = match t.points.len() {
                0 => a0,
                1 => t.points[0].0,
                n => 2.0 * t.points[n - 1].0 - t.points[n - 2].0,
            };
            match locate(self.s, &|va, vb| self.system(va, vb), kind, guess, self.window, vb, self.n) {
                Ok((va, labels, others)) => {
                    for other in others.iter().filter(|o| (o.1 - va).abs() <= CODIM2_TOL) {
                        t.codim2.push((format!("{}-{}", kind.name(), other.0), va, vb));
                    }
                    t.points.push((va, vb, labels));
                }
                Err(why) => {
                    t.ended = Some(format!("at {} = {vb}: {why}", self.pb));
                    break;
                }
            }
        }
        t
    }
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
