//! Classification of the steady motion of a cell as n-p-q.
//!
//! Periods are simulated until the period (stroboscopic, `t = kT`) section
//! repeats: the smallest `n <= n_max` such that the last `2n` section points each
//! equal the point `n` periods earlier (within `periodic_tol`), with the same
//! impacts per stop, is the period. Then `p`, `q` are the impacts of each mass
//! at its p-stop and q-stop over those n periods (`S` where the mass sticks to the
//! stop). No period within `max_periods`: the largest Lyapunov exponent tells a
//! long transient (contracting: the record is extended), a torus (`Q`) and chaos
//! (class `chaotic`, label `C`); with `chaos_check` it is measured early too, and
//! a clearly chaotic record ends there. A cell that exhausts its event budget or
//! stalls is `unresolved`, label `U`.

use crate::accuracy::Accuracy;
use crate::floquet::{multipliers, spectral_radius};
use crate::flow::Method;
use crate::lyapunov::{fills_closed_curve, largest_exponent};
use crate::newton::{evaluate, fixed_point, MapKind, Pattern, Solution};
use crate::section::record_window;
use crate::simulate::{Halt, Ignore, Observer, PeriodRecord, Simulator};
use crate::system::System;
use nalgebra::DVector;
use std::collections::VecDeque;

/// Kind of steady motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// Periodic with period n forcing periods.
    Periodic,
    /// No period up to `n_max` within `max_periods`: chaotic (positive largest
    /// Lyapunov exponent) or long-period / not decided (written `C`).
    Chaotic,
    /// No period, a zero largest Lyapunov exponent and period-section points on
    /// a closed curve: motion on an invariant torus (written `Q`).
    Quasiperiodic,
    /// The event budget ran out or an event search stalled.
    Unresolved,
}

impl Class {
    /// Lower-case name used in output.
    pub fn name(self) -> &'static str {
        match self {
            Class::Periodic => "periodic",
            Class::Chaotic => "chaotic",
            Class::Quasiperiodic => "quasiperiodic",
            Class::Unresolved => "unresolved",
        }
    }
}

/// Mirror symmetry of a periodic orbit of a symmetric scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// `x(t + nT/2) = -x(t)` (up to a whole number of periods).
    Symmetric,
    /// Not symmetric.
    Asymmetric,
}

impl Symmetry {
    /// `S` or `AS`.
    pub fn name(self) -> &'static str {
        match self {
            Symmetry::Symmetric => "S",
            Symmetry::Asymmetric => "AS",
        }
    }
}

/// Impacts at one stop in a label, or `S` when the mass sticks to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Count {
    /// Impacts in n periods.
    Impacts(u32),
    /// The stop held the mass (complete chattering), written `S`.
    Stuck,
}

impl std::fmt::Display for Count {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Count::Impacts(c) => write!(f, "{c}"),
            Count::Stuck => write!(f, "S"),
        }
    }
}

/// The n-p-q label of one mass; prints as `1-4-4`, `1-S-S`, `C` or `U`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MassLabel {
    /// Mass name.
    pub mass: String,
    /// `(n, p, q)` of a periodic motion; `None` for chaotic and unresolved cells.
    pub npq: Option<(u32, Count, Count)>,
    /// Class of the cell, which names non-periodic labels.
    pub class: Class,
}

impl std::fmt::Display for MassLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.npq, self.class) {
            (Some((n, p, q)), _) => write!(f, "{n}-{p}-{q}"),
            (None, Class::Unresolved) => write!(f, "U"),
            (None, Class::Quasiperiodic) => write!(f, "Q"),
            (None, _) => write!(f, "C"),
        }
    }
}

/// Periods of tangent alignment before the Lyapunov exponent is averaged.
const LYAPUNOV_WARMUP: usize = 10;

/// A cell without a period whose `λ T` is below minus this still contracts: a
/// long transient, whose record is extended (see `Accuracy::extensions`).
const CONTRACTING_EXPONENT: f64 = 2e-3;

/// Smallest `λ T` at which the early look of `Accuracy::chaos_check` ends a
/// record as chaotic: five times the quasi-periodic band, so that a torus or a
/// weakly chaotic motion gets the whole record.
const CHAOTIC_EXPONENT: f64 = 0.05;

/// Largest `|λ T|` (growth per forcing period) of a quasi-periodic motion: a
/// torus has `λ = 0`, and a finite average over 100 periods stays within this.
pub const QUASIPERIODIC_EXPONENT: f64 = 0.01;

