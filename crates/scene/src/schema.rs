//! The TOML schema of a scene file, as written by users (numbers or expressions).
//!
//! Every number may be a TOML number or a string holding an expression of the
//! scene's parameters (`"mu_m/(1-mu_m)"`, `"-delta"`, `"PI/2"`). Unknown keys are
//! rejected so that a typo never silently falls back to a default.

use serde::Deserialize;
use std::collections::BTreeMap;

/// A number or an expression of the parameters.
#[derive(Debug, Clone)]
pub enum Num {
    /// A literal number.
    Value(f64),
    /// An expression of parameters, evaluated per cell.
    Expr(String),
}

/// A TOML number (integer or float) is a [`Num::Value`], a string a
/// [`Num::Expr`]; anything else is refused with what was expected, which
/// the parse error prints beside the key's line and column.
impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Num, D::Error> {
        d.deserialize_any(NumVisitor)
    }
}

/// Reads a [`Num`] from a TOML number or string ([`ParamSpec`]'s visitor
/// hands it those).
struct NumVisitor;

impl serde::de::Visitor<'_> for NumVisitor {
    type Value = Num;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a number or an expression in quotes (\"2*zeta\")")
    }
    fn visit_f64<E>(self, v: f64) -> Result<Num, E> {
        Ok(Num::Value(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Num, E> {
        Ok(Num::Value(v as f64))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Num, E> {
        Ok(Num::Value(v as f64))
    }
    fn visit_str<E>(self, v: &str) -> Result<Num, E> {
        Ok(Num::Expr(v.to_string()))
    }
}

impl Default for Num {
    fn default() -> Self {
        Num::Value(0.0)
    }
}

/// A parameter: a plain number/expression, or a table with an allowed range.
#[derive(Debug, Clone)]
pub enum ParamSpec {
    /// `delta = 0.6` or `delta1 = "delta"`.
    Plain(Num),
    /// `mu_m = { value = 0.5, range = "(0, 1)", doc = "…", symbol = "μ_m" }`.
    Ranged(RangedParam),
}

/// A number or a string is a [`ParamSpec::Plain`], a table a
/// [`ParamSpec::Ranged`] whose own errors (an unknown key, a `value` of
/// the wrong type) are the parse error's; anything else is refused with
/// what was expected.
impl<'de> Deserialize<'de> for ParamSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<ParamSpec, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = ParamSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number, an expression in quotes, or a table { value = …, range = … }")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<ParamSpec, E> {
                NumVisitor.visit_f64(v).map(ParamSpec::Plain)
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ParamSpec, E> {
                NumVisitor.visit_i64(v).map(ParamSpec::Plain)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ParamSpec, E> {
                NumVisitor.visit_u64(v).map(ParamSpec::Plain)
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ParamSpec, E> {
                NumVisitor.visit_str(v).map(ParamSpec::Plain)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<ParamSpec, A::Error> {
                RangedParam::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(ParamSpec::Ranged)
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// A parameter with the interval its values must lie in.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangedParam {
    /// Default value or expression.
    pub value: Num,
    /// Interval in mathematical notation: `"(0, 1)"`, `"[0, 1]"`, `"[0, inf)"`.
    pub range: Option<String>,
    /// What the parameter means; documentation for readers of the file (the
    /// long name of the parameter when `long_name` is not given).
    #[serde(default)]
    pub doc: String,
    /// How figures and files write the parameter (`"ω"`); by default
    /// [`crate::symbol_of`] its name.
    pub symbol: Option<String>,
    /// What the parameter is, in a few words (`"forcing frequency"`), for
    /// files (CF `long_name`) and figures; by default the first line of `doc`.
    pub long_name: Option<String>,
}

/// Whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Short name of the scene.
    pub name: String,
    /// One-paragraph description (equations, source).
    #[serde(default)]
    pub description: String,
    /// Whether the scene is invariant under the mirror `x -> -x` combined with a
    /// half forcing period shift; enables the `S`/`AS` symmetry report.
    #[serde(default)]
    pub symmetric: bool,
    /// Named parameters (numbers or expressions of other parameters).
    pub parameters: BTreeMap<String, ParamSpec>,
    /// Harmonic forcing `sin(omega t + phase)`.
    pub forcing: ForcingSpec,
    /// Point masses, in the order of the state vector.
    pub masses: Vec<MassSpec>,
    /// Springs and dampers, to the frame or between two masses.
    #[serde(default)]
    pub links: Vec<LinkSpec>,
    /// Rigid stops (mass against the frame, or two masses against each other).
    #[serde(default)]
    pub stops: Vec<StopSpec>,
    /// Coulomb friction contacts between two masses.
    #[serde(default)]
    pub friction: Vec<FrictionSpec>,
    /// Which stops are the p-stop and the q-stop of each mass in its n-p-q label.
    #[serde(default)]
    pub labels: BTreeMap<String, LabelSpec>,
    /// Quantities of the steady motion the scene defines, by name.
    #[serde(default)]
    pub quantities: BTreeMap<String, QuantitySpec>,
    /// Physical scales of the scene's dimensionless units.
    #[serde(default)]
    pub scales: ScalesSpec,
}

/// `[scales]`: what one of the scene's units of length, time and force is
/// physically (`length = { value = 0.002, units = "m" }`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScalesSpec {
    /// The unit of length.
    pub length: Option<ScaleSpec>,
    /// The unit of time.
    pub time: Option<ScaleSpec>,
    /// The unit of force.
    pub force: Option<ScaleSpec>,
}

/// One scale: its value in `units`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScaleSpec {
    /// How many `units` one scene unit is (finite, above 0).
    pub value: f64,
    /// The physical units (CF / UDUNITS: `m`, `s`, `N`).
    pub units: String,
}

/// `[quantities]`: `attenuation = { value = "20*log10(…)", units = "dB" }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuantitySpec {
    /// An expression over the scene's parameters and the built-in quantities.
    pub value: String,
    /// CF units (by default `1`).
    pub units: Option<String>,
    /// Symbol in figures (by default the name).
    pub symbol: Option<String>,
    /// Long name (by default the expression).
    pub long_name: Option<String>,
}

/// `[forcing]`: frequency and phase of `sin(omega t + phase)`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForcingSpec {
    /// Forcing frequency ω (> 0).
    pub omega: Num,
    /// Phase τ.
    #[serde(default)]
    pub phase: Num,
}

/// `[[masses]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MassSpec {
    /// Name used in labels and output (`M1`).
    pub name: String,
    /// Mass (> 0).
    pub mass: Num,
    /// Amplitude of the harmonic force `force * sin(omega t + phase)` on this mass.
    #[serde(default)]
    pub force: Num,
    /// A constant force on this mass (a static or mean load).
    #[serde(default)]
    pub load: Num,
    /// Further harmonics of the forcing on this mass,
    /// `amplitude * sin(order * omega t + phase)`.
    #[serde(default)]
    pub harmonics: Vec<HarmonicSpec>,
    /// Initial displacement.
    #[serde(default)]
    pub x0: Num,
    /// Initial velocity.
    #[serde(default)]
    pub v0: Num,
}

