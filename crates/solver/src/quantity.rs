//! Quantities of the steady motion (issue 60): what a designer measures of a
//! cell, each declared once in [`TABLE`] and computed from the closed form of
//! the exact flow, never from samples of a plotted trace.
//!
//! Over a window of `W` forcing periods of length `T` (a periodic cell's `n`
//! periods of its orbit), with `x_i`, `v_i` a mass's position and velocity,
//! `g_k = n_k·x + c_k` a stop's gap and `w_j = n_j·v` a friction contact's
//! slip rate:
//!
//! - a position's extremes are its values at the window's ends, at events,
//!   and where its velocity vanishes (a root of the flow's velocity, refined
//!   to the last bits by regula falsi on the closed form); a velocity's and
//!   a contact force's extremes are refined by Brent's search, whose error
//!   in the value is quadratic in its error in time;
//! - means and integrals (`mean_x`, `rms_x`, `rms_v`, power, dissipation)
//!   are Gauss–Legendre quadratures over pieces of each flow segment no
//!   longer than one period of its fastest term, with the fewest nodes (2 to
//!   16) that integrate the piece to rounding, exact to rounding for the sums
//!   of exponentials and sinusoids the flow is made of;
//! - energy: the forcing's harmonics put in `∫ F(t)·v dt`; the mechanical
//!   energy `E = ½vᵀMv + ½xᵀKx − Lᵀx + Σ ½k g²` (pressed soft stops) changes
//!   by `ΔE`; damping takes `∫ vᵀCv dt`, soft stops `∫ c ġ² dt` and the
//!   spring energy they let go when a contact parts, friction `∫ f_k |w| dt`
//!   while slipping, and every impact (or stick, which is a plastic impact)
//!   the energy its jump removes. `energy_residual` is
//!   `input − ΔE − dissipated` relative to the largest energy at stake: what
//!   the forcing moved in and out (`∫|F·v| dt`), what was dissipated, and
//!   the mechanical energy at the window's ends (a lossless or unforced
//!   motion puts in nothing net): zero to rounding where the physics and
//!   its bookkeeping agree;
//! - a rigid stop's holding reaction `λ` (the constraint force of Newton's
//!   law on the held motion, affine in the mode's state) is integrated and
//!   peaked as a contact force is, and an impact's impulse is taken to the
//!   state once its event is handled (the end of a chatter sequence it
//!   ends included): over an orbit the mean force on every mass vanishes,
//!   so the stops' impulses and holding impulses make `T (K x̄ − L)`.
//!
//! Every quantity is per forcing period where it is a count or an integral.

use crate::accuracy::Accuracy;
use crate::contact::{Contact, Spring};
use crate::error::SolverError;
use crate::extremum::peak;
use crate::flow::Method;
use crate::label::Mask;
use crate::simulate::{EventObserver, Halt, Segment, Simulator};
use crate::system::System;
use nalgebra::DVector;
use scene::{Operand, Scales, MAX_STOPS};
use std::f64::consts::TAU;

/// What a quantity belongs to: one value per mass, per stop, per friction
/// contact, or one per cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Owner {
    /// Every mass, labelled or not.
    Mass,
    /// Every stop.
    Stop,
    /// Every rigid stop (restitution).
    RigidStop,
    /// Every soft stop (spring and dashpot).
    SoftStop,
    /// Every friction contact (`M1-M2`).
    Contact,
    /// The cell as a whole.
    Cell,
}

/// The dimension of a quantity, in the scene's (dimensionless) units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// A length.
    Length,
    /// A velocity (length per unit time).
    Velocity,
    /// A force.
    Force,
    /// An impulse per forcing period.
    ImpulsePerPeriod,
    /// A length per forcing period.
    LengthPerPeriod,
    /// A count per forcing period.
    PerPeriod,
    /// A share of time, 0 to 1.
    Fraction,
    /// A power (energy per unit time).
    Power,
    /// An energy per forcing period.
    EnergyPerPeriod,
    /// A pure number.
    One,
}

impl Dimension {
    /// What one scene unit of the dimension is physically, by the scene's
    /// `scales`: the factor and the CF units (`m/s`); `None` for a pure
    /// number or a count, or where a scale it needs is not given (the
    /// quantity stays in the scene's dimensionless units, `1`).
    pub fn scale(self, scales: &Scales) -> Option<(f64, String)> {
        let (l, t, f) = (scales.length.as_ref(), scales.time.as_ref(), scales.force.as_ref());
        match self {
            Dimension::Length | Dimension::LengthPerPeriod => l.map(|l| (l.value, l.units.clone())),
            Dimension::Velocity => Some((l?.value / t?.value, format!("{}/{}", l?.units, t?.units))),
            Dimension::Force => f.map(|f| (f.value, f.units.clone())),
            Dimension::ImpulsePerPeriod => Some((f?.value * t?.value, format!("{} {}", f?.units, t?.units))),
            Dimension::Power => {
                Some((f?.value * l?.value / t?.value, format!("{} {}/{}", f?.units, l?.units, t?.units)))
            }
            Dimension::EnergyPerPeriod => Some((f?.value * l?.value, format!("{} {}", f?.units, l?.units))),
            Dimension::PerPeriod | Dimension::Fraction | Dimension::One => None,
        }
    }

    /// The CF `units` of the dimension by the scene's `scales`: its
    /// physical units ([`Dimension::scale`]), else `1`.
    pub fn units(self, scales: &Scales) -> String {
        self.scale(scales).map_or_else(|| "1".to_string(), |(_, u)| u)
    }
}

