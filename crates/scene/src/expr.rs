//! Parameter expressions: parsed once per scene, evaluated per cell.
//!
//! Expressions use exmex's float operators (`+ - * / ^`, `sin`, `cos`, `sqrt`,
//! `exp`, `ln`, `abs`, …) and constants `PI`/`π`, `E`/`e`. Any other identifier must be
//! a parameter of the scene.

use crate::error::SceneError;
use crate::schema::Num;
use exmex::prelude::*;
use std::collections::HashMap;

/// Longest expression, in characters (issue 30). Real expressions are a few
/// dozen characters (`2*zeta*mu_c/(1-mu_c)`); compiling one costs time growing
/// with the square of its length (exmex folds constants one by one), about
/// 10 ms at this length (0.1 s at 4 000, 90 s at 100 000), so that the
/// compilation of a scene stays linear in its size.
pub const MAX_EXPRESSION_CHARS: usize = 1000;

/// Most expressions among a scene's parameters and links, whose number is not
/// limited otherwise (issue 30's limits, the ninth audit; counted before any
/// is compiled): each holds exmex's compiled form, about 20 KB whatever its length
/// (its nodes and operators kept inline, 32 of each), and takes 0.1 to 0.2 ms
/// to compile, so that this many take some 4 GB and 20 to 40 s. Real scenes hold a
/// few dozen; the limit keeps a chain of 100 000 parameters (docs/scenes.md).
pub const MAX_EXPRESSIONS: usize = 200_000;

/// The parameter names of a scene with their indices, looked up by hashing so
/// that resolving the identifiers of all expressions is linear in their number.
#[derive(Debug)]
pub struct Names<'a> {
    index: HashMap<&'a str, usize>,
    /// Whether an identifier that is no parameter is let through, for the
    /// caller to resolve (the quantities an expression of `[quantities]`
    /// names).
    open: bool,
}