/// Everything known about a cell's steady motion.
#[derive(Debug, Clone, PartialEq)]
pub struct CellResult {
    /// Kind of motion.
    pub class: Class,
    /// Period in forcing periods, when periodic.
    pub n: Option<usize>,
    /// Label per labelled mass.
    pub labels: Vec<MassLabel>,
    /// Impacts per stop over the n periods (over the last `n_max` periods when not periodic).
    pub impacts: Vec<u32>,
    /// Chattering flag per stop (at least `chatter_impacts` impacts in the window).
    pub chatter: Vec<bool>,
    /// Sticking flag per stop (the stop held its mass during the window).
    pub sticking: Vec<bool>,
    /// Per friction contact: whether it stuck during the window.
    pub friction_stick: Vec<bool>,
    /// Symmetry of a periodic orbit of a symmetric scene.
    pub symmetry: Option<Symmetry>,
    /// Largest Lyapunov exponent (per unit time) of a cell without a period,
    /// when measured.
    pub lyapunov: Option<f64>,
    /// Largest Floquet multiplier modulus of a periodic cell (the Jacobian of
    /// the n-period map at the final state), when measured.
    pub multiplier: Option<f64>,
    /// Full state `[x; v]` at the end of the simulation (at `t = kT`).
    pub final_state: Vec<f64>,
    /// State at the start of the classified window (for traces and sections).
    pub window_start: Vec<f64>,
    /// Period-section points of the window (n points when periodic).
    pub section: Vec<Vec<f64>>,
    /// Forcing periods simulated.
    pub periods: u64,
    /// Events handled.
    pub events: usize,
    /// Why the cell is unresolved.
    pub reason: Option<String>,
}

/// Distance of two section points, relative to `1 + |a|` (max norm).
fn distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    let d = a.iter().zip(b.iter()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    d / (1.0 + a.amax())
}

fn close(a: &DVector<f64>, b: &DVector<f64>, tol: f64) -> bool {
    distance(a, b) <= tol
}

/// Largest distance between each of the last `2n` points and the point `lag` earlier.
fn residual(h: &VecDeque<PeriodRecord>, n: usize, lag: usize) -> f64 {
    let len = h.len();
    (len - 2 * n..len).map(|i| distance(&h[i].end, &h[i - lag].end)).fold(0.0, f64::max)
}

fn repeats(h: &VecDeque<PeriodRecord>, i: usize, n: usize, tol: f64) -> bool {
    let (a, b) = (&h[i], &h[i - n]);
    a.end_key == b.end_key && a.impacts == b.impacts && close(&a.end, &b.end, tol)
}

/// Smallest n whose last 2n section points repeat with period n. A candidate is
/// refused (and the run goes on) while a proper divisor d of n nearly repeats
/// too, within 1000 times the residual: that is a transient still converging to
/// a period-d orbit (e.g. one that flips sign every period), not a period-n orbit.
fn detect(h: &VecDeque<PeriodRecord>, acc: &Accuracy) -> Option<usize> {
    let len = h.len();
    let n = (1..=acc.n_max).find(|&n| {
        len >= 3 * n
            && repeats(h, len - 1, n, acc.periodic_tol)
            && (len - 2 * n..len).all(|i| repeats(h, i, n, acc.periodic_tol))
    })?;
    let res = residual(h, n, n);
    let converging_divisor = (1..n).filter(|d| n % d == 0).any(|d| residual(h, n, d) <= 1e3 * res);
    (!converging_divisor).then_some(n)
}

/// Newton acceleration of one cell: tries spent, when the next may start, and
/// the probe simulator that evaluates the period map (its work counts towards
/// the cell's budget).
#[derive(Default)]
struct Newton<'s> {
    tries: usize,
    next: u64,
    probe: Option<Simulator<'s>>,
}

impl<'s> Newton<'s> {
    /// Events the probe has spent.
    fn events(&self) -> usize {
        self.probe.as_ref().map_or(0, |p| p.events)
    }

