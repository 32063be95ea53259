//! Standard output and standard error that never panic.
//!
//! Standard output carries a command's result (`inspect`, `cell`, …): when
//! the reader goes away (`| head`) the command ends quietly with exit 0, and a
//! full disk or any other write error is one error line (exit 2). A command
//! whose result is a file (`atlas`, `study`, `merge`, `render`) calls [`reports_only`]:
//! what it prints is then a report of that file, dropped silently when it
//! cannot be written, and the exit code is the work's (0 when the file was
//! written and verified: nothing is lost).
//!
//! Standard error carries progress, warnings and the final error line; a
//! closed, full or broken standard error drops them silently (`eprintln!`
//! panics there, exit 101 with a journal left behind).

use anyhow::{anyhow, Result};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether standard output carries only reports of a file written (see the
/// module's doc).
static REPORTS_ONLY: AtomicBool = AtomicBool::new(false);

/// Standard output carries only reports from now on: its write errors and a
/// closed reader are ignored, and the command goes on.
pub fn reports_only() {
    REPORTS_ONLY.store(true, Ordering::Relaxed);
}

/// Writes `text` to standard output.
pub fn text(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(_) if REPORTS_ONLY.load(Ordering::Relaxed) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(anyhow!("standard output: {e}")),
    }
}

/// Writes `text` and a newline to standard output.
pub fn line(text: &str) -> Result<()> {
    self::text(&format!("{text}\n"))
}

/// Writes `text` and a newline to standard error, or nothing when standard
/// error cannot be written (closed, full, a broken pipe): never panics.
pub fn err_line(text: &str) {
    let mut err = std::io::stderr().lock();
    let _ = err.write_all(format!("{text}\n").as_bytes()).and_then(|()| err.flush());
}

/// `println!` through [`line()`], returning its error from the enclosing function.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::out::line(&format!($($arg)*))? };
}

/// `print!` through [`text()`], returning its error from the enclosing function.
macro_rules! outp {
    ($($arg:tt)*) => { $crate::out::text(&format!($($arg)*))? };
}

/// `eprintln!` through [`err_line()`]: never panics, never fails.
macro_rules! errln {
    ($($arg:tt)*) => { $crate::out::err_line(&format!($($arg)*)) };
}

pub(crate) use {errln, outln, outp};
