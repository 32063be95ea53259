//! What a cell's steady motion is called: its [`Class`], the n-p-q [`Label`]
//! of each labelled mass, the [`Symmetry`] of a periodic orbit, and [`Mask`],
//! the set of stops (or friction contacts) that chattered, stuck or held.
//!
//! A label is kept as these types from the solver to the store, which encodes
//! it; its `Display` is the one place that writes it as text.

use crate::contact::Contact;
use crate::system::System;

/// Kind of steady motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Class {
    /// Periodic with period n forcing periods.
    Periodic,
    /// No period up to `n_max` within the record and a largest Lyapunov
    /// exponent beyond the quasi-periodic band (written `C`).
    Chaotic,
    /// No period, a zero largest Lyapunov exponent and period-section points on
    /// a closed curve: motion on an invariant torus (written `Q`).
    Quasiperiodic,
    /// Not decided: the event budget ran out, an event search stalled, or the
    /// exponent could not tell (see [`crate::Unresolved`]).
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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

/// The n-p-q label of one mass in one cell; prints as `1-4-4`, `1-S-S`, `C`,
/// `Q` or `U`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Label {
    /// A periodic motion of period `n` forcing periods, with `p` and `q` the
    /// counts at the mass's p-stop and q-stop over those n periods.
    Periodic {
        /// Period in forcing periods.
        n: u32,
        /// Count at the p-stop.
        p: Count,
        /// Count at the q-stop.
        q: Count,
    },
    /// Chaotic (`C`).
    Chaotic,
    /// Quasi-periodic (`Q`).
    Quasiperiodic,
    /// Unresolved (`U`).
    Unresolved,
}

impl Label {
    /// The label of a mass in a cell of class `class`, with `(n, p, q)` when
    /// periodic (a periodic class without counts is not a label: `C`).
    pub fn new(class: Class, npq: Option<(u32, Count, Count)>) -> Label {
        match (class, npq) {
            (Class::Periodic, Some((n, p, q))) => Label::Periodic { n, p, q },
            (Class::Unresolved, _) => Label::Unresolved,
            (Class::Quasiperiodic, _) => Label::Quasiperiodic,
            _ => Label::Chaotic,
        }
    }

    /// The class the label belongs to.
    pub fn class(self) -> Class {
        match self {
            Label::Periodic { .. } => Class::Periodic,
            Label::Chaotic => Class::Chaotic,
            Label::Quasiperiodic => Class::Quasiperiodic,
            Label::Unresolved => Class::Unresolved,
        }
    }

    /// `(n, p, q)` of a periodic label.
    pub fn npq(self) -> Option<(u32, Count, Count)> {
        match self {
            Label::Periodic { n, p, q } => Some((n, p, q)),
            _ => None,
        }
    }
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Label::Periodic { n, p, q } => write!(f, "{n}-{p}-{q}"),
            Label::Chaotic => write!(f, "C"),
            Label::Quasiperiodic => write!(f, "Q"),
            Label::Unresolved => write!(f, "U"),
        }
    }
}

impl std::str::FromStr for Label {
    type Err = String;

    /// Reads a label as it prints (`1-4-4`, `2-S-1`, `C`, `Q`, `U`): the one
    /// grammar of labels for files and colours.
    fn from_str(text: &str) -> Result<Label, String> {
        let bad = || format!("'{text}' is not a label (n-p-q, C, Q or U)");
        match text {
            "C" => return Ok(Label::Chaotic),
            "Q" => return Ok(Label::Quasiperiodic),
            "U" => return Ok(Label::Unresolved),
            _ => {}
        }
        let parts: Vec<&str> = text.split('-').collect();
        let [n, p, q] = parts[..] else { return Err(bad()) };
        let count = |s: &str| match s {
            "S" => Ok(Count::Stuck),
            _ => s.parse().map(Count::Impacts).map_err(|_| bad()),
        };
        let n: u32 = n.parse().map_err(|_| bad())?;
        if n == 0 {
            return Err(bad());
        }
        Ok(Label::Periodic { n, p: count(p)?, q: count(q)? })
    }
}

/// The label of a named mass; prints as its [`Label`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MassLabel {
    /// Mass name.
    pub mass: String,
    /// Its label.
    pub label: Label,
}

impl std::fmt::Display for MassLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.label.fmt(f)
    }
}

/// A set of stops or of friction contacts: bit k holds index k (at most 32;
/// a system has at most 16 stops and 8 contacts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Mask(u32);

impl Mask {
    /// The empty set.
    pub const EMPTY: Mask = Mask(0);

    /// The set of the bits of `bits`.
    pub fn from_bits(bits: u32) -> Mask {
        Mask(bits)
    }