impl<'a> Names<'a> {
    /// The index of every name of `names`.
    pub fn new(names: &'a [String]) -> Names<'a> {
        Names { index: names.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect(), open: false }
    }

    /// [`Names::new`] that lets any other identifier through as well.
    pub fn open(names: &'a [String]) -> Names<'a> {
        Names { open: true, ..Names::new(names) }
    }

    /// The index of parameter `name`.
    pub fn get(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    fn admits(&self, name: &str) -> bool {
        self.open || self.index.contains_key(name)
    }
}

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
    /// Compiles `num` for the field `field`, resolving identifiers against
    /// `names`; an expression longer than [`MAX_EXPRESSION_CHARS`] is refused.
    pub fn new(num: &Num, names: &Names<'_>, field: &str) -> Result<Self, SceneError> {
        match num {
            Num::Value(v) => Ok(Compiled::Value(*v)),
            Num::Expr(source) => {
                let bad = |why: String| SceneError::field(field, format!("{why} in expression '{source}'"));
                // A plain number, scientific notation included ("1e-3").
                if let Ok(v) = source.trim().parse::<f64>() {
                    if v.is_finite() {
                        return Ok(Compiled::Value(v));
                    }
                    return Err(bad(format!("not a finite number, got {v}")));
                }
                let expr = parse(source, names, field)?;
                let vars = expr
                    .var_names()
                    .iter()
                    .map(|v| {
                        names.get(v).ok_or_else(|| {
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

    /// Evaluates with the given parameter values; a non-finite result is an
    /// error naming the field `field()` (only called for an error: scenes are
    /// evaluated for every cell and every orbit solve).
    pub fn eval(&self, values: &[f64], field: impl FnOnce() -> String) -> Result<f64, SceneError> {
        let v = match self {
            Compiled::Value(v) => *v,
            Compiled::Expr { source, expr, vars } => {
                let args: Vec<f64> = vars.iter().map(|&i| values[i]).collect();
                match expr.eval(&args) {
                    Ok(v) => v,
                    Err(e) => return Err(SceneError::field(field(), format!("cannot evaluate '{source}': {e}"))),
                }
            }
        };
        if v.is_finite() {
            Ok(v)
        } else {
            let what = match self {
                Compiled::Value(_) => String::new(),
                Compiled::Expr { source, .. } => format!(" ('{source}')"),
            };
            Err(SceneError::field(field(), format!("not a finite number{what}, got {v}")))
        }
    }
}

/// Parses expression `source` of field `field`, its identifiers checked
/// against `names`; one longer than [`MAX_EXPRESSION_CHARS`] is refused.
pub(crate) fn parse(source: &str, names: &Names<'_>, field: &str) -> Result<FlatEx<f64>, SceneError> {
    let chars = source.chars().count();
    if chars > MAX_EXPRESSION_CHARS {
        return Err(SceneError::field(
            field,
            format!("expression of {chars} characters, at most {MAX_EXPRESSION_CHARS} are supported"),
        ));
    }
    let bad = |why: String| SceneError::field(field, format!("{why} in expression '{source}'"));
    let text = check(source, names).map_err(bad)?;
    exmex::parse::<f64>(&text).map_err(|e| {
        let first = e.to_string().lines().next().unwrap_or_default().to_string();
        bad(format!("cannot parse ({first})"))
    })
}

/// Functions an expression may call (exmex's float operators).
pub const FUNCTIONS: [&str; 26] = [
    "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "floor", "ceil",
    "round", "trunc", "fract", "sqrt", "cbrt", "exp", "ln", "log", "log2", "log10", "abs", "signum",
];
/// Constants an expression may use.
pub const CONSTANTS: [&str; 4] = ["PI", "π", "E", "e"];

/// Whether `name` may name a parameter: an identifier (a letter or `_`, then
/// letters, digits, `_`) that is neither a function nor a constant.
pub fn valid_parameter_name(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    let ident =
        chars.next().is_some_and(|c| c.is_alphabetic() || c == '_') && chars.all(|c| c.is_alphanumeric() || c == '_');
    if !ident {
        return Err(format!("'{name}' is not a name (a letter or '_', then letters, digits or '_')"));
    }
    if FUNCTIONS.contains(&name) || CONSTANTS.contains(&name) {
        return Err(format!("'{name}' is reserved (a function or constant of expressions)"));
    }
    Ok(())
}

/// Checks the tokens of an expression and returns the text exmex parses: every
/// number written out without an exponent (exmex reads `1e-3` as `1 e - 3`),
/// every variable in braces.
/// Errors say what is wrong: an unknown function or parameter, a missing
/// operand, an unbalanced parenthesis, a stray character.
fn check(source: &str, names: &Names<'_>) -> Result<String, String> {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::new();
    let mut depth = 0i32;
    // Whether the last token ends an operand (a number, a name, ')').
    let mut operand = false;
    let mut last_op: Option<char> = None;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            out.push(c);
            i += 1;
        } else if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit())) {
            let (literal, v, end) = number_at(&chars, i)?;
            i = end;
            if operand {
                return Err(format!("expected an operator before '{literal}'"));
            }
            out.push_str(&plain(v));
            operand = true;
            last_op = None;
        } else if c.is_alphabetic() || c == '_' {
            let (name, call, end) = name_at(&chars, i, names)?;
            i = end;
            if operand {
                return Err(format!("expected an operator before '{name}'"));
            }
            if call || CONSTANTS.contains(&name.as_str()) {
                out.push_str(&name);
            } else {
                // A variable in braces, as exmex reads any name: bare, a name
                // that begins like one of its operators (`max_x`, `min_gap`)
                // is split into the operator and the rest.
                out.push_str(&format!("{{{name}}}"));
            }
            operand = !call;
            last_op = None;
        } else if c == '{' {
            // A name written in braces, which may hold characters that a bare
            // name may not: a built-in quantity of a stop or friction contact
            // whose name has a '-' (`{slip_M1-M2}`).
            let Some(len) = chars[i + 1..].iter().position(|&d| d == '}') else {
                return Err("'{' without '}': a name in braces ends with '}'".into());
            };
            let name: String = chars[i + 1..i + 1 + len].iter().collect();
            if name.trim().is_empty() || name.contains('{') {
                return Err(format!("'{{{name}}}' is not a name in braces"));
            }
            if operand {
                return Err(format!("expected an operator before '{{{name}}}'"));
            }
            if !names.admits(&name) {
                return Err(format!("unknown parameter '{name}'"));
            }
            out.push_str(&format!("{{{name}}}"));
            i += len + 2;
            operand = true;
            last_op = None;
        } else if "+-*/^".contains(c) {
            let unary = c == '+' || c == '-';
            if !operand && !unary {
                return Err(match last_op {
                    Some(op) => format!("expected an operand after '{op}'"),
                    None => format!("expected an operand before '{c}'"),
                });
            }
            out.push(c);
            operand = false;
            last_op = Some(c);
            i += 1;
        } else if c == '(' {
            if operand {
                return Err("expected an operator before '('".into());
            }
            depth += 1;
            out.push(c);
            i += 1;
        } else if c == ')' {
            if !operand {
                return Err(match last_op {
                    Some(op) => format!("expected an operand after '{op}'"),
                    None => "empty parentheses".into(),
                });
            }
            depth -= 1;
            if depth < 0 {
                return Err("unbalanced parentheses: ')' without '('".into());
            }
            out.push(c);
            i += 1;
        } else {
            return Err(format!("unexpected character '{c}'"));
        }
    }
    if depth > 0 {
        return Err("unbalanced parentheses: '(' without ')'".into());
    }
    if !operand {
        return Err(match last_op {
            Some(op) => format!("expected an operand after '{op}'"),
            None => "empty expression".into(),
        });
    }
    Ok(out)
}

/// The number literal starting at `chars[i]` (digits, a point, an exponent):
/// its text, its finite value, and where it ends.
fn number_at(chars: &[char], mut i: usize) -> Result<(String, f64, usize), String> {
    let start = i;
    while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
        i += 1;
    }
    if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
        let mut j = i + 1;
        if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
            j += 1;
        }
        if j < chars.len() && chars[j].is_ascii_digit() {
            while j < chars.len() && chars[j].is_ascii_digit() {
                j += 1;
            }
            i = j;
        }
    }
    let literal: String = chars[start..i].iter().collect();
    let v: f64 = literal.parse().map_err(|_| format!("'{literal}' is not a number"))?;
    if !v.is_finite() {
        return Err(format!("'{literal}' is not a finite number"));
    }
    Ok((literal, v, i))
}

/// The name starting at `chars[i]`, whether it is called (a known function
/// followed by `(`), and where it ends; an unknown function or parameter is
/// refused.
fn name_at(chars: &[char], mut i: usize, names: &Names<'_>) -> Result<(String, bool, usize), String> {
    let start = i;
    while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
        i += 1;
    }
    let name: String = chars[start..i].iter().collect();
    let mut k = i;
    while k < chars.len() && chars[k].is_whitespace() {
        k += 1;
    }
    let call = chars.get(k) == Some(&'(');
    if call && !FUNCTIONS.contains(&name.as_str()) {
        return Err(format!("unknown function '{name}' (known: {})", FUNCTIONS.join(", ")));
    }
    if !call && !CONSTANTS.contains(&name.as_str()) && !names.admits(&name) {
        return Err(if FUNCTIONS.contains(&name.as_str()) {
            format!("function '{name}' needs an argument in parentheses")
        } else {
            format!("unknown parameter '{name}'")
        });
    }
    Ok((name, call, i))
}

/// `v` written without an exponent, as exmex reads numbers (Rust's `Display`
/// of an f64 never uses one, and reads back to the same value).
fn plain(v: f64) -> String {
    format!("{v}")
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

    /// Its ends `[lo, hi]` (open or closed; infinite where unbounded).
    pub fn bounds(&self) -> [f64; 2] {
        [self.lo, self.hi]
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
    fn a_name_that_begins_like_an_operator_is_a_variable() {
        // exmex reads a bare `max_gap` as its operator `max` and `_gap`.
        let names = ["max_gap".to_string(), "min".to_string(), "e2".to_string()];
        let c = Compiled::new(&Num::Expr("2*max_gap + min - e2 + e".into()), &Names::new(&names), "f").unwrap();
        let v = c.eval(&[3.0, 0.5, 1.0], String::new).unwrap();
        assert!((v - (6.0 + 0.5 - 1.0 + std::f64::consts::E)).abs() < 1e-15, "{v}");
    }

    /// A name in braces may hold a '-' (a built-in quantity of a stop or
    /// contact whose name has one, `{slip_M1-M2}`), which bare reads as a
    /// subtraction.
    #[test]
    fn a_name_in_braces_may_hold_a_hyphen() {
        let names = ["a-b".to_string(), "c".to_string()];
        let c = Compiled::new(&Num::Expr("2*{a-b} - {c} + c".into()), &Names::new(&names), "f").unwrap();
        let v = c.eval(&[3.0, 0.5], String::new).unwrap();
        assert!((v - 6.0).abs() < 1e-15, "{v}");
        let err = |t: &str| Compiled::new(&Num::Expr(t.into()), &Names::new(&names), "f").unwrap_err().to_string();
        assert_eq!(err("2*{a-c}"), "f: unknown parameter 'a-c' in expression '2*{a-c}'");
        assert_eq!(err("{a-b"), "f: '{' without '}': a name in braces ends with '}' in expression '{a-b'");
        assert_eq!(err("1 + {}"), "f: '{}' is not a name in braces in expression '1 + {}'");
        assert_eq!(err("c {c}"), "f: expected an operator before '{c}' in expression 'c {c}'");
        // Where any name is admitted (a quantity's operands, resolved later).
        let expr = parse("{slip_M1-M2} / 2", &Names::open(&[]), "f").unwrap();
        assert_eq!(expr.var_names(), ["slip_M1-M2"]);
    }

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
        let list = vec!["a".to_string(), "mu_m".to_string()];
        let names = Names::new(&list);
        let c = Compiled::new(&Num::Expr("mu_m/(1-mu_m) + a".into()), &names, "f").unwrap();
        let v = c.eval(&[2.0, 0.5], || "f".into()).unwrap();
        assert!((v - 3.0).abs() < 1e-15);
        let e = Compiled::new(&Num::Expr("delt".into()), &names, "masses[0].x0").unwrap_err();
        assert_eq!(e.to_string(), "masses[0].x0: unknown parameter 'delt' in expression 'delt'");
        let value =
            |t: &str| Compiled::new(&Num::Expr(t.into()), &names, "f").and_then(|c| c.eval(&[2.0, 0.5], || "f".into()));
        assert!((value("1e-3").unwrap() - 1e-3).abs() < 1e-18);
        assert!((value("2.5E2 * a").unwrap() - 500.0).abs() < 1e-12);
        assert!((value("-1.5e-2 + mu_m").unwrap() - 0.485).abs() < 1e-15);
        let err = |t: &str| value(t).unwrap_err().to_string();
        assert_eq!(err("1e308*10"), "f: not a finite number ('1e308*10'), got inf");
        assert_eq!(err("1 + * 2"), "f: expected an operand after '+' in expression '1 + * 2'");
        assert!(err("foo(1)").starts_with("f: unknown function 'foo' (known: sin"), "{}", err("foo(1)"));
        assert_eq!(err("(a + 1"), "f: unbalanced parentheses: '(' without ')' in expression '(a + 1'");
        assert_eq!(err("a 2"), "f: expected an operator before '2' in expression 'a 2'");
        assert_eq!(err("a $ 2"), "f: unexpected character '$' in expression 'a $ 2'");
        assert!(valid_parameter_name("PI").is_err() && valid_parameter_name("sin").is_err());
        assert!(valid_parameter_name("a b").is_err() && valid_parameter_name("mu_m").is_ok());
        let c = Compiled::new(&Num::Expr("1/(1-mu_m)".into()), &names, "m").unwrap();
        assert!(c.eval(&[0.0, 1.0], || "m".into()).is_err());
    }

    /// Issue 30: an expression longer than the limit is refused with one line
    /// naming the field, without echoing the expression; one at the limit compiles.
    #[test]
    fn long_expressions_are_refused() {
        let list = vec!["a".to_string()];
        let names = Names::new(&list);
        let at_limit = format!("a{}", "+1".repeat((MAX_EXPRESSION_CHARS - 1) / 2));
        assert!(at_limit.chars().count() <= MAX_EXPRESSION_CHARS);
        let c = Compiled::new(&Num::Expr(at_limit.clone()), &names, "f").unwrap();
        assert!(
            (c.eval(&[1.0], || "f".into()).unwrap() - (1.0 + ((MAX_EXPRESSION_CHARS - 1) / 2) as f64)).abs() < 1e-9
        );
        let long = format!("{at_limit}+1+1");
        let e = Compiled::new(&Num::Expr(long.clone()), &names, "stops[0].position").unwrap_err().to_string();
        let chars = long.chars().count();
        assert_eq!(
            e,
            format!(
                "stops[0].position: expression of {chars} characters, at most {MAX_EXPRESSION_CHARS} are supported"
            )
        );
    }
}
