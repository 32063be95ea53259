//! Accuracy knobs: one `Copy` struct built from a named preset and overridable.
//!
//! Every field states its unit (times are in the dimensionless time of the
//! equations, displacements and velocities in their dimensionless units), its
//! `standard` default and what it trades.

use crate::error::SolverError;
use scene::Named;

scene::named_enum! {
    /// Named accuracy presets.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Preset {
        /// Looser tolerances and shorter records: the quick look.
        Fast = "fast",
        /// The default: labels agree with `precise` on nearly every cell.
        Standard = "standard",
        /// Tight tolerances and long records: the reference.
        Precise = "precise",
    }
}

/// The kind of value a knob takes: its type and lower bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnobKind {
    /// A number > 0.
    Positive,
    /// A number >= 0.
    NonNegative,
    /// A whole number >= 1.
    Count,
    /// A whole number >= 0.
    Whole,
    /// 0 (off) or 1 (on).
    Switch,
}

/// A knob's value in its field's type, and back to the number it is given as.
trait KnobValue: Copy {
    fn to_f64(self) -> f64;
    fn from_f64(v: f64) -> Self;
}
impl KnobValue for f64 {
    fn to_f64(self) -> f64 {
        self
    }
    fn from_f64(v: f64) -> Self {
        v
    }
}
impl KnobValue for usize {
    fn to_f64(self) -> f64 {
        self as f64
    }
    fn from_f64(v: f64) -> Self {
        v as usize
    }
}
impl KnobValue for bool {
    fn to_f64(self) -> f64 {
        f64::from(u8::from(self))
    }
    fn from_f64(v: f64) -> Self {
        v.to_bits() == 1f64.to_bits()
    }
}

