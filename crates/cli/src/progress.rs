//! Progress of a run: a bar on a terminal, a line at most every few seconds
//! otherwise (`VIBROATLAS_PROGRESS_EVERY`: another interval, in seconds),
//! nothing with `--quiet`. Numbers are written for people (`3 650 cells/s`,
//! `2 min 05 s`). What they say is counted by [`crate::eta::Meter`]: the cells
//! done, and where the scheduler probed the lines' costs the work they stand
//! for, from which the time left is estimated (see [`crate::eta::Work`]: counting
//! cells says the first tenth of an atlas's cells took a tenth of the time,
//! when the most expensive lines, computed first, took a third).

use crate::eta::{Meter, Status};
use engine::Begin;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
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

/// A run's progress on standard error.
pub struct Bar {
    bar: Option<ProgressBar>,
    meter: Meter,
    quiet: bool,
    last: Mutex<Instant>,
    every: Duration,
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
    /// The bar of a run called `label` that begins (`w`: cells done before it
    /// starts on a resume, probed costs).
    pub fn new(label: &str, w: &Begin<'_>, quiet: bool) -> Bar {
        let meter = Meter::new(w);
        let bar = terminal_bar(label, if meter.weighed() { BAR_STEPS } else { w.total }, quiet);
        if let (Some(b), false) = (&bar, meter.weighed()) {
            b.set_position(w.done);
        }
        let every = if bar.is_some() { BAR_EVERY } else { line_every() };
        Bar { bar, meter, quiet, last: Mutex::new(Instant::now()), every }
    }

    /// `done/total cells (p %), [work q %,] elapsed, rate, time left`.
    fn status(s: &Status) -> String {
        let weighed = match s.weighed {
            true => format!(", work {} %", s.work_percent()),
            false => String::new(),
        };
        format!(
            "{}/{} cells ({} %){weighed}, {} elapsed, {} cells/s, about {} left",
            thousands(s.done),
            thousands(s.total),
            s.done * 100 / s.total.max(1),
            duration(s.elapsed),
            thousands(s.rate.round() as u64),
            s.left.map_or("?".into(), duration)
        )
    }

    /// Ends the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }

    /// `cells` more cells are done.
    fn advance(&self, cells: u64) {
        let now = self.meter.advance(cells);
        if self.quiet {
            return;
        }
        let weighed = self.meter.weighed();
        if !due(&self.last, self.every, now == self.meter.total()) {
            if let (Some(b), false) = (&self.bar, weighed) {
                b.set_position(now);
            }
            return;
        }
        let s = self.meter.status();
        match &self.bar {
            Some(b) => {
                let (w, total) = s.work;
                b.set_position(if weighed { ((w / total.max(1e-300)) * BAR_STEPS as f64).round() as u64 } else { now });
                b.set_message(Bar::status(&s));
            }
            None => crate::out::errln!("progress: {}", Bar::status(&s)),
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
    fn begin(&self, w: &Begin<'_>) {
        let _ = self.bar.set(Bar::new(&self.label, w, self.quiet));
    }
    fn advance(&self, cells: u64) {
        if let Some(b) = self.bar.get() {
            b.advance(cells);
        }
    }
    fn line_done(&self, job: usize) {
        if let Some(b) = self.bar.get() {
            b.meter.line_done(job);
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
