//! A continued branch of periodic orbits: the fixed point's first coordinate
//! and the largest Floquet multiplier modulus against the parameter, stable
//! parts dark and unstable parts light, bifurcations marked and named.

use crate::axis::range;
use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Draws `points` `(value, x, max |μ|, stable)` with `marks` `(value, kind)`
/// at the size of `page`.
pub fn branch<'o>(
    points: &[(f64, f64, f64, bool)],
    marks: &[(f64, String)],
    title: &str,
    axis: &str,
    mass: &str,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1000, 760), |w| if w < 120.0 { 1.3 * w } else { 0.75 * w })?;
    save!(out, canvas, |root| draw(&root, &canvas, points, marks, title, axis, mass))
}

fn draw<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    points: &[(f64, f64, f64, bool)],
    marks: &[(f64, String)],
    title: &str,
    axis: &str,
    mass: &str,
) -> Result<(), RenderError> {
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, title, layout::TITLE)?;
    let (x0, x1) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (x0, x1) = if x1 > x0 { (x0, x1) } else { (x0 - 1.0, x0 + 1.0) };
    let stable = RGBColor(31, 119, 180);
    let unstable = RGBColor(255, 152, 150);
    let (key, body) = body.split_vertically(legend::height(canvas, 1));
    let rows = [
        Entry::new(Swatch::Line(stable, 1.2, (1.0, 0.0)), "stable"),
        Entry::new(Swatch::Line(unstable, 1.2, (1.0, 0.0)), "unstable"),
        Entry::new(Swatch::Dot(BLACK, 2.0), "bifurcation"),
    ];
    let keys_w: u32 = legend::columns(&key, canvas, &rows, 1).iter().sum();
    let spare = key.dim_in_pixel().0.saturating_sub(keys_w) / 2;
    legend::draw(&key.margin(0, 0, spare as i32, 0), canvas, &rows)?;
    for (pi, area) in body.split_evenly((2, 1)).iter().enumerate() {
        let ys: Vec<f64> = points.iter().map(|p| if pi == 0 { p.1 } else { p.2 }).collect();
        let y = if pi == 1 { range(ys.iter().copied().chain([0.9, 1.1])) } else { range(ys.iter().copied()) };
        let desc = if pi == 0 { format!("x_{mass} at the section") } else { "largest |multiplier|".to_string() };
        let chart = layout::chart(
            area,
            canvas,
            &Axes { caption: None, x: (x0, x1), y, x_desc: axis, y_desc: &desc, x_labels: true, y_label_chars: None },
        )?;
        let plot = chart.plotting_area();
        if pi == 1 {
            plot.draw(&PathElement::new(vec![(x0, 1.0), (x1, 1.0)], BLACK.mix(0.4).stroke_width(canvas.pt(0.5))))
                .map_err(err)?;
        }
        for w in points.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let (ya, yb) = if pi == 0 { (a.1, b.1) } else { (a.2, b.2) };
            let col = if a.3 && b.3 { stable } else { unstable };
            plot.draw(&PathElement::new(vec![(a.0, ya), (b.0, yb)], col.stroke_width(canvas.pt(1.2)))).map_err(err)?;
        }
        let pad = 0.05 * (y.1 - y.0);
        for (v, kind) in marks {
            let at = points.iter().min_by(|p, q| (p.0 - v).abs().total_cmp(&(q.0 - v).abs()));
            let yv = at.map_or(0.0, |p| if pi == 0 { p.1 } else { p.2 });
            plot.draw(&Circle::new((*v, yv), canvas.pt(2.0), BLACK.filled())).map_err(err)?;
            plot.draw(&Text::new(kind.clone(), (*v, yv + pad), canvas.font(layout::FOOT))).map_err(err)?;
        }
    }
    Ok(())
}