/// One quantity of the table.
#[derive(Debug, Clone, Copy)]
pub struct Spec {
    /// Its name's stem: the name is `<stem>_<owner>` (`max_abs_x_M1`), or the
    /// stem alone for a quantity of the cell.
    pub stem: &'static str,
    /// What it belongs to.
    pub owner: Owner,
    /// Its symbol (`max |x|`).
    pub symbol: &'static str,
    /// Its long name (the CF `long_name`, before the owner's name).
    pub long_name: &'static str,
    /// Its dimension.
    pub dimension: Dimension,
    /// What the window's sums make of it ([`Meter::value`]).
    measure: Measure,
}

impl Spec {
    /// Its symbol and long name for an owner that is a soft stop where they
    /// differ from a rigid one's: a soft stop's events are contacts begun,
    /// and their speed is the speed at which a contact starts.
    pub fn words(&self, soft: bool) -> (&'static str, &'static str) {
        match (self.measure, soft) {
            (Measure::ImpactRate, true) => ("contacts per period", "contacts begun per forcing period at"),
            (Measure::ImpactSpeedMax, true) => {
                ("max contact speed", "largest normal speed at the start of a contact at")
            }
            (Measure::ImpactSpeedMean, true) => {
                ("mean contact speed", "mean normal speed at the start of a contact at")
            }
            _ => (self.symbol, self.long_name),
        }
    }
}

/// How a quantity is made of a window's sums: one variant per entry of
/// [`TABLE`], so that an entry without its computation does not compile.
#[derive(Debug, Clone, Copy)]
enum Measure {
    MaxAbsX,
    PtpX,
    MeanX,
    RmsX,
    MaxAbsV,
    RmsV,
    ImpactRate,
    ImpactSpeedMax,
    ImpactSpeedMean,
    Impulse,
    HeldFraction,
    HoldImpulse,
    HoldForceMax,
    ContactForceMax,
    ContactFraction,
    StuckFraction,
    Slip,
    PowerIn,
    DissipatedImpacts,
    DissipatedContacts,
    DissipatedDamping,
    DissipatedFriction,
    EnergyResidual,
}

macro_rules! table {
    ($( $measure:ident: $stem:literal, $owner:ident, $symbol:literal, $long:literal, $dim:ident; )*) => {
        /// Every quantity of the steady motion, in the order files, JSON and
        /// tables list them.
        pub const TABLE: &[Spec] = &[$(
            Spec {
                stem: $stem,
                owner: Owner::$owner,
                symbol: $symbol,
                long_name: $long,
                dimension: Dimension::$dim,
                measure: Measure::$measure,
            },
        )*];
    };
}

table! {
    MaxAbsX: "max_abs_x", Mass, "max |x|", "largest |position| of", Length;
    PtpX: "ptp_x", Mass, "x peak-to-peak", "peak-to-peak position of", Length;
    MeanX: "mean_x", Mass, "mean x", "mean position of", Length;
    RmsX: "rms_x", Mass, "rms x", "root mean square of the position about its mean of", Length;
    MaxAbsV: "max_abs_v", Mass, "max |v|", "largest |velocity| of", Velocity;
    RmsV: "rms_v", Mass, "rms v", "root mean square velocity of", Velocity;
    ImpactRate: "impact_rate", Stop, "impacts per period", "impacts per forcing period at", PerPeriod;
    ImpactSpeedMax: "impact_speed_max", Stop, "max impact speed", "largest normal speed before an impact at", Velocity;
    ImpactSpeedMean: "impact_speed_mean", Stop, "mean impact speed", "mean normal speed before an impact at", Velocity;
    Impulse: "impulse", RigidStop, "impulse per period", "impulse per forcing period of", ImpulsePerPeriod;
    HeldFraction: "stick_fraction", RigidStop, "share held", "share of time holding its mass of", Fraction;
    HoldImpulse: "hold_impulse", RigidStop, "holding impulse per period", "impulse of the holding reaction per forcing period of", ImpulsePerPeriod;
    HoldForceMax: "hold_force_max", RigidStop, "max holding force", "largest holding reaction of", Force;
    ContactForceMax: "contact_force_max", SoftStop, "max contact force", "largest contact force of", Force;
    ContactFraction: "contact_fraction", SoftStop, "share in contact", "share of time in contact of", Fraction;
    StuckFraction: "stick_fraction", Contact, "share stuck", "share of time stuck of friction contact", Fraction;
    Slip: "slip", Contact, "slip per period", "slip distance per forcing period of friction contact", LengthPerPeriod;
    PowerIn: "power_in", Cell, "P in", "mean input power of the forcing", Power;
    DissipatedImpacts: "dissipated_impacts", Cell, "D impacts", "energy dissipated by impacts per forcing period", EnergyPerPeriod;
    DissipatedContacts: "dissipated_contacts", Cell, "D contacts", "energy dissipated by soft contacts per forcing period", EnergyPerPeriod;
    DissipatedDamping: "dissipated_damping", Cell, "D damping", "energy dissipated by damping per forcing period", EnergyPerPeriod;
    DissipatedFriction: "dissipated_friction", Cell, "D friction", "energy dissipated by friction per forcing period", EnergyPerPeriod;
    EnergyResidual: "energy_residual", Cell, "energy residual", "input minus change and dissipation, relative to the energy at stake", One;
}

/// Forcing periods of a window without a period over which its quantities
/// are taken: the first of the cell's classification window (the last
/// `n_max` periods of its record).
pub const APERIODIC_WINDOW: usize = 16;

