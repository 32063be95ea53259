//! The coloured (x, y) map of one mass's labels, as in the literature: one
//! rectangle per cell in the label's fixed colour ([`grid::palette`]: the same
//! label has the same colour in every figure), and a legend of the labels
//! present, most frequent first, that says what p and q count.
//!
//! Hysteresis is drawn as three panels side by side, so that no map is hidden:
//! the up sweep, the down sweep, and the cells where they end on different
//! periodic motions, in the colour of the down sweep's label (the rest light
//! grey).

use crate::output::save;
use crate::{err, RenderError};
use grid::palette::{colour, family, family_colour};
use grid::{Atlas, Axis, CellData, Meta, SweepKind};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// What a map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// The labels of one sweep.
    Sweep(SweepKind),
    /// Up | down | where they differ.
    Hysteresis,
}

/// Colour of cells a panel does not show (not computed, or no hysteresis):
/// white, apart from every label's colour (1-0-0 is light grey).
const BLANK: RGBColor = RGBColor(255, 255, 255);
/// Legend entries listed one by one; the rest are summed per family.
const LEGEND_ROWS: usize = 30;

/// The plotters colour of a label.
pub(crate) fn rgb(label: &str) -> RGBColor {
    let [r, g, b] = colour(label);
    RGBColor(r, g, b)
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
        let step = |a: &Axis| if a.count > 1 { a.step() } else { 1.0 };
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
            .caption(title, ("sans-serif", font + 4))
            .margin(10)
            .margin_right(20)
            .x_label_area_size(font * 3)
            .y_label_area_size(font * 4)
            .build_cartesian_2d(x.start - dx / 2.0..x.stop + dx / 2.0, y.start - dy / 2.0..y.stop + dy / 2.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x.name.as_str())
            .y_desc(y.name.as_str())
            .x_label_formatter(&|v| crate::tick(*v))
            .y_label_formatter(&|v| crate::tick(*v))
            .label_style(("sans-serif", font))
            .axis_desc_style(("sans-serif", font + 3))
            .draw()
            .map_err(err)?;
        Ok(chart)
    }
}

/// A bifurcation curve drawn over a map: its kind (`PD`, `SN`, `PF`, `NS`,
/// `grazing`), its points and its codimension-two points, in the plane's
/// (x, y) coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlay {
    /// Kind of bifurcation (legend text and line style).
    pub kind: String,
    /// Points along the curve.
    pub points: Vec<(f64, f64)>,
    /// Codimension-two points, marked.
    pub marks: Vec<(f64, f64)>,
}

/// Line style of a kind of curve: black, dashed differently per kind.
fn dashes(kind: &str) -> (u32, u32) {
    match kind {
        "PD" => (10, 4),
        "SN" => (2, 3),
        "PF" => (14, 6),
        "NS" => (6, 6),
        _ => (1, 0),
    }
}

/// Draws cells in the colours `paint` gives (None: not drawn), and `curves` over them.
fn draw_cells<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    meta: &Meta,
    title: &str,
    font: u32,
    paint: impl Fn(usize) -> Option<RGBColor>,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let grid = CellGrid::of(meta);
    let mut chart = grid.chart(area, title, font)?;
    chart
        .draw_series((0..meta.plane.cells()).filter_map(|i| Some(Rectangle::new(grid.rect(i), paint(i)?.filled()))))
        .map_err(err)?;
    for (i, c) in curves.iter().enumerate() {
        let (on, off) = dashes(&c.kind);
        let style = BLACK.stroke_width(3);
        let drawn = if off == 0 {
            chart.draw_series(LineSeries::new(c.points.iter().copied(), style)).map_err(err)?
        } else {
            chart.draw_series(DashedLineSeries::new(c.points.iter().copied(), on, off, style)).map_err(err)?
        };
        // One legend entry per kind.
        if !curves[..i].iter().any(|d| d.kind == c.kind) {
            drawn
                .label(format!("{} curve", c.kind))
                .legend(move |(a, b)| PathElement::new(vec![(a, b), (a + 18, b)], BLACK.stroke_width(3)));
        }
        chart.draw_series(c.marks.iter().map(|&p| Circle::new(p, 6, WHITE.filled().stroke_width(2)))).map_err(err)?;
        chart.draw_series(c.marks.iter().map(|&p| Circle::new(p, 6, BLACK.stroke_width(2)))).map_err(err)?;
    }
    if !curves.is_empty() {
        crate::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

/// Colours of one sweep's labels of mass `mass`, cell by cell.
fn label_colours(cells: &[Option<CellData>], mass: usize) -> impl Fn(usize) -> Option<RGBColor> + '_ {
    move |i| Some(cells[i].as_ref().map_or(BLANK, |c| rgb(&c.labels[mass].to_string())))
}

