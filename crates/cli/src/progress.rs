//! Progress of a run: an indicatif bar (cells/s, ETA) on a terminal, a line at
//! every tenth otherwise, nothing with `--quiet`.

use grid::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Progress reporter for `total` cells.
pub struct Bar {
    bar: Option<ProgressBar>,
    total: u64,
    done: AtomicU64,
    quiet: bool,
    start: Instant,
}

impl Bar {
    /// A reporter; `already` cells are done before it starts (resume).
    pub fn new(label: &str, total: u64, already: u64, quiet: bool) -> Bar {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template("{prefix} {bar:40.cyan/blue} {pos}/{len} cells  {per_sec}  ETA {eta}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b.set_prefix(label.to_string());
            b.set_position(already);
            b
        });
        Bar { bar, total, done: AtomicU64::new(already), quiet, start: Instant::now() }
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
        let before = self.done.fetch_add(cells, Ordering::Relaxed);
        let now = before + cells;
        match &self.bar {
            Some(b) => b.set_position(now),
            None if !self.quiet && self.total >= 10 && (before * 10 / self.total) != (now * 10 / self.total) => {
                let rate = now as f64 / self.start.elapsed().as_secs_f64().max(1e-9);
                eprintln!("progress: {now}/{} cells ({}%), {rate:.0} cells/s", self.total, now * 100 / self.total);
            }
            None => {}
        }
    }
}
