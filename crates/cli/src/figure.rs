//! Figure options shared by every command that draws (`--size`, `--font-size`,
//! `--dpi`), checked into a [`render::Page`].

use crate::args::FigureArgs;
use anyhow::{anyhow, bail, Result};
use render::{Page, PrintSize};

/// The page of the figure options: a print size, or each figure's screen size.
pub fn page(f: &FigureArgs) -> Result<Page> {
    let Some(size) = &f.size else {
        if f.font_size.is_some() {
            bail!("--font-size: sets the text of a printed figure; give --size too");
        }
        if f.dpi.is_some() {
            bail!("--dpi: sets the resolution of a printed figure; give --size too");
        }
        return Ok(Page::screen());
    };
    let size: PrintSize = size.parse().map_err(|e: String| anyhow!("--size: {e}"))?;
    if let Some(pt) = f.font_size {
        if !(render::MIN_TEXT_PT..=24.0).contains(&pt) {
            bail!("--font-size: must be in [{}, 24] pt, got {pt}", render::MIN_TEXT_PT);
        }
    }
    let dpi = match f.dpi {
        Some(d) if !(72..=1200).contains(&d) => bail!("--dpi: must be in [72, 1200], got {d}"),
        Some(d) => Some(d as u32),
        None => None,
    };
    Ok(Page::print(size, f.font_size, dpi)?)
}
