//! One bifurcation followed in a plane of two parameters ([`curve`], see
//! [`solver::curve`]), the file it writes and the JSON object of
//! `curve --json` ([`FollowedCurve::to_json`]).

use crate::error::{Error, Result};
use crate::error::{Opt, RequestError};
use crate::sim::{check_period, labels_of, unknown, Setup, Sim, Start};
use scene::Named;
use serde::Serialize;
use serde_json::Value;
use solver::curve::{Curve, CurvePoint, Tracing};
use solver::Bifurcation;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A curve to follow.
#[derive(Debug, Clone)]
pub struct CurveRequest {
    /// The simulation options.
    pub sim: Sim,
    /// The bifurcation.
    pub kind: Bifurcation,
    /// The free parameters: A is located, B is stepped.
    pub free: [String; 2],
    /// Where to start: values of A and B (`--start`), in any order.
    pub start: Vec<(String, f64)>,
    /// The value of B to go to; `None`: both ways, within the scene's range
    /// of B, until the curve ends.
    pub to: Option<f64>,
    /// Steps in B.
    pub steps: usize,
    /// Half-width of the window in A searched for the bifurcation.
    pub window: f64,
    /// Bounds of A (default: the scene's range of A).
    pub bounds: Option<[f64; 2]>,
    /// The orbit's period in forcing periods (found from the start when `None`).
    pub n: Option<usize>,
    /// The state (x of every mass, then v) that the first cell, at the
    /// start's parameters, is simulated from (`--state`), where orbits
    /// coexist: the curve of the orbit it reaches; `None`: the scene's
    /// initial state.
    pub state: Option<Vec<f64>>,
    /// The curve file to write, if any.
    pub output: Option<PathBuf>,
    /// What made the curve (the file's `command` attribute).
    pub command: String,
}

/// Steps in B of a curve when the caller names none (`--steps`).
pub const DEFAULT_STEPS: usize = 20;
/// Half-width of the window in A searched for the bifurcation when the
/// caller names none (`--window`).
pub const DEFAULT_WINDOW: f64 = 0.05;

impl CurveRequest {
    /// The curve of `kind` in the free parameters `free` (A located, B
    /// stepped) from `start`, both ways in the scene's range of B, every
    /// other option at its default: [`DEFAULT_STEPS`] steps, a window of
    /// [`DEFAULT_WINDOW`], A within the scene's range, the period found from
    /// the start, no output.
    pub fn new(sim: Sim, kind: Bifurcation, free: [String; 2], start: Vec<(String, f64)>) -> CurveRequest {
        CurveRequest {
            sim,
            kind,
            free,
            start,
            to: None,
            steps: DEFAULT_STEPS,
            window: DEFAULT_WINDOW,
            bounds: None,
            n: None,
            state: None,
            output: None,
            command: String::new(),
        }
    }
}

/// A followed curve.
#[derive(Debug, Clone)]
pub struct FollowedCurve {
    /// The free parameters.
    pub free: [String; 2],
    /// The curve.
    pub curve: Curve,
    /// Why it ended.
    pub ended: String,
    /// The labels either side of every point.
    pub sides: Vec<Sides>,
}

