//! Running a plane's lines: fresh lines tile their cells across cores; up
//! and down lines are continuation chains, run in parallel with each other.
//! Every line's result depends only on its inputs, so the plane is identical
//! whatever the number of threads or the order in which lines finish.

use crate::cell::CellSetup;
use crate::error::GridError;
use crate::observer::Observer;
use crate::sweep::chain_from;
use maps::{Entries, Line, Plane, SweepKind};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Checks that every cell's parameters make a valid scene, before any work
/// (cells in parallel on `threads` threads; the first failing cell in row
/// order is reported).
pub fn validate(plane: &Plane, setup: &CellSetup, threads: usize) -> Result<(), GridError> {
    for (field, axis) in [("x", &plane.x), ("y", &plane.y)] {
        setup.scene.check_parameter(&axis.name, field).map_err(|e| match e {
            scene::SceneError::Field { message, .. } => GridError::field(field, message),
            other => GridError::field(field, other.to_string()),
        })?;
    }
    let pool = crate::pool(threads)?;
    // The first failing cell in row order, whatever the thread count.
    let failed = pool.install(|| {
        (0..plane.y.count)
            .into_par_iter()
            .find_map_first(|iy| (0..plane.x.count).find_map(|ix| setup.system(&plane.params(iy, ix)).err()))
    });
    failed.map_or(Ok(()), Err)
}

/// Computes one line of one sweep; a chain starts from `entry` (the
/// scene's initial state when `None`).
pub fn line(
    plane: &Plane,
    setup: &CellSetup,
    sweep: SweepKind,
    index: usize,
    entry: Option<&[f64]>,
    progress: &dyn Observer,
) -> Result<Line, GridError> {
    let len = plane.line_len();
    let point = |pos: usize| {
        let (iy, ix) = plane.cell(index, pos);
        plane.params(iy, ix)
    };
    let cells = match sweep {
        SweepKind::Fresh => (0..len)
            .into_par_iter()
            .map(|pos| {
                if progress.cancelled() {
                    return Err(GridError::Cancelled);
                }
                let c = setup.run(&point(pos), None);
                progress.advance(1);
                c
            })
            .collect::<Result<Vec<_>, _>>()?,
        SweepKind::Up => chain_from(setup, &(0..len).map(point).collect::<Vec<_>>(), entry, progress)?,
        SweepKind::Down => {
            let mut c = chain_from(setup, &(0..len).rev().map(point).collect::<Vec<_>>(), entry, progress)?;
            c.reverse();
            c
        }
    };
    Ok(Line { sweep, index, cells })
}

/// Computes the given `(sweep, line)` jobs on `threads` threads (chains
/// from their `entries`), handing each finished line to `sink` (from the
/// worker thread that computed it). Workers take jobs first come, first
/// served in the order given, so that a caller listing expensive lines
/// first keeps both cores busy to the end.
pub fn run(
    plane: &Plane,
    setup: &CellSetup,
    jobs: &[(SweepKind, usize)],
    entries: &Entries,
    threads: usize,
    progress: &dyn Observer,
    sink: &(dyn Fn(Line) + Sync),
) -> Result<(), GridError> {
    let pool = crate::pool(threads)?;
    let next = AtomicUsize::new(0);
    let failed: Mutex<Option<GridError>> = Mutex::new(None);
    pool.broadcast(|_| loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        let Some(&(sweep, index)) = jobs.get(i) else { break };
        match line(plane, setup, sweep, index, entries.get(sweep, index), progress) {
            Ok(line) => sink(line),
            Err(e) => {
                failed.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
                next.store(jobs.len(), Ordering::Relaxed);
            }
        }
    });
    match failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
