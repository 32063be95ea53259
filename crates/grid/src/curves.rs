//! Bifurcation curves seeded from a stored map.
//!
//! A seed is a pair of neighbouring cells (in a row or in a column) of one of
//! the map's sweeps whose periodic labels differ: a bifurcation lies between
//! them. Seeds are taken from every sweep asked for, so that in an atlas with
//! up and down sweeps both ends of every hysteresis zone are seeds (each
//! sweep's label changes where its branch ends). A seed's bifurcation is
//! located on the segment between its two cells, by continuation of the orbit
//! found from the stored final state of one of them (the other failing), and
//! followed both ways ([`solver::curve::Tracing`]): along `b` by rows (row
//! seeds) or by pseudo-arclength (column seeds), to the plane's edges.
//!
//! Seeds are visited boundaries between large regions first: by the number of
//! cells of the smaller of their two labels in the map, largest first; among
//! equals from the top row down, a row's seeds left to right, then the column
//! seeds below it. A seed whose cells a curve already found passes between is
//! skipped; a curve whose points mostly lie on one found before (same kind) is
//! dropped, and one found before whose points mostly lie on a new one gives way
//! to it; a curve of fewer than three points is dropped too (the fine structure of a map
//! seeds many short ones). Seeds are decided one by one in seed order, each on
//! the curves of the seeds before it, so the result is that of one thread on
//! any number of threads. The threads trace the seeds after the next to
//! decide while its curve is traced (speculatively: a seed that the curve of
//! one before it turns out to cross is dropped), so that no core waits for
//! a slow curve; a seed that a curve already traced before it crosses is put
//! off until it is the next to decide, where it is most likely skipped, not
//! traced in vain, and a seed that a curve committed while it is traced
//! crosses is abandoned (its trace ends at its next step: its commit skips
//! it), as are the traces still running once `max` curves are kept.

use crate::cell::CellSetup;
use crate::error::GridError;
use maps::Atlas;
use maps::SweepKind;
use solver::curve::{Curve, Plane2, Start, Tracing};
use solver::{Bifurcation, Class};
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

/// Fewest points of a curve kept.
const MIN_POINTS: usize = 3;

/// What to look for.
#[derive(Debug, Clone)]
pub struct Seeding {
    /// Kinds of bifurcation located at a seed (the one nearest the seed is kept).
    pub kinds: Vec<Bifurcation>,
    /// Sweeps whose label changes seed curves.
    pub sweeps: Vec<SweepKind>,
    /// Most curves.
    pub max: usize,
    /// Worker threads.
    pub threads: usize,
}

/// A pair of neighbouring cells with different periodic labels.
#[derive(Debug, Clone)]
struct Seed {
    /// The midpoint `(a, b)` of the two cells.
    at: [f64; 2],
    /// The two cells' `(a, b)`.
    cells: [[f64; 2]; 2],
    /// Whether the cells are neighbours in a column (else in a row).
    vertical: bool,
    /// The stored final states of the two cells (starts of the orbit).
    starts: [Vec<f64>; 2],
    /// Cells of the smaller of the two labels in the seed's map: boundaries
    /// between large regions come first.
    weight: usize,
}

/// Curves found, and the seeds traced.
#[derive(Debug, Clone)]
pub struct Search {
    /// The curves kept, in seed order.
    pub curves: Vec<Curve>,
    /// Seeds traced (not skipped as lying on a curve already found).
    pub seeds: usize,
}

/// Where a search stands: seeds done (traced, or skipped as lying on a curve
/// already found) of all the seeds, seeds traced, curves kept so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tally {
    /// Seeds done, traced or skipped.
    pub done: usize,
    /// All the seeds of the map.
    pub total: usize,
    /// Seeds traced.
    pub traced: usize,
    /// Curves kept so far.
    pub kept: usize,
}

