//! The basins of attraction of one parameter point over a plane of initial
//! states ([`basins`]): two state components (`x_M2`, `v_M2`) over a grid,
//! the others at a given state, at a given forcing phase; every start
//! simulated exactly and grouped by the attractor it reaches (see
//! `grid::basins`), into a [`BasinMap`] that the store writes and the
//! renderer draws.

use crate::error::{Opt, RequestError, Result};
use crate::sim::{Origin, Sim, Start};
use crate::summary::AxisReport;
use grid::basins::StateGrid;
use grid::{Axis, BasinAttractor, BasinMap};
use grid::{Begin, Observer};
use serde::Serialize;
use std::collections::BTreeMap;

/// Most starts one run may take (2048 × 2048).
pub const MAX_STARTS: usize = 1 << 22;

/// The largest forcing phase accepted at the start, in radians (a phase is
/// defined modulo 2π; beyond this it has lost digits to its size).
const MAX_PHASE: f64 = 1000.0;

/// The basins to compute.
#[derive(Debug, Clone)]
pub struct BasinsRequest {
    /// The simulation options (the point is the scene's values with `set`).
    pub sim: Sim,
    /// The state outside the two axes: the scene's initial state, a given
    /// state, or a stored cell's (whose parameters the point then takes).
    pub start: Start,
    /// The horizontal axis: a state component (`x_M2`) and its values.
    pub x: Axis,
    /// The vertical axis.
    pub y: Axis,
    /// The forcing phase `ω t + τ` at the start (radians); the scene's τ when `None`.
    pub phase: Option<f64>,
    /// Worker threads.
    pub threads: usize,
    /// Stop a start once it reaches a stable periodic attractor already
    /// found (`basins --early-stop`; see `grid::basins`).
    pub early: bool,
    /// The basin file written (checked before any work), if any.
    pub output: Option<std::path::PathBuf>,
    /// The command line, stored in the file.
    pub command: String,
}

/// The names of a system's state components: `x_<mass>` for each mass,
/// then `v_<mass>`.
pub fn components(sys: &solver::System) -> Vec<String> {
    let names = sys.model.masses.iter().map(|m| &m.name);
    names.clone().map(|n| format!("x_{n}")).chain(names.map(|n| format!("v_{n}"))).collect()
}

