//! Parameter studies: one atlas per value of a parameter, around a reference
//! scene (e.g. the mass ratio μm ∈ {0.05, 0.25, 0.75, 0.95}); at most
//! [`MAX_VALUES`] values, each naming its own file.
//!
//! ```toml
//! scene = "../multi-stop.toml"     # relative to the study file
//! parameter = "mu_m"
//! values = [0.05, 0.25, 0.75, 0.95]
//! x = "omega=0.1:3.05:120"
//! y = "delta=0.05:2:80"
//! sweep = "fresh"                   # fresh, up, down or both
//! along = "x"
//! [set]                             # optional overrides for every atlas
//! zeta = 0.1
//! ```

use crate::error::GridError;
use serde::Deserialize;
use std::collections::BTreeMap;

/// A study file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    /// Scene file, relative to the study file.
    pub scene: String,
    /// Varied parameter.
    pub parameter: String,
    /// Its values, one atlas each.
    pub values: Vec<f64>,
    /// Horizontal axis `NAME=START:STOP:COUNT`.
    pub x: String,
    /// Vertical axis.
    pub y: String,
    /// Sweep kind (`fresh` by default).
    #[serde(default = "fresh")]
    pub sweep: String,
    /// Direction of continuation chains (`x` by default).
    #[serde(default = "along_x")]
    pub along: String,
    /// Overrides common to every atlas.
    #[serde(default)]
    pub set: BTreeMap<String, f64>,
}

/// Most values of a study: one atlas each, and one panel each on the contact
/// sheet (two panels a row: 100 values draw a sheet about 22 000 pixels tall).
pub const MAX_VALUES: usize = 100;

/// Longest file-name stem of a value's atlas (`parameter=value`), in bytes.
const MAX_STEM_BYTES: usize = 128;

fn fresh() -> String {
    "fresh".into()
}

fn along_x() -> String {
    "x".into()
}

impl Study {
    /// Parses and checks a study file's text.
    pub fn parse(text: &str) -> Result<Study, GridError> {
        let s: Study = toml::from_str(text)
            .map_err(|e| GridError::field("study file", e.to_string().trim().replace('\n', " ")))?;
        if s.values.is_empty() {
            return Err(GridError::field("values", "give at least one value"));
        }
        if s.values.len() > MAX_VALUES {
            return Err(GridError::field(
                "values",
                format!(
                    "at most {MAX_VALUES} values (one atlas and one contact-sheet panel each), got {}; split the study",
                    s.values.len()
                ),
            ));
        }
        if let Some(v) = s.values.iter().find(|v| !v.is_finite()) {
            return Err(GridError::field("values", format!("not a finite number: {v}")));
        }
        for (i, v) in s.values.iter().enumerate() {
            // Values that name the same file (0.5 and 0.50 are one number),
            // or are the same number (-0 + 0 is 0).
            if s.values[..i].iter().any(|w| s.stem(w + 0.0) == s.stem(v + 0.0)) {
                return Err(GridError::field("values", format!("{v} is given twice")));
            }
            let stem = s.stem(*v);
            if stem.len() > MAX_STEM_BYTES {
                return Err(GridError::field(
                    "values",
                    format!("{v:e} makes a file name of {} bytes, more than {MAX_STEM_BYTES}", stem.len() + 3),
                ));
            }
        }
        if let Some((k, _)) = s.set.iter().find(|(_, v)| !v.is_finite()) {
            return Err(GridError::field(format!("set.{k}"), "not a finite number"));
        }
        if s.set.contains_key(&s.parameter) {
            let why = format!("{} is the study's parameter, given by values; set it there", s.parameter);
            return Err(GridError::field(format!("set.{}", s.parameter), why));
        }
        Ok(s)
    }

    /// File-name stem of the atlas of one value, e.g. `mu_m=0.25`.
    pub fn stem(&self, value: f64) -> String {
        format!("{}={value}", self.parameter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_refuses() {
        let s = Study::parse(
            "scene = \"a.toml\"\nparameter = \"mu_m\"\nvalues = [0.25]\nx = \"omega=1:2:3\"\ny = \"delta=1:2:3\"\n",
        )
        .unwrap();
        assert_eq!(s.sweep, "fresh");
        assert_eq!(s.stem(0.25), "mu_m=0.25");
        assert!(Study::parse("scene = \"a.toml\"\nparameter = \"mu_m\"\nvalues = []\nx = \"\"\ny = \"\"\n").is_err());
        assert!(Study::parse(
            "scene = \"a.toml\"\nparameter = \"mu_m\"\nvalues = [1]\nx = \"\"\ny = \"\"\ncolour = 1\n"
        )
        .is_err());
        let values = |v: &str| {
            Study::parse(&format!("scene = \"a.toml\"\nparameter = \"mu_m\"\nvalues = {v}\nx = \"\"\ny = \"\"\n"))
                .map_err(|e| e.to_string())
        };
        let many = format!("[{}]", (0..=MAX_VALUES).map(|i| i.to_string()).collect::<Vec<_>>().join(","));
        assert!(values(&many).unwrap_err().contains("at most 100 values"));
        assert!(values("[0.5, 0.50]").unwrap_err().contains("given twice"));
        assert!(values("[0.0, -0.0]").unwrap_err().contains("-0 is given twice"));
        assert!(values("[1e300]").unwrap_err().contains("file name"));
        assert!(values("[0.25, 0.5]").is_ok());
        // The studied parameter's values are `values`; a `[set]` of it is refused.
        let set = |name: &str| {
            let text = format!(
                "scene = \"a.toml\"\nparameter = \"mu_m\"\nvalues = [0.25]\nx = \"\"\ny = \"\"\n[set]\n{name} = 0.3\n"
            );
            Study::parse(&text).map_err(|e| e.to_string())
        };
        assert!(set("zeta").is_ok(), "{:?}", set("zeta"));
        assert!(set("mu_m").unwrap_err().contains("set.mu_m: mu_m is the study's parameter"), "{:?}", set("mu_m"));
    }
}