    /// One attempt on a contracting pattern of the records `hist` of `sim`: the
    /// state to restart from when the trajectory is heading to a stable orbit.
    /// Farther than [`NEWTON_REACH`] it waits as many periods as the observed
    /// contraction needs, without spending a try.
    fn step(&mut self, sim: &mut Simulator<'s>, hist: &VecDeque<PeriodRecord>, acc: &Accuracy) -> Option<DVector<f64>> {
        let (n, pattern, to_go, rho) = contracting_pattern(hist, acc)?;
        self.tries += 1;
        self.next = sim.periods + 3 * n as u64;
        let spent = sim.events + self.events();
        let p = self.probe.get_or_insert_with(|| sim.probe());
        p.set_budget(acc.max_events.saturating_sub(spent) + p.events);
        let solved = fixed_point(p, &sim.y, n, &pattern, 1e-3 * acc.periodic_tol);
        // One budget per cell: what the probe spent is the simulation's no more.
        sim.set_budget(acc.max_events.saturating_sub(p.events));
        let sol = solved?;
        let d = distance(&sim.y, &sol.x);
        if d > NEWTON_REACH && d <= 10.0 * to_go {
            let periods = ((NEWTON_REACH / d).ln() / rho.ln()).ceil().max(1.0);
            self.next = sim.periods + periods as u64 * n as u64;
            self.tries -= 1;
            return None;
        }
        // The fixed point must be where this trajectory is heading: a stable
        // orbit much farther away than the remaining contraction reaches belongs
        // to another attractor, and so does one whose linearisation does not
        // carry the trajectory's last n periods (it is outside the orbit's linear
        // neighbourhood, e.g. across a grazing): brute force goes on.
        (heading_to(hist, n, &sim.y, &sol, to_go) && within_margin(p, &sol, n, &sim.y).unwrap_or(false))
            .then_some(sol.x)
    }
}

/// Largest distance (relative, max norm) from which a Newton solution is taken
/// as the trajectory's destination: farther out a slowly attracting orbit may
/// lose the trajectory to another attractor (a long transient passes near it).
const NEWTON_REACH: f64 = 5e-3;

/// Whether the trajectory, now at `y` after the records `h`, is heading to the
/// Newton solution `sol` of its n-period map: within ten times the distance it
/// still has to go (`to_go`) and within [`NEWTON_REACH`], closer than n periods ago, and its last n-period
/// step is the orbit's linearisation `y - x* ≈ DPⁿ (y_prev - x*)`, with an error
/// below half the contraction the linearisation predicts.
fn heading_to(h: &VecDeque<PeriodRecord>, n: usize, y: &DVector<f64>, sol: &Solution, to_go: f64) -> bool {
    let len = h.len();
    if len <= n || distance(y, &sol.x) > (10.0 * to_go).min(NEWTON_REACH) {
        return false;
    }
    let (now, before) = (y - &sol.x, &h[len - 1 - n].end - &sol.x);
    let predicted = &sol.jacobian * &before;
    // The part of the step the linearisation misses must be smaller than the
    // contraction it predicts, or it may undo it (near |μ| = 1 it does).
    let contraction = before.norm() - predicted.norm();
    now.norm() < before.norm() && (&now - predicted).norm() <= 0.5 * contraction
}

/// Whether `y` lies well inside the orbit's smooth neighbourhood: its position
/// deviation from the fixed point is below a quarter of the smallest gap that
/// a stop the orbit never hits keeps along the orbit (64 samples per period).
/// Closer to such a stop the trajectory may graze it and leave for another
/// attractor although the orbit is stable. `None` when the orbit cannot be
/// simulated.
fn within_margin(probe: &mut Simulator<'_>, sol: &Solution, n: usize, y: &DVector<f64>) -> Option<bool> {
    struct Gaps<'a>(&'a System, Vec<f64>);
    impl Observer for Gaps<'_> {
        fn sample(&mut self, _t: f64, y: &DVector<f64>) {
            for (k, g) in self.1.iter_mut().enumerate() {
                *g = g.min(self.0.gap(k, y));
            }
        }
    }
    let sys = probe.system();
    let mut gaps = Gaps(sys, vec![f64::INFINITY; sys.stops.len()]);
    let times: Vec<f64> = (1..64).map(|i| sys.period * i as f64 / 64.0).collect();
    probe.restart(sol.x.as_slice()).ok()?;
    for _ in 0..n {
        probe.run_period(&times, false, &mut gaps).ok()?;
    }
    let hit = |k: usize| sol.pattern.iter().any(|p| p[k] > 0);
    let margin = (0..sys.stops.len()).filter(|&k| !hit(k)).map(|k| gaps.1[k]).fold(f64::INFINITY, f64::min);
    let m = sys.dof();
    let deviation = (0..m).map(|i| (y[i] - sol.x[i]).abs()).fold(0.0, f64::max);
    Some(deviation <= 0.25 * margin)
}

