//! The coloured (x, y) map of one mass's labels, as in the literature: one
//! rectangle per cell in the label's fixed colour ([`maps::palette`]: the same
//! label has the same colour in every figure), and a legend beside or below
//! the map of the labels present, most frequent first (the rest grouped by
//! family, hatched), that says what p and q count.
//!
//! Hysteresis is drawn as three panels, so that no map is hidden: the up
//! sweep, the down sweep, and the cells where they end on different periodic
//! motions, each split along its rising diagonal: the up label's colour above,
//! the down label's below, with a legend of the most frequent (up, down)
//! pairs; the other cells white.

use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use maps::palette::{self, colour, delta_e, Family};
use maps::{Atlas, Axis, CellData, Meta, SweepKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use scene::Named;
use solver::Label;
use std::collections::HashMap;

/// What a map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// The labels of one sweep.
    Sweep(SweepKind),
    /// Up | down | where they differ.
    Hysteresis,
}

/// `hysteresis`, or the name of a sweep (`fresh`, `up`, `down`).
impl Named for View {
    const ALL: &'static [View] =
        &[View::Sweep(SweepKind::Fresh), View::Sweep(SweepKind::Up), View::Sweep(SweepKind::Down), View::Hysteresis];

    fn name(self) -> &'static str {
        match self {
            View::Sweep(sweep) => sweep.name(),
            View::Hysteresis => "hysteresis",
        }
    }

    fn help(self) -> &'static str {
        match self {
            View::Sweep(SweepKind::Fresh) => "The fresh cells.",
            View::Sweep(SweepKind::Up) => "The up sweep.",
            View::Sweep(SweepKind::Down) => "The down sweep.",
            View::Hysteresis => "Up | down | where they differ.",
        }
    }
}

impl std::fmt::Display for View {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Colour of cells a panel does not show (not computed, or no hysteresis):
/// white, apart from every label's colour.
const BLANK: RGBColor = RGBColor(palette::BLANK[0], palette::BLANK[1], palette::BLANK[2]);
/// Most labels a legend lists one by one; the rest are summed per family.
const LEGEND_ROWS: usize = 30;
/// A legend goes beside the panels on canvases at least this many text
/// heights wide, below them on narrower ones.
const LEGEND_BESIDE_EM: f64 = 50.0;
/// Rows of a legend below the panels, at most (a hysteresis view's legend,
/// with its two lists, may take half as many again).
const LEGEND_BELOW_ROWS: usize = 9;
/// A legend below the panels leaves them at least this many text heights.
const MIN_PANEL_EM: f64 = 14.0;
/// The least size of a map panel (width, height in text heights), by which
/// several panels are arranged.
const PANEL_EM: (f64, f64) = (16.0, 12.0);

/// The plotters colour of a label.
pub(crate) fn rgb(label: Label) -> RGBColor {
    let [r, g, b] = colour(label);
    RGBColor(r, g, b)
}

/// The cells of one sweep of `atlas`, or an error naming the missing sweep.
pub(crate) fn sweep_cells(atlas: &Atlas, sweep: SweepKind) -> Result<&[Option<CellData>], RenderError> {
    atlas
        .map(sweep)
        .map(|m| m.cells.as_slice())
        .ok_or_else(|| RenderError::new(format!("the file has no '{}' sweep", sweep.name())))
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

    /// The point at fractional cell indices `(fx, fy)`: cell centres at
    /// whole ones, linear between them.
    pub(crate) fn at(&self, fx: f64, fy: f64) -> (f64, f64) {
        (self.x.value(0) + fx * self.dx, self.y.value(0) + fy * self.dy)
    }

    /// Corners of cell `i`.
    pub(crate) fn rect(&self, i: usize) -> [(f64, f64); 2] {
        let (cx, cy) = self.centre(i);
        [(cx - self.dx / 2.0, cy - self.dy / 2.0), (cx + self.dx / 2.0, cy + self.dy / 2.0)]
    }

    /// A chart over the whole plane (half a cell of margin), axes named after
    /// the parameters' symbols.
    pub(crate) fn chart<'b, DB: Backend>(
        &self,
        area: &'b DrawingArea<DB, Shift>,
        canvas: &Canvas,
        meta: &Meta,
        title: &str,
    ) -> Result<layout::Chart<'b, DB>, RenderError> {
        let (x, y, dx, dy) = (self.x, self.y, self.dx, self.dy);
        let axes = Axes {
            caption: (!title.is_empty()).then_some(title),
            x: (x.start - dx / 2.0, x.stop + dx / 2.0),
            y: (y.start - dy / 2.0, y.stop + dy / 2.0),
            x_desc: &meta.symbol(&x.name),
            y_desc: &meta.symbol(&y.name),
            x_labels: true,
            y_label_chars: None,
        };
        layout::chart(area, canvas, &axes)
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

impl Overlay {
    /// A curve of `kind` in the parameters `free`, through `points` with
    /// codimension-two points `marks` (each in the order of `free`), as an
    /// overlay of `plane`, whose axes its parameters must be in either order
    /// (`None` otherwise).
    pub fn on(
        plane: &maps::Plane,
        kind: &str,
        free: &[String; 2],
        points: &[(f64, f64)],
        marks: impl IntoIterator<Item = (f64, f64)>,
    ) -> Option<Overlay> {
        let swap = match (free[0].as_str(), free[1].as_str()) {
            (a, b) if a == plane.x.name && b == plane.y.name => false,
            (a, b) if a == plane.y.name && b == plane.x.name => true,
            _ => return None,
        };
        let xy = |(a, b): (f64, f64)| if swap { (b, a) } else { (a, b) };
        let (points, marks) = (points.iter().copied().map(xy).collect(), marks.into_iter().map(xy).collect());
        Some(Overlay { kind: kind.to_string(), points, marks })
    }
}

/// Line style of a kind of curve: colour, width (pt) and dash (pt on, off).
pub(crate) fn curve_style(kind: &str) -> (RGBColor, f64, (f64, f64)) {
    match kind {
        "PD" => (RGBColor(213, 94, 0), 1.3, (4.0, 1.5)),
        "SN" => (RGBColor(0, 0, 0), 1.3, (1.0, 0.0)),
        "PF" => (RGBColor(204, 121, 167), 1.3, (6.0, 2.0)),
        "NS" => (RGBColor(0, 114, 178), 1.3, (1.2, 1.2)),
        _ => (RGBColor(0, 0, 0), 1.0, (2.5, 1.5)),
    }
}

/// How one cell is painted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Paint {
    /// One colour.
    Fill(RGBColor),
    /// Split along the rising diagonal: the first colour above, the second below.
    Split(RGBColor, RGBColor),
}

