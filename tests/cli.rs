//! `vibroatlas cell` end to end (issue 2).

use crate::util::{cell_json, run};

/// Issue 2: the published labels of the multi-stop scene.
#[test]
fn published_labels() {
    for (omega, delta, label) in solver::reference::PUBLISHED_MULTI_STOP {
        let j = cell_json(&[
            "configs/multi-stop.toml",
            "--set",
            &format!("omega={omega}"),
            "--set",
            &format!("delta={delta}"),
        ]);
        assert_eq!(j["labels"]["M1"], label, "omega {omega} delta {delta}: {j}");
        assert_eq!(j["class"], "periodic");
    }
    // Complete chattering sticks at both of M1's stops (A1 below, A12 at M2).
    let j = cell_json(&["configs/multi-stop.toml", "--set", "omega=0.2", "--set", "delta=0.6"]);
    assert_eq!(j["sticking"]["A1"], true);
    assert_eq!(j["sticking"]["A12"], true);
    assert_eq!(j["chatter"]["A1"], true);
}

/// Issue 2: the JSON object carries every documented field.
#[test]
fn json_shape() {
    let j = cell_json(&["configs/multi-stop.toml", "--set", "omega=0.33", "--set", "delta=0.6"]);
    for key in [
        "class",
        "n",
        "labels",
        "impacts",
        "chatter",
        "sticking",
        "symmetry",
        "final_state",
        "periods_simulated",
        "events",
    ] {
        assert!(j.get(key).is_some(), "missing {key}");
    }
    assert_eq!(j["n"], 1);
    assert_eq!(j["impacts"]["A1"], 4);
    assert_eq!(j["impacts"]["A12"], 4);
    assert_eq!(j["final_state"].as_array().unwrap().len(), 4);
    assert!(j["symmetry"].is_null());
    let j = cell_json(&["configs/impact-damper.toml"]);
    assert_eq!(j["labels"]["M2"], "1-1-1", "{j}");
    assert_eq!(j["symmetry"], "S", "{j}");
}

/// Issue 2: the same cell gives bit-identical JSON twice, with either integrator.
#[test]
fn deterministic_output() {
    for integ in ["exact", "rk4"] {
        let args = [
            "cell",
            "configs/multi-stop.toml",
            "--set",
            "omega=0.295",
            "--set",
            "delta=0.6",
            "--integrator",
            integ,
            "--json",
        ];
        let (a, b) = (run(&args), run(&args));
        assert!(a.status.success());
        assert_eq!(a.stdout, b.stdout);
    }
}

/// Issue 2: RK4 (the literature's method) reaches the same published labels.
#[test]
fn rk4_reaches_the_published_labels() {
    for (omega, label) in [("0.33", "1-4-4"), ("0.20", "1-S-S")] {
        let j = cell_json(&["configs/multi-stop.toml", "--set", &format!("omega={omega}"), "--integrator", "rk4"]);
        assert_eq!(j["labels"]["M1"], label);
        assert_eq!(j["integrator"], "rk4");
    }
}