/// Names of a system's quantities with their specs, in [`TABLE`]'s order,
/// each spec's owners in the scene's order: `max_abs_x_M1`, `max_abs_x_M2`,
/// …, `power_in`, ….
pub fn names(sys: &System) -> Vec<(String, &'static Spec)> {
    let model = &sys.model;
    let contacts: Vec<String> = (0..model.friction.len()).map(|i| sys.friction_name(i)).collect();
    let mut out = Vec::new();
    for spec in TABLE {
        let owners: Vec<&str> = match spec.owner {
            Owner::Mass => model.masses.iter().map(|m| m.name.as_str()).collect(),
            Owner::Stop => model.stops.iter().map(|s| s.name.as_str()).collect(),
            Owner::RigidStop => model.stops.iter().filter(|s| s.law.impacts()).map(|s| s.name.as_str()).collect(),
            Owner::SoftStop => {
                model.stops.iter().filter(|s| s.law.spring().is_some()).map(|s| s.name.as_str()).collect()
            }
            Owner::Contact => contacts.iter().map(String::as_str).collect(),
            Owner::Cell => {
                out.push((spec.stem.to_string(), spec));
                continue;
            }
        };
        out.extend(owners.into_iter().map(|o| (format!("{}_{o}", spec.stem), spec)));
    }
    out
}

/// Every quantity a system measures: the built-in ones ([`names`]), then
/// those its scene defines (`[quantities]`, [`scene::Derived`]), in the
/// order of [`Quantities`].
pub fn all_names(sys: &System) -> Vec<String> {
    let built_in = names(sys).into_iter().map(|(n, _)| n);
    built_in.chain(sys.model.quantities.iter().map(|d| d.name.clone())).collect()
}

/// The quantities of a window, in the order of [`all_names`] ([`named`]
/// names them).
pub type Quantities = Vec<f64>;

/// `values` of `sys`'s quantities by name.
pub fn named(sys: &System, values: &[f64]) -> Vec<(String, f64)> {
    all_names(sys).into_iter().zip(values.iter().copied()).collect()
}

/// Per quantity the scene defines, where the value of each of its operands
/// is found in `[parameters…, built-in quantities…]`; an operand that is
/// neither, or a quantity named like a built-in one, is refused naming its
/// field.
pub(crate) fn resolve(sys: &System) -> Result<Vec<Vec<usize>>, SolverError> {
    if sys.model.quantities.is_empty() {
        return Ok(Vec::new());
    }
    let built_in: Vec<String> = names(sys).into_iter().map(|(n, _)| n).collect();
    let params = sys.model.parameters.len();
    sys.model
        .quantities
        .iter()
        .map(|d| {
            let refuse = |field: String, message: String| SolverError::Unsupported { field, message };
            if built_in.contains(&d.name) {
                return Err(refuse(
                    format!("quantities.{}", d.name),
                    format!(
                        "'{}' is a built-in quantity of this scene; a quantity it defines needs a name of its own",
                        d.name
                    ),
                ));
            }
            d.operands()
                .iter()
                .map(|o| match o {
                    Operand::Parameter(k) => Ok(*k),
                    Operand::Quantity(name) => {
                        built_in.iter().position(|b| b == name).map(|k| params + k).ok_or_else(|| {
                            // A name with a '-' reads as a subtraction unless it is in braces.
                            let braced = built_in.iter().find(|b| b.contains('-') && d.source.contains(b.as_str()));
                            let hint = braced.map_or(String::new(), |b| format!("; write '{b}' in braces: {{{b}}}"));
                            refuse(
                                format!("quantities.{}.value", d.name),
                                format!(
                                    "unknown parameter or quantity '{name}' in expression '{}'{hint} (its quantities: {})",
                                    d.source,
                                    built_in.join(", ")
                                ),
                            )
                        })
                    }
                })
                .collect()
        })
        .collect()
}

/// `built_in` (the values of [`names`]) followed by the quantities the
/// scene defines, computed from them and the parameters.
fn with_derived(sys: &System, mut built_in: Quantities) -> Quantities {
    if sys.model.quantities.is_empty() {
        return built_in;
    }
    let operand = |k: usize, built_in: &[f64]| {
        sys.model.parameters.get(k).map_or_else(|| built_in[k - sys.model.parameters.len()], |p| p.1)
    };
    let derived: Vec<f64> = sys
        .model
        .quantities
        .iter()
        .zip(&sys.derived)
        .map(|(d, at)| d.eval(&at.iter().map(|&k| operand(k, &built_in)).collect::<Vec<f64>>()))
        .collect();
    built_in.extend(derived);
    built_in
}

/// Measures the quantities of the motion that starts at full state `y0` (at
/// a whole number of forcing periods) over the next `periods` periods, by the
/// exact flow whatever the cell's integrator.
pub fn measure(sys: &System, acc: &Accuracy, y0: &[f64], periods: usize) -> Result<Quantities, Halt> {
    measure_on(&mut Simulator::new(sys, *acc, Method::Exact, y0)?, y0, periods)
}

/// [`measure`] on a simulator of the exact flow (its modes kept), restarted
/// at `y0`.
pub(crate) fn measure_on(sim: &mut Simulator<'_>, y0: &[f64], periods: usize) -> Result<Quantities, Halt> {
    sim.restart(y0)?;
    let mut meter = Meter::new(sim.system(), periods.max(1));
    for _ in 0..periods.max(1) {
        sim.run_period(&[], false, &mut meter)?;
    }
    Ok(meter.finish(periods.max(1)))
}

/// A Gauss–Legendre rule on [-1, 1]: its nodes and weights, and the
/// longest piece it integrates to rounding, as the phase `θ = h r` its
/// fastest term (rate r) turns through over the piece (length h).
struct Rule {
    points: Vec<(f64, f64)>,
    reach: f64,
}

/// Nodes of the rules, the fewest first.
const RULE_NODES: [usize; 8] = [2, 3, 4, 6, 8, 10, 12, 16];

