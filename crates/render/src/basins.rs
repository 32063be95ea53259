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
    let (x0, x1) = crate::range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.0)));
    let (y0, y1) = crate::range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.1)));
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    crate::axes(&mut chart, &axes.0, &axes.1, 14)?;
    for ((name, pts), label) in groups.iter().zip(colours) {
        let col = rgb(label);
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))
            .map_err(err)?
            .label(name.clone())
            .legend(move |(a, b)| Circle::new((a + 8, b), 5, col.filled()));
    }
    crate::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    Ok(())
}
