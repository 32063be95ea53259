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
//! The replay of these policies on many virtual workers, which predicts the
//! efficiency on many cores from job times measured on few, is lab tooling:
//! `cargo bench --bench replay` (benches/replay.rs).

use crate::cell::CellSetup;
use crate::error::GridError;
use maps::Plane;
use maps::SweepKind;
use rayon::prelude::*;

/// Cells of each line run by [`probe`].
pub const PROBE_CELLS: usize = 5;

/// Estimated cost of every line of `plane` (forcing periods simulated by
/// [`PROBE_CELLS`] fresh cells spread along it; a cell that fails counts as
/// one period). Deterministic, parallel over lines on `threads` threads.
pub fn probe(plane: &Plane, setup: &CellSetup, threads: usize) -> Result<Vec<f64>, GridError> {
    let pool = crate::pool(threads)?;
    Ok(pool.install(|| line_costs(plane, setup)))
}

fn line_costs(plane: &Plane, setup: &CellSetup) -> Vec<f64> {
    let len = plane.line_len();
    let picks: Vec<usize> = if len <= PROBE_CELLS {
        (0..len).collect()
    } else {
        (0..PROBE_CELLS).map(|k| k * (len - 1) / (PROBE_CELLS - 1)).collect()
    };
    let quick = CellSetup { section_cap: 0, quantities: Vec::new(), ..setup.clone() };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn longest_first_is_stable() {
        let jobs: Vec<(SweepKind, usize)> = (0..6).map(|l| (SweepKind::Up, l)).collect();
        let cost = [1.0, 1.0, 1.0, 1.0, 1.0, 5.0];
        let order = longest_first(&jobs, &cost);
        assert_eq!(order[0].1, 5);
        assert_eq!(order[1..].iter().map(|j| j.1).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4], "ties keep their order");
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
