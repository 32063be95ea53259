//! Pictures of atlases: coloured label maps, bifurcation diagrams, and contact
//! sheets of studies, as PNG, SVG or PDF files (plotters; PDF through svg2pdf),
//! the format chosen by the file's extension.
#![deny(missing_docs)]

mod basins;
mod bifurcation;
mod branch;
mod font;
mod map;
mod output;
mod portrait;
mod scalar;
mod section;
mod trade;

pub use basins::basins;
pub use bifurcation::{bifurcation, component_name, Diagram, Impact};
pub use branch::branch;
pub use map::{map, sheet, View};
pub use output::Format;
pub use portrait::{portrait, Portrait};
pub use scalar::{scalar_map, Quantity};
pub use section::{sections, Panel};
pub use trade::trade;

/// An axis tick: up to four significant digits, never `-0`.
fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let text = format!("{:.4}", v);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        text.to_string()
    }
}

/// Wraps a drawing, scene or solver error.
fn err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError { message: e.to_string() }
}

/// A picture could not be drawn or written.
#[derive(Debug, Clone, thiserror::Error)]
#[error("render: {message}")]
pub struct RenderError {
    /// What failed.
    pub message: String,
}
