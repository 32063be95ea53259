//! How a parameter is written for readers: its symbol (`ω` for `omega`) and
//! its long name (`forcing frequency`), declared in the scene or derived from
//! the parameter's name.

use crate::error::SceneError;

/// Longest symbol a scene may declare, in characters (Unicode scalar values).
pub const SYMBOL_MAX_CHARS: usize = 16;

/// The Greek alphabet: (name, small letter, capital letter).
const GREEK: [(&str, char, char); 24] = [
    ("alpha", 'α', 'Α'),
    ("beta", 'β', 'Β'),
    ("gamma", 'γ', 'Γ'),
    ("delta", 'δ', 'Δ'),
    ("epsilon", 'ε', 'Ε'),
    ("zeta", 'ζ', 'Ζ'),
    ("eta", 'η', 'Η'),
    ("theta", 'θ', 'Θ'),
    ("iota", 'ι', 'Ι'),
    ("kappa", 'κ', 'Κ'),
    ("lambda", 'λ', 'Λ'),
    ("mu", 'μ', 'Μ'),
    ("nu", 'ν', 'Ν'),
    ("xi", 'ξ', 'Ξ'),
    ("omicron", 'ο', 'Ο'),
    ("pi", 'π', 'Π'),
    ("rho", 'ρ', 'Ρ'),
    ("sigma", 'σ', 'Σ'),
    ("tau", 'τ', 'Τ'),
    ("upsilon", 'υ', 'Υ'),
    ("phi", 'φ', 'Φ'),
    ("chi", 'χ', 'Χ'),
    ("psi", 'ψ', 'Ψ'),
    ("omega", 'ω', 'Ω'),
];

/// The symbol of a parameter that declares none: a name that is a Greek
/// letter's, optionally followed by digits or by `_` and a suffix, is written
/// with the letter (`omega` → `ω`, `delta12` → `δ12`, `mu_k` → `μ_k`; a
/// capitalised name gives the capital, `Omega` → `Ω`); any other name is
/// written as it is (`fk`, `b`, `R`, `f20`, `deltax`). Figures draw plain
/// text, so a subscript stays `_k`.
pub fn symbol_of(name: &str) -> String {
    for &(greek, small, capital) in &GREEK {
        let (letter, rest) = if let Some(rest) = name.strip_prefix(greek) {
            (small, rest)
        } else {
            let mut chars = greek.chars();
            let first = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or_default();
            match name.strip_prefix(first).and_then(|r| r.strip_prefix(chars.as_str())) {
                Some(rest) => (capital, rest),
                None => continue,
            }
        };
        let suffix_ok =
            rest.is_empty() || rest.chars().all(|c| c.is_ascii_digit()) || (rest.len() > 1 && rest.starts_with('_'));
        if suffix_ok {
            return format!("{letter}{rest}");
        }
    }
    name.to_string()
}

/// Checks a short text of field `field` (a symbol, units): not empty (else
/// the message `empty`), at most [`SYMBOL_MAX_CHARS`] characters (else the
/// message names `kind`), no control characters.
fn check_short(text: &str, field: &str, empty: &str, kind: &str) -> Result<(), SceneError> {
    if text.trim().is_empty() {
        return Err(SceneError::field(field, format!("must not be empty ({empty})")));
    }
    let n = text.chars().count();
    if n > SYMBOL_MAX_CHARS {
        return Err(SceneError::field(field, format!("at most {SYMBOL_MAX_CHARS} characters ({kind}), got {n}")));
    }
    if let Some(c) = text.chars().find(|c| c.is_control()) {
        return Err(SceneError::field(field, format!("must not hold control characters, got {c:?}")));
    }
    Ok(())
}

/// Checks a declared `symbol` (field `parameters.NAME.symbol`): not empty, at
/// most [`SYMBOL_MAX_CHARS`] characters, no control characters.
pub(crate) fn check_symbol(symbol: &str, field: &str) -> Result<(), SceneError> {
    check_short(symbol, field, "e.g. symbol = \"ω\"", "a short symbol; a description goes in long_name")
}

/// Checks a declared `long_name` (field `parameters.NAME.long_name`): one line
/// of text, not empty.
pub(crate) fn check_long_name(long_name: &str, field: &str) -> Result<(), SceneError> {
    if long_name.trim().is_empty() {
        return Err(SceneError::field(field, "must not be empty (leave it out to use the parameter's doc)"));
    }
    if let Some(c) = long_name.chars().find(|c| c.is_control()) {
        return Err(SceneError::field(
            field,
            format!("must be one line, without newlines or control characters, got {c:?}"),
        ));
    }
    Ok(())
}

/// The long name a `doc` gives: its first line, trimmed (`None` when empty).
pub(crate) fn long_name_of_doc(doc: &str) -> Option<&str> {
    Some(doc.lines().next()?.trim()).filter(|l| !l.is_empty())
}

