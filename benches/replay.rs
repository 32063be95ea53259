//! Lab tooling, not shipped: predicts the makespan and parallel efficiency of
//! an atlas run on many cores by replaying the scheduler's policy, current and
//! previous, on the job times of a run measured on few. It was
//! `vibroatlas bench --simulate-threads` (see docs/performance.md).
//!
//! ```text
//! cargo bench --bench replay -- [--threads P] [--simulate-threads P,…] [--sync-ms MS] [--grid N] [--scene FILE]
//! ```
//!
//! `--threads` (default 2; the last of a list) is the measured run's thread
//! count; `--simulate-threads` (default 4,16,64,256) the virtual workers;
//! `--sync-ms` takes a journal write (its sync to disk) to cost this many
//! milliseconds instead of the time measured here (a cluster's network
//! filesystem, a slow disk); `--grid` (default 48) the N x N reference plane
//! of `vibroatlas bench`. For each sweep (fresh, both) it prints one `serial`
//! line (the costs measured outside the workers' cells) and one `simulated`
//! line per virtual thread count and policy.
//!
//! The replay: [`pipeline`] replays a list schedule on `p` virtual workers
//! (each job to the earliest free worker, in order), which is what a pool
//! taking jobs first come, first served does, with the [`Writer`] thread that
//! keeps the finished lines.

use anyhow::{anyhow, bail, Context, Result};
use engine::bench::{periods, sweeps, BenchRequest};
use engine::{Executed, Plan, Quiet, SceneSource, Setup};
use grid::schedule::longest_first;
use grid::{Plane, SweepKind};
use scene::Scene;
use solver::{Accuracy, Method, Preset};
use std::path::Path;

/// The thread that keeps finished lines (appends them to the resume journal),
/// serial, first come first served, once it has done `start` seconds of its
/// own work (creating the output file): a write costs `per_write` (the sync)
/// plus `per_line` for each line in it; `batched` writes take every line
/// finished while the previous write ran, else one line each.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Writer {
    /// Seconds of work before the first line (from the workers' start).
    start: f64,
    /// Seconds per write (the sync to disk).
    per_write: f64,
    /// Seconds per line written (encoding, when the writer does it).
    per_line: f64,
    /// Whether a write takes all the lines waiting.
    batched: bool,
}

/// When the last line is kept, for `jobs` (duration, line) taken in order by
/// `p` workers (each job to the worker that frees first; a line is finished
/// when its last job is) and kept by `writer`: the later of the workers'
/// makespan and the writer's end.
fn pipeline(jobs: &[(f64, usize)], p: usize, writer: &Writer) -> f64 {
    let mut free = vec![0.0f64; p.max(1)];
    let lines = jobs.iter().map(|j| j.1 + 1).max().unwrap_or(0);
    let mut done = vec![0.0f64; lines];
    for &(d, line) in jobs {
        let w = (0..free.len()).min_by(|&a, &b| free[a].total_cmp(&free[b])).unwrap_or(0);
        free[w] += d;
        done[line] = done[line].max(free[w]);
    }
    let span = free.into_iter().fold(0.0, f64::max);
    done.sort_by(f64::total_cmp);
    let (mut t, mut i) = (writer.start, 0);
    while i < done.len() {
        t = t.max(done[i]);
        // The lines finished by the time this write starts.
        let n = if writer.batched { done[i..].iter().take_while(|&&d| d <= t).count().max(1) } else { 1 };
        t += writer.per_write + n as f64 * writer.per_line;
        i += n;
    }
    span.max(t)
}

/// What a run costs outside its workers' cells, measured on one run with a
/// journal and a file (as `atlas -o` runs): seconds per line to seal it for
/// the journal, per journal write (one line and its sync), the cost probe,
/// the file's creation by the writer thread while the workers compute, and
/// its completion after the last line.
#[derive(Debug, Clone, Copy)]
struct Serial {
    seal: f64,
    append: f64,
    probe: f64,
    /// Creating the file with what does not depend on the results.
    create: f64,
    /// Per line: writing the chunks it completes (by the writer thread).
    stream: f64,
    /// Finishing the file: the part that stays serial and the part its
    /// threads share (chunk compression), from finishes on one and on all threads.
    finish: (f64, f64),
}

/// The lines of the atlas of `m`, every sweep.
fn lines_of(m: &Executed) -> Vec<grid::Line> {
    let p = &m.atlas.meta.plane;
    m.atlas
        .maps
        .iter()
        .flat_map(|map| {
            (0..p.lines()).map(move |l| grid::Line {
                sweep: map.sweep,
                index: l,
                cells: (0..p.line_len())
                    .filter_map(|pos| {
                        let (iy, ix) = p.cell(l, pos);
                        map.cells[iy * p.x.count + ix].clone()
                    })
                    .collect(),
            })
        })
        .collect()
}

