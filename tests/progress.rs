//! Issue 29 (item 8): progress off a terminal. `atlas` and `curves` print
//! `progress:` lines on standard error (here one per report, with
//! `VIBROATLAS_PROGRESS_EVERY=0`), well formed, ending at 100 %, and never on
//! standard output; the results are those of a quiet run. No timing is checked.

use crate::util::scratch;
use std::process::{Command, Output};

/// Runs the binary with progress lines as often as it reports.
fn run_chatty(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
        .args(args)
        .env("VIBROATLAS_PROGRESS_EVERY", "0")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// The `progress:` lines of standard error, without the prefix.
fn progress_lines(out: &Output) -> Vec<String> {
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.lines().any(|l| l.starts_with("progress:")), "progress on standard output: {stdout}");
    String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter_map(|l| l.strip_prefix("progress: ").map(str::to_string))
        .collect()
}

/// A count written for people (`116 032`).
fn count(text: &str) -> u64 {
    assert!(!text.is_empty() && text.chars().all(|c| c.is_ascii_digit() || c == ' '), "not a count: '{text}'");
    text.replace(' ', "").parse().unwrap()
}

/// A duration written for people (`9.8 s`, `2 min 05 s`, `1 h 02 min`).
fn is_duration(text: &str) -> bool {
    let w: Vec<&str> = text.split(' ').collect();
    match w[..] {
        [s, "s"] => s.parse::<f64>().is_ok(),
        [m, "min", s, "s"] | [m, "h", s, "min"] => m.parse::<u64>().is_ok() && s.len() == 2 && s.parse::<u64>().is_ok(),
        _ => false,
    }
}

/// `P %` as P.
fn percent(text: &str) -> u64 {
    text.strip_suffix(" %").unwrap_or_else(|| panic!("not a percentage: '{text}'")).parse().unwrap()
}

/// Parses `D/T cells (P %)[, work Q %], E elapsed, R cells/s, about L left`:
/// (D, T, P, Q).
fn atlas_line(line: &str) -> (u64, u64, u64, Option<u64>) {
    let parts: Vec<&str> = line.split(", ").collect();
    let (cells, rest) = parts[0].split_once(" cells (").unwrap_or_else(|| panic!("{line}"));
    let (done, total) = cells.split_once('/').unwrap_or_else(|| panic!("{line}"));
    let p = percent(rest.strip_suffix(')').unwrap_or_else(|| panic!("{line}")));
    let (work, rest) = match parts[1].strip_prefix("work ") {
        Some(q) => (Some(percent(q)), &parts[2..]),
        None => (None, &parts[1..]),
    };
    let [elapsed, rate, left] = rest else { panic!("{line}") };
    assert!(is_duration(elapsed.strip_suffix(" elapsed").unwrap_or_else(|| panic!("{line}"))), "{line}");
    count(rate.strip_suffix(" cells/s").unwrap_or_else(|| panic!("{line}")));
    let left = left.strip_prefix("about ").and_then(|l| l.strip_suffix(" left")).unwrap_or_else(|| panic!("{line}"));
    assert!(left == "?" || is_duration(left), "{line}");
    (count(done), count(total), p, work)
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn atlas_and_curves_print_well_formed_progress_lines_off_a_terminal() {
    let d = scratch("progress");
    let (quiet, chatty) = (d.join("quiet.h5"), d.join("chatty.h5"));
    // 12 lines of 20 cells, up and down, on two threads: probed, so weighted.
    let grid = ["configs/multi-stop.toml", "--x", "omega=0.6:1.6:20", "--y", "delta=1.2:2:12", "--sweep", "both"];
    let mut args = vec!["atlas"];
    args.extend(grid);
    args.extend(["--threads", "2", "-o", chatty.to_str().unwrap()]);
    let lines = progress_lines(&run_chatty(&args));
    assert!(lines.len() >= 10, "{lines:?}");
    let parsed: Vec<_> = lines.iter().map(|l| atlas_line(l)).collect();
    for &(done, total, p, work) in &parsed {
        assert_eq!(total, 480);
        assert!(done <= total && p == done * 100 / total, "{lines:?}");
        assert!(work.is_some_and(|q| q <= 100), "the probed run weighs its lines: {lines:?}");
    }
    // The line of the last cell (workers report concurrently: not always printed last).
    let end = parsed.iter().position(|p| p.0 == 480).unwrap_or_else(|| panic!("{lines:?}"));
    assert_eq!((parsed[end].2, parsed[end].3), (100, Some(100)), "{lines:?}");
    assert!(lines[end].ends_with("about 0.0 s left"), "{lines:?}");

    // Progress changes nothing in the file.
    let mut args = vec!["atlas"];
    args.extend(grid);
    args.extend(["--threads", "1", "--quiet", "-o", quiet.to_str().unwrap()]);
    crate::util::ok(&args);
    assert_eq!(store::read(&quiet).unwrap().atlas, store::read(&chatty).unwrap().atlas);

    // curves: seeds done of all, seeds traced, curves kept; --json's stdout is one object.
    let c = d.join("c.h5");
    let out = run_chatty(&["curves", chatty.to_str().unwrap(), "--max", "3", "--json", "-o", c.to_str().unwrap()]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let lines = progress_lines(&out);
    assert!(!lines.is_empty());
    let mut last = (0, 0, 0, 0);
    for line in &lines {
        let parts: Vec<&str> = line.split(", ").collect();
        let [seeds, traced, kept, elapsed] = parts[..] else { panic!("{line}") };
        let (seeds, p) = seeds.split_once(" seeds (").unwrap_or_else(|| panic!("{line}"));
        let (done, total) = seeds.split_once('/').unwrap_or_else(|| panic!("{line}"));
        let (done, total) = (count(done), count(total));
        let traced = count(traced.strip_suffix(" traced").unwrap_or_else(|| panic!("{line}")));
        let kept = count(kept.strip_suffix(" curves kept").unwrap_or_else(|| panic!("{line}")));
        assert!(is_duration(elapsed.strip_suffix(" elapsed").unwrap_or_else(|| panic!("{line}"))), "{line}");
        assert_eq!(percent(p.strip_suffix(')').unwrap()), done * 100 / total.max(1), "{line}");
        assert!(traced <= done && done <= total && kept <= 3, "{line}");
        last = (done, total, traced, kept);
    }
    // The last line is told once the seeds are done (by the search's own thread).
    assert_eq!(last.0, last.1, "the last line has every seed done: {lines:?}");
    assert_eq!(last.2, json["seeds"].as_u64().unwrap(), "{lines:?}");
    assert_eq!(last.3, json["curves"].as_array().unwrap().len() as u64, "{lines:?}");
}
