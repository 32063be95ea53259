//! The bifurcation diagram of a sweep, as in the literature: one panel per
//! section against the swept parameter — the period section (one state
//! component at t = kT) and, per stop, the impact speed or the forcing phase of
//! each impact — drawn from the stored raw section points as small dots. The
//! number of branches at a parameter value is n (period panel) or the impacts
//! per n periods at that stop; a stop without impacts gets no panel (the
//! footnote names it). Up and down sweeps are both drawn, with a legend above
//! the panels: down as vermillion rings, up as blue dots drawn inside them, so
//! that where they agree both show and where they differ (hysteresis) each can
//! be told apart; marks are sized in points, so they stay visible in print.

use crate::axis::{range, tick};
use crate::error::{err, RenderError};
use crate::layout::{self, Axes};
use crate::legend::{self, Entry, Swatch};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use maps::{Atlas, SweepKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use scene::Named;

scene::named_enum! {
    /// What the impact panels plot for each impact.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Impact {
        /// The normal impact speed `|ġ|` just before the impact.
        Speed = "speed",
        /// The forcing phase `ωt mod 2π` of the impact.
        Phase = "phase",
    }
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
    /// For a hysteresis loop (`sweep --direction down-up|up-down`), the
    /// sweep run first: the other started from its end state.
    pub first: Option<SweepKind>,
    /// A quantity of the steady motion ([`maps::Meta::quantities`]) the first
    /// panel shows instead of the period section, one point per cell: an
    /// amplitude–frequency response with its jumps.
    pub quantity: Option<usize>,
}

impl Diagram {
    /// The diagram of row `row` of `atlas`, its first panel showing the
    /// period section's state component named `variable` (`x_M1`, `v_M2`: see
    /// [`component_name`]; default: the position of the first labelled mass)
    /// or, for the name of a stored quantity (`max_abs_x_M1`), that quantity;
    /// an error, whose [`RenderError::what`] lists the names, for another name.
    pub fn of(atlas: &Atlas, row: usize, variable: Option<&str>, impact: Impact) -> Result<Diagram, RenderError> {
        let (component, quantity) = variable_of(&atlas.meta, variable)?;
        Ok(Diagram { row, component, impact, first: None, quantity })
    }
}

/// The period section's state component and the stored quantity (if it is
/// one) that a diagram of a file described by `m` shows for `variable`
/// ([`Diagram::of`]); checked on the description alone, so that a run can
/// refuse a wrong name before it computes the file.
pub fn variable_of(m: &maps::Meta, variable: Option<&str>) -> Result<(usize, Option<usize>), RenderError> {
    let first = m.masses.first().and_then(|first| m.state_masses.iter().position(|n| n == first)).unwrap_or(0);
    let quantity = variable.and_then(|v| m.quantities.iter().position(|q| q.name == v));
    let component = match variable {
        Some(_) if quantity.is_some() => first,
        Some(v) => {
            let mut names: Vec<String> = (0..m.dim).map(|k| component_name(m, k)).collect();
            names.extend(m.quantities.iter().map(|q| q.name.clone()));
            let unknown = || RenderError::new(format!("expected one of {}, got '{v}'", names.join(", ")));
            names.iter().position(|n| n == v).ok_or_else(unknown)?
        }
        None => first,
    };
    Ok((component, quantity))
}

/// Radius (pt) of a down sweep's ring and of an up sweep's dot.
const RING_PT: f64 = 1.7;
const DOT_PT: f64 = 0.9;

/// Colour of a sweep in diagrams.
fn sweep_colour(s: SweepKind) -> RGBColor {
    match s {
        SweepKind::Down => RGBColor(213, 94, 0),
        SweepKind::Up => RGBColor(0, 114, 178),
        SweepKind::Fresh => RGBColor(0, 0, 0),
    }
}

/// Name of state component `k` (`x_M1`, `v_M2`) of a file described by `m`.
pub fn component_name(m: &maps::Meta, k: usize) -> String {
    let names = &m.state_masses;
    let n = names.len().max(1);
    format!("{}_{}", if k < n { "x" } else { "v" }, names.get(k % n).map_or("?", String::as_str))
}

