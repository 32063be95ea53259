//! A periodic orbit solved by Newton's method, with its Floquet multipliers,
//! labels, symmetry and impacts.

use crate::accuracy::Accuracy;
use crate::executor::run_cell;
use crate::floquet::multipliers;
use crate::flow::Method;
use crate::label::{label_masses, Class, Mask, MassLabel, Symmetry};
use crate::newton::{try_solve, Failure, Limits, MapKind, Pattern, Solution};
use crate::simulate::{Both, EventObserver, Ignore, Simulator};
use crate::system::System;
use nalgebra::DVector;
use num_complex::Complex64 as C64;

/// Newton tolerance of an orbit (relative residual of the fixed-point equation).
pub const ORBIT_TOL: f64 = 1e-12;

/// Newton's method for an orbit: to [`ORBIT_TOL`] in at most 40 steps of at
/// most half the state's size, given up after 8 steps without a new least
/// residual above 1e-8. Measured on `curves` of the reference map: the
/// iterations that fail by wandering took 3.4 M of its 4.5 M map evaluations
/// (`--max 10`, one thread), while of its 1.9 M converging iterations
/// (`--max 40`) 3 found a new least residual after such a stall.
const ORBIT_LIMITS: Limits = Limits { tol: ORBIT_TOL, max_iter: 40, max_step: 0.5, stall: Some(8) };

/// One impact along an orbit.
#[derive(Debug, Clone)]
pub struct OrbitImpact {
    /// Stop index.
    pub stop: usize,
    /// Time from the fixed point's section, in `[0, nT)`.
    pub time: f64,
    /// Forcing phase `ω t + τ` at the impact, in `[0, 2π)`.
    pub phase: f64,
    /// Normal velocity of the stop's gap before (negative: closing) and after.
    pub velocity: (f64, f64),
}

/// A periodic orbit.
#[derive(Debug, Clone)]
pub struct Orbit {
    /// Period in forcing periods.
    pub n: usize,
    /// The fewest forcing periods after which the orbit closes: a divisor of
    /// `n`, less than `n` where the `n`-period map was solved on an orbit of a
    /// shorter period (its state after `least_period` periods within
    /// `periodic_tol` of the fixed point, relative to 1 + |state|).
    pub least_period: usize,
    /// The map whose fixed point was solved.
    pub map: MapKind,
    /// The Newton solution (fixed point at `t = 0`, the map's Jacobian).
    pub solution: Solution,
    /// Multipliers of the solved map, largest modulus first.
    pub map_multipliers: Vec<C64>,
    /// Multipliers of the n-period map (squares of the half map's), largest first.
    pub multipliers: Vec<C64>,
    /// All multipliers strictly inside the unit circle.
    pub stable: bool,
    /// Symmetry in a mirror-symmetric scene.
    pub symmetry: Option<Symmetry>,
    /// n-p-q labels.
    pub labels: Vec<MassLabel>,
    /// Impacts over the n periods, in time order.
    pub impacts: Vec<OrbitImpact>,
}

#[derive(Default)]
struct Impacts {
    list: Vec<(f64, usize, DVector<f64>, DVector<f64>)>,
}

impl EventObserver for Impacts {
    fn impact(&mut self, t: f64, stop: usize, before: &DVector<f64>, after: &DVector<f64>) {
        self.list.push((t, stop, before.clone(), after.clone()));
    }
}

/// Completes a Newton solution into an [`Orbit`] (multipliers, labels, impacts).
pub fn describe(sys: &System, acc: &Accuracy, solution: Solution, map: MapKind, n: usize) -> Orbit {
    let sim = Simulator::new(sys, *acc, Method::Exact, solution.x.as_slice()).ok();
    describe_in(sys, acc, sim, solution, map, n, &mut Ignore)
}

