//! Periodic orbits: one by Newton's method ([`orbit`], `orbit --json`), and
//! one followed along a parameter with its bifurcations located
//! ([`continuation`], `continue --json`).

use crate::error::{Error, Result};
use crate::error::{Opt, RequestError};
use crate::sim::{check_period, labels_of, unknown, Sim, Source, Start};
use grid::Axis;
use grid::Observer;
use scene::Named;
use serde::Serialize;
use serde_json::Value;
use solver::continuation::Branch;
use solver::{orbit_of_cell, Complex64, Orbit, OrbitError, System};
use std::collections::BTreeMap;

/// The orbit a cell settles on: simulated from its start, then solved by
/// Newton's method on the `n`-period map (the cell's own period when `None`).
#[derive(Debug, Clone)]
pub struct CellOrbit {
    /// The system.
    pub system: System,
    /// The orbit.
    pub orbit: Orbit,
    /// A warning about the start (the scene differs from a stored one).
    pub warning: Option<String>,
    /// Which stored cell `--at` took, where it is off the values given
    /// ([`crate::Origin::note`]).
    pub note: Option<String>,
    /// Where the cell started, when not from the scene's initial state.
    pub source: Option<Source>,
}

/// What [`orbit`] solves: the orbit a cell settles on.
#[derive(Debug, Clone)]
pub struct OrbitRequest {
    /// The simulation options.
    pub sim: Sim,
    /// Where the cell starts.
    pub start: Start,
    /// The period in forcing periods; the cell's own when `None`.
    pub n: Option<usize>,
}

impl OrbitRequest {
    /// The orbit of the cell of `sim` from the scene's initial state, of its own period.
    pub fn new(sim: Sim) -> OrbitRequest {
        OrbitRequest { sim, start: Start::Initial, n: None }
    }
}

/// Finds the periodic orbit of a cell. `observer` may stop it before it
/// starts (one cell's simulation and one Newton solve run to their end, as
/// a cell of an atlas does).
pub fn orbit(r: &OrbitRequest, observer: &dyn Observer) -> Result<CellOrbit> {
    let (s, origin) = r.sim.setup_from(&r.start)?;
    let n = r.n;
    check_period(n)?;
    if observer.cancelled() {
        return Err(Error::Cancelled);
    }
    let model = s.scene.evaluate(&s.overrides)?;
    let (warning, note, source) = said_of(origin.as_ref());
    let y0 = origin.map_or_else(|| model.initial_state(), |o| o.state);
    let system = System::new(model)?;
    let orbit = orbit_of_cell(&system, &s.accuracy, &y0, n).map_err(|e| no_orbit(None, e))?;
    Ok(CellOrbit { system, orbit, warning, note, source })
}

/// What a result says of where it started: the warning and the note of its
/// origin, and its source (the results' `from`).
fn said_of(origin: Option<&crate::Origin>) -> (Option<String>, Option<String>, Option<Source>) {
    origin.map_or((None, None, None), |o| (o.warning.clone(), o.note.clone(), Some(o.source.clone())))
}

/// No orbit found (`at`: where, or empty): a motion that is not periodic
/// needs its period given ([`Opt::N`]).
fn no_orbit(at: Option<String>, e: OrbitError) -> Error {
    match e {
        OrbitError::NoPeriod(_) => {
            let at = at.unwrap_or_default();
            RequestError::message().text(format!("{at}{e}; give its period with ")).opt(Opt::N).into()
        }
        cause => Error::Orbit { at, cause },
    }
}

/// A Floquet multiplier: its parts and modulus (the JSON contract).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Multiplier {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
    /// Modulus.
    pub abs: f64,
}

/// The multipliers `mu`.
fn multipliers(mu: &[Complex64]) -> Vec<Multiplier> {
    mu.iter().map(|m| Multiplier { re: m.re, im: m.im, abs: m.norm() }).collect()
}