/// `harmonics = [{ order = 2, amplitude = "f2", phase = "phi2" }]` of a mass:
/// a force `amplitude * sin(order * omega t + phase)`, `order` a whole number
/// (the forcing period stays `2 pi / omega`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// Multiple of ω: a whole number from 1 to [`crate::MAX_HARMONIC`], written
    /// as a number (not an expression: it shapes the state of the solver).
    pub order: Num,
    /// Amplitude.
    pub amplitude: Num,
    /// Phase at `t = 0` (radians).
    #[serde(default)]
    pub phase: Num,
}

/// `[[links]]`: a spring and a damper in parallel.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkSpec {
    /// One mass (tied to the frame) or two masses (tied to each other).
    pub masses: Vec<String>,
    /// Spring stiffness (>= 0).
    #[serde(default)]
    pub stiffness: Num,
    /// Viscous damping coefficient (>= 0).
    #[serde(default)]
    pub damping: Num,
}

/// Side of a frame stop relative to its mass.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// The stop is below the mass: `x >= position`.
    Below,
    /// The stop is above the mass: `x <= position`.
    Above,
}

/// `[[stops]]`: either `mass` + `side` + `position`, or `masses = [a, b]` + `gap`
/// meaning `x_a - x_b <= gap`; either `restitution` (a rigid stop, Newton's
/// impact law) or `stiffness` and `damping` (a soft stop: a spring and dashpot
/// that push beyond the clearance).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Name used in output (`A1`).
    pub name: String,
    /// Mass of a frame stop.
    pub mass: Option<String>,
    /// Side of a frame stop.
    pub side: Option<Side>,
    /// Position of a frame stop.
    pub position: Option<Num>,
    /// The two masses of a pair stop, `x_a - x_b <= gap`.
    pub masses: Option<Vec<String>>,
    /// Gap of a pair stop (>= 0).
    pub gap: Option<Num>,
    /// Coefficient of restitution in [0, 1] (a rigid stop).
    pub restitution: Option<Num>,
    /// Contact stiffness (>= 0) of a soft stop.
    pub stiffness: Option<Num>,
    /// Contact damping coefficient (>= 0) of a soft stop.
    pub damping: Option<Num>,
}

/// `[[friction]]`: Coulomb friction between two masses.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionSpec {
    /// The two masses in contact.
    pub masses: Vec<String>,
    /// Kinetic friction force (>= 0).
    pub kinetic: Num,
    /// Static friction limit (>= kinetic).
    #[serde(rename = "static")]
    pub static_limit: Num,
}

/// `[labels.M1]`: the p-stop and q-stop of a mass.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabelSpec {
    /// Stop counted as p.
    pub p: Option<String>,
    /// Stop counted as q.
    pub q: Option<String>,
}
