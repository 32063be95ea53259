//! File checks (issue 30, second audit): never a file that lies, checksums a reader
//! verifies. Each test reproduces one finding and checks the fix through the
//! binary.

use crate::integrity::{mutated, python};
use crate::run_safety::refused;
use crate::util::{run, scratch};
use std::path::{Path, PathBuf};

/// The audit's atlas: both sweeps, with an unresolved cell (its reason in
/// its sweep's `reason` table; in the down sweep since tori are told by
/// their rotation number, issue 40).
/// The plane of these checks: records without extensions, so that the
/// down sweep keeps a cell unresolved, whose stored reason the checks need
/// (19 columns: on 20 its unresolved cells were tori whose period section
/// impacts cut, `Q` since they are told at another phase, issue 62).
const PLANE: [&str; 9] = [
    "configs/multi-stop.toml",
    "--x",
    "omega=0.1:3:19",
    "--y",
    "delta=0.05:2:12",
    "--sweep",
    "both",
    "--accuracy",
    "extensions=0",
];

fn atlas_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["atlas"];
    v.extend(PLANE);
    v.extend_from_slice(extra);
    v.extend(["--threads", "1", "--quiet", "-o", out]);
    v
}

fn atlas(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let o = out.to_str().unwrap();
    let r = run(&atlas_args(o, extra));
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    out
}

/// A copy of `from` at `to` with the byte at the first occurrence of
/// `text` (offset `at` into it) changed.
fn flipped(from: &Path, to: &Path, text: &[u8], at: usize) -> PathBuf {
    let mut b = std::fs::read(from).unwrap();
    let i = b.windows(text.len()).position(|w| w == text).unwrap_or_else(|| panic!("{text:?} not in the file"));
    b[i + at] ^= 0x1b;
    std::fs::write(to, b).unwrap();
    to.to_path_buf()
}

