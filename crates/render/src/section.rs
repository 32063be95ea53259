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

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        (-1.0, 1.0)
    } else if hi > lo {
        (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
    } else {
        (lo - 1e-3 * (1.0 + lo.abs()), hi + 1e-3 * (1.0 + hi.abs()))
    }
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
        let (x0, x1) = range(panel.points.iter().map(|p| p.0));
        let (y0, y1) = range(panel.points.iter().map(|p| p.1));
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(panel.x.as_str())
            .y_desc(panel.y.as_str())
            .x_label_formatter(&|v| crate::tick(*v))
            .y_label_formatter(&|v| crate::tick(*v))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 15))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(panel.points.iter().map(|&p| Circle::new(p, 1, RGBColor(31, 119, 180).filled())))
            .map_err(err)?;
    }
    Ok(())
}