/// The least size on a printed page, in millimetres, of a cell drawn split
/// along its diagonal: smaller halves alias into a moiré in which neither
/// colour reads once printed (a 296-cell-wide plane in a 12 cm panel has
/// 0.4 mm cells; 0.5 mm is 6 pixels at 300 dpi).
const MIN_SPLIT_MM: f64 = 0.5;

/// Draws cells as `paint` gives them (None: not drawn), and `curves` over them.
fn draw_cells<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    meta: &Meta,
    title: &str,
    paint: impl Fn(usize) -> Option<Paint>,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    draw_blocks(area, canvas, meta, title, 1, paint, curves)
}

/// [`draw_cells`] of split cells (the hysteresis panel): on a printed
/// figure whose cells would be smaller than [`MIN_SPLIT_MM`], blocks of
/// k × k cells are drawn, each as the paint most of its cells have (an
/// area-faithful picture of the zones; a tie goes to a split); `title` says
/// the block's side. On screen sizes every cell is drawn (a viewer zooms).
fn draw_split_cells<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    meta: &Meta,
    title: &dyn Fn(usize) -> String,
    paint: impl Fn(usize) -> Option<Paint>,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let (nx, ny) = (meta.plane.x.count as f64, meta.plane.y.count as f64);
    // The plot's size before the chart is built: the area less its axes (about).
    let (w, h) = area.dim_in_pixel();
    let cell = ((w as f64 - canvas.em(8.0) as f64) / nx).min((h as f64 - canvas.em(5.0) as f64) / ny);
    let cell_mm = cell / canvas.dpi * 25.4;
    let k = match canvas.mm {
        Some(_) if cell_mm < MIN_SPLIT_MM => (MIN_SPLIT_MM / cell_mm.max(1e-3)).ceil() as usize,
        _ => 1,
    };
    draw_blocks(area, canvas, meta, &title(k), k, paint, curves)
}

/// Draws the plane's cells in blocks of `k` × `k` cells, each painted as
/// most of its cells are (the cells themselves for blocks of one).
fn draw_blocks<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    meta: &Meta,
    title: &str,
    k: usize,
    paint: impl Fn(usize) -> Option<Paint>,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let grid = CellGrid::of(meta);
    let chart = grid.chart(area, canvas, meta, title)?;
    let plot = chart.plotting_area();
    let (nx, ny, k) = (meta.plane.x.count, meta.plane.y.count, k.max(1));
    for (by, bx) in (0..ny.div_ceil(k)).flat_map(|by| (0..nx.div_ceil(k)).map(move |bx| (by, bx))) {
        let (rows, columns) = (by * k..((by + 1) * k).min(ny), bx * k..((bx + 1) * k).min(nx));
        let (first, last) = (rows.start * nx + columns.start, (rows.end - 1) * nx + columns.end - 1);
        let ([(x0, y0), _], [_, (x1, y1)]) = (grid.rect(first), grid.rect(last));
        let chosen = if k == 1 {
            paint(first)
        } else {
            most(rows.flat_map(|iy| columns.clone().map(move |ix| iy * nx + ix)).filter_map(&paint))
        };
        match chosen {
            None => {}
            Some(Paint::Fill(c)) => plot.draw(&Rectangle::new([(x0, y0), (x1, y1)], c.filled())).map_err(err)?,
            Some(Paint::Split(above, below)) => {
                // The whole cell, then the upper triangle over it: no seam
                // of background between the two halves.
                plot.draw(&Rectangle::new([(x0, y0), (x1, y1)], below.filled())).map_err(err)?;
                plot.draw(&Polygon::new(vec![(x0, y0), (x0, y1), (x1, y1)], above.filled())).map_err(err)?;
            }
        }
    }
    for c in curves {
        let (colour, width, dash) = curve_style(&c.kind);
        legend::line(plot, canvas, &c.points, colour, width, dash)?;
        let r = canvas.pt(2.2);
        for &p in &c.marks {
            plot.draw(&Circle::new(p, r, WHITE.filled())).map_err(err)?;
            plot.draw(&Circle::new(p, r, BLACK.stroke_width(canvas.pt(0.7)))).map_err(err)?;
        }
    }
    Ok(())
}

