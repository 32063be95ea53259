//! Output formats, chosen by the file's extension: `.png` (bitmap), `.svg`
//! (vector, text as text, `font-family="DejaVu Sans, sans-serif"`) and `.pdf`
//! (the SVG converted by svg2pdf, the family mapped to the figures' font,
//! which it embeds: every text stays text). Every figure is drawn by one generic function on a
//! plotters drawing area, whatever the format ([`save!`]).

use crate::error::RenderError;
use scene::Named;
use std::path::{Path, PathBuf};

scene::named_enum! {
    /// An output format.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Format {
        /// Portable Network Graphics (bitmap).
        Png = "png",
        /// Scalable Vector Graphics.
        Svg = "svg",
        /// Portable Document Format (vector).
        Pdf = "pdf",
    }
}

impl Format {
    /// The format of `path` from its extension, or an error naming it.
    pub fn of(path: &Path) -> Result<Format, RenderError> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        ext.as_deref().and_then(Format::parse).ok_or_else(|| {
            RenderError::new(format!(
                "{}: unknown picture format{}; use .png, .svg or .pdf",
                path.display(),
                ext.map(|e| format!(" '.{e}'")).unwrap_or_default()
            ))
        })
    }

    /// Its media type (`image/png`).
    pub fn media_type(self) -> &'static str {
        match self {
            Format::Png => "image/png",
            Format::Svg => "image/svg+xml",
            Format::Pdf => "application/pdf",
        }
    }
}

/// Where a figure goes: a file, in the format its extension names, or bytes
/// in memory (a picture served by the explorer), in the format given.
#[derive(Debug)]
pub enum Out<'a> {
    /// A file at this path.
    File(&'a Path),
    /// Bytes put into this buffer (what it held before is replaced).
    Bytes(Format, &'a mut Vec<u8>),
}

impl<'a> From<&'a Path> for Out<'a> {
    fn from(path: &'a Path) -> Out<'a> {
        Out::File(path)
    }
}

impl<'a> From<&'a PathBuf> for Out<'a> {
    fn from(path: &'a PathBuf) -> Out<'a> {
        Out::File(path)
    }
}

impl Out<'_> {
    /// The format the figure is drawn in.
    pub(crate) fn format(&self) -> Result<Format, RenderError> {
        match self {
            Out::File(path) => Format::of(path),
            Out::Bytes(format, _) => Ok(*format),
        }
    }

    /// What errors name: the file, or the format drawn in memory.
    pub(crate) fn name(&self) -> String {
        match self {
            Out::File(path) => path.display().to_string(),
            Out::Bytes(format, _) => format!("the {} picture", format.name()),
        }
    }

    /// Puts the encoded figure where it goes.
    pub(crate) fn put(self, bytes: Vec<u8>) -> Result<(), RenderError> {
        match self {
            Out::File(path) => {
                std::fs::write(path, bytes).map_err(|e| RenderError::because(path.display().to_string(), e))
            }
            Out::Bytes(_, buffer) => {
                *buffer = bytes;
                Ok(())
            }
        }
    }
}

/// Converts an SVG text to PDF bytes, the font included, at `dpi` SVG units
/// per inch; errors name `name`.
pub(crate) fn pdf(svg: &str, name: &str, dpi: f64) -> Result<Vec<u8>, RenderError> {
    let fail = |e: Box<dyn std::error::Error + Send + Sync>| RenderError::because(name.to_string(), e);
    let mut options = svg2pdf::usvg::Options::default();
    let font = crate::font::path()?;
    let db = options.fontdb_mut();
    db.load_font_file(&font).map_err(|e| RenderError::because(format!("{name}: {}", font.display()), e))?;
    // The figures name the generic family; it must resolve to the loaded font,
    // or usvg drops every text.
    let family = db.faces().next().and_then(|f| f.families.first()).map(|f| f.0.clone());
    let family =
        family.ok_or_else(|| RenderError::new(format!("{name}: {}: no font family in the file", font.display())))?;
    db.set_sans_serif_family(family.clone());
    options.font_family = family;
    let tree = svg2pdf::usvg::Tree::from_str(svg, &options).map_err(|e| fail(Box::new(e)))?;
    svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), svg2pdf::PageOptions { dpi: dpi as f32 })
        .map(in_stable_order)
        // svg2pdf's error is not a std::error::Error: its text is kept.
        .map_err(|e| RenderError::new(format!("{name}: {e}")))
}