/// The rules of [`RULE_NODES`], nodes by Newton's method on the Legendre
/// polynomial (to rounding). A rule of n nodes integrates `e^{iΘ}` over a
/// piece with the error `Θ^{2n} (n!)⁴ / ((2n+1) ((2n)!)³)`; its reach is the
/// θ at which a product of two terms (`x²`, `vᵀCv`: Θ = 2θ) is integrated to
/// 1e-14 of its size (about a hundred ulps). 12 nodes reach 5.0 rad, 16
/// nodes 9.1, more than one period of the fastest term.
fn rules() -> &'static [Rule] {
    static RULES: std::sync::OnceLock<Vec<Rule>> = std::sync::OnceLock::new();
    RULES.get_or_init(|| RULE_NODES.iter().map(|&n| rule(n)).collect())
}

fn rule(nodes: usize) -> Rule {
    let n = nodes as f64;
    let factorial = |k: usize| (1..=k).map(|j| j as f64).product::<f64>();
    let bound = 1e-14 * (2.0 * n + 1.0) * factorial(2 * nodes).powi(3) / factorial(nodes).powi(4);
    let points = (0..nodes)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and its derivative by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=nodes {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() <= 1e-16 {
                    break;
                }
            }
            (-x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect();
    Rule { points, reach: 0.5 * bound.powf(0.5 / n) }
}

/// Per stop, what its impacts and contacts add up to.
#[derive(Debug, Clone, Default)]
struct StopSums {
    impacts: u64,
    speed_max: f64,
    speed_sum: f64,
    impulse: f64,
    held_time: f64,
    /// `∫λ dt` of the holding reaction, and its largest value.
    hold_impulse: f64,
    hold_force_max: f64,
    pressed_time: f64,
    force_max: f64,
}

/// A flow segment's end, as the next segment's start is weighed against it.
#[derive(Clone, Copy)]
struct SegmentEnd {
    /// Mechanical energy, and its pressed soft springs' part.
    energy: f64,
    soft: f64,
    /// Pressed and parting soft stops (bit k).
    pressed: u32,
    parting: u32,
}

/// The observer that adds the window up.
pub(crate) struct Meter<'s> {
    sys: &'s System,
    /// Per mass: smallest and largest position, largest |velocity|.
    x_min: Vec<f64>,
    x_max: Vec<f64>,
    v_abs_max: Vec<f64>,
    /// Per mass: the reference position the sums are taken about (the first
    /// state's), `∫(x − r)`, `∫(x − r)²`, `∫v²`.
    x_ref: Option<Vec<f64>>,
    int_x: Vec<f64>,
    int_x2: Vec<f64>,
    int_v2: Vec<f64>,
    stops: Vec<StopSums>,
    /// Per friction contact: time stuck, `∫|w|`.
    stuck_time: Vec<f64>,
    slip: Vec<f64>,
    /// Energy: input, damping, soft contacts, friction, events.
    input: f64,
    /// The energy the forcing moved in and out, `∫|F·v| dt`.
    gross: f64,
    damping: f64,
    contacts: f64,
    friction: f64,
    events: f64,
    /// Where the last segment ended, and the mechanical energy at the
    /// window's start.
    last: Option<SegmentEnd>,
    first: Option<f64>,
    time: f64,
    /// The window's length: segments and impacts after it are not counted.
    limit: f64,
    y: DVector<f64>,
    nodes: Vec<(f64, DVector<f64>)>,
    /// The held stops' reactions at a piece's points, stop by stop (buffer).
    reactions: Vec<f64>,
    /// The rigid stop of the impact being handled, and its normal rate
    /// before it.
    struck: Option<(usize, f64)>,
    /// Per stop, the time left until a cut chatter sequence would have
    /// accumulated ([`EventObserver::accumulates`]): the simulation holds the
    /// mass from the cut, the true motion bounces on the stop until then, so
    /// that span is counted as impacts' (their impulse), not as the hold's
    /// (its time, impulse and largest reaction).
    tails: Vec<f64>,
}

