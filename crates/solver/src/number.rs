//! Numbers of results in serde's data model: a finite `f64` is a number, a
//! non-finite one the text `inf`, `-inf` or `nan` (JSON has no such numbers,
//! and a result such as an [`crate::Unresolved`] reason may hold an infinite
//! distance or interval), so that every value survives a round trip through
//! JSON bit for bit.

use serde::{Deserialize, Deserializer, Serializer};

/// Serialises `x` as a number when finite, else as its text.
pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    match *x {
        x if x.is_finite() => s.serialize_f64(x),
        x if x.is_nan() => s.serialize_str("nan"),
        x if x > 0.0 => s.serialize_str("inf"),
        _ => s.serialize_str("-inf"),
    }
}

/// A number, or one of the texts `inf`, `-inf`, `nan`.
#[derive(Deserialize)]
#[serde(untagged)]
enum Written {
    Number(f64),
    Text(String),
}

/// Reads what [`serialize`] wrote.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    read(Written::deserialize(d)?)
}

/// The number a [`Written`] value stands for.
fn read<E: serde::de::Error>(w: Written) -> Result<f64, E> {
    match w {
        Written::Number(x) => Ok(x),
        Written::Text(t) => match t.as_str() {
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            "nan" => Ok(f64::NAN),
            _ => Err(E::custom(format!("'{t}' is not a number (nor inf, -inf or nan)"))),
        },
    }
}

/// The same for an optional number: `None` is `null` (and a missing field,
/// with `#[serde(default)]`).
pub mod optional {
    use super::{read, Written};
    use serde::{Deserialize, Deserializer, Serializer};

    /// Serialises `x` as [`super::serialize`] does, `None` as `null`.
    pub fn serialize<S: Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match x {
            Some(x) => super::serialize(x, s),
            None => s.serialize_none(),
        }
    }

    /// Reads what [`serialize`] wrote.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        Option::<Written>::deserialize(d)?.map(read).transpose()
    }
}

#[cfg(test)]
mod tests {
    use crate::{Interval, Rotation, SolverError, Stretch, Unresolved};

    fn round_trip(u: &Unresolved) -> Unresolved {
        let text = serde_json::to_string(u).unwrap();
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn every_reason_survives_json_bit_for_bit() {
        let growth = Interval { mean: -1.234_567_890_123e-4, half_width: f64::INFINITY, periods: 9 };
        let rotation = Rotation { turns: 0.123_456_789_012_345_67, error: f64::NAN, points: 400 };
        let reasons = [
            Unresolved::Budget { max_events: 400_000 },
            Unresolved::Stalled,
            Unresolved::Failed(SolverError::OutOfRange { message: "x = 1e300".into() }),
            Unresolved::Contracting { growth: -0.1, stuck: None },
            Unresolved::Undecided {
                growth,
                rotation: Some(rotation),
                gain: Some(f64::INFINITY),
                lossless: true,
                excess: Some(Box::new(Stretch { periods: 1600, growth: 2.25, bound: 0.575_364_144_903_562_1 })),
                off_section: Some(1600),
            },
            Unresolved::Undecided {
                growth,
                rotation: None,
                gain: None,
                lossless: false,
                excess: None,
                off_section: None,
            },
            Unresolved::Polynomial {
                growth,
                late: growth,
                rotation: Some(rotation),
                gain: Some(3.5),
                excess: None,
                off_section: Some(1600),
            },
            Unresolved::NoExponent { halt: Box::new(Unresolved::Budget { max_events: 7 }), measured: None },
            Unresolved::LongPeriod { n: 140, n_max: 128 },
            Unresolved::Unsettled { periods: 2251, multiplier: 0.992_227_769_430_1, distance: 1.3e-7, left: None },
            Unresolved::Unsettled { periods: 3, multiplier: 1.0, distance: f64::INFINITY, left: None },
            Unresolved::Unsettled {
                periods: 116,
                multiplier: 1.0,
                distance: f64::INFINITY,
                left: Some(crate::executor::Departure { periods: 6400, distance: 2.3e-6 }),
            },
            Unresolved::Unstable { periods: 10, multiplier: f64::NEG_INFINITY },
            Unresolved::Linear { periods: 50, closing: None, meets: None, overlap: None, followed: None },
            Unresolved::Linear {
                periods: 50,
                closing: None,
                meets: None,
                overlap: Some(2.5e-3),
                followed: Some(60_000),
            },
            Unresolved::Linear {
                periods: 50,
                closing: Some(3e-5),
                meets: Some(f64::INFINITY),
                overlap: None,
                followed: None,
            },
            Unresolved::Unbounded { periods: 20, drift: 5e-324 },
            Unresolved::Described { text: "an older atlas's words, 1.5e-3".into() },
            Unresolved::NoExponent { halt: Box::new(Unresolved::Stalled), measured: Some(growth) },
            Unresolved::TorusUntold { growth, late: growth, events: 7, grew: None },
            Unresolved::TorusUntold {
                growth,
                late: growth,
                events: 6400,
                grew: Some(Box::new(Stretch { periods: 3200, growth: 3.697, bound: 1.383_176_667_581_308_4 })),
            },
            Unresolved::Contracting { growth: -6.5, stuck: Some(6) },
        ];
        for u in &reasons {
            let back = round_trip(u);
            // Debug shows NaN, which PartialEq does not equal to itself.
            assert_eq!(format!("{back:?}"), format!("{u:?}"));
            assert_eq!(back.to_string(), u.to_string());
        }
        let text = serde_json::to_string(&reasons[9]).unwrap();
        assert_eq!(text, r#"{"kind":"unsettled","periods":2251,"multiplier":0.9922277694301,"distance":1.3e-7}"#);
        let text = serde_json::to_string(&reasons[2]).unwrap();
        assert_eq!(text, r#"{"kind":"failed","error":"out_of_range","message":"x = 1e300"}"#);
        assert!(serde_json::to_string(&reasons[10]).unwrap().contains(r#""distance":"inf""#));
        // A reason's new field where it has a value only: the old reason's
        // text and JSON stay what they were.
        assert_eq!(serde_json::to_string(&reasons[3]).unwrap(), r#"{"kind":"contracting","growth":-0.1}"#);
        let stuck = serde_json::to_string(reasons.last().unwrap()).unwrap();
        assert_eq!(stuck, r#"{"kind":"contracting","growth":-6.5,"stuck":6}"#);
        // A reason written before `gain` was stored reads back without it.
        let old = r#"{"kind":"undecided","growth":{"mean":0.001,"half_width":0.002,"periods":1600},"rotation":null}"#;
        assert!(matches!(serde_json::from_str::<Unresolved>(old).unwrap(), Unresolved::Undecided { gain: None, .. }));
        let bad = r#"{"kind":"unsettled","periods":1,"multiplier":"big","distance":1}"#;
        assert!(serde_json::from_str::<Unresolved>(bad).unwrap_err().to_string().contains("'big' is not a number"));
    }
}
