//! Issue 66: `vibroatlas basins`, the basins of attraction of one parameter
//! point over a grid of initial states: the same file on one thread and two,
//! read by h5py and xarray; starts checked by `cell` (the exact flow and the
//! independent RK4 integrator); the symmetric damper's basins at phase 0 and
//! π mirror each other; an edited file is refused; bad options are one line.

use crate::run_safety::refused;
use crate::util::{cell_json, run, scratch};

/// The impact damper at ω = 1.3, δ = 1: the asymmetric 1-1-2 and 1-2-1
/// coexist.
const POINT: [&str; 5] = ["configs/impact-damper.toml", "--set", "omega=1.3", "--set", "delta=1"];
const GRID: [&str; 4] = ["--x", "x_M2=-1:1:40", "--y", "v_M2=-3:3:40"];

fn basins(out: &std::path::Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["basins"];
    args.extend(POINT);
    args.extend(GRID);
    args.extend(extra);
    args.extend(["--quiet", "--json", "-o", out.to_str().unwrap()]);
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn python(script: &str, args: &[&str]) -> String {
    let o = std::process::Command::new("/usr/bin/python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("/usr/bin/python3 (scripts/setup.sh installs python3-h5py and python3-xarray)");
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{text}");
    text
}

#[test]
fn basins_are_the_same_on_any_threads_and_read_back_in_h5py_and_xarray() {
    let d = scratch("basins-threads");
    let (one, two) = (d.join("one.h5"), d.join("two.h5"));
    let j = basins(&one, &["--threads", "1"]);
    basins(&two, &["--threads", "2"]);
    // Dataset by dataset, bit for bit (exit 1 on any difference).
    let cmp = std::process::Command::new("/usr/bin/python3")
        .args(["scripts/compare_atlases.py", one.to_str().unwrap(), two.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(cmp.status.success(), "{}{}", String::from_utf8_lossy(&cmp.stdout), String::from_utf8_lossy(&cmp.stderr));
    let labels: Vec<&str> =
        j["attractors"].as_array().unwrap().iter().map(|a| a["labels"]["M2"].as_str().unwrap()).collect();
    let mut sorted = labels.clone();
    sorted.sort();
    assert_eq!(sorted, ["1-1-2", "1-2-1"], "{j}");
    assert_eq!(j["starts"], 1600);
    // Both xarray engines: named dimensions, the ids' histogram is the
    // counts, the fractions sum to one, labels decode as text.
    let check = r#"
import sys, numpy as np, xarray as xr
for engine in ("h5netcdf", "netcdf4"):
    ds = xr.open_dataset(sys.argv[1], engine=engine)
    assert ds["basin"].dims == ("v_M2", "x_M2"), ds["basin"].dims
    ids = ds["basin"].values
    counts = np.bincount(ids.ravel(), minlength=ds.sizes["attractor"])
    assert (counts == ds["count"].values).all(), (counts, ds["count"].values)
    assert abs(float(ds["fraction"].sum()) - 1) < 1e-12
    assert float(ds["x_M2"][0]) == -1.0 and float(ds["v_M2"][-1]) == 3.0
    print(engine, [str(x) for x in ds["labels_M2"].values], ds.attrs["fractal"], ds.attrs["uncertainty_exponent"])
"#;
    let out = python(check, &[one.to_str().unwrap()]);
    assert!(out.contains("h5netcdf") && out.contains("netcdf4"), "{out}");
}

#[test]
fn starts_away_from_a_boundary_reach_their_attractor_in_cell_and_in_rk4() {
    let d = scratch("basins-cells");
    let out = d.join("b.h5");
    let j = basins(&out, &[]);
    let ids = python(
        "import sys, h5py; f = h5py.File(sys.argv[1]); print(' '.join(map(str, f['basin'][:].ravel())))",
        &[out.to_str().unwrap()],
    );
    let ids: Vec<i64> = ids.split_whitespace().map(|t| t.parse().unwrap()).collect();
    let n = 40;
    let value = |i: usize, lo: f64, hi: f64| lo + (hi - lo) * i as f64 / (n - 1) as f64;
    // Starts whose 3 x 3 neighbourhood reaches one attractor.
    let inner: Vec<usize> = (0..n * n)
        .filter(|&i| {
            let (ix, iy) = (i % n, i / n);
            (1..n - 1).contains(&ix)
                && (1..n - 1).contains(&iy)
                && (0..9).all(|k| ids[(iy + k / 3 - 1) * n + ix + k % 3 - 1] == ids[i])
        })
        .collect();
    assert!(inner.len() >= 4, "{} starts inside a basin", inner.len());
    for &i in inner.iter().step_by(inner.len() / 4).take(4) {
        let state = format!("0,{},0,{}", value(i % n, -1.0, 1.0), value(i / n, -3.0, 3.0));
        let want = &j["attractors"][ids[i] as usize]["labels"]["M2"];
        let mut args = POINT.to_vec();
        args.extend(["--state", &state]);
        let exact = cell_json(&args);
        assert_eq!(&exact["labels"]["M2"], want, "exact flow from {state}");
        args.extend(["--integrator", "rk4"]);
        let rk4 = cell_json(&args);
        assert_eq!(&rk4["labels"]["M2"], want, "RK4 from {state}");
    }
}

#[test]
fn the_symmetric_dampers_basins_at_phase_zero_and_pi_mirror_each_other() {
    // (x, v) at phase 0 reaches the mirror image of what (−x, −v) reaches at
    // phase π: 1-1-2 and 1-2-1 swap. Starts on a fractal boundary may go
    // either way on a rounding (the grid's −x is not bit for bit the negated
    // x, nor sin(φ + π) −sin φ): at most 3 % of them differ.
    let d = scratch("basins-mirror");
    let (a, b) = (d.join("zero.h5"), d.join("pi.h5"));
    basins(&a, &[]);
    basins(&b, &["--phase", "3.141592653589793"]);
    let check = r#"
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
text = lambda f: [x.decode() if isinstance(x, bytes) else x for x in f["labels_M2"][:]]
mirror = lambda l: "-".join([l.split("-")[0], l.split("-")[2], l.split("-")[1]])
la, lb = text(a), text(b)
A = np.array([mirror(la[i]) for i in a["basin"][:].ravel()])
B = np.array([lb[i] for i in b["basin"][:][::-1, ::-1].ravel()])
print((A == B).mean())
"#;
    let share: f64 = python(check, &[a.to_str().unwrap(), b.to_str().unwrap()]).trim().parse().unwrap();
    assert!(share >= 0.97, "{share} of the starts mirror");
}

#[test]
fn the_symmetric_stops_basins_at_phase_zero_and_pi_map_onto_each_other_start_for_start() {
    // The two-mass scene with symmetric stops at ω = 1.5, δ = 0.3: two 1-1-1
    // AS mirror images. The start (x, v) at phase 0 and (−x, −v) at phase π
    // reach images of one another: an attractor at π is the one whose
    // section points are the negatives of its partner's at 0. Measured: all
    // 1 600 starts.
    let d = scratch("basins-symmetric");
    let (a, b) = (d.join("zero.h5"), d.join("pi.h5"));
    for (out, phase) in [(&a, "0"), (&b, "3.141592653589793")] {
        let args = [
            "configs/symmetric-stops.toml",
            "--set",
            "omega=1.5",
            "--set",
            "delta=0.3",
            "--x",
            "x_M1=-0.6:0.6:40",
            "--y",
            "v_M1=-2:2:40",
            "--phase",
            phase,
        ];
        let j = report(&args, out);
        assert_eq!(j["attractors"].as_array().unwrap().len(), 2, "{j}");
    }
    let check = r#"
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
sa, sb = a["section"][:, 0, :], b["section"][:, 0, :]
image = {i: int(np.argmin(np.abs(sb + sa[i]).max(axis=1))) for i in range(len(sa))}
assert sorted(image.values()) == list(range(len(sb))), image
mapped = np.vectorize(image.get)(a["basin"][:])
print(int((mapped != b["basin"][:][::-1, ::-1]).sum()))
"#;
    let differ = python(check, &[a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(differ.trim(), "0", "starts whose images differ");
}

#[test]
fn a_basin_file_renders_and_an_edited_one_is_refused() {
    let d = scratch("basins-edit");
    let out = d.join("b.h5");
    basins(&out, &[]);
    let png = d.join("b.png");
    let o = run(&["render", out.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("wrote"));
    // Commands that read an atlas say what the file is.
    for cmd in
        [vec!["inspect", out.to_str().unwrap()], vec!["cell", "--from", out.to_str().unwrap(), "--at", "omega=1"]]
    {
        refused(&cmd, "not an atlas (a basin file");
    }
    // inspect --verify reads every value back under the checksums.
    let o = run(&["inspect", out.to_str().unwrap(), "--verify", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((report["content"].as_str(), report["verified"].as_bool()), (Some("basins"), Some(true)), "{report}");
    // One id changed, as h5py would change it: an error naming the checksum.
    python(
        "import sys, h5py\nf = h5py.File(sys.argv[1], 'r+')\nb = f['basin'][:]\nb[0, 0] = 1 - b[0, 0]\nf['basin'][:] = b",
        &[out.to_str().unwrap()],
    );
    for cmd in [
        vec!["render", out.to_str().unwrap(), "-o", d.join("c.png").to_str().unwrap()],
        vec!["inspect", out.to_str().unwrap(), "--verify"],
    ] {
        let o = run(&cmd);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{cmd:?}: {err}");
        assert!(err.contains("basins_crc32") && !err.contains("panicked"), "{err}");
    }
}

#[test]
fn bad_basin_options_are_one_line_naming_the_option() {
    let d = scratch("basins-bad");
    let o = d.join("b.h5");
    let o = o.to_str().unwrap();
    let with = |x: &'static str, y: &'static str, extra: &'static [&'static str]| {
        let mut a = vec!["basins", "configs/impact-damper.toml", "--x", x, "--y", y, "-o", o];
        a.extend(extra);
        a
    };
    refused(&with("x_M9=-1:1:4", "v_M2=-1:1:4", &[]), "--x: no state component 'x_M9'");
    refused(&with("x_M2=-1:1:4", "x_M2=-1:1:4", &[]), "--y: the same component as --x");
    refused(&with("x_M2=-1:1:4000", "v_M2=-1:1:4000", &[]), "--y: 16000000 starts");
    refused(&with("x_M2=-1:1:4", "v_M2=-1:1:4", &["--phase", "nan"]), "--phase");
    refused(&with("x_M2=-1:1:4", "v_M2=-1:1:4", &["--state", "0,0"]), "--state");
    refused(&with("x_M2=-1:1:4", "v_M2=-1:1:4", &["--phase", "1e300"]), "--phase: expected a phase in radians within");
    // A figure that cannot be written is refused before the work, leaving no file.
    refused(&with("x_M2=-1:1:4", "v_M2=-1:1:4", &["--png", "no/such/folder/b.png"]), "its folder does not exist");
    assert!(!d.join("b.h5").exists());
    // Atlas options on a basin file's picture are refused, naming the option.
    let made = run(&with("x_M2=-1:1:4", "v_M2=-1:1:4", &["--quiet"]));
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let png = d.join("b.png");
    refused(&["render", o, "--view", "basin:0", "-o", png.to_str().unwrap()], "--view: ");
    refused(&["render", o, "--mass", "M2", "-o", png.to_str().unwrap()], "--mass: ");
}

/// `basins … --json` of a shipped scene on a grid, with the options given.
fn report(args: &[&str], out: &std::path::Path) -> serde_json::Value {
    let mut all = vec!["basins"];
    all.extend(args);
    all.extend(["--quiet", "--json", "-o", out.to_str().unwrap()]);
    let o = run(&all);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The single stop at ω = 2.5, σ = 1, ζ = 0.05: the non-impacting 1-0-0 and
/// the impacting 2-1-0 coexist, their basins bounded by smooth curves.
const SINGLE: [&str; 7] = ["configs/single-stop.toml", "--set", "omega=2.5", "--set", "sigma=1", "--set", "zeta=0.05"];

#[test]
#[ignore = "slow: the full suite runs it"]
fn a_smooth_boundary_has_exponent_one_and_a_riddled_one_near_zero() {
    let d = scratch("basins-boundary");
    let mut smooth = SINGLE.to_vec();
    smooth.extend(["--x", "x_M=-3:1:96", "--y", "v_M=-3:3:96"]);
    let j = report(&smooth, &d.join("smooth.h5"));
    let b = &j["boundary"];
    let alpha = b["uncertainty_exponent"].as_f64().unwrap();
    assert!((alpha - 1.0).abs() < 0.1 && b["fractal"] == false, "{b}");
    // The damper at ω = 1.3, δ = 0.5 with every record in full (`precise`):
    // 1-1-3 and 1-3-1 intermingled start by start, the uncertain share flat
    // in ε. With two basins S_bb is at most ln 2: the criterion is silent.
    let riddled = [
        "configs/impact-damper.toml",
        "--set",
        "omega=1.3",
        "--set",
        "delta=0.5",
        "--preset",
        "precise",
        "--x",
        "x_M2=-0.5:0.5:48",
        "--y",
        "v_M2=-3:3:48",
    ];
    let j = report(&riddled, &d.join("riddled.h5"));
    let b = &j["boundary"];
    let alpha = b["uncertainty_exponent"].as_f64().unwrap();
    assert!(alpha < 0.3 && b["boundary_basin_entropy"].as_f64().unwrap() > 0.6, "{b}");
    let mut labels: Vec<&str> =
        j["attractors"].as_array().unwrap().iter().map(|a| a["labels"]["M2"].as_str().unwrap()).collect();
    labels.sort();
    assert_eq!(labels, ["1-1-3", "1-3-1"], "{j}");
}

#[test]
fn early_stopping_reaches_the_same_attractors_where_basins_are_smooth() {
    // The single stop's two basins, 64 x 64: every start reaches the
    // attractor its full record reaches, in fewer periods on average; any
    // number of threads gives the same file.
    let d = scratch("basins-early");
    let mut grid = SINGLE.to_vec();
    grid.extend(["--x", "x_M=-3:1:64", "--y", "v_M=-3:3:64"]);
    let whole = report(&grid, &d.join("whole.h5"));
    let mut early = grid.clone();
    early.push("--early-stop");
    let (one, two) = (d.join("one.h5"), d.join("two.h5"));
    let mut on_one = early.clone();
    on_one.extend(["--threads", "1"]);
    let stopped = report(&on_one, &one);
    let mut on_two = early.clone();
    on_two.extend(["--threads", "2"]);
    report(&on_two, &two);
    assert_eq!(stopped["early_stop"], true);
    let count = |j: &serde_json::Value| -> Vec<(String, u64)> {
        j["attractors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| (a["labels"]["M"].to_string(), a["count"].as_u64().unwrap()))
            .collect()
    };
    assert_eq!(count(&stopped), count(&whole));
    let mean = |j: &serde_json::Value| j["mean_periods"].as_f64().unwrap();
    assert!(mean(&stopped) < 0.8 * mean(&whole), "{} against {}", mean(&stopped), mean(&whole));
    let check = r#"
import sys, h5py, numpy as np
w, e, t = (h5py.File(p) for p in sys.argv[1:4])
label = lambda f: np.array([x.decode() for x in f["labels_M"][:]])[f["basin"][:]]
assert (label(w) == label(e)).all(), int((label(w) != label(e)).sum())
assert np.array_equal(e["basin"][:], t["basin"][:]) and np.array_equal(e["periods"][:], t["periods"][:])
print(e.attrs["early_stop"])
"#;
    let out = python(check, &[d.join("whole.h5").to_str().unwrap(), one.to_str().unwrap(), two.to_str().unwrap()]);
    assert!(out.contains("yes"), "{out}");
    // The symmetric damper, whose records split each period at its half:
    // the early stop follows the same trajectory, so even its fine-grained
    // basins come out start for start as the full records'.
    let (full, fast) = (d.join("damper.h5"), d.join("damper-early.h5"));
    basins(&full, &[]);
    basins(&fast, &["--early-stop"]);
    let same = r#"
import sys, h5py, numpy as np
w, e = (h5py.File(p) for p in sys.argv[1:3])
label = lambda f: np.array([x.decode() for x in f["labels_M2"][:]])[f["basin"][:]]
print(int((label(w) != label(e)).sum()), float(e["periods"][:].mean()), float(w["periods"][:].mean()))
"#;
    let out = python(same, &[full.to_str().unwrap(), fast.to_str().unwrap()]);
    assert!(out.starts_with("0 "), "differing starts, periods early and whole: {out}");
}

#[test]
#[ignore = "slow: the full suite runs it"]
fn basin_fractions_agree_with_the_sampled_attractors() {
    // A one-mass scene: `attractors --box 2,3` draws (x, v) uniformly in
    // [−2, 2] × [−3, 3] and draws again where x passes the stop at σ, so
    // it samples the grid's admissible starts of [−2, 1] × [−3, 3]
    // uniformly. Four cells where two motions coexist.
    let d = scratch("basins-agree");
    for (omega, sigma) in [("2.5", "1"), ("1.6", "1"), ("2.5", "0.5"), ("3", "0.5")] {
        let (o, s) = (format!("omega={omega}"), format!("sigma={sigma}"));
        let point = ["configs/single-stop.toml", "--set", &o, "--set", &s, "--set", "zeta=0.05"];
        let mut grid = point.to_vec();
        grid.extend(["--x", "x_M=-2:1:90", "--y", "v_M=-3:3:180"]);
        let basins = report(&grid, &d.join("b.h5"));
        let mut sampled = vec!["attractors"];
        sampled.extend(point);
        sampled.extend(["--samples", "600", "--box", "2,3", "--json"]);
        let o = run(&sampled);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let sampled: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let share = |j: &serde_json::Value, label: &str| {
            let all = j["attractors"].as_array().unwrap();
            all.iter().filter(|a| a["labels"]["M"] == label).map(|a| a["fraction"].as_f64().unwrap()).sum::<f64>()
        };
        let labels: Vec<String> = basins["attractors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["labels"]["M"].as_str().unwrap().to_string())
            .collect();
        assert_eq!(labels.len(), 2, "{omega}, {sigma}: {labels:?}");
        for label in &labels {
            let (p, q) = (share(&basins, label), share(&sampled, label));
            // Three standard errors of 600 samples.
            let sigma_p = (p * (1.0 - p) / 600.0).sqrt();
            assert!(
                (p - q).abs() < 3.0 * sigma_p,
                "{omega}, {sigma}, {label}: grid {p}, sampled {q} (sigma {sigma_p})"
            );
        }
    }
}

/// `atlas --attractors K` of the impact damper over a small window, one
/// run or two shards merged.
fn damper_attractors(out: &std::path::Path, shard: Option<&str>) {
    let mut args = vec![
        "atlas",
        "configs/impact-damper.toml",
        "--x",
        "omega=1.6:2.2:12",
        "--y",
        "delta=0.3:0.9:6",
        "--sweep",
        "up",
        "--attractors",
        "12",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ];
    if let Some(s) = shard {
        args.extend(["--shard", s]);
    }
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn attractor_families_are_followed_across_the_plane_and_merge_from_shards() {
    let d = scratch("basins-families");
    let whole = d.join("whole.h5");
    damper_attractors(&whole, None);
    // Every sampled cell's family fractions add up to one; a family's label
    // is its every member's; family 0 has the largest summed fraction.
    let check = r#"
import sys, numpy as np, xarray as xr
a = xr.open_dataset(sys.argv[1], engine="h5netcdf", group="attractors")
ff = a["family_fraction"].values
sampled = a["count"].values > 0
assert np.allclose(np.nansum(ff, axis=0)[sampled], 1.0), np.nansum(ff, axis=0)
fid, codes = a["family_id"].values, a["label_code_M2"].values
fam_codes = a["family_label_code_M2"].values
for f in range(ff.shape[0]):
    members = codes[fid == f]
    assert members.size > 0 and (members == fam_codes[f]).all(), (f, members, fam_codes[f])
totals = np.nansum(ff, axis=(1, 2))
assert (np.diff(totals) <= 1e-12).all(), totals
print(ff.shape[0], str(a["label"].values[fam_codes[0]]), round(float(totals[0]), 3))
"#;
    let out = python(check, &[whole.to_str().unwrap()]);
    assert!(out.contains("1-1-1"), "{out}");
    // Two shards merged: the same families as the whole run, bit for bit.
    let (p1, p2, merged) = (d.join("p1.h5"), d.join("p2.h5"), d.join("merged.h5"));
    damper_attractors(&p1, Some("1/2"));
    damper_attractors(&p2, Some("2/2"));
    let o = run(&["merge", p1.to_str().unwrap(), p2.to_str().unwrap(), "-o", merged.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let same = r#"
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
for name in ("family_id", "family_fraction", "family_label_code_M2", "section", "fraction"):
    x, y = a["attractors/" + name][()], b["attractors/" + name][()]
    assert x.shape == y.shape and np.array_equal(x, y, equal_nan=True), name
print("same")
"#;
    assert!(python(same, &[whole.to_str().unwrap(), merged.to_str().unwrap()]).contains("same"));
    // The family's map: a cell where family 0 takes at least 3/4 of the
    // starts is drawn in the darkest band.
    let png = d.join("family.png");
    let o = run(&["render", whole.to_str().unwrap(), "--view", "basin:0", "-o", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A family the file does not have: the option named, not the figure's path.
    let o = run(&["render", whole.to_str().unwrap(), "--view", "basin:9999", "-o", png.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(
        said.starts_with("error: --view basin:9999: the file's attractors form") && said.contains("families (0 to"),
        "{said}"
    );
}
