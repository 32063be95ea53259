//! One cell of a plane as kept for storage: labels, flags as stop masks, the
//! final state and capped raw sections.

use solver::contact::Contact;
use solver::{CellResult, Class, ImpactSections, Label, Mask, Points, Symmetry, Unresolved};
use std::collections::HashMap;

/// What is kept of a classified cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellData {
    /// Kind of motion.
    pub class: Class,
    /// Label per labelled mass.
    pub labels: Vec<Label>,
    /// Stops that chattered.
    pub chatter: Mask,
    /// Stops that held their mass.
    pub sticking: Mask,
    /// Symmetry of periodic orbits of symmetric scenes.
    pub symmetry: Option<Symmetry>,
    /// Largest Lyapunov exponent (per unit time) of a cell without a period.
    pub lyapunov: Option<f64>,
    /// Largest Floquet multiplier modulus of a periodic cell.
    pub multiplier: Option<f64>,
    /// Final state `[x…, v…]`.
    pub final_state: Vec<f64>,
    /// Periods simulated.
    pub periods: u64,
    /// Events handled.
    pub events: u64,
    /// Period-section points (states at `t = kT`).
    pub period_section: Points,
    /// Per stop: `[phase, x…, v…]` before each impact of the window.
    pub impact_sections: ImpactSections,
    /// Why the cell is unresolved (the solver's reason, with its numbers),
    /// if it is (boxed: few cells have one, and the record of every cell is
    /// held until its file is written).
    pub reason: Option<Box<Unresolved>>,
    /// The quantities of its steady motion, one per [`crate::Meta::quantities`]
    /// (NaN where its motion could not be followed); empty when the atlas
    /// measures none.
    pub quantities: Vec<f64>,
}

impl CellData {
    /// What is kept of the classification `cell`: at most `section_cap` of
    /// its period-section points, its `impact_sections` and the values of
    /// the `quantities` its run measures.
    pub fn from_result(
        cell: CellResult,
        impact_sections: ImpactSections,
        quantities: Vec<f64>,
        section_cap: usize,
    ) -> CellData {
        CellData {
            class: cell.class,
            labels: cell.labels.iter().map(|l| l.label).collect(),
            chatter: cell.chatter,
            sticking: cell.sticking,
            symmetry: cell.symmetry,
            lyapunov: cell.lyapunov,
            multiplier: cell.multiplier,
            final_state: cell.final_state,
            periods: cell.periods,
            events: cell.events as u64,
            // States of one length: never refused.
            period_section: Points::from_rows(cell.section.iter().take(section_cap)).unwrap_or_default(),
            impact_sections,
            reason: cell.reason.map(Box::new),
            quantities,
        }
    }
}

/// A number per cell of an atlas: the two its classification gives, and
/// each quantity of the steady motion it measures ([`crate::Meta::quantities`]).
/// Its name is its dataset's in the file and its view's (`render --view`,
/// the explorer's `NAME:SWEEP`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Number {
    /// Largest Lyapunov exponent per unit time (cells without a period).
    Lyapunov,
    /// Largest Floquet multiplier modulus (periodic cells).
    Multiplier,
    /// Quantity `k` of the steady motion.
    Quantity(usize),
}

impl Number {
    /// [`Number::Lyapunov`]'s name.
    pub const LYAPUNOV: &'static str = "lyapunov";
    /// [`Number::Multiplier`]'s name.
    pub const MULTIPLIER: &'static str = "multiplier";

    /// Every number per cell of an atlas of `m`: the two of its
    /// classification, then its quantities in the file's order.
    pub fn all(m: &crate::Meta) -> impl Iterator<Item = Number> {
        [Number::Multiplier, Number::Lyapunov].into_iter().chain((0..m.quantities.len()).map(Number::Quantity))
    }

    /// The number named `name` in an atlas of `m`, if it has one.
    pub fn named(m: &crate::Meta, name: &str) -> Option<Number> {
        Number::all(m).find(|q| q.name(m) == name)
    }

    /// Its name.
    pub fn name(self, m: &crate::Meta) -> &str {
        match self {
            Number::Lyapunov => Number::LYAPUNOV,
            Number::Multiplier => Number::MULTIPLIER,
            Number::Quantity(k) => &m.quantities[k].name,
        }
    }

    /// Its symbol (`max |μ|`, `λ`, a quantity's `max |x| M1`).
    pub fn symbol(self, m: &crate::Meta) -> &str {
        match self {
            Number::Lyapunov => "λ",
            Number::Multiplier => "max |μ|",
            Number::Quantity(k) => &m.quantities[k].symbol,
        }
    }

    /// Its long name: the file's `long_name` and a figure's title.
    pub fn long_name(self, m: &crate::Meta) -> &str {
        match self {
            Number::Lyapunov => "largest Lyapunov exponent per unit time (cells without a period)",
            Number::Multiplier => "largest Floquet multiplier modulus (periodic cells)",
            Number::Quantity(k) => &m.quantities[k].long_name,
        }
    }

    /// Its CF units (the classification's numbers are pure numbers of the
    /// scene's time).
    pub fn units(self, m: &crate::Meta) -> &str {
        match self {
            Number::Lyapunov | Number::Multiplier => "1",
            Number::Quantity(k) => &m.quantities[k].units,
        }
    }

    /// Whether it is a quantity of the steady motion (which has an up less
    /// down map), not a number of the classification.
    pub fn of_motion(self) -> bool {
        matches!(self, Number::Quantity(_))
    }

