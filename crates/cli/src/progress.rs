//! Progress of a run: a bar on a terminal, a line at most every few seconds
//! otherwise, nothing with `--quiet`. The rate and the time left come from the
//! cells this run has finished over the time it has run (cells cost very
//! unevenly, so a recent-steps estimate swings by a factor of five); numbers are
//! written for people (`3 650 cells/s`, `2 min 05 s`).

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

/// Progress reporter for `total` cells.
pub struct Bar {
    bar: Option<ProgressBar>,
    total: u64,
    already: u64,
    done: AtomicU64,
    quiet: bool,
    start: Instant,
    last: Mutex<Instant>,
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

impl Bar {
    /// A reporter; `already` cells are done before it starts (resume).
    pub fn new(label: &str, total: u64, already: u64, quiet: bool) -> Bar {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template("{prefix} {bar:40.cyan/blue} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b.set_prefix(label.to_string());
            b.set_position(already);
            b
        });
        let start = Instant::now();
        Bar { bar, total, already, done: AtomicU64::new(already), quiet, start, last: Mutex::new(start) }
    }

    /// `done/total cells (p %), elapsed, rate, time left` at `done` cells.
    fn status(&self, done: u64) -> String {
        let elapsed = self.start.elapsed().as_secs_f64();
        let run = done.saturating_sub(self.already);
        let rate = run as f64 / elapsed.max(1e-9);
        let left = self.total.saturating_sub(done) as f64 / rate;
        format!(
            "{}/{} cells ({} %), {} elapsed, {} cells/s, about {} left",
            thousands(done),
            thousands(self.total),
            done * 100 / self.total.max(1),
            duration(elapsed),
            thousands(rate.round() as u64),
            if run > 0 { duration(left) } else { "?".into() }
        )
    }

    /// Ends the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl Progress for Bar {
    fn advance(&self, cells: u64) {
        let now = self.done.fetch_add(cells, Ordering::Relaxed) + cells;
        if self.quiet {
            return;
        }
        let every = if self.bar.is_some() { BAR_EVERY } else { LINE_EVERY };
        let due = {
            let Ok(mut last) = self.last.lock() else { return };
            let due = last.elapsed() >= every || now == self.total;
            if due {
                *last = Instant::now();
            }
            due
        };
        if !due {
            if let Some(b) = &self.bar {
                b.set_position(now);
            }
            return;
        }
        match &self.bar {
            Some(b) => {
                b.set_position(now);
                b.set_message(self.status(now));
            }
            None => eprintln!("progress: {}", self.status(now)),
        }
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