/// The seeds of `sweeps` of `atlas`, in the order described in the module doc.
fn seeds(atlas: &Atlas, sweeps: &[SweepKind]) -> Vec<Seed> {
    let (x, y) = (&atlas.meta.plane.x, &atlas.meta.plane.y);
    let maps: Vec<_> = sweeps.iter().filter_map(|&s| atlas.map(s)).collect();
    let counts: Vec<std::collections::HashMap<solver::Label, usize>> = maps
        .iter()
        .map(|m| {
            let mut c = std::collections::HashMap::new();
            for cell in m.cells.iter().flatten() {
                if let Some(&l) = cell.labels.first() {
                    *c.entry(l).or_insert(0) += 1;
                }
            }
            c
        })
        .collect();
    let mut out = Vec::new();
    for iy in (0..y.count).rev() {
        for (pairs, vertical) in [
            ((0..x.count.saturating_sub(1)).map(|ix| (iy, ix, iy, ix + 1)).collect::<Vec<_>>(), false),
            ((0..x.count).filter(|_| iy > 0).map(|ix| (iy, ix, iy - 1, ix)).collect(), true),
        ] {
            for (jy, jx, ky, kx) in pairs {
                for (map, count) in maps.iter().zip(&counts) {
                    let (i, k) = (jy * x.count + jx, ky * x.count + kx);
                    let periodic = |i: usize| map.cells[i].as_ref().filter(|c| c.class == Class::Periodic);
                    let (Some(c1), Some(c2)) = (periodic(i), periodic(k)) else { continue };
                    if c1.labels.first() == c2.labels.first() {
                        continue;
                    }
                    let cells = [[x.value(jx), y.value(jy)], [x.value(kx), y.value(ky)]];
                    let at = [(cells[0][0] + cells[1][0]) / 2.0, (cells[0][1] + cells[1][1]) / 2.0];
                    let starts = [c1.final_state.clone(), c2.final_state.clone()];
                    let size = |c: &maps::CellData| c.labels.first().map_or(0, |l| count[l]);
                    out.push(Seed { at, cells, vertical, starts, weight: size(c1).min(size(c2)) });
                }
            }
        }
    }
    // Stable: among equal weights, the order above.
    out.sort_by_key(|s| std::cmp::Reverse(s.weight));
    out
}

/// Follows the bifurcations of the map's label boundaries (see the module doc),
/// telling `progress` where it stands as each seed is done (from the worker
/// threads, as seeds finish; the last tally says every seed is done). Progress
/// does not change what is found.
pub fn find(
    setup: &CellSetup,
    atlas: &Atlas,
    seeding: &Seeding,
    progress: &(dyn Fn(Tally) + Sync),
) -> Result<Search, GridError> {
    let p = &atlas.meta.plane;
    let (x, y) = (&p.x, &p.y);
    if x.count < 2 {
        return Err(GridError::field("x", "curves need at least two columns"));
    }
    let (dx, dy) = (x.step().abs(), if y.count > 1 { y.step().abs() } else { 1.0 });
    let (ax, ay) = (x.name.clone(), y.name.clone());
    let plane = move |a: f64, b: f64| setup.system(&[(ax.clone(), a), (ay.clone(), b)]).ok();
    let bounds = [[x.start.min(x.stop), x.start.max(x.stop)], [y.start.min(y.stop), y.start.max(y.stop)]];
    let tracing = |kind, scale| Tracing {
        kind,
        acc: setup.accuracy,
        n: None,
        scale,
        bounds,
        max_points: 4 * (x.count + y.count),
    };
    let pool = crate::pool(seeding.threads)?;
    let all = seeds(atlas, &seeding.sweeps);
    let total = all.len();
    progress(Tally { done: 0, total, traced: 0, kept: 0 });
    let abandoned: Vec<AtomicBool> = (0..total).map(|_| AtomicBool::new(false)).collect();
    let run = Run { all: &all, abandoned: &abandoned, max: seeding.max, cell: [dx, dy], progress };
    let state = std::sync::Mutex::new(Schedule::new(total));
    let advanced = std::sync::Condvar::new();
    let trace_one = |i: usize| {
        // An abandoned seed's plane admits no system: its trace ends at its next step.
        let seed_plane = |a: f64, b: f64| if abandoned[i].load(Relaxed) { None } else { plane(a, b) };
        trace(&seed_plane, &all[i], &seeding.kinds, &tracing, [dx, dy], y)
    };
    pool.scope(|scope| {
        for _ in 0..seeding.threads.max(1) {
            scope.spawn(|_| run.worker(&state, &advanced, &trace_one));
        }
    });
    let state = state.into_inner().unwrap_or_else(|p| p.into_inner());
    progress(Tally { done: total, total, traced: state.found.seeds, kept: state.found.curves.len() });
    Ok(state.found)
}

