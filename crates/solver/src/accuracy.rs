//! Accuracy knobs: one `Copy` struct built from a named preset and overridable.
//!
//! Every field states its unit (times are in the dimensionless time of the
//! equations, displacements and velocities in their dimensionless units), its
//! `standard` default and what it trades.

use crate::error::SolverError;

/// Named accuracy presets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// Looser tolerances and shorter records: the quick look.
    Fast,
    /// The default: labels agree with `precise` on nearly every cell.
    Standard,
    /// Tight tolerances and long records: the reference.
    Precise,
}

impl Preset {
    /// Parses `fast`, `standard` or `precise`.
    pub fn parse(name: &str) -> Option<Preset> {
        match name {
            "fast" => Some(Preset::Fast),
            "standard" => Some(Preset::Standard),
            "precise" => Some(Preset::Precise),
            _ => None,
        }
    }

    /// The preset's name.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Fast => "fast",
            Preset::Standard => "standard",
            Preset::Precise => "precise",
        }
    }
}

/// All accuracy knobs of a cell simulation. Built from a [`Preset`]; a knob
/// is changed only through [`Accuracy::set`] (or [`Accuracy::with`]), which
/// checks it against [`LIMITS`], and read through its getter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accuracy {
    /// Time tolerance of event location (standard 1e-12). Smaller costs a few more
    /// advancement steps per event.
    pub(crate) event_tol: f64,
    /// A gap below this counts as contact (standard 1e-11). It is also the largest
    /// penetration of a stop the solver allows.
    pub(crate) contact_tol: f64,
    /// Impacts with a normal velocity below this are plastic and may start sticking
    /// (standard 1e-7). Larger ends chatter sooner and cheaper, and less exactly.
    pub(crate) stick_velocity: f64,
    /// Jump to the accumulation point of a geometric chatter sequence once its
    /// impact velocity is below this (standard 1e-4; 0 disables the jump).
    pub(crate) chatter_velocity: f64,
    /// Periods always simulated before periodicity is tested (standard 8).
    pub(crate) min_transient: usize,
    /// Periods after which a cell without a period is declared non-periodic
    /// (standard 600). Longer finds slowly converging orbits; costs linearly.
    pub(crate) max_periods: usize,
    /// Two period-section points closer than this (max norm, relative to
    /// 1 + |state|) are the same point (standard 1e-7).
    pub(crate) periodic_tol: f64,
    /// Largest period n tested in the record, in forcing periods (standard
    /// 32): the limit of period detection and of Newton acceleration. A
    /// record that contracts onto a longer orbit (up to 128 periods) is not
    /// extended: Newton's method on that period's map confirms the orbit and
    /// the cell is labelled with it, or it ends `unresolved`, naming it.
    pub(crate) n_max: usize,
    /// Impacts at one stop in n periods from which a motion is flagged chattering (6).
    pub(crate) chatter_impacts: usize,
    /// Event budget of one cell; past it the cell is `unresolved` (standard 400 000).
    /// RK4's steps count against it, a fraction of an event each (`flow::rk4`).
    pub(crate) max_events: usize,
    /// Accelerate slowly contracting transients by Newton's method on the period
    /// map once the impact pattern repeats (standard and fast: on; precise: off,
    /// so that the reference is plain simulation).
    pub(crate) newton: bool,
    /// Periods over which the largest Lyapunov exponent of a cell without a
    /// period is measured (standard 100; 0 skips it and leaves such cells `C`).
    /// Costs about as much as that many periods of simulation, with tangents.
    pub(crate) lyapunov_periods: usize,
    /// Periods after which a cell without a period has its largest Lyapunov
    /// exponent measured early (standard and fast 100; precise 0: off, the
    /// reference simulates every record in full). A clearly chaotic cell
    /// (`λT > 0.05`, five times the quasi-periodic band) ends there as `C`
    /// instead of simulating the rest of `max_periods`; any other goes on.
    /// Saves most of the record of chaotic cells and costs one more Lyapunov
    /// measurement on slow transients; a chaotic transient that would settle on
    /// an orbit later stays `C`. On by default since the trade measured its
    /// label agreement with `precise` above RK4's (docs/performance.md).
    pub(crate) chaos_check: usize,
    /// Times the record of a cell without a period is extended by `max_periods`
    /// when its largest Lyapunov exponent shows it still contracting (a long
    /// transient, `λT < -0.002`): standard and precise 4, fast 1. Costs only on
    /// such cells.
    pub(crate) extensions: usize,
    /// Measure the largest Floquet multiplier modulus of periodic cells (the
    /// exact Jacobian over n more periods; standard: on, 0 or 1 as a knob).
    pub(crate) multipliers: bool,
    /// Step of the RK4 integrator (0.01, the literature's value).
    pub(crate) rk4_step: f64,
    /// RK4 refines a crossing by dividing the step by 10 until it is below this (1e-10).
    pub(crate) rk4_min_step: f64,
}