impl<'s> Meter<'s> {
    /// A meter of a window of `periods` forcing periods of `sys`'s motion
    /// (what follows the window is not counted), empty.
    pub(crate) fn new(sys: &'s System, periods: usize) -> Meter<'s> {
        let (m, s, f) = (sys.dof(), sys.stops.len(), sys.frictions.len());
        Meter {
            sys,
            x_min: vec![f64::INFINITY; m],
            x_max: vec![f64::NEG_INFINITY; m],
            v_abs_max: vec![0.0; m],
            x_ref: None,
            int_x: vec![0.0; m],
            int_x2: vec![0.0; m],
            int_v2: vec![0.0; m],
            stops: vec![StopSums::default(); s],
            stuck_time: vec![0.0; f],
            slip: vec![0.0; f],
            input: 0.0,
            gross: 0.0,
            damping: 0.0,
            contacts: 0.0,
            friction: 0.0,
            events: 0.0,
            last: None,
            first: None,
            time: 0.0,
            limit: periods as f64 * sys.period * (1.0 - 1e-12),
            y: DVector::zeros(2 * m),
            nodes: Vec::new(),
            reactions: Vec::new(),
            struck: None,
            tails: vec![0.0; s],
        }
    }

    /// The soft springs' energy `Σ ½ k g²` of the pressed stops at `y`.
    fn spring_energy(&self, y: &DVector<f64>, pressed: u32) -> f64 {
        (self.sys.stops.iter().enumerate())
            .filter(|(k, _)| pressed & (1 << k) != 0)
            .map(|(k, row)| row.law.spring().map_or(0.0, |spring| spring.energy(self.sys.gap(k, y))))
            .sum()
    }

    /// The mechanical energy at `y`: kinetic, the links' springs, the loads'
    /// potential and the pressed soft stops' springs.
    fn energy(&self, y: &DVector<f64>, pressed: u32) -> (f64, f64) {
        let sys = self.sys;
        let m = sys.dof();
        let (x, v) = (y.rows(0, m), y.rows(m, m));
        let kinetic: f64 = (0..m).map(|i| 0.5 * sys.mass[i] * v[i] * v[i]).sum();
        let springs = 0.5 * quadratic(&sys.stiffness, x.as_slice());
        let springs_soft = self.spring_energy(y, pressed);
        (kinetic + springs - sys.load.dot(&x) + springs_soft, springs_soft)
    }

    /// The forcing `F(t)` (harmonics only; the loads are in the potential)
    /// at the phase `φ = ω t + τ`, dotted with `v`.
    fn forcing_power(&self, phase: f64, y: &DVector<f64>) -> f64 {
        let m = self.sys.dof();
        let v = y.rows(m, m);
        (1..)
            .zip(&self.sys.harmonics)
            .map(|(k, [p, q]): (i32, _)| {
                let (s, c) = crate::spectral::sin_cos(f64::from(k) * phase);
                s * p.dot(&v) + c * q.dot(&v)
            })
            .sum()
    }

    /// The positions' and velocities' extremes at `y`.
    fn extremes_at(&mut self, y: &DVector<f64>) {
        let m = self.sys.dof();
        for i in 0..m {
            self.x_min[i] = self.x_min[i].min(y[i]);
            self.x_max[i] = self.x_max[i].max(y[i]);
            self.v_abs_max[i] = self.v_abs_max[i].max(y[m + i].abs());
        }
    }

    /// Adds the integrands at `y` (phase `phase`, the segment's contact state)
    /// with quadrature weight `w`.
    fn integrate(&mut self, y: &DVector<f64>, phase: f64, seg: (u32, u32), w: f64) {
        let sys = self.sys;
        let m = sys.dof();
        let x_ref = self.x_ref.as_ref().expect("set at the first segment");
        for i in 0..m {
            let d = y[i] - x_ref[i];
            self.int_x[i] += w * d;
            self.int_x2[i] += w * d * d;
            self.int_v2[i] += w * y[m + i] * y[m + i];
        }
        let v = y.rows(m, m);
        self.damping += w * quadratic(&sys.damping, v.as_slice());
        let power = self.forcing_power(phase, y);
        self.input += w * power;
        self.gross += w * power.abs();
        let (stuck, pressed) = seg;
        for (k, row) in sys.stops.iter().enumerate().filter(|(k, _)| pressed & (1 << k) != 0) {
            if let Some(Spring { damping, .. }) = row.law.spring() {
                let rate = sys.gap_rate(k, y);
                self.contacts += w * damping * rate * rate;
            }
        }
        for (j, row) in sys.frictions.iter().enumerate().filter(|(j, _)| stuck & (1 << j) == 0) {
            let rate = sys.slip_rate(j, y).abs();
            self.slip[j] += w * rate;
            self.friction += w * row.kinetic * rate;
        }
    }

    /// The values of the window, in the order of [`all_names`]: the table's
    /// order, each spec's owners in the scene's order, then the quantities
    /// the scene defines.
    pub(crate) fn finish(self, periods: usize) -> Quantities {
        let sys = self.sys;
        let stops = |soft: Option<bool>| {
            (0..sys.stops.len()).filter(move |&k| soft.is_none_or(|soft| sys.stops[k].law.spring().is_some() == soft))
        };
        let mut values = Vec::with_capacity(TABLE.len() * sys.dof().max(sys.stops.len()));
        // Where the scene gives its scales, each spec's values and the factor
        // to physical units they take once the quantities the scene defines
        // have read them in its own units.
        let mut factors = Vec::new();
        for spec in TABLE {
            let owners: Box<dyn Iterator<Item = usize>> = match spec.owner {
                Owner::Mass => Box::new(0..sys.dof()),
                Owner::Stop => Box::new(stops(None)),
                Owner::RigidStop => Box::new(stops(Some(false))),
                Owner::SoftStop => Box::new(stops(Some(true))),
                Owner::Contact => Box::new(0..sys.frictions.len()),
                Owner::Cell => Box::new(0..1),
            };
            let first = values.len();
            values.extend(owners.map(|k| self.value(spec.measure, k, periods as f64)));
            if let Some((factor, _)) = spec.dimension.scale(&sys.model.scales) {
                factors.push((first..values.len(), factor));
            }
        }
        let mut all = with_derived(sys, values);
        for (range, factor) in factors {
            all[range].iter_mut().for_each(|v| *v *= factor);
        }
        all
    }

    /// Quantity `measure` of owner `k` (a mass, stop or friction contact;
    /// 0 for the cell) over a window of `periods` forcing periods.
    fn value(&self, measure: Measure, k: usize, periods: f64) -> f64 {
        let t = self.time;
        let mean = |k: usize| self.int_x[k] / t;
        let s = self.stops.get(k);
        let stop = |f: fn(&StopSums) -> f64| s.map_or(0.0, f);
        match measure {
            Measure::MaxAbsX => self.x_max[k].abs().max(self.x_min[k].abs()),
            Measure::PtpX => self.x_max[k] - self.x_min[k],
            Measure::MeanX => self.x_ref.as_ref().map_or(0.0, |r| r[k]) + mean(k),
            Measure::RmsX => (self.int_x2[k] / t - mean(k) * mean(k)).max(0.0).sqrt(),
            Measure::MaxAbsV => self.v_abs_max[k],
            Measure::RmsV => (self.int_v2[k] / t).sqrt(),
            Measure::ImpactRate => stop(|s| s.impacts as f64) / periods,
            Measure::ImpactSpeedMax => stop(|s| s.speed_max),
            Measure::ImpactSpeedMean => stop(|s| if s.impacts == 0 { 0.0 } else { s.speed_sum / s.impacts as f64 }),
            Measure::Impulse => stop(|s| s.impulse) / periods,
            Measure::HeldFraction => stop(|s| s.held_time) / t,
            Measure::HoldImpulse => stop(|s| s.hold_impulse) / periods,
            Measure::HoldForceMax => stop(|s| s.hold_force_max),
            Measure::ContactForceMax => stop(|s| s.force_max),
            Measure::ContactFraction => stop(|s| s.pressed_time) / t,
            Measure::StuckFraction => self.stuck_time[k] / t,
            Measure::Slip => self.slip[k] / periods,
            Measure::PowerIn => self.input / t,
            Measure::DissipatedImpacts => self.events / periods,
            Measure::DissipatedContacts => self.contacts / periods,
            Measure::DissipatedDamping => self.damping / periods,
            Measure::DissipatedFriction => self.friction / periods,
            Measure::EnergyResidual => {
                let (end, start) = (self.last.map_or(0.0, |l| l.energy), self.first.unwrap_or(0.0));
                let dissipated = self.damping + self.contacts + self.friction + self.events;
                // The largest energy at stake: a lossless or unforced motion
                // puts in nothing net, and its balance is measured against
                // what flows and what it holds.
                let scale = self.gross.max(dissipated.abs()).max(end.abs()).max(start.abs()).max(f64::MIN_POSITIVE);
                (self.input - (end - start) - dissipated) / scale
            }
        }
    }
}

impl EventObserver for Meter<'_> {
    fn impact(&mut self, _time: f64, stop: usize, before: &DVector<f64>, _after: &DVector<f64>) {
        if self.time >= self.limit {
            return;
        }
        let sys = self.sys;
        let speed = -sys.gap_rate(stop, before);
        let s = &mut self.stops[stop];
        s.impacts += 1;
        s.speed_max = s.speed_max.max(speed);
        s.speed_sum += speed;
        if sys.stops[stop].law.impacts() {
            self.struck = Some((stop, sys.gap_rate(stop, before)));
        }
    }

