//! Statements of the user pages that no other test reads, checked against
//! the sources and against what the program prints for the page's own
//! commands (an audit at the close of issue 44 found these pages had drifted:
//! a scene excerpt, the crates' dependencies, and the routes of three sweeps).

use crate::util::json_of;
use std::collections::BTreeSet;
use std::path::Path;

fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

/// The arguments (without `vibroatlas`) of the command that `page` shows
/// starting with `start`.
fn command<'a>(page: &'a str, start: &str) -> Vec<&'a str> {
    let line = page.lines().map(str::trim).find(|l| l.starts_with(start));
    line.unwrap_or_else(|| panic!("the page shows no `{start}`")).split_whitespace().skip(1).collect()
}

/// One point of a sweep's JSON: its value, `mass`'s label, its symmetry
/// (empty when none), λT (the largest Lyapunov exponent times the forcing
/// period; NaN when none) and its largest multiplier (NaN when none).
struct Point {
    value: f64,
    label: String,
    symmetry: String,
    lambda_t: f64,
    max_multiplier: f64,
}

fn points(json: &serde_json::Value, mass: &str) -> Vec<Point> {
    let text = |v: &serde_json::Value| v.as_str().unwrap_or("").to_string();
    json["points"]
        .as_array()
        .expect("a sweep's points")
        .iter()
        .map(|p| {
            let value = p["value"].as_f64().unwrap();
            Point {
                value,
                label: text(&p["labels"][mass]),
                symmetry: text(&p["symmetry"]),
                lambda_t: p["lyapunov"].as_f64().map_or(f64::NAN, |l| l * std::f64::consts::TAU / value),
                max_multiplier: p["max_multiplier"].as_f64().unwrap_or(f64::NAN),
            }
        })
        .collect()
}

/// The point at `value` (to rounding).
fn at(points: &[Point], value: f64) -> &Point {
    points.iter().find(|p| (p.value - value).abs() < 1e-9).unwrap_or_else(|| panic!("no point at {value}"))
}

/// The labels of the points in `[from, to]`, each once.
fn labels_on(points: &[Point], from: f64, to: f64) -> BTreeSet<&str> {
    points.iter().filter(|p| p.value >= from - 1e-9 && p.value <= to + 1e-9).map(|p| p.label.as_str()).collect()
}

/// The points for `mass` of the sweep that docs/models.md shows starting
/// with `start`, once the page is seen to say each of `claims`.
fn models_sweep(start: &str, mass: &str, claims: &[&str]) -> Vec<Point> {
    let page = read("docs/models.md");
    for claim in claims {
        says(&page, claim);
    }
    points(&json_of(&command(&page, start)), mass)
}

/// Every point in `[from, to]` is labelled `label`.
fn only(points: &[Point], from: f64, to: f64, label: &str) {
    assert_eq!(labels_on(points, from, to), BTreeSet::from([label]), "on [{from}, {to}]");
}

