//! Phase portraits and time series of one cell's steady motion: per mass its
//! path in the (x, v) plane over the classified window, with its frame stops
//! drawn as vertical lines and the impacts marked; below, the positions of all
//! masses against time with every event marked.

use crate::axis::range;
use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use plotters::coord::Shift;
use plotters::prelude::*;

/// What a portrait shows (all per row of the window). Serialised as an
/// object of these fields (an event as `[row, what]`, a stop as
/// `[mass, position, name]`): Python's `va.cell(..., portrait=True)`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Portrait {
    /// Title (scene and parameters).
    pub title: String,
    /// Names of the masses, in state order.
    pub masses: Vec<String>,
    /// Times.
    pub t: Vec<f64>,
    /// Positions, per mass.
    pub x: Vec<Vec<f64>>,
    /// Velocities, per mass.
    pub v: Vec<Vec<f64>>,
    /// Rows that are events, with what each was (`impact A1`, …).
    pub events: Vec<(usize, String)>,
    /// Frame stops: mass, position, name.
    pub stops: Vec<(usize, f64, String)>,
}

/// Colours of the masses' curves (Okabe–Ito).
const CURVES: [RGBColor; 4] =
    [RGBColor(0, 114, 178), RGBColor(213, 94, 0), RGBColor(0, 158, 115), RGBColor(204, 121, 167)];

/// Draws the portrait (to `out`: [`Out`]).
pub fn portrait<'o>(p: &Portrait, page: &Page, out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1200, 900), |w| if w < 120.0 { 1.5 * w } else { 0.75 * w })?;
    save!(out, canvas, |root| draw(&root, &canvas, p))
}

fn draw<DB: Backend>(root: &DrawingArea<DB, Shift>, canvas: &Canvas, p: &Portrait) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, &p.title, layout::TITLE)?;
    let (top, bottom) = body.split_vertically(body.dim_in_pixel().1 * 4 / 7);
    let panels = layout::panels(&top, p.masses.len().max(1), p.masses.len().max(1));
    let impacts: Vec<usize> = p.events.iter().filter(|e| e.1.starts_with("impact")).map(|e| e.0).collect();
    let dot = canvas.pt(1.3);
    for (k, area) in panels.iter().enumerate() {
        let stops: Vec<&(usize, f64, String)> = p.stops.iter().filter(|s| s.0 == k).collect();
        let (x0, x1) = range(p.x[k].iter().copied().chain(stops.iter().map(|s| s.1)));
        let (v0, v1) = range(p.v[k].iter().copied());
        let caption = format!("{}: phase portrait", p.masses[k]);
        let (xd, vd) = (format!("x_{}", p.masses[k]), format!("v_{}", p.masses[k]));
        let axes = Axes {
            caption: Some(&caption),
            x: (x0, x1),
            y: (v0, v1),
            x_desc: &xd,
            y_desc: &vd,
            x_labels: true,
            y_label_chars: None,
        };
        let chart = layout::chart(area, canvas, &axes)?;
        let plot = chart.plotting_area();
        let colour = CURVES[k % CURVES.len()];
        let path: Vec<(f64, f64)> = p.x[k].iter().copied().zip(p.v[k].iter().copied()).collect();
        plot.draw(&PathElement::new(path, colour.stroke_width(canvas.pt(0.6)))).map_err(err)?;
        for (_, pos, name) in &stops {
            plot.draw(&PathElement::new(vec![(*pos, v0), (*pos, v1)], BLACK.stroke_width(canvas.pt(1.0))))
                .map_err(err)?;
            plot.draw(&Text::new(name.clone(), (*pos, v1), canvas.font(layout::FOOT))).map_err(err)?;
        }
        for &i in &impacts {
            plot.draw(&Circle::new((p.x[k][i], p.v[k][i]), dot, BLACK.filled())).map_err(err)?;
        }
    }
    let (plot_area, key) = bottom.split_horizontally(bottom.dim_in_pixel().0.saturating_sub(canvas.emu(7.0)));
    let axes = Axes {
        caption: Some("positions against time (events marked)"),
        x: range(p.t.iter().copied()),
        y: range(p.x.iter().flatten().copied()),
        x_desc: "t",
        y_desc: "x",
        x_labels: true,
        y_label_chars: None,
    };
    let chart = layout::chart(&plot_area, canvas, &axes)?;
    let plot = chart.plotting_area();
    let mut rows = Vec::new();
    for (k, name) in p.masses.iter().enumerate() {
        let colour = CURVES[k % CURVES.len()];
        let path: Vec<(f64, f64)> = p.t.iter().copied().zip(p.x[k].iter().copied()).collect();
        plot.draw(&PathElement::new(path, colour.stroke_width(canvas.pt(0.9)))).map_err(err)?;
        for (i, _) in &p.events {
            plot.draw(&Circle::new((p.t[*i], p.x[k][*i]), dot, BLACK.filled())).map_err(err)?;
        }
        rows.push(Entry::new(Swatch::Line(colour, 0.9, (1.0, 0.0)), format!("x_{name}")));
    }
    rows.push(Entry::new(Swatch::Dot(BLACK, 1.3), "event"));
    legend::draw(&key.margin(canvas.em(2.0), 0, 0, 0), canvas, &rows)
}
