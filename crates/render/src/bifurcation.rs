//! The bifurcation diagram of a sweep, as in the literature: one panel per
//! section against the swept parameter — the period section (displacement of
//! the first labelled mass at t = kT) and the impact speed at each stop — drawn
//! from the stored raw section points, up-sweep blue, down-sweep red. The
//! number of branches at a parameter value is n (period panel) or the impacts
//! per n periods at that stop.

use crate::{err, font, RenderError};
use grid::{Atlas, SweepKind};
use plotters::prelude::*;
use std::path::Path;

/// Draws the diagram of the first row of `atlas` to a PNG.
pub fn bifurcation(atlas: &Atlas, path: &Path) -> Result<(), RenderError> {
    font::ensure()?;
    let m = &atlas.meta;
    let scene = scene::Scene::parse(&m.scene_toml).map_err(err)?;
    let model = scene.evaluate(&m.overrides).map_err(err)?;
    let mass = model.labels.first().map_or(0, |l| l.mass);
    let sys = solver::System::new(model).map_err(err)?;
    let dof = sys.dof();
    let x = &m.plane.x;
    let panels = 1 + m.stops.len();
    let root = BitMapBackend::new(path, (1100, 260 * panels as u32 + 40)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let root = root
        .titled(
            &format!("{}: continuation in {} (up-sweep blue, down-sweep red)", m.scene_name, x.name),
            ("sans-serif", 22),
        )
        .map_err(err)?;
    let areas = root.split_evenly((panels, 1));
    for (pi, area) in areas.iter().enumerate() {
        // Points (parameter, value, sweep) of this panel.
        let mut pts: Vec<(f64, f64, SweepKind)> = Vec::new();
        for map in &atlas.maps {
            for (ix, cell) in map.cells.iter().take(x.count).enumerate() {
                let Some(c) = cell else { continue };
                let v = x.value(ix);
                if pi == 0 {
                    pts.extend(c.period_section.iter().map(|s| (v, s[mass], map.sweep)));
                } else {
                    let k = pi - 1;
                    let n = &sys.stops[k].normal;
                    pts.extend(c.impact_sections[k].iter().map(|r| {
                        let vel = &r[1 + dof..1 + 2 * dof];
                        (v, -n.iter().zip(vel).map(|(a, b)| a * b).sum::<f64>(), map.sweep)
                    }));
                }
            }
        }
        let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let (lo, hi) = if lo.is_finite() && hi > lo {
            (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
        } else {
            (lo.min(0.0) - 1.0, hi.max(0.0) + 1.0)
        };
        let desc = if pi == 0 {
            format!("x_{} at t = kT", sys.model.masses[mass].name)
        } else {
            format!("impact speed at {}", m.stops[pi - 1])
        };
        let (x0, x1) = if x.count > 1 { (x.start, x.stop) } else { (x.start - 1.0, x.start + 1.0) };
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, lo..hi)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x.name.as_str())
            .y_desc(desc.as_str())
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(pts.iter().map(|&(v, y, s)| {
                let col = if s == SweepKind::Down { RGBColor(214, 39, 40) } else { RGBColor(31, 119, 180) };
                Circle::new((v, y), 1, col.filled())
            }))
            .map_err(err)?;
    }
    root.present().map_err(err)
}