/// Seeds a worker may trace ahead of the next to decide: later seeds wait,
/// so that speculative work on seeds a curve decided before them may yet
/// cross stays bounded.
const AHEAD: usize = 64;

/// Where one seed stands.
#[derive(Debug)]
enum SeedState {
    /// Not traced yet (or being traced).
    Pending,
    /// A curve committed before it crosses it: not traced.
    Skipped,
    /// Traced (speculatively, if the seeds before it are not all decided).
    Traced(Option<Curve>),
}

/// The curves committed so far and each seed's state: seeds are committed
/// in order, each as one thread would decide it (skipped where a curve
/// committed before it crosses it, else its curve accepted or dropped), so
/// the result does not depend on how many threads traced them or in which
/// order they finished.
struct Schedule {
    found: Search,
    states: Vec<SeedState>,
    /// Seeds committed: the next to commit.
    committed: usize,
    /// Seeds decided (skipped or traced).
    decided: usize,
    /// The next seed not yet taken.
    next: usize,
    /// Seeds put off because a curve traced before them crosses them (their
    /// commit will most likely skip them): taken up once each is the next to
    /// commit.
    deferred: Vec<usize>,
    /// `max` curves are kept: nothing more is traced.
    finished: bool,
}

impl Schedule {
    fn new(total: usize) -> Schedule {
        Schedule {
            found: Search { curves: Vec::new(), seeds: 0 },
            states: (0..total).map(|_| SeedState::Pending).collect(),
            committed: 0,
            decided: 0,
            next: 0,
            deferred: Vec::new(),
            finished: false,
        }
    }

    /// Whether a curve committed, or traced from a seed before `i` not yet
    /// committed, crosses `seed` (the `i`-th).
    fn crossed(&self, i: usize, seed: &Seed) -> bool {
        let mut traced = self.states[self.committed.min(i)..i].iter().filter_map(|s| match s {
            SeedState::Traced(Some(c)) if c.points.len() >= MIN_POINTS => Some(c),
            _ => None,
        });
        self.committed_cross(seed) || traced.any(|c| crosses(c, seed))
    }

    /// Whether a curve committed crosses `seed`.
    fn committed_cross(&self, seed: &Seed) -> bool {
        self.found.curves.iter().any(|c| crosses(c, seed))
    }
}

/// What the workers of one search share.
struct Run<'a> {
    all: &'a [Seed],
    /// Per seed, whether a curve committed before it crosses it while it is
    /// being traced (speculatively), or `max` curves are kept: its commit
    /// skips it or never comes, so its trace is ended at once.
    abandoned: &'a [AtomicBool],
    max: usize,
    cell: [f64; 2],
    progress: &'a (dyn Fn(Tally) + Sync),
}