/// The forcing frequency ω of each cell of row `row`, from the stored
/// scene's forcing expression at the cell's parameters (a stored impact's
/// first column is its time within the forcing period, `t mod T`, whose phase
/// is `ω (t mod T)`).
fn forcing_frequencies(m: &maps::Meta, row: usize) -> Result<Vec<f64>, RenderError> {
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

/// The points (parameter, value) of every panel and sweep of a diagram:
/// the period section, then each stop's impacts.
type Series = Vec<Vec<(SweepKind, Vec<(f64, f64)>)>>;

fn series(atlas: &Atlas, d: &Diagram, omega: &[f64]) -> Series {
    let m = &atlas.meta;
    let x = &m.plane.x;
    let dof = m.state_masses.len();
    (0..1 + m.stops.len())
        .map(|pi| {
            let mut per_sweep: Vec<(SweepKind, Vec<(f64, f64)>)> = atlas
                .maps
                .iter()
                .map(|map| {
                    let mut pts = Vec::new();
                    for (ix, &w) in omega.iter().enumerate() {
                        let Some(c) = &map.cells[d.row * x.count + ix] else { continue };
                        let v = x.value(ix);
                        if let (0, Some(k)) = (pi, d.quantity) {
                            pts.extend(c.quantities.get(k).copied().filter(|q| q.is_finite()).map(|q| (v, q)));
                        } else if pi == 0 {
                            pts.extend(c.period_section.iter().map(|s| (v, s[d.component])));
                        } else {
                            let n = &m.stop_normals[pi - 1];
                            pts.extend(c.impact_sections[pi - 1].iter().map(|r| match d.impact {
                                Impact::Speed => {
                                    let vel = &r[1 + dof..1 + 2 * dof];
                                    (v, n.iter().zip(vel).map(|(a, b)| a * b).sum::<f64>().abs())
                                }
                                Impact::Phase => (v, (w * r[0]).rem_euclid(std::f64::consts::TAU)),
                            }));
                        }
                    }
                    (map.sweep, pts)
                })
                .collect();
            // Down first: its rings under the up sweep's dots.
            per_sweep.sort_by_key(|s| s.0 != SweepKind::Down);
            per_sweep
        })
        .collect()
}

/// Draws the diagram at the size of `page` (to `out`: [`Out`]).
pub fn bifurcation<'o>(
    atlas: &Atlas,
    diagram: &Diagram,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    if diagram.row >= m.plane.y.count {
        return Err(RenderError::new(format!("row {} is outside the file's {} rows", diagram.row, m.plane.y.count)));
    }
    if diagram.component >= m.dim {
        return Err(RenderError::new(format!("state component {} of {}", diagram.component, m.dim)));
    }
    let omega = forcing_frequencies(m, diagram.row)?;
    let all = series(atlas, diagram, &omega);
    // The period panel, and a panel per stop with impacts.
    let shown: Vec<usize> =
        (0..all.len()).filter(|&pi| pi == 0 || all[pi].iter().any(|(_, pts)| !pts.is_empty())).collect();
    let k = shown.len() as f64;
    let height = |w: f64| 24.0 + k * if w < 120.0 { 0.5 * w } else { 0.26 * w };
    let out = out.into();
    let canvas = Canvas::of(page, &out, (1100, 250 * shown.len() as u32 + 110), height)?;
    save!(out, canvas, |root| draw(&root, &canvas, atlas, diagram, &all, &shown))
}

/// The sweeps of a diagram, for its title.
fn directions(atlas: &Atlas, first: Option<SweepKind>) -> String {
    let sweeps: Vec<SweepKind> = atlas.maps.iter().map(|map| map.sweep).collect();
    let other = |s: SweepKind| if s == SweepKind::Down { SweepKind::Up } else { SweepKind::Down };
    match (first, sweeps.contains(&SweepKind::Up), sweeps.contains(&SweepKind::Down)) {
        (Some(f), true, true) => format!("{} sweep, then {} from its end", f.name(), other(f).name()),
        (None, true, true) => "up and down sweeps".to_string(),
        (_, true, false) => "up sweep".to_string(),
        (_, false, true) => "down sweep".to_string(),
        _ => "fresh cells".to_string(),
    }
}