/// Measures [`Serial`] on `m` (a run with an output file), re-sealing and
/// re-appending its lines one by one into a journal beside `out`.
fn serial_costs(m: &Executed, out: &Path, probe: f64, threads: usize) -> Result<Serial> {
    let lines = lines_of(m);
    let mut journal = store::Journal::create(&store::journal_path(out), "bench")?;
    let sealer = journal.sealer();
    let clock = std::time::Instant::now();
    let sealed = lines.iter().map(|l| sealer.seal(l)).collect::<Result<Vec<_>, _>>()?;
    let seal = clock.elapsed().as_secs_f64();
    let clock = std::time::Instant::now();
    for s in &sealed {
        journal.append_sealed([s])?;
    }
    let append = clock.elapsed().as_secs_f64();
    journal.remove()?;
    let n = lines.len().max(1) as f64;
    // The file finished again on one thread, every line kept as in the run:
    // with the run's finish, the shared part.
    let info =
        store::RunInfo { command: "bench".into(), run_time_s: m.secs, shard: None, history: Vec::new(), parent: None };
    let mut draft = store::Draft::create(&out.with_extension("one.h5"), &m.atlas.meta, 1)?;
    for l in &lines {
        draft.keep(&m.atlas, l.sweep, l.index)?;
    }
    let clock = std::time::Instant::now();
    draft.finish(&m.atlas, &info)?;
    let one = clock.elapsed().as_secs_f64();
    let shared =
        if threads > 1 { ((one - m.write_s) * threads as f64 / (threads - 1) as f64).clamp(0.0, one) } else { 0.0 };
    let (create, stream, finish) = (m.prelude_s, m.stream_s / n, (one - shared, shared));
    Ok(Serial { seal: seal / n, append: append / n, probe, create, stream, finish })
}

/// One replayed schedule.
struct Replayed {
    threads: usize,
    policy: &'static str,
    makespan_s: f64,
    efficiency: f64,
}

/// Jobs (seconds, line) of the run `m` taken in `order`: a chain, or each
/// cell of a fresh line; each cell's time is the workers' thread time
/// `thread_secs` shared in proportion to the forcing periods it simulated;
/// `seal` is the sealing each line's worker does (the current policy).
fn jobs(m: &Executed, thread_secs: f64, order: &[(SweepKind, usize)], seal: f64) -> Vec<(f64, usize)> {
    let atlas = &m.atlas;
    let p = &atlas.meta.plane;
    let per_period = thread_secs / periods(atlas, |_| true).max(1) as f64;
    let line_cells = |map: &grid::Map, line: usize| -> Vec<f64> {
        (0..p.line_len())
            .map(|pos| {
                let (iy, ix) = p.cell(line, pos);
                map.cells[iy * p.x.count + ix].as_ref().map_or(0.0, |c| c.periods as f64 * per_period)
            })
            .collect()
    };
    order
        .iter()
        .flat_map(|&(s, l)| {
            let id = atlas.maps.iter().position(|m| m.sweep == s).unwrap_or(0) * p.lines() + l;
            let cells = atlas.map(s).map(|m| line_cells(m, l)).unwrap_or_default();
            let n = cells.len().max(1) as f64;
            if s == SweepKind::Fresh {
                cells.into_iter().map(|d| (d + seal / n, id)).collect()
            } else {
                vec![(cells.iter().sum::<f64>() + seal, id)]
            }
        })
        .collect()
}