/// The JSON of an orbit (the contract of `orbit --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitReport {
    /// The scene's name.
    pub scene: String,
    /// Per labelled mass, its label.
    pub labels: BTreeMap<String, String>,
    /// The period in forcing periods.
    pub n: usize,
    /// The fewest forcing periods after which the orbit closes: less than `n`
    /// where `--n` asked for a multiple of the orbit's own period (the
    /// labels then count `n` periods).
    pub least_period: usize,
    /// The period in time.
    pub period: f64,
    /// The fixed point of the `n`-period map, `[x…, v…]`.
    pub fixed_point: Vec<f64>,
    /// Newton's final residual.
    pub residual: f64,
    /// Newton's iterations.
    pub newton_iterations: usize,
    /// The Floquet multipliers.
    pub multipliers: Vec<Multiplier>,
    /// The multipliers of the half-period map of a symmetric orbit solved on it.
    pub half_map_multipliers: Option<Vec<Multiplier>>,
    /// Whether the orbit is stable.
    pub stable: bool,
    /// The orbit's symmetry, when the scene is symmetric.
    pub symmetry: Option<&'static str>,
    /// The impacts of one period, in time order.
    pub impacts: Vec<OrbitImpact>,
    /// Where the cell started, when not from the scene's initial state (the
    /// stored cell `--from … --at` took, or the state `--state` gave).
    #[serde(rename = "from", skip_serializing_if = "Option::is_none")]
    pub origin: Option<Source>,
}

/// An impact of a periodic orbit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitImpact {
    /// The stop's name.
    pub stop: String,
    /// Time after the period's start.
    pub time: f64,
    /// Forcing phase in `[0, 2π)`.
    pub phase: f64,
    /// Closing speed before.
    pub velocity_before: f64,
    /// Speed after.
    pub velocity_after: f64,
}

impl CellOrbit {
    /// The orbit as its report ([`OrbitReport`]).
    pub fn report(&self) -> OrbitReport {
        let (sys, o) = (&self.system, &self.orbit);
        let impacts = o
            .impacts
            .iter()
            .map(|i| OrbitImpact {
                stop: sys.model.stops[i.stop].name.clone(),
                time: i.time,
                phase: i.phase,
                velocity_before: i.velocity.0,
                velocity_after: i.velocity.1,
            })
            .collect();
        OrbitReport {
            scene: sys.model.name.clone(),
            labels: labels_of(&o.labels),
            n: o.n,
            least_period: o.least_period,
            period: sys.period * o.n as f64,
            fixed_point: o.solution.x.as_slice().to_vec(),
            residual: o.solution.residual,
            newton_iterations: o.solution.iterations,
            multipliers: multipliers(&o.multipliers),
            half_map_multipliers: (o.map == solver::MapKind::Half).then(|| multipliers(&o.map_multipliers)),
            stable: o.stable,
            symmetry: o.symmetry.map(|x| x.name()),
            impacts,
            origin: self.source.clone(),
        }
    }