/// The paint most frequent among `paints` (a tie: a split before a fill,
/// then the first met).
fn most(paints: impl Iterator<Item = Paint>) -> Option<Paint> {
    let mut counts: Vec<(Paint, usize)> = Vec::new();
    for p in paints {
        match counts.iter_mut().find(|(q, _)| *q == p) {
            Some((_, n)) => *n += 1,
            None => counts.push((p, 1)),
        }
    }
    let rank = |(p, n): &(Paint, usize)| (*n, matches!(p, Paint::Split(..)));
    let best = counts.iter().map(rank).max()?;
    counts.iter().find(|c| rank(c) == best).map(|c| c.0)
}

/// Legend rows of the kinds of `curves` (one per kind, in order of appearance).
fn curve_entries(curves: &[Overlay]) -> Vec<Entry> {
    let mut kinds: Vec<&str> = Vec::new();
    for c in curves {
        if !kinds.contains(&c.kind.as_str()) {
            kinds.push(&c.kind);
        }
    }
    let mut rows: Vec<Entry> = kinds
        .iter()
        .map(|k| {
            let (colour, width, dash) = curve_style(k);
            Entry::new(Swatch::Line(colour, width, dash), format!("{k} curve"))
        })
        .collect();
    if curves.iter().any(|c| !c.marks.is_empty()) {
        rows.push(Entry::new(Swatch::Ring(BLACK, 2.2), "codimension-two point"));
    }
    if !rows.is_empty() {
        rows.insert(0, Entry::new(Swatch::Heading, "bifurcation curves"));
    }
    rows
}

/// Paint of one sweep's labels of mass `mass`, cell by cell.
pub(crate) fn label_paint(cells: &[Option<CellData>], mass: usize) -> impl Fn(usize) -> Option<Paint> + '_ {
    move |i| Some(Paint::Fill(cells[i].as_ref().map_or(BLANK, |c| rgb(c.labels[mass]))))
}

/// What p and q count for a mass, e.g. `M1: p = impacts at A12, q = impacts at A1`
/// (`contacts at` for soft stops).
pub(crate) fn pq_text(meta: &Meta, mass: usize) -> String {
    let stops = meta.label_stops.get(mass).cloned().unwrap_or_default();
    let events = meta.stop_events();
    let side = |s: &str| {
        if s.is_empty() {
            return "no stop".to_string();
        }
        let word = meta.stops.iter().position(|n| n == s).map_or("impacts", |k| events[k]);
        format!("{word} at {s}")
    };
    format!(
        "{}: n-p-q, n = period (forcing periods), p = {}, q = {} in n periods",
        meta.masses[mass],
        side(&stops[0]),
        side(&stops[1])
    )
}

/// The run's fixed settings, for a subtitle.
pub(crate) fn settings_text(meta: &Meta) -> String {
    let set: Vec<String> = meta.overrides.iter().map(|(k, v)| format!("{} = {v}", meta.symbol(k))).collect();
    let fixed = if set.is_empty() { "scene defaults".to_string() } else { set.join(", ") };
    format!("{}; preset {}; {}", meta.scene_name, meta.preset.name(), fixed)
}

/// A label's legend text: the letter classes spelled out.
fn label_text(label: Label) -> String {
    match label {
        Label::Chaotic => "C chaotic".to_string(),
        Label::Quasiperiodic => "Q quasi-periodic".to_string(),
        Label::Unresolved => "U unresolved".to_string(),
        l => l.to_string(),
    }
}

/// Least CIEDE2000 difference between the colours of two labels that a
/// legend names one by one (what the palette's table keeps between its
/// labels): a label nearer than this to a more frequent one named is counted
/// in its family's hatched group instead, so that every named swatch can be
/// told apart in the map.
pub(crate) const LEGEND_MIN_DE: f64 = 10.0;

