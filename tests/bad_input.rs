//! Bad input: one clear error line naming the field, exit code 2, no panic (issue 2).

use crate::util::run;

fn expect_error(args: &[&str], field: &str) {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(field), "error should name '{field}': {err}");
    assert!(out.stdout.is_empty());
}

fn scene_file(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("vibroatlas-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn multi_stop_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(crate::util::config("multi-stop.toml")).unwrap();
    assert!(text.contains(from));
    text.replacen(from, to, 1)
}

#[test]
fn malformed_toml() {
    let p = scene_file("malformed.toml", "name = \"x\"\n[parameters\nomega = 1\n");
    expect_error(&["cell", p.to_str().unwrap()], "scene file");
}

#[test]
fn unknown_key() {
    let p = scene_file("unknown.toml", &multi_stop_with("restitution = \"R\"", "restitution = \"R\"\nelasticity = 1"));
    expect_error(&["cell", p.to_str().unwrap()], "elasticity");
}

#[test]
fn missing_parameter_in_expression() {
    let p = scene_file("missing.toml", &multi_stop_with("position = \"-delta1\"", "position = \"-delta9\""));
    expect_error(&["cell", p.to_str().unwrap()], "stops[0].position");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omgea=0.3"], "omgea");
}

#[test]
fn mass_ratio_outside_unit_interval() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "mu_m=1.5"], "parameters.mu_m");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "mu_k=0"], "parameters.mu_k");
}

#[test]
fn restitution_outside_unit_interval() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "R=1.2"], "parameters.R");
    expect_error(&["cell", "configs/single-stop.toml", "--set", "r=-0.1"], "parameters.r");
    // Without a declared range the stop itself refuses it.
    let p = scene_file(
        "r.toml",
        &multi_stop_with("R = { value = 0.8, range = \"[0, 1]\", doc = \"coefficient of restitution\" }", "R = 1.2"),
    );
    expect_error(&["cell", p.to_str().unwrap()], "stops[0].restitution");
}

#[test]
fn negative_clearance() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "delta=-0.1"], "delta");
    expect_error(&["cell", "configs/impact-damper.toml", "--set", "delta=-1"], "delta");
}

#[test]
fn nan_in_set() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega=nan"], "--set omega");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega=abc"], "--set omega");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega"], "--set");
}

#[test]
fn bad_options() {
    expect_error(&["cell", "configs/multi-stop.toml", "--preset", "quick"], "--preset");
    expect_error(&["cell", "configs/multi-stop.toml", "--integrator", "euler"], "--integrator");
    expect_error(&["cell", "configs/multi-stop.toml", "--accuracy", "n_max=0"], "n_max");
    expect_error(&["cell", "configs/missing.toml"], "configs/missing.toml");
    expect_error(&["cell", "configs/multi-stop.toml", "--trace", "/nonexistent-dir/t.csv"], "/nonexistent-dir/t.csv");
}