/// Follows a curve (and writes its file when asked, unless `observer` asked
/// to stop meanwhile: a curve's steps cannot be interrupted, its file can).
pub fn curve(r: &CurveRequest, observer: &dyn crate::Observer) -> Result<FollowedCurve> {
    let s = r.sim.setup()?;
    check_period(r.n)?;
    // Where it goes, before any work (not over its scene).
    if let Some(out) = &r.output {
        store::check_output(out, &r.sim.inputs(&Start::Initial))?;
    }
    let [pa, pb] = &r.free;
    let refuse = RequestError::option;
    if pa == pb {
        return Err(refuse(Opt::Free).text(format!("expected two different parameters, got '{pa}' twice")).into());
    }
    for p in [pa, pb] {
        s.scene.check_parameter(p, "").map_err(|e| unknown(refuse(Opt::Free), e))?;
    }
    r.sim.refuse_set_of(&[pa, pb], "a free parameter of the curve")?;
    if let Some((other, _)) = r.start.iter().find(|(n, _)| n != pa && n != pb) {
        let why = format!("gives the free parameters {pa} and {pb} only, got {other} (fix others with ");
        return Err(refuse(Opt::Start).text(why).opt(Opt::Set).text(")").into());
    }
    let value = |name: &str| {
        let missing = || refuse(Opt::Start).text(format!("give {name}=VALUE"));
        r.start.iter().find(|(n, _)| n == name).map(|x| x.1).ok_or_else(missing)
    };
    let (a0, b0) = (value(pa)?, value(pb)?);
    if r.steps == 0 || r.steps > 10_000 {
        return Err(refuse(Opt::Steps).text(format!("expected 1 to 10000, got {}", r.steps)).into());
    }
    if !(r.window > 0.0 && r.window.is_finite()) {
        return Err(refuse(Opt::Window).text(format!("expected a finite number > 0, got {}", r.window)).into());
    }
    if let Some(to) = r.to.filter(|to| !to.is_finite()) {
        return Err(refuse(Opt::To).text(format!("expected a finite number, got {to}")).into());
    }
    // The start and the end in B must make valid scenes (ranges of the parameters).
    let at_start = s.system_with(&[(pa.as_str(), a0), (pb.as_str(), b0)]).map_err(|e| refuse(Opt::Start).because(e))?;
    // A given state fits the scene at the start (a stop's gap there).
    let state = r.state.as_deref().map(|x| crate::sim::given_state(&at_start.model, x)).transpose()?;
    if let Some(to) = r.to {
        s.system_with(&[(pa.as_str(), a0), (pb.as_str(), to)]).map_err(|e| refuse(Opt::To).because(e))?;
    }
    let range = |name: &str| s.scene.range(name).unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
    let a_bounds = r.bounds.unwrap_or_else(|| range(pa));
    if a0 < a_bounds[0] || a0 > a_bounds[1] {
        let why = format!("the start {pa} = {a0} is outside {}:{}", a_bounds[0], a_bounds[1]);
        return Err(refuse(Opt::Bounds).text(why).into());
    }
    let (b_bounds, step) = match r.to {
        Some(to) => ([b0.min(to), b0.max(to)], (to - b0).abs() / r.steps as f64),
        None => (range(pb), r.window),
    };
    let tracing = Tracing {
        kind: r.kind,
        acc: s.accuracy,
        n: r.n,
        scale: [r.window, if step > 0.0 { step } else { r.window }],
        bounds: [a_bounds, b_bounds],
        max_points: 10 * r.steps + 1,
    };
    let plane = |va: f64, vb: f64| s.system_with(&[(pa.as_str(), va), (pb.as_str(), vb)]).ok();
    let from = state.as_ref().map_or(solver::curve::Start::Fresh, |o| solver::curve::Start::State(&o.state));
    let curve = match tracing.locate(&plane, a0, b0, from) {
        Ok(first) => follow(&tracing, &plane, first, r.to.map_or(b_bounds, |to| [to, to]), pb),
        Err(why) => Curve {
            kind: r.kind,
            points: Vec::new(),
            codim2: Vec::new(),
            ended: Some(format!("at {pb} = {b0}: {why}")),
        },
    };
    let ended = curve.ended.clone().unwrap_or_default();
    if observer.cancelled() {
        return Err(crate::Error::Cancelled);
    }
    if let Some(out) = &r.output {
        let stored = stored(&curve, [pa, pb], &ended);
        store::write_curves(out, std::slice::from_ref(&stored), &r.command, s.scene.source())?;
    }
    let sides = curve.points.iter().map(|p| sides_of(&tracing, &plane, p)).collect();
    Ok(FollowedCurve { free: r.free.clone(), curve, ended, sides })
}

/// Follows the curve through `first` to B = `ends[1]`, and from there back
/// to `ends[0]` too where they differ (one curve, in order of B); each way
/// that reaches its end says so in `ended`.
fn follow(tracing: &Tracing, plane: &solver::curve::Plane2, first: CurvePoint, ends: [f64; 2], pb: &str) -> Curve {
    let way = |first: CurvePoint, to: f64| {
        let mut c = tracing.follow(plane, first, to);
        c.ended.get_or_insert_with(|| format!("reached {pb} = {to}"));
        c
    };
    if ends[0] == ends[1] {
        return way(first, ends[1]);
    }
    let back = way(first.clone(), ends[0]);
    Curve::join(back, way(first, ends[1]))
}

