//! Output formats, chosen by the file's extension: `.png` (bitmap), `.svg`
//! (vector, text as text) and `.pdf` (the SVG converted by svg2pdf, with the
//! same font embedded). Every figure is drawn by one generic function on a
//! plotters drawing area, whatever the format ([`save!`]).

use crate::RenderError;
use std::path::Path;

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Portable Network Graphics (bitmap).
    Png,
    /// Scalable Vector Graphics.
    Svg,
    /// Portable Document Format (vector).
    Pdf,
}

impl Format {
    /// The format of `path` from its extension, or an error naming it.
    pub fn of(path: &Path) -> Result<Format, RenderError> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            Some("pdf") => Ok(Format::Pdf),
            other => Err(RenderError {
                message: format!(
                    "{}: unknown picture format{}; use .png, .svg or .pdf",
                    path.display(),
                    other.map(|e| format!(" '.{e}'")).unwrap_or_default()
                ),
            }),
        }
    }
}

/// Converts an SVG text to a PDF file at `path`, the font included.
pub(crate) fn pdf(svg: &str, path: &Path) -> Result<(), RenderError> {
    let fail = |m: String| RenderError { message: format!("{}: {m}", path.display()) };
    let mut options = svg2pdf::usvg::Options::default();
    let font = crate::font::path()?;
    options.fontdb_mut().load_font_file(&font).map_err(|e| fail(format!("{}: {e}", font.display())))?;
    options.font_family = "DejaVu Sans".into();
    let tree = svg2pdf::usvg::Tree::from_str(svg, &options).map_err(|e| fail(e.to_string()))?;
    let bytes = svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), svg2pdf::PageOptions::default())
        .map_err(|e| fail(e.to_string()))?;
    std::fs::write(path, bytes).map_err(|e| fail(e.to_string()))
}

/// Draws a figure into `$path` in the format of its extension: `$size` in
/// pixels (points for vector formats), `$draw` a call of a generic drawing
/// function with the drawing area bound to `$root`.
macro_rules! save {
    ($path:expr, $size:expr, |$root:ident| $draw:expr) => {{
        use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};
        crate::font::ensure()?;
        match crate::output::Format::of($path)? {
            crate::output::Format::Png => {
                let $root = BitMapBackend::new($path, $size).into_drawing_area();
                $draw?;
                $root.present().map_err(crate::err)
            }
            crate::output::Format::Svg => {
                let $root = SVGBackend::new($path, $size).into_drawing_area();
                $draw?;
                $root.present().map_err(crate::err)
            }
            crate::output::Format::Pdf => {
                let mut svg = String::new();
                {
                    let $root = SVGBackend::with_string(&mut svg, $size).into_drawing_area();
                    $draw?;
                    $root.present().map_err(crate::err)?;
                }
                crate::output::pdf(&svg, $path)
            }
        }
    }};
}

pub(crate) use save;
