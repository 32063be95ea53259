//! The size of a figure: a screen canvas in pixels (each figure's own default,
//! text 15 px), or a printed page of a given width and height in millimetres
//! with text in points (`--size single|double|WxH`, `--font-size`, `--dpi`).
//!
//! On a page, lengths are points (1 pt = 1/72 in = 25.4/72 mm): a vector
//! figure's canvas is measured in tenths of a point (plotters writes whole
//! units; an SVG states its size in mm, a PDF page is exactly that size) and a
//! PNG has `dpi / 72` pixels per point. Every
//! text size is a multiple of the body size (`--font-size`, 8 pt by default),
//! and never below [`MIN_TEXT_PT`]; every margin, legend row and label area is
//! measured in body text heights, so the layout keeps its proportions to the
//! text at any size.

use crate::error::RenderError;
use crate::output::{Format, MAX_PNG_SIDE};
use plotters::style::{FontDesc, IntoFont};

/// A plotters backend whose errors can be kept as a [`RenderError`]'s source.
pub(crate) trait Backend: plotters::prelude::DrawingBackend<ErrorType: 'static> {}
impl<B: plotters::prelude::DrawingBackend<ErrorType: 'static>> Backend for B {}

/// Width of one journal column (mm).
pub const SINGLE_MM: f64 = 86.0;
/// Width of a figure across both columns of a journal page (mm).
pub const DOUBLE_MM: f64 = 178.0;
/// No text of a printed figure is smaller than this (points).
pub const MIN_TEXT_PT: f64 = 6.0;
/// Millimetres per point.
const MM_PER_PT: f64 = 25.4 / 72.0;
/// Units of a printed vector figure per point: plotters writes whole units,
/// so a unit of 0.1 pt keeps cells and curves where they belong.
const VECTOR_UNITS_PER_PT: f64 = 10.0;

/// A printed size: the width, and the height unless the figure chooses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrintSize {
    /// Width on the page (mm).
    pub width_mm: f64,
    /// Height on the page (mm); `None`: the figure's own proportion.
    pub height_mm: Option<f64>,
}

impl std::str::FromStr for PrintSize {
    type Err = String;

    /// `single` (one column, 86 mm wide), `double` (two columns, 178 mm) or
    /// `WxH` in millimetres (`120x80`), each between 20 and 1000 mm.
    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "single" => return Ok(PrintSize { width_mm: SINGLE_MM, height_mm: None }),
            "double" => return Ok(PrintSize { width_mm: DOUBLE_MM, height_mm: None }),
            _ => {}
        }
        let bad = || format!("expected single, double or WxH in millimetres (e.g. 120x80), got '{text}'");
        let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
        let mm = |s: &str| -> Result<f64, String> {
            let v: f64 = s.trim().parse().map_err(|_| bad())?;
            if (20.0..=1000.0).contains(&v) {
                Ok(v)
            } else {
                Err(format!("{v} mm is outside 20..1000 mm"))
            }
        };
        Ok(PrintSize { width_mm: mm(w)?, height_mm: Some(mm(h)?) })
    }
}

/// An option of a figure's size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PageOption {
    /// The print size ([`PrintSize`]).
    Size,
    /// The body text size (points).
    FontSize,
    /// The resolution of a printed PNG (dots per inch).
    Dpi,
}

/// Figure options that make no page: the option at fault and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PageError {
    /// A text size or a resolution without a print size (only a printed
    /// figure has them).
    #[error("sets the {} of a printed figure", if *.0 == PageOption::FontSize { "text" } else { "resolution" })]
    WithoutSize(PageOption),
    /// A value that cannot be read or is out of range.
    #[error("{1}")]
    Value(PageOption, String),
}

impl PageError {
    /// The option at fault.
    pub fn option(&self) -> PageOption {
        match self {
            PageError::WithoutSize(o) | PageError::Value(o, _) => *o,
        }
    }
}

/// How large a figure is drawn: on screen (today's pixel canvases) or on a
/// printed page.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Page {
    print: Option<PrintSize>,
    font_pt: f64,
    dpi: f64,
}

impl Default for Page {
    fn default() -> Self {
        Page::screen()
    }
}