/// The smallest n whose impact pattern repeated over the last 3n periods while
/// the section points still move and contract too slowly: at the observed rate
/// `ρ = |s_k - s_{k-n}| / |s_{k-n} - s_{k-2n}|`, reaching `periodic_tol` would
/// take longer than a Newton solve (about `3 (dim + 1) n` periods). Returns n,
/// the pattern, the distance the trajectory still has to go at that rate,
/// `|s_k - s_{k-n}| / (1 - ρ)`, and ρ.
fn contracting_pattern(h: &VecDeque<PeriodRecord>, acc: &Accuracy) -> Option<(usize, Pattern, f64, f64)> {
    let len = h.len();
    let dim = h.back()?.end.len() as f64;
    let (n, e1, rho) = (1..=acc.n_max).find_map(|n| {
        if len <= 3 * n
            || !(len - 2 * n..len).all(|i| h[i].impacts == h[i - n].impacts && h[i].end_key == h[i - n].end_key)
        {
            return None;
        }
        let e1 = distance(&h[len - 1].end, &h[len - 1 - n].end);
        let rho = e1 / distance(&h[len - 1 - n].end, &h[len - 1 - 2 * n].end);
        let remaining = (acc.periodic_tol / e1).ln() / rho.ln() * n as f64;
        (e1 > acc.periodic_tol && rho < 1.0 && remaining > 3.0 * (dim + 1.0) * n as f64).then_some((n, e1, rho))
    })?;
    Some((n, h.iter().skip(len - n).map(|r| r.impacts.clone()).collect(), e1 / (1.0 - rho), rho))
}

/// Period records kept: enough to test every period up to `n_max` and the
/// 3n-period pattern Newton acceleration needs.
fn history_len(acc: &Accuracy) -> usize {
    3 * acc.n_max + 1
}

/// Simulates periods into `hist` until its section repeats (the period n,
/// returned) or `limit` periods in all are simulated (`None`), with Newton
/// acceleration of slowly contracting patterns on the way.
fn record<'s>(
    sim: &mut Simulator<'s>,
    hist: &mut VecDeque<PeriodRecord>,
    newton: &mut Newton<'s>,
    limit: usize,
    acc: &Accuracy,
    symmetric: bool,
) -> Result<Option<usize>, Halt> {
    while (sim.periods as usize) < limit {
        let rec = sim.run_period(&[], symmetric, &mut Ignore)?;
        if hist.len() == history_len(acc) {
            hist.pop_front();
        }
        hist.push_back(rec);
        if (sim.periods as usize) < acc.min_transient {
            continue;
        }
        if let Some(n) = detect(hist, acc) {
            return Ok(Some(n));
        }
        if acc.newton && newton.tries < 3 && sim.periods >= newton.next {
            if let Some(x) = newton.step(sim, hist, acc) {
                if sim.restart(x.as_slice()).is_ok() {
                    hist.clear();
                }
            }
        }
    }
    Ok(None)
}

/// Simulates a cell from full state `y0` and classifies its steady motion.
pub fn run_cell(sys: &System, acc: &Accuracy, method: Method, y0: &[f64]) -> CellResult {
    run_cell_with_sections(sys, acc, method, y0, 0).0
}