    fn accumulates(&mut self, stop: usize, time: f64, until: f64) {
        if self.time < self.limit {
            self.tails[stop] = (until - time).max(0.0);
        }
    }

    /// An impact's impulse, from the normal rate before it to the rate once
    /// the event is handled: the rest of a chatter sequence that ends in it
    /// (its rebound taken out, the mass held) is that stop's impulse too,
    /// and with it the impulses and the holding reactions balance the mean
    /// forces on the masses over an orbit.
    fn event(&mut self, _time: f64, y: &DVector<f64>) {
        if let Some((stop, before)) = self.struck.take() {
            let sys = self.sys;
            self.stops[stop].impulse += (sys.gap_rate(stop, y) - before).abs() / sys.stops[stop].inv_effective_mass;
        }
    }

    fn wants_segments(&self) -> bool {
        true
    }

    fn segment(&mut self, seg: &mut Segment<'_>) {
        if self.time >= self.limit {
            return;
        }
        let sys = self.sys;
        let m = sys.dof();
        let mut y = std::mem::take(&mut self.y);
        seg.state(0.0, &mut y);
        if self.x_ref.is_none() {
            self.x_ref = Some(y.rows(0, m).iter().copied().collect());
        }
        // The energy an event removed: the last segment's end against this
        // start. A soft stop that stopped pressing with its gap closed (it
        // parts) let its spring's energy go, and one that presses again from
        // parting takes it back; an impulse at a rigid stop took the rest.
        // Elsewhere the two states are one state evaluated twice, and their
        // difference is rounding, left to the residual: without rigid stops
        // no event dissipates, and `dissipated_impacts` is exactly 0.
        let (e, soft) = self.energy(&y, seg.pressed);
        match self.last {
            None => self.first = Some(e),
            Some(end) => {
                let parted = (end.pressed ^ seg.pressed) & (end.parting | seg.parting) != 0;
                let soft_jump = if parted { end.soft - soft } else { 0.0 };
                self.contacts += soft_jump;
                if sys.has_rigid_stops() {
                    self.events += end.energy - e - soft_jump;
                }
            }
        }
        self.extremes_at(&y);
        // Pieces no longer than one period of the fastest term (the forcing's
        // highest harmonic included) and a quarter of the forcing period, each
        // with the fewest nodes that integrate it to rounding.
        let fastest = seg.fastest().max(sys.omega * sys.harmonics.len() as f64);
        let longest = (TAU / fastest).min(sys.period / 4.0);
        let all = rules();
        let mut nodes = std::mem::take(&mut self.nodes);
        // Parts of the segment: one, but where a held stop's chatter tail
        // ends within it (the hold counted from there on).
        let held = Mask::from_bits(seg.held);
        let (mut ends, mut parts) = ([0.0; MAX_STOPS + 1], 0);
        for t in held.indices().map(|k| self.tails[k]).filter(|&t| t > 0.0 && t < seg.span) {
            ends[parts] = t;
            parts += 1;
        }
        ends[parts] = seg.span;
        ends[..=parts].sort_by(f64::total_cmp);
        let mut from = 0.0;
        for &to in &ends[..=parts] {
            if to <= from {
                continue;
            }
            let pieces = ((to - from) / longest).ceil().max(1.0) as usize;
            let h = (to - from) / pieces as f64;
            let rule = all.iter().find(|r| h * fastest <= r.reach).unwrap_or(&all[all.len() - 1]);
            let count = rule.points.len();
            // The piece's points, its start, the nodes and its end (buffers kept).
            nodes.resize_with(count + 2, || (0.0, DVector::zeros(2 * m)));
            nodes[0].0 = from;
            if from > 0.0 {
                seg.state(from, &mut y);
            }
            nodes[0].1.copy_from(&y);
            // The held stops' reactions at the points, stop by stop: read where
            // each point's state was just evaluated (the part's start above).
            let stride = count + 2;
            self.reactions.resize(seg.held.count_ones() as usize * stride, 0.0);
            self.note_reactions(seg, 0, stride);
            // The held stops still in their chatter's tail over this part.
            let tail = held.indices().filter(|&k| self.tails[k] >= to).fold(0u32, |t, k| t | 1 << k);
            for p in 0..pieces {
                let (a, b) = (from + p as f64 * h, if p + 1 == pieces { to } else { from + (p + 1) as f64 * h });
                for (k, &(node, weight)) in rule.points.iter().enumerate() {
                    let u = a + 0.5 * (b - a) * (1.0 + node);
                    let (at, state) = &mut nodes[k + 1];
                    *at = u;
                    seg.state(u, state);
                    self.note_reactions(seg, k + 1, stride);
                    let phase = sys.omega * (seg.clock + u) + sys.tau;
                    self.integrate(state, phase, (seg.stuck, seg.pressed), 0.5 * (b - a) * weight);
                    self.extremes_at(state);
                }
                let (at, end) = &mut nodes[count + 1];
                *at = b;
                seg.state(b, end);
                self.note_reactions(seg, count + 1, stride);
                self.extremes_at(end);
                self.refine(seg, &nodes[..count + 2], &mut y);
                self.hold(seg, &nodes[..count + 2], &rule.points, 0.5 * (b - a), tail, &mut y);
                // The next piece starts where this one ends.
                nodes.swap(0, count + 1);
                for values in self.reactions.chunks_mut(stride) {
                    values[0] = values[count + 1];
                }
            }
            from = to;
        }
        for (k, s) in self.stops.iter_mut().enumerate() {
            if seg.held & (1 << k) != 0 {
                s.held_time += seg.span - self.tails[k].min(seg.span);
            }
            if seg.pressed & (1 << k) != 0 {
                s.pressed_time += seg.span;
            }
        }
        for (j, t) in self.stuck_time.iter_mut().enumerate() {
            if seg.stuck & (1 << j) != 0 {
                *t += seg.span;
            }
        }
        for t in &mut self.tails {
            *t = (*t - seg.span).max(0.0);
        }
        self.time += seg.span;
        // The segment's end: the last piece's (now first of the points).
        let (energy, soft) = self.energy(&nodes[0].1, seg.pressed);
        self.last = Some(SegmentEnd { energy, soft, pressed: seg.pressed, parting: seg.parting });
        self.nodes = nodes;
        self.y = y;
    }
}

