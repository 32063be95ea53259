//! Continuation along one parameter ([`sweep`]): a plane of one row (the
//! other axis a plain parameter held at its value), so that the file, the
//! renderer and the hysteresis logic are those of the atlas; and the JSON
//! object of `sweep --json` ([`Sweep::to_json`]).

use crate::error::Result;
use crate::error::{grid_error, with_fields, Opt, RequestError};
use crate::plan::Plan;
use crate::record::{labels, CellRecord};
use crate::sim::{Origin, Sim, Source, Start};
use grid::{Along, Atlas, Axis, CellData, Line, Plane, SweepKind};
use grid::{Begin, Observer};
use scene::Named;
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

scene::named_enum! {
    /// The directions of a sweep.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Direction {
        /// Upwards.
        Up = "up",
        /// Downwards.
        Down = "down",
        /// Up and down, each from the scene's initial state.
        Both = "both",
        /// Down, then up from where the down leg ended.
        DownUp = "down-up",
        /// Up, then down from where the up leg ended.
        UpDown = "up-down",
    }
}

/// The legs of a sweep: independent directions (each from the same start), or
/// a hysteresis loop whose second leg starts from the first leg's end state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Legs {
    /// Each sweep from the start.
    Separate,
    /// This sweep first, the other from its end.
    Loop(SweepKind),
}

/// A sweep to run.
#[derive(Debug, Clone)]
pub struct SweepRequest {
    /// The simulation options.
    pub sim: Sim,
    /// Where the first cells start.
    pub start: Start,
    /// The swept parameter (its start and stop give the direction when
    /// `direction` is `None`).
    pub axis: Axis,
    /// The directions.
    pub direction: Option<Direction>,
    /// Section points kept per cell.
    pub section_cap: usize,
    /// Worker threads.
    pub threads: usize,
    /// The file to write, if any.
    pub output: Option<PathBuf>,
    /// What made the run (the file's `command` attribute).
    pub command: String,
    /// The variable its diagram is to show (a state component `x_M1`,
    /// `v_M2`, or a stored quantity's name; [`render::Diagram::of`]), if the
    /// front end draws one: checked before any work.
    pub variable: Option<String>,
}

impl SweepRequest {
    /// A sweep of `axis` from the scene's initial state, in the axis's
    /// direction, every other option at its default: sections of
    /// [`grid::DEFAULT_SECTION_CAP`] points, one thread per core, no output.
    pub fn new(sim: Sim, axis: Axis) -> SweepRequest {
        SweepRequest {
            sim,
            start: Start::Initial,
            axis,
            direction: None,
            section_cap: grid::DEFAULT_SECTION_CAP,
            threads: crate::threads(None).unwrap_or(1),
            output: None,
            command: String::new(),
            variable: None,
        }
    }
}

/// A finished sweep.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The cells, as a plane of one row.
    pub atlas: Atlas,
    /// How the legs were run.
    pub legs: Legs,
    /// The leg computed first (or the one asked for).
    pub first: SweepKind,
    /// The direction asked for.
    pub direction: Option<Direction>,
    /// Where it started, when not from the scene's initial state.
    pub origin: Option<Origin>,
}

