//! Helpers shared by the integration tests: the binary's runs, and (from the
//! solver's physics tests, one copy for both) the shipped scenes' systems and
//! a recording observer.

use std::path::PathBuf;
use std::process::{Command, Output};

#[path = "../crates/solver/tests/physics/common.rs"]
#[allow(dead_code, reason = "shared with the solver's physics tests, which read the impacts' states")]
mod common;
pub use common::{config, record, system};

/// Runs the real binary.
pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vibroatlas")).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

/// Runs `cell ... --json` and parses its one JSON object.
pub fn cell_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["cell"];
    all.extend_from_slice(args);
    all.push("--json");
    let out = run(&all);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The folder of the tests' scratch files: Cargo's `target/tmp` (which
/// `cargo clean` empties), not the system's temp dir, which runs would fill.
pub fn scratch_root() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
}

/// A fresh scratch folder for one test (`vibroatlas-NAME` in
/// [`scratch_root`]), emptied when the test starts: a run leaves at most one
/// of each, to look at after a failure.
pub fn scratch(name: &str) -> PathBuf {
    let d = scratch_root().join(format!("vibroatlas-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the binary, which must succeed, and parses its one JSON object.
pub fn json_of(args: &[&str]) -> serde_json::Value {
    let out = run(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Runs the binary, which must succeed.
pub fn ok(args: &[&str]) {
    let out = run(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// The arguments of `curve` for the dry-friction pitchfork from
/// (ω, fk) = (6.845, 0.01) to fk = `to` in `steps` steps, then `extra`.
pub fn pitchfork<'a>(to: &'a str, steps: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["curve", "configs/dry-friction.toml", "--kind", "pf", "--start", "omega=6.845,fk=0.01"];
    args.extend(["--free", "omega,fk", "--to", to, "--steps", steps]);
    args.extend_from_slice(extra);
    args
}
