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

/// The forcing frequency ω of each cell of row `row`, from the stored
/// scene's forcing expression at the cell's parameters (a stored impact's
/// first column is its time within the forcing period, `t mod T`, whose phase
/// is `ω (t mod T)`).
fn forcing_frequencies(m: &grid::Meta, row: usize) -> Result<Vec<f64>, RenderError> {
    let scene = scene::Scene::parse(&m.scene_toml).map_err(err)?;
    let (x, y) = (&m.plane.x, &m.plane.y);
    (0..x.count)
        .map(|ix| {
            let mut set = m.overrides.clone();
            set.push((x.name.clone(), x.value(ix)));
            set.push((y.name.clone(), y.value(row)));
            Ok(scene.evaluate(&set).map_err(err)?.omega)
        })
        .collect()
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
    let dof = m.state_masses.len();
    let omega = forcing_frequencies(m, d.row)?;
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
            for (ix, &w) in omega.iter().enumerate() {
                let Some(c) = &map.cells[d.row * x.count + ix] else { continue };
                let v = x.value(ix);
                if pi == 0 {
                    pts.extend(c.period_section.iter().map(|s| (v, s[d.component])));
                } else {
                    let k = pi - 1;
                    let n = &m.stop_normals[k];
                    pts.extend(c.impact_sections[k].iter().map(|r| match d.impact {
                        Impact::Speed => {
                            let vel = &r[1 + dof..1 + 2 * dof];
                            (v, n.iter().zip(vel).map(|(a, b)| a * b).sum::<f64>().abs())
                        }
                        Impact::Phase => (v, (w * r[0]).rem_euclid(std::f64::consts::TAU)),
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

#[cfg(test)]
mod tests {
    use super::*;
    use grid::{Along, Axis, Meta, Plane};

    fn meta(x: &str, y: &str, overrides: &[(&str, f64)]) -> Meta {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/multi-stop.toml");
        Meta {
            scene_name: "multi-stop".into(),
            scene_toml: std::fs::read_to_string(path).unwrap(),
            overrides: overrides.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            preset: "standard".into(),
            accuracy: Vec::new(),
            integrator: "exact".into(),
            plane: Plane { x: Axis::parse(x, "x").unwrap(), y: Axis::parse(y, "y").unwrap(), along: Along::X },
            sweeps: vec![SweepKind::Up],
            masses: vec!["M1".into(), "M2".into()],
            state_masses: vec!["M1".into(), "M2".into()],
            label_stops: Vec::new(),
            stops: vec!["A1".into(), "A2".into(), "A12".into()],
            stop_normals: Vec::new(),
            dim: 4,
            section_cap: 16,
            notation: Vec::new(),
        }
    }

    /// The phase of a stored impact uses the forcing frequency of its own
    /// cell: the x value along ω, the row's value when ω is the y axis, the
    /// override (or the scene's default) when neither is.
    #[test]
    fn each_cell_has_its_own_forcing_frequency() {
        let along_x = forcing_frequencies(&meta("omega=0.2:1.0:5", "delta=0.4:0.8:3", &[]), 1).unwrap();
        let expected: Vec<f64> = (0..5).map(|i| 0.2 + 0.2 * i as f64).collect();
        assert!(along_x.iter().zip(&expected).all(|(a, b)| (a - b).abs() < 1e-15), "{along_x:?}");
        let along_y = forcing_frequencies(&meta("delta=0.4:0.8:3", "omega=0.5:1.5:3", &[]), 2).unwrap();
        assert_eq!(along_y, vec![1.5; 3]);
        let fixed = forcing_frequencies(&meta("delta=0.4:0.8:3", "zeta=0.1:0.2:2", &[("omega", 0.7)]), 0).unwrap();
        assert_eq!(fixed, vec![0.7; 3]);
        let default = forcing_frequencies(&meta("delta=0.4:0.8:3", "zeta=0.1:0.2:2", &[]), 0).unwrap();
        assert_eq!(default, vec![0.33; 3]);
    }
}