/// Largest value of each knob, and what a larger one would do: sizes bound the
/// memory and time of one cell, tolerances must stay below the scale of the
/// motion (of order one in the dimensionless models).
pub const LIMITS: [(&str, f64, &str); 17] = [
    ("event_tol", 1e-3, "a coarser event time is no longer an event"),
    ("contact_tol", 1e-3, "a coarser contact is a visible penetration"),
    ("stick_velocity", 1e-1, "faster impacts would be plastic"),
    ("chatter_velocity", 1.0, "every impact would end a chatter sequence"),
    ("min_transient", 1e6, "time per cell"),
    ("max_periods", 1e7, "time per cell"),
    ("periodic_tol", 1e-2, "distinct points would count as one"),
    ("n_max", 1e4, "memory of the period history"),
    ("chatter_impacts", 1e6, "no motion chatters beyond it"),
    ("max_events", 1e10, "time per cell"),
    ("newton", 1.0, "a switch"),
    ("multipliers", 1.0, "a switch"),
    ("extensions", 1e3, "time per cell"),
    ("lyapunov_periods", 1e6, "memory of the section points kept for the exponent"),
    ("chaos_check", 1e7, "beyond max_periods it never acts"),
    ("rk4_step", 1.0, "RK4 would be unstable"),
    ("rk4_min_step", 1.0, "above the step"),
];

impl Accuracy {
    /// The knobs of a preset.
    pub fn preset(p: Preset) -> Accuracy {
        let standard = Accuracy {
            event_tol: 1e-12,
            contact_tol: 1e-11,
            stick_velocity: 1e-7,
            chatter_velocity: 1e-4,
            min_transient: 8,
            max_periods: 600,
            periodic_tol: 1e-7,
            n_max: 32,
            chatter_impacts: 6,
            max_events: 400_000,
            newton: true,
            lyapunov_periods: 100,
            chaos_check: 100,
            extensions: 4,
            multipliers: true,
            rk4_step: 0.01,
            rk4_min_step: 1e-10,
        };
        match p {
            Preset::Standard => standard,
            Preset::Fast => Accuracy {
                event_tol: 1e-10,
                contact_tol: 1e-9,
                stick_velocity: 1e-6,
                chatter_velocity: 1e-3,
                min_transient: 4,
                max_periods: 300,
                periodic_tol: 1e-6,
                max_events: 100_000,
                extensions: 1,
                ..standard
            },
            Preset::Precise => Accuracy {
                event_tol: 1e-14,
                contact_tol: 1e-12,
                stick_velocity: 1e-9,
                chatter_velocity: 1e-6,
                min_transient: 32,
                max_periods: 3000,
                periodic_tol: 1e-9,
                max_events: 4_000_000,
                newton: false,
                chaos_check: 0,
                ..standard
            },
        }
    }

    /// Every knob by name with its value, in the order of [`LIMITS`]
    /// (switches as 0 or 1), for provenance.
    pub fn knobs(&self) -> Vec<(&'static str, f64)> {
        let v = [
            self.event_tol,
            self.contact_tol,
            self.stick_velocity,
            self.chatter_velocity,
            self.min_transient as f64,
            self.max_periods as f64,
            self.periodic_tol,
            self.n_max as f64,
            self.chatter_impacts as f64,
            self.max_events as f64,
            f64::from(u8::from(self.newton)),
            f64::from(u8::from(self.multipliers)),
            self.extensions as f64,
            self.lyapunov_periods as f64,
            self.chaos_check as f64,
            self.rk4_step,
            self.rk4_min_step,
        ];
        LIMITS.iter().map(|l| l.0).zip(v).collect()
    }