/// `text` with every run of whitespace one space: prose as it reads,
/// however its lines are wrapped.
fn flat(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn says(page: &str, text: &str) {
    assert!(flat(page).contains(text), "the page does not say: {text}");
}

/// docs/models.md, section 3: the impact damper's route at δ = 2, as the
/// page's sweep prints it.
#[test]
fn the_impact_dampers_route_is_as_the_models_page_says() {
    let p = models_sweep(
        "vibroatlas sweep configs/impact-damper.toml",
        "M2",
        &[
            "chaos from 1.56 to 1.68 (λT ≈ 0.54 at ω = 1.6), a 19-19-19 window at 1.69",
            "[1.70, 1.79] (at 1.78 the exponent over its first periods, λT ≈ 0.001, once read as weak chaos;",
            "shear, and the section points lie on one closed curve), and 1-1-1 from 1.80.",
            "at 1.80 (largest |μ| 0.992) the section repeats after 1 702 periods",
        ],
    );
    only(&p, 1.3, 1.54, "1-1-1");
    assert_eq!(at(&p, 1.55).label, "Q");
    only(&p, 1.56, 1.68, "C");
    assert!((at(&p, 1.6).lambda_t - 0.54).abs() < 0.005, "λT = {}", at(&p, 1.6).lambda_t);
    assert_eq!(at(&p, 1.69).label, "19-19-19");
    only(&p, 1.70, 1.79, "Q");
    assert!(at(&p, 1.78).lambda_t.abs() < 2e-4, "λT = {}", at(&p, 1.78).lambda_t);
    only(&p, 1.80, 1.9, "1-1-1");
    let mu = at(&p, 1.80).max_multiplier;
    assert!((mu - 0.992).abs() < 5e-4, "|μ| = {mu}");
}

/// docs/models.md, section 4: past the Neimark–Sacker point of the
/// symmetric stops, as the page's sweep prints it.
#[test]
fn the_symmetric_stops_past_their_ns_point_are_as_the_models_page_says() {
    let p = models_sweep(
        "vibroatlas sweep configs/symmetric-stops.toml",
        "M2",
        &[
            "the sweep finds a quasi-periodic motion at 1.705 and 1.71, and from 1.715 the orbit 1-0-0",
            "its points at t = kT lie on two arcs and their rotation number does not converge",
        ],
    );
    only(&p, 1.69, 1.70, "1-1-1");
    only(&p, 1.705, 1.71, "Q");
    only(&p, 1.715, 1.8, "1-0-0");
}

/// docs/models.md, section 2: the dry-friction sweep down from ω = 8, as
/// the page's sweep prints it (its windows, and where 1-2-2 begins).
#[test]
#[ignore = "slow: the full suite runs it"]
fn the_dry_friction_route_down_is_as_the_models_page_says() {
    let p = models_sweep(
        "vibroatlas sweep configs/dry-friction.toml --axis omega=8:1",
        "M1",
        &["windows of 2-4-2 and 1-2-1, 1-2-2 S from ω = 3.62 (AS from 3.24"],
    );
    let between = labels_on(&p, 3.63, 5.5);
    assert!(between.contains("2-4-2") && between.contains("1-2-1"), "{between:?}");
    assert!(p.iter().all(|q| q.label != "1-1-2"), "1-1-2 on the way down");
    assert_eq!(at(&p, 3.625).label, "C");
    assert_eq!((at(&p, 3.62).label.as_str(), at(&p, 3.62).symmetry.as_str()), ("1-2-2", "S"));
    assert_eq!((at(&p, 3.245).label.as_str(), at(&p, 3.245).symmetry.as_str()), ("1-2-2", "S"));
    assert_eq!((at(&p, 3.24).label.as_str(), at(&p, 3.24).symmetry.as_str()), ("1-2-2", "AS"));
}

/// docs/scenes.md: every line of its excerpt of `configs/multi-stop.toml`
/// (comments aside; the abbreviated description aside) is a line of the file.
#[test]
fn the_scenes_pages_excerpt_is_the_shipped_file() {
    let page = read("docs/scenes.md");
    let file = read("configs/multi-stop.toml");
    let bare = |l: &str| l.split(" #").next().unwrap_or("").trim().to_string();
    let lines: BTreeSet<String> = file.lines().map(bare).collect();
    let start = page.find("```toml\n").expect("the excerpt") + "```toml\n".len();
    let excerpt = &page[start..start + page[start..].find("```").unwrap()];
    let mut checked = 0;
    for line in excerpt.lines().map(bare).filter(|l| !l.is_empty() && !l.starts_with('#') && !l.contains('…')) {
        assert!(lines.contains(&line), "not a line of configs/multi-stop.toml: {line}");
        checked += 1;
    }
    assert!(checked > 10, "{checked} lines");
}

/// docs/architecture.md: "Exactly, from the `Cargo.toml` files", each
/// crate's dependencies among the workspace's libraries.
#[test]
fn the_architecture_pages_dependencies_are_the_cargo_files() {
    let flat = flat(&read("docs/architecture.md"));
    let from = flat.find("Exactly, from the `Cargo.toml` files:").expect("the sentence");
    let sentence = &flat[from..from + flat[from..].find("No library crate").unwrap()];
    let libraries = ["scene", "solver", "maps", "grid", "store", "render", "engine", "explore"];
    let names = |text: &str| -> BTreeSet<String> {
        text.split('`').skip(1).step_by(2).filter(|n| libraries.contains(n)).map(str::to_string).collect()
    };
    let mut seen = BTreeSet::new();
    for clause in sentence.split(';') {
        let clause = clause.trim().trim_start_matches("Exactly, from the `Cargo.toml` files:").trim();
        let Some(rest) = clause.strip_prefix('`') else { continue };
        let (krate, rest) = rest.split_once('`').unwrap();
        let listed = names(rest.split('(').next().unwrap());
        let manifest: toml::Table = read(&format!("crates/{krate}/Cargo.toml")).parse().unwrap();
        let actual: BTreeSet<String> = manifest["dependencies"]
            .as_table()
            .unwrap()
            .keys()
            .filter(|n| libraries.contains(&n.as_str()))
            .cloned()
            .collect();
        assert_eq!(listed, actual, "docs/architecture.md on {krate}");
        seen.insert(krate.to_string());
    }
    // Every crate but `scene`, which depends on none of them.
    let all: BTreeSet<String> =
        libraries.iter().filter(|&&n| n != "scene").chain(&["python"]).map(|s| s.to_string()).collect();
    assert_eq!(seen, all, "crates the sentence names");
}

/// docs/models.md's chaotic transient longer than the record: the single
/// stop it names is `C` at `standard` and with `chaos_check = 0`, and the
/// orbit it reaches at `precise`, each over the periods the page gives.
/// Where a change tells it at `standard`, the page must say so.
#[test]
fn models_chaotic_transient_is_what_cell_prints() {
    let page = read("docs/models.md");
    let said = "single stop with ζ = 1e-4, σ = 0.2 and r = 0.377368 at ω = 2.672414";
    let at = page.find(said).expect("the example");
    let text = page[at..at + 400].split_whitespace().collect::<Vec<_>>().join(" ");
    let scene = ["cell", "configs/single-stop.toml", "--json", "--set", "zeta=1e-4", "--set", "sigma=0.2"];
    let scene = [&scene[..], &["--set", "r=0.377368", "--set", "omega=2.672414"]].concat();
    for (extra, label, periods) in [
        (&[][..], "C", 321),
        (&["--accuracy", "chaos_check=0"][..], "C", 721),
        (&["--preset", "precise"][..], "40-28-0", 3310),
    ] {
        let v = json_of(&[&scene[..], extra].concat());
        assert_eq!(
            (v["labels"]["M"].as_str(), v["periods_simulated"].as_u64()),
            (Some(label), Some(periods)),
            "{extra:?}"
        );
        let shown = format!("{}", periods).replace("3310", "3 310");
        assert!(text.contains(&format!("`{label}`")) && text.contains(&shown), "{label} over {shown}: {text}");
    }
}

/// Issue 60: docs/models.md section 13 runs its command and quotes what it
/// prints: every `"name": value` the section quotes is the value of
/// `quantities` (bit for bit, as JSON prints it), and its attenuation in dB is
/// 20 log₁₀ of M1's amplitude over the closed-form bare primary's at the
/// scene's ω and ζ, to the digits shown.
#[test]
fn models_quantities_are_what_cell_prints() {
    let page = read("docs/models.md");
    let section = &page[page.find("## 13. Quantities of the steady motion").expect("section 13")..];
    let json = json_of(&command(section, "vibroatlas cell configs/impact-damper.toml"));
    let q = &json["quantities"];
    let mut quoted = 0;
    for piece in section.split("`\"").skip(1) {
        let Some((name, rest)) = piece.split_once("\": ") else { continue };
        let value: f64 = rest.split('`').next().unwrap().parse().unwrap();
        assert_eq!(q[name].as_f64(), Some(value), "{name}");
        quoted += 1;
    }
    assert!(quoted >= 4, "{quoted} values quoted");
    let a = q["max_abs_x_M1"].as_f64().unwrap();
    let bare = solver::reference::free_amplitude(1.5, 0.1);
    assert!(section.contains(&format!("= {bare:.6}")), "the bare amplitude {bare:.6}");
    let db = format!("{:.2}", 20.0 * (a / bare).log10()).replace('-', "−");
    assert!(section.contains(&format!("= {db} dB")), "{db} dB");
}

/// Issue 60: docs/scenes.md's `[quantities]` section: its TOML is the
/// damper scene's table, and its commands print the lines it quotes.
#[test]
fn the_scenes_quantities_section_is_what_the_program_prints() {
    let page = read("docs/scenes.md");
    let section = &page[page.find("## `[quantities]`").expect("the section")..page.find("## Limits").unwrap()];
    let scene = read("configs/impact-damper.toml");
    let table = section.lines().find(|l| l.starts_with("attenuation = {")).expect("the table");
    assert!(scene.lines().any(|l| l == table), "{table}");
    let d = crate::util::scratch("scenes-quantities");
    let file = d.join("damper.h5");
    let mut atlas = command(section, "vibroatlas atlas configs/impact-damper.toml");
    let at = atlas.iter().position(|a| *a == "damper.h5").unwrap();
    atlas[at] = file.to_str().unwrap();
    atlas.push("--quiet");
    crate::util::ok(&atlas);
    let shown = command(section, "vibroatlas inspect damper.h5");
    assert_eq!(shown, ["inspect", "damper.h5", "--quantity", "attenuation"]);
    let out = crate::util::run(&["inspect", file.to_str().unwrap(), "--quantity", "attenuation"]);
    assert!(out.status.success());
    let out = String::from_utf8(out.stdout).unwrap();
    for line in out.lines() {
        assert!(section.lines().any(|l| l == line), "the page does not say: {line}");
    }
    assert_eq!(out.lines().count(), 3, "{out}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 65: docs/python.md's dict scene drops the stop between the masses
/// and gives each mass its one stop as p (it gave a mass the same stop as p
/// and q, counting every impact twice). The same scene as TOML, through the
/// CLI, prints the labels the page quotes.
#[test]
fn pythons_dict_scene_counts_each_impact_once() {
    let page = read("docs/python.md");
    let line = page.lines().find(|l| l.starts_with("scene[\"labels\"] =")).expect("the page relabels the scene");
    assert!(line.contains(r#"{"M1": {"p": "A1"}, "M2": {"p": "A2"}}"#), "{line}");
    let quoted = page.lines().find(|l| l.starts_with("va.cell(scene, omega=0.5)[\"labels\"]")).unwrap();
    let text = read("configs/multi-stop.toml");
    let (head, labels) = text.split_at(text.find("[[stops]]\nname = \"A12\"").expect("the A12 stop"));
    assert!(labels.contains("[labels.M1]"), "the labels follow A12");
    let scene = format!("{head}[labels.M1]\np = \"A1\"\n\n[labels.M2]\np = \"A2\"\n");
    let d = crate::util::scratch("python-dict-scene");
    let path = d.join("two-stops.toml");
    std::fs::write(&path, scene).unwrap();
    let cell = json_of(&["cell", path.to_str().unwrap(), "--set", "omega=0.5", "--json"]);
    let (m1, m2) = (cell["labels"]["M1"].as_str().unwrap(), cell["labels"]["M2"].as_str().unwrap());
    assert!(quoted.ends_with(&format!("# {{'M1': '{m1}', 'M2': '{m2}'}}")), "{quoted} against {m1}, {m2}");
    assert_eq!(cell["impacts"]["A1"].as_u64(), m1.split('-').nth(1).unwrap().parse().ok());
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 65: docs/scenes.md said figures draw a symbol's `_k` as plain text;
/// they draw it as a subscript, and the page now says so.
#[test]
fn scenes_page_says_subscripts_are_drawn() {
    let page = read("docs/scenes.md").split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(!page.contains("figures draw plain text"));
    assert!(page.contains("figures and the explorer draw what follows `_` as a subscript"));
    let runs = render::subscript_runs("μ_k");
    assert_eq!(runs, vec![("μ", false), ("k", true)]);
}

/// Issue 66: docs/basins.md prints what its `basins` commands print, line
/// for line (the files they write go to a scratch folder), and its Python
/// block reads the file the first one writes.
#[test]
#[ignore = "slow: the full suite runs it"]
fn the_basins_page_prints_what_basins_prints() {
    let page = read("docs/basins.md");
    let d = crate::util::scratch("docs-basins");
    std::fs::create_dir_all(d.join("out")).unwrap();
    std::fs::create_dir_all(d.join("img")).unwrap();
    let here = |t: &str| {
        t.replace("out/", &format!("{}/out/", d.display())).replace("docs/img/", &format!("{}/img/", d.display()))
    };
    let mut shown = 0;
    for block in page.split("```sh\n").skip(1) {
        let (commands, rest) = block.split_once("```").unwrap();
        let Some(cmd) = commands.lines().find(|l| l.starts_with("vibroatlas basins")) else { continue };
        let text = rest.split_once("```text\n").unwrap().1.split_once("```").unwrap().0;
        let cmd = here(cmd);
        let args: Vec<&str> = cmd.split_whitespace().skip(1).collect();
        let out = crate::util::run(&args);
        assert!(out.status.success(), "{cmd}: {}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(String::from_utf8_lossy(&out.stdout), here(text), "{cmd}");
        // A map with chaotic starts under the chaos check says they may be transients.
        let warned = String::from_utf8_lossy(&out.stderr).contains("warning: some starts end chaotic");
        assert_eq!(warned, text.contains(" C  chaotic") && !cmd.contains("precise"), "{cmd}");
        shown += 1;
    }
    assert_eq!(shown, 3, "the page shows three basins commands");
    let python = page.split("```python\n").nth(1).unwrap().split_once("```").unwrap().0;
    let out = std::process::Command::new("/usr/bin/python3").args(["-c", python]).current_dir(&d).output().unwrap();
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{printed}{}", String::from_utf8_lossy(&out.stderr));
    assert!(printed.contains("['1-0-0', '2-1-0'] [0.6582 0.3418]"), "{printed}");
    // The atlas of attractor families, its map, and what xarray reads of it.
    let section = &page[page.find("## Attractors across the plane").expect("the families' section")..];
    for start in ["vibroatlas atlas configs/impact-damper.toml", "vibroatlas render out/damper-attractors.h5"] {
        let cmd = here(section.lines().find(|l| l.starts_with(start)).unwrap());
        let out = crate::util::run(&cmd.split_whitespace().skip(1).collect::<Vec<_>>());
        assert!(out.status.success(), "{cmd}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let block = section.split("```python\n").nth(1).unwrap();
    let (python, rest) = block.split_once("```").unwrap();
    let shown = rest.split_once("```text\n").unwrap().1.split_once("```").unwrap().0;
    let out = std::process::Command::new("/usr/bin/python3").args(["-c", python]).current_dir(&d).output().unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout), shown, "{}", String::from_utf8_lossy(&out.stderr));
    let (some, most) = shown.trim().split_once(' ').unwrap();
    says(section, &format!("{some} of the 1 152 cells hold it, and in {most} it attracts more than half"));
}

/// docs/file-format.md, section 1: the text attributes `attributes_crc32`
/// covers are those the writer's checksum covers, every one named.
#[test]
fn the_file_formats_checked_texts_are_the_writers() {
    let page = flat(&read("docs/file-format.md"));
    let from =
        page.find("The names it covers:").expect("the page lists the covered names") + "The names it covers:".len();
    let list = &page[from..from + page[from..].find(". A text attribute").unwrap()];
    let named: BTreeSet<&str> = list.split('`').skip(1).step_by(2).collect();
    let covered: BTreeSet<&str> = store::layout::attr::CHECKED_TEXTS.iter().copied().collect();
    assert_eq!(named, covered, "the names docs/file-format.md lists");
}
