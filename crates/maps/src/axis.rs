//! A parameter axis `NAME=START:STOP:COUNT`: COUNT equally spaced values from
//! START to STOP inclusive; a zoomed axis also takes, where its values
//! coincide with those of its parent's axis to rounding, the parent's own
//! values ([`Lattice`]), so that a box aligned with the parent's grid computes
//! at the very same parameters.

use crate::error::FieldError;

/// Largest number of values of one axis (a plane then has at most 10^12 cells,
/// which the memory check refuses long before).
pub const MAX_COUNT: usize = 1_000_000;

/// One swept parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Scene parameter name.
    pub name: String,
    /// First value.
    pub start: f64,
    /// Last value.
    pub stop: f64,
    /// Number of values (>= 1).
    pub count: usize,
    /// The parent's axis whose values this one takes where they coincide
    /// (a zoom's axis); `None` for an axis of its own.
    pub lattice: Option<Lattice>,
}

/// The values of a parent axis that a zoomed [`Axis`] snaps to: its value
/// `v` becomes the parent's value `j` where `v` lies within [`Lattice::SNAP`]
/// of the parent's spacing of the parent's own `START + (STOP - START) j /
/// (COUNT - 1)`; and as the parent's value is itself snapped to its own
/// parent's where it was a zoom, so on, level by level (a zoom of a zoom
/// computes at its grandparent's values where they coincide).
#[derive(Debug, Clone, PartialEq)]
pub struct Lattice {
    /// `(START, STOP, COUNT)` of the parent's axis, then of its parent's, …
    /// (each COUNT >= 2).
    pub levels: Vec<(f64, f64, usize)>,
}

impl Lattice {
    /// How near, in parts of the lattice's spacing, a value must be to a
    /// lattice value to be taken as it: far above rounding (1e-16 of the
    /// values), far below any spacing a user asks for.
    pub const SNAP: f64 = 1e-9;

    /// The lattice of `axis`'s values (`None` for a single value).
    pub fn of(axis: &Axis) -> Option<Lattice> {
        let mut levels = vec![(axis.start, axis.stop, axis.count)];
        levels.extend(axis.lattice.iter().flat_map(|l| l.levels.iter().copied()));
        (axis.count > 1).then_some(Lattice { levels })
    }

    /// `v` snapped level by level: the parent's value it coincides with, if any.
    pub fn snap(&self, v: f64) -> f64 {
        self.levels.iter().fold(v, |v, &(start, stop, count)| {
            let step = (stop - start) / (count - 1) as f64;
            let value = |j: f64| start + (stop - start) * j / (count - 1) as f64;
            let j = ((v - start) / step).round();
            if j >= 0.0 && j < count as f64 && (v - value(j)).abs() <= Lattice::SNAP * step.abs() {
                value(j)
            } else {
                v
            }
        })
    }
}

impl Axis {
    /// `count` values from `start` to `stop`, of no lattice (not checked:
    /// see [`Axis::checked`]).
    pub fn new(name: impl Into<String>, start: f64, stop: f64, count: usize) -> Axis {
        Axis { name: name.into(), start, stop, count, lattice: None }
    }

