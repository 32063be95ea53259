//! Stability tools: one Newton orbit with its Floquet multipliers (`orbit`), and
//! one continuation with bifurcation location (`continue`), exact solver at
//! `standard`. Run with `cargo bench --bench stability`.

use criterion::{criterion_group, criterion_main, Criterion};
use solver::continuation::follow;
use solver::orbit::{natural_map, solve_orbit};
use solver::{orbit_of_cell, Accuracy, DVector, System};
use std::hint::black_box;
use std::time::Duration;

fn scene(file: &str) -> scene::Scene {
    let text = std::fs::read_to_string(format!("{}/configs/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    scene::Scene::parse(&text).unwrap()
}

fn bench_stability(c: &mut Criterion) {
    let acc = Accuracy::default();
    let mut g = c.benchmark_group("orbit");
    g.warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3)).sample_size(30);
    // Newton from the settled state perturbed by 1e-3: the work of `orbit` after its cell.
    for (name, file, sets) in [
        ("multi-stop-1-4-4", "multi-stop.toml", vec![("omega", 0.33), ("delta", 0.6)]),
        ("impact-damper-1-1-1-S", "impact-damper.toml", vec![("omega", 1.5), ("delta", 2.0), ("R", 0.8), ("v20", 2.0)]),
        ("dry-friction-1-1-1-S", "dry-friction.toml", vec![("omega", 7.5)]),
    ] {
        let overrides: Vec<(String, f64)> = sets.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        let sys = System::new(scene(file).evaluate(&overrides).unwrap()).unwrap();
        let orbit = orbit_of_cell(&sys, &acc, &sys.model.initial_state(), None).unwrap();
        let start: DVector<f64> = orbit.solution.x.map(|v| v * (1.0 + 1e-3));
        let map = natural_map(&sys, &acc, &orbit.solution.x, orbit.n);
        g.bench_function(name, |b| b.iter(|| black_box(solve_orbit(&sys, &acc, &start, map, orbit.n, None).unwrap())));
    }
    g.finish();

    let mut g = c.benchmark_group("continue");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    let damper = scene("impact-damper.toml");
    let base = [("delta", 2.0), ("R", 0.8), ("v20", 2.0)];
    let family = |v: f64| {
        let mut o: Vec<(String, f64)> = base.iter().map(|(k, x)| (k.to_string(), *x)).collect();
        o.push(("omega".into(), v));
        System::new(damper.evaluate(&o).ok()?).ok()
    };
    let values: Vec<f64> = (0..31).map(|i| 1.3 + 0.01 * i as f64).collect();
    let sys = family(values[0]).unwrap();
    let start = orbit_of_cell(&sys, &acc, &sys.model.initial_state(), None).unwrap();
    g.bench_function("impact-damper-omega-1.3-1.6-31-points-NS", |b| {
        b.iter(|| black_box(follow(&family, &acc, &values, start.clone())))
    });
    g.finish();
}

criterion_group!(benches, bench_stability);
criterion_main!(benches);