impl Meter<'_> {
    /// The extremes between the points of a piece (`nodes`, ascending in
    /// time): a position's where its velocity changes sign (regula falsi on
    /// the closed form), a velocity's and a pressed soft stop's force where
    /// an inner point is the largest (Brent's search).
    fn refine(&mut self, seg: &mut Segment<'_>, nodes: &[(f64, DVector<f64>)], y: &mut DVector<f64>) {
        let m = self.sys.dof();
        for i in 0..m {
            for pair in nodes.windows(2) {
                let ((ua, ya), (ub, yb)) = (&pair[0], &pair[1]);
                let (va, vb) = (ya[m + i], yb[m + i]);
                if va * vb >= 0.0 {
                    continue;
                }
                // The extreme lies within the speed times the bracket of its
                // points (twice that, for a velocity not monotone there): one
                // that cannot pass the extremes known is not refined.
                let (xa, xb, reach) = (ya[i], yb[i], 2.0 * va.abs().max(vb.abs()) * (ub - ua));
                let passes =
                    if va > 0.0 { xa.max(xb) + reach >= self.x_max[i] } else { xa.min(xb) - reach <= self.x_min[i] };
                if passes {
                    let x = root(seg, *ua, *ub, va, vb, m + i, y, i);
                    self.x_min[i] = self.x_min[i].min(x);
                    self.x_max[i] = self.x_max[i].max(x);
                }
            }
            let v_abs = |_: &Segment<'_>, y: &DVector<f64>| y[m + i].abs();
            let at_node = |j: usize| nodes[j].1[m + i].abs();
            if let (_, Some(bracket)) = node_peak(seg, nodes, at_node, v_abs, self.v_abs_max[i], y) {
                let best = peak(seg, bracket, y, v_abs);
                self.v_abs_max[i] = self.v_abs_max[i].max(best);
            }
        }
        for k in 0..self.sys.stops.len() {
            if seg.pressed & (1 << k) == 0 {
                continue;
            }
            let force = |_: &Segment<'_>, y: &DVector<f64>| self.sys.contact_force(k, y);
            let at_node = |j: usize| self.sys.contact_force(k, &nodes[j].1);
            let (mut best, bracket) = node_peak(seg, nodes, at_node, force, self.stops[k].force_max, y);
            if let Some(bracket) = bracket {
                best = best.max(peak(seg, bracket, y, force));
            }
            self.stops[k].force_max = self.stops[k].force_max.max(best);
        }
    }

    /// The reactions of the stops that `seg` holds, at the state it last
    /// evaluated, as point `at` of a piece (of `stride` points) in
    /// [`Meter::hold`]'s buffer.
    fn note_reactions(&mut self, seg: &Segment<'_>, at: usize, stride: usize) {
        for (j, k) in Mask::from_bits(seg.held).indices().enumerate() {
            self.reactions[j * stride + at] = seg.reaction(k).unwrap_or(0.0);
        }
    }

    /// The reactions of the stops that hold their masses over a piece of
    /// `seg` (its points `nodes`, ascending in time: its start, `points`'
    /// nodes with their weights, its end, where [`Meter::note_reactions`]
    /// read them; `half` its half length): their impulse `∫λ dt` by the
    /// rule, exact to rounding as the flow's other integrals, and their
    /// largest value, refined as a contact force is. The reaction is an
    /// affine function of the mode's state, so the closed form gives it
    /// anywhere.
    fn hold(
        &mut self,
        seg: &mut Segment<'_>,
        nodes: &[(f64, DVector<f64>)],
        points: &[(f64, f64)],
        half: f64,
        tail: u32,
        y: &mut DVector<f64>,
    ) {
        let all = std::mem::take(&mut self.reactions);
        for (k, values) in Mask::from_bits(seg.held).indices().zip(all.chunks(nodes.len())) {
            let sums = &mut self.stops[k];
            let impulse = half * points.iter().zip(&values[1..]).map(|(&(_, w), v)| w * v).sum::<f64>();
            if tail & (1 << k) != 0 {
                // Within a cut chatter's tail, the bounces' impulse.
                sums.impulse += impulse;
                continue;
            }
            sums.hold_impulse += impulse;
            let reaction = |seg: &Segment<'_>, _: &DVector<f64>| seg.reaction(k).unwrap_or(0.0);
            let (mut best, bracket) = node_peak(seg, nodes, |j| values[j], reaction, sums.hold_force_max, y);
            if let Some(bracket) = bracket {
                best = best.max(peak(seg, bracket, y, reaction));
            }
            self.stops[k].hold_force_max = self.stops[k].hold_force_max.max(best);
        }
        self.reactions = all;
    }
}

