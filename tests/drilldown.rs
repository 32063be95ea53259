//! Issue 18: from a map to a motion. Cells of a stored atlas opened again,
//! hysteresis loops along one parameter, coexisting attractors, the papers'
//! chattering, and named trace events.

use crate::util::{cell_json, json_of, run, scratch};
use scene::Named;

#[test]
fn a_stored_cell_opens_again_bit_for_bit() {
    let d = scratch("from");
    let f = d.join("a.h5");
    let out = run(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=1.5:2.5:11",
        "--y",
        "delta=0.6:1.4:9",
        "--sweep",
        "both",
        "--quiet",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let atlas = store::read(&f).unwrap().atlas;
    let hyst = atlas.hysteresis().unwrap();
    let nx = atlas.meta.plane.x.count;
    let i = hyst.iter().position(|&h| h == 1).expect("a cell where up and down differ");
    let (iy, ix) = (i / nx, i % nx);
    let at = format!("omega={},delta={}", atlas.meta.plane.x.value(ix), atlas.meta.plane.y.value(iy));
    for sweep in ["up", "down"] {
        let stored = atlas.map(grid::SweepKind::parse(sweep).unwrap()).unwrap().cells[i].clone().unwrap();
        let c = cell_json(&["configs/multi-stop.toml", "--from", f.to_str().unwrap(), "--at", &at, "--sweep", sweep]);
        assert_eq!(c["labels"]["M1"], stored.labels[0].to_string(), "{sweep}: {c}");
        assert_eq!(c["labels"]["M2"], stored.labels[1].to_string(), "{sweep}");
        let fs: Vec<f64> = c["final_state"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let same = fs.iter().zip(&stored.final_state).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "{sweep}: {fs:?} against {:?}", stored.final_state);
        // The work too: the run counts its sections' re-simulation, as the atlas did.
        assert_eq!(
            (c["periods_simulated"].as_u64(), c["events"].as_u64()),
            (Some(stored.periods), Some(stored.events))
        );
        assert_eq!(c["from"]["sweep"], sweep);
    }
    // The up-sweep branch there is a periodic orbit that orbit --from finds.
    let from_up = |command: &str, extra: &[&str]| {
        let args = [command, "configs/multi-stop.toml", "--from", f.to_str().unwrap(), "--at", &at, "--sweep", "up"];
        json_of(&[&args[..], extra, &["--json"]].concat())
    };
    let o = from_up("orbit", &[]);
    let up = atlas.map(grid::SweepKind::Up).unwrap().cells[i].as_ref().unwrap().labels[0].to_string();
    assert_eq!(o["labels"]["M1"], up);
    // orbit and continue say which stored cell they took, as cell does.
    let c = |sweep: &str| {
        cell_json(&["configs/multi-stop.toml", "--from", f.to_str().unwrap(), "--at", &at, "--sweep", sweep])
    };
    assert_eq!(o["from"], c("up")["from"], "{o}");
    let axis = format!("omega={}:{}:2", atlas.meta.plane.x.value(ix), atlas.meta.plane.x.value(ix) + 0.01);
    let b = from_up("continue", &["--axis", &axis]);
    assert_eq!(b["from"], o["from"], "{b}");
    assert_eq!(b["from"]["cell"]["omega"].as_f64(), Some(atlas.meta.plane.x.value(ix)));
    let fresh = json_of(&["orbit", "configs/multi-stop.toml", "--json"]);
    assert!(fresh.get("from").is_none(), "{fresh}");
    // A state given directly, and one that penetrates a stop.
    let c = cell_json(&["configs/multi-stop.toml", "--state", "0,0,0,0"]);
    assert_eq!(c["class"], "periodic");
    let bad = run(&["cell", "configs/multi-stop.toml", "--state", "-5,0,0,0"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--state: penetrates stop A1"));
}

#[test]
fn a_down_up_loop_finds_the_published_hysteresis_zone() {
    let j = json_of(&[
        "sweep",
        "configs/dry-friction.toml",
        "--axis",
        "omega=4.5:8:141",
        "--set",
        "fk=0.01",
        "--direction",
        "down-up",
        "--quiet",
        "--json",
    ]);
    let (down, up) = (j["down"].as_array().unwrap(), j["up"].as_array().unwrap());
    assert_eq!((down.len(), up.len()), (141, 141));
    // Run order: the down leg from 8, the up leg from 4.5.
    assert_eq!(down[0]["value"].as_f64().unwrap(), 8.0);
    assert_eq!(up[0]["value"].as_f64().unwrap(), 4.5);
    let at = |leg: &[serde_json::Value], v: f64| {
        leg.iter().find(|p| (p["value"].as_f64().unwrap() - v).abs() < 1e-9).unwrap().clone()
    };
    // HR1 (5.79 to 5.942): 1-1-1 AS on the way down, 1-2-1 on the way up, or
    // its mirror image 1-1-2 (the clearance is symmetric: x -> -x swaps p and q).
    let pair = |l: &serde_json::Value| l == "1-2-1" || l == "1-1-2";
    let (d, u) = (at(down, 5.85), at(up, 5.85));
    assert_eq!((d["labels"]["M1"].as_str(), d["symmetry"].as_str()), (Some("1-1-1"), Some("AS")));
    assert!(pair(&u["labels"]["M1"]), "{u}");
    let zone: Vec<f64> = j["hysteresis"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|h| h["down"]["M1"] == "1-1-1" && pair(&h["up"]["M1"]))
        .map(|h| h["value"].as_f64().unwrap())
        .collect();
    let (lo, hi) = (zone.iter().copied().fold(f64::INFINITY, f64::min), zone.iter().copied().fold(0.0, f64::max));
    assert!((lo - 5.79).abs() < 0.03 && (hi - 5.942).abs() < 0.03, "zone {lo}..{hi}");
}

#[test]
fn coexisting_attractors_are_found_with_their_basins() {
    let args = |threads: &str| {
        json_of(&[
            "attractors",
            "configs/multi-stop.toml",
            "--set",
            "omega=0.3149",
            "--set",
            "delta=0.7",
            "--samples",
            "48",
            "--threads",
            threads,
            "--json",
        ])
    };
    let one = args("1");
    assert_eq!(one, args("2"), "identical for 1 and 2 threads");
    assert_eq!(one, args("1"), "identical when repeated");
    let list = one["attractors"].as_array().unwrap();
    let labels: Vec<&str> = list.iter().map(|a| a["labels"]["M1"].as_str().unwrap()).collect();
    assert!(labels.contains(&"1-3-3") && labels.contains(&"1-3-4"), "{labels:?}");
    let total: f64 = list.iter().map(|a| a["fraction"].as_f64().unwrap()).sum();
    assert!((total - 1.0).abs() < 1e-12);
    let fractions: Vec<f64> = list.iter().map(|a| a["fraction"].as_f64().unwrap()).collect();
    assert!(fractions.windows(2).all(|w| w[0] >= w[1]), "largest first: {fractions:?}");
    assert_eq!(one["samples"], 48);
}

/// Issue 63: the attractors of a stored cell (`attractors --from … --at …`,
/// the explorer's route) are those of its parameters with its file's
/// settings, the set-up the engine does for every stored cell; a start state
/// is refused, naming the option.
#[test]
fn a_stored_cells_attractors_are_those_of_its_parameters() {
    let f = up_atlas("attractors-stored", "omega=0.3:0.33:3", "delta=0.7:0.8:2");
    let f = f.to_str().unwrap();
    let samples = ["--samples", "12", "--threads", "1", "--json"];
    let at = ["attractors", "--from", f, "--at", "omega=0.3149,delta=0.71"];
    let of_cell = json_of(&[&at[..], &samples].concat());
    let said = run(&[&at[..], &["--samples", "4"]].concat());
    let note = String::from_utf8_lossy(&said.stderr);
    assert!(note.contains("note: --at: the stored cell nearest to omega=0.3149,delta=0.71 is omega="), "{note}");
    let scene = ["attractors", "configs/multi-stop.toml", "--set", "omega=0.315", "--set", "delta=0.7"];
    assert_eq!(of_cell, json_of(&[&scene[..], &samples].concat()), "the nearest cell's parameters");
    let state = run(&["attractors", "configs/multi-stop.toml", "--state", "0,0,0,0", "--samples", "4"]);
    let said = String::from_utf8_lossy(&state.stderr);
    assert_eq!(state.status.code(), Some(2), "{said}");
    assert!(said.contains("--state: the attractors sample their own start states"), "{said}");
    let help = String::from_utf8_lossy(&run(&["attractors", "--help"]).stdout).to_string();
    assert!(help.contains("--from") && !help.contains("--state"), "the help offers no --state: {help}");
}

#[test]
fn chattering_is_many_impacts_within_one_forcing_period() {
    // One impact per period at each stop over 19 periods is not chattering.
    let c = cell_json(&["configs/impact-damper.toml", "--set", "omega=1.69"]);
    assert_eq!(c["labels"]["M2"], "19-19-19");
    assert_eq!(c["chatter"]["left"], false);
    assert_eq!(c["chatter"]["right"], false);
    // Complete chattering stays complete chattering.
    let c = cell_json(&["configs/multi-stop.toml", "--set", "omega=0.20", "--set", "delta=0.6"]);
    assert_eq!(c["labels"]["M1"], "1-S-S");
    assert_eq!((c["chatter"]["A1"].as_bool(), c["sticking"]["A1"].as_bool()), (Some(true), Some(true)));
}

#[test]
fn no_cell_with_a_negative_exponent_is_chaotic() {
    let d = scratch("chaos");
    let f = d.join("a.h5");
    let out = run(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.5:1.9:16",
        "--y",
        "delta=0.05:0.3:8",
        "--quiet",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let atlas = store::read(&f).unwrap().atlas;
    let cells: Vec<_> = atlas.maps[0].cells.iter().flatten().collect();
    let chaotic: Vec<_> = cells.iter().filter(|c| c.class == solver::Class::Chaotic).collect();
    assert!(!chaotic.is_empty(), "a chaos-heavy window");
    for c in chaotic {
        let l = c.lyapunov.expect("a chaotic cell has an exponent");
        assert!(l > 0.0, "chaotic with λ = {l}");
    }
    let c = cell_json(&["configs/multi-stop.toml", "--set", "omega=1.0"]);
    assert!(c["class"] != "chaotic" || c["lyapunov"].as_f64().unwrap() > 0.0, "{c}");
}

#[test]
fn trace_events_say_what_happened_where() {
    let d = scratch("trace");
    let t = d.join("t.csv");
    let out = run(&["cell", "configs/multi-stop.toml", "--set", "omega=0.33", "--trace", t.to_str().unwrap()]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&t).unwrap();
    let events: Vec<&str> =
        text.lines().skip(1).map(|l| l.rsplit(',').next().unwrap()).filter(|e| !e.is_empty()).collect();
    assert!(events.contains(&"impact A1") && events.contains(&"impact A12"), "{events:?}");
    assert!(events.iter().all(|e| ["impact ", "stick ", "release ", "grazing "].iter().any(|k| e.starts_with(k))));
}

#[test]
fn atlas_attractors_are_stored_per_cell_and_deterministic() {
    let d = scratch("atlas-attractors");
    let make = |name: &str, extra: &[&str]| {
        let f = d.join(name);
        let mut args = vec![
            "atlas",
            "configs/multi-stop.toml",
            "--x",
            "omega=0.27:0.31:3",
            "--y",
            "delta=0.55:0.65:3",
            "--sweep",
            "both",
            "--attractors",
            "12",
            "--quiet",
            "-o",
            f.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = run(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        store::read(&f).unwrap().atlas
    };
    let one = make("one.h5", &["--threads", "1"]);
    let two = make("two.h5", &["--threads", "2"]);
    let a = one.attractors.as_ref().expect("an attractors group");
    assert_eq!(one.attractors, two.attractors, "the same for 1 and 2 threads");
    assert_eq!(a.samples, 12);
    for cell in &a.cells {
        let found = cell.as_ref().expect("every cell sampled");
        let total: f64 = found.iter().map(|f| f.fraction).sum();
        assert!((total - 1.0).abs() < 1e-12 && !found.is_empty());
    }
    assert!(a.cells.iter().flatten().any(|c| c.len() >= 2), "two coexisting motions somewhere in this window");
    // Only where up and down differ.
    let h = make("h.h5", &["--attractors-where", "hysteresis"]);
    let mask = h.hysteresis().unwrap();
    let sampled: Vec<bool> = h.attractors.unwrap().cells.iter().map(Option::is_some).collect();
    assert_eq!(sampled, mask.iter().map(|&m| m == 1).collect::<Vec<_>>());
    let png = d.join("count.png");
    let out = run(&["render", d.join("one.h5").to_str().unwrap(), "--view", "attractors", "-o", png.to_str().unwrap()]);
    assert!(out.status.success() && png.exists());
}

/// Issue 31: a stored unresolved cell keeps why. Every U cell of an atlas has
/// its reason in the file (the solver's text, read back by `store::read`),
/// `cell --from` on it computes the same reason again and shows the stored
/// one, resolved cells have none, and `inspect --json` counts them.
#[test]
fn a_stored_unresolved_cell_keeps_its_reason() {
    let f = up_atlas("reason", "omega=0.86:0.92:7", "delta=0.07:0.08:2");
    let file = f.to_str().unwrap();
    let atlas = store::read(&f).unwrap().atlas;
    let p = &atlas.meta.plane;
    let cells = &atlas.map(grid::SweepKind::Up).unwrap().cells;
    let mut unresolved = 0;
    for (i, c) in cells.iter().enumerate() {
        let c = c.as_ref().unwrap();
        assert_eq!(c.reason.is_some(), c.class == solver::Class::Unresolved, "cell {i}: {:?}", c.reason);
        let Some(reason) = &c.reason else { continue };
        unresolved += 1;
        let at = format!("omega={},delta={}", p.x.value(i % p.x.count), p.y.value(i / p.x.count));
        let again = cell_json(&["configs/multi-stop.toml", "--from", file, "--at", &at]);
        assert_eq!(again["reason"], reason.to_string(), "{at}");
        assert_eq!(again["from"]["reason"], reason.to_string(), "{at}");
        // The stored reason is the solver's, with its numbers: the same value.
        assert_eq!(again["reason_detail"], serde_json::to_value(reason).unwrap(), "{at}");
    }
    assert!(unresolved > 0, "the plane has an unresolved cell");
    let summary = json_of(&["inspect", file, "--json"]);
    let counted: u64 =
        summary["sweeps"][0]["reasons"].as_array().unwrap().iter().map(|r| r["cells"].as_u64().unwrap()).sum();
    assert_eq!(counted, unresolved);
}

/// Issue 65: `--at` between grid values takes the nearest stored cell and
/// says which on standard error (the cell `from` reports); at a grid value
/// it says nothing. Standard output stays the result (one JSON object).
#[test]
fn at_says_which_cell_it_took() {
    let f = up_atlas("at-note", "omega=0.3:0.5:5", "delta=0.4:0.8:3");
    let file = f.to_str().unwrap();
    let off = run(&["cell", "--from", file, "--at", "omega=0.33,delta=0.61", "--json"]);
    assert!(off.status.success(), "{}", String::from_utf8_lossy(&off.stderr));
    let taken: serde_json::Value = serde_json::from_slice(&off.stdout).unwrap();
    let cell = &taken["from"]["cell"];
    let (omega, delta) = (cell["omega"].as_f64().unwrap(), cell["delta"].as_f64().unwrap());
    // The grid's values, 0.35 and 0.6 to rounding.
    assert!((omega - 0.35).abs() < 1e-12 && (delta - 0.6).abs() < 1e-12, "{cell}");
    let said = String::from_utf8_lossy(&off.stderr);
    let expected =
        format!("note: --at: the stored cell nearest to omega=0.33,delta=0.61 is omega={omega},delta={delta}\n");
    assert!(said.contains(&expected), "{said}");
    let on = run(&["cell", "--from", file, "--at", &format!("omega={omega},delta={delta}"), "--json"]);
    assert!(on.status.success() && !String::from_utf8_lossy(&on.stderr).contains("note:"));
}

/// The up sweep of the multi-stop scene over `x` by `y`, written to a fresh
/// folder named for `test`.
fn up_atlas(test: &str, x: &str, y: &str) -> std::path::PathBuf {
    let f = scratch(test).join("a.h5");
    let args = ["atlas", "configs/multi-stop.toml", "--x", x, "--y", y, "--sweep", "up", "--quiet", "-o"];
    assert!(run(&[&args[..], &[f.to_str().unwrap()]].concat()).status.success());
    f
}
