//! Results as JSON: every result has a report type that derives
//! `serde::Serialize`; `--json`, Python and the explorer print the same value.

use serde::Serialize;
use serde_json::Value;

/// A report as a JSON value: objects with their keys in sorted order, as
/// every `--json` prints them.
pub(crate) fn to_value(report: &impl Serialize) -> Value {
    // Every report is made of strings, numbers, options, sequences and
    // string-keyed maps, which always serialise.
    serde_json::to_value(report).unwrap_or(Value::Null)
}