/// Computes the basins of `r`, reporting each start done to `observer`
/// (which may stop the run); with the stored cell or state it started
/// from, when not the scene's initial state (its `note` says which cell
/// `--at` took).
pub fn basins(r: &BasinsRequest, observer: &dyn Observer) -> Result<(BasinMap, Option<Origin>)> {
    let (s, origin) = r.sim.setup_from(&r.start)?;
    if let Some(out) = &r.output {
        store::check_output(out, &r.sim.inputs(&r.start))?;
    }
    let cs = s.cell_setup(0)?;
    let sys = cs.system(&[])?;
    let names = components(&sys);
    let index = |axis: &Axis, opt: Opt| -> Result<usize> {
        names.iter().position(|n| *n == axis.name).ok_or_else(|| {
            let what = format!("no state component '{}' (the scene's are {})", axis.name, names.join(", "));
            RequestError::option(opt).text(what).into()
        })
    };
    let (xi, yi) = (index(&r.x, Opt::X)?, index(&r.y, Opt::Y)?);
    if xi == yi {
        let same = RequestError::option(Opt::Y).text("the same component as ").opt(Opt::X);
        return Err(same.text(format!(" ({})", r.x.name)).into());
    }
    let starts = r.x.count.saturating_mul(r.y.count);
    if starts > MAX_STARTS {
        let what = format!("{starts} starts ({} x {}), at most {MAX_STARTS}", r.x.count, r.y.count);
        return Err(RequestError::option(Opt::Y).text(what).into());
    }
    let phase = r.phase.unwrap_or(sys.tau);
    if !(phase.is_finite() && phase.abs() <= MAX_PHASE) {
        let what = format!("expected a phase in radians within ±{MAX_PHASE}, got {phase:e}");
        return Err(RequestError::option(Opt::Phase).text(what).into());
    }
    let grid = StateGrid {
        x: r.x.clone(),
        y: r.y.clone(),
        x_index: xi,
        y_index: yi,
        start: origin.as_ref().map_or_else(|| sys.model.initial_state(), |o| o.state.clone()),
        phase,
        early: r.early,
    };
    observer.begin(&Begin { total: starts as u64, done: 0, lines: &[], prior: None, line_len: 1, threads: r.threads });
    let reached = grid::basins::basins(&cs, &[], &grid, r.threads, observer);
    observer.finish();
    let reached = reached?;
    let m = &sys.model;
    let attractors = reached
        .attractors
        .into_iter()
        .map(|a| {
            let c = a.cell;
            BasinAttractor {
                class: c.class.name().to_string(),
                labels: c.labels,
                symmetry: c.symmetry.map(|x| x.name().to_string()),
                reason: c.reason.map(|x| x.to_string()),
                multiplier: c.multiplier,
                lyapunov: c.lyapunov,
                count: a.count as u64,
                start: a.start,
                section: c.period_section.to_rows(),
            }
        })
        .collect();
    let map = BasinMap {
        scene: m.name.clone(),
        parameters: m.parameters.clone(),
        masses: m.labelled_masses(),
        components: names,
        // The two axes' components take the grid's values: none of their own.
        start: grid.start.iter().enumerate().map(|(k, &v)| if k == xi || k == yi { f64::NAN } else { v }).collect(),
        phase,
        early: r.early,
        x: grid.x,
        y: grid.y,
        ids: reached.ids,
        periods: reached.periods,
        attractors,
    };
    let checked = cs.accuracy.chaos_check();
    if checked > 0 && map.attractors.iter().any(|a| a.class == solver::Class::Chaotic.name()) {
        observer.warn(&format!(
            "some starts end chaotic: the chaos check ends a clearly chaotic record at {checked} periods, and a chaotic \
             transient may still settle on a periodic attractor later; --accuracy chaos_check=0 or --preset precise \
             follows every record in full (docs/basins.md)"
        ));
    }
    if let Some(out) = &r.output {
        store::write_basins(out, &map, &r.command)?;
    }
    Ok((map, origin))
}

/// A grid of starts to propose for the basins of a cell's point: the
/// position and velocity of its first labelled mass (of its first mass when
/// none is labelled), each over `±h` with `count` values, `h` twice the
/// largest value the cell's motion takes (its final state and section
/// points), at least 1, rounded up to two significant digits.
pub fn proposed_axes(cell: &crate::Cell, count: usize) -> (Axis, Axis) {
    let sys = &cell.system;
    let mass = sys.model.labels.first().map_or(0, |l| l.mass);
    let names = components(sys);
    let r = &cell.result;
    let axis = |k: usize| {
        let reach = std::iter::once(&r.final_state).chain(&r.section).map(|s| s[k].abs()).fold(0.0, f64::max);
        let h = (2.0 * reach).max(1.0);
        let digits = 10f64.powi(h.log10().floor() as i32 - 1);
        let h = (h / digits).ceil() * digits;
        Axis::new(names[k].clone(), -h, h, count)
    };
    (axis(mass), axis(sys.dof() + mass))
}

/// The JSON of a basin map (the contract of `basins --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BasinsReport {
    /// The scene's name.
    pub scene: String,
    /// Every parameter of the point's model.
    pub parameters: BTreeMap<String, f64>,
    /// The forcing phase at the start (radians).
    pub phase: f64,
    /// Whether starts stopped once they reached a stable periodic attractor
    /// already found (`--early-stop`).
    pub early_stop: bool,
    /// The horizontal axis.
    pub x: AxisReport,
    /// The vertical axis.
    pub y: AxisReport,
    /// The state outside the two axes.
    pub start: Vec<f64>,
    /// Starts on the grid.
    pub starts: usize,
    /// Of those, the starts that do not penetrate a stop.
    pub admissible: u64,
    /// The attractors, the largest basin first (their ids are their places).
    pub attractors: Vec<BasinAttractorReport>,
    /// Forcing periods simulated per admissible start: their mean.
    pub mean_periods: f64,
    /// The measures of the boundary between basins.
    pub boundary: BoundaryReport,
}

