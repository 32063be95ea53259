//! Poincaré sections of one motion, one scatter panel each: a periodic motion
//! shows n points, a quasi-periodic one a closed curve (the invariant circle
//! born at a Neimark–Sacker bifurcation), a chaotic one a fractal cloud. A
//! few points are drawn larger, and their panel is padded around them
//! ([`crate::range`]) rather than scaled to their round-off.

use crate::axis::range;
use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One scatter panel (serialised as an object of its fields, a point as
/// `[x, y]`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Panel {
    /// Horizontal axis description.
    pub x: String,
    /// Vertical axis description.
    pub y: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
}

/// Draws the panels side by side (two per row) at the size of `page`
/// (to `out`: [`Out`]); the title is wrapped to the width.
pub fn sections<'o>(panels: &[Panel], title: &str, page: &Page, out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols).max(1);
    let height = |w: f64| 18.0 + rows as f64 * w / cols as f64 * 0.85;
    let out = out.into();
    let canvas = Canvas::of(page, &out, (520 * cols as u32, 460 * rows as u32 + 60), height)?;
    save!(out, canvas, |root| draw(&root, &canvas, panels, title))
}

fn draw<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    panels: &[Panel],
    title: &str,
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, title, layout::TITLE)?;
    for (panel, area) in panels.iter().zip(layout::grid(&body, canvas, panels.len(), (16.0, 14.0)).iter()) {
        let axes = Axes {
            caption: None,
            x: range(panel.points.iter().map(|p| p.0)),
            y: range(panel.points.iter().map(|p| p.1)),
            x_desc: &panel.x,
            y_desc: &panel.y,
            x_labels: true,
            y_label_chars: None,
        };
        let chart = layout::chart(area, canvas, &axes)?;
        // A periodic motion's few distinct points (repeated every n periods)
        // drawn large; a curve or a cloud of many, small.
        let cell = |v: f64, (lo, hi): (f64, f64)| ((v - lo) / (hi - lo) * 400.0).round() as i64;
        let mut distinct: Vec<(i64, i64)> =
            panel.points.iter().map(|p| (cell(p.0, axes.x), cell(p.1, axes.y))).collect();
        distinct.sort_unstable();
        distinct.dedup();
        let r = if distinct.len() > 64 { 0.6 } else { 1.6 };
        let colour = RGBColor(0, 114, 178).filled();
        for &p in &panel.points {
            chart.plotting_area().draw(&Circle::new(p, canvas.pt(r), colour)).map_err(err)?;
        }
    }
    Ok(())
}