/// Replays the run `m` on `virtual_threads` workers: the lines are kept by
/// one writer thread, the cost probe comes before (its thread time shared by
/// the workers) and the file's completion after (its compression shared by
/// the workers, the rest serial). The previous policy takes lines in order,
/// both directions of a line together, its writer seals and syncs every line,
/// and the whole file is written after the last line; the current one takes
/// chains longest first by the probed `estimate` (fresh lines in order),
/// seals in the workers, syncs once per batch, and its writer creates the
/// file before it keeps the first line. Efficiency is the replayed one-worker
/// time over `P` times the replayed time on `P`.
fn replay(
    sweep: &str,
    m: &Executed,
    threads: usize,
    estimate: &[f64],
    c: Serial,
    virtual_threads: &[usize],
) -> Vec<Replayed> {
    let atlas = &m.atlas;
    let p = &atlas.meta.plane;
    let lines = atlas.maps.len() * p.lines();
    let thread_secs = (m.secs * threads as f64 - c.seal * lines as f64).max(0.0);
    let previous: Vec<(SweepKind, usize)> =
        (0..p.lines()).flat_map(|l| atlas.meta.sweeps.iter().map(move |&s| (s, l))).collect();
    // Chains longest first; fresh lines in order (their cells are shared).
    let current = if sweep == "fresh" { previous.clone() } else { longest_first(&previous, estimate) };
    // The probe runs its lines in parallel: its thread time, shared.
    let probe = if sweep == "fresh" { 0.0 } else { c.probe * threads as f64 };
    let (finish, shared) = c.finish;
    let current_writer = Writer { start: c.create, per_write: c.append, per_line: c.stream, batched: true };
    let previous_writer = Writer { start: 0.0, per_write: c.append, per_line: c.seal, batched: false };
    let whole_file = c.create + c.stream * lines as f64 + finish;
    let policies = [
        ("current", jobs(m, thread_secs, &current, c.seal), current_writer, probe, finish),
        ("previous", jobs(m, thread_secs, &previous, 0.0), previous_writer, 0.0, whole_file),
    ];
    let mut rows = Vec::new();
    for &t in virtual_threads {
        for &(policy, ref order, writer, before, after) in &policies {
            let time = |workers: usize| {
                let w = workers as f64;
                before / w + pipeline(order, workers, &writer) + after + shared / w
            };
            let span = time(t);
            rows.push(Replayed { threads: t, policy, makespan_s: span, efficiency: time(1) / (t as f64 * span) });
        }
    }
    rows
}

/// One run of `plane` as `atlas -o` runs it (journal, file with sections)
/// in the scratch folder `dir`, for the replay. Also returns each line's
/// estimated cost (the run's own probe, or one run here when the run did
/// not need it).
fn measured_run(
    scene: &Scene,
    plane: &Plane,
    sweeps: &[SweepKind],
    threads: usize,
    dir: &Path,
) -> Result<(Executed, Serial, Vec<f64>)> {
    let out = dir.join("replay.h5");
    let s = Setup {
        scene: scene.clone(),
        overrides: Vec::new(),
        accuracy: Accuracy::preset(Preset::Standard),
        accuracy_overrides: Vec::new(),
        preset: Preset::Standard,
        method: Method::Exact,
    };
    let mut plan = Plan::new(&s, 16, plane.clone(), sweeps.to_vec(), threads)?;
    plan.output = Some(out.clone());
    let clock = std::time::Instant::now();
    plan.check()?;
    let probe = clock.elapsed().as_secs_f64();
    let m = plan.execute(&Quiet)?;
    let serial = serial_costs(&m, &out, probe, threads)?;
    let estimate = match plan.cost {
        Some(cost) => cost,
        None => grid::schedule::probe(plane, &plan.setup, threads)?,
    };
    Ok((m, serial, estimate))
}

/// The command line.
struct Options {
    threads: usize,
    virtual_threads: Vec<usize>,
    sync_ms: Option<f64>,
    grid: usize,
    scene: Option<std::path::PathBuf>,
}

/// A comma-separated list of counts in `range`, for `flag`.
fn counts(flag: &str, text: &str, range: std::ops::RangeInclusive<usize>) -> Result<Vec<usize>> {
    text.split(',')
        .map(|t| t.trim().parse::<usize>().ok().filter(|n| range.contains(n)))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| anyhow!("{flag}: expected a comma-separated list of counts, got '{text}'"))
}

/// Parses the arguments after `--` (and the `--bench` that `cargo bench` adds).
fn options() -> Result<Options> {
    let mut o = Options { threads: 2, virtual_threads: vec![4, 16, 64, 256], sync_ms: None, grid: 48, scene: None };
    let mut args = std::env::args().skip(1).filter(|a| a != "--bench");
    while let Some(flag) = args.next() {
        let value = args.next().ok_or_else(|| anyhow!("{flag}: expected a value"))?;
        match flag.as_str() {
            "--threads" => o.threads = *counts(&flag, &value, 1..=1024)?.last().unwrap_or(&2),
            "--simulate-threads" => o.virtual_threads = counts(&flag, &value, 1..=1_000_000)?,
            "--sync-ms" => {
                let ms: f64 = value.parse().with_context(|| format!("{flag}: not a number: {value}"))?;
                if !(ms.is_finite() && (0.0..=60_000.0).contains(&ms)) {
                    bail!("{flag}: expected 0 to 60000 milliseconds, got {ms}");
                }
                o.sync_ms = Some(ms);
            }
            "--grid" => o.grid = value.parse().with_context(|| format!("{flag}: not a count: {value}"))?,
            "--scene" => o.scene = Some(value.into()),
            _ => bail!("unknown option {flag} (expected --threads, --simulate-threads, --sync-ms, --grid, --scene)"),
        }
    }
    Ok(o)
}