/// Legend rows of `(label, cells)` entries, most frequent first, in at most
/// `room` rows: the most frequent labels one by one (at least half the rows),
/// each at least [`LEGEND_MIN_DE`] from every label named before it; the rest
/// summed per family, or in one row when the families do not fit, each group
/// hatched so that it is never taken for a listed label (a family of one
/// label told apart from the named ones is named too, before the groups).
pub(crate) fn label_entries(counts: &[(Label, u64)], room: usize) -> Vec<Entry> {
    let entry =
        |&(label, n): &(Label, u64)| Entry::new(Swatch::Fill(rgb(label)), format!("{}  ({n})", label_text(label)));
    // Indices of the labels told apart from every more frequent one so told.
    let mut named: Vec<usize> = Vec::new();
    for (i, (label, _)) in counts.iter().enumerate() {
        if named.iter().all(|&j| delta_e(colour(counts[j].0), colour(*label)) >= LEGEND_MIN_DE) {
            named.push(i);
        }
    }
    if named.len() == counts.len() && counts.len() <= room.min(LEGEND_ROWS) {
        return counts.iter().map(entry).collect();
    }
    if room == 0 {
        return Vec::new();
    }
    // The labels not named when the first `k` told apart are, most frequent first.
    let rest = |k: usize| -> Vec<usize> { (0..counts.len()).filter(|i| !named[..k].contains(i)).collect() };
    let families = |rest: &[usize]| {
        let mut g: HashMap<Family, (u64, u64, usize)> = HashMap::new();
        for &i in rest {
            let (label, n) = counts[i];
            let e = g.entry(Family::of(label)).or_insert((0, 0, i));
            e.0 += 1;
            e.1 += n;
        }
        let mut v: Vec<(Family, (u64, u64, usize))> = g.into_iter().collect();
        v.sort_by(|a, b| b.1 .1.cmp(&a.1 .1).then(a.0.name().cmp(b.0.name())));
        v
    };
    let most = LEGEND_ROWS.min(room - 1).min(named.len());
    let fits = (room.div_ceil(2).min(most)..=most).rev().find(|&k| k + families(&rest(k)).len() <= room);
    let listed = fits.unwrap_or(most);
    let mut rows: Vec<Entry> = named[..listed].iter().map(|&i| entry(&counts[i])).collect();
    let rest = rest(listed);
    if fits.is_none() {
        let cells: u64 = rest.iter().map(|&i| counts[i].1).sum();
        rows.push(Entry::new(Swatch::Hatch(RGBColor(90, 90, 90)), format!("+{} other labels ({cells})", rest.len())));
        return rows;
    }
    let mut groups = Vec::new();
    for (fam, (labels, cells, first)) in families(&rest) {
        if labels == 1 && named.contains(&first) {
            rows.push(entry(&counts[first])); // a family of one label: the label itself
        } else {
            let [r, g, b] = fam.colour();
            groups.push(Entry::new(Swatch::Hatch(RGBColor(r, g, b)), format!("+{labels} {} ({cells})", fam.name())));
        }
    }
    rows.extend(groups);
    rows
}

/// `(label, cells)` of mass `mass` over several sweeps' cells, most frequent first.
pub(crate) fn count(cells: &[&[Option<CellData>]], mass: usize) -> Vec<(Label, u64)> {
    maps::label_counts(cells.iter().flat_map(|c| c.iter()).flatten(), mass)
}

/// A legend placed beside the panels on a wide canvas (one column as high
/// as the panels), below them on a narrow one (columns across the width, at
/// most `below_rows` rows), with as many rows as `make(room)` gives for the
/// largest room that fits.
struct Placed {
    rows: Vec<Entry>,
    beside: bool,
    size: u32,
}

fn place<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    below_rows: usize,
    make: impl Fn(usize) -> Vec<Entry>,
) -> Placed {
    let (w, h) = area.dim_in_pixel();
    // Rows below that still leave the panels their least height.
    let spare = h.saturating_sub(canvas.emu(MIN_PANEL_EM));
    let below_rows = below_rows.min((1..=below_rows).rev().find(|&r| legend::height(canvas, r) <= spare).unwrap_or(0));
    if canvas.width_em() >= LEGEND_BESIDE_EM || below_rows < 5 {
        let rows = make(legend::rows(canvas, h));
        let size = legend::width(area, canvas, &rows).min(w / 2);
        return Placed { rows, beside: true, size };
    }
    let mut room = make(usize::MAX).len();
    loop {
        let rows = make(room);
        let tall = (1..=below_rows).find(|&r| legend::columns(area, canvas, &rows, r).iter().sum::<u32>() <= w);
        match tall {
            Some(r) => return Placed { size: legend::height(canvas, r), rows, beside: false },
            None if room <= 1 => return Placed { size: legend::height(canvas, below_rows), rows, beside: false },
            None => room -= 1,
        }
    }
}

impl Placed {
    /// `area` split into the panels' area and the legend's.
    fn split<DB: Backend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        canvas: &Canvas,
    ) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>) {
        let (w, h) = area.dim_in_pixel();
        if self.beside {
            area.split_horizontally(w.saturating_sub(self.size + canvas.emu(0.5)))
        } else {
            area.split_vertically(h.saturating_sub(self.size))
        }
    }

    /// Draws the legend into its area.
    fn draw<DB: Backend>(&self, area: &DrawingArea<DB, Shift>, canvas: &Canvas) -> Result<(), RenderError> {
        legend::draw(area, canvas, &self.rows)
    }
}

/// Draws the map of mass `mass` (index into `atlas.meta.masses`) at the size
/// of `page`, to `out` ([`Out`]: a file in the format of its extension, or bytes). `curves` are drawn over every panel.
pub fn map<'o>(
    atlas: &Atlas,
    view: View,
    mass: usize,
    curves: &[Overlay],
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    if mass >= atlas.meta.masses.len() {
        return Err(RenderError::new(match atlas.meta.masses.len() {
            0 => "the atlas labels no mass (its scene has no [labels] table): draw its lyapunov or multiplier view, or a quantity".to_string(),
            k => format!("mass {mass} of an atlas that labels {k}"),
        }));
    }
    let panels = if view == View::Hysteresis { 3 } else { 1 };
    let narrow = |w: f64| w < 120.0;
    let height = |w: f64| match (view, narrow(w)) {
        (View::Sweep(_), true) => 1.3 * w,
        (View::Sweep(_), false) => 0.7 * w,
        (View::Hysteresis, true) => 2.45 * w,
        (View::Hysteresis, false) => 0.85 * w,
    };
    let out = out.into();
    let canvas = Canvas::of(page, &out, (760 * panels + 380, 800), height)?;
    save!(out, canvas, |root| draw_map(&root, &canvas, atlas, view, mass, curves))
}

