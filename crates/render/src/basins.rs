//! Basins of attraction in a plane of initial states: each sampled initial
//! state ([`basins`]), or each start of a grid ([`basin_map`]), drawn in the
//! colour of the label of the attractor it reaches, with a legend of the
//! attractors and their basin fractions.

use crate::axis::range;
use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::map::rgb;
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use maps::basins::INADMISSIBLE;
use maps::BasinMap;
use plotters::coord::Shift;
use plotters::prelude::*;
use solver::Label;

/// Draws `groups` (legend text, points) in the colours of the labels
/// `colours` (one per group), axes named `axes` (to `out`: [`Out`]).
pub fn basins<'o>(
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[Label],
    title: &str,
    axes: &(String, String),
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1000, 700), |w| if w < 120.0 { 1.1 * w } else { 0.6 * w })?;
    save!(out, canvas, |root| draw(&root, &canvas, groups, colours, title, axes))
}

fn draw<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    groups: &[(String, Vec<(f64, f64)>)],
    colours: &[Label],
    title: &str,
    axes: &(String, String),
) -> Result<(), RenderError> {
    let rows: Vec<Entry> = groups
        .iter()
        .zip(colours)
        .map(|((name, _), &label)| Entry::new(Swatch::Fill(rgb(label)), name.clone()))
        .collect();
    let [plot_area, key] = frame(root, canvas, title, &rows)?;
    let a = Axes {
        caption: None,
        x: range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.0))),
        y: range(groups.iter().flat_map(|g| g.1.iter().map(|p| p.1))),
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

/// The page of a picture with a legend: the title, then the plot's area and
/// the legend's (beside the plot on a wide page, below it on a narrow one).
fn frame<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    title: &str,
    rows: &[Entry],
) -> Result<[DrawingArea<DB, Shift>; 2], RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, title, layout::TITLE)?;
    let column = legend::width(&body, canvas, rows);
    let (w, h) = body.dim_in_pixel();
    let (plot, key) = if canvas.width_em() >= 50.0 {
        body.split_horizontally(w.saturating_sub(column))
    } else {
        body.split_vertically(h.saturating_sub(legend::height(canvas, rows.len())))
    };
    Ok([plot, key])
}

/// The colour of a start that penetrates a stop.
const INADMISSIBLE_GREY: RGBColor = RGBColor(225, 225, 225);

/// Draws the basin map `map`: every start in its attractor's colour
/// ([`BasinMap::colours`]), the periodic attractors' period-section points
/// over them (white dots ringed in black), and a legend of the attractors
/// with their basin fractions (to `out`: [`Out`]).
pub fn basin_map<'o>(map: &BasinMap, page: &Page, out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1000, 700), |w| if w < 120.0 { 1.1 * w } else { 0.6 * w })?;
    save!(out, canvas, |root| draw_map(&root, &canvas, map))
}

fn draw_map<DB: Backend>(root: &DrawingArea<DB, Shift>, canvas: &Canvas, map: &BasinMap) -> Result<(), RenderError> {
    let fills: Vec<RGBColor> = map.colours().into_iter().map(|[r, g, b]| RGBColor(r, g, b)).collect();
    let mut rows: Vec<Entry> = map
        .attractors
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let named: Vec<String> = map.masses.iter().zip(&a.labels).map(|(m, l)| format!("{m} {l}")).collect();
            let what = if named.is_empty() { a.class.clone() } else { named.join(", ") };
            let sym = a.symmetry.as_deref().map_or(String::new(), |s| format!(" {s}"));
            Entry::new(Swatch::Fill(fills[k]), format!("{what}{sym} ({:.1} %)", 100.0 * map.fraction(k)))
        })
        .collect();
    if map.ids.contains(&INADMISSIBLE) {
        rows.push(Entry::new(Swatch::Fill(INADMISSIBLE_GREY), "penetrates a stop"));
    }
    if map.attractors.iter().any(|at| at.class == solver::Class::Periodic.name()) {
        rows.push(Entry::new(Swatch::Ring(BLACK, 1.8), "periodic orbits' section points"));
    }
    let title = format!(
        "{}: basins of attraction, {} × {} starts at phase {:.3} rad",
        map.scene, map.x.count, map.y.count, map.phase
    );
    let [plot_area, key] = frame(root, canvas, &title, &rows)?;
    let step = |a: &maps::Axis| if a.count > 1 { a.step() } else { 1.0 };
    let (dx, dy) = (step(&map.x), step(&map.y));
    let at_start = |name: &str| format!("{name} at the start");
    let a = Axes {
        caption: None,
        x: (map.x.start - dx / 2.0, map.x.stop + dx / 2.0),
        y: (map.y.start - dy / 2.0, map.y.stop + dy / 2.0),
        x_desc: &at_start(&map.x.name),
        y_desc: &at_start(&map.y.name),
        x_labels: true,
        y_label_chars: None,
    };
    let chart = layout::chart(&plot_area, canvas, &a)?;
    let plot = chart.plotting_area();
    for (i, &id) in map.ids.iter().enumerate() {
        let (cx, cy) = (map.x.value(i % map.x.count), map.y.value(i / map.x.count));
        let fill = if id == INADMISSIBLE { INADMISSIBLE_GREY } else { fills[id as usize] };
        let corners = [(cx - dx / 2.0, cy - dy / 2.0), (cx + dx / 2.0, cy + dy / 2.0)];
        plot.draw(&Rectangle::new(corners, fill.filled())).map_err(err)?;
    }
    let (xi, yi) = (component(map, &map.x.name), component(map, &map.y.name));
    let (r, edge) = (canvas.pt(1.8), BLACK.stroke_width(canvas.pt(0.6)));
    let within = |v: f64, (lo, hi): (f64, f64)| lo.min(hi) <= v && v <= lo.max(hi);
    let inside = |(x, y): (f64, f64)| within(x, a.x) && within(y, a.y);
    for at in map.attractors.iter().filter(|at| at.class == solver::Class::Periodic.name()) {
        for p in at.section.iter().map(|s| (s[xi], s[yi])).filter(|&p| inside(p)) {
            plot.draw(&Circle::new(p, r, WHITE.filled())).map_err(err)?;
            plot.draw(&Circle::new(p, r, edge)).map_err(err)?;
        }
    }
    legend::draw(&key, canvas, &rows)
}

/// The index of the state component `name` in the map's states.
fn component(map: &BasinMap, name: &str) -> usize {
    map.components.iter().position(|c| c == name).unwrap_or(0)
}
