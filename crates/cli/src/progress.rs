//! Progress of a run: a bar on a terminal, a line at most every few seconds
//! otherwise (`VIBROATLAS_PROGRESS_EVERY`: another interval, in seconds),
//! nothing with `--quiet`. Numbers are written for people (`3 650 cells/s`,
//! `2 min 05 s`).
//!
//! The time left is the time run so far times the work left over the work
//! done, `t (W - w) / w`. Cells cost very unevenly (a recent-steps estimate
//! swings by a factor of five), and an atlas's lines are computed the most
//! expensive first, so counting cells says the first tenth of the cells took
//! a tenth of the time when it took a third (the ETA was 2 to 4 times too
//! long until three quarters of the run). Where the scheduler probed the
//! lines' costs (and ordered them by it), the work is counted per line
//! ([`Work`]): the lines finished weigh the time they took, the others the
//! time lines near them took; elsewhere in cells.

use engine::{eta, Work};
use grid::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Shortest time between two progress lines when standard error is not a terminal.
const LINE_EVERY: Duration = Duration::from_secs(5);
/// Shortest time between two updates of the terminal bar's text.
const BAR_EVERY: Duration = Duration::from_millis(200);
/// Steps of a terminal bar that shows estimated work rather than cells.
const BAR_STEPS: u64 = 1000;

/// The interval between two progress lines off a terminal: 5 s, or
/// `VIBROATLAS_PROGRESS_EVERY` seconds (for tests and logs).
fn line_every() -> Duration {
    std::env::var("VIBROATLAS_PROGRESS_EVERY")
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0)
        .map_or(LINE_EVERY, Duration::from_secs_f64)
}

/// Progress reporter for `total` cells.
pub struct Bar {
    bar: Option<ProgressBar>,
    total: u64,
    already: u64,
    done: AtomicU64,
    quiet: bool,
    start: Instant,
    last: Mutex<Instant>,
    every: Duration,
    work: Option<Work>,
}

/// `n` with a thin space between groups of three digits (`116 032`).
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// A duration for people: `9.8 s`, `2 min 05 s`, `1 h 02 min`.
pub fn duration(s: f64) -> String {
    if !s.is_finite() {
        return "?".into();
    }
    let whole = s.round() as u64;
    match whole {
        _ if s < 60.0 => format!("{s:.1} s"),
        _ if whole < 3600 => format!("{} min {:02} s", whole / 60, whole % 60),
        _ => format!("{} h {:02} min", whole / 3600, whole % 3600 / 60),
    }
}

/// A terminal bar of `len` steps labelled `label`, or `None` off a terminal
/// or when quiet.
fn terminal_bar(label: &str, len: u64, quiet: bool) -> Option<ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::new(len);
        b.set_style(
            ProgressStyle::with_template("{prefix} {bar:40.cyan/blue} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b.set_prefix(label.to_string());
        b
    })
}

/// Whether a report is due: `every` has passed since the last one (which it
/// then becomes), or `last_one` (the end).
fn due(last: &Mutex<Instant>, every: Duration, last_one: bool) -> bool {
    let Ok(mut last) = last.lock() else { return false };
    let due = last.elapsed() >= every || last_one;
    if due {
        *last = Instant::now();
    }
    due
}

impl Bar {
    /// A reporter; `already` cells are done before it starts (resume). The
    /// time left is counted in the estimated `work` of the cells this run
    /// computes (when given, reported by [`Bar::finish_job`]), else in cells.
    pub fn weighted(label: &str, total: u64, already: u64, quiet: bool, work: Option<Work>) -> Bar {
        let bar = terminal_bar(label, if work.is_some() { BAR_STEPS } else { total }, quiet);
        if let (Some(b), None) = (&bar, &work) {
            b.set_position(already);
        }
        let start = Instant::now();
        let every = if bar.is_some() { BAR_EVERY } else { line_every() };
        Bar { bar, total, already, done: AtomicU64::new(already), quiet, start, last: Mutex::new(start), every, work }
    }

    /// Job `job` of the weighted work (its place in the order taken) is
    /// finished, on the thread that computed it.
    pub fn finish_job(&self, job: usize) {
        if let Some(w) = &self.work {
            w.finish_at(job, self.start.elapsed().as_secs_f64());
        }
    }

    /// This run's work done and to do: estimated units, or cells.
    fn work(&self, done: u64) -> (f64, f64) {
        let run = done.saturating_sub(self.already);
        match &self.work {
            // The last cell: done, whatever the last lines are thought to weigh.
            Some(w) if done >= self.total => {
                let (_, total) = w.done(run);
                (total, total)
            }
            Some(w) => w.done(run),
            None => (run as f64, self.total.saturating_sub(self.already) as f64),
        }
    }