/// The JSON of a followed curve (the contract of `curve --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveReport {
    /// The bifurcation's kind (`pd`, `sn`, `pf`, `ns`, `grazing`).
    pub kind: &'static str,
    /// The two free parameters.
    pub free: [String; 2],
    /// The points, in order, with the labels either side.
    pub points: Vec<CurveReportPoint>,
    /// The codimension-two points met.
    pub codim2: Vec<Codim2>,
    /// Why the curve ended.
    pub ended: String,
}

/// A point of a curve: its two parameters by name and the labels either side.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveReportPoint {
    /// The free parameters' values by name.
    #[serde(flatten)]
    pub at: BTreeMap<String, f64>,
    /// The labels either side: of the cells simulated from the scene's
    /// initial state a quarter window below and above in A (where orbits
    /// coexist, not necessarily the curve's orbit).
    pub labels: Sides,
}

/// A codimension-two point of a curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Codim2 {
    /// Its kind.
    pub kind: String,
    /// The free parameters' values by name.
    #[serde(flatten)]
    pub at: BTreeMap<String, f64>,
}

impl Codim2 {
    /// A point of kind `kind` at `a`, `b` of the free parameters `free`.
    fn at(kind: &str, free: &[String; 2], a: f64, b: f64) -> Codim2 {
        Codim2 { kind: kind.to_string(), at: BTreeMap::from([(free[0].clone(), a), (free[1].clone(), b)]) }
    }
}

/// The motions either side of a curve point (`None` where none was found).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sides {
    /// Below the curve.
    pub below: Option<SideMotion>,
    /// Above it.
    pub above: Option<SideMotion>,
}

/// The motion on one side of a curve: its labels by mass and its symmetry.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SideMotion {
    /// Per labelled mass, its label.
    #[serde(flatten)]
    pub labels: BTreeMap<String, String>,
    /// The symmetry of the orbit, when the scene is symmetric.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetry: Option<&'static str>,
}

impl FollowedCurve {
    /// The curve as its report ([`CurveReport`]).
    pub fn report(&self) -> CurveReport {
        let [pa, pb] = &self.free;
        let at = |a: f64, b: f64| BTreeMap::from([(pa.clone(), a), (pb.clone(), b)]);
        let points = self
            .curve
            .points
            .iter()
            .zip(&self.sides)
            .map(|(p, l)| CurveReportPoint { at: at(p.a, p.b), labels: l.clone() })
            .collect();
        let codim2 = self.curve.codim2.iter().map(|c| Codim2::at(&c.kind, &self.free, c.a, c.b)).collect();
        CurveReport { kind: self.curve.kind.name(), free: self.free.clone(), points, codim2, ended: self.ended.clone() }
    }