/// The one table of accuracy knobs: from each row come the [`Knob`] variant,
/// the [`Accuracy`] field and its getter, its name (in `--accuracy NAME=V`,
/// Python's `accuracy={…}` and the files' `accuracy` attribute), its kind,
/// its largest value and why, and a floor for the RK4 steps. Rows are in the
/// order the files list the knobs.
macro_rules! knobs {
    ($(
        $(#[doc = $doc:literal])*
        $variant:ident $field:ident: $ty:ty, $kind:ident, max $max:expr, $why:literal $(, floor $floor:expr)?;
    )*) => {
        /// An accuracy knob (see the field of [`Accuracy`] of the same name).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum Knob {
            $($(#[doc = $doc])* $variant,)*
        }

        /// Every knob in the order files list them, named as its field (`event_tol`, …).
        impl Named for Knob {
            const ALL: &'static [Knob] = &[$(Knob::$variant),*];

            fn name(self) -> &'static str {
                match self {
                    $(Knob::$variant => stringify!($field),)*
                }
            }

            fn help(self) -> &'static str {
                match self {
                    $(Knob::$variant => concat!($($doc),*).trim_ascii(),)*
                }
            }
        }

        impl Knob {
            /// The knob of a name, or an error naming it as unknown (and the
            /// knob meant, where one is close).
            pub fn named(name: &str) -> Result<Knob, SolverError> {
                Knob::parse(name).ok_or_else(|| SolverError::Accuracy {
                    field: name.to_string(),
                    message: format!("unknown accuracy knob{}", Knob::meant(name)),
                })
            }

            /// The kind of value it takes.
            pub fn kind(self) -> KnobKind {
                match self {
                    $(Knob::$variant => KnobKind::$kind,)*
                }
            }

            /// Its largest value, and what a larger one would do: sizes bound
            /// the memory and time of one cell, tolerances must stay below the
            /// scale of the motion (of order one in the dimensionless models).
            pub fn max(self) -> (f64, &'static str) {
                match self {
                    $(Knob::$variant => ($max, $why),)*
                }
            }

            /// Its smallest value beyond its kind's bound (the RK4 steps:
            /// smaller ones take hours per cell).
            pub fn floor(self) -> Option<f64> {
                match self {
                    $(Knob::$variant => None $(.or(Some($floor)))?,)*
                }
            }
        }

        /// All accuracy knobs of a cell simulation. Built from a [`Preset`];
        /// a knob is changed only through [`Accuracy::with`] or
        /// [`Accuracy::set`], which check it against its [`Knob`]'s kind and
        /// limits, and read through its getter.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct Accuracy {
            $($(#[doc = $doc])* pub(crate) $field: $ty,)*
        }

        impl Accuracy {
            $(
                #[doc = concat!("The `", stringify!($field), "` knob (see [`Knob::", stringify!($variant), "`]).")]
                pub fn $field(&self) -> $ty {
                    self.$field
                }
            )*

            /// The value of a knob as a number (switches as 0 or 1).
            pub fn get(&self, knob: Knob) -> f64 {
                match knob {
                    $(Knob::$variant => KnobValue::to_f64(self.$field),)*
                }
            }

            /// Stores a value already checked against the knob's kind.
            fn put(&mut self, knob: Knob, value: f64) {
                match knob {
                    $(Knob::$variant => self.$field = KnobValue::from_f64(value),)*
                }
            }
        }
    };
}

knobs! {
    /// Time tolerance of event location (standard 1e-12). Smaller costs a few more
    /// advancement steps per event.
    EventTol event_tol: f64, Positive, max 1e-3, "a coarser event time is no longer an event";
    /// A gap below this counts as contact (standard 1e-11). It is also the largest
    /// penetration of a stop the solver allows.
    ContactTol contact_tol: f64, Positive, max 1e-3, "a coarser contact is a visible penetration";
    /// Impacts with a normal velocity below this are plastic and may start sticking
    /// (standard 1e-7). Larger ends chatter sooner and cheaper, and less exactly.
    StickVelocity stick_velocity: f64, Positive, max 1e-1, "faster impacts would be plastic";
    /// Jump to the accumulation point of a geometric chatter sequence once its
    /// impact velocity is below this (standard 1e-4; 0 disables the jump).
    ChatterVelocity chatter_velocity: f64, NonNegative, max 1.0, "every impact would end a chatter sequence";
    /// Periods always simulated before periodicity is tested (standard 8).
    MinTransient min_transient: usize, Count, max 1e6, "time per cell";
    /// Periods after which a cell without a period is declared non-periodic
    /// (standard 600). Longer finds slowly converging orbits; costs linearly.
    MaxPeriods max_periods: usize, Count, max 1e7, "time per cell";
    /// Two period-section points closer than this (max norm, relative to
    /// 1 + |state|) are the same point (standard 1e-7).
    PeriodicTol periodic_tol: f64, Positive, max 1e-2, "distinct points would count as one";
    /// Largest period n tested in the record, in forcing periods (standard
    /// 32): the limit of period detection and of Newton acceleration. A
    /// record that contracts onto a longer orbit (up to 128 periods) is not
    /// extended: Newton's method on that period's map confirms the orbit and
    /// the cell is labelled with it, or it ends `unresolved`, naming it.
    NMax n_max: usize, Count, max 1e4, "memory of the period history";
    /// Impacts at one stop in n periods from which a motion is flagged chattering (6).
    ChatterImpacts chatter_impacts: usize, Count, max 1e6, "no motion chatters beyond it";
    /// Event budget of one cell; past it the cell is `unresolved` (standard
    /// 1 600 000: the 102 400 periods a record is measured for at most in a
    /// scene that dissipates nothing, at 16 events a period). It bounds the
    /// time of a cell; the periods of a record, not the budget, limit every
    /// ordinary one. RK4's steps count against it, a fraction of an event
    /// each (`flow::rk4`).
    MaxEvents max_events: usize, Count, max 1e10, "time per cell";
    /// Accelerate slowly contracting transients by Newton's method on the period
    /// map once the impact pattern repeats (standard and fast: on; precise: off,
    /// so that the reference is plain simulation).
    Newton newton: bool, Switch, max 1.0, "a switch";
    /// Measure the largest Floquet multiplier modulus of periodic cells (the
    /// exact Jacobian over n more periods; standard: on, 0 or 1 as a knob).
    Multipliers multipliers: bool, Switch, max 1.0, "a switch";
    /// Times the record of a cell without a period is extended by `max_periods`
    /// when its largest Lyapunov exponent shows it still contracting (a long
    /// transient, `λT < -0.002`), or chaotic-looking while its record passes
    /// near a stable periodic orbit (a chaotic transient that may yet settle):
    /// standard and precise 4, fast 1. Costs only on such cells.
    Extensions extensions: usize, Whole, max 1e3, "time per cell";
    /// Periods over which the largest Lyapunov exponent of a cell without a
    /// period is measured (standard 100; 0 skips it and leaves such cells `C`),
    /// doubled while its interval contains 0, at most `2 + extensions / 2`
    /// times (standard 4, fast 2). Costs about as much as that many periods of
    /// simulation, with tangents.
    LyapunovPeriods lyapunov_periods: usize, Whole, max 1e6, "memory of the section points kept for the exponent";
    /// Periods after which a cell without a period has its largest Lyapunov
    /// exponent measured early (standard and fast 100; precise 0: off, the
    /// reference simulates every record in full). A clearly chaotic cell
    /// (`λT > 0.05`, its interval above 0, no stable orbit near its record)
    /// ends there as `C` instead of simulating the rest of `max_periods`; any
    /// other goes on. Saves most of the record of chaotic cells and costs one
    /// more Lyapunov measurement on slow transients; a chaotic transient that
    /// would settle on an orbit its record has not come near stays `C`. On by default since the trade measured its
    /// label agreement with `precise` above RK4's (99.70 % against 99.65 %
    /// on 2026-11-29; docs/performance.md).
    ChaosCheck chaos_check: usize, Whole, max 1e7, "beyond max_periods it never acts";
    /// Step of the RK4 integrator (0.01, the literature's value).
    Rk4Step rk4_step: f64, Positive, max 1.0, "RK4 would be unstable", floor 1e-5;
    /// RK4 refines a crossing by dividing the step by 10 until it is below this (1e-10).
    Rk4MinStep rk4_min_step: f64, Positive, max 1.0, "above the step", floor 1e-15;
}

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
            max_events: 1_600_000,
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

    /// Every knob by name with its value, in the order of [`Knob::ALL`]
    /// (switches as 0 or 1), for provenance.
    pub fn knobs(&self) -> Vec<(&'static str, f64)> {
        Knob::ALL.iter().map(|&k| (k.name(), self.get(k))).collect()
    }

    /// These knobs with `knob` set to `value` ([`Accuracy::set`]).
    pub fn with(mut self, knob: Knob, value: f64) -> Result<Accuracy, SolverError> {
        self.set(knob, value)?;
        Ok(self)
    }

    /// Sets a knob by its name (`--accuracy NAME=VALUE`).
    pub fn set_named(&mut self, name: &str, value: f64) -> Result<(), SolverError> {
        self.set(Knob::named(name)?, value)
    }

    /// Sets a knob, checked against its kind and limits; `max_periods` must
    /// stay at least `min_transient`.
    pub fn set(&mut self, knob: Knob, value: f64) -> Result<(), SolverError> {
        let err = |m: String| SolverError::Accuracy { field: knob.name().to_string(), message: m };
        if !value.is_finite() {
            return Err(err(format!("must be a finite number, got {value}")));
        }
        let whole = value.fract() == 0.0;
        match knob.kind() {
            KnobKind::Positive if value <= 0.0 => return Err(err("must be > 0".into())),
            KnobKind::NonNegative if value < 0.0 => return Err(err(format!("must be >= 0, got {value}"))),
            KnobKind::Count if !whole || value < 1.0 => {
                return Err(err(format!("must be a whole number >= 1, got {value}")))
            }
            KnobKind::Whole if !whole || value < 0.0 => {
                return Err(err(format!("must be a whole number >= 0, got {value}")))
            }
            // Switches given as numbers: exactly 0 or 1.
            KnobKind::Switch if value.to_bits() != 0f64.to_bits() && value.to_bits() != 1f64.to_bits() => {
                return Err(err(format!("must be 0 or 1, got {value}")))
            }
            _ => {}
        }
        let (max, why) = knob.max();
        if value > max {
            return Err(err(format!("at most {max:e} ({why}), got {value:e}")));
        }
        if let Some(floor) = knob.floor().filter(|&f| value < f) {
            return Err(err(format!("at least {floor:e} (smaller steps take hours per cell), got {value:e}")));
        }
        let before = *self;
        self.put(knob, value);
        if self.max_periods < self.min_transient {
            *self = before;
            return Err(err("max_periods must be >= min_transient".into()));
        }
        Ok(())
    }
}

