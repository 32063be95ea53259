//! Phase portraits and time series of one cell's steady motion: per mass its
//! path in the (x, v) plane over the classified window, with its frame stops
//! drawn as vertical lines and the impacts marked; below, the positions of all
//! masses against time with every event marked.

use crate::output::save;
use crate::{err, RenderError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What a portrait shows (all per row of the window).
#[derive(Debug, Clone, PartialEq)]
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

/// Draws the portrait (format by the extension of `path`).
pub fn portrait(p: &Portrait, path: &Path) -> Result<(), RenderError> {
    save!(path, (1200, 900), |root| draw(&root, p))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &Portrait) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(&p.title, ("sans-serif", 18)).map_err(err)?;
    let (top, bottom) = root.split_vertically(520);
    let panels = top.split_evenly((1, p.masses.len().max(1)));
    let impacts: Vec<usize> = p.events.iter().filter(|e| e.1.starts_with("impact")).map(|e| e.0).collect();
    for (k, area) in panels.iter().enumerate() {
        let stops: Vec<&(usize, f64, String)> = p.stops.iter().filter(|s| s.0 == k).collect();
        let (x0, x1) = crate::range(p.x[k].iter().copied().chain(stops.iter().map(|s| s.1)));
        let (v0, v1) = crate::range(p.v[k].iter().copied());
        let mut chart = ChartBuilder::on(area)
            .caption(format!("{}: phase portrait", p.masses[k]), ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, v0..v1)
            .map_err(err)?;
        crate::axes(&mut chart, &format!("x_{}", p.masses[k]), &format!("v_{}", p.masses[k]), 13)?;
        let colour = CURVES[k % CURVES.len()];
        chart
            .draw_series(LineSeries::new(p.x[k].iter().copied().zip(p.v[k].iter().copied()), colour.stroke_width(1)))
            .map_err(err)?;
        for (_, pos, name) in &stops {
            chart.draw_series(LineSeries::new([(*pos, v0), (*pos, v1)], BLACK.stroke_width(2))).map_err(err)?;
            chart.draw_series([Text::new(name.clone(), (*pos, v1), ("sans-serif", 13).into_font())]).map_err(err)?;
        }
        chart
            .draw_series(impacts.iter().map(|&i| Circle::new((p.x[k][i], p.v[k][i]), 3, BLACK.filled())))
            .map_err(err)?;
    }
    let (t0, t1) = crate::range(p.t.iter().copied());
    let (y0, y1) = crate::range(p.x.iter().flatten().copied());
    let mut chart = ChartBuilder::on(&bottom)
        .caption("positions against time (events marked)", ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(err)?;
    crate::axes(&mut chart, "t", "x", 13)?;
    for (k, name) in p.masses.iter().enumerate() {
        let colour = CURVES[k % CURVES.len()];
        chart
            .draw_series(LineSeries::new(p.t.iter().copied().zip(p.x[k].iter().copied()), colour.stroke_width(2)))
            .map_err(err)?
            .label(format!("x_{name}"))
            .legend(move |(a, b)| PathElement::new(vec![(a, b), (a + 16, b)], colour.stroke_width(2)));
        chart
            .draw_series(p.events.iter().map(|(i, _)| Circle::new((p.t[*i], p.x[k][*i]), 3, BLACK.filled())))
            .map_err(err)?;
    }
    crate::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    Ok(())
}
