//! Standard output that ends quietly when the reader goes away (`| head`: exit
//! 0) and reports a full disk or any other write error as one line.

use anyhow::{anyhow, Result};
use std::io::Write;

/// Writes `text` to standard output.
pub fn text(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(anyhow!("standard output: {e}")),
    }
}

/// Writes `text` and a newline to standard output.
pub fn line(text: &str) -> Result<()> {
    self::text(&format!("{text}\n"))
}

/// `println!` through [`line()`], returning its error from the enclosing function.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::out::line(&format!($($arg)*))? };
}

/// `print!` through [`text()`], returning its error from the enclosing function.
macro_rules! outp {
    ($($arg:tt)*) => { $crate::out::text(&format!($($arg)*))? };
}

pub(crate) use {outln, outp};
