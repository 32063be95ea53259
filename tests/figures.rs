//! Issue 17: figures a paper can print. Colours read back from rendered PNGs
//! at known cells, SVG parsed as XML, PDF headers, titles that match what was
//! run.

use crate::util::{ok, run, scratch};
use scene::Named;
use std::path::Path;

/// RGB rows of a PNG.
fn pixels(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let step = info.line_size / info.width as usize;
    let px = (0..(info.width * info.height) as usize).map(|i| [buf[i * step], buf[i * step + 1], buf[i * step + 2]]);
    (info.width as usize, info.height as usize, px.collect())
}

/// The colour that most of a 9 x 9 block around (x, y) has.
fn sample(img: &(usize, usize, Vec<[u8; 3]>), x: usize, y: usize) -> [u8; 3] {
    let mut counts = std::collections::BTreeMap::new();
    for j in y - 4..=y + 4 {
        for i in x - 4..=x + 4 {
            *counts.entry(img.2[j * img.0 + i]).or_insert(0) += 1;
        }
    }
    counts.into_iter().max_by_key(|e| e.1).unwrap().0
}

/// Pixel centre of cell (ix, iy) of a 2 x 2 single-panel map (1140 x 800): the
/// plot spans about x 70..740 and y 75..717 (cells of about 335 x 320 pixels,
/// so the estimate has a wide margin).
fn centre(ix: usize, iy: usize) -> (usize, usize) {
    (70 + 167 + 335 * ix, 717 - 160 - 320 * iy)
}

#[test]
fn a_label_has_the_same_colour_in_every_sweep_and_file() {
    let d = scratch("colours");
    let (a, b) = (d.join("a.h5"), d.join("b.h5"));
    // Two files with labels in common (2 x 2 cells each, in different places).
    ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.33:2.5:2",
        "--y",
        "delta=0.6:1.2:2",
        "--sweep",
        "both",
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=1.0:2.5:2",
        "--y",
        "delta=0.6:1.6:2",
        "--sweep",
        "both",
        "--quiet",
        "-o",
        b.to_str().unwrap(),
    ]);
    let mut seen: std::collections::BTreeMap<String, [u8; 3]> = Default::default();
    for (file, sweep) in [(&a, "up"), (&a, "down"), (&b, "up"), (&b, "down")] {
        let png = d.join(format!("{}-{sweep}.png", file.file_stem().unwrap().to_string_lossy()));
        ok(&["render", file.to_str().unwrap(), "--sweep", sweep, "-o", png.to_str().unwrap()]);
        let img = pixels(&png);
        assert_eq!((img.0, img.1), (1140, 800));
        let atlas = store::read(file).unwrap().atlas;
        let map = atlas.map(grid::SweepKind::parse(sweep).unwrap()).unwrap();
        for iy in 0..2 {
            for ix in 0..2 {
                let label = map.cells[iy * 2 + ix].as_ref().unwrap().labels[0];
                let (x, y) = centre(ix, iy);
                let got = sample(&img, x, y);
                assert_eq!(got, grid::palette::colour(label), "{png:?} cell ({ix}, {iy}) {label}");
                if let Some(before) = seen.insert(label.to_string(), got) {
                    assert_eq!(before, got, "{label} changed colour");
                }
            }
        }
    }
    assert!(seen.len() >= 2, "labels seen: {seen:?}");
}