/// Item 1: a byte flipped in a text that HDF5 keeps in its unchecksummed
/// global heap (a reason, the stored scene) is refused, naming the dataset or
/// the object and the checksum attribute; the checksums are the ones the
/// file format documents (CRC-32, zlib's), which Python verifies with no
/// project code; xarray still reads the file through both engines.
#[test]
fn texts_in_the_global_heap_carry_checksums_readers_verify() {
    let d = scratch("file-checks-texts");
    let a = atlas(&d, "a.h5", &[]);
    let f = a.to_str().unwrap();
    let out = run(&["inspect", f]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("no period within the record"));

    let x = flipped(&a, &d.join("reason.h5"), b"no period within", 4);
    let x = x.to_str().unwrap();
    refused(&["inspect", x], "/reason: its texts do not match their checksum (attribute text_crc32)");
    refused(&["cell", "configs/multi-stop.toml", "--from", x, "--at", "omega=1,delta=1"], "/reason:");

    let scene = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/multi-stop.toml")).unwrap();
    let line = scene.lines().find(|l| l.len() > 12 && !l.starts_with('#')).unwrap();
    let x = flipped(&a, &d.join("scene.h5"), line.as_bytes(), 2);
    refused(
        &["inspect", x.to_str().unwrap()],
        "the text attributes of / do not match their checksum (attribute attributes_crc32)",
    );

    // The documented checksums, computed in Python.
    const CHECK: &str = r#"
import os, sys, struct, zlib, h5py
def crc(texts):
    c = 0
    for b in texts:
        c = zlib.crc32(struct.pack("<Q", len(b)) + b, c)
    return c
with h5py.File(sys.argv[1], "r") as f:
    for name in ["up/reason", "down/reason", "up/label", "legend/up/M1/label"]:
        d = f[name]
        assert crc(v for v in d[()]) == d.attrs["text_crc32"], name
    covered = set(os.environ["CHECKED_TEXTS"].split(","))
    for o in [f, f["omega"]]:
        texts = []
        for n in sorted(o.attrs.keys(), key=lambda k: k.encode()):
            t = o.attrs.get_id(n).get_type()
            if isinstance(t, h5py.h5t.TypeStringID) and t.is_variable_str() and t.get_cset() == h5py.h5t.CSET_UTF8:
                assert n in covered, ("a text attribute the checksum does not cover", o.name, n)
                texts += [n.encode(), o.attrs[n].encode()]
        assert crc(texts) == o.attrs["attributes_crc32"], o.name
import xarray as xr
for engine in ["h5netcdf", "netcdf4"]:
    reasons = [str(r) for g in ["up", "down"] for r in xr.open_dataset(sys.argv[1], group=g, engine=engine).reason.values]
    assert any("no period within" in r for r in reasons), engine
    root = xr.open_dataset(sys.argv[1], engine=engine)
    assert root.attrs["sweeps"] == "up,down", engine
print("ok")
"#;
    assert_eq!(python(CHECK, &[f]).trim(), "ok");

    // A text attribute a user adds (h5py) is not covered: the file still reads.
    let noted = d.join("noted.h5");
    std::fs::copy(&a, &noted).unwrap();
    const NOTE: &str = r#"
import sys, h5py
with h5py.File(sys.argv[1], "r+") as f:
    f.attrs["note"] = "run for the referee"
    f["omega"].attrs["comment"] = "mine"
print("ok")
"#;
    assert_eq!(python(NOTE, &[noted.to_str().unwrap()]).trim(), "ok");
    let out = run(&["inspect", noted.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// Reasons are stored with their numbers (issue 38): the entry of
/// `reason_detail` of each sweep's first unresolved cell (a sweep without
/// one has neither reasons nor details), read with h5py and
/// Python's own JSON, is the `reason_detail` that `cell --from` gives when it
/// simulates that cell again (from the same start, to the same numbers), its
/// text that cell's `reason`; the details carry the documented CRC-32.
#[test]
fn reasons_are_stored_with_their_numbers() {
    let d = scratch("file-checks-reason-detail");
    let a = atlas(&d, "a.h5", &[]);
    let f = a.to_str().unwrap();
    const FIRST_U: &str = r#"
import sys, json, struct, zlib, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    for sweep in ["up", "down"]:
        g = f[sweep]
        if "reason_detail" not in g:
            assert len(g["reason"]) == 0, sweep
            continue
        c = 0
        for b in g["reason_detail"][()]:
            c = zlib.crc32(struct.pack("<Q", len(b)) + b, c)
        assert c == g["reason_detail"].attrs["text_crc32"], sweep
        code = g["reason_code"][()]
        iy, ix = np.argwhere(code >= 0)[0]
        k = code[iy, ix]
        print(json.dumps({"sweep": sweep, "at": f"omega={f['omega'][ix]!r},delta={f['delta'][iy]!r}",
                          "detail": json.loads(g["reason_detail"][k]), "text": g["reason"][k].decode()}))
"#;
    let found = python(FIRST_U, &[f]);
    assert!(found.lines().count() >= 1, "no sweep with an unresolved cell: {found}");
    for line in found.lines() {
        let stored: serde_json::Value = serde_json::from_str(line).unwrap();
        let (sweep, at) = (stored["sweep"].as_str().unwrap(), stored["at"].as_str().unwrap());
        let again = crate::util::cell_json(&["configs/multi-stop.toml", "--from", f, "--at", at, "--sweep", sweep]);
        assert_eq!(again["class"], "unresolved", "{sweep} {at}");
        assert_eq!(again["reason_detail"], stored["detail"], "{sweep} {at}");
        assert_eq!(again["reason"], stored["text"], "{sweep} {at}");
        assert!(stored["detail"]["kind"].is_string(), "{line}");
    }
}

/// Issue 61: a deleted `reason_detail` does not read as a file from before
/// the details. The root's `reason_details` names the sweeps written with
/// them (h5py reads it); deleting one sweep's details is refused naming the
/// dataset, by `inspect` and `inspect --verify`, and deleting the attribute
/// too fails the root's `attributes_crc32`.
#[test]
fn a_deleted_reason_detail_is_refused() {
    let d = scratch("file-checks-reason-detail-deleted");
    let a = atlas(&d, "a.h5", &[]);
    const DELETE: &str = r#"
import sys, shutil, h5py
src, dst, attr = sys.argv[1], sys.argv[2], sys.argv[3] == "attr"
shutil.copy(src, dst)
with h5py.File(dst, "r+") as f:
    sweeps = f.attrs["reason_details"].split(",")
    assert sweeps and all(s in ("up", "down") and "reason_detail" in f[s] for s in sweeps), sweeps
    del f[sweeps[0] + "/reason_detail"]
    if attr:
        del f.attrs["reason_details"]
    print(sweeps[0])
"#;
    let cut = d.join("cut.h5");
    let sweep = python(DELETE, &[a.to_str().unwrap(), cut.to_str().unwrap(), "dataset"]);
    let sweep = sweep.trim();
    for args in [vec!["inspect"], vec!["inspect", "--verify"]] {
        let mut args = args.clone();
        args.push(cut.to_str().unwrap());
        let out = run(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} read a file without {sweep}/reason_detail");
        assert!(err.contains(&format!("{sweep}/reason_detail")) && err.contains("reason_details"), "{err}");
    }
    python(DELETE, &[a.to_str().unwrap(), cut.to_str().unwrap(), "attr"]);
    let out = run(&["inspect", cut.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("attributes_crc32"), "{err}");
}

/// Item 2: `--resume` on this run's finished file with a damaged dataset
/// (one the reader skips, or one it reads) is refused naming the dataset,
/// neither taken as done nor computed again over it; whole, it is done.
#[test]
fn resume_checks_a_finished_file_whole() {
    let d = scratch("file-checks-resume");
    let a = atlas(&d, "a.h5", &[]);
    let again = |out: &Path| {
        let mut args = atlas_args(out.to_str().unwrap(), &["--resume"]);
        args.retain(|&s| s != "--quiet");
        run(&args)
    };
    let out = again(&a);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("nothing to do"));
    // One byte of a dataset's stored bytes flipped (its checksum then fails).
    const FLIP: &str = r#"
import sys, shutil, h5py
src, dst, name = sys.argv[1:4]
shutil.copy(src, dst)
with h5py.File(dst, "r") as f:
    d = f[name]
    off = d.id.get_chunk_info(0).byte_offset if d.chunks else d.id.get_offset()
with open(dst, "r+b") as g:
    g.seek(off + 3)
    b = g.read(1)
    g.seek(off + 3)
    g.write(bytes([b[0] ^ 0x5A]))
"#;
    // Datasets the reader reads (up/class, a reason table) and ones it skips
    // (a label code, the hysteresis): each refused, none recomputed over.
    for name in ["up/label_code_M1", "hysteresis", "up/class", "down/reason"] {
        let x = d.join("x.h5");
        python(FLIP, &[a.to_str().unwrap(), x.to_str().unwrap(), name]);
        let out = again(&x);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(!String::from_utf8_lossy(&out.stdout).contains("nothing to do"), "{name}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(&format!("x.h5: {name}: ")), "{name}: {err}");
    }
    // A root attribute that no longer reads (its checksum written again:
    // the file says it is an atlas): refused, naming it, not computed again.
    let x = mutated(&a, &d.join("sweeps.h5"), &["attr|@sweeps|'up,down,fresh'"]);
    let out = again(&x);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("attribute sweeps of /"), "{err}");
}

/// Items 4 and 5: an attribute of another type than the layout's, or a
/// `sweeps` attribute empty or naming an unknown sweep, in a file whose
/// texts are whole (their checksum written again), is refused when the file
/// is opened, naming the attribute; changed without its checksum, the file
/// is refused by the checksum.
#[test]
fn attributes_of_the_wrong_type_or_empty_sweeps_are_named() {
    let d = scratch("file-checks-attrs");
    let a = atlas(&d, "a.h5", &[]);
    let cases = [
        ("attr|@dim|'four'", "attribute dim of /: expected an unsigned integer, found a string"),
        ("attr|@sweeps|''", "attribute sweeps of /: empty"),
        ("attr|@sweeps|'up,sideways'", "attribute sweeps of /: unknown sweep 'sideways'"),
        ("attr|@sweeps|'up,down,fresh'", "attribute sweeps of /: names sweep fresh, whose group the file lacks"),
        ("attr|@section_cap|'a lot'", "attribute section_cap of /: expected an integer, found a string"),
        ("attr|@scene|np.int64(3)", "attribute scene of /: expected a string, found a signed integer"),
        ("rawattr|@sweeps|''", "do not match their checksum (attribute attributes_crc32)"),
    ];
    for (k, (spec, what)) in cases.iter().enumerate() {
        let x = mutated(&a, &d.join(format!("m{k}.h5")), &[spec]);
        let x = x.to_str().unwrap();
        refused(&["inspect", x], what);
        refused(&["cell", "configs/multi-stop.toml", "--from", x, "--at", "omega=1,delta=1", "--sweep", "up"], what);
    }
}

/// Item 6: parts of a merge with other settings are refused naming each
/// setting that differs, with both values.
#[test]
fn a_merge_of_parts_with_other_settings_names_each_difference() {
    let d = scratch("file-checks-merge");
    let q1 = atlas(&d, "q1.h5", &["--shard", "1/2"]);
    let q2 = atlas(&d, "q2.h5", &["--shard", "2/2", "--section-cap", "4", "--preset", "fast"]);
    let m = d.join("m.h5");
    let out = run(&["merge", q1.to_str().unwrap(), q2.to_str().unwrap(), "-o", m.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("is not a part of the same run as"), "{err}");
    assert!(err.contains("preset standard and fast"), "{err}");
    let cap = err.split("section_cap ").nth(1).unwrap_or_else(|| panic!("{err}"));
    assert!(cap.split(" and 4").count() == 2, "{err}");
    assert!(!m.exists());
}