fn draw_map<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    atlas: &Atlas,
    view: View,
    mass: usize,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, &pq_text(m, mass), layout::TITLE)?;
    let body = layout::footer(&body, canvas, &settings_text(m))?;
    let name = &m.masses[mass];
    match view {
        View::Sweep(sweep) => {
            let cells = sweep_cells(atlas, sweep)?;
            let counts = count(&[cells], mass);
            let placed = place(&body, canvas, LEGEND_BELOW_ROWS, |room| sweep_rows(&counts, curves, room));
            let (maps, key) = placed.split(&body, canvas);
            let title = format!("{name}, {} sweep", sweep.name());
            draw_cells(&maps, canvas, m, &title, label_paint(cells, mass), curves)?;
            placed.draw(&key, canvas)
        }
        View::Hysteresis => draw_hysteresis(&body, canvas, atlas, mass, curves),
    }
}

/// The three panels of the hysteresis view and their legend: labels of both
/// sweeps, then the (up, down) pairs of the differing cells.
fn draw_hysteresis<DB: Backend>(
    body: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    atlas: &Atlas,
    mass: usize,
    curves: &[Overlay],
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    let h = Hysteresis::of(atlas, mass)?;
    let placed = place(body, canvas, LEGEND_BELOW_ROWS * 3 / 2, |room| h.rows(curves, room));
    let (maps, key) = placed.split(body, canvas);
    let name = &m.masses[mass];
    let panels = |up: &DrawingArea<DB, Shift>, down: &DrawingArea<DB, Shift>, differ: &DrawingArea<DB, Shift>| {
        draw_cells(up, canvas, m, &format!("{name}, up sweep"), label_paint(h.up, mass), curves)?;
        draw_cells(down, canvas, m, &format!("{name}, down sweep"), label_paint(h.down, mass), curves)?;
        let zones = h.zones();
        let title = |k: usize| match k {
            1 => format!("up / down differ: {zones} cells"),
            k => format!("up / down differ: {zones} cells; in blocks of {k} × {k}"),
        };
        draw_split_cells(differ, canvas, m, &title, |i| Some(h.paint(i)), curves)
    };
    if placed.beside && layout::grid_columns(&maps, canvas, 3, PANEL_EM) < 3 {
        // Stacked beside the legend the panels would be strips, or a grid
        // with an empty quarter: two up instead (up | down over differ |
        // legend), each panel its aspect.
        // The legend as wide as its columns need, between half and three
        // fifths of the width; the differing cells keep the rest.
        let (w, height) = body.dim_in_pixel();
        let (top, bottom) = body.split_vertically(height / 2);
        let sweeps = top.split_evenly((1, 2));
        let per_column = legend::rows(canvas, bottom.dim_in_pixel().1.saturating_sub(canvas.emu(1.0)));
        let all = h.rows(curves, usize::MAX);
        let need = legend::columns(&bottom, canvas, &all, per_column).iter().sum::<u32>() + canvas.emu(1.0);
        let (differ, key) = bottom.split_horizontally(w - need.clamp(w / 2, 3 * w / 5));
        panels(&sweeps[0], &sweeps[1], &differ)?;
        let key = key.margin(canvas.em(0.5), canvas.em(0.5), canvas.em(0.5), 0);
        let width = key.dim_in_pixel().0;
        let fits = |rows: &[Entry]| legend::columns(&key, canvas, rows, per_column).iter().sum::<u32>() <= width;
        let rows = (1..=all.len()).rev().map(|room| h.rows(curves, room)).find(|r| fits(r)).unwrap_or_default();
        return legend::draw(&key, canvas, &rows);
    }
    let grid = layout::grid(&maps, canvas, 3, PANEL_EM);
    panels(&grid[0], &grid[1], &grid[2])?;
    placed.draw(&key, canvas)
}

/// The labels of a sweep's map and their legend: the curves drawn over it,
/// then its labels (`counts`), in `room` rows.
pub(crate) fn sweep_rows(counts: &[(Label, u64)], curves: &[Overlay], room: usize) -> Vec<Entry> {
    let mut rows = curve_entries(curves);
    rows.push(Entry::new(Swatch::Heading, "label (cells)"));
    rows.extend(label_entries(counts, room.saturating_sub(rows.len())));
    rows
}

/// The hysteresis of one mass: both sweeps' cells, where they end on
/// different periodic motions, and the (up, down) label pairs there.
pub(crate) struct Hysteresis<'a> {
    /// The up sweep's cells.
    pub up: &'a [Option<CellData>],
    /// The down sweep's cells.
    pub down: &'a [Option<CellData>],
    /// 1 where they differ.
    hyst: Vec<u8>,
    /// The (up, down) label pairs where they differ, most frequent first.
    pairs: Vec<((Label, Label), u64)>,
    /// The labels of both sweeps, most frequent first.
    counts: Vec<(Label, u64)>,
    mass: usize,
}

