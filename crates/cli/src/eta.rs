//! How long a run has left: the time so far times the work left over the
//! work done, `t (W - w) / w` ([`eta`]). Cells cost very unevenly (a
//! recent-steps estimate swings by a factor of five), and an atlas's lines
//! are computed the most expensive first, so counting cells says the first
//! tenth of the cells took a tenth of the time when it took a third. Where
//! the scheduler probed the lines' costs, the work is counted per line
//! ([`Work`]): the lines finished weigh the time they took, the others the
//! time lines near them took. The command line's progress bar shows
//! what this estimates.

use std::sync::Mutex;

/// `t (W - w) / w`: the seconds left when `done` of `total` units of work
/// took `elapsed` seconds (the rate so far, applied to the work left); `None`
/// before any work is done.
pub fn eta(elapsed: f64, done: f64, total: f64) -> Option<f64> {
    (done > 0.0).then(|| elapsed * (total - done).max(0.0) / done)
}

/// The estimated work of a run's jobs (lines, each `line_len` cells, taken
/// by the workers first come, first served in the order given), in seconds of
/// a worker once calibrated:
///
/// - a finished job weighs the time its worker took for it (measured from
///   the end of that worker's previous job);
/// - a job not finished weighs what finished jobs of nearby lines took,
///   interpolated along the line index (a line's cost varies smoothly with
///   the parameter across lines, and its up and down sweeps cost about the
///   same; beyond the last finished line on one side, the nearest one's);
/// - before any job is finished, every job weighs its probed cost (the
///   scheduler's estimate, `grid::schedule::probe`, in forcing periods).
///
/// The probed cost alone predicts a line's time poorly (it counts the forcing
/// periods of a few fresh cells, whose transients and impacts differ from a
/// continuation chain's), but it orders the lines: the first ones finished are
/// spread over the whole plane, so their times calibrate the rest.
///
/// The cells finished in lines still running count their share of the first
/// `threads` jobs not finished (those running, as jobs are taken in order).
pub struct Work {
    line: Vec<usize>,
    prior: Vec<f64>,
    lines: usize,
    line_len: u64,
    threads: usize,
    state: Mutex<WorkState>,
}

struct WorkState {
    /// Seconds each finished job took.
    secs: Vec<Option<f64>>,
    /// Jobs before this one are all finished.
    first_open: usize,
    finished: u64,
    /// When each worker finished its last job (seconds from the start).
    last: std::collections::HashMap<std::thread::ThreadId, f64>,
}

impl Work {
    /// The work of jobs on lines `line` (in the order taken) of probed costs
    /// `prior`, each of `line_len` cells, on `threads` workers. `None` when
    /// there is nothing to weigh (no job, lengths that differ, or a cost that
    /// is not a positive number).
    pub fn new(line: Vec<usize>, prior: Vec<f64>, line_len: usize, threads: usize) -> Option<Work> {
        if line.is_empty() || line.len() != prior.len() || line_len == 0 {
            return None;
        }
        if prior.iter().any(|c| !(c.is_finite() && *c > 0.0)) {
            return None;
        }
        let lines = line.iter().max().map_or(0, |l| l + 1);
        let state = WorkState {
            secs: vec![None; line.len()],
            first_open: 0,
            finished: 0,
            last: std::collections::HashMap::new(),
        };
        Some(Work { line, prior, lines, line_len: line_len as u64, threads: threads.max(1), state: Mutex::new(state) })
    }

    /// Job `job` (its place in the order) finished on the calling thread at
    /// `at` seconds from the start: it took the time since that thread's
    /// previous job (or since the start).
    pub fn finish_at(&self, job: usize, at: f64) {
        let Ok(mut s) = self.state.lock() else { return };
        let since = s.last.insert(std::thread::current().id(), at).unwrap_or(0.0);
        s.record(job, (at - since).max(0.0));
    }

    /// Job `job` finished, having taken `secs` seconds.
    #[cfg(test)]
    fn finish(&self, job: usize, secs: f64) {
        if let Ok(mut s) = self.state.lock() {
            s.record(job, secs.max(0.0));
        }
    }