#[test]
fn vector_formats_are_valid_and_unknown_ones_refused() {
    let d = scratch("vector");
    let a = d.join("a.h5");
    ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.3:2.5:6",
        "--y",
        "delta=0.4:1.2:4",
        "--sweep",
        "both",
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    let svg = d.join("map.svg");
    ok(&["render", a.to_str().unwrap(), "--sweep", "hysteresis", "-o", svg.to_str().unwrap()]);
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("SVG parses as XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    assert!(doc.descendants().filter(|n| n.has_tag_name("rect")).count() >= 3 * 24, "three panels of 24 cells");
    let pdf = d.join("map.pdf");
    ok(&["render", a.to_str().unwrap(), "--view", "lyapunov", "--sweep", "up", "-o", pdf.to_str().unwrap()]);
    assert!(std::fs::read(&pdf).unwrap().starts_with(b"%PDF"));
    let out = run(&["render", a.to_str().unwrap(), "-o", d.join("map.jpg").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("unknown picture format '.jpg'") && err.trim().lines().count() == 1, "{err}");
    assert!(!d.join("map.jpg").exists());
}

#[test]
fn diagrams_say_which_directions_were_run() {
    let d = scratch("diagram");
    let svg = d.join("down.svg");
    let out = run(&[
        "sweep",
        "configs/dry-friction.toml",
        "--axis",
        "omega=8:6.5:16",
        "--set",
        "fk=0.01",
        "--direction",
        "down",
        "--quiet",
        "--png",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let words: Vec<&str> = doc.descendants().filter_map(|n| n.text()).collect();
    let title = words.iter().find(|t| t.contains("bifurcation diagram")).expect("a title");
    assert!(title.contains("down sweep") && !title.contains("up"), "{title}");
    // Both directions, from a stored sweep file, with its legend.
    let file = d.join("both.h5");
    let out = run(&[
        "sweep",
        "configs/dry-friction.toml",
        "--axis",
        "omega=6.5:8:16",
        "--set",
        "fk=0.01",
        "--direction",
        "both",
        "--quiet",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let svg = d.join("both.svg");
    ok(&["render", file.to_str().unwrap(), "-o", svg.to_str().unwrap(), "--variable", "v_M1", "--impact", "phase"]);
    let text = std::fs::read_to_string(&svg).unwrap();
    for want in ["up and down sweeps", "up sweep", "down sweep", "impact phase"] {
        assert!(text.contains(want), "{want} missing");
    }
    // Its panels, stacked, share the swept axis: named once, under the lowest.
    let doc = roxmltree::Document::parse(&text).unwrap();
    let texts: Vec<&str> = doc.descendants().filter(|n| n.is_text()).filter_map(|n| n.text()).map(str::trim).collect();
    let panels = texts.iter().filter(|t| t.starts_with("impact phase") || t.ends_with("at t = kT")).count();
    assert!(panels >= 2, "{texts:?}");
    assert_eq!(texts.iter().filter(|t| **t == "ω").count(), 1, "{texts:?}");
    // v_M1 written v with the subscript M1, drawn smaller.
    let size = |t: &str| {
        let node = doc.descendants().find(|n| n.is_element() && n.text().map(str::trim) == Some(t)).unwrap();
        node.attribute("font-size").and_then(|s| s.trim_end_matches("px").parse::<f64>().ok()).unwrap()
    };
    let at = texts.iter().position(|t| *t == "at t = kT").expect("the period panel's axis");
    assert_eq!(texts[..at].iter().rev().filter(|t| !t.is_empty()).take(2).collect::<Vec<_>>(), [&"M1", &"v"]);
    assert!(size("M1") < size("v"), "{} {}", size("M1"), size("v"));
}

/// Issue 20: a curve file is self-describing (read back equal to the curve's
/// JSON) and is drawn over the map of an atlas of the same plane; a curve of
/// another plane is refused.
#[test]
fn curves_are_stored_and_drawn_over_maps() {
    let d = scratch("curves");
    let (c, a) = (d.join("pf.h5"), d.join("df.h5"));
    let j = crate::util::json_of(&crate::util::pitchfork("0.05", "4", &["--json", "-o", c.to_str().unwrap()]));
    let curve = store::read_curves(&c).unwrap().remove(0);
    assert_eq!((curve.kind.as_str(), curve.free.clone()), ("PF", ["omega".to_string(), "fk".to_string()]));
    let points = j["points"].as_array().unwrap();
    assert_eq!(curve.points.len(), points.len());
    for (p, q) in curve.points.iter().zip(points) {
        assert_eq!((p.0, p.1), (q["omega"].as_f64().unwrap(), q["fk"].as_f64().unwrap()));
    }
    ok(&[
        "atlas",
        "configs/dry-friction.toml",
        "--x",
        "omega=6.6:7:6",
        "--y",
        "fk=0.005:0.06:4",
        "--sweep",
        "down",
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    let png = d.join("overlay.png");
    ok(&["render", a.to_str().unwrap(), "--curves", c.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert!(png.exists());
    let other = d.join("other.h5");
    ok(&[
        "atlas",
        "configs/dry-friction.toml",
        "--x",
        "omega=6.6:7:3",
        "--y",
        "b=0.02:0.04:2",
        "--quiet",
        "-o",
        other.to_str().unwrap(),
    ]);
    let out = run(&[
        "render",
        other.to_str().unwrap(),
        "--curves",
        c.to_str().unwrap(),
        "-o",
        d.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is a curve in (omega, fk)"));
}

/// Issue 20: `curves` seeds curves where neighbouring labels of a stored map
/// differ, follows them row by row, and writes a file `render --curves` draws;
/// the same atlas gives the same curves.
#[test]
#[ignore = "slow: the full suite runs it"]
fn curves_are_found_on_a_map() {
    let d = scratch("curves-map");
    let a = d.join("a.h5");
    ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.6:1.6:24",
        "--y",
        "delta=1.2:2:8",
        "--sweep",
        "up",
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    let (c1, c2) = (d.join("c1.h5"), d.join("c2.h5"));
    for (c, threads) in [(&c1, "1"), (&c2, "2")] {
        ok(&["curves", a.to_str().unwrap(), "--max", "3", "--threads", threads, "-o", c.to_str().unwrap()]);
    }
    let (one, two) = (store::read_curves(&c1).unwrap(), store::read_curves(&c2).unwrap());
    assert_eq!(one, two, "the same curves on one thread and two");
    assert!(!one.is_empty() && one.iter().all(|c| c.points.len() >= 3), "{one:?}");
    let png = d.join("map.png");
    ok(&["render", a.to_str().unwrap(), "--curves", c1.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    // Stored into the atlas: the same curves, every other dataset as it was.
    let before = store::read(&a).unwrap();
    ok(&["curves", a.to_str().unwrap(), "--max", "3", "--into"]);
    assert_eq!(store::read_curves(&a).unwrap(), one);
    assert_eq!(store::read(&a).unwrap().atlas, before.atlas);
    ok(&["render", a.to_str().unwrap(), "--curves", a.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    // Stored again: replaced, not added.
    ok(&["curves", a.to_str().unwrap(), "--max", "2", "--into"]);
    assert_eq!(store::read_curves(&a).unwrap(), one[..2].to_vec());
    let err = crate::util::run(&["curves", a.to_str().unwrap(), "--max", "2"]);
    assert!(!err.status.success() && String::from_utf8_lossy(&err.stderr).contains("--into"));
}

/// Issue 64: `curves` over a stored map places every grazing it traces on
/// a closed-form grazing line to 1e-9, at the root of the orbit's grazing
/// margin (a bisection on where Newton's method stops converging fell
/// 1e-8–1e-5 short). The lines:
/// - single stop (ζ = 0.05): the non-impacting orbit's amplitude
///   σ = 1/|1 − ω² + 2iζω|;
/// - gear pair (fm = 0.1, k = 1, ζ = 0.05): the mesh keeps contact while
///   its amplitude is below the mean deflection, f1 = fm |k − ω² + 2iζω| / k.
///
/// A curve's point is on the line where it lies within 1e-5 of it; at
/// least 5 such points are asked of each map.
#[test]
#[ignore = "slow: the full suite runs it"]
fn curves_place_grazings_on_closed_forms() {
    let single = |w: f64| 1.0 / (1.0 - w * w).hypot(0.1 * w);
    grazings_on_line("single-stop.toml", ["omega=0.5:3:25", "sigma=-1:1.5:20"], &["--set", "zeta=0.05"], single);
    let gear = |w: f64| 0.1 * (1.0 - w * w).hypot(0.1 * w);
    grazings_on_line("gear-backlash.toml", ["omega=0.3:2:24", "f1=0.05:0.35:16"], &[], gear);
}

/// The grazing curves `curves` finds over an up sweep of `scene` on the
/// plane `axes`: at least 5 of their points lie within 1e-5 of `line` (the
/// second parameter as a function of ω), and those within 1e-9.
fn grazings_on_line(scene: &str, [x, y]: [&str; 2], extra: &[&str], line: impl Fn(f64) -> f64) {
    let d = scratch(&format!("curves-closed-form-{scene}"));
    let (a, c) = (d.join("atlas.h5"), d.join("curves.h5"));
    let path = format!("configs/{scene}");
    let mut args = vec!["atlas", &path, "--x", x, "--y", y, "--sweep", "up", "--quiet", "-o", a.to_str().unwrap()];
    args.extend_from_slice(extra);
    ok(&args);
    ok(&["curves", a.to_str().unwrap(), "--kinds", "grazing", "--max", "4", "-o", c.to_str().unwrap()]);
    let offs: Vec<f64> = store::read_curves(&c)
        .unwrap()
        .iter()
        .flat_map(|curve| curve.points.iter().map(|&(w, b)| (b - line(w)).abs()))
        .filter(|off| *off < 1e-5)
        .collect();
    let worst = offs.iter().copied().fold(0.0, f64::max);
    assert!(
        offs.len() >= 5 && worst < 1e-9,
        "{scene}: {} points on the line, the farthest {worst:.2e} off it",
        offs.len()
    );
}

/// Issue 64: `curves --json` lists each curve's codimension-two points,
/// typed and placed by the free parameters' names: the points of the file it
/// writes, in order, and as many as it counts.
#[test]
fn curves_json_lists_the_typed_codimension_two_points() {
    let d = scratch("curves-json-codim2");
    let (a, c) = (d.join("atlas.h5"), d.join("curves.h5"));
    let (a, c) = (a.to_str().unwrap(), c.to_str().unwrap());
    let grid = ["--x", "omega=2:3.5:12", "--y", "sigma=-0.5:0.5:10", "--set", "zeta=0.05", "--quiet", "-o", a];
    ok(&[&["atlas", "configs/single-stop.toml"][..], &grid].concat());
    let out = run(&["curves", a, "--max", "3", "--json", "-o", c]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let listed = json["curves"].as_array().unwrap();
    let stored = store::read_curves(std::path::Path::new(c)).unwrap();
    assert_eq!(listed.len(), stored.len());
    for (l, s) in listed.iter().zip(&stored) {
        let points = l["codim2_points"].as_array().unwrap();
        assert_eq!(l["codim2"].as_u64().unwrap() as usize, points.len(), "{l}");
        let read: Vec<(String, f64, f64)> = points
            .iter()
            .map(|p| (p["kind"].as_str().unwrap().into(), p["omega"].as_f64().unwrap(), p["sigma"].as_f64().unwrap()))
            .collect();
        assert_eq!(read, s.codim2, "{l}");
    }
    let kinds: Vec<&str> = listed
        .iter()
        .flat_map(|l| l["codim2_points"].as_array().unwrap())
        .map(|p| p["kind"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"PD-grazing"), "{json}");
}

/// Issue 43: a legend writes a state variable as the axes do, `x` with the
/// subscript `M1` drawn smaller (the portrait's time series named its lines
/// `x_M1`, underscore and all).
#[test]
fn legends_draw_subscripts() {
    let d = scratch("legend-subscripts");
    let svg = d.join("portrait.svg");
    ok(&["cell", "configs/multi-stop.toml", "--set", "omega=0.33", "--portrait", svg.to_str().unwrap()]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(!text.contains("x_M1") && !text.contains("x_M2"), "an underscore drawn");
    let doc = roxmltree::Document::parse(&text).unwrap();
    let texts: Vec<roxmltree::Node> =
        doc.descendants().filter(|n| n.is_element() && n.text().is_some_and(|t| !t.trim().is_empty())).collect();
    let size =
        |n: &roxmltree::Node| n.attribute("font-size").and_then(|s| s.trim_end_matches("px").parse::<f64>().ok());
    // The legend's "event" row follows its two lines' names, each an x then
    // its subscript.
    let event = texts.iter().position(|n| n.text().map(str::trim) == Some("event")).expect("the legend");
    let names: Vec<&str> = texts[event - 4..event].iter().filter_map(|n| n.text()).map(str::trim).collect();
    assert_eq!(names, ["x", "M1", "x", "M2"], "{names:?}");
    assert!(size(&texts[event - 3]) < size(&texts[event - 4]), "the subscript drawn smaller");
}

/// Issue 65: `cell` names every file it writes in a `wrote` line, as every
/// other command does (the trace, the portrait, the sections); with `--json`
/// its standard output stays one JSON object.
#[test]
fn cell_names_every_file_it_writes() {
    let d = scratch("cell-wrote");
    let (trace, portrait, sections) = (d.join("t.csv"), d.join("p.svg"), d.join("s.png"));
    let files = [trace.to_str().unwrap(), portrait.to_str().unwrap(), sections.to_str().unwrap()];
    let args = ["cell", "configs/multi-stop.toml", "--set", "omega=0.33", "--section-periods", "50"];
    let writes = ["--trace", files[0], "--portrait", files[1], "--section-png", files[2]];
    let out = run(&[&args[..], &writes[..], &["--size", "single"]].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains(&format!("wrote {}\n", files[0])), "{text}");
    assert!(text.contains(&format!("wrote {} (86 mm wide)", files[1])), "{text}");
    assert!(text.contains(&format!("wrote {} (86 mm wide)", files[2])), "{text}");
    assert!(files.iter().all(|f| Path::new(f).exists()));
    let out = run(&[&args[..], &writes[..], &["--json"]].concat());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(json["labels"]["M1"], "1-4-4");
}
