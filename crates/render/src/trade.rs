//! The speed/accuracy trade as a picture: label agreement with the `precise`
//! reference against cells per second (log scale), one point per setting; the
//! settings that no other beats in both are joined as the Pareto front, and a
//! legend beside the chart names each setting's colour.

use crate::error::{err, RenderError};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Draws `(setting, cells/s, label agreement)` points (a screen-sized figure).
pub fn trade<'o>(points: &[(String, f64, f64)], out: impl Into<Out<'o>>) -> Result<(), RenderError> {
    let out = out.into();
    let canvas = Canvas::of(&Page::screen(), &out, (1000, 600), |w| w)?;
    save!(out, canvas, |root| draw(&root, points))
}

fn draw<DB: Backend>(root: &DrawingArea<DB, Shift>, points: &[(String, f64, f64)]) -> Result<(), RenderError> {
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (lo, hi) = if lo.is_finite() && hi > 0.0 { (lo / 2.0, hi * 2.0) } else { (1.0, 10.0) };
    // Agreement axis from a little below the worst setting to just above 1, so
    // that settings a few cells apart are told apart.
    let amin = points.iter().map(|p| p.2).fold(1.0f64, f64::min);
    let bottom = (amin - (0.5 * (1.0 - amin)).max(0.002)).max(0.0);
    let top = 1.0 + 0.1 * (1.0 - bottom);
    root.fill(&WHITE).map_err(err)?;
    let (plot, legend) = root.split_horizontally(780);
    let mut chart = ChartBuilder::on(&plot)
        .caption("speed / accuracy trade (reference: precise)", (crate::font::FAMILY, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((lo..hi).log_scale(), bottom..top)
        .map_err(err)?;
    // A few round speeds and agreements in per cent: a log axis's every key
    // point written as a decimal overlaps its neighbours.
    chart
        .configure_mesh()
        .x_desc("cells per second")
        .y_desc("label agreement (%)")
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{:.2}", 100.0 * v))
        .light_line_style(RGBColor(238, 238, 238))
        .label_style((crate::font::FAMILY, 15))
        .axis_desc_style((crate::font::FAMILY, 17))
        .draw()
        .map_err(err)?;
    let mut front: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| !points.iter().any(|q| q.1 > p.1 && q.2 >= p.2 || q.1 >= p.1 && q.2 > p.2))
        .map(|p| (p.1, p.2))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart.draw_series(LineSeries::new(front, BLUE.stroke_width(2))).map_err(err)?;
    // Settings close in both speed and agreement would overlap as text: each
    // gets its own colour, named in the legend beside the chart.
    for (i, (name, rate, agree)) in points.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart.draw_series(std::iter::once(Circle::new((*rate, *agree), 6, color.filled()))).map_err(err)?;
        let y = 60 + 26 * i as i32;
        legend.draw(&Circle::new((12, y), 6, color.filled())).map_err(err)?;
        legend.draw(&Text::new(name.clone(), (26, y - 8), (crate::font::FAMILY, 15).into_font())).map_err(err)?;
    }
    Ok(())
}
