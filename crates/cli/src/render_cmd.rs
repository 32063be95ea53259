//! `vibroatlas render`: the pictures of a stored file: the coloured label map
//! of an atlas (one sweep, or the three-panel hysteresis view), a continuous
//! map of the Lyapunov exponent or the Floquet multiplier, or a bifurcation
//! diagram of a sweep file or of one row of an atlas (`--row`).

use crate::args::RenderArgs;
use anyhow::{anyhow, bail, Result};
use render::{NoSuchView, Show, View};
use scene::Named;
use std::path::{Path, PathBuf};
use store::write_atomically;

/// Runs the command.
pub fn run(a: RenderArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let inputs: Vec<&Path> = std::iter::once(a.file.as_path()).chain(a.curves.iter().map(PathBuf::as_path)).collect();
    crate::figure::check("-o", Some(&a.output), &inputs, &page)?;
    if store::is_basins(&a.file) {
        let given = [
            ("--contours", a.contours.is_some()),
            ("--view", a.view != "labels"),
            ("--mass", a.mass.is_some()),
            ("--sweep", a.sweep.is_some()),
            ("--row", a.row.is_some()),
        ];
        if let Some((flag, _)) = given.iter().find(|(_, g)| *g) {
            bail!("{flag}: {} is a basin file, drawn as its map; {flag} applies to an atlas", a.file.display());
        }
        let map = store::read_basins(&a.file)?;
        write_atomically(&a.output, |tmp| render::basin_map(&map, &page, tmp))?;
        return wrote(&a.output, &page);
    }
    let discrete = ["labels", "attractors"].contains(&a.view.as_str()) || a.view.starts_with("basin:");
    if a.contours.is_some() && (discrete || a.row.is_some()) {
        let what =
            if a.row.is_some() { "a bifurcation diagram (--row)".to_string() } else { format!("--view {}", a.view) };
        bail!("--contours: draws the levels of a continuous map (--view lyapunov, multiplier or a quantity), not of {what}");
    }
    let mut l = store::read(&a.file)?;
    let m = &l.atlas.meta;
    let mass = match &a.mass {
        Some(name) => m
            .masses
            .iter()
            .position(|x| x == name)
            .ok_or_else(|| anyhow!("--mass: no labelled mass '{name}' (the file has {})", m.masses.join(", ")))?,
        None => 0,
    };
    // The sweep, checked before any view: the labels' view of it.
    Show::of(m, render::LABELS, a.sweep).map_err(|e| no_such_view(e, m, &a.view))?;
    if (a.view == "attractors" || a.view.starts_with("basin:")) && l.atlas.attractors.is_none() {
        let lacks = anyhow!(render::RenderError::lacks(render::Missing::Attractors));
        bail!("--view {}: {}", a.view, crate::flags::message(&lacks));
    }
    if let Some(id) = a.view.strip_prefix("basin:") {
        let family = id.parse::<u32>().map_err(|_| anyhow!("--view: basin:ID takes a family's number, got '{id}'"))?;
        render::family_of(&l.atlas, family).map_err(|e| anyhow!("--view {}", e.what()))?;
        return Ok(write_atomically(&a.output, |tmp| render::family_map(&l.atlas, family, &page, tmp))?)
            .and_then(|()| wrote(&a.output, &page));
    }
    if a.view == "attractors" {
        return Ok(write_atomically(&a.output, |tmp| render::attractor_map(&l.atlas, &page, tmp))?)
            .and_then(|()| wrote(&a.output, &page));
    }
    let show = Show::of(m, &a.view, a.sweep).map_err(|e| no_such_view(e, m, &a.view))?;
    // A sweep file (one row), or one row of an atlas: a bifurcation diagram.
    let row = match &a.row {
        Some(text) => Some(nearest_row(&l.atlas, text)?),
        None if m.plane.y.count == 1 && matches!(show, Show::Map(_)) => Some(0),
        None => None,
    };
    if let Some(row) = row {
        let Show::Map(view) = show else {
            bail!("--row: draws a bifurcation diagram; leave out --view {}", a.view);
        };
        if let (Some(_), View::Sweep(s)) = (a.sweep, view) {
            l.atlas.maps.retain(|map| map.sweep == s);
        }
        let d = diagram(&l.atlas, row, a.variable.as_deref(), a.impact)?;
        return Ok(write_atomically(&a.output, |tmp| render::bifurcation(&l.atlas, &d, &page, tmp))?)
            .and_then(|()| wrote(&a.output, &page));
    }
    let (mut curves, p) = (Vec::new(), &m.plane);
    for file in &a.curves {
        for c in store::read_curves(file)? {
            let marks = c.codim2.iter().map(|m| (m.1, m.2));
            curves.push(render::Overlay::on(p, &c.kind, &c.free, &c.points, marks).ok_or_else(|| {
                let (curve, map) = (&c.free, (&p.x.name, &p.y.name));
                anyhow!(
                    "--curves: {} is a curve in ({}, {}), the map is in ({}, {})",
                    file.display(),
                    curve[0],
                    curve[1],
                    map.0,
                    map.1
                )
            })?);
        }
    }
    let contours = usize::from(a.contours.unwrap_or(0));
    write_atomically(&a.output, |tmp| render::draw(&l.atlas, show, mass, &curves, contours, &page, tmp))?;
    wrote(&a.output, &page)
}