impl Hysteresis<'_> {
    /// The hysteresis of mass `mass` of `atlas` (an error without both sweeps).
    pub fn of(atlas: &Atlas, mass: usize) -> Result<Hysteresis<'_>, RenderError> {
        let (up, down) = (sweep_cells(atlas, SweepKind::Up)?, sweep_cells(atlas, SweepKind::Down)?);
        let hyst = atlas
            .hysteresis()
            .ok_or_else(|| RenderError::new("the hysteresis view needs an atlas with up and down sweeps"))?;
        let label = |c: &Option<CellData>| c.as_ref().map(|c| c.labels[mass]);
        let mut pairs: HashMap<(Label, Label), u64> = HashMap::new();
        for (i, &h) in hyst.iter().enumerate() {
            if let (1, Some(a), Some(b)) = (h, label(&up[i]), label(&down[i])) {
                *pairs.entry((a, b)).or_default() += 1;
            }
        }
        let counts = count(&[up, down], mass);
        let pairs = maps::by_frequency(pairs, |(a, b)| (a.to_string(), b.to_string()));
        Ok(Hysteresis { up, down, hyst, pairs, counts, mass })
    }

    /// Cells where the sweeps differ.
    pub fn zones(&self) -> u64 {
        self.pairs.iter().map(|p| p.1).sum()
    }

    /// Cell `i` of the third panel: split between its up and down labels
    /// where they differ; where both sweeps computed it and they agree, the
    /// same split in their colours faded ([`palette::faded`]: one colour
    /// where the labels are the same); blank where a sweep did not compute it.
    pub fn paint(&self, i: usize) -> Paint {
        let m = self.mass;
        match (self.hyst[i], &self.up[i], &self.down[i]) {
            (1, Some(a), Some(b)) => Paint::Split(rgb(a.labels[m]), rgb(b.labels[m])),
            (_, Some(a), Some(b)) => match (a.labels[m], b.labels[m]) {
                (a, b) if a == b => Paint::Fill(faded(a)),
                (a, b) => Paint::Split(faded(a), faded(b)),
            },
            _ => Paint::Fill(BLANK),
        }
    }

    /// Cells both sweeps computed without a hysteresis between them (drawn
    /// faded).
    fn agreeing(&self) -> u64 {
        let both = |i: &usize| self.up[*i].is_some() && self.down[*i].is_some();
        (0..self.hyst.len()).filter(|&i| self.hyst[i] == 0).filter(both).count() as u64
    }

    /// The legend in `room` rows: the curves, the labels of both sweeps,
    /// then the (up, down) pairs (up to two fifths of the rows, the rest
    /// summed in one).
    pub fn rows(&self, curves: &[Overlay], room: usize) -> Vec<Entry> {
        let pair_entry = |&((a, b), n): &((Label, Label), u64)| {
            Entry::new(Swatch::Split(rgb(a), rgb(b)), format!("{a} / {b}  ({n})"))
        };
        let curve_rows = curve_entries(curves);
        let pairs = &self.pairs;
        let room = room.saturating_sub(3 + curve_rows.len());
        let pair_room = if pairs.len() <= room / 2 { pairs.len() } else { (2 * room / 5).max(2) };
        let mut pair_rows: Vec<Entry> = pairs.iter().take(pair_room.saturating_sub(1)).map(pair_entry).collect();
        match &pairs[pair_rows.len()..] {
            [] => {}
            [last] => pair_rows.push(pair_entry(last)),
            rest => {
                let cells: u64 = rest.iter().map(|p| p.1).sum();
                let text = format!("+{} pairs ({cells})", rest.len());
                pair_rows.push(Entry::new(Swatch::Hatch(RGBColor(90, 90, 90)), text));
            }
        }
        let mut rows = curve_rows;
        rows.push(Entry::new(Swatch::Heading, "label (cells, both)"));
        rows.extend(label_entries(&self.counts, room.saturating_sub(pair_rows.len())));
        rows.push(Entry::new(Swatch::Heading, "up / down (cells)"));
        rows.extend(pair_rows);
        let agree = RGBColor(150, 150, 150);
        rows.push(Entry::new(Swatch::Fill(faded_rgb(agree)), format!("agree: label faded ({})", self.agreeing())));
        rows
    }
}

/// Draws a contact sheet: the maps of one mass and sweep for several atlases
/// (a study), side by side with one legend; a label has the same colour in
/// every panel.
pub fn sheet<'o>(
    panels: &[(String, Atlas)],
    sweep: SweepKind,
    mass: usize,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols);
    let screen = (560 * cols as u32 + 340, 440 * rows as u32 + 40);
    let out = out.into();
    let canvas = Canvas::of(page, &out, screen, |w| {
        if w < 120.0 {
            w * 0.75 * rows as f64 + 60.0
        } else {
            w * 0.4 * rows as f64 + 30.0
        }
    })?;
    save!(out, canvas, |root| draw_sheet(&root, &canvas, panels, sweep, mass))
}

fn draw_sheet<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    panels: &[(String, Atlas)],
    sweep: SweepKind,
    mass: usize,
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let title = panels.first().map_or(String::new(), |(_, a)| pq_text(&a.meta, mass));
    let body = layout::header(root, canvas, &title, layout::TITLE)?;
    let all: Vec<&[Option<CellData>]> = panels.iter().map(|(_, a)| sweep_cells(a, sweep)).collect::<Result<_, _>>()?;
    let counts = count(&all, mass);
    let placed = place(&body, canvas, LEGEND_BELOW_ROWS, |room| {
        let mut rows = vec![Entry::new(Swatch::Heading, "label (cells, all panels)")];
        rows.extend(label_entries(&counts, room.saturating_sub(1)));
        rows
    });
    let (maps, key) = placed.split(&body, canvas);
    for ((title, atlas), (area, cells)) in
        panels.iter().zip(layout::grid(&maps, canvas, panels.len(), PANEL_EM).iter().zip(&all))
    {
        draw_cells(area, canvas, &atlas.meta, title, label_paint(cells, mass), &[])?;
    }
    placed.draw(&key, canvas)
}