    /// The JSON object of the orbit (the contract of `orbit --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// An orbit followed along one parameter.
#[derive(Debug, Clone)]
pub struct FollowedOrbit {
    /// The system at the first value.
    pub system: System,
    /// The parameter.
    pub axis: Axis,
    /// The parameter's symbol in the scene (`ω`), for figures.
    pub symbol: String,
    /// The branch and its bifurcations.
    pub branch: Branch,
    /// A warning about the start (the scene differs from a stored one).
    pub warning: Option<String>,
    /// Which stored cell `--at` took, where it is off the values given
    /// ([`crate::Origin::note`]).
    pub note: Option<String>,
    /// Where the cell at the first value started, when not from the scene's
    /// initial state.
    pub source: Option<Source>,
}

/// What [`continuation`] follows: the orbit of a cell along one parameter.
#[derive(Debug, Clone)]
pub struct ContinuationRequest {
    /// The simulation options.
    pub sim: Sim,
    /// Where the cell at the axis's first value starts.
    pub start: Start,
    /// The parameter and its values, in the order followed (at least two).
    pub axis: Axis,
    /// The orbit's period in forcing periods; the cell's own when `None`.
    pub n: Option<usize>,
    /// Pseudo-arclength continuation (around folds) instead of natural.
    pub arclength: bool,
}

impl ContinuationRequest {
    /// The orbit of the cell of `sim` at `axis`'s first value, from the
    /// scene's initial state, followed naturally.
    pub fn new(sim: Sim, axis: Axis) -> ContinuationRequest {
        ContinuationRequest { sim, start: Start::Initial, axis, n: None, arclength: false }
    }
}

/// Follows the orbit of a cell along the request's axis (natural
/// continuation, or pseudo-arclength), locating its bifurcations. `observer`
/// may stop it between any two solves ([`Error::Cancelled`]).
pub fn continuation(r: &ContinuationRequest, observer: &dyn Observer) -> Result<FollowedOrbit> {
    let (axis, n) = (&r.axis, r.n);
    r.sim.refuse_set_of(&[&axis.name], "the parameter the orbit is followed along")?;
    let (s, origin) = r.sim.setup_from(&r.start)?;
    s.scene.check_parameter(&axis.name, "").map_err(|e| unknown(RequestError::option(Opt::Axis), e))?;
    if axis.count < 2 {
        return Err(RequestError::option(Opt::Axis)
            .text(format!("the count must be at least 2, got {}", axis.count))
            .into());
    }
    check_period(n)?;
    let values = axis.values();
    // Every solve asks for its system: a cancel ends the branch there.
    let family = |v: f64| -> Option<System> {
        if observer.cancelled() {
            return None;
        }
        s.system_with(&[(&axis.name, v)]).ok()
    };
    let system = s.system_with(&[(&axis.name, values[0])])?;
    // Both ends within the parameter's range (and so every value between).
    s.system_with(&[(&axis.name, values[values.len() - 1])])?;
    let (warning, note, source) = said_of(origin.as_ref());
    let y0 = origin.map_or_else(|| system.model.initial_state(), |o| o.state);
    let start = orbit_of_cell(&system, &s.accuracy, &y0, n)
        .map_err(|e| no_orbit(Some(format!("at {} = {}: ", axis.name, values[0])), e))?;
    let branch = if r.arclength {
        solver::arclength::follow_arclength(&family, &s.accuracy, &values, start)
    } else {
        solver::continuation::follow(&family, &s.accuracy, &values, start)
    };
    if observer.cancelled() {
        return Err(Error::Cancelled);
    }
    let symbol = s.scene.symbol(&axis.name);
    Ok(FollowedOrbit { system, axis: axis.clone(), symbol, branch, warning, note, source })
}

impl FollowedOrbit {
    /// Each point of the branch as a figure draws it: the parameter, the
    /// first coordinate of the fixed point, the largest |Floquet multiplier|,
    /// and whether the orbit is stable.
    pub fn points(&self) -> Vec<(f64, f64, f64, bool)> {
        let radius = |o: &Orbit| solver::floquet::spectral_radius(&o.multipliers);
        self.branch.points.iter().map(|p| (p.value, p.orbit.solution.x[0], radius(&p.orbit), p.orbit.stable)).collect()
    }

    /// Each bifurcation: the parameter and the kind's name (`PD`).
    pub fn marks(&self) -> Vec<(f64, String)> {
        self.branch.bifurcations.iter().map(|b| (b.value, b.kind.name().to_string())).collect()
    }

