//! Pictures of atlases: coloured label maps, bifurcation diagrams, and contact
//! sheets of studies, as PNG, SVG or PDF files (plotters; PDF through svg2pdf),
//! the format chosen by the file's extension, on screen or at a printed size
//! ([`Page`]: every text at least 6 pt on the page).
#![deny(missing_docs)]

mod basins;
mod bifurcation;
mod branch;
mod font;
mod layout;
mod legend;
mod map;
mod output;
mod page;
mod portrait;
mod scalar;
mod section;
mod trade;

pub use basins::basins;
pub use bifurcation::{bifurcation, component_name, Diagram, Impact};
pub use branch::branch;
pub use map::{attractor_map, map, sheet, Overlay, View};
pub use output::Format;
pub use page::{Page, PrintSize, DOUBLE_MM, MIN_TEXT_PT, SINGLE_MM};
pub use portrait::{portrait, Portrait};
pub use scalar::{scalar_map, Quantity};
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

/// Wraps a drawing, scene or solver error.
fn err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::new(e.to_string())
}

/// A picture could not be drawn or written.
#[derive(Debug, Clone, thiserror::Error)]
#[error("render: {message}")]
pub struct RenderError {
    /// What failed.
    pub message: String,
}

impl RenderError {
    /// An error saying `message`.
    pub fn new(message: impl Into<String>) -> RenderError {
        RenderError { message: message.into() }
    }
}
