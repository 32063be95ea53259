//! Hot paths: one multi-stop cell per regime (no impact, 1-1-1, 1-4-4,
//! chattering, sticking) with the exact solver at `standard`, and one
//! continuation chain of 64 cells; dry-friction cells at ω = 2, 5, 7.5 (fk = 0.01).
//! Run with `cargo bench --bench regimes`.

use criterion::{criterion_group, criterion_main, Criterion};
use grid::{chain, CellSetup, Quiet};
use solver::reference::REGIMES_MULTI_STOP;
use solver::{run_cell, Accuracy, Method, System};
use std::hint::black_box;
use std::time::Duration;

fn scene(file: &str) -> scene::Scene {
    let text = std::fs::read_to_string(format!("{}/configs/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    scene::Scene::parse(&text).unwrap()
}

fn bench_regimes(c: &mut Criterion) {
    let sc = scene("multi-stop.toml");
    let acc = Accuracy::default();
    let mut g = c.benchmark_group("regime");
    g.warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2)).sample_size(30);
    for (name, omega, delta) in REGIMES_MULTI_STOP {
        let sys = System::new(sc.evaluate(&[("omega".into(), omega), ("delta".into(), delta)]).unwrap()).unwrap();
        let y0 = sys.model.initial_state();
        g.bench_function(name, |b| b.iter(|| black_box(run_cell(&sys, &acc, Method::Exact, &y0))));
    }
    g.finish();

    let friction = scene("dry-friction.toml");
    let mut g = c.benchmark_group("dry-friction");
    g.warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3)).sample_size(20);
    for omega in [2.0, 5.0, 7.5] {
        let sys = System::new(friction.evaluate(&[("omega".into(), omega)]).unwrap()).unwrap();
        let y0 = sys.model.initial_state();
        g.bench_function(format!("omega-{omega}"), |b| b.iter(|| black_box(run_cell(&sys, &acc, Method::Exact, &y0))));
    }
    g.finish();

    let setup = CellSetup {
        scene: sc,
        base: vec![("delta".into(), 0.6)],
        accuracy: acc,
        method: Method::Exact,
        section_cap: 16,
        quantities: Vec::new(),
    };
    let points: Vec<Vec<(String, f64)>> =
        (0..64).map(|i| vec![("omega".to_string(), 0.25 + 0.15 * i as f64 / 63.0)]).collect();
    let mut g = c.benchmark_group("chain");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    g.bench_function("64-cells-omega-0.25-0.4", |b| b.iter(|| black_box(chain(&setup, &points, &Quiet).unwrap())));
    g.finish();
}

criterion_group!(benches, bench_regimes);
criterion_main!(benches);
