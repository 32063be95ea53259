//! Parameter expressions: parsed once per scene, evaluated per cell.
//!
//! Expressions use exmex's float operators (`+ - * / ^`, `sin`, `cos`, `sqrt`,
//! `exp`, `ln`, `abs`, …) and constants `PI`/`π`, `E`. Any other identifier must be
//! a parameter of the scene.

use crate::error::SceneError;
use crate::schema::Num;
use exmex::prelude::*;

/// A number or a compiled expression whose variables are parameter indices.
#[derive(Debug, Clone)]
pub enum Compiled {
    /// Literal value.
    Value(f64),
    /// Compiled expression; `vars[i]` is the parameter index of the i-th exmex variable.
    Expr {
        /// Source text, kept for messages.
        source: String,
        /// The compiled expression (boxed: it is much larger than a number).
        expr: Box<FlatEx<f64>>,
        /// Parameter index of each variable, in exmex's variable order.
        vars: Vec<usize>,
    },
}

impl Compiled {
    /// Compiles `num` for the field `field`, resolving identifiers against `names`.
    pub fn new(num: &Num, names: &[String], field: &str) -> Result<Self, SceneError> {
        match num {
            Num::Value(v) => Ok(Compiled::Value(*v)),
            Num::Expr(source) => {
                let expr = exmex::parse::<f64>(source)
                    .map_err(|e| SceneError::field(field, format!("cannot parse expression '{source}': {e}")))?;
                let vars = expr
                    .var_names()
                    .iter()
                    .map(|v| {
                        names.iter().position(|n| n == v).ok_or_else(|| {
                            SceneError::field(field, format!("unknown parameter '{v}' in expression '{source}'"))
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Compiled::Expr { source: source.clone(), expr: Box::new(expr), vars })
            }
        }
    }

    /// Parameter indices this value depends on.
    pub fn dependencies(&self) -> &[usize] {
        match self {
            Compiled::Value(_) => &[],
            Compiled::Expr { vars, .. } => vars,
        }
    }

    /// Evaluates with the given parameter values; a non-finite result is an error.
    pub fn eval(&self, values: &[f64], field: &str) -> Result<f64, SceneError> {
        let v = match self {
            Compiled::Value(v) => *v,
            Compiled::Expr { source, expr, vars } => {
                let args: Vec<f64> = vars.iter().map(|&i| values[i]).collect();
                expr.eval(&args).map_err(|e| SceneError::field(field, format!("cannot evaluate '{source}': {e}")))?
            }
        };
        if v.is_finite() {
            Ok(v)
        } else {
            let what = match self {
                Compiled::Value(_) => String::new(),
                Compiled::Expr { source, .. } => format!(" ('{source}')"),
            };
            Err(SceneError::field(field, format!("not a finite number{what}, got {v}")))
        }
    }
}

/// An interval a parameter must lie in, written `"(0, 1)"`, `"[0, inf)"`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Range {
    /// Parses interval notation; `field` names the parameter in errors.
    pub fn parse(text: &str, field: &str) -> Result<Self, SceneError> {
        let bad =
            || SceneError::field(field, format!("range must look like \"(0, 1)\" or \"[0, inf)\", got \"{text}\""));
        let t = text.trim();
        let lo_open = match t.chars().next() {
            Some('(') => true,
            Some('[') => false,
            _ => return Err(bad()),
        };
        let hi_open = match t.chars().last() {
            Some(')') => true,
            Some(']') => false,
            _ => return Err(bad()),
        };
        let inner = &t[1..t.len() - 1];
        let (a, b) = inner.split_once(',').ok_or_else(bad)?;
        let num = |s: &str| -> Result<f64, SceneError> {
            match s.trim() {
                "inf" | "+inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                other => other.parse::<f64>().map_err(|_| bad()),
            }
        };
        let (lo, hi) = (num(a)?, num(b)?);
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(bad());
        }
        Ok(Range { lo, hi, lo_open, hi_open })
    }

    /// Whether `v` lies in the interval.
    pub fn contains(&self, v: f64) -> bool {
        let above = if self.lo_open { v > self.lo } else { v >= self.lo };
        let below = if self.hi_open { v < self.hi } else { v <= self.hi };
        above && below
    }
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = |v: f64| {
            if v.is_infinite() {
                if v > 0.0 {
                    "inf".to_string()
                } else {
                    "-inf".to_string()
                }
            } else {
                format!("{v}")
            }
        };
        write!(
            f,
            "{}{}, {}{}",
            if self.lo_open { '(' } else { '[' },
            b(self.lo),
            b(self.hi),
            if self.hi_open { ')' } else { ']' }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_and_bound() {
        let r = Range::parse("(0, 1)", "p").unwrap();
        assert!(r.contains(0.5) && !r.contains(0.0) && !r.contains(1.0));
        let r = Range::parse("[0, inf)", "p").unwrap();
        assert!(r.contains(0.0) && r.contains(1e300) && !r.contains(-1e-300));
        assert!(Range::parse("0, 1", "p").is_err());
        assert!(Range::parse("[2, 1]", "p").is_err());
    }

    #[test]
    fn expressions_resolve_parameters() {
        let names = vec!["a".to_string(), "mu_m".to_string()];
        let c = Compiled::new(&Num::Expr("mu_m/(1-mu_m) + a".into()), &names, "f").unwrap();
        let v = c.eval(&[2.0, 0.5], "f").unwrap();
        assert!((v - 3.0).abs() < 1e-15);
        let e = Compiled::new(&Num::Expr("delt".into()), &names, "masses[0].x0").unwrap_err();
        assert_eq!(e.to_string(), "masses[0].x0: unknown parameter 'delt' in expression 'delt'");
        let c = Compiled::new(&Num::Expr("1/(1-mu_m)".into()), &names, "m").unwrap();
        assert!(c.eval(&[0.0, 1.0], "m").is_err());
    }
}