impl Default for Accuracy {
    fn default() -> Self {
        Accuracy::preset(Preset::Standard)
    }
}

impl std::fmt::Display for Knob {
    /// The knob's name (`event_tol`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every knob of every preset, written by `knobs()` (as files store them),
    /// reads back through `set_named` to the same settings; and a value past
    /// each knob's limit, or of the wrong kind, is refused naming the knob.
    #[test]
    fn knobs_round_trip_by_name_and_refuse_bad_values() {
        for preset in [Preset::Fast, Preset::Standard, Preset::Precise] {
            let acc = Accuracy::preset(preset);
            // Start from another preset so that every knob that differs must be set.
            let mut back = Accuracy::preset(if preset == Preset::Precise { Preset::Fast } else { Preset::Precise });
            let written = acc.knobs();
            assert_eq!(written.len(), Knob::ALL.len());
            // max_periods before min_transient could be refused midway: set in an order that keeps it valid.
            let mut rows = written.clone();
            rows.sort_by_key(|(k, _)| *k != "max_periods");
            for (name, value) in rows {
                back.set_named(name, value).unwrap();
            }
            assert_eq!(back, acc, "{preset:?}");
        }
        for &k in Knob::ALL {
            let mut a = Accuracy::default();
            let (max, _) = k.max();
            let e = a.set(k, max * 2.0 + 1.0).unwrap_err().to_string();
            assert!(e.contains(k.name()), "{e}");
            assert_eq!(a, Accuracy::default(), "a refused value leaves the knobs as they were");
            let wrong = match k.kind() {
                KnobKind::Positive => 0.0,
                KnobKind::NonNegative => -1.0,
                KnobKind::Count => 0.5,
                KnobKind::Whole => -1.0,
                KnobKind::Switch => 0.5,
            };
            assert!(a.set(k, wrong).is_err(), "{} accepted {wrong}", k.name());
            assert_eq!(Knob::parse(k.name()), Some(k));
        }
        assert!(Accuracy::default().set_named("no_such_knob", 1.0).is_err());
    }
}
