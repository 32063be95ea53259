//! Poincaré sections of one motion, one scatter panel each: a periodic motion
//! shows n points, a quasi-periodic one a closed curve (the invariant circle
//! born at a Neimark–Sacker bifurcation), a chaotic one a fractal cloud.

use crate::output::save;
use crate::{err, RenderError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One scatter panel.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Horizontal axis description.
    pub x: String,
    /// Vertical axis description.
    pub y: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
}

/// Draws the panels side by side (two per row) to a PNG.
pub fn sections(panels: &[Panel], title: &str, path: &Path) -> Result<(), RenderError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols).max(1);
    save!(path, (520 * cols as u32, 460 * rows as u32 + 40), |root| draw(&root, panels, title))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, panels: &[Panel], title: &str) -> Result<(), RenderError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols).max(1);
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
    for (panel, area) in panels.iter().zip(root.split_evenly((rows, cols)).iter()) {
        let (x0, x1) = crate::range(panel.points.iter().map(|p| p.0));
        let (y0, y1) = crate::range(panel.points.iter().map(|p| p.1));
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        crate::axes(&mut chart, &panel.x, &panel.y, 13)?;
        chart
            .draw_series(panel.points.iter().map(|&p| Circle::new(p, 1, RGBColor(31, 119, 180).filled())))
            .map_err(err)?;
    }
    Ok(())
}
