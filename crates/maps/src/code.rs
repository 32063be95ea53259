//! The integer codes of a cell's class, labels and symmetry, as an atlas file
//! stores them and the resume journal writes them, and the one serde form of
//! a cell ([`CellData`]) that the journal holds: codes for the class, labels
//! and symmetry, bits for the stop masks, null for a quantity that is NaN
//! (which JSON cannot hold).

use crate::CellData;
use serde::{de::Error as _, Deserialize, Deserializer, Serialize, Serializer};
use solver::{Class, Count, Label, Mask, Points, Symmetry, Unresolved};
use std::borrow::Cow;

/// Code of an `S` count in labels.
pub const STUCK: u16 = u16::MAX;

/// The stored `(n, p, q)` of a label: `n = 0` when not periodic, [`STUCK`]
/// for an `S` count, impact counts capped below it.
pub fn npq_code(label: Label) -> [u16; 3] {
    let code = |c: Count| match c {
        Count::Impacts(v) => v.min(STUCK as u32 - 1) as u16,
        Count::Stuck => STUCK,
    };
    match label.npq() {
        Some((n, p, q)) => [n.min(u16::MAX as u32) as u16, code(p), code(q)],
        None => [0, 0, 0],
    }
}

/// The label of a stored `(n, p, q)` in a cell of class `class`.
pub fn label_of(class: Class, npq: [u16; 3]) -> Label {
    let count = |v: u16| if v == STUCK { Count::Stuck } else { Count::Impacts(v as u32) };
    Label::new(class, Some((npq[0] as u32, count(npq[1]), count(npq[2]))))
}

/// Class code of a solver class.
pub fn class_code(c: Class) -> u8 {
    match c {
        Class::Periodic => 0,
        Class::Chaotic => 1,
        Class::Unresolved => 2,
        Class::Quasiperiodic => 3,
    }
}

/// Solver class of a code (`None` for not computed).
pub fn class_of(code: u8) -> Option<Class> {
    match code {
        0 => Some(Class::Periodic),
        1 => Some(Class::Chaotic),
        2 => Some(Class::Unresolved),
        3 => Some(Class::Quasiperiodic),
        _ => None,
    }
}

/// Symmetry code.
pub fn symmetry_code(s: Option<Symmetry>) -> u8 {
    match s {
        None => 0,
        Some(Symmetry::Symmetric) => 1,
        Some(Symmetry::Asymmetric) => 2,
    }
}

/// Symmetry of a code.
pub fn symmetry_of(code: u8) -> Option<Symmetry> {
    match code {
        1 => Some(Symmetry::Symmetric),
        2 => Some(Symmetry::Asymmetric),
        _ => None,
    }
}

/// A cell in its serde form (borrowing the cell it writes, owning the one it
/// reads). The field order is the journal's, unchanged since its first
/// version.
#[derive(Serialize, Deserialize)]
struct Coded<'a> {
    class: u8,
    labels: Vec<[u16; 3]>,
    chatter: u32,
    sticking: u32,
    symmetry: u8,
    #[serde(default)]
    lyapunov: Option<f64>,
    #[serde(default)]
    multiplier: Option<f64>,
    final_state: Cow<'a, [f64]>,
    periods: u64,
    events: u64,
    period_section: Cow<'a, Points>,
    impact_sections: Cow<'a, [Points]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    reason: Option<Cow<'a, Unresolved>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    quantities: Vec<Option<f64>>,
}

impl Serialize for CellData {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Coded {
            class: class_code(self.class),
            labels: self.labels.iter().map(|&l| npq_code(l)).collect(),
            chatter: self.chatter.bits(),
            sticking: self.sticking.bits(),
            symmetry: symmetry_code(self.symmetry),
            lyapunov: self.lyapunov,
            multiplier: self.multiplier,
            final_state: Cow::Borrowed(&self.final_state),
            periods: self.periods,
            events: self.events,
            period_section: Cow::Borrowed(&self.period_section),
            impact_sections: Cow::Borrowed(&self.impact_sections),
            reason: self.reason.as_deref().map(Cow::Borrowed),
            quantities: self.quantities.iter().map(|&v| (!v.is_nan()).then_some(v)).collect(),
        }
        .serialize(s)
    }
}

/// Reads a cell; an unknown class code is an error. The cell's shape (its
/// number of labels, its state's dimension) is for the reader to check
/// against its atlas.
impl<'de> Deserialize<'de> for CellData {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = Coded::deserialize(d)?;
        let class = class_of(c.class).ok_or_else(|| D::Error::custom(format!("unknown class code {}", c.class)))?;
        Ok(CellData {
            class,
            labels: c.labels.iter().map(|&l| label_of(class, l)).collect(),
            chatter: Mask::from_bits(c.chatter),
            sticking: Mask::from_bits(c.sticking),
            symmetry: symmetry_of(c.symmetry),
            lyapunov: c.lyapunov,
            multiplier: c.multiplier,
            final_state: c.final_state.into_owned(),
            periods: c.periods,
            events: c.events,
            period_section: c.period_section.into_owned(),
            impact_sections: c.impact_sections.into_owned(),
            reason: c.reason.map(|r| Box::new(r.into_owned())),
            quantities: c.quantities.iter().map(|v| v.unwrap_or(f64::NAN)).collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell of each class comes back from its serde form as it was (an S
    /// count, the masks, the reason, a NaN quantity written as null), and a
    /// class code that names no class is refused.
    #[test]
    fn a_cell_comes_back_from_its_serde_form() {
        let periodic = Label::Periodic { n: 2, p: Count::Stuck, q: Count::Impacts(3) };
        let cells = [
            (Class::Periodic, periodic),
            (Class::Chaotic, Label::Chaotic),
            (Class::Quasiperiodic, Label::Quasiperiodic),
        ];
        for (class, label) in cells {
            let cell = CellData {
                class,
                labels: vec![label],
                chatter: Mask::from_bits(0b10),
                sticking: Mask::from_bits(0b01),
                symmetry: Some(Symmetry::Asymmetric),
                lyapunov: Some(-0.25),
                multiplier: None,
                final_state: vec![0.1, -1e-300],
                periods: 7,
                events: 40,
                period_section: Points::from_rows([[0.1, 0.2]]).unwrap(),
                impact_sections: vec![Points::from_rows([[0.5, 0.1, 0.2]]).unwrap(), Points::default()],
                reason: None,
                quantities: vec![1.5, f64::NAN],
            };
            let text = serde_json::to_string(&cell).unwrap();
            assert!(text.contains("\"quantities\":[1.5,null]"), "{text}");
            let back: CellData = serde_json::from_str(&text).unwrap();
            assert_eq!(back.labels, cell.labels);
            assert_eq!(back.quantities[0].to_bits(), 1.5f64.to_bits());
            assert!(back.quantities[1].is_nan());
            assert_eq!(CellData { quantities: vec![], ..back }, CellData { quantities: vec![], ..cell });
        }
        let text = r#"{"class":7,"labels":[],"chatter":0,"sticking":0,"symmetry":0,"final_state":[],"periods":0,"events":0,"period_section":[],"impact_sections":[]}"#;
        let refused = serde_json::from_str::<CellData>(text).unwrap_err().to_string();
        assert!(refused.contains("unknown class code 7"), "{refused}");
    }
}
