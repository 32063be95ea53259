//! The coloured (x, y) map of one mass's labels, as in the literature: one
//! rectangle per cell, a legend of the labels present (most frequent first,
//! rare ones grouped), and in the hysteresis view the up-sweep labels with the
//! cells where up and down differ crossed out.

use crate::palette::{assign, Swatch};
use crate::{font, RenderError};
use grid::{label_text, Atlas, SweepKind};
use plotters::prelude::*;
use std::path::Path;

/// What a map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// The labels of one sweep.
    Sweep(SweepKind),
    /// Up-sweep labels with hysteresis cells marked.
    Hysteresis,
}

fn err<E: std::fmt::Debug>(e: E) -> RenderError {
    RenderError { message: format!("{e:?}") }
}

/// Draws the map of mass `mass` (index into `atlas.meta.masses`) to a PNG.
pub fn map(atlas: &Atlas, view: View, mass: usize, path: &Path) -> Result<(), RenderError> {
    font::ensure()?;
    let m = &atlas.meta;
    let sweep = match view {
        View::Sweep(s) => s,
        View::Hysteresis => SweepKind::Up,
    };
    let hyst = match view {
        View::Hysteresis => Some(atlas.hysteresis().ok_or_else(|| RenderError {
            message: "--sweep hysteresis needs an atlas with up and down sweeps".into(),
        })?),
        View::Sweep(_) => None,
    };
    let cells = &atlas
        .map(sweep)
        .ok_or_else(|| RenderError { message: format!("the file has no '{}' sweep", sweep.name()) })?
        .cells;
    let legend = atlas.legend(sweep, mass);
    let colours = assign(&legend);
    let colour_of = |label: &str| colours.iter().find(|(l, _, _)| l == label).map_or(RGBColor(255, 255, 255), |c| c.2);

    let (x, y) = (&m.plane.x, &m.plane.y);
    let step = |a: &grid::Axis| if a.count > 1 { (a.stop - a.start) / (a.count - 1) as f64 } else { 1.0 };
    let (dx, dy) = (step(x), step(y));
    let root = BitMapBackend::new(path, (1200, 760)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (left, right) = root.split_horizontally(860);
    let title = format!(
        "{}: {} ({})",
        m.scene_name,
        m.masses[mass],
        match view {
            View::Sweep(s) => s.name().to_string(),
            View::Hysteresis => "up sweep, hysteresis marked".into(),
        }
    );
    let mut chart = ChartBuilder::on(&left)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x.start - dx / 2.0..x.stop + dx / 2.0, y.start - dy / 2.0..y.stop + dy / 2.0)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x.name.as_str())
        .y_desc(y.name.as_str())
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 18))
        .draw()
        .map_err(err)?;
    let nx = x.count;
    chart
        .draw_series(cells.iter().enumerate().filter_map(|(i, c)| {
            let c = c.as_ref()?;
            let (cx, cy) = (x.value(i % nx), y.value(i / nx));
            let colour = colour_of(&label_text(c.class, c.labels[mass]));
            Some(Rectangle::new([(cx - dx / 2.0, cy - dy / 2.0), (cx + dx / 2.0, cy + dy / 2.0)], colour.filled()))
        }))
        .map_err(err)?;
    if let Some(h) = &hyst {
        chart
            .draw_series(h.iter().enumerate().filter(|(_, &v)| v == 1).flat_map(|(i, _)| {
                let (cx, cy) = (x.value(i % nx), y.value(i / nx));
                [
                    PathElement::new(
                        vec![(cx - dx / 2.0, cy - dy / 2.0), (cx + dx / 2.0, cy + dy / 2.0)],
                        BLACK.stroke_width(1),
                    ),
                    PathElement::new(
                        vec![(cx - dx / 2.0, cy + dy / 2.0), (cx + dx / 2.0, cy - dy / 2.0)],
                        RED.stroke_width(1),
                    ),
                ]
            }))
            .map_err(err)?;
    }

    // Legend: one entry per swatch, counts summed, in order of first appearance.
    let mut entries: Vec<(Swatch, RGBColor, u64)> = Vec::new();
    for ((_, count), (_, sw, col)) in legend.iter().zip(&colours) {
        match entries.iter_mut().find(|e| e.0 == *sw) {
            Some(e) => e.2 += count,
            None => entries.push((sw.clone(), *col, *count)),
        }
    }
    if let Some(h) = &hyst {
        entries.push((Swatch::Label("hysteresis (up != down)".into()), RED, h.iter().map(|&v| v as u64).sum()));
    }
    let style = ("sans-serif", 15).into_font();
    right.draw(&Text::new("labels (cells)", (10, 30), ("sans-serif", 18).into_font())).map_err(err)?;
    for (i, (sw, col, count)) in entries.iter().take(34).enumerate() {
        let yy = 55 + 20 * i as i32;
        right.draw(&Rectangle::new([(10, yy), (28, yy + 14)], col.filled())).map_err(err)?;
        right.draw(&Rectangle::new([(10, yy), (28, yy + 14)], BLACK.stroke_width(1))).map_err(err)?;
        right.draw(&Text::new(format!("{}  ({count})", sw.text()), (36, yy), style.clone())).map_err(err)?;
    }
    root.present().map_err(err)
}
