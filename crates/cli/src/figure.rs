//! Figure options shared by every command that draws (`--size`, `--font-size`,
//! `--dpi`), checked into a [`render::Page`].

use crate::args::FigureArgs;
use anyhow::{anyhow, Result};
use render::{Format, Page, PageError, PageOption};
use std::path::{Path, PathBuf};

/// The page of the figure options: a print size, or each figure's screen size.
pub fn page(f: &FigureArgs) -> Result<Page> {
    Page::of(f.size.as_deref(), f.font_size, f.dpi).map_err(page_error)
}

/// A page option's error, naming its flag.
fn page_error(e: PageError) -> anyhow::Error {
    let flag = match e.option() {
        PageOption::Size => "--size",
        PageOption::FontSize => "--font-size",
        PageOption::Dpi => "--dpi",
    };
    let advice = if matches!(e, PageError::WithoutSize(_)) { "; give --size too" } else { "" };
    anyhow!("{flag}: {e}{advice}")
}

/// Checks, before any work, that the picture asked for with `flag` (if any)
/// has a format (`.png`, `.svg`, `.pdf`) and may be written there (a file
/// name in a folder that exists, not a directory, a pipe or a device: a pipe
/// would block the run, nor one of the command's `inputs`), and for a PNG
/// that `page` fits one, so that a wrong name is refused up front, naming
/// the flag and the user's file.
pub fn check(flag: &str, path: Option<&PathBuf>, inputs: &[&Path], page: &Page) -> Result<()> {
    match path {
        Some(p) => {
            // Where first: a folder given as the picture is a folder, not a format.
            output(flag, Some(p), inputs)?;
            match Format::of(p).map_err(|e| anyhow!("{flag}: {e}"))? {
                Format::Png => page.check_png().map_err(page_error),
                _ => Ok(()),
            }
        }
        None => Ok(()),
    }
}

/// Checks that an output file asked for with `flag` (if any) may be written
/// at its path, as [`check`] does for a picture (a trace's CSV).
pub fn output(flag: &str, path: Option<&PathBuf>, inputs: &[&Path]) -> Result<()> {
    match path {
        Some(p) => store::check_output(p, inputs).map_err(|e| anyhow!("{flag}: {e}")),
        None => Ok(()),
    }
}