    /// The estimated cost of every job: measured, interpolated or probed.
    fn costs(&self, s: &WorkState) -> Vec<f64> {
        if s.finished == 0 {
            return self.prior.clone();
        }
        // Mean seconds of the finished jobs of each line.
        let mut sum = vec![(0.0f64, 0u32); self.lines];
        for (j, t) in s.secs.iter().enumerate() {
            if let Some(t) = t {
                sum[self.line[j]].0 += t;
                sum[self.line[j]].1 += 1;
            }
        }
        let mean: Vec<Option<f64>> = sum.iter().map(|&(t, n)| (n > 0).then(|| t / f64::from(n))).collect();
        // The nearest measured line at or below, and at or above, each line.
        let mut below = vec![None; self.lines];
        let mut above = vec![None; self.lines];
        let mut seen = None;
        for l in 0..self.lines {
            if mean[l].is_some() {
                seen = Some(l);
            }
            below[l] = seen;
        }
        seen = None;
        for l in (0..self.lines).rev() {
            if mean[l].is_some() {
                seen = Some(l);
            }
            above[l] = seen;
        }
        let at = |l: usize| -> f64 {
            let value = |k: usize| mean[k].unwrap_or(0.0);
            match (below[l], above[l]) {
                (Some(a), Some(b)) if a != b => value(a) + (value(b) - value(a)) * (l - a) as f64 / (b - a) as f64,
                (Some(a), _) => value(a),
                (None, Some(b)) => value(b),
                (None, None) => 0.0,
            }
        };
        s.secs.iter().zip(&self.line).map(|(t, &l)| t.unwrap_or_else(|| at(l))).collect()
    }

    /// The estimated work done once this run has finished `cells` cells, and
    /// the whole work: `(w, W)`.
    pub fn done(&self, cells: u64) -> (f64, f64) {
        let Ok(s) = self.state.lock() else { return (0.0, 0.0) };
        let cost = self.costs(&s);
        let total: f64 = cost.iter().sum();
        let finished: f64 = s.secs.iter().zip(&cost).filter(|(t, _)| t.is_some()).map(|(_, c)| c).sum();
        let running = cells.saturating_sub(s.finished * self.line_len);
        let open: Vec<f64> =
            (s.first_open..s.secs.len()).filter(|&j| s.secs[j].is_none()).take(self.threads).map(|j| cost[j]).collect();
        let partial = if open.is_empty() {
            0.0
        } else {
            let c: f64 = open.iter().sum();
            (running as f64 * c / (open.len() as u64 * self.line_len) as f64).min(c)
        };
        ((finished + partial).min(total), total)
    }
}

/// Where a run stands, for a bar or a line ([`Meter::status`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Status {
    /// Cells done, those done before the run (a resume) included.
    pub done: u64,
    /// Cells of the run, those done before included.
    pub total: u64,
    /// Seconds since the run began.
    pub elapsed: f64,
    /// Cells per second this run.
    pub rate: f64,
    /// This run's work done and its whole work, `(w, W)`: estimated
    /// ([`Work`]) when the lines' costs were probed, else in cells.
    pub work: (f64, f64),
    /// Whether `work` is estimated rather than counted in cells.
    pub weighed: bool,
    /// Seconds left ([`eta`]), once any work is done.
    pub left: Option<f64>,
}

/// A run's progress, counted from any thread: its cells, the work they stand
/// for where the lines' costs were probed ([`Work`]), the rate and the time
/// left ([`Meter::status`]). Any front end's bar reads it.
pub struct Meter {
    total: u64,
    already: u64,
    done: std::sync::atomic::AtomicU64,
    start: std::time::Instant,
    work: Option<Work>,
}

impl Status {
    /// The work done in whole percent, rounded down: 100 exactly when all of
    /// it is done (`100 w / W` in floating point can fall just below 100 when
    /// `w = W`, for about one `W` in fifteen).
    pub fn work_percent(&self) -> u64 {
        let (w, total) = self.work;
        match w >= total {
            true => 100,
            false => (100.0 * w / total.max(1e-300)).floor() as u64,
        }
    }
}

impl Meter {
    /// The meter of a run that begins ([`engine::Begin`]): weighed by its
    /// jobs' probed costs where it has them, else counted in cells.
    pub fn new(b: &engine::Begin<'_>) -> Meter {
        let work = b.prior.and_then(|prior| Work::new(b.lines.to_vec(), prior.to_vec(), b.line_len, b.threads));
        Meter {
            total: b.total,
            already: b.done,
            done: std::sync::atomic::AtomicU64::new(b.done),
            start: std::time::Instant::now(),
            work,
        }
    }

