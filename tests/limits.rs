//! Issue 30 (items 3 and 9): every budget bounds every integrator, and scene
//! sizes are bounded. Each test runs the real binary on one reproducer of the
//! audit, with a deadline: a run still going after it is killed and the test
//! fails (a hang). No test asserts a speed.

use crate::util::scratch;

use std::io::Read;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_vibroatlas");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Runs the binary with `args`, killed after `secs` seconds (the test then
/// fails: a hang). Output is read while the child runs, so that a full pipe
/// cannot block it.
fn run_within(args: &[&str], secs: u64) -> Output {
    let mut child =
        Command::new(BIN).args(args).current_dir(ROOT).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let deadline = Instant::now() + Duration::from_secs(secs);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{}: still running after {secs} s (a hang)", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output { status, stdout: out.join().unwrap(), stderr: err.join().unwrap() }
}

/// Exit code 2 and one line on stderr naming `field` and containing `what`.
fn refused(out: &Output, field: &str, what: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "expected exit 2: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(&format!("{field}: ")) && err.contains(what), "expected '{field}: … {what}' in: {err}");
    assert!(err.len() < 400, "the line must not echo the input: {} bytes", err.len());
}

/// A chain of `masses` masses, each tied to the previous one (the first to
/// the frame), with a stop under the first; `position` is its expression.
fn chain(masses: usize, position: &str) -> String {
    let mut s =
        String::from("name = \"chain\"\n[parameters]\nomega = 1.0\ndelta = 0.5\n[forcing]\nomega = \"omega\"\n");
    for i in 1..=masses {
        s += &format!("[[masses]]\nname = \"M{i}\"\nmass = 1\nforce = {}\n", u8::from(i == 1));
    }
    for i in 1..=masses {
        let ends = if i == 1 { "\"M1\"".to_string() } else { format!("\"M{}\", \"M{i}\"", i - 1) };
        s += &format!("[[links]]\nmasses = [{ends}]\nstiffness = 1\ndamping = 0.1\n");
    }
    s + &format!(
        "[[stops]]\nname = \"A1\"\nmass = \"M1\"\nside = \"below\"\nposition = \"{position}\"\nrestitution = 0.8\n"
    )
}

/// The `cell` JSON of a successful run.
fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Issue 30, item 3: RK4 at `precise` on a chattering cell (δ = 1e-4, ω = 1)
/// ran for minutes, every event's step-back refinement creeping on at the
/// smallest step; `--accuracy max_events=3e5` took 121 s. RK4's steps now
/// count against the event budget, so the cell ends `U`, both labels, with
/// the budget's reason, well before the deadline.
#[test]
#[ignore = "slow: the full suite runs it"]
fn rk4_steps_count_against_the_event_budget() {
    let base = ["cell", "configs/multi-stop.toml", "--set", "delta=1e-4", "--set", "omega=1.0"];
    for extra in [&["--accuracy", "max_events=3e5"][..], &[][..]] {
        let mut args = base.to_vec();
        args.extend(["--preset", "precise", "--integrator", "rk4", "--json"]);
        args.extend_from_slice(extra);
        let cell = json(&run_within(&args, 300));
        assert_eq!(cell["class"], "unresolved", "{cell}");
        assert_eq!(cell["labels"]["M1"], "U");
        assert_eq!(cell["labels"]["M2"], "U");
        let max = if extra.is_empty() { 4_000_000 } else { 300_000 };
        assert_eq!(cell["reason"], format!("event budget of {max} events exhausted"), "{cell}");
        // The steps' share of the budget: fewer events than the limit were handled.
        assert!(cell["events"].as_u64().unwrap() < max, "{cell}");
    }
    // The same cell under the exact integrator at `standard` (0.02 s) is periodic.
    let mut args = base.to_vec();
    args.push("--json");
    let cell = json(&run_within(&args, 120));
    assert_eq!(cell["class"], "periodic", "{cell}");
}

