//! Run safety (issue 21): nothing lost, nothing wrong, never a crash. Each test reproduces
//! one defect of the adversarial audit and checks the fix through the binary.

use crate::util::{run, scratch};

use std::process::{Command, Stdio};

/// Exit code 2, one line on stderr containing `what`, no panic.
pub(crate) fn refused(args: &[&str], what: &str) {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(what), "{args:?}: expected '{what}' in: {err}");
}

const SMALL: [&str; 6] = ["--x", "omega=0.2:2.5:12", "--y", "delta=0.1:1.5:4", "--sweep", "both"];

fn atlas(out: &str, extra: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = ["atlas", "configs/multi-stop.toml"].iter().map(|s| s.to_string()).collect();
    v.extend(SMALL.iter().map(|s| s.to_string()));
    v.extend(extra.iter().map(|s| s.to_string()));
    v.extend(["--quiet", "-o", out].iter().map(|s| s.to_string()));
    v
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[test]
fn a_second_run_on_the_same_output_is_refused_and_the_first_completes() {
    let d = scratch("lock");
    let out = d.join("cc.h5");
    let o = out.to_str().unwrap();
    let big = ["atlas", "configs/multi-stop.toml", "--x", "omega=0.1:3.05:48", "--y", "delta=0.05:2:48"];
    let mut first = Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(big)
        .args(["--sweep", "both", "--threads", "1", "--quiet", "-o", o])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the first run to hold its lock (its journal appears with it).
    let lock = d.join(".cc.h5.lock");
    for _ in 0..200 {
        if lock.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let second: Vec<&str> =
        big.iter().copied().chain(["--sweep", "both", "--set", "zeta=0.15", "--quiet", "-o", o]).collect();
    refused(&second, "is being written by another vibroatlas run (pid");
    assert!(first.wait().unwrap().success());
    let info = run(&["inspect", o, "--json"]);
    let j: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert!(!j["command"].as_str().unwrap().contains("zeta=0.15"), "the file is the first run's");
    assert!(!lock.exists() && !d.join(".cc.h5.journal").exists());
}

#[test]
fn outputs_that_are_folders_scenes_or_devices_are_refused_before_work() {
    let d = scratch("paths");
    let ds = d.to_str().unwrap();
    refused(&strs(&atlas(ds, &[])), "is a directory");
    assert!(std::fs::read_dir(&d).unwrap().next().is_none(), "nothing left beside it");
    let scene = d.join("s.toml");
    std::fs::copy("configs/multi-stop.toml", &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let args = ["atlas", scene.to_str().unwrap(), "--x", "omega=0.2:2:3", "--y", "delta=0.5:1:2", "--quiet", "-o"];
    refused(&[&args[..], &[scene.to_str().unwrap()]].concat(), "is also an input");
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    refused(&strs(&atlas("/dev/null", &[])), "not a regular file");
    refused(&["merge", "x.h5", "-o", ds], "is a directory");
    refused(&["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:2:3", "--quiet", "-o", ds], "is a directory");
}

/// The seventh audit (2026-12-07): every output a command writes beside its
/// file (a trace, a figure) is checked against its inputs (the scene, the
/// `--from` file) before any work, as `-o` is; a sweep's `-o` against its
/// `--from` file; a sweep's `--variable` before its file replaces one; a
/// repeated `--set` or `--accuracy` is refused as a repeated `--at` is; a
/// PNG too large to draw is refused, never a panic. Each left its input
/// lost, or the old file replaced, with exit 0 (or 101).
#[test]
fn side_outputs_never_replace_an_input_and_late_checks_come_first() {
    let d = scratch("side-outputs");
    let at = |name: &str| d.join(name).to_str().unwrap().to_string();
    let (scene, atlas_h5) = (at("v.toml"), at("v.h5"));
    std::fs::copy("configs/multi-stop.toml", &scene).unwrap();
    let made = run(&["atlas", &scene, "--x", "omega=0.5:1.5:4", "--y", "delta=0.1:1:3", "--quiet", "-o", &atlas_h5]);
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let kept = |path: &str| std::fs::read(path).unwrap();
    let (scene_bytes, atlas_bytes) = (kept(&scene), kept(&atlas_h5));
    let from = ["--from", atlas_h5.as_str(), "--at", "omega=1,delta=0.5"];
    refused(&["cell", &scene, "--trace", &scene], "--trace: ");
    refused(&[&["cell"][..], &from, &["--trace", &atlas_h5]].concat(), "is also an input");
    refused(
        &[&["sweep", "--axis", "omega=0.6:0.8:3"][..], &from, &["--quiet", "-o", &atlas_h5]].concat(),
        "is also an input",
    );
    // A figure named like an input (its extension the figure's).
    let (svg, png) = (at("s.svg"), at("a.png"));
    std::fs::copy(&scene, &svg).unwrap();
    std::fs::copy(&atlas_h5, &png).unwrap();
    refused(&["cell", &svg, "--portrait", &svg], "--portrait: ");
    refused(&["sweep", &svg, "--axis", "omega=0.2:0.4:3", "--png", &svg], "--png: ");
    let png_from = ["--from", png.as_str(), "--at", "omega=1,delta=0.5"];
    refused(&[&["attractors"][..], &png_from, &["--samples", "3", "--png", &png]].concat(), "is also an input");
    refused(&[&["cell"][..], &png_from, &["--section-png", &png]].concat(), "is also an input");
    assert_eq!((kept(&scene), kept(&atlas_h5), kept(&svg)), (scene_bytes.clone(), atlas_bytes.clone(), scene_bytes));
    // --variable checked before the sweep's file replaces one.
    let other = at("keep.h5");
    std::fs::copy(&atlas_h5, &other).unwrap();
    let sweep = ["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:0.4:3", "--quiet"];
    refused(
        &[&sweep[..], &["--variable", "x_M9", "--png", &at("s.png"), "-o", &other]].concat(),
        "--variable: expected one of x_M1",
    );
    refused(&[&sweep[..], &["--variable", "v_M9"]].concat(), "--variable: ");
    assert_eq!(kept(&other), atlas_bytes);
    // Given twice, as --at is.
    refused(&["cell", "configs/multi-stop.toml", "--set", "zeta=0.1", "--set", "zeta=0.9"], "--set zeta: given twice");
    refused(
        &["cell", "configs/multi-stop.toml", "--accuracy", "n_max=4", "--accuracy", "n_max=8"],
        "--accuracy n_max: given twice",
    );
    // 1000 mm at 1200 dpi: 47 244 pixels a side (a 6.7 GB bitmap).
    refused(&["render", &atlas_h5, "-o", &at("r.png"), "--size", "1000x1000", "--dpi", "1200"], "--dpi: ");
    refused(
        &["cell", "configs/multi-stop.toml", "--portrait", &at("p.png"), "--size", "900x900", "--dpi", "1200"],
        "--dpi: ",
    );
    let pdf = run(&["render", &atlas_h5, "-o", &at("r.pdf"), "--size", "1000x1000", "--dpi", "1200"]);
    assert!(pdf.status.success(), "a vector figure has no pixels: {}", String::from_utf8_lossy(&pdf.stderr));
}

/// The eighth audit's finds: two outputs of one run named alike (a basin
/// file and its figure, a cell's two figures, a sweep's file and its
/// figure) are refused before any work, as is a study whose map or contact
/// sheet would replace its scene or itself; a `--set` of what a
/// continuation or a curve varies is refused, not ignored; a
/// continuation's axis is checked against the parameter's range at both
/// ends; and `bench` takes each thread count once and a bounded repeat.
/// The re-audit's: an output named through a link to another, an input
/// named as its output's journal (the run removed it), and the map of an
/// atlas that labels no mass.
#[test]
fn outputs_of_one_run_and_what_a_run_varies_are_checked_before_work() {
    let d = scratch("one-run");
    let at = |name: &str| d.join(name).to_str().unwrap().to_string();
    let same = at("same.png");
    // A basin file and its figure, one new file.
    let basins = |png: &str| {
        let args = ["basins", "configs/single-stop.toml", "--x", "x_M=-1:-0.5:3", "--y", "v_M=-1:1:3"];
        refused(&[&args[..], &["-o", &same, "--png", png]].concat(), "is also another of the run's outputs");
    };
    basins(&same);
    refused(&["cell", "configs/single-stop.toml", "--portrait", &same, "--section-png", &same], "--section-png: ");
    refused(&["sweep", "configs/single-stop.toml", "--axis", "omega=2:2.2:3", "-o", &same, "--png", &same], "--png: ");
    // The same new file named through a link to it.
    let link = at("link.png");
    std::os::unix::fs::symlink("same.png", &link).unwrap();
    basins(&link);
    assert!(!d.join("same.png").exists());
    // An input named as a file the run writes beside its output and removes.
    let journal = at(".o.h5.journal");
    std::fs::copy("configs/single-stop.toml", &journal).unwrap();
    let o = at("o.h5");
    refused(&["atlas", &journal, "--x", "omega=1:3:4", "--y", "r=0.5:0.9:3", "--quiet", "-o", &o], "which is an input");
    assert_eq!(std::fs::read(&journal).unwrap(), std::fs::read("configs/single-stop.toml").unwrap());
    // A study's scene named as its contact sheet, and a study file named as a map.
    let study = |file: &str, scene: &str| {
        std::fs::copy("configs/single-stop.toml", d.join(scene)).unwrap();
        let text = format!(
            "scene = \"{scene}\"\nparameter = \"zeta\"\nvalues = [0.0]\nx = \"omega=1:3:4\"\ny = \"r=0.5:0.9:3\"\n"
        );
        std::fs::write(d.join(file), text).unwrap();
        let bytes = (std::fs::read(d.join(file)).unwrap(), std::fs::read(d.join(scene)).unwrap());
        refused(&["study", &at(file), "-o", d.to_str().unwrap(), "--quiet"], "is also an input");
        assert_eq!((std::fs::read(d.join(file)).unwrap(), std::fs::read(d.join(scene)).unwrap()), bytes);
    };
    study("study.toml", "contact-sheet.png");
    study("zeta=0.png", "scene.toml");
    let single = "configs/single-stop.toml";
    refused(
        &["continue", single, "--axis", "omega=2.5:2.6:3", "--set", "omega=2"],
        "--set omega: omega is the parameter",
    );
    refused(
        &["curve", single, "--kind", "pd", "--start", "omega=1.26,zeta=0", "--free", "omega,zeta", "--set", "zeta=0.1"],
        "--set zeta: zeta is a free parameter of the curve",
    );
    refused(&["continue", single, "--axis", "r=0.8:1.5:5"], "parameters.r: must be in [0, 1], got 1.5");
    refused(&["continue", single, "--axis", "omega=2.5:0:10"], "parameters.omega: must be in (0, inf), got 0");
    refused(&["bench", "--grid", "4", "--threads", "1,1"], "--threads: 1 given twice");
    refused(&["bench", "--grid", "4", "--repeat", "1000000000"], "--repeat: must be 1 to 100");
    // An atlas of a scene that labels no mass has no labels' map to draw
    // (it panicked), but its other views.
    let scene = at("unlabelled.toml");
    let text = std::fs::read_to_string("configs/single-stop.toml").unwrap();
    std::fs::write(&scene, text.replace("[labels.M]\np = \"A\"\n", "")).unwrap();
    let atlas = at("unlabelled.h5");
    let made = run(&["atlas", &scene, "--x", "omega=1:3:4", "--y", "r=0.5:0.9:3", "--quiet", "-o", &atlas]);
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    refused(&["render", &atlas, "-o", &at("u.png")], "the atlas labels no mass");
    assert!(!d.join("u.png").exists() && !d.join(".u.partial.png").exists());
    let lyapunov = run(&["render", &atlas, "-o", &at("u.png"), "--view", "lyapunov"]);
    assert!(lyapunov.status.success(), "{}", String::from_utf8_lossy(&lyapunov.stderr));
}

#[test]
fn an_edited_or_malformed_journal_is_refused_and_an_intact_one_resumes_bit_for_bit() {
    let d = scratch("journal");
    let (full, part) = (d.join("full.h5"), d.join("part.h5"));
    assert!(run(&strs(&atlas(full.to_str().unwrap(), &[]))).status.success());
    // Journal lines as an interrupted run leaves them: read while a run goes on.
    let keep = d.join("keep.h5");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(strs(&atlas(keep.to_str().unwrap(), &["--threads", "1"])))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .spawn()
        .unwrap();
    let journal = d.join(".keep.h5.journal");
    let mut lines = Vec::new();
    // Polled until the run ends, however slow the build: the journal is
    // removed when the run completes.
    while child.try_wait().unwrap().is_none() {
        if let Ok(t) = std::fs::read_to_string(&journal) {
            // Only whole lines: the run may be writing the fourth, or the third.
            if t.matches('\n').count() >= 3 {
                lines = t.lines().take(3).map(str::to_string).collect();
                break;
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.wait().unwrap();
    assert_eq!(lines.len(), 3, "journal lines seen while the run went on");
    let pj = d.join(".part.h5.journal");
    let resume = atlas(part.to_str().unwrap(), &["--resume"]);
    // An edited digit.
    std::fs::write(
        &pj,
        format!("{}\n{}\n{}\n", lines[0], lines[1].replacen("\"events\":", "\"events\":9", 1), lines[2]),
    )
    .unwrap();
    refused(&strs(&resume), "line 2: checksum mismatch");
    // Not JSON at all, in the middle.
    std::fs::write(&pj, format!("{}\nnot json\n{}\n", lines[0], lines[2])).unwrap();
    refused(&strs(&resume), "line 2: not a journal line");
    // Intact lines and a torn last one: resumed, and equal to a full run.
    std::fs::write(&pj, format!("{}\n{}\n{}\n{{\"chec", lines[0], lines[1], lines[2])).unwrap();
    let resumed = run(&strs(&resume));
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    // Debian's h5py (installed by scripts/setup.sh) compares them dataset by
    // dataset; a missing python3 or h5py fails the test.
    let cmp = Command::new("/usr/bin/python3")
        .args(["scripts/compare_atlases.py", full.to_str().unwrap(), part.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("/usr/bin/python3 (scripts/setup.sh installs python3-h5py)");
    let report = format!("{}{}", String::from_utf8_lossy(&cmp.stdout), String::from_utf8_lossy(&cmp.stderr));
    assert!(cmp.status.success(), "{report}");
}

#[test]
fn merge_refuses_missing_duplicated_and_foreign_parts() {
    let d = scratch("merge");
    let part = |k: &str, extra: &[&str]| {
        let p = d.join(format!("p{}{}.h5", k.replace('/', "of"), extra.len()));
        let mut a = atlas(p.to_str().unwrap(), extra);
        a.extend(["--shard".to_string(), k.to_string()]);
        assert!(run(&strs(&a)).status.success());
        p.to_str().unwrap().to_string()
    };
    let (p1, p2, p3) = (part("1/3", &[]), part("2/3", &[]), part("3/3", &[]));
    let foreign = part("3/3", &["--set", "zeta=0.2"]);
    let out = d.join("m.h5");
    let o = out.to_str().unwrap();
    refused(&["merge", &p1, &p2, "-o", o], "shards 3/3 missing");
    assert!(!out.exists());
    refused(&["merge", &p1, &p2, &p2, "-o", o], "given twice");
    // Issue 42, R9: one file twice, by another name too (it merged, doubling the run time).
    let whole = d.join("whole.h5");
    assert!(run(&strs(&atlas(whole.to_str().unwrap(), &[]))).status.success());
    let w = whole.to_str().unwrap();
    refused(&["merge", w, w, "-o", o], "is given twice");
    let alias = d.join("alias.h5");
    std::os::unix::fs::symlink(&whole, &alias).unwrap();
    refused(&["merge", w, alias.to_str().unwrap(), "-o", o], &format!("is given twice (also as {w})"));
    refused(&["merge", &p1, &p2, &foreign, "-o", o], "is not a part of the same run");
    // Issue 30: a part sampled for attractors and one not (or sampled otherwise).
    let sampled = part("3/3", &["--attractors", "2"]);
    refused(&["merge", &p1, &p2, &sampled, "-o", o], "attractors 2 samples per cell, seed 1 against none");
    // A shard of a run split in two beside shards of one split in three.
    let half = part("2/2", &[]);
    refused(&["merge", &p1, &half, "-o", o], "the parts split the run into different numbers of shards");
    let with_gap = run(&["merge", &p1, &p2, "--allow-missing", "-o", o]);
    assert!(with_gap.status.success() && out.exists());
    assert!(run(&["merge", &p1, &p2, &p3, "-o", o]).status.success());
    let j: serde_json::Value = serde_json::from_slice(&run(&["inspect", o, "--json"]).stdout).unwrap();
    // The parts' commands are kept in the history, and the merge adds its own.
    assert!(j["command"].as_str().unwrap().contains("merge"), "{j}");
    let history: Vec<&str> = j["history"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
    assert!(history.iter().any(|l| l.contains("--shard 1/3")) && history.iter().any(|l| l.contains("--shard 3/3")));
    assert!(history.last().unwrap().contains("merge"), "{history:?}");
}

#[test]
fn closed_and_full_output_streams_end_without_a_panic() {
    let d = scratch("streams");
    let f = d.join("a.h5");
    assert!(run(&strs(&atlas(f.to_str().unwrap(), &[]))).status.success());
    let full = std::fs::File::create("/dev/full");
    if let Ok(full) = full {
        let out = Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
            .args(["inspect", f.to_str().unwrap()])
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("No space left") && !err.contains("panicked"), "{err}");
    }
    // A reader that closes at once: exit 0, nothing on stderr.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:2.5:200", "--quiet"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn sizes_are_bounded_before_any_allocation() {
    refused(
        &[
            "atlas",
            "configs/multi-stop.toml",
            "--x",
            "omega=0.1:3:4294967296",
            "--y",
            "delta=0.1:2:4294967296",
            "-o",
            "x.h5",
        ],
        "the count must be 1 to 1000000",
    );
    for knob in ["lyapunov_periods=1e12", "n_max=1e12", "max_periods=1e12", "max_events=1e12"] {
        refused(&["cell", "configs/multi-stop.toml", "--accuracy", knob], "at most");
    }
    refused(
        &["cell", "configs/multi-stop.toml", "--trace", "t.csv", "--trace-samples", "1000000000"],
        "--trace-samples",
    );
    refused(
        &["atlas", "configs/multi-stop.toml", "--x", "omega=0.1:3:200000", "--y", "delta=0.1:2:200000", "-o", "x.h5"],
        "more --shard parts",
    );
}

#[test]
fn expressions_and_names_give_errors_that_say_what_is_wrong() {
    let d = scratch("expr");
    let base = std::fs::read_to_string("configs/multi-stop.toml").unwrap();
    let scene = |name: &str, from: &str, to: &str| {
        let p = d.join(name);
        std::fs::write(&p, base.replacen(from, to, 1)).unwrap();
        p.to_str().unwrap().to_string()
    };
    let ok = scene("sci.toml", "R = { value = 0.8", "R = { value = \"8e-1\"");
    assert!(run(&["cell", &ok, "--set", "omega=2.5e0"]).status.success());
    refused(
        &["cell", &scene("op.toml", "position = \"-delta1\"", "position = \"1 + * 2\"")],
        "expected an operand after '+'",
    );
    refused(&["cell", &scene("fn.toml", "position = \"-delta1\"", "position = \"foo(1)\"")], "unknown function 'foo'");
    refused(&["cell", &scene("inf.toml", "position = \"-delta1\"", "position = \"-1e308*10\"")], "not a finite number");
    refused(&["cell", &scene("pi.toml", "tau = { value = 0.0", "PI = { value = 0.0")], "reserved");
    refused(&["cell", &scene("sin.toml", "tau = { value = 0.0", "sin = { value = 0.0")], "reserved");
    refused(&["cell", "configs/multi-stop.toml", "--bogus"], "--bogus");
}

#[test]
fn silent_cases_are_refused() {
    refused(
        &[
            "atlas",
            "configs/multi-stop.toml",
            "--set",
            "omega=1",
            "--x",
            "omega=0.1:1:3",
            "--y",
            "delta=0.1:1:3",
            "-o",
            "x.h5",
        ],
        "also an axis",
    );
    let d = scratch("silent");
    let base = std::fs::read_to_string("configs/multi-stop.toml").unwrap();
    let p = d.join("sym.toml");
    std::fs::write(&p, base.replacen("symmetric = false", "symmetric = true", 1)).unwrap();
    refused(&["cell", p.to_str().unwrap()], "symmetric");
    let study = d.join("study.toml");
    std::fs::write(
        &study,
        format!(
            "scene = \"{}\"\nparameter = \"omega\"\nvalues = [0.5, 1.0]\nx = \"omega=0.2:2:3\"\ny = \"delta=0.5:1:2\"\n",
            crate::util::config("multi-stop.toml").display()
        ),
    )
    .unwrap();
    refused(&["study", study.to_str().unwrap(), "-o", d.join("out").to_str().unwrap()], "also an axis");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn numbers_the_solver_cannot_handle_are_refused_and_contraction_is_never_chaos() {
    for w in ["omega=1e-7", "omega=5e-324"] {
        refused(&["cell", "configs/multi-stop.toml", "--set", w], "forcing.omega: must be at least 1e-6");
    }
    // Slow but representable forcing: the impacts are found (it was 1-0-0 below 5e-7).
    let c = crate::util::cell_json(&["configs/multi-stop.toml", "--set", "omega=1e-6"]);
    assert_ne!(c["labels"]["M1"], "1-0-0", "{c}");
    for w in ["omega=1.0", "omega=1e6"] {
        let c = crate::util::cell_json(&["configs/multi-stop.toml", "--set", w]);
        if let Some(l) = c["lyapunov"].as_f64() {
            assert!(c["class"] != "chaotic" || l > 0.0, "{w}: {c}");
        }
    }
}

#[test]
fn small_clearances_resolve_instead_of_stalling() {
    // δ from 1e-11 to 1e-5 stalled in zero-time events (a reaction slightly
    // negative at a new contact, positive within the time resolution): the
    // audit found 34 of 250 random points, 74 % of a log-uniform sample here.
    // The δ → 0 limit is continuous: the label at ω = 1 is that of δ = 1e-3.
    for d in ["1e-11", "1e-9", "1e-7", "1e-5", "1e-3"] {
        let c =
            crate::util::cell_json(&["configs/multi-stop.toml", "--set", "omega=1.0", "--set", &format!("delta={d}")]);
        assert_eq!(c["labels"]["M1"], "1-5-3", "δ = {d}: {c}");
    }
    for w in ["0.45", "0.9", "1.7", "2.3"] {
        let c =
            crate::util::cell_json(&["configs/multi-stop.toml", "--set", &format!("omega={w}"), "--set", "delta=1e-7"]);
        assert!(!c["reason"].as_str().is_some_and(|r| r.contains("stalled")), "ω = {w}: {c}");
    }
}

/// The output file is written while the cells compute: when it cannot be
/// (its temporary path taken by a folder), the run still computes and
/// journals every line, ends with one error that says so, leaves nothing
/// under the final name, and `--resume` then writes the file without
/// computing again, equal to an uninterrupted run.
#[test]
fn an_output_that_cannot_be_written_keeps_the_lines_for_resume() {
    let d = scratch("unwritable");
    let (full, out) = (d.join("full.h5"), d.join("x.h5"));
    assert!(run(&strs(&atlas(full.to_str().unwrap(), &[]))).status.success());
    let blocker = store::partial_path(&out);
    std::fs::create_dir(&blocker).unwrap();
    refused(&strs(&atlas(out.to_str().unwrap(), &[])), "the computed lines are kept: --resume");
    assert!(!out.exists(), "nothing under the final name");
    let journal = d.join(".x.h5.journal");
    let lines = std::fs::read_to_string(&journal).unwrap().lines().count();
    assert!(lines >= 2 * 4, "every line journaled: {lines}");
    std::fs::remove_dir(&blocker).unwrap();
    let resumed = run(&strs(&atlas(out.to_str().unwrap(), &["--resume"])));
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    assert!(!journal.exists() && !blocker.exists());
    assert_eq!(store::read(&out).unwrap().atlas, store::read(&full).unwrap().atlas);
    std::fs::remove_dir_all(&d).unwrap();
}

/// A file that grows past the process's size limit (`ulimit -f`) is a write
/// error (EFBIG) like a full disk: one line, exit 2, the journal kept; the
/// signal SIGXFSZ used to end the run without a word (exit 153). `--resume`
/// without the limit then completes it, equal to an uninterrupted run.
#[test]
fn a_file_size_limit_is_an_error_and_the_run_resumes() {
    let d = scratch("file-size-limit");
    let (full, out) = (d.join("full.h5"), d.join("x.h5"));
    assert!(run(&strs(&atlas(full.to_str().unwrap(), &[]))).status.success());
    assert!(std::fs::metadata(&full).unwrap().len() > 64 * 1024, "the limit below is below the file's size");
    let limited = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 16; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(atlas(out.to_str().unwrap(), &[]))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&limited.stderr);
    assert_eq!(limited.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("File too large"), "{err}");
    assert!(d.join(".x.h5.journal").exists() && !out.exists());
    let resumed = run(&strs(&atlas(out.to_str().unwrap(), &["--resume"])));
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    assert_eq!(store::read(&out).unwrap().atlas, store::read(&full).unwrap().atlas);
    std::fs::remove_dir_all(&d).unwrap();
}

/// A zoom has no resume, so a zoom that fails (here past the file size limit)
/// leaves nothing behind: no journal, no partial file, no lock (issue 61).
#[test]
#[ignore = "slow: the full suite runs it"]
fn a_failed_zoom_leaves_nothing_behind() {
    let d = scratch("zoom-fails");
    let parent = d.join("p.h5");
    assert!(run(&strs(&atlas(parent.to_str().unwrap(), &[]))).status.success());
    let limited = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 16; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(["zoom", parent.to_str().unwrap(), "--x", "omega=0.3:1.5:60", "--y", "delta=0.2:0.8:30", "--quiet"])
        .arg("-o")
        .arg(d.join("c.h5"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&limited.stderr);
    assert_eq!(limited.status.code(), Some(2), "{err}");
    assert!(err.contains("File too large"), "{err}");
    let mut left: Vec<String> =
        std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    left.sort();
    assert_eq!(left, ["p.h5"], "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}