    /// The JSON object of the curve (the contract of `curve --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// The labels either side of a curve point.
fn sides_of(tracing: &Tracing, plane: &solver::curve::Plane2, p: &CurvePoint) -> Sides {
    let one = |side: Option<(Vec<solver::MassLabel>, Option<solver::Symmetry>)>| {
        side.map(|(labels, symmetry)| SideMotion { labels: labels_of(&labels), symmetry: symmetry.map(|s| s.name()) })
    };
    let sides = tracing.sides(plane, p);
    Sides { below: one(sides.below), above: one(sides.above) }
}

/// A curve as stored in files.
pub fn stored(c: &Curve, free: [&str; 2], ended: &str) -> store::Curve {
    store::Curve {
        kind: c.kind.name().to_string(),
        free: free.map(str::to_string),
        points: c.points.iter().map(|p| (p.a, p.b)).collect(),
        codim2: c.codim2.iter().map(|x| (x.kind.clone(), x.a, x.b)).collect(),
        ended: ended.to_string(),
    }
}

/// The simulation set-up a stored atlas was computed with.
pub fn stored_setup(m: &grid::Meta, file: &std::path::Path) -> Result<Setup> {
    let scene = store::scene_of_run(file, m)?;
    let preset = m.preset;
    let mut accuracy = solver::Accuracy::preset(preset);
    for &(k, v) in &m.accuracy {
        accuracy.set(k, v)?;
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

/// Curves seeded from a stored atlas (`curves`): where to find them and
/// where to put them.
#[derive(Debug, Clone)]
pub struct CurvesRequest {
    /// The atlas file.
    pub file: PathBuf,
    /// The kinds of bifurcation to follow.
    pub kinds: Vec<Bifurcation>,
    /// The sweeps whose maps seed them (the file's all when `None`).
    pub sweep: Option<grid::SweepKind>,
    /// The most curves.
    pub max: usize,
    /// A curve file to write, if any.
    pub output: Option<PathBuf>,
    /// Store the curves in the atlas file itself.
    pub into: bool,
    /// Worker threads.
    pub threads: usize,
    /// What made the curves (the files' `command` attribute).
    pub command: String,
}

/// The curves found from an atlas.
#[derive(Debug, Clone)]
pub struct MapCurves {
    /// The curves, as stored.
    pub curves: Vec<store::Curve>,
    /// Seeds tried.
    pub seeds: usize,
    /// Seconds the search took.
    pub secs: f64,
}

/// Finds the curves of a stored atlas's maps and writes them where asked;
/// `report` hears how many seeds are done (from the worker threads).
pub fn curves(r: &CurvesRequest, report: &(dyn Fn(grid::curves::Tally) + Sync)) -> Result<MapCurves> {
    let clock = std::time::Instant::now();
    if r.output.is_none() && !r.into {
        let refusal = RequestError::option(Opt::Output).text("give the curve file to write, or ").opt(Opt::Into);
        return Err(refusal.text(" to store the curves in the atlas").into());
    }
    if r.max == 0 || r.max > 100_000 {
        return Err(RequestError::option(Opt::Max).text(format!("expected 1 to 100000 curves, got {}", r.max)).into());
    }
    if let Some(out) = &r.output {
        store::check_output(out, &[&r.file])?;
    }
    let loaded = store::read(&r.file)?;
    // Before the search: an atlas that cannot be rewritten is refused now.
    if r.into {
        store::check_writable(&r.file)?;
    }
    let atlas = &loaded.atlas;
    let m = &atlas.meta;
    let sweeps = r.sweep.map_or_else(|| m.sweeps.clone(), |s| vec![s]);
    if let Some(missing) = sweeps.iter().find(|s| atlas.map(**s).is_none()) {
        return Err(RequestError::option(Opt::Sweep).text(format!("the file has no {} sweep", missing.name())).into());
    }
    let setup = stored_setup(m, &r.file)?.cell_setup(0)?;
    let seeding = grid::curves::Seeding { kinds: r.kinds.clone(), sweeps, max: r.max, threads: r.threads };
    if m.plane.x.count < 2 {
        return Err(Error::file(&r.file, "curves need at least two columns", None));
    }
    let found = grid::curves::find(&setup, atlas, &seeding, report)?;
    let (x, y) = (&m.plane.x.name, &m.plane.y.name);
    let curves: Vec<store::Curve> = found
        .curves
        .iter()
        .map(|c| stored(c, [x, y], c.ended.as_deref().unwrap_or("reached the plane's edges")))
        .collect();
    if let Some(out) = &r.output {
        store::write_curves(out, &curves, &r.command, &m.scene_toml)?;
    }
    if r.into {
        store::add_curves(&r.file, &curves, &r.command)?;
    }
    Ok(MapCurves { curves, seeds: found.seeds, secs: clock.elapsed().as_secs_f64() })
}

/// The JSON of the curves seeded from an atlas (the contract of `curves --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurvesReport {
    /// Each curve kept, in order.
    pub curves: Vec<CurveSummary>,
    /// Seeds traced.
    pub seeds: usize,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// A curve kept: its kind, its size and why it ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveSummary {
    /// Its kind.
    pub kind: String,
    /// Its points.
    pub points: usize,
    /// How many codimension-two points it met.
    pub codim2: usize,
    /// Those points, each typed and placed by the free parameters' names
    /// (as [`CurveReport::codim2`]).
    pub codim2_points: Vec<Codim2>,
    /// Why it ended.
    pub ended: String,
}

impl MapCurves {
    /// The curves as their report ([`CurvesReport`]).
    pub fn report(&self) -> CurvesReport {
        let curves = self
            .curves
            .iter()
            .map(|c| CurveSummary {
                kind: c.kind.clone(),
                points: c.points.len(),
                codim2: c.codim2.len(),
                codim2_points: c.codim2.iter().map(|(kind, a, b)| Codim2::at(kind, &c.free, *a, *b)).collect(),
                ended: c.ended.clone(),
            })
            .collect();
        CurvesReport { curves, seeds: self.seeds, seconds: self.secs }
    }

    /// The JSON object of the curves (the contract of `curves --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}