/// The colour of `label` faded toward white ([`palette::faded`]).
fn faded(label: Label) -> RGBColor {
    faded_rgb(rgb(label))
}

fn faded_rgb(c: RGBColor) -> RGBColor {
    let [r, g, b] = palette::faded([c.0, c.1, c.2]);
    RGBColor(r, g, b)
}

/// Colours of 1, 2, 3 and 4 or more coexisting attractors (light to dark).
const COEXISTING: [RGBColor; 4] =
    [RGBColor(198, 219, 239), RGBColor(107, 174, 214), RGBColor(33, 113, 181), RGBColor(8, 48, 107)];

/// Draws the number of coexisting attractors found in each sampled cell of
/// `atlas` (`atlas --attractors`), cells not sampled white (to `out`: [`Out`]).
pub fn attractor_map<'o>(atlas: &Atlas, page: &Page, out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let a = atlas.attractors.as_ref().ok_or_else(|| RenderError::lacks(crate::error::Missing::Attractors))?;
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1140, 800), |w| if w < 120.0 { 1.15 * w } else { 0.65 * w })?;
    save!(out, canvas, |root| draw_attractors(&root, &canvas, atlas, a))
}

fn draw_attractors<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    atlas: &Atlas,
    a: &maps::AttractorMap,
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    root.fill(&WHITE).map_err(err)?;
    let title = format!("coexisting attractors ({} sampled initial states per cell, seed {})", a.samples, a.seed);
    let body = layout::header(root, canvas, &title, layout::TITLE)?;
    let body = layout::footer(&body, canvas, &settings_text(m))?;
    let shade = |n: usize| COEXISTING[n.clamp(1, 4) - 1];
    let mut counts = [0u64; 5];
    for c in &a.cells {
        counts[c.as_ref().map_or(0, |c| c.len().min(4))] += 1;
    }
    let mut rows = vec![Entry::new(Swatch::Heading, "cells")];
    rows.extend((1..=4).filter(|&n| counts[n] > 0).map(|n| {
        let more = if n == 4 { " or more" } else { "" };
        let plural = if n == 1 { "" } else { "s" };
        Entry::new(Swatch::Fill(shade(n)), format!("{n}{more} attractor{plural}  ({})", counts[n]))
    }));
    if counts[0] > 0 {
        rows.push(Entry::new(Swatch::Fill(BLANK), format!("not sampled  ({})", counts[0])));
    }
    let placed = place(&body, canvas, LEGEND_BELOW_ROWS, |_| rows.clone());
    let (plot, key) = placed.split(&body, canvas);
    let paint = |i: usize| Some(Paint::Fill(a.cells[i].as_ref().map_or(BLANK, |c| shade(c.len()))));
    draw_cells(&plot, canvas, m, "number of attractors", paint, &[])?;
    placed.draw(&key, canvas)
}

/// Colours of a family's basin fraction in bands of a quarter (light to
/// dark, the blues of [`COEXISTING`] from white): absent, then the
/// intervals (0, 25 %], (25, 50 %], (50, 75 %] and (75, 100 %].
const FRACTION_BANDS: [RGBColor; 5] = [
    RGBColor(255, 255, 255),
    RGBColor(198, 219, 239),
    RGBColor(107, 174, 214),
    RGBColor(33, 113, 181),
    RGBColor(8, 48, 107),
];

/// The attractors of `atlas` and their families (`maps::families`), where
/// family `family` is one of them: what [`family_map`] draws, checked
/// before a file is written for it.
pub fn family_of(atlas: &Atlas, family: u32) -> Result<(&maps::AttractorMap, maps::Families), RenderError> {
    let a = atlas.attractors.as_ref().ok_or_else(|| RenderError::lacks(crate::error::Missing::Attractors))?;
    let f = maps::families(a, atlas.meta.plane.x.count);
    if family as usize >= f.labels.len() {
        return Err(RenderError::new(format!(
            "basin:{family}: the file's attractors form {} families (0 to {})",
            f.labels.len(),
            f.labels.len().saturating_sub(1)
        )));
    }
    Ok((a, f))
}

/// Draws the basin fraction of attractor family `family` of `atlas`
/// (`maps::families`) in each sampled cell, in bands of a quarter; cells
/// not sampled grey (to `out`: [`Out`]).
pub fn family_map<'o>(atlas: &Atlas, family: u32, page: &Page, out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let (a, f) = family_of(atlas, family)?;
    let labels = &f.labels[family as usize];
    let named: Vec<String> = atlas.meta.masses.iter().zip(labels).map(|(m, l)| format!("{m} {l}")).collect();
    let fractions = f.fraction_map(a, family);
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1140, 800), |w| if w < 120.0 { 1.15 * w } else { 0.65 * w })?;
    save!(out, canvas, |root| draw_family(&root, &canvas, atlas, a.samples, &named.join(", "), family, &fractions))
}