impl Page {
    /// Body text on a page by default (points).
    pub const FONT_PT: f64 = 8.0;
    /// Resolution of a printed PNG by default (dots per inch).
    pub const DPI: u32 = 300;

    /// Each figure's screen canvas (pixels), body text 15 px.
    pub fn screen() -> Page {
        Page { print: None, font_pt: Page::FONT_PT, dpi: 72.0 * 15.0 / Page::FONT_PT }
    }

    /// A printed page of `size`, body text `font_pt` points (6 to 24; default
    /// 8) and, for PNG, `dpi` dots per inch (72 to 1200; default 300).
    pub fn print(size: PrintSize, font_pt: Option<f64>, dpi: Option<i64>) -> Result<Page, PageError> {
        let font_pt = font_pt.unwrap_or(Page::FONT_PT);
        if !(MIN_TEXT_PT..=24.0).contains(&font_pt) {
            let why = format!("must be in [{MIN_TEXT_PT}, 24] pt, got {font_pt}");
            return Err(PageError::Value(PageOption::FontSize, why));
        }
        let dpi = dpi.unwrap_or(Page::DPI.into());
        if !(72..=1200).contains(&dpi) {
            return Err(PageError::Value(PageOption::Dpi, format!("must be in [72, 1200], got {dpi}")));
        }
        Ok(Page { print: Some(size), font_pt, dpi: dpi as f64 })
    }

    /// Refuses a printed page too large for a PNG at its resolution (a side
    /// beyond 20 000 pixels), before any work; a height that
    /// follows from the figure's proportion is checked as it is drawn.
    pub fn check_png(&self) -> Result<(), PageError> {
        let Some(size) = self.print else { return Ok(()) };
        let side = size.width_mm.max(size.height_mm.unwrap_or(0.0));
        let px = pixels(side, self.dpi / 72.0);
        if px > MAX_PNG_SIDE {
            let why = format!(
                "{side} mm at {} dpi is {px} pixels a side, more than a PNG may have ({MAX_PNG_SIDE}); lower it or the size",
                self.dpi
            );
            return Err(PageError::Value(PageOption::Dpi, why));
        }
        Ok(())
    }

    /// The page of a figure's options: a printed page of `size` (`single`,
    /// `double`, `WxH`: [`PrintSize`]) with [`Page::print`]'s text size and
    /// resolution, or without a size each figure's screen size, which takes
    /// neither.
    pub fn of(size: Option<&str>, font_pt: Option<f64>, dpi: Option<i64>) -> Result<Page, PageError> {
        match size {
            Some(size) => {
                let size: PrintSize = size.parse().map_err(|e| PageError::Value(PageOption::Size, e))?;
                Page::print(size, font_pt, dpi)
            }
            None if font_pt.is_some() => Err(PageError::WithoutSize(PageOption::FontSize)),
            None if dpi.is_some() => Err(PageError::WithoutSize(PageOption::Dpi)),
            None => Ok(Page::screen()),
        }
    }

    /// The printed size, if any.
    pub fn print_size(&self) -> Option<PrintSize> {
        self.print
    }

    /// The canvas of a figure in `format`: `screen` pixels on screen; on a
    /// page its width, and its height or `height_mm(width_mm)`.
    pub(crate) fn canvas(&self, format: Format, screen: (u32, u32), height_mm: impl Fn(f64) -> f64) -> Canvas {
        let glyph = if format == Format::Png { GLYPH_PNG } else { GLYPH_SVG };
        match self.print {
            None => {
                let pt = self.dpi / 72.0;
                let (width, height) = screen;
                Canvas { width, height, pt, font_pt: self.font_pt, glyph, mm: None, dpi: 72.0 }
            }
            Some(s) => {
                let pt = if format == Format::Png { self.dpi / 72.0 } else { VECTOR_UNITS_PER_PT };
                let h = s.height_mm.unwrap_or_else(|| height_mm(s.width_mm));
                let (width, height) = (pixels(s.width_mm, pt), pixels(h, pt));
                Canvas { width, height, pt, font_pt: self.font_pt, glyph, mm: Some((s.width_mm, h)), dpi: pt * 72.0 }
            }
        }
    }
}

/// The canvas units (pixels of a PNG) of `mm` on the page at `pt` units a
/// point, at least one.
fn pixels(mm: f64, pt: f64) -> u32 {
    (mm / MM_PER_PT * pt).round().max(1.0) as u32
}

