//! Issue 39: `zoom` computes a box of a stored atlas again, its chains
//! entering from the parent. The oracle: a box aligned with the parent's grid
//! at the parent's spacing reproduces the parent's cells bit for bit, every
//! sweep, on the shipped two-mass scenes; the child file is an ordinary atlas
//! whose stored cells `cell --from` reproduces, chains' first cells included.

use crate::util::{config, run};
use engine::{atlas, zoom, AtlasRequest, Quiet, SceneSource, Sim, Start, ZoomRequest};
use grid::{Along, Atlas, Axis, SweepKind};
use scene::Named;
use std::path::{Path, PathBuf};

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    crate::util::scratch(&format!("zoom-{name}"))
}

/// Writes the atlas of `scene` over `x` by `y` with `sweeps` to `out`.
fn parent(scene: &str, x: Axis, y: Axis, along: Along, sweeps: Vec<SweepKind>, out: &Path) -> Atlas {
    let mut r = AtlasRequest::new(Sim::new(SceneSource::File(config(scene))), x, y, sweeps);
    r.along = along;
    r.threads = 2;
    r.output = Some(out.to_path_buf());
    atlas(&r, &Quiet).unwrap().atlas
}

/// The multi-stop atlas over omega=0.2:2.0:37 by delta=0.1:1.0:10, up and
/// down, written to `out`.
fn multi_stop(out: &Path) -> Atlas {
    let (x, y) = (Axis::parse("omega=0.2:2.0:37", "x").unwrap(), Axis::parse("delta=0.1:1.0:10", "y").unwrap());
    parent("multi-stop.toml", x, y, Along::X, vec![SweepKind::Up, SweepKind::Down], out)
}

/// The box `x` by `y` of `parent_file` (every sweep), written to `out`.
fn child(parent_file: &Path, x: &str, y: &str, out: &Path) -> Atlas {
    let mut r = ZoomRequest::new(parent_file, Axis::parse(x, "x").unwrap(), Axis::parse(y, "y").unwrap());
    r.threads = 2;
    r.output = Some(out.to_path_buf());
    zoom(&r, &Quiet).unwrap().atlas
}

/// Asserts that every cell of `child` equals the parent's cell `(iy + dy, ix + dx)`, bit for bit.
fn same_cells(parent: &Atlas, child: &Atlas, dy: usize, dx: usize, what: &str) {
    let (pnx, cnx) = (parent.meta.plane.x.count, child.meta.plane.x.count);
    assert_eq!(child.meta.sweeps, parent.meta.sweeps, "{what}");
    for map in &child.maps {
        let pmap = parent.map(map.sweep).unwrap();
        for (i, c) in map.cells.iter().enumerate() {
            let (iy, ix) = (i / cnx, i % cnx);
            let p = &pmap.cells[(iy + dy) * pnx + ix + dx];
            assert_eq!(c, p, "{what}: {} cell ({iy}, {ix}) differs from the parent's", map.sweep.name());
        }
    }
}

