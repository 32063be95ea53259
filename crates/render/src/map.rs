//! The coloured (x, y) map of one mass's labels, as in the literature: one
//! rectangle per cell, a legend of the labels present (most frequent first,
//! rare ones grouped), and in the hysteresis view the up-sweep labels with the
//! cells where up and down differ crossed out.

use crate::palette::{assign, Swatch};
use crate::{err, font, RenderError};
use grid::{label_text, Atlas, Axis, CellData, Meta, SweepKind};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
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

/// The cells of one sweep of `atlas`, or an error naming the missing sweep.
pub(crate) fn sweep_cells(atlas: &Atlas, sweep: SweepKind) -> Result<&[Option<CellData>], RenderError> {
    atlas
        .map(sweep)
        .map(|m| m.cells.as_slice())
        .ok_or_else(|| RenderError { message: format!("the file has no '{}' sweep", sweep.name()) })
}

/// Geometry of the plane's cells: cell i is centred on its axis values and
/// spans one grid step in each direction.
pub(crate) struct CellGrid<'a> {
    x: &'a Axis,
    y: &'a Axis,
    dx: f64,
    dy: f64,
}

impl<'a> CellGrid<'a> {
    /// The cells of the plane of `meta`.
    pub(crate) fn of(meta: &'a Meta) -> Self {
        let (x, y) = (&meta.plane.x, &meta.plane.y);
        let step = |a: &Axis| if a.count > 1 { (a.stop - a.start) / (a.count - 1) as f64 } else { 1.0 };
        CellGrid { x, y, dx: step(x), dy: step(y) }
    }

    /// Centre of cell `i` (row-major, x fastest).
    pub(crate) fn centre(&self, i: usize) -> (f64, f64) {
        (self.x.value(i % self.x.count), self.y.value(i / self.x.count))
    }

    /// Corners of cell `i`.
    pub(crate) fn rect(&self, i: usize) -> [(f64, f64); 2] {
        let (cx, cy) = self.centre(i);
        [(cx - self.dx / 2.0, cy - self.dy / 2.0), (cx + self.dx / 2.0, cy + self.dy / 2.0)]
    }

    /// A chart over the whole plane (half a cell of margin), axes named after
    /// the parameters, text of size `font`.
    pub(crate) fn chart<'b, DB: DrawingBackend>(
        &self,
        area: &'b DrawingArea<DB, Shift>,
        title: &str,
        font: u32,
    ) -> Result<ChartContext<'b, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, RenderError> {
        let (x, y, dx, dy) = (self.x, self.y, self.dx, self.dy);
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", font + 6))
            .margin(10)
            .x_label_area_size(font * 3)
            .y_label_area_size(font * 4)
            .build_cartesian_2d(x.start - dx / 2.0..x.stop + dx / 2.0, y.start - dy / 2.0..y.stop + dy / 2.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x.name.as_str())
            .y_desc(y.name.as_str())
            .label_style(("sans-serif", font))
            .axis_desc_style(("sans-serif", font + 3))
            .draw()
            .map_err(err)?;
        Ok(chart)
    }
}

/// Colour lookup for a legend.
struct Colours(Vec<(String, Swatch, RGBColor)>);

impl Colours {
    fn of(&self, label: &str) -> RGBColor {
        self.0.iter().find(|(l, _, _)| l == label).map_or(RGBColor(255, 255, 255), |c| c.2)
    }
}

/// Draws the cells of one sweep (and hysteresis crosses) into `area`.
#[allow(clippy::too_many_arguments)]
fn draw_cells<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    atlas: &Atlas,
    sweep: SweepKind,
    mass: usize,
    colours: &Colours,
    title: &str,
    hyst: Option<&[u8]>,
    font: u32,
) -> Result<(), RenderError> {
    let cells = sweep_cells(atlas, sweep)?;
    let grid = CellGrid::of(&atlas.meta);
    let mut chart = grid.chart(area, title, font)?;
    chart
        .draw_series(cells.iter().enumerate().filter_map(|(i, c)| {
            let c = c.as_ref()?;
            let colour = colours.of(&label_text(c.class, c.labels[mass]));
            Some(Rectangle::new(grid.rect(i), colour.filled()))
        }))
        .map_err(err)?;
    if let Some(h) = hyst {
        chart
            .draw_series(h.iter().enumerate().filter(|(_, &v)| v == 1).flat_map(|(i, _)| {
                let [(x0, y0), (x1, y1)] = grid.rect(i);
                [
                    PathElement::new(vec![(x0, y0), (x1, y1)], BLACK.stroke_width(1)),
                    PathElement::new(vec![(x0, y1), (x1, y0)], RED.stroke_width(1)),
                ]
            }))
            .map_err(err)?;
    }
    Ok(())
}

/// Draws a legend (one entry per swatch, counts summed) into `area`.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    legend: &[(String, u64)],
    colours: &Colours,
    extra: Option<(String, RGBColor, u64)>,
) -> Result<(), RenderError> {
    let mut entries: Vec<(String, RGBColor, u64)> = Vec::new();
    for ((_, count), (_, sw, col)) in legend.iter().zip(&colours.0) {
        match entries.iter_mut().find(|e| e.0 == sw.text()) {
            Some(e) => e.2 += count,
            None => entries.push((sw.text(), *col, *count)),
        }
    }
    entries.extend(extra);
    let style = ("sans-serif", 15).into_font();
    area.draw(&Text::new("labels (cells)", (10, 30), ("sans-serif", 18).into_font())).map_err(err)?;
    for (i, (text, col, count)) in entries.iter().take(34).enumerate() {
        let yy = 55 + 20 * i as i32;
        area.draw(&Rectangle::new([(10, yy), (28, yy + 14)], col.filled())).map_err(err)?;
        area.draw(&Rectangle::new([(10, yy), (28, yy + 14)], BLACK.stroke_width(1))).map_err(err)?;
        area.draw(&Text::new(format!("{text}  ({count})"), (36, yy), style.clone())).map_err(err)?;
    }
    Ok(())
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
    let legend = atlas.legend(sweep, mass);
    let colours = Colours(assign(&legend));
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
    draw_cells(&left, atlas, sweep, mass, &colours, &title, hyst.as_deref(), 15)?;
    let extra = hyst.as_ref().map(|h| ("hysteresis (up != down)".to_string(), RED, h.iter().map(|&v| v as u64).sum()));
    draw_legend(&right, &legend, &colours, extra)?;
    root.present().map_err(err)
}

/// Draws a contact sheet: the maps of one mass and sweep for several atlases
/// (a study), side by side with one shared legend and consistent colours.
pub fn sheet(panels: &[(String, Atlas)], sweep: SweepKind, mass: usize, path: &Path) -> Result<(), RenderError> {
    font::ensure()?;
    let mut total: std::collections::BTreeMap<String, u64> = std::collections::BTreeMap::new();
    for (_, a) in panels {
        for (l, c) in a.legend(sweep, mass) {
            *total.entry(l).or_default() += c;
        }
    }
    let mut legend: Vec<(String, u64)> = total.into_iter().collect();
    legend.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let colours = Colours(assign(&legend));
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols);
    let root = BitMapBackend::new(path, (560 * cols as u32 + 320, 420 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (left, right) = root.split_horizontally(560 * cols as u32);
    for ((title, atlas), area) in panels.iter().zip(left.split_evenly((rows, cols)).iter()) {
        draw_cells(area, atlas, sweep, mass, &colours, title, None, 12)?;
    }
    draw_legend(&right, &legend, &colours, None)?;
    root.present().map_err(err)
}
