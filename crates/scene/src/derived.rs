//! Quantities a scene defines (`[quantities]`): each an expression over the
//! scene's parameters and the built-in quantities of the steady motion
//! (`max_abs_x_M1`, `impact_speed_max_right`, …), computed for every cell
//! after them, e.g. the damper's attenuation against the bare primary
//!
//! ```toml
//! [quantities]
//! attenuation = { value = "20*log10(max_abs_x_M1*sqrt((1 - omega^2)^2 + (2*zeta*omega)^2))", units = "dB" }
//! ```
//!
//! The scene compiles each expression once; which of its names are built-in
//! quantities is for the solver, which knows them, to check
//! (`solver::System::new`).

use crate::error::SceneError;
use crate::expr::{self, Names};
use crate::schema::QuantitySpec;
use crate::symbol;
use exmex::prelude::*;

/// A name an expression of `[quantities]` reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Operand {
    /// Parameter `k` of the scene (scene order).
    Parameter(usize),
    /// A quantity of the steady motion, by name, resolved by the solver.
    Quantity(String),
}

/// One quantity a scene defines.
#[derive(Debug, Clone)]
pub struct Derived {
    /// Its name: an identifier, the name of its variable in files and JSON.
    pub name: String,
    /// Its symbol in figures (by default its name).
    pub symbol: String,
    /// Its long name (CF `long_name`; by default its expression).
    pub long_name: String,
    /// Its CF units (by default `1`).
    pub units: String,
    /// Its expression as written.
    pub source: String,
    expr: Box<FlatEx<f64>>,
    operands: Vec<Operand>,
}

impl PartialEq for Derived {
    fn eq(&self, other: &Derived) -> bool {
        (&self.name, &self.symbol, &self.long_name, &self.units, &self.source)
            == (&other.name, &other.symbol, &other.long_name, &other.units, &other.source)
    }
}

/// Names a quantity of a scene may not take: the variables an atlas file's
/// sweep group holds besides the quantities (a quantity is stored as a
/// variable of that group under its name), every name beginning with
/// `label_`, and the views `render --view` names besides the quantities
/// (`labels`, `attractors`; `lyapunov` and `multiplier` are variables too).
/// The tests hold this list to the names the store writes.
pub const TAKEN_NAMES: [&str; 24] = [
    "attractors",
    "class",
    "component",
    "entry_state",
    "events",
    "final_state",
    "flags",
    "impact_column",
    "label",
    "label_colour",
    "labels",
    "line",
    "lines_done",
    "lyapunov",
    "mass",
    "multiplier",
    "npq",
    "periods",
    "reason",
    "reason_code",
    "reason_detail",
    "rgb",
    "sections",
    "symmetry",
];

impl Derived {
    /// Compiles entry `name` of `[quantities]`; `params` are the scene's
    /// parameter names.
    pub(crate) fn compile(name: &str, spec: &QuantitySpec, params: &[String]) -> Result<Derived, SceneError> {
        let field = format!("quantities.{name}");
        expr::valid_parameter_name(name).map_err(|why| SceneError::field(&field, why))?;
        if params.iter().any(|p| p == name) {
            return Err(SceneError::field(
                &field,
                format!("'{name}' is a parameter of the scene; a quantity needs a name of its own"),
            ));
        }
        if TAKEN_NAMES.contains(&name) || name.starts_with("label_") {
            return Err(SceneError::field(
                &field,
                format!("'{name}' is reserved: an atlas file names one of its own variables with it"),
            ));
        }
        if let Some(s) = &spec.symbol {
            symbol::check_symbol(s, &format!("{field}.symbol"))?;
        }
        if let Some(t) = &spec.long_name {
            symbol::check_long_name(t, &format!("{field}.long_name"))?;
        }
        if let Some(u) = &spec.units {
            symbol::check_units(u, &format!("{field}.units"))?;
        }
        let index = Names::open(params);
        let expr = expr::parse(&spec.value, &index, &format!("{field}.value"))?;
        let operands: Vec<Operand> = expr
            .var_names()
            .iter()
            .map(|v| index.get(v).map_or_else(|| Operand::Quantity(v.clone()), Operand::Parameter))
            .collect();
        // An expression of nothing is a constant: one without a value would
        // leave every cell without one.
        if operands.is_empty() {
            if let Some(v) = expr.eval(&[]).ok().filter(|v| !v.is_finite()) {
                return Err(SceneError::field(
                    format!("{field}.value"),
                    format!("'{}' is a constant without a finite value ({v})", spec.value),
                ));
            }
        }
        Ok(Derived {
            name: name.to_string(),
            symbol: spec.symbol.clone().unwrap_or_else(|| name.to_string()),
            long_name: spec.long_name.clone().unwrap_or_else(|| spec.value.clone()),
            units: spec.units.clone().unwrap_or_else(|| "1".into()),
            source: spec.value.clone(),
            expr: Box::new(expr),
            operands,
        })
    }

