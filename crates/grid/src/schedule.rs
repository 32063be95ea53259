//! The order in which the lines of a plane are computed, and how shards split
//! them: by estimated cost, longest first.
//!
//! A line's cost is estimated by a cheap probe (`probe`): a few fresh cells
//! along it, counting the forcing periods they simulate (a deterministic
//! measure of work: the time of a period varies little). Continuation chains
//! cannot be split, so the most expensive chains must start first, or the last
//! ones leave cores idle at the end (longest processing time first, within
//! 4/3 of the best makespan). Every line's result depends only on its inputs,
//! so any order gives the same atlas bit for bit.
//!
//! [`pipeline`] replays a list schedule on `p` virtual workers (each job to the
//! earliest free worker, in order), which is what a pool taking jobs first come,
//! first served does, with the [`Writer`] thread that keeps the finished lines:
//! `bench --simulate-threads` uses it to predict the efficiency on many cores
//! from job times measured on few.

use crate::cell::CellSetup;
use crate::error::GridError;
use crate::plane::Plane;
use crate::sweep::SweepKind;
use rayon::prelude::*;

/// Cells of each line run by [`probe`].
pub const PROBE_CELLS: usize = 5;

/// Estimated cost of every line of `plane` (forcing periods simulated by
/// [`PROBE_CELLS`] fresh cells spread along it; a cell that fails counts as
/// one period). Deterministic, parallel over lines on `threads` threads.
pub fn probe(plane: &Plane, setup: &CellSetup, threads: usize) -> Result<Vec<f64>, GridError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| GridError::field("threads", e.to_string()))?;
    Ok(pool.install(|| line_costs(plane, setup)))
}

fn line_costs(plane: &Plane, setup: &CellSetup) -> Vec<f64> {
    let len = plane.line_len();
    let picks: Vec<usize> = if len <= PROBE_CELLS {
        (0..len).collect()
    } else {
        (0..PROBE_CELLS).map(|k| k * (len - 1) / (PROBE_CELLS - 1)).collect()
    };
    let quick = CellSetup { section_cap: 0, ..setup.clone() };
    (0..plane.lines())
        .into_par_iter()
        .map(|line| {
            let sum: u64 = picks
                .iter()
                .map(|&pos| {
                    let (iy, ix) = plane.cell(line, pos);
                    quick.run(&plane.params(iy, ix), None).map_or(1, |c| c.periods.max(1))
                })
                .sum();
            sum as f64 * len as f64 / picks.len() as f64
        })
        .collect()
}

/// Jobs `(sweep, line)` ordered longest first by `cost[line]`; ties keep the
/// given order (stable), so the order is deterministic.
pub fn longest_first(jobs: &[(SweepKind, usize)], cost: &[f64]) -> Vec<(SweepKind, usize)> {
    let mut v = jobs.to_vec();
    v.sort_by(|a, b| cost[b.1].total_cmp(&cost[a.1]));
    v
}

/// The lines shard `k` of `n` (1-based) computes: lines dealt longest first,
/// each to the shard with the least estimated cost so far (ties: the lowest
/// shard). Deterministic; every line in exactly one shard.
pub fn shard_lines(cost: &[f64], k: usize, n: usize) -> Vec<bool> {
    let mut order: Vec<usize> = (0..cost.len()).collect();
    order.sort_by(|&a, &b| cost[b].total_cmp(&cost[a]).then(a.cmp(&b)));
    let mut load = vec![0.0f64; n];
    let mut owner = vec![0usize; cost.len()];
    for line in order {
        let s = (0..n).min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b))).unwrap_or(0);
        load[s] += cost[line];
        owner[line] = s;
    }
    owner.iter().map(|&s| s + 1 == k).collect()
}

/// The thread that keeps finished lines (appends them to the resume journal),
/// serial, first come first served, once it has done `start` seconds of its
/// own work (creating the output file): a write costs `per_write` (the sync)
/// plus `per_line` for each line in it; `batched` writes take every line
/// finished while the previous write ran, else one line each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Writer {
    /// Seconds of work before the first line (from the workers' start).
    pub start: f64,
    /// Seconds per write (the sync to disk).
    pub per_write: f64,
    /// Seconds per line written (encoding, when the writer does it).
    pub per_line: f64,
    /// Whether a write takes all the lines waiting.
    pub batched: bool,
}

