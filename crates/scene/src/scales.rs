//! Physical scales (`[scales]`): what one of the scene's dimensionless units
//! of length, time and force is, so that files and figures give the
//! quantities of the steady motion in physical units
//!
//! ```toml
//! [scales]
//! length = { value = 0.002, units = "m" }
//! time = { value = 0.0016, units = "s" }
//! force = { value = 40.0, units = "N" }
//! ```
//!
//! A quantity whose dimension needs a scale the scene does not give stays in
//! the scene's units (`1`).

use crate::error::SceneError;
use crate::schema::{ScaleSpec, ScalesSpec};
use crate::symbol;

/// Smallest and largest scale: a product of three (a power, force times
/// length over time) stays within double precision, and so does a quantity
/// of the scene times it.
pub const MIN_SCALE: f64 = 1e-100;
/// See [`MIN_SCALE`].
pub const MAX_SCALE: f64 = 1e100;

/// One scale: a scene unit is `value` `units`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scale {
    /// Its value in `units` (finite, above 0).
    pub value: f64,
    /// Its physical units.
    pub units: String,
}

/// The scales a scene gives.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scales {
    /// The unit of length.
    pub length: Option<Scale>,
    /// The unit of time.
    pub time: Option<Scale>,
    /// The unit of force.
    pub force: Option<Scale>,
}

impl Scales {
    /// The checked scales of `[scales]`.
    pub(crate) fn of(spec: &ScalesSpec) -> Result<Scales, SceneError> {
        let one = |s: &Option<ScaleSpec>, name: &str| -> Result<Option<Scale>, SceneError> {
            let Some(s) = s else { return Ok(None) };
            if !(MIN_SCALE..=MAX_SCALE).contains(&s.value) {
                return Err(SceneError::field(
                    format!("scales.{name}.value"),
                    format!("must be a number from {MIN_SCALE:e} to {MAX_SCALE:e}, got {}", s.value),
                ));
            }
            symbol::check_units(&s.units, &format!("scales.{name}.units"))?;
            Ok(Some(Scale { value: s.value, units: s.units.trim().to_string() }))
        };
        Ok(Scales {
            length: one(&spec.length, "length")?,
            time: one(&spec.time, "time")?,
            force: one(&spec.force, "force")?,
        })
    }

    /// Whether the scene gives none.
    pub fn is_empty(&self) -> bool {
        self.length.is_none() && self.time.is_none() && self.force.is_none()
    }
}