/// [`run_cell`] and the impact sections of its classified window, at most
/// `section_cap` points per stop (see the `section` module). The window is simulated
/// again with the modes the classification built.
pub fn run_cell_with_sections(
    sys: &System,
    acc: &Accuracy,
    method: Method,
    y0: &[f64],
    section_cap: usize,
) -> (CellResult, Vec<Vec<Vec<f64>>>) {
    let no_sections = || vec![Vec::new(); sys.stops.len()];
    let stops = sys.stops.len();
    let symmetric = sys.model.symmetric;
    let unresolved = |reason: String, periods: u64, events: usize, y: Vec<f64>| CellResult {
        class: Class::Unresolved,
        n: None,
        labels: sys
            .model
            .labels
            .iter()
            .map(|l| MassLabel { mass: sys.model.masses[l.mass].name.clone(), npq: None, class: Class::Unresolved })
            .collect(),
        impacts: vec![0; stops],
        chatter: vec![false; stops],
        sticking: vec![false; stops],
        friction_stick: vec![false; sys.frictions.len()],
        symmetry: None,
        lyapunov: None,
        multiplier: None,
        window_start: y.clone(),
        final_state: y,
        section: Vec::new(),
        periods,
        events,
        reason: Some(reason),
    };
    let halt_reason = |h: Halt| match h {
        Halt::Budget => format!("event budget of {} events exhausted", acc.max_events),
        Halt::Stalled => "event location stalled at a degenerate contact".to_string(),
        Halt::Error(e) => e.to_string(),
    };
    let mut sim = match Simulator::new(sys, *acc, method, y0) {
        Ok(s) => s,
        Err(h) => return (unresolved(halt_reason(h), 0, 0, y0.to_vec()), no_sections()),
    };
    let mut hist: VecDeque<PeriodRecord> = VecDeque::with_capacity(history_len(acc) + 1);
    let mut found = None;
    let mut newton = Newton::default();
    // A record that ends without a period but still contracts (negative largest
    // Lyapunov exponent) is a long transient: it is extended. With an early look
    // (`chaos_check`), a clearly chaotic record ends there.
    let mut early_look = acc.chaos_check > 0 && acc.chaos_check < acc.max_periods && acc.lyapunov_periods > 0;
    let mut limit = if early_look { acc.chaos_check } else { acc.max_periods };
    let mut extensions = 0;
    let mut exponent: Option<(f64, Vec<DVector<f64>>)> = None;
    let mut tangent_work = (0u64, 0usize);
    loop {
        match record(&mut sim, &mut hist, &mut newton, limit, acc, symmetric) {
            Ok(Some(n)) => {
                found = Some(n);
                break;
            }
            Ok(None) => {}
            Err(h) => {
                let y = sim.y.as_slice().to_vec();
                return (unresolved(halt_reason(h), sim.periods, sim.events, y), no_sections());
            }
        }
        if acc.lyapunov_periods == 0 {
            break;
        }
        // Without a period: the largest Lyapunov exponent tells chaos from a torus,
        // and a contracting long transient from both.
        let mut tangent = sim.probe();
        let spent = sim.events + newton.events() + tangent_work.1;
        tangent.set_budget(acc.max_events.saturating_sub(spent));
        exponent = largest_exponent(&mut tangent, LYAPUNOV_WARMUP, acc.lyapunov_periods).ok();
        tangent_work = (tangent_work.0 + tangent.periods, tangent_work.1 + tangent.events);
        // Growth per forcing period decides: the record ends, or goes on to a new limit.
        let growth = exponent.as_ref().map(|(l, _)| l * sys.period);
        limit = if early_look {
            early_look = false;
            if growth.is_some_and(|g| g > CHAOTIC_EXPONENT) {
                break;
            }
            acc.max_periods
        } else if growth.is_some_and(|g| g < -CONTRACTING_EXPONENT) && extensions < acc.extensions {
            extensions += 1;
            newton.tries = 0;
            limit + acc.max_periods
        } else {
            break;
        };
    }
    let (mut extra_periods, mut extra_events) = newton.probe.map_or((0, 0), |p| (p.periods, p.events));
    extra_periods += tangent_work.0;
    extra_events += tangent_work.1;
    let mut class = if found.is_some() { Class::Periodic } else { Class::Chaotic };
    let mut lyapunov = None;
    let mut undecided = None;
    if let (None, Some((l, points))) = (found, &exponent) {
        lyapunov = Some(*l);
        (class, undecided) = without_period(l * sys.period, || fills_closed_curve(points));
    }
    // With a period: the stability of the orbit reached.
    let mut multiplier = None;
    if let (Some(n), true) = (found, acc.multipliers) {
        let mut tangent = sim.probe();
        tangent.set_budget(acc.max_events.saturating_sub(sim.events + extra_events));
        tangent.track_tangent();
        let x = sim.y.clone();
        if let Ok(image) = evaluate(&mut tangent, &x, MapKind::Periods(n)) {
            let mu = multipliers(&image.jacobian);
            multiplier = (!mu.is_empty()).then(|| spectral_radius(&mu));
        }
        extra_periods += tangent.periods;
        extra_events += tangent.events;
    }
    let len = hist.len();
    let window = found.unwrap_or(acc.n_max.min(len));
    let recs: Vec<&PeriodRecord> = hist.iter().skip(len - window).collect();
    let mut impacts = vec![0u32; stops];
    let (mut held, mut stuck) = (0u32, 0u32);
    for r in &recs {
        for (a, b) in impacts.iter_mut().zip(&r.impacts) {
            *a += b;
        }
        held |= r.held;
        stuck |= r.stuck;
    }
    let sticking: Vec<bool> = (0..stops).map(|k| held & (1 << k) != 0).collect();
    let chatter: Vec<bool> =
        (0..stops).map(|k| recs.iter().any(|r| r.impacts[k] as usize >= acc.chatter_impacts)).collect();
    let labels = label_masses(sys, found, class, &impacts, &sticking);
    let symmetry = match (symmetric, found) {
        (true, Some(n)) => Some(symmetry_of(&hist, n, acc)),
        _ => None,
    };
    let window_start = if len > window { hist[len - window - 1].end.as_slice().to_vec() } else { y0.to_vec() };
    let cell = CellResult {
        class,
        n: found,
        labels,
        impacts,
        chatter,
        sticking,
        friction_stick: (0..sys.frictions.len()).map(|i| stuck & (1 << i) != 0).collect(),
        symmetry,
        lyapunov,
        multiplier,
        final_state: sim.y.as_slice().to_vec(),
        window_start,
        section: recs.iter().map(|r| r.end.as_slice().to_vec()).collect(),
        periods: sim.periods + extra_periods,
        events: sim.events + extra_events,
        reason: undecided,
    };
    let sections = if section_cap == 0 {
        no_sections()
    } else {
        let mut probe = sim.probe();
        probe.set_budget(acc.max_events);
        record_window(&mut probe, &cell.window_start, cell.section.len(), &cell.impacts, section_cap)
    };
    (cell, sections)
}