/// One attractor of a basin map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BasinAttractorReport {
    /// Its id, the value of `basin` in the file.
    pub id: usize,
    /// The kind of motion.
    pub class: String,
    /// Per labelled mass, its label.
    pub labels: BTreeMap<String, String>,
    /// The symmetry of a periodic orbit of a symmetric scene.
    pub symmetry: Option<String>,
    /// Why it is unresolved, where it is.
    pub reason: Option<String>,
    /// The share of the admissible starts that reach it.
    pub fraction: f64,
    /// The starts that reach it.
    pub count: u64,
    /// The largest Floquet multiplier modulus, when periodic.
    pub max_multiplier: Option<f64>,
    /// The largest Lyapunov exponent, when not periodic.
    pub lyapunov: Option<f64>,
    /// The first start that reaches it.
    pub start: Vec<f64>,
    /// Its period-section points.
    pub section: Vec<Vec<f64>>,
}

/// Basin entropy and uncertainty exponent (see `maps::basins`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryReport {
    /// Starts per side of the entropy's boxes.
    pub entropy_box: usize,
    /// Basin entropy `S_b` (nats).
    pub basin_entropy: f64,
    /// Boundary basin entropy `S_bb` (nats).
    pub boundary_basin_entropy: f64,
    /// Whether `S_bb > ln 2` proves the boundary fractal.
    pub fractal: bool,
    /// The distances, in grid steps, of the uncertainty exponent's fit.
    pub steps: Vec<usize>,
    /// The share of starts uncertain at each distance.
    pub uncertain: Vec<f64>,
    /// The uncertainty exponent α (1 for a smooth boundary; `None` without
    /// a boundary or on a grid under 32 starts a side).
    pub uncertainty_exponent: Option<f64>,
}

impl BasinsReport {
    /// The JSON object of the report (the contract of `basins --json`).
    pub fn to_json(&self) -> serde_json::Value {
        crate::report::to_value(self)
    }
}

/// The report of a basin map ([`BasinsReport`]).
pub fn report(map: &BasinMap) -> BasinsReport {
    let (e, u) = (map.entropy(), map.uncertainty());
    let axis = AxisReport::of;
    let admissible = map.admissible();
    let simulated: u64 = map.periods.iter().sum();
    let attractors = map
        .attractors
        .iter()
        .enumerate()
        .map(|(id, a)| BasinAttractorReport {
            id,
            class: a.class.clone(),
            labels: map.masses.iter().cloned().zip(a.labels.iter().map(|l| l.to_string())).collect(),
            symmetry: a.symmetry.clone(),
            reason: a.reason.clone(),
            fraction: map.fraction(id),
            count: a.count,
            max_multiplier: a.multiplier,
            lyapunov: a.lyapunov,
            start: a.start.clone(),
            section: a.section.clone(),
        })
        .collect();
    BasinsReport {
        scene: map.scene.clone(),
        parameters: map.parameters.iter().cloned().collect(),
        phase: map.phase,
        early_stop: map.early,
        x: axis(&map.x),
        y: axis(&map.y),
        start: map.start.clone(),
        starts: map.ids.len(),
        admissible,
        attractors,
        mean_periods: simulated as f64 / admissible.max(1) as f64,
        boundary: BoundaryReport {
            entropy_box: e.side,
            basin_entropy: e.basin,
            boundary_basin_entropy: e.boundary,
            fractal: e.fractal(),
            steps: u.steps,
            uncertain: u.fractions,
            uncertainty_exponent: (!u.exponent.is_nan()).then_some(u.exponent),
        },
    }
}