    /// The bits (bit k: index k is in the set).
    pub fn bits(self) -> u32 {
        self.0
    }

    /// Whether index `k` is in the set.
    pub fn contains(self, k: usize) -> bool {
        k < 32 && self.0 & (1 << k) != 0
    }

    /// The indices in the set, ascending.
    pub fn indices(self) -> impl Iterator<Item = usize> {
        let mut bits = self.0;
        std::iter::from_fn(move || {
            (bits != 0).then(|| {
                let k = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                k
            })
        })
    }

    /// The set of the indices `k < len` for which `f(k)` holds.
    pub fn of(len: usize, f: impl Fn(usize) -> bool) -> Mask {
        Mask((0..len.min(32)).filter(|&k| f(k)).fold(0, |m, k| m | (1 << k)))
    }
}

/// The n-p-q label of every labelled mass of a cell of class `class`, from
/// the impacts per stop over n periods and the stops that held their mass
/// (`S`; a soft stop only when its contact never separated: no contact begun
/// in the n periods); `n` is `None` when no period was found.
pub fn label_masses(sys: &System, n: Option<usize>, class: Class, impacts: &[u32], held: Mask) -> Vec<MassLabel> {
    sys.model
        .labels
        .iter()
        .map(|l| {
            let count = |s: Option<usize>| match s {
                Some(k) if held.contains(k) && (sys.stops[k].law.impacts() || impacts[k] == 0) => Count::Stuck,
                Some(k) => Count::Impacts(impacts[k]),
                None => Count::Impacts(0),
            };
            MassLabel {
                mass: sys.model.masses[l.mass].name.clone(),
                label: Label::new(class, n.map(|n| (n as u32, count(Some(l.p)), count(l.q)))),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every label reads back from the text it prints as; other texts are refused.
    #[test]
    fn labels_read_back_from_their_text() {
        let counts = [Count::Impacts(0), Count::Impacts(7), Count::Stuck];
        let mut all = vec![Label::Chaotic, Label::Quasiperiodic, Label::Unresolved];
        for n in [1, 2, 37] {
            for p in counts {
                for q in counts {
                    all.push(Label::Periodic { n, p, q });
                }
            }
        }
        for l in all {
            assert_eq!(l.to_string().parse::<Label>(), Ok(l));
        }
        for bad in ["", "0-1-1", "1-1", "1-1-1-1", "1-x-1", "c", "not-computed", "-1-1-1"] {
            assert!(bad.parse::<Label>().is_err(), "{bad}");
        }
    }

    #[test]
    fn labels_print_as_the_literature_writes_them() {
        let periodic = Label::new(Class::Periodic, Some((1, Count::Impacts(4), Count::Impacts(4))));
        assert_eq!(periodic.to_string(), "1-4-4");
        assert_eq!(Label::new(Class::Periodic, Some((2, Count::Stuck, Count::Impacts(0)))).to_string(), "2-S-0");
        assert_eq!(Label::new(Class::Chaotic, None).to_string(), "C");
        assert_eq!(Label::new(Class::Quasiperiodic, None).to_string(), "Q");
        assert_eq!(Label::new(Class::Unresolved, Some((1, Count::Stuck, Count::Stuck))).to_string(), "U");
        // A periodic class needs its counts: without them there is no n-p-q.
        assert_eq!(Label::new(Class::Periodic, None), Label::Chaotic);
    }

    #[test]
    fn a_label_knows_its_class_and_counts() {
        for class in [Class::Chaotic, Class::Quasiperiodic, Class::Unresolved] {
            assert_eq!(Label::new(class, None).class(), class);
            assert_eq!(Label::new(class, None).npq(), None);
        }
        let l = Label::new(Class::Periodic, Some((3, Count::Impacts(1), Count::Stuck)));
        assert_eq!((l.class(), l.npq()), (Class::Periodic, Some((3, Count::Impacts(1), Count::Stuck))));
    }

    #[test]
    fn masks_hold_exactly_their_indices() {
        let m = Mask::of(5, |k| k % 2 == 0);
        assert_eq!(m.bits(), 0b10101);
        assert!((0..5).all(|k| m.contains(k) == (k % 2 == 0)));
        assert!(!m.contains(40));
        assert_eq!(Mask::from_bits(m.bits()), m);
        assert_eq!(Mask::of(3, |_| false), Mask::EMPTY);
        assert_eq!(m.indices().collect::<Vec<_>>(), vec![0, 2, 4]);
        assert_eq!(Mask::from_bits(1 << 31).indices().collect::<Vec<_>>(), vec![31]);
        assert_eq!(Mask::EMPTY.indices().count(), 0);
    }
}
