//! What the pictures of one cell show (`cell --portrait`, `--section-png`,
//! the explorer's cell panel): its phase portraits and time series over the
//! classified window, and its Poincaré sections over many periods.

use crate::cell::Cell;
use crate::error::Result;
use solver::contact::Contact;

/// The portrait of the cell's classified window: per mass its (x, v) path,
/// its frame stops, and the events (400 samples per forcing period).
pub fn portrait(c: &Cell) -> render::Portrait {
    let (sys, s) = (&c.system, &c.setup);
    let rows = crate::window(sys, s, &c.result, crate::window_periods(&c.result), 400).rows;
    let m = sys.dof();
    let masses: Vec<String> = sys.model.masses.iter().map(|x| x.name.clone()).collect();
    let stops = sys
        .model
        .stops
        .iter()
        .filter_map(|st| match st.geometry {
            scene::StopGeometry::Frame { mass, position, .. } => Some((mass, position, st.name.clone())),
            scene::StopGeometry::Pair { .. } => None,
        })
        .collect();
    render::Portrait {
        title: format!("{} ({})", sys.model.name, s.described()),
        masses,
        t: rows.iter().map(|r| r.0).collect(),
        x: (0..m).map(|k| rows.iter().map(|r| r.1[k]).collect()).collect(),
        v: (0..m).map(|k| rows.iter().map(|r| r.1[m + k]).collect()).collect(),
        events: rows.iter().enumerate().filter_map(|(i, r)| r.2.clone().map(|e| (i, e))).collect(),
        stops,
    }
}

/// The panels of the cell's sections over `periods` periods from its final
/// state ([`crate::sections`]): the first labelled mass's (x, v) at t = kT,
/// then each stop's impacts (phase, speed) where it has any; and the title,
/// which names the stops without impacts.
pub fn section_panels(c: &Cell, periods: usize) -> Result<(Vec<render::Panel>, String)> {
    let (sys, s) = (&c.system, &c.setup);
    let sec = crate::sections(sys, s, &c.result, periods)?;
    let name = &sys.model.masses[sec.mass].name;
    let mut panels =
        vec![render::Panel { x: format!("x_{name} at t = kT"), y: format!("v_{name}"), points: sec.period }];
    // Soft stops' events are contacts, rigid stops' impacts.
    let mut silent = Vec::new();
    let mut soft_silent = true;
    for (stop, points) in sys.model.stops.iter().zip(sec.impacts) {
        if points.is_empty() {
            silent.push(stop.name.clone());
            soft_silent &= !stop.law.impacts();
        } else {
            let speed = if stop.law.impacts() { "impact speed" } else { "contact speed" };
            panels.push(render::Panel { x: format!("phase at {} (rad)", stop.name), y: speed.into(), points });
        }
    }
    let events = if soft_silent { "contacts" } else { "impacts" };
    let labels: Vec<String> = c.result.labels.iter().map(|l| format!("{} {l}", l.mass)).collect();
    let silent =
        if silent.is_empty() { String::new() } else { format!("; no {events} at\u{a0}{}", silent.join(",\u{a0}")) };
    let title = format!(
        "{} ({}): {}, Poincaré sections over {periods} periods{silent}",
        sys.model.name,
        s.described(),
        labels.join(", "),
    );
    Ok((panels, title))
}

/// Draws the sampled start states of the attractors `res` found, coloured
/// by the attractor each reaches, with its basin fraction (`attractors
/// --png`; to a file in the format of its extension, or to bytes).
pub fn draw_basins<'o>(
    res: &crate::Attractors,
    page: &render::Page,
    out: impl Into<render::Out<'o>>,
) -> Result<(), render::RenderError> {
    let (sys, found) = (&res.system, &res.found);
    let samples = res.sampling.samples;
    let masses = res.masses();
    let mass = res.basin_mass();
    let groups: Vec<(String, Vec<(f64, f64)>)> = found
        .iter()
        .map(|at| {
            let named: Vec<String> = masses.iter().zip(res.labels(at)).map(|(m, l)| format!("{m} {l}")).collect();
            let share = 100.0 * at.count as f64 / samples as f64;
            (format!("{} ({share:.0} %)", named.join(", ")), res.basin(at))
        })
        .collect();
    let colours: Vec<solver::Label> = found.iter().map(|at| at.cell.labels[0]).collect();
    let title = format!("{}: basins of attraction at t = 0 ({samples} samples)", sys.model.name);
    let axes = (format!("x_{} at t = 0", sys.model.masses[mass].name), format!("v_{}", sys.model.masses[mass].name));
    render::basins(&groups, &colours, &title, &axes, page, out)
}