    /// The names its expression reads, in the order [`Derived::eval`] takes
    /// their values.
    pub fn operands(&self) -> &[Operand] {
        &self.operands
    }

    /// Its value for the `values` of its [`Derived::operands`]; NaN where
    /// the expression has none (an operand NaN, a logarithm of 0).
    pub fn eval(&self, values: &[f64]) -> f64 {
        self.expr.eval(values).ok().filter(|v| v.is_finite()).unwrap_or(f64::NAN)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(value: &str) -> QuantitySpec {
        QuantitySpec { value: value.into(), units: Some("dB".into()), symbol: None, long_name: None }
    }

    #[test]
    fn an_expression_reads_parameters_and_quantities_by_name() {
        let params = ["omega".to_string(), "zeta".to_string()];
        let d = Derived::compile("gain", &spec("20*log10(max_abs_x_M1*omega) + zeta"), &params).unwrap();
        let operands = d.operands().to_vec();
        let value_of = |o: &Operand| match o {
            Operand::Parameter(0) => 2.0,
            Operand::Parameter(1) => 0.5,
            Operand::Parameter(_) => unreachable!(),
            Operand::Quantity(n) if n == "max_abs_x_M1" => 5.0,
            Operand::Quantity(n) => panic!("{n}"),
        };
        let values: Vec<f64> = operands.iter().map(value_of).collect();
        assert!((d.eval(&values) - 20.5).abs() < 1e-12, "{}", d.eval(&values));
        assert_eq!((d.symbol.as_str(), d.units.as_str()), ("gain", "dB"));
        // No value where the expression has none.
        let zero: Vec<f64> =
            operands.iter().map(|o| if matches!(o, Operand::Quantity(_)) { 0.0 } else { 1.0 }).collect();
        assert!(d.eval(&zero).is_nan());
    }

    #[test]
    fn a_bad_name_or_expression_is_refused_naming_the_field() {
        let params = ["omega".to_string()];
        let refused = |name: &str, value: &str| Derived::compile(name, &spec(value), &params).unwrap_err().to_string();
        assert!(
            refused("omega", "1").contains("quantities.omega: 'omega' is a parameter"),
            "{}",
            refused("omega", "1")
        );
        assert!(refused("class", "1").contains("quantities.class: 'class' is reserved"));
        assert!(refused("label_M1", "1").contains("reserved"));
        assert!(refused("2x", "1").contains("quantities.2x:"));
        assert!(refused("g", "sin(").contains("quantities.g.value:"), "{}", refused("g", "sin("));
        assert!(refused("g", "foo(omega)").contains("unknown function 'foo'"));
        assert!(refused("labels", "1").contains("reserved"));
        assert!(refused("g", "1/0").contains("quantities.g.value: '1/0' is a constant without a finite value (inf)"));
        assert!(Derived::compile("g", &spec("ln(omega)"), &params).is_ok(), "a value per cell, NaN where none");
    }
}