fn draw<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    atlas: &Atlas,
    d: &Diagram,
    all: &Series,
    shown: &[usize],
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    let (x, y) = (&m.plane.x, &m.plane.y);
    let sym = |name: &str| m.symbol(name);
    let fixed = if y.count > 1 { format!(", {} = {}", sym(&y.name), tick(y.value(d.row))) } else { String::new() };
    root.fill(&WHITE).map_err(err)?;
    let title =
        format!("{}: bifurcation diagram in {}{fixed} ({})", m.scene_name, sym(&x.name), directions(atlas, d.first));
    let body = layout::header(root, canvas, &title, layout::TITLE)?;
    // The stops without impacts (indices into the stops), named in the footnote.
    let silent: Vec<usize> = (1..all.len()).filter(|pi| !shown.contains(pi)).map(|pi| pi - 1).collect();
    let mut foot = crate::map::settings_text(m);
    let stop_events = m.stop_events();
    if !silent.is_empty() {
        let events = if silent.iter().all(|&k| stop_events[k] == "contacts") { "contacts" } else { "impacts" };
        let names: Vec<&str> = silent.iter().map(|&k| m.stops[k].as_str()).collect();
        foot.push_str(&format!("; no {events} at {}", names.join(", ")));
    }
    let body = layout::footer(&body, canvas, &foot)?;
    // The legend, one row above the panels.
    let keys: Vec<Entry> = all[0]
        .iter()
        .map(|(sweep, _)| {
            let col = sweep_colour(*sweep);
            let swatch = if *sweep == SweepKind::Down { Swatch::Ring(col, RING_PT) } else { Swatch::Dot(col, DOT_PT) };
            let name =
                if *sweep == SweepKind::Fresh { "fresh cells".to_string() } else { format!("{} sweep", sweep.name()) };
            Entry::new(swatch, name)
        })
        .collect();
    let (key, body) = body.split_vertically(legend::height(canvas, 1));
    let keys_w: u32 = legend::columns(&key, canvas, &keys, 1).iter().sum();
    let spare = key.dim_in_pixel().0.saturating_sub(keys_w) / 2;
    legend::draw(&key.margin(0, 0, spare as i32, 0), canvas, &keys)?;
    // Panels stacked in a column share its horizontal axis: only the lowest names it.
    let (n, least) = (shown.len(), (24.0, 8.0));
    let cols = layout::grid_columns(&body, canvas, n, least);
    let y_range = |pi: usize| range(all[pi].iter().flat_map(|s| s.1.iter().map(|p| p.1)));
    let y_chars = shown.iter().map(|&pi| layout::tick_chars(y_range(pi))).max();
    for (i, (&pi, area)) in shown.iter().zip(layout::panels(&body, n, cols).iter()).enumerate() {
        let series = &all[pi];
        let y_range = y_range(pi);
        let desc = if let (0, Some(k)) = (pi, d.quantity) {
            m.quantities[k].with_units(&m.quantities[k].long_name)
        } else if pi == 0 {
            format!("{} at t = kT", component_name(&atlas.meta, d.component))
        } else {
            match d.impact {
                Impact::Speed if stop_events[pi - 1] == "contacts" => format!("contact speed at {}", m.stops[pi - 1]),
                Impact::Phase if stop_events[pi - 1] == "contacts" => {
                    format!("contact phase at {} (rad)", m.stops[pi - 1])
                }
                Impact::Speed => format!("impact speed at {}", m.stops[pi - 1]),
                Impact::Phase => format!("impact phase at {} (rad)", m.stops[pi - 1]),
            }
        };
        // A ring's width of margin at both ends, so that no mark sits on an axis.
        let (x0, x1) = (x.start.min(x.stop), x.start.max(x.stop));
        let x_range = if x.count > 1 { (x0 - 0.01 * (x1 - x0), x1 + 0.01 * (x1 - x0)) } else { (x0 - 1.0, x0 + 1.0) };
        let axes = Axes {
            caption: None,
            x: x_range,
            y: y_range,
            x_desc: &sym(&x.name),
            y_desc: &desc,
            x_labels: i + cols >= n,
            y_label_chars: y_chars,
        };
        let chart = layout::chart(area, canvas, &axes)?;
        let plot = chart.plotting_area();
        for (sweep, pts) in series {
            let col = sweep_colour(*sweep);
            if *sweep == SweepKind::Down {
                let style = col.stroke_width(canvas.pt(0.6));
                for &p in pts {
                    plot.draw(&Circle::new(p, canvas.pt(RING_PT), style)).map_err(err)?;
                }
            } else {
                for &p in pts {
                    plot.draw(&Circle::new(p, canvas.pt(DOT_PT), col.filled())).map_err(err)?;
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use maps::{Along, Axis, Meta, Plane};

    fn meta(x: &str, y: &str, overrides: &[(&str, f64)]) -> Meta {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/multi-stop.toml");
        Meta {
            scene_name: "multi-stop".into(),
            scene_toml: std::fs::read_to_string(path).unwrap(),
            overrides: overrides.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            preset: solver::Preset::Standard,
            accuracy: Vec::new(),
            integrator: solver::Method::Exact,
            plane: Plane { x: Axis::parse(x, "x").unwrap(), y: Axis::parse(y, "y").unwrap(), along: Along::X },
            sweeps: vec![SweepKind::Up],
            masses: vec!["M1".into(), "M2".into()],
            state_masses: vec!["M1".into(), "M2".into()],
            label_stops: Vec::new(),
            stops: vec!["A1".into(), "A2".into(), "A12".into()],
            stop_normals: Vec::new(),
            stop_laws: vec![scene::LawKind::Rigid; 3],
            dim: 4,
            section_cap: 16,
            notation: Vec::new(),
            quantities: Vec::new(),
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