/// What p and q count for a mass, e.g. `M1: p = impacts at A12, q = impacts at A1`.
pub(crate) fn pq_text(meta: &Meta, mass: usize) -> String {
    let stops = meta.label_stops.get(mass).cloned().unwrap_or_default();
    let side = |s: &str| if s.is_empty() { "no stop".to_string() } else { format!("impacts at {s}") };
    format!(
        "{}: n-p-q, n = period (forcing periods), p = {}, q = {} in n periods",
        meta.masses[mass],
        side(&stops[0]),
        side(&stops[1])
    )
}

/// The run's fixed settings, for a subtitle.
pub(crate) fn settings_text(meta: &Meta) -> String {
    let set: Vec<String> = meta.overrides.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    let fixed = if set.is_empty() { "scene defaults".to_string() } else { set.join(", ") };
    format!("{}; preset {}; {}", meta.scene_name, meta.preset, fixed)
}

/// Draws a legend of `(label, cells)` entries, most frequent first.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    heading: &str,
    entries: &[(String, u64)],
    extra: &[(String, RGBColor)],
) -> Result<(), RenderError> {
    let style = ("sans-serif", 15).into_font();
    area.draw(&Text::new(heading, (10, 20), ("sans-serif", 18).into_font())).map_err(err)?;
    let mut rows: Vec<(String, RGBColor)> = extra.to_vec();
    let name = |l: &str| match l {
        "C" => "C chaotic".to_string(),
        "Q" => "Q quasi-periodic".to_string(),
        "U" => "U unresolved".to_string(),
        l => l.to_string(),
    };
    for (label, count) in entries.iter().take(LEGEND_ROWS) {
        rows.push((format!("{}  ({count})", name(label)), rgb(label)));
    }
    let mut rest: BTreeMap<&str, (u64, u64)> = BTreeMap::new();
    for (label, count) in entries.iter().skip(LEGEND_ROWS) {
        let e = rest.entry(family(label)).or_default();
        e.0 += 1;
        e.1 += count;
    }
    for (fam, (labels, cells)) in rest {
        let [r, g, b] = family_colour(fam);
        rows.push((format!("+ {labels} more {fam} ({cells})"), RGBColor(r, g, b)));
    }
    for (i, (text, col)) in rows.iter().enumerate() {
        let y = 42 + 20 * i as i32;
        area.draw(&Rectangle::new([(10, y), (28, y + 14)], col.filled())).map_err(err)?;
        area.draw(&Rectangle::new([(10, y), (28, y + 14)], BLACK.stroke_width(1))).map_err(err)?;
        area.draw(&Text::new(text.clone(), (36, y), style.clone())).map_err(err)?;
    }
    Ok(())
}

/// `(label, cells)` of mass `mass` over several sweeps' cells, most frequent first.
fn count(cells: &[&[Option<CellData>]], mass: usize) -> Vec<(String, u64)> {
    let mut counts: BTreeMap<String, u64> = BTreeMap::new();
    for c in cells.iter().flat_map(|c| c.iter()).flatten() {
        *counts.entry(c.labels[mass].to_string()).or_default() += 1;
    }
    let mut v: Vec<(String, u64)> = counts.into_iter().collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    v
}

/// Draws the map of mass `mass` (index into `atlas.meta.masses`); the format
/// follows the extension of `path` (`.png`, `.svg`, `.pdf`).
/// `curves` are drawn over every panel.
pub fn map(atlas: &Atlas, view: View, mass: usize, curves: &[Overlay], path: &Path) -> Result<(), RenderError> {
    let panels = if view == View::Hysteresis { 3 } else { 1 };
    save!(path, (760 * panels + 380, 800), |root| draw_map(&root, atlas, view, mass, curves))
}