    /// Its value in `c` as the file stores it: NaN where the cell has none.
    pub fn stored(self, c: &CellData) -> f64 {
        match self {
            Number::Lyapunov => c.lyapunov.unwrap_or(f64::NAN),
            Number::Multiplier => c.multiplier.unwrap_or(f64::NAN),
            Number::Quantity(k) => c.quantities.get(k).copied().unwrap_or(f64::NAN),
        }
    }

    /// Its value in `c`, where the cell has a finite one.
    pub fn value(self, c: &CellData) -> Option<f64> {
        Some(self.stored(c)).filter(|v| v.is_finite())
    }
}

/// One quantity an atlas measures in every cell ([`solver::quantity::TABLE`]
/// for an owner of the scene): its name in the file and JSON
/// (`max_abs_x_M1`), symbol, long name and units.
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    /// Its name: `<stem>_<owner>` or a cell quantity's stem.
    pub name: String,
    /// Its symbol, with its owner (`max |x| M1`).
    pub symbol: String,
    /// Its long name, with its owner (`largest |position| of M1`).
    pub long_name: String,
    /// Its CF units.
    pub units: String,
}

impl Quantity {
    /// `text` (its name or long name) with its units in parentheses, unless
    /// it is a pure number (`1`): `attenuation (dB)`.
    pub fn with_units(&self, text: &str) -> String {
        match self.units.as_str() {
            "1" => text.to_string(),
            units => format!("{text} ({units})"),
        }
    }

    /// The quantities a system measures, in [`solver::quantity::all_names`]'
    /// order: the built-in ones, a soft stop's in the words of contacts
    /// ([`solver::quantity::Spec::words`]), then those its scene defines.
    pub fn of(sys: &solver::System) -> Vec<Quantity> {
        let soft = |owner: &str| sys.model.stops.iter().any(|s| s.name == owner && s.law.spring().is_some());
        let built_in = solver::quantity::names(sys).into_iter().map(|(name, spec)| {
            let owner = name.strip_prefix(spec.stem).and_then(|o| o.strip_prefix('_')).unwrap_or("");
            let (symbol, long) = spec.words(soft(owner));
            // Both name the owner, so that two masses' `max |x|` are told
            // apart by their symbols too (`max |x| M1`, as a scene's own
            // `att M1`).
            let (symbol, long_name) = match owner {
                "" => (symbol.to_string(), long.to_string()),
                owner => (format!("{symbol} {owner}"), format!("{long} {owner}")),
            };
            Quantity { symbol, long_name, units: spec.dimension.units(&sys.model.scales), name }
        });
        let defined = sys.model.quantities.iter().map(|d| Quantity {
            name: d.name.clone(),
            symbol: d.symbol.clone(),
            long_name: d.long_name.clone(),
            units: d.units.clone(),
        });
        built_in.chain(defined).collect()
    }
}

/// Largest `section_cap`: points kept per section per cell.
pub const MAX_SECTION_CAP: usize = 100_000;

/// Points kept per section per cell when the caller names no `section_cap`.
pub const DEFAULT_SECTION_CAP: usize = 16;

/// The labels of mass `mass` over `cells` with their cell counts, most
/// frequent first (ties in the order of the labels' text): the order of
/// every legend and label table.
pub fn label_counts<'a>(cells: impl IntoIterator<Item = &'a CellData>, mass: usize) -> Vec<(Label, u64)> {
    let mut counts: HashMap<Label, u64> = HashMap::new();
    for (l, n) in runs(cells.into_iter().map(|c| c.labels[mass])) {
        *counts.entry(l).or_default() += n;
    }
    by_frequency(counts, Label::to_string)
}

/// The runs of equal neighbours of `items`: each value and how many times it
/// repeats where it stands. Neighbouring cells of a map mostly share a label,
/// so counting or collecting labels run by run hashes far fewer of them.
pub fn runs<T: PartialEq>(items: impl IntoIterator<Item = T>) -> impl Iterator<Item = (T, u64)> {
    let mut items = items.into_iter().peekable();
    std::iter::from_fn(move || {
        let first = items.next()?;
        let mut n = 1;
        while items.next_if(|next| *next == first).is_some() {
            n += 1;
        }
        Some((first, n))
    })
}

/// Counts most frequent first, ties in the order of `key` (the text a
/// legend writes): the same order whatever order the counts came in.
pub fn by_frequency<K, S: Ord>(counts: impl IntoIterator<Item = (K, u64)>, key: impl Fn(&K) -> S) -> Vec<(K, u64)> {
    let mut v: Vec<(K, u64)> = counts.into_iter().collect();
    v.sort_by_cached_key(|(k, n)| (std::cmp::Reverse(*n), key(k)));
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs are maximal: they put back the sequence, and no two neighbouring
    /// runs hold the same value.
    #[test]
    fn runs_are_the_maximal_runs_of_equal_neighbours() {
        let seq = [3, 3, 1, 1, 1, 3, 2, 2, 3];
        let r: Vec<(i32, u64)> = runs(seq).collect();
        assert_eq!(r, [(3, 2), (1, 3), (3, 1), (2, 2), (3, 1)]);
        let back: Vec<i32> = r.iter().flat_map(|&(v, n)| std::iter::repeat_n(v, n as usize)).collect();
        assert_eq!(back, seq);
        assert_eq!(runs(std::iter::empty::<i32>()).count(), 0);
        assert_eq!(runs([7]).collect::<Vec<_>>(), [(7, 1)]);
    }
}
