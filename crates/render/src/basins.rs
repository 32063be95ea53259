//! Basins of attraction in a plane of initial states: each sampled initial
//! state drawn in the colour of the label of the attractor it reaches, with a
//! legend of the attractors and their basin fractions.

use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::map::rgb;
use crate::output::save;
use crate::page::{Canvas, Page};
use crate::{err, RenderError};
use plotters::coord::Shift;
use plotters::prelude::*;
use solver::Label;
use std::path::Path;

/// Draws `groups` (legend text, points) in the colours of the labels
/// `colours` (one per group), axes named `axes` (format by the extension of
/// `path`).
pub fn basins(
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[Label],
    title: &str,
    axes: &(String, String),
    page: &Page,
    path: &Path,
) -> Result<(), RenderError> {
    let canvas = Canvas::of(page, path, (1000, 700), |w| if w < 120.0 { 1.1 * w } else { 0.6 * w })?;
    save!(path, canvas, |root| draw(&root, &canvas, groups, colours, title, axes))
}

fn draw<DB: crate::Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[Label],
    title: &str,
    axes: &(String, String),
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, title, layout::TITLE)?;
    let rows: Vec<Entry> = groups
        .iter()
        .zip(colours)
        .map(|((name, _), &label)| Entry::new(Swatch::Fill(rgb(label)), name.clone()))
        .collect();
    let column = legend::width(&body, canvas, &rows);
    let (w, h) = body.dim_in_pixel();
    let (plot_area, key) = if canvas.width_em() >= 50.0 {
        body.split_horizontally(w.saturating_sub(column))
    } else {
        body.split_vertically(h.saturating_sub(legend::height(canvas, rows.len())))
    };
    let a = Axes {
        caption: None,
        x: crate::range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.0))),
        y: crate::range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.1))),
        x_desc: &axes.0,
        y_desc: &axes.1,
        x_labels: true,
        y_label_chars: None,
    };
    let chart = layout::chart(&plot_area, canvas, &a)?;
    let plot = chart.plotting_area();
    // Every point ringed in black, so that light labels (1-0-0) stay visible.
    let (r, edge) = (canvas.pt(1.8), BLACK.mix(0.7).stroke_width(canvas.pt(0.3)));
    for ((_, pts), &label) in groups.iter().zip(colours) {
        let col = rgb(label);
        for &p in pts {
            plot.draw(&Circle::new(p, r, col.filled())).map_err(err)?;
            plot.draw(&Circle::new(p, r, edge)).map_err(err)?;
        }
    }
    legend::draw(&key, canvas, &rows)
}