/// The PDF `pdf` with each dictionary of references in one order, so that
/// a figure is the same bytes on every run. svg2pdf writes a resource
/// dictionary's entries (`/xo3 14 0 R`, one per line) in the order of a hash
/// map, which changes from process to process; a dictionary's order has no
/// meaning in PDF. Each dictionary all of whose entries are such lines is
/// sorted; a stream's bytes (`/Length` of them after `stream`) are copied as
/// they are. Lines move only within their object, so every object keeps
/// its offset and the cross-reference table stays true.
fn in_stable_order(pdf: Vec<u8>) -> Vec<u8> {
    let is_reference = |line: &[u8]| {
        let text = line.trim_ascii_start();
        let mut words = text.split(|&c| c == b' ');
        let name =
            words.next().is_some_and(|w| w.len() > 1 && w[0] == b'/' && w[1..].iter().all(u8::is_ascii_alphanumeric));
        let numbers = words.by_ref().take(2).filter(|w| !w.is_empty() && w.iter().all(u8::is_ascii_digit)).count() == 2;
        name && numbers && words.next() == Some(b"R") && words.next().is_none() && text.len() < line.len()
    };
    // Where the line from `at` ends: past its newline, or at the file's end.
    let line_end = |at: usize| pdf[at..].iter().position(|&c| c == b'\n').map_or(pdf.len(), |i| at + i + 1);
    let mut out = Vec::with_capacity(pdf.len());
    let mut length = None;
    let mut at = 0;
    while at < pdf.len() {
        let end = line_end(at);
        let line = &pdf[at..end];
        out.extend_from_slice(line);
        let text = line.strip_suffix(b"\n").unwrap_or(line);
        at = end;
        if let Some(n) = text.trim_ascii().strip_prefix(b"/Length ") {
            length = std::str::from_utf8(n).ok().and_then(|n| n.parse::<usize>().ok());
        } else if text == b"stream" {
            // The stream's bytes, as they are (to its end if its length is unknown).
            let n = length.take().map_or(pdf.len() - at, |n| n.min(pdf.len() - at));
            out.extend_from_slice(&pdf[at..at + n]);
            at += n;
        } else if text.ends_with(b"<<") {
            let mut entries: Vec<&[u8]> = Vec::new();
            let mut next = at;
            loop {
                let end = line_end(next);
                let line = &pdf[next..end];
                let text = line.strip_suffix(b"\n").unwrap_or(line);
                if is_reference(text) && line.ends_with(b"\n") {
                    entries.push(line);
                    next = end;
                } else {
                    if text.trim_ascii() == b">>" && !entries.is_empty() {
                        entries.sort_unstable();
                        entries.iter().for_each(|e| out.extend_from_slice(e));
                        at = next;
                    }
                    break;
                }
            }
        }
    }
    out
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

/// Encodes RGB pixels as PNG bytes that state their resolution (`dpi`, a
/// pHYs chunk), so that documents place the picture at its printed size;
/// errors name `name`.
pub(crate) fn png(name: &str, (w, h): (u32, u32), rgb: &[u8], dpi: f64) -> Result<Vec<u8>, RenderError> {
    let fail = |e: Box<dyn std::error::Error + Send + Sync>| RenderError::because(name.to_string(), e);
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let per_metre = (dpi / 0.0254).round() as u32;
    encoder.set_pixel_dims(Some(png::PixelDimensions { xppu: per_metre, yppu: per_metre, unit: png::Unit::Meter }));
    let mut writer = encoder.write_header().map_err(|e| fail(Box::new(e)))?;
    writer.write_image_data(rgb).map_err(|e| fail(Box::new(e)))?;
    writer.finish().map_err(|e| fail(Box::new(e)))?;
    Ok(bytes)
}

/// The most pixels a side of a PNG may have: a bitmap of 3 bytes a pixel
/// then takes at most 1.2 GB while it is drawn.
pub(crate) const MAX_PNG_SIDE: u32 = 20_000;

/// Refuses a PNG canvas with a side beyond [`MAX_PNG_SIDE`] (a figure whose
/// height follows from its width at a print size the page did not check).
pub(crate) fn check_bitmap(size: (u32, u32)) -> Result<(), RenderError> {
    let side = size.0.max(size.1);
    if side > MAX_PNG_SIDE {
        let why = format!(
            "the figure is {} x {} pixels, more than a PNG may have ({MAX_PNG_SIDE} a side); lower its resolution or its size",
            size.0, size.1
        );
        return Err(RenderError::new(why));
    }
    Ok(())
}

/// Draws a figure to `$out` (an [`Out`], or what converts into one: a path)
/// on `$canvas` (a [`crate::page::Canvas`]), `$draw` a call of a generic
/// drawing function with the drawing area bound to `$root`.
macro_rules! save {
    ($out:expr, $canvas:expr, |$root:ident| $draw:expr) => {{
        use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};
        crate::font::ensure()?;
        let out: crate::output::Out<'_> = $out;
        let name = out.name();
        let size = $canvas.size();
        let bytes = match out.format()? {
            crate::output::Format::Png => {
                crate::output::check_bitmap(size)?;
                let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
                {
                    let $root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                    $draw?;
                    $root.present().map_err(crate::error::err)?;
                }
                crate::output::png(&name, size, &rgb, $canvas.dpi)?
            }
            format => {
                let mut svg = String::new();
                {
                    let $root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                    $draw?;
                    $root.present().map_err(crate::error::err)?;
                }
                if format == crate::output::Format::Pdf {
                    crate::output::pdf(&svg, &name, $canvas.dpi)?
                } else {
                    $canvas.mm.map_or(svg.clone(), |mm| crate::output::svg_in_mm(&svg, mm)).into_bytes()
                }
            }
        };
        out.put(bytes)
    }};
}

