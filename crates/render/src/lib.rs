//! Pictures of atlases: coloured label maps, bifurcation diagrams, and contact
//! sheets of studies, as PNG files (plotters, bitmap backend).
#![deny(missing_docs)]

mod bifurcation;
mod branch;
mod font;
mod map;
mod palette;
mod scalar;
mod section;
mod trade;

pub use bifurcation::bifurcation;
pub use branch::branch;
pub use map::{map, sheet, View};
pub use scalar::{scalar_map, Quantity};
pub use section::{sections, Panel};
pub use trade::trade;

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
