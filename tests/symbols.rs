//! Parameter symbols (issue 29, item 3): a scene declares each parameter's
//! `symbol` and `long_name` (or they follow from its name and `doc`); bad
//! values are refused naming the field; files store them as attributes of the
//! axis coordinates, which h5py and xarray (both engines) read; the atlas's
//! `Meta` gives them back.

use crate::util::{config, run, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A copy of the multi-stop scene with `from` replaced by `to`.
fn multi_stop_with(dir: &Path, name: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(config("multi-stop.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    let p = dir.join(name);
    std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
    p
}

/// One error line naming `field`, exit code 2, nothing on stdout.
fn refused(args: &[&str], field: &str) {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(field), "the error should name '{field}': {err}");
    assert!(out.stdout.is_empty());
}

const OMEGA: &str = r#"omega = { value = 0.33, range = "(0, inf)", doc = "forcing frequency", symbol = "ω" }"#;

#[test]
fn bad_symbols_and_long_names_are_refused_naming_the_field() {
    let d = scratch("symbols-bad");
    let bad = |name: &str, to: &str| multi_stop_with(&d, name, OMEGA, to).to_str().unwrap().to_string();
    let cases = [
        ("empty.toml", r#"omega = { value = 0.33, symbol = "" }"#, "parameters.omega.symbol: must not be empty"),
        (
            "long.toml",
            r#"omega = { value = 0.33, symbol = "omega the frequency" }"#,
            "parameters.omega.symbol: at most 16",
        ),
        (
            "control.toml",
            r#"omega = { value = 0.33, symbol = "ω\t" }"#,
            "parameters.omega.symbol: must not hold control",
        ),
        (
            "newline.toml",
            r#"omega = { value = 0.33, long_name = "forcing\nfrequency" }"#,
            "parameters.omega.long_name: must be one line",
        ),
        ("blank.toml", r#"omega = { value = 0.33, long_name = "" }"#, "parameters.omega.long_name: must not be empty"),
    ];
    for (name, line, error) in cases {
        refused(&["cell", &bad(name, line)], error);
    }
    // Declared well, anything short: the scene runs.
    let ok = bad("ok.toml", r#"omega = { value = 0.33, symbol = "Ω̃", long_name = "forcing frequency ω/ω₀" }"#);
    let out = run(&["cell", &ok, "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::remove_dir_all(&d).unwrap();
}

/// Runs a Python snippet with Debian's python3 (h5py, xarray, h5netcdf,
/// netCDF4 installed by scripts/setup.sh; CI has them): missing, the test fails.
fn python(script: &str, args: &[&str]) {
    let out = Command::new("/usr/bin/python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("/usr/bin/python3 is needed (scripts/setup.sh installs it)");
    assert!(
        out.status.success(),
        "python3 failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Reads the axis coordinates' attributes of every group of an atlas with
/// h5py and xarray (h5netcdf and netcdf4): argv = file, then per axis
/// `name=symbol=long_name`.
const READ_ATTRS: &str = r#"
import sys
import h5py
import xarray as xr

path, axes = sys.argv[1], [a.split("=", 2) for a in sys.argv[2:]]
with h5py.File(path, "r") as f:
    groups = [""] + f.attrs["sweeps"].split(",") + (["attractors"] if "attractors" in f else [])
    for g in groups:
        for name, symbol, long_name in axes:
            d = f[g + "/" + name if g else name]
            assert d.attrs["symbol"] == symbol, (g, name, d.attrs["symbol"])
            assert d.attrs["long_name"] == long_name, (g, name, d.attrs["long_name"])
            assert d.attrs["units"] == "1"
for engine in ["h5netcdf", "netcdf4"]:
    for g in groups:
        with xr.open_dataset(path, engine=engine, group=g or None) as ds:
            for name, symbol, long_name in axes:
                assert ds[name].attrs["symbol"] == symbol, (engine, g, name, ds[name].attrs)
                assert ds[name].attrs["long_name"] == long_name, (engine, g, name, ds[name].attrs)
            assert name in ds.coords
print("ok", groups)
"#;

#[test]
fn atlas_axes_carry_symbols_that_h5py_and_xarray_read() {
    let d = scratch("symbols-atlas");
    let f = d.join("a.h5");
    let f = f.to_str().unwrap();
    let out = run(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.2:2:12",
        "--y",
        "delta=0.1:1.5:6",
        "--sweep",
        "both",
        "--attractors",
        "2",
        "--attractors-where",
        "hysteresis",
        "-o",
        f,
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    python(READ_ATTRS, &[f, "omega=ω=forcing frequency", "delta=δ=clearance of every stop"]);
    python(
        r#"
import sys
import xarray as xr
ds = xr.open_dataset(sys.argv[1], engine="h5netcdf", group="up")
assert ds.omega.attrs["symbol"] == "ω" and ds.omega.attrs["long_name"] == "forcing frequency", ds.omega.attrs
assert ds.delta.attrs["symbol"] == "δ", ds.delta.attrs
"#,
        &[f],
    );
    let meta = store::read(Path::new(f)).unwrap().atlas.meta;
    assert_eq!(meta.symbol("omega"), "ω");
    assert_eq!(meta.symbol("delta"), "δ");
    assert_eq!(meta.symbol("mu_k"), "μ_k", "not an axis: from the stored scene");
    assert_eq!(meta.long_name("omega"), Some("forcing frequency"));
    assert_eq!(meta.long_name("zeta"), Some("damping ratio of M1"), "declared rather than the doc");

    // Declared symbols of parameters whose names give none (a sweep file,
    // along fk), and a long name from the doc.
    let s = d.join("s.h5");
    let s = s.to_str().unwrap();
    let out = run(&["sweep", "configs/dry-friction.toml", "--axis", "fk=0.01:0.1:4", "--direction", "up", "-o", s]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let meta = store::read(Path::new(s)).unwrap().atlas.meta;
    let y = meta.plane.y.name.clone();
    let y_long = meta.long_name(&y).map_or_else(|| format!("parameter {y}"), str::to_string);
    let y_symbol = meta.symbol(&y);
    assert_eq!(meta.symbol("fk"), "f_k");
    assert_eq!(meta.symbol("fs_ratio"), "f_s/f_k");
    python(READ_ATTRS, &[s, "fk=f_k=kinetic friction force", &format!("{y}={y_symbol}={y_long}")]);
    std::fs::remove_dir_all(&d).unwrap();
}