fn draw_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    atlas: &Atlas,
    view: View,
    mass: usize,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(&pq_text(m, mass), ("sans-serif", 20)).map_err(err)?;
    let (body, foot) = root.split_vertically(root.dim_in_pixel().1 - 28);
    foot.draw(&Text::new(settings_text(m), (12, 4), ("sans-serif", 15).into_font())).map_err(err)?;
    let width = body.dim_in_pixel().0;
    let (maps, legend) = body.split_horizontally(width - 380);
    match view {
        View::Sweep(sweep) => {
            let cells = sweep_cells(atlas, sweep)?;
            let title = format!("{}, {} sweep", m.masses[mass], sweep.name());
            draw_cells(&maps, m, &title, 15, label_colours(cells, mass), curves)?;
            draw_legend(&legend, "label (cells)", &count(&[cells], mass), &[])
        }
        View::Hysteresis => {
            let (up, down) = (sweep_cells(atlas, SweepKind::Up)?, sweep_cells(atlas, SweepKind::Down)?);
            let hyst = atlas.hysteresis().ok_or_else(|| RenderError {
                message: "the hysteresis view needs an atlas with up and down sweeps".into(),
            })?;
            let panels = maps.split_evenly((1, 3));
            draw_cells(&panels[0], m, &format!("{}, up sweep", m.masses[mass]), 14, label_colours(up, mass), curves)?;
            draw_cells(
                &panels[1],
                m,
                &format!("{}, down sweep", m.masses[mass]),
                14,
                label_colours(down, mass),
                curves,
            )?;
            let zones = hyst.iter().filter(|&&h| h == 1).count();
            let differ = |i: usize| {
                Some(match (&down[i], hyst[i]) {
                    (Some(c), 1) => rgb(&c.labels[mass].to_string()),
                    _ => BLANK,
                })
            };
            draw_cells(&panels[2], m, &format!("up and down differ: {zones} cells (down label)"), 14, differ, curves)?;
            let blank = [("no hysteresis (right panel)".to_string(), BLANK)];
            draw_legend(&legend, "label (cells, up + down)", &count(&[up, down], mass), &blank)
        }
    }
}

/// Draws a contact sheet: the maps of one mass and sweep for several atlases
/// (a study), side by side with one legend; a label has the same colour in
/// every panel.
pub fn sheet(panels: &[(String, Atlas)], sweep: SweepKind, mass: usize, path: &Path) -> Result<(), RenderError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols);
    save!(path, (560 * cols as u32 + 340, 440 * rows as u32 + 40), |root| draw_sheet(&root, panels, sweep, mass))
}

fn draw_sheet<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[(String, Atlas)],
    sweep: SweepKind,
    mass: usize,
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols);
    let title = panels.first().map_or(String::new(), |(_, a)| pq_text(&a.meta, mass));
    let root = root.titled(&title, ("sans-serif", 18)).map_err(err)?;
    let (left, right) = root.split_horizontally(560 * cols as u32);
    let mut all = Vec::new();
    for ((title, atlas), area) in panels.iter().zip(left.split_evenly((rows, cols)).iter()) {
        let cells = sweep_cells(atlas, sweep)?;
        all.push(cells);
        draw_cells(area, &atlas.meta, title, 12, label_colours(cells, mass), &[])?;
    }
    draw_legend(&right, "label (cells, all panels)", &count(&all, mass), &[])
}

/// Colours of 1, 2, 3 and 4 or more coexisting attractors (light to dark).
const COEXISTING: [RGBColor; 4] =
    [RGBColor(222, 235, 247), RGBColor(107, 174, 214), RGBColor(33, 113, 181), RGBColor(8, 48, 107)];

/// Draws the number of coexisting attractors found in each sampled cell of
/// `atlas` (`atlas --attractors`), cells not sampled white (format by the
/// extension of `path`).
pub fn attractor_map(atlas: &Atlas, path: &Path) -> Result<(), RenderError> {
    let a = atlas.attractors.as_ref().ok_or_else(|| RenderError {
        message: "the file has no attractors: make it with atlas --attractors K".into(),
    })?;
    save!(path, (1140, 800), |root| draw_attractors(&root, atlas, a))
}

fn draw_attractors<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    atlas: &Atlas,
    a: &grid::AttractorMap,
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    root.fill(&WHITE).map_err(err)?;
    let title = format!("coexisting attractors ({} sampled initial states per cell, seed {})", a.samples, a.seed);
    let root = root.titled(&title, ("sans-serif", 20)).map_err(err)?;
    let (body, foot) = root.split_vertically(root.dim_in_pixel().1 - 28);
    foot.draw(&Text::new(settings_text(m), (12, 4), ("sans-serif", 15).into_font())).map_err(err)?;
    let (plot, legend) = body.split_horizontally(760);
    let shade = |n: usize| COEXISTING[n.clamp(1, 4) - 1];
    draw_cells(
        &plot,
        m,
        "number of attractors",
        15,
        |i| Some(a.cells[i].as_ref().map_or(BLANK, |c| shade(c.len()))),
        &[],
    )?;
    let mut counts = [0u64; 5];
    for c in &a.cells {
        counts[c.as_ref().map_or(0, |c| c.len().min(4))] += 1;
    }
    let rows: Vec<(String, RGBColor)> = (1..=4)
        .map(|n| {
            (
                format!(
                    "{n}{} attractor{}  ({})",
                    if n == 4 { " or more" } else { "" },
                    if n == 1 { "" } else { "s" },
                    counts[n]
                ),
                shade(n),
            )
        })
        .chain(std::iter::once((format!("not sampled  ({})", counts[0]), BLANK)))
        .collect();
    draw_legend(&legend, "cells", &[], &rows)
}