/// Checks declared `units` (field `…units`): not empty, at most
/// [`SYMBOL_MAX_CHARS`] characters (`m/s`, `N m`, `dB`), no control
/// characters.
pub(crate) fn check_units(units: &str, field: &str) -> Result<(), SceneError> {
    check_short(units, field, "e.g. units = \"m\"; a pure number is \"1\"", "CF units: m, m/s, N s, dB")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn greek_names_become_letters_and_others_stay() {
        let table = [
            ("omega", "ω"),
            ("delta", "δ"),
            ("zeta", "ζ"),
            ("mu", "μ"),
            ("sigma", "σ"),
            ("tau", "τ"),
            ("alpha", "α"),
            ("beta", "β"),
            ("gamma", "γ"),
            ("epsilon", "ε"),
            ("eta", "η"),
            ("theta", "θ"),
            ("iota", "ι"),
            ("kappa", "κ"),
            ("lambda", "λ"),
            ("nu", "ν"),
            ("xi", "ξ"),
            ("omicron", "ο"),
            ("pi", "π"),
            ("rho", "ρ"),
            ("upsilon", "υ"),
            ("phi", "φ"),
            ("chi", "χ"),
            ("psi", "ψ"),
            ("Omega", "Ω"),
            ("Delta", "Δ"),
            ("mu_k", "μ_k"),
            ("mu_m", "μ_m"),
            ("delta_12", "δ_12"),
            ("delta1", "δ1"),
            ("delta12", "δ12"),
            ("omega0", "ω0"),
            // Not a Greek letter's name, or one followed by more letters.
            ("fk", "fk"),
            ("b", "b"),
            ("R", "R"),
            ("r", "r"),
            ("f20", "f20"),
            ("deltax", "deltax"),
            ("delta_", "delta_"),
            ("etas", "etas"),
            ("OMEGA", "OMEGA"),
            ("mus", "mus"),
            ("x_mu", "x_mu"),
            ("", ""),
        ];
        for (name, symbol) in table {
            assert_eq!(symbol_of(name), symbol, "{name}");
        }
    }

    #[test]
    fn declared_texts_are_checked() {
        assert!(check_symbol("ω", "f").is_ok());
        assert!(check_symbol("f_k", "f").is_ok());
        assert!(check_symbol("μ_k", "f").is_ok());
        assert!(check_symbol("ωωωωωωωωωωωωωωωω", "f").is_ok(), "16 characters, not bytes");
        let msg = |r: Result<(), SceneError>| r.unwrap_err().to_string();
        assert!(
            msg(check_symbol("", "parameters.omega.symbol")).starts_with("parameters.omega.symbol: must not be empty")
        );
        assert!(msg(check_symbol("  ", "s")).contains("must not be empty"));
        assert!(msg(check_symbol("ωωωωωωωωωωωωωωωωω", "s")).contains("at most 16 characters"));
        assert!(msg(check_symbol("a\tb", "s")).contains("control characters"));
        assert!(check_long_name("forcing frequency", "l").is_ok());
        assert!(msg(check_long_name("two\nlines", "parameters.omega.long_name"))
            .starts_with("parameters.omega.long_name: must be one line"));
        assert!(msg(check_long_name("", "l")).contains("must not be empty"));
        assert_eq!(long_name_of_doc("  mass ratio M2/(M1+M2)\nmore"), Some("mass ratio M2/(M1+M2)"));
        assert_eq!(long_name_of_doc(""), None);
    }

    fn scene(parameters: &str) -> Result<crate::Scene, SceneError> {
        crate::Scene::parse(&format!(
            "name = \"s\"\n[parameters]\n{parameters}\n[forcing]\nomega = \"omega\"\n[[masses]]\nname = \"M1\"\nmass = 1\nforce = 1\n[[links]]\nmasses = [\"M1\"]\nstiffness = 1\n"
        ))
    }

    #[test]
    fn scenes_declare_symbols_and_long_names() {
        let s = scene(
            "omega = { value = 0.5, doc = \"forcing frequency\" }\n\
             fk = { value = 0.1, symbol = \"f_k\", long_name = \"kinetic friction force\", doc = \"f_k: see models.md\" }\n\
             mu_k = 0.5\n\
             w = { value = 1, symbol = \"Ω̃\", doc = \"\" }",
        )
        .unwrap();
        assert_eq!(s.parameter_names(), ["fk", "mu_k", "omega", "w"]);
        assert_eq!(s.symbol("omega"), "ω");
        assert_eq!(s.symbol("fk"), "f_k");
        assert_eq!(s.symbol("mu_k"), "μ_k");
        assert_eq!(s.symbol("w"), "Ω̃");
        assert_eq!(s.symbol("delta"), "δ", "not a parameter: the Greek rule");
        assert_eq!(s.long_name("omega"), Some("forcing frequency"), "from the doc");
        assert_eq!(s.long_name("fk"), Some("kinetic friction force"), "declared, not the doc");
        assert_eq!(s.long_name("mu_k"), None);
        assert_eq!(s.long_name("w"), None);
        assert_eq!(s.long_name("delta"), None);
    }

    #[test]
    fn bad_symbols_and_long_names_name_their_field() {
        let err = |p: &str| scene(p).unwrap_err().to_string();
        assert!(err("omega = { value = 1, symbol = \"\" }").starts_with("parameters.omega.symbol: must not be empty"));
        assert!(err("omega = { value = 1, symbol = \"abcdefghijklmnopq\" }")
            .starts_with("parameters.omega.symbol: at most 16 characters"));
        assert!(
            err("omega = { value = 1, symbol = \"a\\u0007\" }").starts_with("parameters.omega.symbol: must not hold")
        );
        assert!(err("omega = { value = 1, long_name = \"a\\nb\" }")
            .starts_with("parameters.omega.long_name: must be one line"));
        assert!(err("omega = { value = 1, long_name = \" \" }")
            .starts_with("parameters.omega.long_name: must not be empty"));
    }
}