/// Issue 30, item 9: a scene with 300 masses did not finish `cell` in 120 s;
/// it is refused when loaded, one line naming `masses`, by every command that
/// reads a scene. 64 masses (the limit) load and simulate.
#[test]
fn too_many_masses_are_refused_with_one_line() {
    let dir = scratch("limits-masses");
    let many = dir.join("m300.toml");
    std::fs::write(&many, chain(300, "-delta")).unwrap();
    let many = many.to_str().unwrap();
    refused(&run_within(&["cell", many], 60), "masses", "at most 64 masses are supported, got 300");
    let out = dir.join("m300.h5");
    let atlas = ["atlas", many, "--x", "omega=0.5:1:2", "--y", "delta=0.1:1:2", "-o", out.to_str().unwrap()];
    refused(&run_within(&atlas, 60), "masses", "got 300");
    assert!(!out.exists());

    let at_limit = dir.join("m64.toml");
    std::fs::write(&at_limit, chain(64, "-delta")).unwrap();
    let quick = ["--accuracy", "min_transient=1", "--accuracy", "max_periods=4", "--accuracy", "lyapunov_periods=0"];
    let mut args = vec!["cell", at_limit.to_str().unwrap(), "--json"];
    args.extend(quick);
    let cell = json(&run_within(&args, 300));
    assert_eq!(cell["final_state"].as_array().unwrap().len(), 128);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30, item 9: more stops than the solver supports are refused at load,
/// one line naming `stops`.
#[test]
fn too_many_stops_are_refused_with_one_line() {
    let dir = scratch("limits-stops");
    let mut text = chain(2, "-delta");
    for k in 2..=17 {
        text += &format!(
            "[[stops]]\nname = \"B{k}\"\nmass = \"M2\"\nside = \"below\"\nposition = -{k}\nrestitution = 0.8\n"
        );
    }
    let path = dir.join("s17.toml");
    std::fs::write(&path, text).unwrap();
    refused(&run_within(&["cell", path.to_str().unwrap()], 60), "stops", "at most 16 stops are supported, got 17");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30, item 9: a 100 000-term expression took 91 s to parse (exmex
/// folds constants in time growing with the square of the length). An
/// expression longer than the limit is refused, one line naming its field and
/// without echoing it; one of a few hundred terms loads.
#[test]
fn huge_expressions_are_refused_with_one_line() {
    let dir = scratch("limits-expr");
    let huge = format!("-0.5*({})", vec!["1"; 100_000].join("*"));
    let path = dir.join("huge.toml");
    std::fs::write(&path, chain(1, &huge)).unwrap();
    let n = huge.chars().count();
    let out = run_within(&["cell", path.to_str().unwrap()], 60);
    refused(&out, "stops[0].position", &format!("expression of {n} characters, at most 1000 are supported"));

    let fits = format!("-0.5*({})", vec!["1"; 400].join("*"));
    assert!(fits.chars().count() <= 1000);
    let path = dir.join("fits.toml");
    std::fs::write(&path, chain(1, &fits)).unwrap();
    let cell = json(&run_within(&["cell", path.to_str().unwrap(), "--json"], 120));
    assert!(cell["class"].is_string(), "{cell}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30, item 9: parameters are resolved in one pass in dependency order
/// (it took a pass per parameter: 15 s for a chain of 30 000). A chain of
/// 20 000 parameters, each defined by the next, loads and evaluates.
#[test]
fn a_long_chain_of_parameters_loads() {
    let dir = scratch("limits-params");
    let mut text = chain(1, "-delta");
    let n = 20_000;
    let mut params = String::new();
    for i in 0..n {
        params += &format!("p{i:05} = \"p{:05} + 1\"\n", i + 1);
    }
    params += &format!("p{n:05} = 0.25\n");
    text = text.replace("delta = 0.5\n", &format!("delta = \"p00000 - {n} + 0.25\"\n{params}"));
    let path = dir.join("chain.toml");
    std::fs::write(&path, text).unwrap();
    let args =
        ["cell", path.to_str().unwrap(), "--json", "--accuracy", "min_transient=1", "--accuracy", "max_periods=4"];
    let cell = json(&run_within(&args, 120));
    let delta = cell["parameters"]["delta"].as_f64().unwrap();
    assert!((delta - 0.5).abs() < 1e-9, "{delta}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The ninth audit: each compiled expression takes about 20 KB (exmex's
/// nodes kept inline), so a 9 MB scene of distinct expressions asked for
/// 10 GB. Beyond [`scene::MAX_EXPRESSIONS`] among the parameters and links a
/// scene is refused before any is compiled.
#[test]
fn a_scene_of_more_expressions_than_the_limit_is_refused_at_once() {
    let dir = scratch("limits-expressions");
    let n = scene::MAX_EXPRESSIONS;
    let mut params = String::with_capacity(20 * n);
    for i in 0..=n {
        params += &format!("q{i} = \"delta + {i}\"\n");
    }
    let text = chain(1, "-delta").replace("delta = 0.5\n", &format!("delta = 0.5\n{params}"));
    let path = dir.join("many.toml");
    std::fs::write(&path, text).unwrap();
    let out = run_within(&["cell", path.to_str().unwrap()], 60);
    let said = format!(
        "at most {n} expressions (parameters and links; each about 20 KB once compiled) are supported, got {}",
        n + 1
    );
    refused(&out, "parameters", &said);
    let _ = std::fs::remove_dir_all(&dir);
}
