//! Basins of attraction in a plane of initial states: each sampled initial
//! state drawn in the colour of the label of the attractor it reaches, with a
//! legend of the attractors and their basin fractions.

use crate::map::rgb;
use crate::output::save;
use crate::{err, RenderError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Draws `groups` (legend text, points) in the colours of the labels
/// `colours` (one per group), axes named `axes` (format by the extension of
/// `path`).
pub fn basins(
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[String],
    title: &str,
    axes: &(String, String),
    path: &Path,
) -> Result<(), RenderError> {
    save!(path, (1000, 700), |root| draw(&root, groups, colours, title, axes))
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[String],
    title: &str,
    axes: &(String, String),
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let all = groups.iter().flat_map(|g| g.1.iter());
    let (x0, x1, y0, y1) = all.fold((f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.0), a.1.max(p.0), a.2.min(p.1), a.3.max(p.1))
    });
    let pad =
        |lo: f64, hi: f64| if hi > lo { (lo - 0.03 * (hi - lo), hi + 0.03 * (hi - lo)) } else { (lo - 1.0, lo + 1.0) };
    let ((x0, x1), (y0, y1)) = (pad(x0, x1), pad(y0, y1));
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(axes.0.as_str())
        .y_desc(axes.1.as_str())
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(err)?;
    for ((name, pts), label) in groups.iter().zip(colours) {
        let col = rgb(label);
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))
            .map_err(err)?
            .label(name.clone())
            .legend(move |(a, b)| Circle::new((a + 8, b), 5, col.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    Ok(())
}