    /// Parses `NAME=START:STOP:COUNT`; `flag` names the option in errors.
    pub fn parse(text: &str, flag: &str) -> Result<Axis, FieldError> {
        let bad = |m: &str| FieldError::field(flag, format!("{m} (expected NAME=START:STOP:COUNT, got '{text}')"));
        // The last '=': a state component is named after its mass, whose name may hold one.
        let (name, range) = text.rsplit_once('=').ok_or_else(|| bad("missing '='"))?;
        let parts: Vec<&str> = range.split(':').collect();
        let [a, b, c] = parts.as_slice() else { return Err(bad("need three fields")) };
        let num = |s: &str, what: &str| -> Result<f64, FieldError> {
            let v: f64 = s.trim().parse().map_err(|_| bad(&format!("{what} '{}' is not a number", s.trim())))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad(&format!("{what} must be finite")))
            }
        };
        let (start, stop) = (num(a, "START")?, num(b, "STOP")?);
        let count: usize = c.trim().parse().map_err(|_| bad(&format!("COUNT '{}' is not a whole number", c.trim())))?;
        if name.trim().is_empty() {
            return Err(bad("empty parameter name"));
        }
        Axis::new(name.trim(), start, stop, count).checked(flag)
    }

    /// The axis, once checked: a name, finite ends, 1 to [`MAX_COUNT`]
    /// values, one value where its ends are equal, and a range that is not
    /// empty when there are several (`field` names it in errors).
    pub fn checked(self, field: &str) -> Result<Axis, FieldError> {
        let Axis { name, start, stop, count, .. } = &self;
        let field = format!("{field} {name}");
        if name.is_empty() {
            return Err(FieldError::field(field, "empty parameter name"));
        }
        if !(start.is_finite() && stop.is_finite()) {
            return Err(FieldError::field(field, format!("start and stop must be finite, got {start} and {stop}")));
        }
        // The values are start + i (stop - start) / (count - 1): a span
        // beyond the largest number would make them NaN and infinite.
        if !(stop - start).is_finite() {
            return Err(FieldError::field(
                field,
                format!("the span from {start} to {stop} is beyond the largest number; give a narrower range"),
            ));
        }
        if *count == 0 || *count > MAX_COUNT {
            return Err(FieldError::field(field, format!("the count must be 1 to {MAX_COUNT}, got {count}")));
        }
        // Each value is start + span · i / (count − 1): the span times the
        // last index must be a number too.
        let steps = count - 1;
        if !((stop - start) * steps as f64).is_finite() {
            let why = format!("the span from {start} to {stop} times {steps} steps is beyond the largest number");
            return Err(FieldError::field(field, format!("{why}; give a narrower range")));
        }
        if *count == 1 && (stop - start).abs() > 0.0 {
            return Err(FieldError::field(
                field,
                format!("a count of 1 is one value, but start {start} and stop {stop} differ: give equal ends, or more values"),
            ));
        }
        if *count > 1 && (stop - start).abs() <= f64::EPSILON * start.abs().max(stop.abs()) {
            return Err(FieldError::field(field, format!("empty range from {start} to {stop} with {count} values")));
        }
        Ok(self)
    }

    /// Refuses a descending axis (planes are stored ascending; sweep direction is separate).
    pub fn ascending(self, flag: &str) -> Result<Axis, FieldError> {
        if self.start > self.stop {
            return Err(FieldError::field(
                format!("{flag} {}", self.name),
                format!(
                    "inverted range {}:{} (give it ascending; sweep downwards with a down sweep)",
                    self.start, self.stop
                ),
            ));
        }
        Ok(self)
    }

    /// The spacing of the values, `(stop - start) / (count - 1)` (negative for
    /// a descending axis); 0 for a single value.
    pub fn step(&self) -> f64 {
        if self.count > 1 {
            (self.stop - self.start) / (self.count - 1) as f64
        } else {
            0.0
        }
    }

    /// The i-th value (the lattice's where they coincide).
    pub fn value(&self, i: usize) -> f64 {
        let v = if self.count == 1 {
            self.start
        } else {
            self.start + (self.stop - self.start) * i as f64 / (self.count - 1) as f64
        };
        match &self.lattice {
            Some(l) => l.snap(v),
            None => v,
        }
    }

    /// The index of the value nearest to `v`, or an error when `v` lies more
    /// than half a step outside the axis.
    pub fn nearest(&self, v: f64) -> Result<usize, String> {
        let (lo, hi) = (self.start.min(self.stop), self.start.max(self.stop));
        let step = if self.count > 1 { (hi - lo) / (self.count - 1) as f64 } else { 0.0 };
        if !(v >= lo - step / 2.0 && v <= hi + step / 2.0) {
            return Err(format!("{} = {v} is outside the file's {lo} to {hi}", self.name));
        }
        Ok((0..self.count)
            .min_by(|&i, &j| (self.value(i) - v).abs().total_cmp(&(self.value(j) - v).abs()))
            .unwrap_or(0))
    }

    /// All values in order.
    pub fn values(&self) -> Vec<f64> {
        (0..self.count).map(|i| self.value(i)).collect()
    }

    /// The same values in the opposite order.
    pub fn reversed(&self) -> Axis {
        Axis {
            name: self.name.clone(),
            start: self.stop,
            stop: self.start,
            count: self.count,
            lattice: self.lattice.clone(),
        }
    }
}

impl std::fmt::Display for Axis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}:{}:{}", self.name, scene::number(self.start), scene::number(self.stop), self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An axis whose span overflows is refused (the sixth audit: its values
    /// were NaN and infinite, and a basin map over it hung).
    #[test]
    fn a_span_beyond_the_largest_number_is_refused() {
        let e = Axis::new("x_M", -1e308, 1e308, 5).checked("--x").unwrap_err();
        assert!(e.to_string().contains("beyond the largest number"), "{e}");
        assert!(Axis::new("x_M", -1e307, 1e307, 5).checked("--x").is_ok());
    }

    #[test]
    fn parses_and_spaces_values() {
        let a = Axis::parse("omega=0.1:0.3:3", "x").unwrap();
        assert_eq!(a.name, "omega");
        assert_eq!(a.values().len(), 3);
        assert!((a.value(1) - 0.2).abs() < 1e-15 && (a.value(2) - 0.3).abs() < 1e-15);
        assert_eq!(Axis::parse("d=1:1:1", "y").unwrap().values(), vec![1.0]);
    }

    #[test]
    fn refuses_bad_axes() {
        for bad in [
            "omega",
            "omega=1:2",
            "omega=a:2:3",
            "omega=1:2:0",
            "omega=1:1:5",
            "=1:2:3",
            "omega=1:inf:3",
            "omega=1:2:-1",
        ] {
            assert!(Axis::parse(bad, "x").is_err(), "{bad}");
        }
        assert!(Axis::parse("omega=2:1:3", "x").unwrap().ascending("x").is_err());
    }
}