    /// These knobs with `name` set to `value` ([`Accuracy::set`]).
    pub fn with(mut self, name: &str, value: f64) -> Result<Accuracy, SolverError> {
        self.set(name, value)?;
        Ok(self)
    }

    /// Sets a knob by name (for `--accuracy name=value` overrides).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), SolverError> {
        let err = |m: &str| SolverError::Accuracy { field: name.to_string(), message: m.to_string() };
        // Each kind of knob states its own lower bound (a count's is 1).
        if !value.is_finite() {
            return Err(err(&format!("must be a finite number, got {value}")));
        }
        let count = || -> Result<usize, SolverError> {
            if value.fract() != 0.0 || value < 1.0 {
                Err(err(&format!("must be a whole number >= 1, got {value}")))
            } else {
                Ok(value as usize)
            }
        };
        let whole = || {
            if value.fract() != 0.0 || value < 0.0 {
                Err(err(&format!("must be a whole number >= 0, got {value}")))
            } else {
                Ok(value as usize)
            }
        };
        let switch = || match value.to_bits() {
            b if b == 0f64.to_bits() => Ok(false),
            b if b == 1f64.to_bits() => Ok(true),
            _ => Err(err(&format!("must be 0 or 1, got {value}"))),
        };
        let nonnegative = || {
            if value >= 0.0 {
                Ok(value)
            } else {
                Err(err(&format!("must be >= 0, got {value}")))
            }
        };
        let positive = || {
            if value > 0.0 {
                Ok(value)
            } else {
                Err(err("must be > 0"))
            }
        };
        if let Some(&(_, max, why)) = LIMITS.iter().find(|(k, _, _)| *k == name) {
            if value > max {
                return Err(err(&format!("at most {max:e} ({why}), got {value:e}")));
            }
        }
        // RK4 steps below these take hours per cell.
        let floor = match name {
            "rk4_step" => Some(1e-5),
            "rk4_min_step" => Some(1e-15),
            _ => None,
        };
        if let Some(floor) = floor.filter(|&f| value < f) {
            return Err(err(&format!("at least {floor:e} (smaller steps take hours per cell), got {value:e}")));
        }
        match name {
            "event_tol" => self.event_tol = positive()?,
            "contact_tol" => self.contact_tol = positive()?,
            "stick_velocity" => self.stick_velocity = positive()?,
            "chatter_velocity" => self.chatter_velocity = nonnegative()?,
            "min_transient" => self.min_transient = count()?,
            "max_periods" => self.max_periods = count()?,
            "periodic_tol" => self.periodic_tol = positive()?,
            "n_max" => self.n_max = count()?,
            "chatter_impacts" => self.chatter_impacts = count()?,
            "max_events" => self.max_events = count()?,
            // Switches given as numbers: exactly 0 or 1.
            "newton" => self.newton = switch()?,
            "multipliers" => self.multipliers = switch()?,
            "extensions" => self.extensions = whole()?,
            "lyapunov_periods" => self.lyapunov_periods = whole()?,
            "chaos_check" => self.chaos_check = whole()?,
            "rk4_step" => self.rk4_step = positive()?,
            "rk4_min_step" => self.rk4_min_step = positive()?,
            _ => return Err(err("unknown accuracy knob")),
        }
        if self.max_periods < self.min_transient {
            return Err(err("max_periods must be >= min_transient"));
        }
        Ok(())
    }
}

/// Read-only getters of the knobs, one per field, named after it.
macro_rules! getters {
    ($($name:ident: $ty:ty,)*) => {
        impl Accuracy {
            $(
                #[doc = concat!("The `", stringify!($name), "` knob (documented on the field and in docs/scenes.md).")]
                pub fn $name(&self) -> $ty {
                    self.$name
                }
            )*
        }
    };
}

getters! {
    event_tol: f64,
    contact_tol: f64,
    stick_velocity: f64,
    chatter_velocity: f64,
    min_transient: usize,
    max_periods: usize,
    periodic_tol: f64,
    n_max: usize,
    chatter_impacts: usize,
    max_events: usize,
    newton: bool,
    lyapunov_periods: usize,
    chaos_check: usize,
    extensions: usize,
    multipliers: bool,
    rk4_step: f64,
    rk4_min_step: f64,
}

impl Default for Accuracy {
    fn default() -> Self {
        Accuracy::preset(Preset::Standard)
    }
}
