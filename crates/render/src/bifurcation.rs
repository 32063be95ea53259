//! The bifurcation diagram of a sweep, as in the literature: one panel per
//! section against the swept parameter — the period section (one state
//! component at t = kT) and, per stop, the impact speed or the forcing phase of
//! each impact — drawn from the stored raw section points as small dots. The
//! number of branches at a parameter value is n (period panel) or the impacts
//! per n periods at that stop. Up and down sweeps are both drawn, with a
//! legend: down as vermillion rings, up as blue dots drawn inside them, so
//! that where they agree both show and where they differ (hysteresis) each can
//! be told apart.

use crate::output::save;
use crate::{err, RenderError};
use grid::{Atlas, SweepKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What the impact panels plot for each impact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Impact {
    /// The normal impact speed `|ġ|` just before the impact.
    Speed,
    /// The forcing phase `ωt mod 2π` of the impact.
    Phase,
}

/// What a diagram shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagram {
    /// The line of the plane drawn (its row, varying x); 0 for a sweep file.
    pub row: usize,
    /// The state component of the period-section panel (index into `[x…, v…]`).
    pub component: usize,
    /// What the impact panels show.
    pub impact: Impact,
}

/// Colour of a sweep in diagrams.
fn sweep_colour(s: SweepKind) -> RGBColor {
    match s {
        SweepKind::Down => RGBColor(213, 94, 0),
        SweepKind::Up => RGBColor(0, 114, 178),
        SweepKind::Fresh => RGBColor(0, 0, 0),
    }
}

/// Name of a state component (`x_M1`, `v_M2`).
pub fn component_name(atlas: &Atlas, k: usize) -> String {
    let names = &atlas.meta.state_masses;
    let n = names.len().max(1);
    format!("{}_{}", if k < n { "x" } else { "v" }, names.get(k % n).map_or("?", String::as_str))
}

/// Draws the diagram (format by the extension of `path`).
pub fn bifurcation(atlas: &Atlas, diagram: &Diagram, path: &Path) -> Result<(), RenderError> {
    let panels = 1 + atlas.meta.stops.len() as u32;
    save!(path, (1100, 250 * panels + 70), |root| draw(&root, atlas, diagram))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, atlas: &Atlas, d: &Diagram) -> Result<(), RenderError> {
    let m = &atlas.meta;
    let (x, y) = (&m.plane.x, &m.plane.y);
    if d.row >= y.count {
        return Err(RenderError { message: format!("row {} is outside the file's {} rows", d.row, y.count) });
    }
    if d.component >= m.dim {
        return Err(RenderError { message: format!("state component {} of {}", d.component, m.dim) });
    }
    let scene = scene::Scene::parse(&m.scene_toml).map_err(err)?;
    let mut set = m.overrides.clone();
    set.push((y.name.clone(), y.value(d.row)));
    let sys = solver::System::new(scene.evaluate(&set).map_err(err)?).map_err(err)?;
    let dof = sys.dof();
    let sweeps: Vec<SweepKind> = atlas.maps.iter().map(|map| map.sweep).collect();
    let directions = match (sweeps.contains(&SweepKind::Up), sweeps.contains(&SweepKind::Down)) {
        (true, true) => "up and down sweeps".to_string(),
        (true, false) => "up sweep".to_string(),
        (false, true) => "down sweep".to_string(),
        _ => "fresh cells".to_string(),
    };
    let fixed = if y.count > 1 { format!(", {} = {}", y.name, crate::tick(y.value(d.row))) } else { String::new() };
    root.fill(&WHITE).map_err(err)?;
    let title = format!("{}: bifurcation diagram in {}{fixed} ({directions})", m.scene_name, x.name);
    let root = root.titled(&title, ("sans-serif", 21)).map_err(err)?;
    let (body, foot) = root.split_vertically(root.dim_in_pixel().1 - 26);
    foot.draw(&Text::new(crate::map::settings_text(m), (12, 4), ("sans-serif", 14).into_font())).map_err(err)?;
    let panels = 1 + m.stops.len();
    for (pi, area) in body.split_evenly((panels, 1)).iter().enumerate() {
        // Points (parameter, value) of this panel, per sweep.
        let mut series: Vec<(SweepKind, Vec<(f64, f64)>)> = Vec::new();
        for map in &atlas.maps {
            let mut pts = Vec::new();
            for ix in 0..x.count {
                let Some(c) = &map.cells[d.row * x.count + ix] else { continue };
                let v = x.value(ix);
                if pi == 0 {
                    pts.extend(c.period_section.iter().map(|s| (v, s[d.component])));
                } else {
                    let k = pi - 1;
                    let n = &sys.stops[k].normal;
                    pts.extend(c.impact_sections[k].iter().map(|r| match d.impact {
                        Impact::Speed => {
                            let vel = &r[1 + dof..1 + 2 * dof];
                            (v, n.iter().zip(vel).map(|(a, b)| a * b).sum::<f64>().abs())
                        }
                        Impact::Phase => (v, (sys.model.omega * r[0]).rem_euclid(std::f64::consts::TAU)),
                    }));
                }
            }
            series.push((map.sweep, pts));
        }
        series.sort_by_key(|s| s.0 != SweepKind::Down);
        let all = series.iter().flat_map(|s| s.1.iter());
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let (lo, hi) = if lo.is_finite() && hi > lo {
            (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
        } else if lo.is_finite() {
            (lo - 1.0, lo + 1.0)
        } else {
            (-1.0, 1.0)
        };
        let desc = if pi == 0 {
            format!("{} at t = kT", component_name(atlas, d.component))
        } else {
            match d.impact {
                Impact::Speed => format!("impact speed at {}", m.stops[pi - 1]),
                Impact::Phase => format!("impact phase at {} (rad)", m.stops[pi - 1]),
            }
        };
        let (x0, x1) = if x.count > 1 { (x.start, x.stop) } else { (x.start - 1.0, x.start + 1.0) };
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .margin_right(25)
            .x_label_area_size(35)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, lo..hi)
            .map_err(err)?;
        crate::axes(&mut chart, &x.name, &desc, 14)?;
        // Down as rings, up as dots inside them: where the sweeps agree both show.
        for (sweep, pts) in &series {
            let col = sweep_colour(*sweep);
            let style = if *sweep == SweepKind::Down { col.stroke_width(1) } else { col.filled() };
            let size = if *sweep == SweepKind::Down { 3 } else { 1 };
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, size, style)))
                .map_err(err)?
                .label(format!("{} sweep", sweep.name()))
                .legend(move |(a, b)| Circle::new((a + 8, b), 4, style));
        }
        if pi > 0 {
            continue; // one legend, in the first panel
        }
        crate::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    }
    Ok(())
}