/// The `serial` line of a sweep.
fn print_serial(name: &str, s: &Serial) {
    println!(
        "serial     {name:<5} per line: seal {:.2} ms, journal write {:.2} ms, file chunks {:.2} ms; probe {:.2} s; file created {:.3} s (while computing), finished {:.3} s serial + {:.3} s shared",
        1e3 * s.seal,
        1e3 * s.append,
        1e3 * s.stream,
        s.probe,
        s.create,
        s.finish.0,
        s.finish.1
    );
}

fn main() -> Result<()> {
    check_pipeline();
    let o = options()?;
    let mut request = BenchRequest::new(o.grid);
    request.threads = vec![o.threads];
    if let Some(p) = &o.scene {
        request.scene = SceneSource::File(p.clone());
    }
    request.check()?;
    let (scene, plane) = (request.scene()?, request.plane()?);
    let dir = std::env::temp_dir().join(format!("vibroatlas-replay-{}", std::process::id()));
    for (name, sweeps) in sweeps() {
        std::fs::create_dir_all(&dir)?;
        let (m, mut serial, estimate) = measured_run(&scene, &plane, &sweeps, o.threads, &dir)?;
        std::fs::remove_dir_all(&dir)?;
        if let Some(ms) = o.sync_ms {
            serial.append = ms / 1000.0;
        }
        print_serial(name, &serial);
        for r in replay(name, &m, o.threads, &estimate, serial, &o.virtual_threads) {
            println!(
                "simulated  {name:<5} {} threads, {:<8} policy: makespan {:.3} s, efficiency {:.2}",
                r.threads, r.policy, r.makespan_s, r.efficiency
            );
        }
    }
    Ok(())
}

/// The replay's own checks (they were the unit tests of `grid::schedule`'s
/// `pipeline`): list scheduling, and a writer that bounds the pipeline.
fn check_pipeline() {
    let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-12, "{a} != {b}");
    let free = Writer { start: 0.0, per_write: 0.0, per_line: 0.0, batched: false };
    let makespan = |jobs: &[f64], p: usize| {
        let jobs: Vec<(f64, usize)> = jobs.iter().enumerate().map(|(i, &d)| (d, i)).collect();
        pipeline(&jobs, p, &free)
    };
    // Greedy in the given order: 3 | 3, then 2 + 2 on one, 2 + 2 on the other, the last 2 on the first.
    close(makespan(&[3.0, 3.0, 2.0, 2.0, 2.0], 2), 7.0);
    close(makespan(&[4.0; 8], 4), 8.0);
    close(makespan(&[1.0], 16), 1.0);
    close(makespan(&[], 3), 0.0);
    // Longest first beats the given order: 1, 1, 1, 1, 1, 5 on 2 workers.
    let cost = [1.0, 1.0, 1.0, 1.0, 1.0, 5.0];
    let given: Vec<(SweepKind, usize)> = (0..6).map(|l| (SweepKind::Up, l)).collect();
    let d = |o: &[(SweepKind, usize)]| o.iter().map(|j| cost[j.1]).collect::<Vec<_>>();
    close(makespan(&d(&given), 2), 7.0);
    close(makespan(&d(&longest_first(&given, &cost)), 2), 5.0);
    // 8 lines of 1 s on 8 workers: all done at 1 s.
    let jobs: Vec<(f64, usize)> = (0..8).map(|l| (1.0, l)).collect();
    close(pipeline(&jobs, 8, &free), 1.0);
    // A 0.5 s sync per line, one line per write: 1 + 8 × 0.5.
    let slow = Writer { per_write: 0.5, ..free };
    close(pipeline(&jobs, 8, &slow), 5.0);
    // Batched: every line waiting goes in one write: 1 + 0.5.
    let batched = Writer { batched: true, ..slow };
    close(pipeline(&jobs, 8, &batched), 1.5);
    // A writer busy for 1.2 s at the start delays only the lines before.
    let late = Writer { start: 1.2, ..batched };
    close(pipeline(&jobs, 8, &late), 1.7);
    close(pipeline(&jobs, 1, &late), 8.5);
    // On one worker the lines come 1 s apart and the writer keeps up.
    close(pipeline(&jobs, 1, &slow), 8.5);
    // A line of several jobs is finished by its last one.
    let split = [(1.0, 0), (3.0, 0), (1.0, 1)];
    close(pipeline(&split, 2, &Writer { per_line: 0.25, ..free }), 3.25);
    close(makespan(&split.map(|j| j.0), 2), 3.0);
}