/// The class of a cell without a period from its largest Lyapunov exponent
/// `growth = λT` per forcing period, and the reason when it is undecided:
/// chaotic only when the exponent is positive beyond the quasi-periodic band;
/// quasi-periodic inside the band when the period-section points lie on one
/// closed curve; otherwise (inside the band without a closed curve, or still
/// contracting after every extension: a transient longer than the record)
/// unresolved, never chaotic.
fn without_period(growth: f64, closed_curve: impl FnOnce() -> bool) -> (Class, Option<String>) {
    if growth > QUASIPERIODIC_EXPONENT {
        (Class::Chaotic, None)
    } else if growth < -QUASIPERIODIC_EXPONENT {
        let why = format!(
            "no period within the record, and the motion still contracts (λT = {growth:.3e}): a transient longer than max_periods x (1 + extensions)"
        );
        (Class::Unresolved, Some(why))
    } else if closed_curve() {
        (Class::Quasiperiodic, None)
    } else {
        let why = format!(
            "no period within the record; the largest Lyapunov exponent is in the quasi-periodic band (λT = {growth:.3e}) but the period section is not one closed curve"
        );
        (Class::Unresolved, Some(why))
    }
}

/// The n-p-q label of every labelled mass of a cell of class `class` from the
/// impacts per stop over n periods and the stops that held their mass (`None`:
/// no period found).
pub fn label_masses(
    sys: &System,
    n: Option<usize>,
    class: Class,
    impacts: &[u32],
    sticking: &[bool],
) -> Vec<MassLabel> {
    sys.model
        .labels
        .iter()
        .map(|l| {
            let count = |s: Option<usize>| match s {
                Some(k) if sticking[k] => Count::Stuck,
                Some(k) => Count::Impacts(impacts[k]),
                None => Count::Impacts(0),
            };
            MassLabel {
                mass: sys.model.masses[l.mass].name.clone(),
                npq: n.map(|n| (n as u32, count(l.p), count(l.q))),
                class,
            }
        })
        .collect()
}

/// Symmetric when, for some shift m, the state half a period after the start of
/// period j + m is the mirror image of the state at the start of period j.
fn symmetry_of(h: &VecDeque<PeriodRecord>, n: usize, acc: &Accuracy) -> Symmetry {
    let len = h.len();
    let tol = 10.0 * acc.periodic_tol;
    let mirrored = |j: usize, m: usize| match &h[j + m].half {
        Some(half) => close(half, &(-&h[j - 1].end), tol),
        None => false,
    };
    let symmetric = (0..n).any(|m| (len - 2 * n..len - n).all(|j| j >= 1 && mirrored(j, m)));
    if symmetric {
        Symmetry::Symmetric
    } else {
        Symmetry::Asymmetric
    }
}