/// When the last line is kept, for `jobs` (duration, line) taken in order by
/// `p` workers (each job to the worker that frees first; a line is finished
/// when its last job is) and kept by `writer`: the later of the workers'
/// makespan and the writer's end.
pub fn pipeline(jobs: &[(f64, usize)], p: usize, writer: &Writer) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Makespan of the list schedule of `jobs` (durations, in the order
    /// taken) on `p` workers: the pipeline with a writer that costs nothing.
    fn makespan(jobs: &[f64], p: usize) -> f64 {
        let jobs: Vec<(f64, usize)> = jobs.iter().enumerate().map(|(i, &d)| (d, i)).collect();
        pipeline(&jobs, p, &Writer { start: 0.0, per_write: 0.0, per_line: 0.0, batched: false })
    }

    /// Parallel efficiency of a schedule: the work over `p` times its makespan.
    fn efficiency(jobs: &[f64], p: usize) -> f64 {
        jobs.iter().sum::<f64>() / (p as f64 * makespan(jobs, p))
    }

    #[test]
    fn longest_first_is_stable_and_beats_the_given_order() {
        let jobs: Vec<(SweepKind, usize)> = (0..6).map(|l| (SweepKind::Up, l)).collect();
        let cost = [1.0, 1.0, 1.0, 1.0, 1.0, 5.0];
        let order = longest_first(&jobs, &cost);
        assert_eq!(order[0].1, 5);
        assert_eq!(order[1..].iter().map(|j| j.1).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4], "ties keep their order");
        let d = |o: &[(SweepKind, usize)]| o.iter().map(|j| cost[j.1]).collect::<Vec<_>>();
        // Given order on 2 workers: the 5 starts last (makespan 2 + 5 = 7); longest first: 5.
        assert!((makespan(&d(&jobs), 2) - 7.0).abs() < 1e-12);
        assert!((makespan(&d(&order), 2) - 5.0).abs() < 1e-12);
        assert!((efficiency(&d(&order), 2) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn makespan_of_list_scheduling() {
        // Greedy in the given order: 3 | 3, then 2 + 2 on one, 2 + 2 on the other, the last 2 on the first.
        assert!((makespan(&[3.0, 3.0, 2.0, 2.0, 2.0], 2) - 7.0).abs() < 1e-12);
        assert!((makespan(&[4.0; 8], 4) - 8.0).abs() < 1e-12);
        assert!((makespan(&[1.0], 16) - 1.0).abs() < 1e-12);
        assert!((makespan(&[], 3)).abs() < 1e-12);
    }

    #[test]
    fn a_slow_writer_bounds_the_pipeline_and_batching_relieves_it() {
        // 8 lines of 1 s on 8 workers: all done at 1 s.
        let jobs: Vec<(f64, usize)> = (0..8).map(|l| (1.0, l)).collect();
        let free = Writer { start: 0.0, per_write: 0.0, per_line: 0.0, batched: false };
        assert!((pipeline(&jobs, 8, &free) - 1.0).abs() < 1e-12);
        // A 0.5 s sync per line, one line per write: 1 + 8 × 0.5.
        let slow = Writer { start: 0.0, per_write: 0.5, per_line: 0.0, batched: false };
        assert!((pipeline(&jobs, 8, &slow) - 5.0).abs() < 1e-12);
        // Batched: every line waiting goes in one write: 1 + 0.5.
        let batched = Writer { batched: true, ..slow };
        assert!((pipeline(&jobs, 8, &batched) - 1.5).abs() < 1e-12);
        // A writer busy for 1.2 s at the start delays only the lines before.
        let late = Writer { start: 1.2, ..batched };
        assert!((pipeline(&jobs, 8, &late) - 1.7).abs() < 1e-12);
        assert!((pipeline(&jobs, 1, &late) - 8.5).abs() < 1e-12);
        // On one worker the lines come 1 s apart and the writer keeps up.
        assert!((pipeline(&jobs, 1, &slow) - 8.5).abs() < 1e-12);
        // A line of several jobs is finished by its last one.
        let split = [(1.0, 0), (3.0, 0), (1.0, 1)];
        let per_line = Writer { start: 0.0, per_write: 0.0, per_line: 0.25, batched: false };
        assert!((pipeline(&split, 2, &per_line) - 3.25).abs() < 1e-12);
        assert!((makespan(&split.map(|j| j.0), 2) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn shards_partition_lines_and_balance_cost() {
        let cost: Vec<f64> = (0..20).map(|i| if i < 3 { 10.0 } else { 1.0 }).collect();
        let shards: Vec<Vec<bool>> = (1..=3).map(|k| shard_lines(&cost, k, 3)).collect();
        for line in 0..cost.len() {
            assert_eq!(shards.iter().filter(|s| s[line]).count(), 1, "line {line} in one shard");
        }
        let loads: Vec<f64> =
            shards.iter().map(|s| s.iter().zip(&cost).filter(|(o, _)| **o).map(|(_, c)| c).sum()).collect();
        let (lo, hi) = (loads.iter().copied().fold(f64::INFINITY, f64::min), loads.iter().copied().fold(0.0, f64::max));
        assert!(hi - lo <= 1.0 + 1e-12, "{loads:?}");
        assert_eq!(shard_lines(&cost, 2, 3), shard_lines(&cost, 2, 3), "deterministic");
    }
}