/// Runs a sweep (and writes its file when asked).
pub fn sweep(r: &SweepRequest, observer: &dyn Observer) -> Result<Sweep> {
    r.sim.refuse_set_of(&[&r.axis.name], "also an axis of the run")?;
    let (mut s, origin) = r.sim.setup_from(&r.start)?;
    let axis = &r.axis;
    // From a stored cell, the swept parameter is the axis, not the cell's value.
    s.overrides.retain(|(k, _)| *k != axis.name || origin.is_none());
    // Checked as given, before a down sweep reverses it (its message shows START:STOP as written).
    axis.clone().checked("x").map_err(|e| grid_error(e, &[("x", Opt::Axis)]))?;
    let given = if axis.start <= axis.stop { SweepKind::Up } else { SweepKind::Down };
    let (sweeps, legs) = match r.direction {
        None => (vec![given], Legs::Separate),
        Some(Direction::Up) => (vec![SweepKind::Up], Legs::Separate),
        Some(Direction::Down) => (vec![SweepKind::Down], Legs::Separate),
        Some(Direction::Both) => (vec![SweepKind::Up, SweepKind::Down], Legs::Separate),
        Some(Direction::DownUp) => (vec![SweepKind::Up, SweepKind::Down], Legs::Loop(SweepKind::Down)),
        Some(Direction::UpDown) => (vec![SweepKind::Up, SweepKind::Down], Legs::Loop(SweepKind::Up)),
    };
    let x = if given == SweepKind::Up { axis.clone() } else { axis.reversed() };
    let model = s.scene.evaluate(&s.overrides)?;
    let (held, value) =
        model.parameters.iter().find(|(n, _)| *n != x.name && s.scene.is_plain(n)).cloned().ok_or_else(|| {
            RequestError::option(Opt::Axis).text("the scene needs a second plain parameter to hold fixed")
        })?;
    let plane =
        Plane::new(x, Axis::new(held, value, value, 1), Along::X).map_err(|e| grid_error(e, &[("x", Opt::Axis)]))?;
    let mut plan = Plan::new(&s, r.section_cap, plane, sweeps.clone(), r.threads)?;
    plan.output = r.output.clone();
    plan.inputs = r.sim.inputs(&r.start).into_iter().map(Path::to_path_buf).collect();
    plan.command = r.command.clone();
    if let Some(v) = &r.variable {
        render::variable_of(&plan.meta, Some(v)).map_err(|e| RequestError::option(Opt::Variable).text(e.what()))?;
    }
    plan.check().map_err(|e| with_fields(e, &[("x", Opt::Axis), ("threads", Opt::Threads)]))?;
    let atlas = match (legs, &origin) {
        (Legs::Separate, None) => plan.execute(observer)?.atlas,
        _ => legs_from(&plan, legs, origin.as_ref().map(|o| o.state.as_slice()), observer)?,
    };
    let first = match legs {
        Legs::Loop(first) => first,
        Legs::Separate if sweeps.contains(&given) => given,
        Legs::Separate => sweeps[0],
    };
    Ok(Sweep { atlas, legs, first, direction: r.direction, origin })
}

/// Runs the legs of a sweep that do not start from the scene's initial state:
/// from a given state, and the second leg of a loop from the first leg's end
/// state (the protocol of experiments and of published hysteresis zones).
/// Writes the file (under the output's lock) when the plan has an output.
fn legs_from(plan: &Plan, legs: Legs, start: Option<&[f64]>, observer: &dyn Observer) -> Result<Atlas> {
    let p = &plan.meta.plane;
    let _lock = plan.output.as_deref().map(store::OutputLock::acquire).transpose()?;
    let clock = std::time::Instant::now();
    let ascending: Vec<Vec<(String, f64)>> = (0..p.x.count).map(|ix| p.params(0, ix)).collect();
    let descending: Vec<Vec<(String, f64)>> = ascending.iter().rev().cloned().collect();
    let total = (p.x.count * plan.meta.sweeps.len()) as u64;
    observer.begin(&Begin { total, done: 0, lines: &[], prior: None, line_len: p.x.count, threads: 1 });
    let leg = |sweep: SweepKind, from: Option<&[f64]>| -> Result<Line> {
        let mut cells = match sweep {
            SweepKind::Down => grid::chain_from(&plan.setup, &descending, from, observer)?,
            _ => grid::chain_from(&plan.setup, &ascending, from, observer)?,
        };
        if sweep == SweepKind::Down {
            cells.reverse();
        }
        Ok(Line { sweep, index: 0, cells })
    };
    let mut atlas = Atlas::new(plan.meta.clone());
    match legs {
        Legs::Loop(first) => {
            let one = leg(first, start)?;
            // The first leg ends at the far end of the axis from where it began.
            let end = match first {
                SweepKind::Down => one.cells.first(),
                _ => one.cells.last(),
            }
            .map(|c| c.final_state.clone());
            let second = if first == SweepKind::Down { SweepKind::Up } else { SweepKind::Down };
            let two = leg(second, end.as_deref())?;
            atlas.insert(one);
            atlas.insert(two);
        }
        Legs::Separate => {
            for &sweep in &plan.meta.sweeps {
                atlas.insert(leg(sweep, start)?);
            }
        }
    }
    observer.finish();
    if observer.cancelled() {
        return Err(crate::Error::Cancelled);
    }
    if let Some(out) = &plan.output {
        let info = store::RunInfo {
            command: plan.command.clone(),
            run_time_s: clock.elapsed().as_secs_f64(),
            shard: None,
            history: Vec::new(),
            parent: None,
        };
        store::write(out, &atlas, &info, plan.threads)?;
    }
    Ok(atlas)
}

