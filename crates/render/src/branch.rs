//! A continued branch of periodic orbits: the fixed point's first coordinate
//! and the largest Floquet multiplier modulus against the parameter, stable
//! parts dark and unstable parts light, bifurcations marked and named.

use crate::output::save;
use crate::{err, RenderError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Draws `points` `(value, x, max |μ|, stable)` with `marks` `(value, kind)`.
pub fn branch(
    points: &[(f64, f64, f64, bool)],
    marks: &[(f64, String)],
    title: &str,
    axis: &str,
    mass: &str,
    path: &Path,
) -> Result<(), RenderError> {
    save!(path, (1000, 760), |root| draw(&root, points, marks, title, axis, mass))
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    points: &[(f64, f64, f64, bool)],
    marks: &[(f64, String)],
    title: &str,
    axis: &str,
    mass: &str,
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(err)?;
    let (x0, x1) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (x0, x1) = if x1 > x0 { (x0, x1) } else { (x0 - 1.0, x0 + 1.0) };
    let panels = root.split_evenly((2, 1));
    let stable = RGBColor(31, 119, 180);
    let unstable = RGBColor(255, 152, 150);
    for (pi, area) in panels.iter().enumerate() {
        let ys: Vec<f64> = points.iter().map(|p| if pi == 0 { p.1 } else { p.2 }).collect();
        let (lo, hi) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
        let (lo, hi) = if pi == 1 { (lo.min(0.9), hi.max(1.1)) } else { (lo, hi) };
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 1.0 };
        let desc = if pi == 0 { format!("x_{mass} at the section") } else { "largest |multiplier|".to_string() };
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .margin_right(30)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, (lo - pad)..(hi + pad))
            .map_err(err)?;
        crate::axes(&mut chart, axis, &desc, 14)?;
        if pi == 1 {
            chart.draw_series(LineSeries::new([(x0, 1.0), (x1, 1.0)], BLACK.mix(0.4))).map_err(err)?;
        }
        for w in points.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let (ya, yb) = if pi == 0 { (a.1, b.1) } else { (a.2, b.2) };
            let col = if a.3 && b.3 { stable } else { unstable };
            chart.draw_series(LineSeries::new([(a.0, ya), (b.0, yb)], col.stroke_width(2))).map_err(err)?;
        }
        for (v, kind) in marks {
            let y = points.iter().min_by(|p, q| (p.0 - v).abs().total_cmp(&(q.0 - v).abs())).map_or(0.0, |p| {
                if pi == 0 {
                    p.1
                } else {
                    p.2
                }
            });
            chart.draw_series([Circle::new((*v, y), 5, BLACK.filled())]).map_err(err)?;
            chart.draw_series([Text::new(kind.clone(), (*v, y + pad), ("sans-serif", 16).into_font())]).map_err(err)?;
        }
    }
    Ok(())
}