    /// Cells of the run, those done before it included.
    pub fn total(&self) -> u64 {
        self.total
    }

    /// Whether the work is weighed by the lines' costs (else counted in cells).
    pub fn weighed(&self) -> bool {
        self.work.is_some()
    }

    /// `cells` more cells are done; returns the cells done.
    pub fn advance(&self, cells: u64) -> u64 {
        self.done.fetch_add(cells, std::sync::atomic::Ordering::Relaxed) + cells
    }

    /// Job `job` (its place in the order taken) is finished, on the thread
    /// that computed it.
    pub fn line_done(&self, job: usize) {
        if let Some(w) = &self.work {
            w.finish_at(job, self.start.elapsed().as_secs_f64());
        }
    }

    /// Where the run stands now.
    pub fn status(&self) -> Status {
        let done = self.done.load(std::sync::atomic::Ordering::Relaxed);
        let elapsed = self.start.elapsed().as_secs_f64();
        let run = done.saturating_sub(self.already);
        let (w, total) = match &self.work {
            // The last cell: done, whatever the last lines are thought to weigh.
            Some(work) if done >= self.total => {
                let (_, total) = work.done(run);
                (total, total)
            }
            Some(work) => work.done(run),
            None => (run as f64, self.total.saturating_sub(self.already) as f64),
        };
        Status {
            done,
            total: self.total,
            elapsed,
            rate: run as f64 / elapsed.max(1e-9),
            work: (w, total),
            weighed: self.work.is_some(),
            left: eta(elapsed, w, total),
        }
    }
}