impl Run<'_> {
    /// The next seed a worker traces, or `None` when none is left: a seed
    /// put off that is now the next to commit, else the next seed in order,
    /// at most [`AHEAD`] seeds ahead of the next to commit (waiting until the
    /// commits reach it). A later seed that a curve traced before it crosses
    /// is put off (not traced now: its commit most likely skips it). The
    /// seed next to commit is skipped where a committed curve crosses it.
    fn take(&self, state: &std::sync::Mutex<Schedule>, advanced: &std::sync::Condvar) -> Option<usize> {
        let mut st = state.lock().unwrap_or_else(|p| p.into_inner());
        loop {
            if st.finished {
                return None;
            }
            let current = st.committed;
            let i = match st.deferred.iter().position(|&j| j <= current) {
                Some(k) => st.deferred.swap_remove(k),
                None if st.next >= self.all.len() && st.deferred.is_empty() => return None,
                None if st.next >= self.all.len() || st.next > current + AHEAD => {
                    st = advanced.wait(st).unwrap_or_else(|p| p.into_inner());
                    continue;
                }
                None => {
                    st.next += 1;
                    let i = st.next - 1;
                    if i > current && st.crossed(i, &self.all[i]) {
                        st.deferred.push(i);
                        continue;
                    }
                    i
                }
            };
            if i == current && st.committed_cross(&self.all[i]) {
                st.states[i] = SeedState::Skipped;
                st.decided += 1;
                self.commit(&mut st);
                advanced.notify_all();
                continue;
            }
            self.abandoned[i].store(false, Relaxed);
            return Some(i);
        }
    }

    /// Takes seeds ([`Run::take`]), traces them, and commits every seed
    /// decided whose seeds before it are. A seed after the next to commit is
    /// traced speculatively (its commit drops it if a curve committed before
    /// crosses it).
    fn worker(
        &self,
        state: &std::sync::Mutex<Schedule>,
        advanced: &std::sync::Condvar,
        trace_one: &(dyn Fn(usize) -> Option<Curve> + Sync),
    ) {
        let lock = || state.lock().unwrap_or_else(|p| p.into_inner());
        loop {
            let Some(i) = self.take(state, advanced) else {
                advanced.notify_all();
                return;
            };
            let curve = trace_one(i);
            let mut st = lock();
            st.states[i] = SeedState::Traced(curve);
            st.decided += 1;
            let (done, total, traced, kept) = (st.decided, self.all.len(), st.found.seeds, st.found.curves.len());
            if !self.commit(&mut st) {
                (self.progress)(Tally { done, total, traced, kept });
            }
            advanced.notify_all();
        }
    }

    /// Commits every seed, in order, that is decided; whether one was. A
    /// seed abandoned for a curve that has since given way to one that does
    /// not cross it is traced again (it is put off, as the next to commit).
    fn commit(&self, st: &mut Schedule) -> bool {
        let total = self.all.len();
        let mut any = false;
        while !st.finished && st.committed < total {
            let i = st.committed;
            // A skipped seed was crossed when it was skipped, under this lock.
            let crossed = match st.states[i] {
                SeedState::Pending => break,
                SeedState::Skipped => true,
                SeedState::Traced(_) => st.committed_cross(&self.all[i]),
            };
            if !crossed && self.abandoned[i].load(Relaxed) {
                st.states[i] = SeedState::Pending;
                st.decided -= 1;
                st.deferred.push(i);
                break;
            }
            any = true;
            st.committed += 1;
            let state = std::mem::replace(&mut st.states[i], SeedState::Skipped);
            // A seed that a curve committed before it crosses is skipped.
            if let SeedState::Traced(curve) = state {
                if !crossed {
                    st.found.seeds += 1;
                    self.accept(st, curve);
                }
            }
            let done = st.committed.max(st.decided);
            (self.progress)(Tally { done, total, traced: st.found.seeds, kept: st.found.curves.len() });
        }
        any
    }

    /// Keeps a committed seed's curve unless it is short or lies on one kept
    /// before; kept curves that lie on it give way to it.
    fn accept(&self, st: &mut Schedule, curve: Option<Curve>) {
        let Some(curve) = curve else { return };
        if curve.points.len() < MIN_POINTS || st.found.curves.iter().any(|c| same(c, &curve, self.cell)) {
            return;
        }
        st.found.curves.retain(|c| !same(&curve, c, self.cell));
        st.found.curves.push(curve);
        st.finished = st.found.curves.len() >= self.max;
        // Seeds after it being traced that it crosses will be skipped; with
        // `max` curves kept, none after it is committed.
        let curve = st.found.curves.last().expect("just kept");
        for j in st.committed..st.next {
            if matches!(st.states[j], SeedState::Pending) && (st.finished || crosses(curve, &self.all[j])) {
                self.abandoned[j].store(true, Relaxed);
            }
        }
    }
}