pub(crate) use save;

#[cfg(test)]
mod tests {
    use super::*;

    /// A figure drawn to bytes is the file drawn to a path, byte for byte, in
    /// every format; the format of a path is its extension's.
    #[test]
    fn bytes_are_the_file() {
        // One folder however often the tests run (emptied first), not one a run.
        let dir = std::env::temp_dir().join("vibroatlas-render-out");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let points = [("fast".to_string(), 2000.0, 0.98), ("precise".to_string(), 300.0, 1.0)];
        for &format in Format::ALL {
            let path = dir.join(format!("trade.{}", format.name().to_uppercase()));
            assert_eq!(Format::of(&path).unwrap(), format);
            crate::trade(&points, &path).unwrap();
            let mut bytes = vec![1, 2, 3];
            crate::trade(&points, Out::Bytes(format, &mut bytes)).unwrap();
            let file = std::fs::read(&path).unwrap();
            assert!(bytes == file, "{format}");
        }
        let unknown = Format::of(Path::new("figure.gif")).unwrap_err().to_string();
        assert_eq!(unknown, "render: figure.gif: unknown picture format '.gif'; use .png, .svg or .pdf");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A dictionary of references comes out sorted, whatever order it was
    /// written in; a stream's bytes, other dictionaries and the length of
    /// the file stay as they were.
    #[test]
    fn dictionaries_of_references_come_out_in_one_order() {
        let pdf = |entries: &[&str], data: &str| {
            let head = "%PDF-1.7\n4 0 obj\n<<\n  /Type /Page\n  /Resources <<\n    /XObject <<\n";
            let tail = "    >>\n  >>\n>>\nendobj\n5 0 obj\n<<\n  /Length 27\n>>\nstream\n";
            let lines: String = entries.iter().map(|e| format!("      {e}\n")).collect();
            format!("{head}{lines}{tail}{data}\nendstream\nendobj\n").into_bytes()
        };
        // The stream's bytes look like a dictionary to sort: they are kept.
        let data = "<<\n  /b 2 0 R\n  /a 1 0 R\n>>";
        assert_eq!(data.len(), 27);
        let one = pdf(&["/xo15 38 0 R", "/xo0 8 0 R", "/xo3 14 0 R"], data);
        let other = pdf(&["/xo3 14 0 R", "/xo15 38 0 R", "/xo0 8 0 R"], data);
        assert_ne!(one, other);
        let (one, other) = (in_stable_order(one.clone()), in_stable_order(other));
        assert_eq!(one, other);
        assert_eq!(one, pdf(&["/xo0 8 0 R", "/xo15 38 0 R", "/xo3 14 0 R"], data));
        // A dictionary with anything but references is left as it is.
        let mixed = b"<<\n  /b 2 0 R\n  /Type /Page\n  /a 1 0 R\n>>\n".to_vec();
        assert_eq!(in_stable_order(mixed.clone()), mixed);
    }

    /// The same figure drawn twice, in two processes' hash orders as in one,
    /// is the same PDF.
    #[test]
    fn a_pdf_is_the_same_bytes_each_time() {
        let points: Vec<(String, f64, f64)> =
            (0..12).map(|i| (format!("preset {i}"), 100.0 * (i + 1) as f64, 0.9 + 0.008 * i as f64)).collect();
        let draw = || {
            let mut bytes = Vec::new();
            crate::trade(&points, Out::Bytes(Format::Pdf, &mut bytes)).unwrap();
            bytes
        };
        let first = draw();
        assert!((0..5).all(|_| draw() == first));
    }
}