impl WorkState {
    fn record(&mut self, job: usize, secs: f64) {
        if job >= self.secs.len() || self.secs[job].is_some() {
            return;
        }
        self.secs[job] = Some(secs);
        self.finished += 1;
        while self.first_open < self.secs.len() && self.secs[self.first_open].is_some() {
            self.first_open += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All work done reads 100 %, also for a total whose `100 w / w` falls
    /// just below 100 in floating point (751.5627143418114 is one).
    #[test]
    fn all_the_work_done_is_a_hundred_percent() {
        let at = |w: f64, total: f64| Status {
            done: 1,
            total: 1,
            elapsed: 1.0,
            rate: 1.0,
            work: (w, total),
            weighed: true,
            left: None,
        };
        let total: f64 = 751.5627143418114;
        assert!((100.0 * total / total).floor() < 100.0, "the case this guards against");
        assert_eq!(at(total, total).work_percent(), 100);
        assert_eq!(at(0.999 * total, total).work_percent(), 99);
        assert_eq!(at(0.0, total).work_percent(), 0);
    }

    #[test]
    fn eta_is_the_rate_so_far_applied_to_the_work_left() {
        assert_eq!(eta(0.0, 0.0, 10.0), None);
        assert!((eta(5.0, 2.0, 10.0).unwrap() - 20.0).abs() < 1e-12);
        assert!((eta(5.0, 10.0, 10.0).unwrap()).abs() < 1e-12);
    }

    /// A synthetic run on two workers: a line's time falls smoothly with its
    /// index (20 times from the first to the last), up and down alike; the
    /// probe sees it through noise of a factor of up to 20 either way (as in
    /// the multi-stop reference atlas, whose probed costs correlate 0.33 with
    /// the lines' times) and the lines are taken longest first by the probe. From a tenth of the cells on, the
    /// weighted time left is within 30 % of the time that remains; counting
    /// cells (the weights removed) is more than twice off.
    #[test]
    fn weighted_eta_tracks_the_time_left_where_counting_cells_does_not() {
        let (len, threads, lines) = (10usize, 2usize, 60usize);
        let secs = |l: usize| 0.05 + 0.95 * (-3.0 * l as f64 / lines as f64).exp();
        // Deterministic noise in [1/20, 20].
        let noise = |l: usize, k: usize| 20f64.powf(((l * 7919 + k * 104_729) % 1000) as f64 / 500.0 - 1.0);
        let mut jobs: Vec<(usize, f64)> = (0..lines)
            .flat_map(|l| (0..2).map(move |k| (l, k)))
            .map(|(l, k)| (l, secs(l) * 1000.0 * noise(l, k)))
            .collect();
        jobs.sort_by(|a, b| b.1.total_cmp(&a.1));
        let work =
            Work::new(jobs.iter().map(|j| j.0).collect(), jobs.iter().map(|j| j.1).collect(), len, threads).unwrap();
        // The list schedule: each job to the worker that frees first.
        let mut free = vec![0.0f64; threads];
        let mut ends: Vec<(f64, usize, f64)> = Vec::new();
        for (j, &(l, _)) in jobs.iter().enumerate() {
            let w = (0..threads).min_by(|&a, &b| free[a].total_cmp(&free[b])).unwrap();
            free[w] += secs(l);
            ends.push((free[w], j, secs(l)));
        }
        let makespan = free.iter().copied().fold(0.0, f64::max);
        ends.sort_by(|a, b| a.0.total_cmp(&b.0));
        let cells_total = (jobs.len() * len) as f64;
        let (mut worst_weighted, mut worst_cells) = (1.0f64, 1.0f64);
        for (k, &(t, j, took)) in ends.iter().enumerate() {
            work.finish(j, took);
            let cells = ((k + 1) * len) as u64;
            let left = makespan - t;
            if cells as f64 >= 0.1 * cells_total && left > 0.05 * makespan {
                let (w, total) = work.done(cells);
                let weighted = eta(t, w, total).unwrap();
                let by_cells = eta(t, cells as f64, cells_total).unwrap();
                worst_weighted = worst_weighted.max((weighted / left).max(left / weighted));
                worst_cells = worst_cells.max((by_cells / left).max(left / by_cells));
            }
        }
        assert!(worst_weighted < 1.3, "weighted ETA off by a factor {worst_weighted}");
        assert!(worst_cells > 2.0, "counting cells should be far off here, got {worst_cells}");
    }

    #[test]
    fn a_meter_counts_cells_or_weighs_lines() {
        let b = engine::Begin { total: 10, done: 4, lines: &[], prior: None, line_len: 1, threads: 1 };
        let m = Meter::new(&b);
        assert!(!m.weighed());
        assert_eq!(m.advance(3), 7);
        let s = m.status();
        assert_eq!((s.done, s.total, s.work, s.weighed), (7, 10, (3.0, 6.0), false));
        let prior = [10.0, 30.0];
        let b = engine::Begin { total: 8, done: 0, lines: &[0, 1], prior: Some(&prior), line_len: 4, threads: 2 };
        let m = Meter::new(&b);
        assert!(m.weighed());
        assert_eq!(m.status().work, (0.0, 40.0));
        m.advance(8);
        let (w, total) = m.status().work;
        assert_eq!(w, total, "the last cell: all the work done");
    }

    #[test]
    fn before_any_line_the_probe_weighs() {
        // Jobs of probed costs 10 and 30 running on two workers, 4 cells a line.
        let work = Work::new(vec![0, 1, 2, 3], vec![10.0, 30.0, 2.0, 2.0], 4, 2).unwrap();
        let (w, total) = work.done(0);
        assert!(w.abs() < 1e-12 && (total - 44.0).abs() < 1e-12);
        // 4 cells in flight: a mean of 40 / 8 per cell.
        assert!((work.done(4).0 - 20.0).abs() < 1e-12);
        // Never more than the running lines' own cost.
        assert!((work.done(7).0 - 35.0).abs() < 1e-12);
        assert!((eta(2.0, 11.0, 44.0).unwrap() - 6.0).abs() < 1e-12);
    }

    #[test]
    fn finished_lines_weigh_their_time_and_calibrate_their_neighbours() {
        // Lines 0..=4, one job each, taken in this order; 2 cells a line.
        let work = Work::new(vec![0, 4, 2, 1, 3], vec![1.0; 5], 2, 1).unwrap();
        work.finish(0, 8.0);
        // Line 0 measured: every other line is thought to take as long.
        assert_eq!(work.done(2), (8.0, 40.0));
        work.finish(1, 4.0);
        // Lines 1..3 between 8 s (line 0) and 4 s (line 4): 7, 6, 5; one cell of line 2 running.
        let (w, total) = work.done(5);
        assert!((total - 30.0).abs() < 1e-12, "{total}");
        assert!((w - 15.0).abs() < 1e-12, "{w}");
        assert!((eta(6.0, w, total).unwrap() - 6.0).abs() < 1e-12);
    }
}