/// A view the file does not have (`--view VIEW`, `--sweep`), in the
/// command's words.
fn no_such_view(e: NoSuchView, m: &grid::Meta, view: &str) -> anyhow::Error {
    let have: Vec<&str> = m.sweeps.iter().map(|k| k.name()).collect();
    match e {
        NoSuchView::Sweep(kind) => {
            let hysteresis = if m.has_up_and_down() { ", or hysteresis with up and down" } else { "" };
            anyhow!("--sweep: the file has {}{hysteresis}; not {}", have.join(", "), kind.name())
        }
        NoSuchView::Hysteresis => {
            anyhow!("--sweep hysteresis: needs up and down sweeps; the file has {}", have.join(", "))
        }
        NoSuchView::Number(_) => {
            let stored: Vec<&str> = m.quantities.iter().map(|q| q.name.as_str()).collect();
            let quantities = match stored.is_empty() {
                true => "the file stores no quantities".to_string(),
                false => format!("a quantity the file stores ({})", stored.join(", ")),
            };
            anyhow!("--view: '{view}' is not labels, lyapunov, multiplier, attractors, basin:ID or {quantities}")
        }
        NoSuchView::Difference(_) => anyhow!(
            "--view {view}: needs --sweep fresh, up or down (hysteresis draws a quantity of the motion's up less down)"
        ),
    }
}

/// The bifurcation diagram of row `row` (`sweep --png`, `render` of a sweep
/// file or of one row of an atlas): `--variable`, `--impact`.
pub fn diagram(
    atlas: &grid::Atlas,
    row: usize,
    variable: Option<&str>,
    impact: render::Impact,
) -> Result<render::Diagram> {
    render::Diagram::of(atlas, row, variable, impact).map_err(|e| anyhow!("--variable: {}", e.what()))
}

/// Says what was written: the file and its printed size (or its pixels).
pub(crate) fn wrote(path: &std::path::Path, page: &render::Page) -> Result<()> {
    let size = match page.print_size() {
        Some(s) => match s.height_mm {
            Some(h) => format!("{} x {} mm", s.width_mm, h),
            None => format!("{} mm wide", s.width_mm),
        },
        None => "screen size".to_string(),
    };
    crate::out::line(&format!("wrote {} ({size})", path.display()))
}

/// The row of the y axis nearest to `NAME=VALUE`.
fn nearest_row(atlas: &grid::Atlas, text: &str) -> Result<usize> {
    let y = &atlas.meta.plane.y;
    let (name, value) = crate::common::parse_assignment(text, "--row")?;
    if name != y.name {
        bail!("--row: the file's rows are values of {}, got '{name}'", y.name);
    }
    y.nearest(value).map_err(|e| anyhow!("--row: {e}"))
}