/// The band of a basin fraction (0: absent; 1 to 4: up to 25, 50, 75, 100 %).
fn band(fraction: f64) -> usize {
    if fraction <= 0.0 {
        0
    } else {
        ((fraction * 4.0).ceil() as usize).clamp(1, 4)
    }
}

fn draw_family<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    atlas: &Atlas,
    samples: usize,
    named: &str,
    family: u32,
    fractions: &[f64],
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    root.fill(&WHITE).map_err(err)?;
    let title = format!("basin fraction of attractor family {family} ({named}), {samples} initial states per cell");
    let body = layout::header(root, canvas, &title, layout::TITLE)?;
    let body = layout::footer(&body, canvas, &settings_text(m))?;
    let mut counts = [0u64; 6];
    for &f in fractions {
        counts[if f.is_nan() { 5 } else { band(f) }] += 1;
    }
    let texts = ["absent", "(0, 25 %]", "(25, 50 %]", "(50, 75 %]", "(75, 100 %]"];
    let mut rows = vec![Entry::new(Swatch::Heading, "cells")];
    rows.extend(
        (0..5)
            .filter(|&b| counts[b] > 0)
            .map(|b| Entry::new(Swatch::Fill(FRACTION_BANDS[b]), format!("{}  ({})", texts[b], counts[b]))),
    );
    if counts[5] > 0 {
        rows.push(Entry::new(Swatch::Fill(BLANK), format!("not sampled  ({})", counts[5])));
    }
    let placed = place(&body, canvas, LEGEND_BELOW_ROWS, |_| rows.clone());
    let (plot, key) = placed.split(&body, canvas);
    let paint = |i: usize| {
        let f = fractions[i];
        Some(Paint::Fill(if f.is_nan() { BLANK } else { FRACTION_BANDS[band(f)] }))
    };
    draw_cells(&plot, canvas, m, "basin fraction", paint, &[])?;
    placed.draw(&key, canvas)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells a legend row counts: the number in its last parentheses.
    fn cells(e: &Entry) -> u64 {
        let open = e.text.rfind('(').expect("a count");
        e.text[open + 1..e.text.len() - 1].parse().expect("a number")
    }

    fn label(text: &str) -> Label {
        text.parse().unwrap_or_else(|e| panic!("{e}"))
    }

    fn colour(text: &str) -> [u8; 3] {
        super::colour(label(text))
    }

    fn named(rows: &[Entry]) -> Vec<(String, [u8; 3])> {
        rows.iter()
            .filter_map(|e| match e.swatch {
                Swatch::Fill(c) => Some((e.text.split_whitespace().next().unwrap().to_string(), [c.0, c.1, c.2])),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn legends_name_only_labels_told_apart_by_colour() {
        // Two pairs of the tour's second mass that the palette's rules put
        // near each other (ΔE 4.1 and 8.3), among labels told apart.
        for (a, b) in [("4-0-2", "3-0-6"), ("1-1-6", "1-0-12")] {
            assert!(delta_e(colour(a), colour(b)) < LEGEND_MIN_DE, "{a} and {b} are told apart: pick another pair");
        }
        // docs/gallery.md quotes the first pair's difference.
        let d = delta_e(colour("4-0-2"), colour("3-0-6"));
        assert!((d - 4.1).abs() < 0.05, "docs/gallery.md says ΔE 4.1, it is {d:.2}");
        let labels = ["1-1-1", "4-0-2", "3-0-6", "1-1-6", "1-0-12", "C", "2-1-1", "1-0-1"];
        let counts: Vec<(Label, u64)> =
            labels.iter().enumerate().map(|(i, l)| (label(l), 1000 - 10 * i as u64)).collect();
        for room in [4, 6, 9, 40] {
            let rows = label_entries(&counts, room);
            assert!(rows.len() <= room, "{} rows in room for {room}", rows.len());
            let named = named(&rows);
            for (i, (a, ca)) in named.iter().enumerate() {
                for (b, cb) in &named[..i] {
                    let d = delta_e(*ca, *cb);
                    assert!(d >= LEGEND_MIN_DE, "room {room}: {a} and {b} both named, ΔE {d:.1}");
                }
            }
            assert!(!named.iter().any(|(l, _)| l == "3-0-6" || l == "1-0-12"), "room {room}: {named:?}");
            // No cell lost or counted twice.
            let total: u64 = rows.iter().map(cells).sum();
            assert_eq!(total, counts.iter().map(|c| c.1).sum::<u64>(), "room {room}");
            // Groups come after every named label.
            let first_group = rows.iter().position(|e| matches!(e.swatch, Swatch::Hatch(_)));
            let last_named = rows.iter().rposition(|e| matches!(e.swatch, Swatch::Fill(_)));
            if let (Some(g), Some(n)) = (first_group, last_named) {
                assert!(n < g, "room {room}: a named label after a group: {:?}", rows);
            }
        }
        // Labels of the palette's table (ΔE ≥ 10.25 apart) that fit are all
        // named, most frequent first.
        let table = ["1-1-1", "1-2-2", "1-1-2", "1-3-3", "C", "1-0-1", "1-2-1"];
        let apart: Vec<(Label, u64)> = table.iter().enumerate().map(|(i, l)| (label(l), 90 - i as u64)).collect();
        let rows = label_entries(&apart, 40);
        let names: Vec<String> = named(&rows).into_iter().map(|n| n.0).collect();
        assert_eq!(names, table.map(String::from));
    }
}