/// `zᵀ A z` of a square matrix `a`, without allocating.
fn quadratic(a: &nalgebra::DMatrix<f64>, z: &[f64]) -> f64 {
    (0..z.len()).map(|i| z[i] * (0..z.len()).map(|j| a[(i, j)] * z[j]).sum::<f64>()).sum()
}

/// The largest value of a function at the points of `nodes` (a piece of
/// `seg`, ascending in time; `at_node(j)` its value at point j, `f` its
/// value at the state `seg` last evaluated), and the bracket that holds a
/// larger one, if it may
/// pass `known` (the peak of a smooth function between points no farther
/// apart than a sixth of its oscillation exceeds the largest of them by
/// less than a quarter): around an inner point; and between an end and its
/// neighbour where `f` still rises into the piece from that end, a peak
/// just before an impact or across a piece's boundary (the symmetric
/// stops' `max_abs_v_M1` at their default read 1.1715001 at the impact
/// that ends the segment, 1.1715112 at its peak 3e-3 before it). That rise
/// is told `1e-6` of the bracket inside the end: a peak nearer the end
/// than half of that exceeds it by less than `1e-13` of its value.
fn node_peak(
    seg: &mut Segment<'_>,
    nodes: &[(f64, DVector<f64>)],
    at_node: impl Fn(usize) -> f64,
    f: impl Fn(&Segment<'_>, &DVector<f64>) -> f64,
    known: f64,
    y: &mut DVector<f64>,
) -> (f64, Option<(f64, f64)>) {
    let (mut best, mut value) = (0, f64::NEG_INFINITY);
    for k in 0..nodes.len() {
        let v = at_node(k);
        if v > value {
            (best, value) = (k, v);
        }
    }
    let last = nodes.len() - 1;
    if 1.25 * value < known || last == 0 {
        return (value, None);
    }
    if best > 0 && best < last {
        return (value, Some((nodes[best - 1].0, nodes[best + 1].0)));
    }
    let (end, next) = if best == 0 { (nodes[0].0, nodes[1].0) } else { (nodes[last].0, nodes[last - 1].0) };
    seg.state(end + 1e-6 * (next - end), y);
    (value, (f(seg, y) > value).then_some((end.min(next), end.max(next))))
}

/// Position `i` where velocity component `k` of the state vanishes between
/// `ua` (value `va`) and `ub` (`vb`, of the other sign): regula falsi
/// (Illinois) on the closed form, to the last bits of the time.
#[allow(clippy::too_many_arguments)]
fn root(seg: &mut Segment<'_>, ua: f64, ub: f64, va: f64, vb: f64, k: usize, y: &mut DVector<f64>, i: usize) -> f64 {
    let (mut a, mut b, mut fa, mut fb) = (ua, ub, va, vb);
    // Which end the last two steps kept: the Illinois step halves the other's value.
    let mut kept = 0i8;
    let mut u = 0.5 * (a + b);
    for _ in 0..100 {
        u = (a * fb - b * fa) / (fb - fa);
        if !(u > a && u < b) {
            u = 0.5 * (a + b);
        }
        seg.state(u, y);
        let fu = y[k];
        if fu == 0.0 || b - a <= 4.0 * f64::EPSILON * b.abs().max(1.0) {
            break;
        }
        if (fu < 0.0) == (fa < 0.0) {
            (a, fa) = (u, fu);
            if kept == 1 {
                fb *= 0.5;
            }
            kept = 1;
        } else {
            (b, fb) = (u, fu);
            if kept == -1 {
                fa *= 0.5;
            }
            kept = -1;
        }
    }
    seg.state(u, y);
    y[i]
}
