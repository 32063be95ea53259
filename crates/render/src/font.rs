//! The font of every picture: DejaVu Sans from Debian's `fonts-dejavu-core`
//! (installed by `scripts/setup.sh`), registered once with plotters.

use crate::error::RenderError;
use std::sync::OnceLock;

const CANDIDATES: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
];

static FONT: OnceLock<Result<(), String>> = OnceLock::new();

/// The font file (`VIBROATLAS_FONT`, or DejaVu Sans where Debian puts it).
pub fn path() -> Result<std::path::PathBuf, RenderError> {
    std::env::var("VIBROATLAS_FONT")
        .ok()
        .into_iter()
        .chain(CANDIDATES.iter().map(|s| s.to_string()))
        .map(std::path::PathBuf::from)
        .find(|p| p.exists())
        .ok_or_else(|| {
            RenderError::new(
                "no TrueType font found: install fonts-dejavu-core (scripts/setup.sh does) or set VIBROATLAS_FONT",
            )
        })
}

/// The font family every figure names: DejaVu Sans, which the layout is
/// measured with, and the generic family where it is missing (SVG viewers).
pub const FAMILY: &str = "DejaVu Sans, sans-serif";

/// Registers the font as [`FAMILY`] (once).
pub fn ensure() -> Result<(), RenderError> {
    FONT.get_or_init(|| {
        let path = path().map_err(|e| e.what().to_string())?;
        let path = path.display().to_string();
        let bytes = std::fs::read(&path).map_err(|e| format!("{path}: {e}"))?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font(FAMILY, plotters::style::FontStyle::Normal, bytes)
            .map_err(|_| format!("{path}: not a usable font"))
    })
    .clone()
    .map_err(RenderError::new)
}