/// [`describe`], its impacts simulated by `sim` (started at the solution;
/// `None`: it could not be).
fn describe_in(
    sys: &System,
    acc: &Accuracy,
    mut sim: Option<Simulator<'_>>,
    solution: Solution,
    map: MapKind,
    n: usize,
    watch: &mut dyn EventObserver,
) -> Orbit {
    let map_multipliers = multipliers(&solution.jacobian);
    let mut full: Vec<C64> = match map {
        MapKind::Half => map_multipliers.iter().map(|m| m * m).collect(),
        MapKind::Periods(_) => map_multipliers.clone(),
    };
    full.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.re.total_cmp(&a.re)).then(b.im.total_cmp(&a.im)));
    let stable = !map_multipliers.is_empty() && map_multipliers.iter().all(|m| m.norm() < 1.0);
    let mut obs = Impacts::default();
    let (mut impacts, mut held, mut least_period) = (vec![0u32; sys.stops.len()], 0u32, n);
    let x0 = &solution.x;
    let closes = |x: &DVector<f64>| (x - x0).amax() <= acc.periodic_tol() * (1.0 + x0.amax());
    if let Some(sim) = sim.as_mut() {
        for k in 1..=n {
            if let Ok(rec) = sim.run_period(&[], false, &mut Both(&mut obs, watch)) {
                impacts.iter_mut().zip(&rec.impacts).for_each(|(a, b)| *a += b);
                held |= rec.held;
            }
            if k < least_period && n.is_multiple_of(k) && closes(sim.state()) {
                least_period = k;
            }
        }
    }
    let labels = label_masses(sys, Some(n), Class::Periodic, &impacts, Mask::from_bits(held));
    let orbit_impacts = obs
        .list
        .iter()
        .map(|(t, k, before, after)| OrbitImpact {
            stop: *k,
            time: *t,
            phase: sys.phase_at(*t),
            velocity: (sys.gap_rate(*k, before), sys.gap_rate(*k, after)),
        })
        .collect();
    let symmetry =
        sys.model.symmetric.then_some(if map == MapKind::Half { Symmetry::Symmetric } else { Symmetry::Asymmetric });
    Orbit {
        n,
        least_period,
        map,
        solution,
        map_multipliers,
        multipliers: full,
        stable,
        symmetry,
        labels,
        impacts: orbit_impacts,
    }
}

/// Solves the orbit of `map` from `x0` (keeping `pattern` when given).
pub fn solve_orbit(
    sys: &System,
    acc: &Accuracy,
    x0: &DVector<f64>,
    map: MapKind,
    n: usize,
    pattern: Option<&Pattern>,
) -> Result<Orbit, Failure> {
    solve_orbit_watched(sys, acc, x0, map, n, pattern, &mut Ignore)
}

/// [`solve_orbit`], `watch` told of the orbit's n periods from its fixed
/// point as they are simulated to describe it (a grazing's margin is
/// measured so, [`crate::grazing`], without a simulation of its own).
pub(crate) fn solve_orbit_watched(
    sys: &System,
    acc: &Accuracy,
    x0: &DVector<f64>,
    map: MapKind,
    n: usize,
    pattern: Option<&Pattern>,
    watch: &mut dyn EventObserver,
) -> Result<Orbit, Failure> {
    let mut sim = Simulator::new(sys, *acc, Method::Exact, x0.as_slice()).map_err(|_| Failure::Simulation)?;
    let solution = try_solve(&mut sim, x0, map, pattern, ORBIT_LIMITS)?;
    // The solver's simulator, started again, has the modes built.
    let sim = sim.reset(solution.x.as_slice()).is_ok().then_some(sim);
    Ok(describe_in(sys, acc, sim, solution, map, n, watch))
}

/// The map to solve for a period-`n` orbit of `sys` near `x0`: the half map for a
/// period-one orbit of a symmetric scene when `x0` is (nearly) mirrored by it.
pub fn natural_map(sys: &System, acc: &Accuracy, x0: &DVector<f64>, n: usize) -> MapKind {
    if sys.model.symmetric && n == 1 {
        if let Ok(mut sim) = Simulator::new(sys, *acc, Method::Exact, x0.as_slice()) {
            if let Ok(rec) = sim.run_period(&[], true, &mut crate::simulate::Ignore) {
                if let Some(h) = rec.half {
                    let d = (&h + x0).amax() / (1.0 + x0.amax());
                    if d < 1e-4 {
                        return MapKind::Half;
                    }
                }
            }
        }
    }
    MapKind::Periods(n)
}

/// Why no orbit was found.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum OrbitError {
    /// The simulated cell is not periodic and no period was given (the
    /// caller says how to give one).
    NoPeriod(String),
    /// Newton's method did not converge.
    NoConvergence,
}

impl std::fmt::Display for OrbitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OrbitError::NoPeriod(class) => {
                write!(f, "the simulated motion is {class}, not periodic")
            }
            OrbitError::NoConvergence => write!(f, "Newton's method did not converge to a periodic orbit"),
        }
    }
}

impl std::error::Error for OrbitError {}

/// Simulates the cell from `y0`, then solves the periodic orbit it settles on
/// (period `n`, or the cell's period when `None`).
pub fn orbit_of_cell(sys: &System, acc: &Accuracy, y0: &[f64], n: Option<usize>) -> Result<Orbit, OrbitError> {
    let cell = run_cell(sys, acc, Method::Exact, y0);
    let n = n.or(cell.n).ok_or_else(|| OrbitError::NoPeriod(cell.class.name().to_string()))?;
    let x0 = DVector::from_vec(cell.final_state);
    let map = natural_map(sys, acc, &x0, n);
    solve_orbit(sys, acc, &x0, map, n, None).map_err(|_| OrbitError::NoConvergence)
}