    /// The branch as its report ([`BranchReport`]).
    pub fn report(&self) -> BranchReport {
        let b = &self.branch;
        let branch = b
            .points
            .iter()
            .map(|p| BranchPoint {
                value: p.value,
                stable: p.orbit.stable,
                multipliers: multipliers(&p.orbit.multipliers),
                labels: labels_of(&p.orbit.labels),
                symmetry: p.orbit.symmetry.map(|x| x.name()),
                fixed_point: p.orbit.solution.x.as_slice().to_vec(),
            })
            .collect();
        let bifurcations = b
            .bifurcations
            .iter()
            .map(|x| BranchBifurcation {
                kind: x.kind.name(),
                value: x.value,
                multipliers: multipliers(&x.multipliers),
                critical: Critical {
                    re: x.critical.re,
                    im: x.critical.im,
                    abs: x.critical.norm(),
                    arg: x.critical.arg(),
                },
            })
            .collect();
        BranchReport { branch, bifurcations, ended: b.ended.clone(), origin: self.source.clone() }
    }

    /// The JSON object of the branch (the contract of `continue --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// The JSON of a followed orbit (the contract of `continue --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchReport {
    /// The points followed, in order.
    pub branch: Vec<BranchPoint>,
    /// The bifurcations located between them.
    pub bifurcations: Vec<BranchBifurcation>,
    /// Why the branch ended before the last value, if it did.
    pub ended: Option<String>,
    /// Where the cell at the first value started, when not from the scene's
    /// initial state (as [`OrbitReport`]'s).
    #[serde(rename = "from", skip_serializing_if = "Option::is_none")]
    pub origin: Option<Source>,
}

/// A point of a followed orbit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchPoint {
    /// The parameter's value.
    pub value: f64,
    /// Whether the orbit is stable.
    pub stable: bool,
    /// The Floquet multipliers.
    pub multipliers: Vec<Multiplier>,
    /// Per labelled mass, its label.
    pub labels: BTreeMap<String, String>,
    /// The orbit's symmetry, when the scene is symmetric.
    pub symmetry: Option<&'static str>,
    /// The fixed point.
    pub fixed_point: Vec<f64>,
}

/// A bifurcation located on a branch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchBifurcation {
    /// Its kind (`PD`, `SN`, `NS`, …).
    pub kind: &'static str,
    /// The parameter's value.
    pub value: f64,
    /// The multipliers there.
    pub multipliers: Vec<Multiplier>,
    /// The multiplier that crossed the unit circle.
    pub critical: Critical,
}

/// The critical multiplier of a bifurcation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Critical {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
    /// Modulus.
    pub abs: f64,
    /// Argument in `(-π, π]`.
    pub arg: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Quiet, SceneSource};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Asks to stop once it has been asked `after` times.
    struct StopAfter {
        after: usize,
        asked: AtomicUsize,
    }
    impl Observer for StopAfter {
        fn advance(&self, _: u64) {}
        fn cancelled(&self) -> bool {
            self.asked.fetch_add(1, Ordering::Relaxed) >= self.after
        }
    }

    /// A continuation asked to stop builds no system after that (each value
    /// left is asked once and skipped, no step refined) and ends as
    /// cancelled; the same request not stopped follows the whole axis.
    #[test]
    fn a_continuation_stops_when_its_observer_asks() {
        let sim = Sim::new(SceneSource::File("../../configs/single-stop.toml".into()));
        let r = ContinuationRequest::new(sim, Axis::new("sigma", 0.0, -1.5, 31));
        let whole = continuation(&r, &Quiet).unwrap();
        assert!(whole.branch.points.len() >= 31, "{} points", whole.branch.points.len());
        let stop = StopAfter { after: 3, asked: AtomicUsize::new(0) };
        assert!(matches!(continuation(&r, &stop), Err(Error::Cancelled)));
        let asked = stop.asked.load(Ordering::Relaxed);
        assert!(asked <= 3 + 31 + 1, "{asked} systems asked for");
        let never = StopAfter { after: 0, asked: AtomicUsize::new(0) };
        assert!(matches!(orbit(&OrbitRequest::new(r.sim.clone()), &never), Err(Error::Cancelled)));
    }
}
