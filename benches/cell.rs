//! Time of one `cell` (simulate + classify from the scene's initial state) on the
//! multi-stop scene, for the exact solver at each preset and for RK4 at the
//! literature's step h = 0.01. Run with `cargo bench --bench cell`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use solver::{run_cell, Accuracy, Method, Preset, System};
use std::hint::black_box;
use std::time::Duration;

/// (ω, δ) cells of the issue: 1-4-4 chattering-free impacts, a no-impact cell, and a high-ω impact cell.
const CELLS: [(f64, f64); 3] = [(0.3, 0.6), (1.0, 1.2), (2.5, 0.6)];

fn system(omega: f64, delta: f64) -> System {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/multi-stop.toml")).unwrap();
    let scene = scene::Scene::parse(&text).unwrap();
    let model = scene.evaluate(&[("omega".into(), omega), ("delta".into(), delta)]).unwrap();
    System::new(model).unwrap()
}

fn bench_cells(c: &mut Criterion) {
    let mut g = c.benchmark_group("cell");
    g.warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2)).sample_size(20);
    for &(omega, delta) in &CELLS {
        let sys = system(omega, delta);
        let y0 = sys.model.initial_state();
        for (name, method, preset) in [
            ("exact-fast", Method::Exact, Preset::Fast),
            ("exact-standard", Method::Exact, Preset::Standard),
            ("exact-precise", Method::Exact, Preset::Precise),
            ("rk4-h0.01", Method::Rk4, Preset::Standard),
        ] {
            let acc = Accuracy::preset(preset);
            g.bench_with_input(BenchmarkId::new(name, format!("w{omega}-d{delta}")), &acc, |b, acc| {
                b.iter(|| black_box(run_cell(&sys, acc, method, &y0)))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench_cells);
criterion_main!(benches);
