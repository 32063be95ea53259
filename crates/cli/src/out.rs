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

/// Writes the command's error line, `error: MESSAGE`, to standard error,
/// with what it echoes kept readable ([`readable`]).
pub fn error(message: &str) {
    let words: Vec<String> = message.split(' ').map(readable).collect();
    err_line(&format!("error: {}", words.join(" ")));
}

/// Longest word an error line echoes whole.
const LONGEST_WORD: usize = 200;
/// Characters kept of a longer word.
const WORD_KEPT: usize = 60;

/// A word of an error line as a reader takes it in: a number longer than 24
/// characters (`1e308` written out in full) in exponent form, any other word
/// longer than [`LONGEST_WORD`] characters (a 100 000-character name) cut to
/// its first [`WORD_KEPT`] and its length; punctuation around it kept.
fn readable(word: &str) -> String {
    let edge = |c: char| ",;:()'\"".contains(c);
    let core = word.trim_start_matches(edge).trim_end_matches(edge);
    let start = word.len() - word.trim_start_matches(edge).len();
    let (before, after) = (&word[..start], &word[start + core.len()..]);
    let length = core.chars().count();
    match core.parse::<f64>() {
        Ok(x) if length > 24 && x.is_finite() && core.bytes().all(|b| b"0123456789.eE+-".contains(&b)) => {
            format!("{before}{x:e}{after}")
        }
        _ if length > LONGEST_WORD => {
            let kept: String = core.chars().take(WORD_KEPT).collect();
            format!("{before}{kept}… ({length} characters){after}")
        }
        _ => word.to_string(),
    }
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

#[cfg(test)]
mod tests {
    use super::readable;

    #[test]
    fn echoed_words_stay_readable() {
        let big = format!("1{}", "0".repeat(308));
        assert_eq!(readable(&big), "1e308");
        assert_eq!(readable(&format!("'{big}',")), "'1e308',");
        assert_eq!(readable(&format!("0.{}1", "0".repeat(30))), "1e-31");
        // Digits too many for a finite number are a word, cut like any other.
        let digits = "9".repeat(100_000);
        assert_eq!(readable(&digits), format!("{}… (100000 characters)", "9".repeat(60)));
        let name = "a".repeat(100_000);
        assert_eq!(readable(&format!("{name}=1:")), format!("{}… (100002 characters):", "a".repeat(60)));
        for kept in ["omega", "0.31459999999999999", "/a/b.h5:", "1-3-3", ""] {
            assert_eq!(readable(kept), kept);
        }
    }
}