fn trace(
    plane: &Plane2,
    seed: &Seed,
    kinds: &[Bifurcation],
    tracing: &dyn Fn(Bifurcation, [f64; 2]) -> Tracing,
    cell: [f64; 2],
    y: &maps::Axis,
) -> Option<Curve> {
    // On the segment between the two cells (half-width half a cell), per kind
    // the bifurcation from the first stored state that gives one.
    let t = tracing(*kinds.first()?, [cell[0] / 2.0, cell[1] / 2.0]);
    let mut found: Vec<Option<solver::curve::CurvePoint>> = vec![None; kinds.len()];
    for start in &seed.starts {
        if found.iter().all(Option::is_some) {
            break;
        }
        let located = t.locate_kinds(plane, seed.at, seed.vertical, Start::State(start), kinds);
        for (slot, p) in found.iter_mut().zip(located) {
            if slot.is_none() {
                *slot = p.ok();
            }
        }
    }
    let distance = |p: &solver::curve::CurvePoint| ((p.a - seed.at[0]) / cell[0]).hypot((p.b - seed.at[1]) / cell[1]);
    let (kind, first) = kinds
        .iter()
        .zip(found)
        .filter_map(|(&k, p)| p.map(|p| (k, p)))
        .min_by(|p, q| distance(&p.1).total_cmp(&distance(&q.1)))?;
    // The curve may move more than a cell from one row to the next.
    let t = tracing(kind, [2.0 * cell[0], cell[1]]);
    let (back, ahead) = if seed.vertical {
        (t.follow_along(plane, first.clone(), [-1.0, 0.0]), t.follow_along(plane, first, [1.0, 0.0]))
    } else {
        (t.follow(plane, first.clone(), y.start), t.follow(plane, first, y.stop))
    };
    Some(Curve::join(back, ahead))
}

/// Whether `curve` passes between the seed's two cells: one of its segments
/// crosses the segment joining them.
fn crosses(curve: &Curve, seed: &Seed) -> bool {
    let [p, q] = seed.cells;
    let side = |o: [f64; 2], u: [f64; 2], v: [f64; 2]| (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0]);
    curve.points.windows(2).any(|w| {
        let (r, t) = ([w[0].a, w[0].b], [w[1].a, w[1].b]);
        side(p, q, r) * side(p, q, t) <= 0.0 && side(r, t, p) * side(r, t, q) <= 0.0
    })
}

/// Whether `b` is a curve `a` already holds: the same kind, and more than
/// half of its points within a quarter of a cell of `a`'s polyline (points
/// followed from another seed fall elsewhere along the same curve).
fn same(a: &Curve, b: &Curve, cell: [f64; 2]) -> bool {
    let scaled = |p: &solver::curve::CurvePoint| [p.a / cell[0], p.b / cell[1]];
    let line: Vec<[f64; 2]> = a.points.iter().map(scaled).collect();
    let near = |q: [f64; 2]| {
        let segment = |u: [f64; 2], v: [f64; 2]| {
            let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
            let len2 = dx * dx + dy * dy;
            let t = if len2 > 0.0 { (((q[0] - u[0]) * dx + (q[1] - u[1]) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
            (u[0] + t * dx - q[0]).hypot(u[1] + t * dy - q[1])
        };
        let d = match line.len() {
            0 => f64::INFINITY,
            1 => segment(line[0], line[0]),
            _ => line.windows(2).map(|w| segment(w[0], w[1])).fold(f64::INFINITY, f64::min),
        };
        d <= 0.25
    };
    a.kind == b.kind && 2 * b.points.iter().filter(|p| near(scaled(p))).count() > b.points.len()
}