/// Issue 2: `--trace` writes the classified window as CSV with a header naming
/// every coordinate and velocity.
#[test]
fn trace_csv() {
    let dir = crate::util::scratch("trace-csv");
    let path = dir.join("trace.csv");
    let out = run(&["cell", "configs/multi-stop.toml", "--trace", path.to_str().unwrap(), "--trace-samples", "50"]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "t,x_M1,x_M2,v_M1,v_M2,event");
    // The last column names the event (issue 18): `impact A1`, or empty for a sample.
    let (rows, events): (Vec<Vec<f64>>, Vec<String>) = lines
        .map(|l| {
            let (numbers, event) = l.rsplit_once(',').unwrap();
            (numbers.split(',').map(|x| x.parse().unwrap()).collect(), event.to_string())
        })
        .unzip();
    // One period of samples plus the 8 impact events of a 1-4-4 motion.
    assert_eq!(rows.len(), 51 + 8);
    assert_eq!(events.iter().filter(|e| e.starts_with("impact ")).count(), 8);
    // No sample penetrates a stop (delta = 0.6).
    for r in &rows {
        assert!(r[1] >= -0.6 - 1e-9 && r[1] - r[2] <= 0.6 + 1e-9 && r[2] >= -0.6 - 1e-9);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 67: `bench --paper --json` times `standard` and `standard
/// chaos_check=0` against the literature's method in rounds on one thread,
/// the reference `precise` once, and reports each one's median speed-up over
/// the rounds (each round's against RK4's of the same round) and its spread;
/// no throughput.
#[test]
fn bench_paper_json() {
    let out = run(&["bench", "--paper", "--grid", "3", "--trade-repeat", "3", "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["grid"], 3);
    assert_eq!(j["throughput"], serde_json::json!([]));
    let trade = j["trade"].as_array().unwrap();
    let names: Vec<&str> = trade.iter().map(|t| t["setting"].as_str().unwrap()).collect();
    assert_eq!(names, ["standard", "standard chaos_check=0", "precise", "rk4 h=0.01"]);
    let rounds = |t: &serde_json::Value| -> Vec<f64> {
        t["round_seconds"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
    };
    let rk4 = rounds(&trade[3]);
    for t in trade {
        let secs = rounds(t);
        assert_eq!(secs.len(), if t["setting"] == "precise" { 1 } else { 3 }, "{t}");
        let mut ratios: Vec<f64> = rk4.iter().zip(&secs).map(|(b, s)| b / s).collect();
        ratios.sort_by(f64::total_cmp);
        let median = ratios[(ratios.len() - 1) / 2] / 2.0 + ratios[ratios.len() / 2] / 2.0;
        let got = t["speedup_median"].as_f64().unwrap();
        assert!((got - median).abs() <= 1e-12 * median, "{t}: median {median}");
        let spread = t["speedup_spread"].as_array().unwrap();
        assert_eq!(spread[0].as_f64().unwrap(), ratios[0], "{t}");
        assert_eq!(spread[1].as_f64().unwrap(), *ratios.last().unwrap(), "{t}");
        // One thread: the per-period time is the best round's over the periods.
        let best = secs.iter().copied().fold(f64::INFINITY, f64::min);
        let per_period = 1e6 * best / t["periods"].as_f64().unwrap();
        assert!((t["us_per_period"].as_f64().unwrap() - per_period).abs() <= 1e-9 * per_period, "{t}");
    }
    assert_eq!(trade[2]["label_agreement"], 1.0);
    // In words: each setting's median and spread, and the note that so
    // small a plane does not steady the ratio.
    let text = run(&["bench", "--paper", "--grid", "2", "--trade-repeat", "1"]);
    assert!(text.status.success(), "stderr: {}", String::from_utf8_lossy(&text.stderr));
    let text = String::from_utf8_lossy(&text.stdout);
    for line in [
        "standard against rk4 h=0.01 on 1 thread(s): ",
        "standard chaos_check=0 against rk4 h=0.01 on 1 thread(s): ",
        "median of 1 round(s)",
        "note: a round of standard took less than 5 s",
    ] {
        assert!(text.contains(line), "{line:?} missing from:\n{text}");
    }
    assert!(!text.contains("throughput"), "{text}");
}

/// Issue 5: `bench --trade --json` prints one object with every setting of the
/// trade (each against the `precise` reference) and the throughput of both
/// sweeps on each thread count, and draws the Pareto front.
#[test]
fn bench_trade_json() {
    let dir = crate::util::scratch("bench");
    let out = run(&[
        "bench",
        "--grid",
        "4",
        "--threads",
        "1,2",
        "--repeat",
        "2",
        "--trade",
        "--trade-repeat",
        "2",
        "--json",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["grid"], 4);
    let trade = j["trade"].as_array().unwrap();
    let names: Vec<&str> = trade.iter().map(|t| t["setting"].as_str().unwrap()).collect();
    for name in ["standard", "fast", "precise", "rk4 h=0.01", "rk4 h=0.001"] {
        assert!(names.contains(&name), "{name} missing from {names:?}");
    }
    for t in trade {
        assert!(t["cells_per_s"].as_f64().unwrap() > 0.0, "{t}");
        assert!(t["periods"].as_u64().unwrap() >= 16, "at least a period per cell: {t}");
        assert!(t["us_per_period"].as_f64().unwrap() > 0.0, "{t}");
        assert!(t["nonperiodic_periods"].as_u64().unwrap() <= t["periods"].as_u64().unwrap(), "{t}");
        assert!(t["speedup_vs_rk4"].as_f64().unwrap() > 0.0, "{t}");
        for key in ["label_agreement", "class_agreement"] {
            let share = t[key].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&share), "{t}");
            assert!(t["class_agreement"].as_f64().unwrap() >= t["label_agreement"].as_f64().unwrap(), "{t}");
        }
        assert!(t["median_state_error"].as_f64().unwrap() >= 0.0);
    }
    let precise = trade.iter().find(|t| t["setting"] == "precise").unwrap();
    assert_eq!(precise["label_agreement"], 1.0);
    assert_eq!(precise["median_state_error"], 0.0);
    let rk4 = trade.iter().find(|t| t["setting"] == "rk4 h=0.01").unwrap();
    assert_eq!(rk4["speedup_vs_rk4"], 1.0);
    assert_eq!(rk4["speedup_spread"], serde_json::json!([1.0, 1.0]));
    // Each round's time, its best the one reported; the spread of the
    // speed-up is each round's against RK4's of the same round.
    let rounds = |t: &serde_json::Value| -> Vec<f64> {
        t["round_seconds"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
    };
    for t in trade {
        let secs = rounds(t);
        assert_eq!(secs.len(), 2, "{t}");
        let best = secs.iter().copied().fold(f64::INFINITY, f64::min);
        assert!((t["cells_per_s"].as_f64().unwrap() * best - 16.0).abs() < 1e-9, "{t}");
        let ratios: Vec<f64> = rounds(rk4).iter().zip(&secs).map(|(b, s)| b / s).collect();
        let spread = t["speedup_spread"].as_array().unwrap();
        assert_eq!(spread[0].as_f64().unwrap(), ratios.iter().copied().fold(f64::INFINITY, f64::min), "{t}");
        assert_eq!(spread[1].as_f64().unwrap(), ratios.iter().copied().fold(0.0, f64::max), "{t}");
    }
    let standard = trade.iter().find(|t| t["setting"] == "standard").unwrap();
    let ratio = standard["cells_per_s"].as_f64().unwrap() / rk4["cells_per_s"].as_f64().unwrap();
    assert!((standard["speedup_vs_rk4"].as_f64().unwrap() - ratio).abs() <= 1e-12 * ratio);
    let throughput = j["throughput"].as_array().unwrap();
    assert_eq!(throughput.len(), 4, "fresh and both on 1 and 2 threads: {throughput:?}");
    for (t, (sweep, threads, cells)) in
        throughput.iter().zip([("fresh", 1, 16), ("fresh", 2, 16), ("both", 1, 32), ("both", 2, 32)])
    {
        assert_eq!(t["sweep"], sweep);
        assert_eq!(t["threads"], threads);
        assert_eq!(t["cells"], cells);
        assert!(t["efficiency"].as_f64().unwrap() > 0.0);
    }
    assert!(std::fs::metadata(dir.join("trade.png")).unwrap().len() > 1000);
    // The replay that filled `simulated` is `cargo bench --bench replay`; the key stays, empty.
    assert_eq!(j["simulated"], serde_json::json!([]));
    std::fs::remove_dir_all(&dir).unwrap();
}