/// plotters' font size is the glyph box, not the em: SVG text is written at
/// `size / 1.24`; bitmaps scale DejaVu Sans's ascent-to-descent height
/// (1.164 em) to `size`.
const GLYPH_SVG: f64 = 1.24;
const GLYPH_PNG: f64 = 1.164;

/// One figure's canvas: its size in pixels (points for vector formats on a
/// page) and the scale of its text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Canvas {
    /// Width (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    /// Pixels per point.
    pt: f64,
    /// Body text (points).
    font_pt: f64,
    /// plotters size per em.
    glyph: f64,
    /// Size on the page (mm), if printed.
    pub mm: Option<(f64, f64)>,
    /// Units of the canvas per inch on the page (a PNG's resolution; a PDF
    /// page's scale).
    pub dpi: f64,
}

impl Canvas {
    /// The canvas size (px).
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The canvas of a figure in the format of `out` (see [`Page::canvas`]).
    pub fn of(
        page: &Page,
        out: &crate::output::Out<'_>,
        screen: (u32, u32),
        height_mm: impl Fn(f64) -> f64,
    ) -> Result<Canvas, RenderError> {
        Ok(page.canvas(out.format()?, screen, height_mm))
    }

    /// Text `scale` times the body size, never below [`MIN_TEXT_PT`].
    pub fn font(&self, scale: f64) -> FontDesc<'static> {
        (crate::font::FAMILY, self.text_px(scale) * self.glyph).into_font()
    }

    /// The em of text `scale` times the body size (px).
    pub fn text_px(&self, scale: f64) -> f64 {
        (scale * self.font_pt).max(MIN_TEXT_PT) * self.pt
    }

    /// `k` body text heights (px), rounded.
    pub fn em(&self, k: f64) -> i32 {
        (k * self.font_pt * self.pt).round() as i32
    }

    /// `k` body text heights (px) as an unsigned size.
    pub fn emu(&self, k: f64) -> u32 {
        self.em(k).max(0) as u32
    }

    /// `k` points (px), at least one pixel.
    pub fn pt(&self, k: f64) -> u32 {
        (k * self.pt).round().max(1.0) as u32
    }

    /// Body text heights across the canvas.
    pub fn width_em(&self) -> f64 {
        self.width as f64 / (self.font_pt * self.pt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn print_sizes_parse_and_refuse() {
        assert_eq!("single".parse::<PrintSize>(), Ok(PrintSize { width_mm: 86.0, height_mm: None }));
        assert_eq!("120x80".parse::<PrintSize>(), Ok(PrintSize { width_mm: 120.0, height_mm: Some(80.0) }));
        assert!("120".parse::<PrintSize>().unwrap_err().contains("WxH"));
        assert!("5x80".parse::<PrintSize>().unwrap_err().contains("20..1000"));
        assert!("ax80".parse::<PrintSize>().is_err());
        assert!(Page::print(PrintSize { width_mm: 86.0, height_mm: None }, Some(5.0), None).is_err());
        assert!(Page::print(PrintSize { width_mm: 86.0, height_mm: None }, None, Some(20)).is_err());
    }

    /// A page's canvas: points for vector formats, dpi/72 pixels per point
    /// for PNG; text never below 6 pt.
    #[test]
    fn canvases_measure_points() {
        let size = PrintSize { width_mm: 86.0, height_mm: Some(60.0) };
        let page = Page::print(size, None, Some(300)).unwrap();
        let pdf = page.canvas(Format::Pdf, (1, 1), |w| w);
        assert_eq!(pdf.size(), (2438, 1701), "tenths of a point");
        let png = page.canvas(Format::Png, (1, 1), |w| w);
        assert_eq!(png.size(), (1016, 709));
        assert!((png.text_px(1.0) - 8.0 * 300.0 / 72.0).abs() < 1e-9);
        assert!((pdf.text_px(0.5) - 60.0).abs() < 1e-9, "clamped to 6 pt");
        let screen = Page::screen().canvas(Format::Png, (1100, 800), |w| w);
        assert_eq!(screen.size(), (1100, 800));
        assert!((screen.text_px(1.0) - 15.0).abs() < 1e-9);
    }
}
