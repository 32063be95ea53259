//! Output formats, chosen by the file's extension: `.png` (bitmap), `.svg`
//! (vector, text as text, `font-family="DejaVu Sans, sans-serif"`) and `.pdf`
//! (the SVG converted by svg2pdf, the family mapped to the figures' font,
//! which it embeds: every text stays text). Every figure is drawn by one generic function on a
//! plotters drawing area, whatever the format ([`save!`]).

use crate::error::RenderError;
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
            other => Err(RenderError::new(format!(
                "{}: unknown picture format{}; use .png, .svg or .pdf",
                path.display(),
                other.map(|e| format!(" '.{e}'")).unwrap_or_default()
            ))),
        }
    }
}

/// Converts an SVG text to a PDF file at `path`, the font included, at `dpi`
/// SVG units per inch.
pub(crate) fn pdf(svg: &str, path: &Path, dpi: f64) -> Result<(), RenderError> {
    let fail = |e: Box<dyn std::error::Error + Send + Sync>| RenderError::because(path.display().to_string(), e);
    let mut options = svg2pdf::usvg::Options::default();
    let font = crate::font::path()?;
    let db = options.fontdb_mut();
    db.load_font_file(&font).map_err(|e| RenderError::because(format!("{}: {}", path.display(), font.display()), e))?;
    // The figures name the generic family; it must resolve to the loaded font,
    // or usvg drops every text.
    let family = db.faces().next().and_then(|f| f.families.first()).map(|f| f.0.clone());
    let family = family.ok_or_else(|| {
        RenderError::new(format!("{}: {}: no font family in the file", path.display(), font.display()))
    })?;
    db.set_sans_serif_family(family.clone());
    options.font_family = family;
    let tree = svg2pdf::usvg::Tree::from_str(svg, &options).map_err(|e| fail(Box::new(e)))?;
    let bytes = svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), svg2pdf::PageOptions { dpi: dpi as f32 })
        // svg2pdf's error is not a std::error::Error: its text is kept.
        .map_err(|e| RenderError::new(format!("{}: {e}", path.display())))?;
    std::fs::write(path, bytes).map_err(|e| fail(Box::new(e)))
}

/// An SVG text whose size is stated in millimetres (its user units stay
/// points, through the view box), so that it prints at the figure's size.
pub(crate) fn svg_in_mm(svg: &str, (w, h): (f64, f64)) -> String {
    match svg.find('>') {
        Some(end) if svg.starts_with("<svg") => {
            let head = &svg[..end];
            let sized = head
                .split(' ')
                .map(|attr| {
                    if attr.starts_with("width=") {
                        format!("width=\"{w:.1}mm\"")
                    } else if attr.starts_with("height=") {
                        format!("height=\"{h:.1}mm\"")
                    } else {
                        attr.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join(" ");
            format!("{sized}{}", &svg[end..])
        }
        _ => svg.to_string(),
    }
}

/// Writes RGB pixels as a PNG file at `path` that states its resolution
/// (`dpi`, a pHYs chunk), so that documents place it at its printed size.
pub(crate) fn png(path: &Path, (w, h): (u32, u32), rgb: &[u8], dpi: f64) -> Result<(), RenderError> {
    let fail = |e: Box<dyn std::error::Error + Send + Sync>| RenderError::because(path.display().to_string(), e);
    let file = std::fs::File::create(path).map_err(|e| fail(Box::new(e)))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let per_metre = (dpi / 0.0254).round() as u32;
    encoder.set_pixel_dims(Some(png::PixelDimensions { xppu: per_metre, yppu: per_metre, unit: png::Unit::Meter }));
    let mut writer = encoder.write_header().map_err(|e| fail(Box::new(e)))?;
    writer.write_image_data(rgb).map_err(|e| fail(Box::new(e)))?;
    writer.finish().map_err(|e| fail(Box::new(e)))
}

/// Draws a figure into `$path` in the format of its extension on `$canvas`
/// (a [`crate::page::Canvas`]), `$draw` a call of a generic drawing function
/// with the drawing area bound to `$root`.
macro_rules! save {
    ($path:expr, $canvas:expr, |$root:ident| $draw:expr) => {{
        use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};
        crate::font::ensure()?;
        let size = $canvas.size();
        match crate::output::Format::of($path)? {
            crate::output::Format::Png => {
                let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
                {
                    let $root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                    $draw?;
                    $root.present().map_err(crate::error::err)?;
                }
                crate::output::png($path, size, &rgb, $canvas.dpi)
            }
            format => {
                let mut svg = String::new();
                {
                    let $root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                    $draw?;
                    $root.present().map_err(crate::error::err)?;
                }
                if format == crate::output::Format::Pdf {
                    crate::output::pdf(&svg, $path, $canvas.dpi)
                } else {
                    let svg = $canvas.mm.map_or(svg.clone(), |mm| crate::output::svg_in_mm(&svg, mm));
                    std::fs::write($path, svg)
                        .map_err(|e| crate::error::RenderError::because($path.display().to_string(), e))
                }
            }
        }
    }};
}

pub(crate) use save;
