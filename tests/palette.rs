//! Issue 29, item 4 ("colours that stay apart"): among the 20 most frequent
//! labels of each shipped scene's reference map, for every labelled mass and
//! both sweeps, any two colours differ by CIEDE2000 ΔE ≥ 10, and every
//! periodic one is ΔE ≥ 20 from `C`'s black and ≥ 15 from `Q`, `U` and
//! `1-0-0` (the palette's guarantees: chaos never passes for a dark periodic
//! label).
//!
//! The reference planes (each shows its scene's dynamics; the grids are as
//! coarse as keeps the top 20 meaningful, for about 40 s on two cores):
//! - multi-stop: the README's plane ω 0.1–3.05 × δ 0.05–2 (there 296 × 196;
//!   120 × 80 here, as in the gallery): 1-p-q groups, chattering, complete
//!   chattering, subharmonics; masses M1 and M2.
//! - single-stop: ω 0.5–5 × σ −1.5–0.5 with the scene's ζ = 0 (the test
//!   oracle): 1-1-0, the (1, n) orbits n-1-0, complete chattering 1-S-0.
//! - impact-damper: ω 0.8–2.4 × δ 0.5–3 (docs/models.md): 1-1-1, its period
//!   doublings, quasi-periodic and chaotic bands; the free mass M2.
//! - symmetric-stops: ω 0.5–3 × δ 0.05–1: no impact at large clearance,
//!   1-p-p from 1-1-1 down to chattering and sticking at small ones; M2.
//! - dry-friction: ω 1–9 × fk 0.005–0.1: the 1-p-p sequence 1-1-1 … 1-10-10
//!   as ω falls, with its pitchforks, period doublings (2-4-2, 2-2-4) and
//!   sticking (1-S-S); M1.

use crate::util::{json_of, ok, scratch};
use grid::palette::delta_e;

/// The colour of a label as `inspect --json` writes it.
fn colour(text: &str) -> [u8; 3] {
    grid::palette::colour(text.parse().unwrap_or_else(|e| panic!("{e}")))
}

/// The least ΔE of a periodic label's colour from each fixed colour.
const FIXED_GAP: [(&str, f64); 4] = [("C", 20.0), ("Q", 15.0), ("U", 15.0), ("1-0-0", 15.0)];

/// Runs the scene's reference plane (both sweeps), then checks the top 20
/// labels of each mass and sweep pairwise; prints each map's closest pair.
fn top_labels_stay_apart(config: &str, x: &str, y: &str) {
    let dir = scratch(&format!("palette-{}", config.trim_end_matches(".toml")));
    let file = dir.join("atlas.h5");
    let file = file.to_str().unwrap();
    let scene = format!("configs/{config}");
    ok(&["atlas", &scene, "--x", x, "--y", y, "--sweep", "both", "--quiet", "-o", file]);
    let info = json_of(&["inspect", file, "--json"]);
    let mut failures = Vec::new();
    for sweep in info["sweeps"].as_array().unwrap() {
        let name = sweep["sweep"].as_str().unwrap();
        for (mass, counts) in sweep["labels"].as_object().unwrap() {
            let mut top: Vec<(&str, u64)> =
                counts.as_object().unwrap().iter().map(|(l, c)| (l.as_str(), c.as_u64().unwrap())).collect();
            top.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
            top.truncate(20);
            let mut worst = (f64::INFINITY, "", "");
            for &(a, _) in top.iter().filter(|(l, _)| !FIXED_GAP.iter().any(|(f, _)| f == l)) {
                for (f, gap) in FIXED_GAP {
                    let d = delta_e(colour(a), colour(f));
                    if d < gap {
                        failures.push(format!("{config} {name} {mass}: {a} {:?} is ΔE {d:.2} from {f}", colour(a)));
                    }
                }
            }
            for (i, &(a, _)) in top.iter().enumerate() {
                for &(b, _) in &top[..i] {
                    let d = delta_e(colour(a), colour(b));
                    if d < worst.0 {
                        worst = (d, a, b);
                    }
                    if d < 10.0 {
                        failures.push(format!(
                            "{config} {name} {mass}: {a} {:?} and {b} {:?}, ΔE {d:.2}",
                            colour(a),
                            colour(b)
                        ));
                    }
                }
            }
            let (d, a, b) = worst;
            println!(
                "{config} {name} {mass}: {} labels, top {}; closest pair {a} / {b}, ΔE {d:.2}",
                counts.as_object().unwrap().len(),
                top.len()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "frequent labels too close:\n{}", failures.join("\n"));
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn multi_stop_top_labels_stay_apart() {
    top_labels_stay_apart("multi-stop.toml", "omega=0.1:3.05:120", "delta=0.05:2:80");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn single_stop_top_labels_stay_apart() {
    top_labels_stay_apart("single-stop.toml", "omega=0.5:5:100", "sigma=-1.5:0.5:64");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn impact_damper_top_labels_stay_apart() {
    top_labels_stay_apart("impact-damper.toml", "omega=0.8:2.4:100", "delta=0.5:3:64");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn symmetric_stops_top_labels_stay_apart() {
    top_labels_stay_apart("symmetric-stops.toml", "omega=0.5:3:100", "delta=0.05:1:64");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn dry_friction_top_labels_stay_apart() {
    top_labels_stay_apart("dry-friction.toml", "omega=1:9:64", "fk=0.005:0.1:40");
}
