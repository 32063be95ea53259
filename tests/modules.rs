//! Issue 63: no module of a crate imports one that imports it back. Each
//! crate's top-level modules (`src/NAME.rs` or `src/NAME/`) and the
//! `crate::NAME` paths their code names (comments and test modules aside)
//! make a graph that must have no circle, but for the edges named in
//! [`ALLOWED`] with their reason.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Edges `(crate, from, to)` left in place, each for a stated reason:
/// `System::new` resolves the quantities a scene defines (their operands'
/// names are the built-in quantities', which the motion's measurement
/// declares), so that a bad expression is refused when the system is built.
const ALLOWED: [(&str, &str, &str); 1] = [("solver", "system", "quantity")];

/// The code of a file: its lines that are not comments, up to its inline
/// test module (`#[cfg(test)] mod tests { … }`, last in the file; a test
/// module of its own file, `tests.rs`, is skipped by [`sources`]).
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]\nmod tests {").next().unwrap_or_default();
    text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// Every `.rs` file under `dir`, with its text.
fn sources(dir: &Path, into: &mut String) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            sources(&p, into);
        } else if p.extension().is_some_and(|e| e == "rs") && !p.ends_with("tests.rs") {
            into.push_str(&code(&std::fs::read_to_string(&p).unwrap()));
        }
    }
}

/// The modules of a crate's `src` and the modules each one names.
fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut texts = BTreeMap::new();
    for e in std::fs::read_dir(src).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_stem().unwrap().to_str().unwrap().to_string();
        if ["lib", "main"].contains(&name.as_str()) {
            continue;
        }
        let mut text = String::new();
        match p.is_dir() {
            true => sources(&p, &mut text),
            false if p.extension().is_some_and(|e| e == "rs") => text = code(&std::fs::read_to_string(&p).unwrap()),
            false => continue,
        }
        texts.entry(name).or_insert_with(String::new).push_str(&text);
    }
    let names: BTreeSet<String> = texts.keys().cloned().collect();
    texts
        .iter()
        .map(|(m, text)| {
            let named = text
                .match_indices("crate::")
                .map(|(at, _)| {
                    let rest = &text[at + 7..];
                    rest[..rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len())]
                        .to_string()
                })
                .filter(|n| names.contains(n) && n != m)
                .collect();
            (m.clone(), named)
        })
        .collect()
}

/// A circle through `from`, if there is one: the path back to it.
fn circle(g: &BTreeMap<String, BTreeSet<String>>, from: &str) -> Option<Vec<String>> {
    let mut stack = vec![vec![from.to_string()]];
    let mut seen = BTreeSet::new();
    while let Some(path) = stack.pop() {
        for next in &g[path.last().unwrap()] {
            if next == from {
                return Some([path.clone(), vec![from.to_string()]].concat());
            }
            if seen.insert(next.clone()) {
                stack.push([path.clone(), vec![next.clone()]].concat());
            }
        }
    }
    None
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates");
    let mut circles = Vec::new();
    for krate in std::fs::read_dir(&crates).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()) {
        let mut g = graph(&crates.join(&krate).join("src"));
        for (c, from, to) in ALLOWED.iter().filter(|a| a.0 == krate) {
            assert!(g[*from].contains(*to), "{c}: {from} no longer names {to}: take it off ALLOWED");
            g.get_mut(*from).unwrap().remove(*to);
        }
        circles.extend(g.keys().filter_map(|m| circle(&g, m)).map(|c| format!("{krate}: {}", c.join(" → "))));
    }
    assert!(circles.is_empty(), "import circles:\n{}", circles.join("\n"));
}

/// The check sees a circle where there is one (the engine's error and its
/// scenes named each other until issue 63).
#[test]
fn a_circle_is_seen() {
    let g: BTreeMap<String, BTreeSet<String>> = [("error", "sim"), ("sim", "error"), ("lib2", "error")]
        .iter()
        .map(|(a, b)| (a.to_string(), BTreeSet::from([b.to_string()])))
        .chain([("x".to_string(), BTreeSet::new())])
        .collect();
    let mut g = g;
    g.entry("sim".into()).or_default();
    assert_eq!(circle(&g, "error"), Some(vec!["error".into(), "sim".into(), "error".into()]));
    assert_eq!(circle(&g, "lib2"), None);
    // The code after a `mod tests;` line counts; an inline test module does not.
    assert_eq!(
        code("use crate::a;\n// crate::b\n#[cfg(test)]\nmod tests;\nuse crate::d;\n#[cfg(test)]\nmod tests {\nuse crate::c;\n}"),
        "use crate::a;\n#[cfg(test)]\nmod tests;\nuse crate::d;"
    );
}