/// The JSON of a sweep (the contract of `sweep --json`): the points of the
/// leg asked for (`points`, in the order computed), both legs and where
/// they differ when both were run, and where it started.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepReport {
    /// The swept parameter.
    pub axis: String,
    /// `up`, `down`, `both` or `fresh`.
    pub direction: &'static str,
    /// The points of the first leg, in the order computed.
    pub points: Vec<SweepPoint>,
    /// The up leg, in increasing order, when both were run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec<SweepPoint>>,
    /// The down leg, in the order computed (decreasing), when both were run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub down: Option<Vec<SweepPoint>>,
    /// The values where up and down end on different periodic motions.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<Vec<Differing>>,
    /// Where it started, when not from the scene's initial state.
    #[serde(rename = "from", skip_serializing_if = "Option::is_none")]
    pub origin: Option<Source>,
}

/// One point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepPoint {
    /// The parameter's value.
    pub value: f64,
    /// The period of the first labelled mass, when periodic.
    pub n: Option<u32>,
    /// Its classification, labels, stability, reason, final state, section
    /// points and quantities ([`CellRecord`]).
    #[serde(flatten)]
    pub record: CellRecord,
}

/// A value where the legs differ, with each leg's labels.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Differing {
    /// The parameter's value.
    pub value: f64,
    /// The up leg's labels.
    pub up: BTreeMap<String, String>,
    /// The down leg's labels.
    pub down: BTreeMap<String, String>,
}

impl Sweep {
    /// The sweep as its report ([`SweepReport`]).
    pub fn report(&self) -> SweepReport {
        let atlas = &self.atlas;
        let first = self.first;
        let both = atlas.meta.sweeps.len() == 2;
        SweepReport {
            axis: atlas.meta.plane.x.name.clone(),
            direction: self.direction.map_or(first.name(), Direction::name),
            points: points(atlas, first, first == SweepKind::Down),
            up: both.then(|| points(atlas, SweepKind::Up, false)),
            down: both.then(|| points(atlas, SweepKind::Down, true)),
            hysteresis: both.then(|| hysteresis(atlas)),
            origin: self.origin.as_ref().map(|o| o.source.clone()),
        }
    }

    /// The JSON object of the sweep (the contract of `sweep --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// One point of a sweep.
fn point(atlas: &Atlas, ix: usize, c: &CellData) -> SweepPoint {
    SweepPoint {
        value: atlas.meta.plane.x.value(ix),
        n: c.labels.first().and_then(|l| l.npq()).map(|(n, _, _)| n),
        record: CellRecord::in_atlas(&atlas.meta, c),
    }
}

/// The points of one sweep in the order they were computed.
fn points(atlas: &Atlas, sweep: SweepKind, descending: bool) -> Vec<SweepPoint> {
    let Some(map) = atlas.map(sweep) else { return Vec::new() };
    let mut v: Vec<SweepPoint> =
        map.cells.iter().enumerate().filter_map(|(ix, c)| c.as_ref().map(|c| point(atlas, ix, c))).collect();
    if descending {
        v.reverse();
    }
    v
}

/// Values where up and down end on different periodic motions.
fn hysteresis(atlas: &Atlas) -> Vec<Differing> {
    let (Some(h), Some(up), Some(down)) = (atlas.hysteresis(), atlas.map(SweepKind::Up), atlas.map(SweepKind::Down))
    else {
        return Vec::new();
    };
    h.iter()
        .enumerate()
        .filter(|(_, &v)| v == 1)
        .filter_map(|(ix, _)| {
            let (u, d) = (up.cells[ix].as_ref()?, down.cells[ix].as_ref()?);
            Some(Differing {
                value: atlas.meta.plane.x.value(ix),
                up: labels(&atlas.meta.masses, u),
                down: labels(&atlas.meta.masses, d),
            })
        })
        .collect()
}