    /// `done/total cells (p %), [work q %,] elapsed, rate, time left` at
    /// `done` cells and `elapsed` seconds.
    fn status(&self, done: u64, elapsed: f64) -> String {
        let run = done.saturating_sub(self.already);
        let rate = run as f64 / elapsed.max(1e-9);
        let (w, total) = self.work(done);
        let weighed = match &self.work {
            Some(_) => format!(", work {} %", (100.0 * w / total.max(1e-300)).floor() as u64),
            None => String::new(),
        };
        format!(
            "{}/{} cells ({} %){weighed}, {} elapsed, {} cells/s, about {} left",
            thousands(done),
            thousands(self.total),
            done * 100 / self.total.max(1),
            duration(elapsed),
            thousands(rate.round() as u64),
            eta(elapsed, w, total).map_or("?".into(), duration)
        )
    }

    /// Ends the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }

    /// Where the terminal bar stands at `done` cells.
    fn position(&self, done: u64) -> u64 {
        match &self.work {
            Some(_) => {
                let (w, total) = self.work(done);
                ((w / total.max(1e-300)) * BAR_STEPS as f64).round() as u64
            }
            None => done,
        }
    }
}

impl Progress for Bar {
    fn advance(&self, cells: u64) {
        let now = self.done.fetch_add(cells, Ordering::Relaxed) + cells;
        if self.quiet {
            return;
        }
        if !due(&self.last, self.every, now == self.total) {
            if let (Some(b), None) = (&self.bar, &self.work) {
                b.set_position(now);
            }
            return;
        }
        let status = self.status(now, self.start.elapsed().as_secs_f64());
        match &self.bar {
            Some(b) => {
                b.set_position(self.position(now));
                b.set_message(status);
            }
            None => crate::out::errln!("progress: {status}"),
        }
    }
}

/// Progress of `curves`: seeds done (traced or skipped) of all, seeds traced,
/// curves kept; a bar on a terminal, a `progress:` line at most every 5 s
/// otherwise (standard error only).
pub struct Seeds {
    bar: Option<ProgressBar>,
    start: Instant,
    last: Mutex<Instant>,
    every: Duration,
}

impl Seeds {
    /// A reporter for `total` seeds.
    pub fn new(total: usize) -> Seeds {
        let bar = terminal_bar("curves", total as u64, false);
        let start = Instant::now();
        let every = if bar.is_some() { BAR_EVERY } else { line_every() };
        Seeds { bar, start, last: Mutex::new(start), every }
    }

    /// Reports a tally (at most every interval, and at the end).
    pub fn report(&self, t: grid::curves::Tally) {
        if !due(&self.last, self.every, t.done == t.total) {
            return;
        }
        let status = format!(
            "{}/{} seeds ({} %), {} traced, {} curves kept, {} elapsed",
            thousands(t.done as u64),
            thousands(t.total as u64),
            t.done * 100 / t.total.max(1),
            thousands(t.traced as u64),
            t.kept,
            duration(self.start.elapsed().as_secs_f64())
        );
        match &self.bar {
            Some(b) => {
                b.set_position(t.done as u64);
                b.set_message(status);
            }
            None => crate::out::errln!("progress: {status}"),
        }
    }

    /// Ends the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// A run's progress on standard error: a [`Bar`] made when the run begins
/// (weighted by the probed costs of its lines where it has them), nothing
/// with `quiet`; warnings as `warning:` lines.
pub struct Shown {
    label: String,
    quiet: bool,
    bar: std::sync::OnceLock<Bar>,
}

impl Shown {
    /// Progress of a run called `label` (`atlas`, `sweep`).
    pub fn new(label: &str, quiet: bool) -> Shown {
        Shown { label: label.to_string(), quiet, bar: std::sync::OnceLock::new() }
    }
}

impl engine::Observer for Shown {
    fn begin(&self, w: &engine::Begin<'_>) {
        let work = w.prior.and_then(|prior| Work::new(w.lines.to_vec(), prior.to_vec(), w.line_len, w.threads));
        let _ = self.bar.set(Bar::weighted(&self.label, w.total, w.done, self.quiet, work));
    }
    fn advance(&self, cells: u64) {
        if let Some(b) = self.bar.get() {
            b.advance(cells);
        }
    }
    fn line_done(&self, job: usize) {
        if let Some(b) = self.bar.get() {
            b.finish_job(job);
        }
    }
    fn finish(&self) {
        if let Some(b) = self.bar.get() {
            b.finish();
        }
    }
    fn warn(&self, message: &str) {
        crate::out::errln!("warning: {message}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(thousands(3650), "3 650");
        assert_eq!(thousands(116_032), "116 032");
        assert_eq!(thousands(12), "12");
        assert_eq!(duration(9.84), "9.8 s");
        assert_eq!(duration(125.0), "2 min 05 s");
        assert_eq!(duration(3720.0), "1 h 02 min");
    }
}
