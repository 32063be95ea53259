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
pub use map::{attractor_map, map, sheet, Overlay, View};
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

/// The range of `values` with a margin of 5 % (or a small one around a single
/// value; `-1..1` when there is none).
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        (-1.0, 1.0)
    } else if hi > lo {
        (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
    } else {
        (lo - 1e-3 * (1.0 + lo.abs()), hi + 1e-3 * (1.0 + hi.abs()))
    }
}

/// A chart's axes as every figure draws them: no grid, named axes, ticks
/// without `-0`, text of size `font`.
fn axes<DB: plotters::prelude::DrawingBackend>(
    chart: &mut plotters::prelude::ChartContext<
        '_,
        DB,
        plotters::prelude::Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    x: &str,
    y: &str,
    font: u32,
) -> Result<(), RenderError> {
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x)
        .y_desc(y)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style(("sans-serif", font))
        .axis_desc_style(("sans-serif", font + 2))
        .draw()
        .map_err(err)
}

/// The legend of a chart's labelled series, in corner `at`, on a light box.
fn legend<'a, DB: plotters::prelude::DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut plotters::prelude::ChartContext<'a, DB, CT>,
    at: plotters::prelude::SeriesLabelPosition,
) -> Result<(), RenderError> {
    use plotters::prelude::{Color, BLACK, WHITE};
    chart
        .configure_series_labels()
        .position(at)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(err)
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