#[test]
fn an_aligned_box_reproduces_its_parents_cells_bit_for_bit() {
    let dir = folder("oracle");
    let both = vec![SweepKind::Up, SweepKind::Down];
    // (scene, parent x, parent y, along, aligned boxes: (x, y, rows skipped, columns skipped))
    type Case<'a> = (&'a str, &'a str, &'a str, Along, Vec<(&'a str, &'a str, usize, usize)>);
    let cases: Vec<Case> = vec![
        (
            "multi-stop.toml",
            "omega=0.2:2.0:37",
            "delta=0.1:1.0:10",
            Along::X,
            vec![("omega=0.5:1.0:11", "delta=0.3:0.6:4", 2, 6), ("omega=0.2:0.8:13", "delta=0.1:1.0:10", 0, 0)],
        ),
        (
            "impact-damper.toml",
            "omega=0.8:2.4:17",
            "delta=0.5:3:6",
            Along::X,
            vec![("omega=1.5:2.4:10", "delta=1:2.5:4", 1, 7)],
        ),
        (
            "symmetric-stops.toml",
            "omega=0.5:2.5:21",
            "delta=0.1:0.5:5",
            Along::X,
            vec![("omega=1.2:2.0:9", "delta=0.2:0.4:3", 1, 7)],
        ),
        // Chains along y: the box's columns enter from the parent's.
        (
            "dry-friction.toml",
            "omega=6.5:7.1:7",
            "fk=0.005:0.1:20",
            Along::Y,
            vec![("omega=6.6:6.9:4", "fk=0.03:0.08:11", 5, 1)],
        ),
    ];
    for (scene, px, py, along, boxes) in cases {
        let pfile = dir.join(scene.replace(".toml", ".h5"));
        let p =
            parent(scene, Axis::parse(px, "x").unwrap(), Axis::parse(py, "y").unwrap(), along, both.clone(), &pfile);
        for (k, (bx, by, dy, dx)) in boxes.into_iter().enumerate() {
            let cfile = dir.join(format!("{}-box{k}.h5", scene.replace(".toml", "")));
            let c = child(&pfile, bx, by, &cfile);
            let what = format!("{scene} box {bx} {by}");
            same_cells(&p, &c, dy, dx, &what);
            // The file is an ordinary atlas holding what was computed, with its parent.
            let loaded = store::read(&cfile).unwrap();
            assert_eq!(loaded.atlas, c, "{what}: the file holds the zoom's atlas");
            let parent_of = loaded.info.parent.as_ref().unwrap();
            assert_eq!(parent_of.path, pfile.display().to_string());
            assert_eq!(parent_of.labels_crc32, store::labels_crc32(&p));
            assert_eq!(
                parent_of.region,
                format!("{} {}", Axis::parse(bx, "x").unwrap(), Axis::parse(by, "y").unwrap())
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `cell --from` a zoom's file re-runs a stored cell from the state it
/// started from: the first cell of a chain starts from the entry the parent
/// gave it, not the scene's initial state.
#[test]
fn a_zooms_stored_cells_run_again_from_their_entry() {
    let dir = folder("entry");
    let pfile = dir.join("p.h5");
    multi_stop(&pfile);
    // Not aligned: a third of the parent's spacing, in a box of its own.
    let cfile = dir.join("c.h5");
    let c = child(&pfile, "omega=0.9:1.3:25", "delta=0.45:0.85:5", &cfile);
    let sim = Sim::new(SceneSource::File(config("multi-stop.toml")));
    let nx = c.meta.plane.x.count;
    let mut entered = 0;
    for (sweep, ix) in [(SweepKind::Up, 0), (SweepKind::Down, nx - 1), (SweepKind::Up, 7)] {
        for iy in 0..c.meta.plane.y.count {
            let stored = c.map(sweep).unwrap().cells[iy * nx + ix].as_ref().unwrap();
            let at =
                vec![("omega".to_string(), c.meta.plane.x.value(ix)), ("delta".to_string(), c.meta.plane.y.value(iy))];
            let again = engine::cell(&sim, &Start::Cell { file: cfile.clone(), at, sweep: Some(sweep) }).unwrap();
            assert_eq!(again.result.final_state, stored.final_state, "{} ({iy}, {ix})", sweep.name());
            assert_eq!(again.result.labels.iter().map(|l| l.label).collect::<Vec<_>>(), stored.labels);
            entered += usize::from(ix != 7 && c.entries.get(sweep, iy).is_some());
        }
    }
    // Every chain of both sweeps enters from the parent but the down chain
    // at δ = 0.55, whose parent's state at the box's edge (a row of another
    // δ) penetrates one of its stops: it starts, and re-runs, from the
    // scene's initial state, and the file records no entry for it.
    assert_eq!(entered, 9, "the chains that entered from the parent");
    assert!(c.entries.get(SweepKind::Down, 1).is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// At three times the parent's resolution a fresh sweep's cells at the
/// parent's own values are the parent's, bit for bit (the box takes the
/// parent's values where they coincide to rounding).
#[test]
fn a_finer_box_computes_at_the_parents_own_values() {
    let dir = folder("finer");
    let pfile = dir.join("p.h5");
    let p = parent(
        "multi-stop.toml",
        Axis::parse("omega=0.1:3.05:60", "x").unwrap(),
        Axis::parse("delta=0.05:2:9", "y").unwrap(),
        Along::X,
        vec![SweepKind::Fresh],
        &pfile,
    );
    let step = 2.95 / 59.0;
    let (a, b) = (0.1 + 10.0 * step, 0.1 + 20.0 * step);
    let c = child(&pfile, &format!("omega={a}:{b}:31"), "delta=0.05:2:9", &dir.join("c.h5"));
    let (cx, px) = (&c.meta.plane.x, &p.meta.plane.x);
    for k in 0..=10 {
        assert_eq!(cx.value(3 * k).to_bits(), px.value(10 + k).to_bits(), "value {k}");
        for iy in 0..9 {
            assert_eq!(c.maps[0].cells[iy * 31 + 3 * k], p.maps[0].cells[iy * 60 + 10 + k], "cell ({iy}, {k})");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bad boxes and parents: one line naming what is wrong, exit 2, no file.
#[test]
fn zoom_refuses_bad_boxes_with_one_clear_line() {
    let dir = folder("bad");
    let pfile = dir.join("p.h5");
    parent(
        "multi-stop.toml",
        Axis::parse("omega=0.2:2.0:10", "x").unwrap(),
        Axis::parse("delta=0.1:1.0:4", "y").unwrap(),
        Along::X,
        vec![SweepKind::Up],
        &pfile,
    );
    let p = pfile.to_str().unwrap();
    let out = dir.join("c.h5");
    let o = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![p, "--x", "omega=1.5:2.5:5", "--y", "delta=0.1:1:4"],
            "--x: omega=1.5:2.5 is not within the parent's 0.2 to 2",
        ),
        (vec![p, "--x", "zeta=0.5:1:5", "--y", "delta=0.1:1:4"], "--x: the parent's x axis is omega, not zeta"),
        (vec![p, "--x", "omega=1:0.5:5", "--y", "delta=0.1:1:4"], "inverted range"),
        (vec![p, "--x", "omega=0.5:1:10000", "--y", "delta=0.1:1:1000"], "more than the 4000000 a zoom computes"),
        (vec![p, "--x", "omega=0.5:1:5", "--y", "delta=0.1:1:4", "--sweep", "down"], "--sweep: "),
        (vec!["configs/multi-stop.toml", "--x", "omega=0.5:1:5", "--y", "delta=0.1:1:4"], "not an HDF5 file"),
    ];
    for (args, said) in cases {
        let mut all = vec!["zoom"];
        all.extend(&args);
        all.extend(["-o", o, "--quiet"]);
        let r = run(&all);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(said), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists(), "{args:?} left {o}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A zoom of a zoom: a box aligned with the child's grid (three times the
/// parent's resolution) reproduces the child's cells bit for bit, its values
/// snapped level by level (to the child's, and through them to the
/// parent's), every sweep.
#[test]
fn a_zoom_of_a_zoom_reproduces_its_parent() {
    let dir = folder("grandchild");
    let pfile = dir.join("p.h5");
    let p = multi_stop(&pfile);
    let cfile = dir.join("c.h5");
    let c = child(&pfile, "omega=0.5:1.0:31", "delta=0.3:0.6:10", &cfile);
    assert_eq!(c.meta.plane.x.value(0).to_bits(), p.meta.plane.x.value(6).to_bits());
    let (cx, cy) = (&c.meta.plane.x, &c.meta.plane.y);
    let (x, y) =
        (format!("omega={}:{}:13", cx.value(3), cx.value(15)), format!("delta={}:{}:5", cy.value(2), cy.value(6)));
    let g = child(&cfile, &x, &y, &dir.join("g.h5"));
    same_cells(&c, &g, 2, 3, "a box of the zoom");
    // Its own box: the chains start as the child's did, from its entries.
    let again = child(&cfile, "omega=0.5:1.0:31", "delta=0.3:0.6:10", &dir.join("again.h5"));
    same_cells(&c, &again, 0, 0, "the zoom's own box");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `zoom --set` (issue 65): the box as a slice at another value of a
/// parameter that is not an axis. Oracles: its fresh cells are those of an
/// atlas of the scene with that value (`atlas --set`), bit for bit, and not
/// the parent's; its continuation cells re-run from their entries with
/// `cell --from` the child file (which so records the value); the file's
/// parent region names it; an axis, an unknown name or a non-number is
/// refused in one line.
#[test]
fn a_zoom_at_another_parameter_value_is_that_slice() {
    let dir = folder("slice");
    let pfile = dir.join("p.h5");
    let (x, y) = (Axis::parse("omega=0.2:2.0:19", "x").unwrap(), Axis::parse("delta=0.1:1.0:10", "y").unwrap());
    let p = parent("multi-stop.toml", x, y, Along::X, vec![SweepKind::Fresh, SweepKind::Up], &pfile);
    let (bx, by) = ("omega=0.5:1.5:11", "delta=0.3:0.7:5");
    let cfile = dir.join("c.h5");
    let mut r = ZoomRequest::new(&pfile, Axis::parse(bx, "x").unwrap(), Axis::parse(by, "y").unwrap());
    r.set = vec![("zeta".to_string(), 0.03)];
    r.threads = 2;
    r.output = Some(cfile.clone());
    let c = zoom(&r, &Quiet).unwrap().atlas;
    // Every fresh cell is the scene's at zeta = 0.03 and the cell's values,
    // from its initial state.
    let fresh = c.map(SweepKind::Fresh).unwrap();
    for iy in 0..5 {
        for ix in 0..11 {
            let mut sim = Sim::new(SceneSource::File(config("multi-stop.toml")));
            sim.set = vec![
                ("zeta".to_string(), 0.03),
                ("omega".to_string(), c.meta.plane.x.value(ix)),
                ("delta".to_string(), c.meta.plane.y.value(iy)),
            ];
            let alone = engine::cell(&sim, &Start::Initial).unwrap().result;
            let stored = fresh.cells[iy * 11 + ix].as_ref().unwrap();
            assert_eq!(alone.final_state, stored.final_state, "fresh cell ({iy}, {ix})");
            assert_eq!(alone.labels.iter().map(|l| l.label).collect::<Vec<_>>(), stored.labels, "({iy}, {ix})");
        }
    }
    let pfresh = p.map(SweepKind::Fresh).unwrap();
    let differ = (0..5)
        .flat_map(|iy| (0..11).map(move |ix| (iy, ix)))
        .filter(|&(iy, ix)| fresh.cells[iy * 11 + ix] != pfresh.cells[(iy + 2) * 19 + ix + 3])
        .count();
    assert_eq!(differ, 55, "every cell moved with zeta (the parent's are at zeta = 0.1)");
    // The up sweep's first cells, again from the child file.
    for iy in 0..5 {
        let at = vec![("omega".to_string(), c.meta.plane.x.value(0)), ("delta".to_string(), c.meta.plane.y.value(iy))];
        let from = Start::Cell { file: cfile.clone(), at, sweep: Some(SweepKind::Up) };
        let again = engine::cell(&Sim::new(SceneSource::File(config("multi-stop.toml"))), &from).unwrap();
        let stored = c.map(SweepKind::Up).unwrap().cells[iy * 11].as_ref().unwrap();
        assert_eq!(again.result.final_state, stored.final_state, "up cell ({iy}, 0)");
    }
    let loaded = store::read(&cfile).unwrap();
    assert_eq!(loaded.info.parent.unwrap().region, "omega=0.5:1.5:11 delta=0.3:0.7:5 at zeta=0.03");
    assert!(loaded.atlas.meta.overrides.contains(&("zeta".to_string(), 0.03)), "{:?}", loaded.atlas.meta.overrides);
    // Bad values: one line each, exit 2, no file.
    let out = dir.join("bad.h5");
    let cases = [
        ("omega=1", "--set omega: omega is an axis of the parent's plane"),
        ("nope=1", "nope"),
        ("zeta=abc", "--set zeta: 'abc' is not a number"),
        ("zeta", "--set zeta: expected NAME=VALUE"),
    ];
    for (set, said) in cases {
        let p = pfile.to_str().unwrap();
        let r = run(&["zoom", p, "--x", bx, "--y", by, "--set", set, "-o", out.to_str().unwrap(), "--quiet"]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{set}: {err}");
        assert!(err.contains(said), "{set}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists(), "{set} left a file");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A zoom whose chains all start from the scene's initial state (the box
/// at the parent's first values, up) is an ordinary readable child: its
/// `entry_state` is all NaN, not missing (the sixth audit: every reader
/// refused such a child). The same name set twice is refused.
#[test]
fn a_zoom_from_the_initial_state_reads_back() {
    let dir = folder("initial");
    let pfile = dir.join("p.h5");
    let (x, y) = (Axis::parse("omega=0.2:2.0:10", "x").unwrap(), Axis::parse("delta=0.1:1.0:4", "y").unwrap());
    parent("multi-stop.toml", x, y, Along::X, vec![SweepKind::Up, SweepKind::Down], &pfile);
    let cfile = dir.join("c.h5");
    let c = cfile.to_str().unwrap();
    let p = pfile.to_str().unwrap();
    let ok = run(&["zoom", p, "--x", "omega=0.2:0.6:5", "--y", "delta=0.1:1.0:4", "--sweep", "up", "-o", c, "--quiet"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let verified = run(&["inspect", "--verify", c]);
    assert!(verified.status.success(), "{}", String::from_utf8_lossy(&verified.stderr));
    let loaded = store::read(&cfile).unwrap();
    assert!(loaded.atlas.entries.0.is_empty(), "every chain from the initial state");
    let d = dir.join("d.h5");
    let args = ["--x", "omega=0.5:1:5", "--y", "delta=0.1:1:4", "--set", "zeta=0.05", "--set", "zeta=0.07", "-o"];
    let twice = run(&[&["zoom", p][..], &args, &[d.to_str().unwrap()]].concat());
    let err = String::from_utf8_lossy(&twice.stderr);
    assert_eq!(twice.status.code(), Some(2), "{err}");
    assert!(err.contains("--set zeta: given twice"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 61: a zoom records the state each chain started from. With the
/// single stop moved to σ = −1 (`--set sigma=-1`), every state the
/// parent's chains had at the box's edge (at σ = 0) penetrates the stop, so
/// each chain starts from the scene's initial state; the child's entries are
/// none (they recorded the penetrating states), its first cells are those
/// of the box alone from the initial state, and a chain of the parent at its
/// own σ still enters with the parent's state.
#[test]
fn a_zoom_records_no_entry_its_stop_refuses() {
    let dir = folder("penetrating");
    let pfile = dir.join("p.h5");
    let (x, y) = (Axis::parse("omega=1:3:20", "x").unwrap(), Axis::parse("zeta=0:0.1:6", "y").unwrap());
    let p = parent("single-stop.toml", x, y, Along::X, vec![SweepKind::Up, SweepKind::Down], &pfile);
    let (bx, by) = ("omega=1.5:2.5:8", "zeta=0.02:0.08:4");
    let zoomed = |set: Vec<(String, f64)>, out: &Path| {
        let mut r = ZoomRequest::new(&pfile, Axis::parse(bx, "x").unwrap(), Axis::parse(by, "y").unwrap());
        (r.set, r.threads, r.output) = (set, 2, Some(out.to_path_buf()));
        zoom(&r, &Quiet).unwrap().atlas
    };
    let moved = zoomed(vec![("sigma".to_string(), -1.0)], &dir.join("moved.h5"));
    assert!(moved.entries.0.is_empty(), "{:?}", moved.entries);
    assert!(store::read(&dir.join("moved.h5")).unwrap().atlas.entries.0.is_empty());
    for (sweep, ix) in [(SweepKind::Up, 0), (SweepKind::Down, 7)] {
        for iy in 0..4 {
            let mut sim = Sim::new(SceneSource::File(config("single-stop.toml")));
            let (omega, zeta) = (moved.meta.plane.x.value(ix), moved.meta.plane.y.value(iy));
            sim.set = vec![("sigma".into(), -1.0), ("omega".into(), omega), ("zeta".into(), zeta)];
            let alone = engine::cell(&sim, &Start::Initial).unwrap().result;
            let stored = moved.map(sweep).unwrap().cells[iy * 8 + ix].as_ref().unwrap();
            assert_eq!(alone.final_state, stored.final_state, "{} cell ({iy}, {ix})", sweep.name());
        }
    }
    // At the parent's own σ the chains enter with the parent's states.
    let same = zoomed(Vec::new(), &dir.join("same.h5"));
    assert_eq!(same.entries.0.len(), 8, "{:?}", same.entries);
    for ((sweep, line), state) in &same.entries.0 {
        let ix = if *sweep == SweepKind::Up { 0 } else { 7 };
        let iy = p.meta.plane.y.nearest(same.meta.plane.y.value(*line)).unwrap();
        let jx = p.meta.plane.x.nearest(same.meta.plane.x.value(ix)).unwrap();
        assert_eq!(Some(state.as_slice()), p.start_of(*sweep, iy, jx), "{} line {line}", sweep.name());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
