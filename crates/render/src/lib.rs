//! Pictures of atlases: coloured label maps, bifurcation diagrams, and contact
//! sheets of studies, as PNG, SVG or PDF files (plotters; PDF through svg2pdf),
//! the format chosen by the file's extension, on screen or at a printed size
//! ([`Page`]: every text at least 6 pt on the page).
#![deny(missing_docs)]

mod basins;
mod bifurcation;
mod branch;
mod contour;
mod font;
mod layers;
mod layout;
mod legend;
mod map;
mod output;
mod page;
mod portrait;
mod rich;
mod scalar;
mod section;
mod trade;

pub use basins::{basin_map, basins};
pub use bifurcation::{bifurcation, component_name, Diagram, Impact};
pub use branch::branch;
pub use layers::{curve_style, label_legend, layer, Key, Layer, Show};
pub use map::{attractor_map, family_map, map, sheet, Overlay, View};
/// A colour faded as the hysteresis view draws the cells where the sweeps agree.
pub use maps::palette::faded;
pub use output::Format;
pub use page::{Page, PageError, PageOption, PrintSize, DOUBLE_MM, MIN_TEXT_PT, SINGLE_MM};
pub use portrait::{portrait, Portrait};
pub use rich::runs as subscript_runs;
pub use scalar::{difference_map, scalar_map};
pub use section::{sections, Panel};
pub use trade::trade;

/// An axis tick: up to four decimals, never `-0`, negative numbers with a
/// minus sign (U+2212), not a hyphen.
fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let text = format!("{:.4}", v);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    let text = if v.abs() >= 1e4 || v.abs() < 1e-3 { format!("{v:.2e}") } else { text.to_string() };
    text.replace('-', "\u{2212}")
}

/// The range of `values` with a margin: 5 % of their span, and at least 5 %
/// of their magnitude (or 1e-3), so that a few points that agree to round-off
/// (a period-n orbit) sit in the middle of readable ticks; `-1..1` when there
/// are none.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let half = (1.1 * half).max(0.05 * mid.abs()).max(1e-3);
    (mid - half, mid + half)
}

/// A plotters backend whose errors can be kept as a [`RenderError`]'s source.
pub(crate) trait Backend: plotters::prelude::DrawingBackend<ErrorType: 'static> {}
impl<B: plotters::prelude::DrawingBackend<ErrorType: 'static>> Backend for B {}

/// Wraps a drawing or scene error (the error's source).
fn err<E: std::error::Error + Send + Sync + 'static>(e: E) -> RenderError {
    RenderError::because("", e)
}

/// What an atlas lacks for the picture asked of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Missing {
    /// Its coexisting attractors (a map of their number).
    Attractors,
}

/// A picture could not be drawn or written: `render: ` and what failed,
/// with the error of the library or of the system that failed (plotters, the
/// scene, svg2pdf, the file system) as its [`source`](std::error::Error::source)
/// where there is one: `{:#}` (anyhow) prints `render: what: cause`.
#[derive(Debug)]
pub struct RenderError {
    /// What failed, without its cause's text (empty: the cause says it).
    what: String,
    /// The error that made it fail.
    cause: Option<Box<dyn std::error::Error + Send + Sync>>,
    /// What the atlas lacks, when that is why.
    missing: Option<Missing>,
}

impl RenderError {
    /// An error saying `message`.
    pub fn new(message: impl Into<String>) -> RenderError {
        RenderError { what: message.into(), cause: None, missing: None }
    }

    /// An error saying `what` failed because of `cause`.
    pub fn because(what: impl Into<String>, cause: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> RenderError {
        RenderError { what: what.into(), cause: Some(cause.into()), missing: None }
    }

    /// The atlas lacks `what` for the picture: `the file has no …`.
    pub fn lacks(what: Missing) -> RenderError {
        let name = match what {
            Missing::Attractors => "attractors",
        };
        RenderError { what: format!("the file has no {name}"), cause: None, missing: Some(what) }
    }

    /// What the atlas lacks, when that is why the picture was not drawn.
    pub fn missing(&self) -> Option<Missing> {
        self.missing
    }

    /// What failed, without its cause.
    pub fn what(&self) -> &str {
        &self.what
    }
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.what.as_str() {
            "" => f.write_str("render"),
            what => write!(f, "render: {what}"),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_of_figure_options() {
        assert_eq!(Page::of(None, None, None), Ok(Page::screen()));
        assert_eq!(Page::of(None, Some(8.0), None), Err(PageError::WithoutSize(PageOption::FontSize)));
        assert_eq!(Page::of(None, None, Some(300)).unwrap_err().option(), PageOption::Dpi);
        assert_eq!(
            Page::of(Some("single"), Some(30.0), None).unwrap_err().to_string(),
            "must be in [6, 24] pt, got 30"
        );
        assert_eq!(Page::of(Some("single"), None, Some(10)).unwrap_err().to_string(), "must be in [72, 1200], got 10");
        assert_eq!(Page::of(Some("10x"), None, None).unwrap_err().option(), PageOption::Size);
        assert!(Page::of(Some("120x80"), Some(10.0), Some(600)).is_ok());
    }

    /// A picture written where it cannot be: the system's error is the
    /// source, typed, and the chain reads `render: path: cause` on one line.
    #[test]
    fn a_failed_write_keeps_its_cause() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-render-cause-{}", std::process::id()));
        let path = dir.join("missing-folder").join("a.svg");
        let e = trade(&[("a".into(), 1.0, 0.5)], &path).unwrap_err();
        let cause = std::error::Error::source(&e).expect("a source");
        assert!(cause.downcast_ref::<std::io::Error>().is_some(), "{cause:?}");
        assert_eq!(e.to_string(), format!("render: {}", path.display()));
        let chain = format!("{e}: {cause}");
        assert!(chain.starts_with(&format!("render: {}: ", path.display())) && !chain.contains('\n'), "{chain}");
        assert!(std::error::Error::source(&RenderError::new("no such view")).is_none());
    }
}
