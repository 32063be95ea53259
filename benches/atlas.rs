//! Atlas throughput on the reference plane of the multi-stop scene (64 x 64
//! cells over ω ∈ [0.1, 3.05], δ ∈ [0.05, 2]), fresh and both sweeps, on 1 and 2
//! threads, and both sweeps with every quantity of the steady motion measured
//! (`both-quantities`: their cost, docs/performance.md). Criterion reports time
//! per atlas; cells/s = 4096 (fresh) or 8192 (both) divided by it. Run with
//! `cargo bench --bench atlas`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use grid::{Along, Axis, CellSetup, Line, Plane, Quiet, SweepKind};
use solver::{Accuracy, Method};
use std::hint::black_box;
use std::time::Duration;

fn setup() -> CellSetup {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/multi-stop.toml")).unwrap();
    CellSetup {
        scene: scene::Scene::parse(&text).unwrap(),
        base: Vec::new(),
        accuracy: Accuracy::default(),
        method: Method::Exact,
        section_cap: 16,
        quantities: Vec::new(),
    }
}

fn bench_atlas(c: &mut Criterion) {
    let plain = setup();
    let system = plain.system(&[("omega".into(), 1.0), ("delta".into(), 1.0)]).unwrap();
    let measured = CellSetup { quantities: (0..solver::quantity::names(&system).len()).collect(), ..setup() };
    let plane = Plane::new(
        Axis::parse("omega=0.1:3.05:64", "--x").unwrap(),
        Axis::parse("delta=0.05:2:64", "--y").unwrap(),
        Along::X,
    )
    .unwrap();
    let mut g = c.benchmark_group("atlas64");
    g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(8));
    let both = || vec![SweepKind::Up, SweepKind::Down];
    for (name, sweeps, cs) in
        [("fresh", vec![SweepKind::Fresh], &plain), ("both", both(), &plain), ("both-quantities", both(), &measured)]
    {
        let jobs: Vec<(SweepKind, usize)> =
            (0..plane.lines()).flat_map(|l| sweeps.iter().map(move |&s| (s, l))).collect();
        g.throughput(Throughput::Elements((plane.cells() * sweeps.len()) as u64));
        for threads in [1, 2] {
            g.bench_with_input(BenchmarkId::new(name, format!("{threads}-threads")), &threads, |b, &t| {
                b.iter(|| {
                    let sink = |l: Line| {
                        black_box(l);
                    };
                    grid::run(&plane, cs, &jobs, &grid::Entries::default(), t, &Quiet, &sink).unwrap()
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench_atlas);
criterion_main!(benches);
