//! The names a user types, one table per enum (`scene::Named`, issue 63):
//! the Python package's type stubs offer exactly the library's names.

use scene::Named;
use std::collections::BTreeSet;

/// The quoted names of every `Literal[...]` that follows `key` in the stubs.
fn literals_after(stubs: &str, key: &str) -> Vec<Vec<String>> {
    stubs
        .match_indices(key)
        .filter_map(|(i, _)| {
            let rest = &stubs[i + key.len()..];
            let rest = rest.strip_prefix("Literal[")?;
            let inside = &rest[..rest.find(']')?];
            Some(inside.split(',').map(|n| n.trim().trim_matches('"').to_string()).collect())
        })
        .collect()
}

fn names<T: Named>() -> Vec<String> {
    T::ALL.iter().map(|v| v.name().to_string()).collect()
}

/// Every `Literal` of a named keyword in `__init__.pyi` lists the names of
/// its library enum, in the table's order: a value added to an enum and not
/// to the stubs (or the reverse) fails here. A bifurcation's kind is offered
/// in lower case (the library reads either case).
#[test]
fn the_python_stubs_offer_the_librarys_names() {
    let stubs = std::fs::read_to_string("crates/python/python/vibroatlas/__init__.pyi").unwrap();
    let lower = |v: Vec<String>| v.into_iter().map(|n| n.to_lowercase()).collect::<Vec<_>>();
    let expect: [(&str, Vec<String>); 8] = [
        ("Preset = ", names::<solver::Preset>()),
        ("Integrator = ", names::<solver::Method>()),
        ("Sweep = ", names::<grid::Sweeps>()),
        ("sweep: ", names::<grid::SweepKind>()),
        ("direction: ", names::<engine::Direction>()),
        ("along: ", names::<grid::Along>()),
        ("attractors_where: ", names::<engine::AttractorCells>()),
        ("kind: ", lower(names::<solver::Bifurcation>())),
    ];
    for (key, want) in expect {
        let found = literals_after(&stubs, key);
        assert!(!found.is_empty(), "no Literal after '{key}' in the stubs");
        let distinct: BTreeSet<&Vec<String>> = found.iter().collect();
        assert_eq!(distinct.into_iter().collect::<Vec<_>>(), vec![&want], "{key}");
    }
}
