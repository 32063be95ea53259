//! A box of a stored atlas computed again on a grid of its own ([`zoom`]):
//! with the parent's scene, parameter values, preset, accuracy, integrator,
//! section cap and sweeps. A fresh sweep starts every cell from the scene's
//! initial state, as the parent did; a continuation sweep enters the box
//! from the parent: each chain starts from the parent's final state of the
//! cell just before the box's edge in the sweep's direction, in the parent
//! line nearest to the chain's. The box's values coincide with the parent's
//! where they are the same to rounding ([`grid::Lattice`]), so that a box
//! aligned with the parent's grid reproduces its cells bit for bit.
//!
//! A zoom may also be a slice at another value of a parameter that is not
//! an axis ([`ZoomRequest::set`]): the box is computed with that value, its
//! chains still entering from the parent's states, and the file's parent
//! region records it (`omega=… delta=… at zeta=0.07`).

use crate::error::{Error, Result};
use crate::error::{Opt, RequestError};
use crate::plan::{Executed, Plan};
use crate::sim::Setup;
use grid::Observer;
use grid::{Along, Atlas, Axis, Entries, Lattice, Plane, SweepKind};
use scene::Named;
use std::path::{Path, PathBuf};

/// Largest number of cells of a zoom's box (per sweep): a box is looked at,
/// not mapped at a cluster's scale.
pub const MAX_ZOOM_CELLS: usize = 4_000_000;

/// A box of a stored atlas to compute.
#[derive(Debug, Clone)]
pub struct ZoomRequest {
    /// The parent atlas.
    pub parent: PathBuf,
    /// The box's axis along the parent's x (the same parameter).
    pub x: Axis,
    /// The box's axis along the parent's y.
    pub y: Axis,
    /// The sweeps to compute, among the parent's (all of them when `None`).
    pub sweeps: Option<Vec<SweepKind>>,
    /// Scene parameters (not the axes) set to other values than the
    /// parent's, `(name, value)`: the box is then a slice of the parameter
    /// space beside the parent's plane.
    pub set: Vec<(String, f64)>,
    /// Worker threads.
    pub threads: usize,
    /// The file to write, if any.
    pub output: Option<PathBuf>,
    /// What made the run (the file's `command` attribute).
    pub command: String,
    /// The parent's labels as the caller knows them
    /// ([`store::labels_crc32`]): a parent file that no longer holds them
    /// (rewritten since) is refused.
    pub parent_labels: Option<u32>,
}

impl ZoomRequest {
    /// The box as its file's parent region records it: the two axes, then
    /// the parameters set, `omega=0.6:1.2:61 delta=0.05:2:196 at zeta=0.07,fm=0.1`.
    pub fn region(&self) -> String {
        let set: Vec<String> =
            self.set.iter().map(|(name, value)| format!("{name}={}", scene::number(*value))).collect();
        match set.is_empty() {
            true => format!("{} {}", self.x, self.y),
            false => format!("{} {} at {}", self.x, self.y, set.join(",")),
        }
    }

    /// A request for the box `x` by `y` of `parent`, every sweep of it, on
    /// one thread per core, written nowhere.
    pub fn new(parent: impl Into<PathBuf>, x: Axis, y: Axis) -> ZoomRequest {
        ZoomRequest {
            parent: parent.into(),
            x,
            y,
            sweeps: None,
            set: Vec::new(),
            threads: crate::threads(None).unwrap_or(1),
            output: None,
            command: String::new(),
            parent_labels: None,
        }
    }
}

/// Computes the box, reporting to `observer` (and writes it when asked).
pub fn zoom(r: &ZoomRequest, observer: &dyn Observer) -> Result<Executed> {
    let loaded = store::read(&r.parent)?;
    store::check_finished(&r.parent, &loaded)?;
    let parent = &loaded.atlas;
    let m = &parent.meta;
    let labels_crc32 = store::labels_crc32(parent);
    if r.parent_labels.is_some_and(|known| known != labels_crc32) {
        let why = "the file changed since it was opened (its labels differ); open it again";
        return Err(Error::file(&r.parent, why, None));
    }
    if let Some(shard) = loaded.info.shard.filter(|s| !s.is_whole()) {
        let why = format!("shard {shard} of an atlas, whose other lines are missing; zoom into the merged atlas");
        return Err(Error::file(&r.parent, why, None));
    }
    let (x, y, sweeps) = zoom_box(m, &r.parent, (&r.x, &r.y), r.sweeps.as_deref())?;
    let setup = zoom_setup(m, &r.parent, &r.set)?;
    let plane = Plane { x, y, along: m.plane.along };
    let mut plan = Plan::new(&setup, m.section_cap, plane, sweeps, r.threads)?;
    // A zoom measures what its parent measured.
    if m.quantities.is_empty() {
        plan.without_quantities();
    }
    plan.entries = admitted(entries(parent, &plan.meta.plane, &plan.meta.sweeps), &plan);
    plan.parent = Some(store::Parent { path: r.parent.display().to_string(), labels_crc32, region: r.region() });
    plan.output = r.output.as_deref().map(store::canonical_output).transpose()?;
    plan.inputs = vec![r.parent.clone()];
    // A zoom has no resume: a failed one leaves no journal.
    plan.resumable = false;
    plan.command = r.command.clone();
    plan.check()
        .map_err(|e| crate::error::with_fields(e, &[("x", Opt::X), ("y", Opt::Y), ("threads", Opt::Threads)]))?;
    plan.execute(observer)
}

/// The box of a zoom into the atlas of `m` (stored at `parent`): its axes
/// `x`, `y`, each the parent's parameter, ascending, within the parent's
/// values and on its lattice, at most [`MAX_ZOOM_CELLS`]
/// cells in all, and its sweeps (`asked`, default the parent's), each one
/// the parent has, in the parent's order. The checks of the box that need no
/// cell computed: the explorer makes them before it queues a zoom.
pub fn zoom_box(
    m: &grid::Meta,
    parent: &Path,
    (x, y): (&Axis, &Axis),
    asked: Option<&[SweepKind]>,
) -> Result<(Axis, Axis, Vec<SweepKind>)> {
    let x = box_axis(x, &m.plane.x, Opt::X)?;
    let y = box_axis(y, &m.plane.y, Opt::Y)?;
    check_size(&x, &y)?;
    let sweeps = match asked {
        None => m.sweeps.clone(),
        Some(asked) => {
            if asked.is_empty() {
                return Err(RequestError::option(Opt::Sweep).text("no sweep given").into());
            }
            if let Some(s) = asked.iter().find(|s| !m.sweeps.contains(s)) {
                let have: Vec<&str> = m.sweeps.iter().map(|k| k.name()).collect();
                let why = format!("{} has {}, not {}", parent.display(), have.join(", "), s.name());
                return Err(RequestError::option(Opt::Sweep).text(why).into());
            }
            m.sweeps.iter().copied().filter(|s| asked.contains(s)).collect()
        }
    };
    Ok((x, y, sweeps))
}

/// The setup of a zoom into the atlas of `m` (stored at `parent`): the
/// parent's, with the parameters `set` beside the box, each checked (not an
/// axis of the parent's plane, finite, given once) and the scene evaluated
/// with them (a name the scene lacks, a value out of its range). The checks
/// of a zoom's request that need no cell computed: the explorer makes them
/// before it queues a zoom.
pub fn zoom_setup(m: &grid::Meta, parent: &Path, set: &[(String, f64)]) -> Result<Setup> {
    let mut setup = crate::stored_setup(m, parent)?;
    setup.method = m.integrator;
    for (k, (name, value)) in set.iter().enumerate() {
        check_set(name, *value, &m.plane)?;
        if set[..k].iter().any(|(n, _)| n == name) {
            return Err(RequestError::keyed(Opt::Set, name).text("given twice").into());
        }
        setup.overrides.retain(|(k, _)| k != name);
        setup.overrides.push((name.clone(), *value));
    }
    setup.scene.evaluate(&setup.overrides)?;
    Ok(setup)
}

/// Parses `NAME=VALUE` with a finite value; `field` names the option or
/// field in the message (`--set`).
pub fn parse_assignment(text: &str, field: &str) -> std::result::Result<(String, f64), String> {
    let (name, value) = text.split_once('=').ok_or_else(|| format!("{field} {text}: expected NAME=VALUE"))?;
    let name = name.trim().to_string();
    let value = value.trim();
    let v: f64 = value.parse().map_err(|_| format!("{field} {name}: '{value}' is not a number"))?;
    if !v.is_finite() {
        // `1e400` reads as infinity: say what was typed, and why.
        let named = ["inf", "nan"].iter().any(|w| value.to_ascii_lowercase().contains(w));
        let why = if named { "is not a finite number" } else { "is beyond the largest number, about 1.8e308" };
        return Err(format!("{field} {name}: '{value}' {why}"));
    }
    // `1e-400` reads as 0: a number typed nonzero that no f64 holds.
    let mantissa = value.split(['e', 'E']).next().unwrap_or_default();
    if v == 0.0 && mantissa.chars().any(|c| matches!(c, '1'..='9')) {
        return Err(format!(
            "{field} {name}: '{value}' is nonzero but below the smallest number, about 4.9e-324 (it would read as 0)"
        ));
    }
    Ok((name, v))
}

/// Refuses setting a parameter that is an axis of the parent's plane (the
/// box gives its values) or to a value that is not finite; a name the
/// scene does not have is refused when the scene is evaluated.
fn check_set(name: &str, value: f64, plane: &Plane) -> Result<()> {
    if name == plane.x.name || name == plane.y.name {
        let why = format!("{name} is an axis of the parent's plane; the box's --x and --y give its values");
        return Err(RequestError::keyed(Opt::Set, name).text(why).into());
    }
    if !value.is_finite() {
        return Err(RequestError::keyed(Opt::Set, name).text(format!("not a finite number, got {value}")).into());
    }
    Ok(())
}

/// Refuses a box of more than [`MAX_ZOOM_CELLS`] cells (before any file is read,
/// where a caller wants to say so at once).
pub fn check_size(x: &Axis, y: &Axis) -> Result<()> {
    let cells = x.count.saturating_mul(y.count);
    if cells > MAX_ZOOM_CELLS {
        let why = format!("the box has {cells} cells ({} x {}), more than the {MAX_ZOOM_CELLS} a zoom computes; give fewer values, or map it with atlas", x.count, y.count);
        return Err(RequestError::option(Opt::X).text(why).into());
    }
    Ok(())
}

/// The box's axis `given` of the parent's axis `parent`: the same parameter,
/// ascending, within the parent's values (to rounding), on the parent's
/// lattice.
fn box_axis(given: &Axis, parent: &Axis, opt: Opt) -> Result<Axis> {
    let field = opt.name();
    let axis = given
        .clone()
        .checked(field)
        .and_then(|a| a.ascending(field))
        .map_err(|e| RequestError::option(opt).text(e.message))?;
    if axis.name != parent.name {
        let why = format!("the parent's {field} axis is {}, not {}", parent.name, axis.name);
        return Err(RequestError::option(opt).text(why).into());
    }
    let slack = Lattice::SNAP * parent.step().abs();
    if axis.start < parent.start - slack || axis.stop > parent.stop + slack {
        let why = format!(
            "{}={}:{} is not within the parent's {} to {}",
            axis.name, axis.start, axis.stop, parent.start, parent.stop
        );
        return Err(RequestError::option(opt).text(why).into());
    }
    Ok(Axis { lattice: Lattice::of(parent), ..axis })
}

/// The entries of `entries` that the first cell of their chain admits: one
/// that penetrates a stop of that cell's system (the parent's chain at
/// another value of a `--set` parameter, or of the row the box's line lies
/// nearest) is dropped, so that the chain starts from the scene's initial
/// state, as its run would, and the file records the state it started from.
/// A cell whose system cannot be built keeps its entry: its run says why.
fn admitted(entries: Entries, plan: &Plan) -> Entries {
    let p = &plan.meta.plane;
    let first = |sweep: SweepKind, line: usize| match sweep {
        SweepKind::Up => p.cell(line, 0),
        _ => p.cell(line, p.line_len() - 1),
    };
    let admits = |(sweep, line): (SweepKind, usize), state: &[f64]| {
        let (iy, ix) = first(sweep, line);
        plan.setup.system(&p.params(iy, ix)).map_or(true, |sys| sys.admits(state))
    };
    Entries(entries.0.into_iter().filter(|(key, state)| admits(*key, state)).collect())
}

/// The states the box's chains enter with: for each chain sweep and line of
/// `plane`, the state the parent's chain had where the box starts — the
/// state its cell at the box's first value (or the first after it, in the
/// sweep's direction) started from ([`Atlas::start_of`]: the final state of
/// the cell before it, or at the parent's first cell the parent's own entry)
/// — in the parent line nearest to the box's line.
fn entries(parent: &Atlas, plane: &Plane, sweeps: &[SweepKind]) -> Entries {
    let pp = &parent.meta.plane;
    let (along, across, p_along, p_across) = match pp.along {
        Along::X => (&plane.x, &plane.y, &pp.x, &pp.y),
        Along::Y => (&plane.y, &plane.x, &pp.y, &pp.x),
    };
    let slack = Lattice::SNAP * p_along.step().abs();
    let mut out = Entries::default();
    for &sweep in sweeps.iter().filter(|&&s| s != SweepKind::Fresh) {
        // The parent's position along its chains where the box's chains start.
        let start = match sweep {
            SweepKind::Up => {
                let first = along.value(0);
                (0..p_along.count).find(|&i| p_along.value(i) >= first - slack)
            }
            _ => {
                let last = along.value(along.count - 1);
                (0..p_along.count).rev().find(|&i| p_along.value(i) <= last + slack)
            }
        };
        let Some(pos) = start else { continue };
        for line in 0..across.count {
            let Ok(p_line) = p_across.nearest(across.value(line)) else { continue };
            let (iy, ix) = pp.cell(p_line, pos);
            if let Some(state) = parent.start_of(sweep, iy, ix) {
                out.0.insert((sweep, line), state.to_vec());
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::parse_assignment;

    /// `NAME=VALUE` reads a finite value; a refusal names the option, the
    /// name and the text as typed.
    #[test]
    fn an_assignment_says_what_was_typed() {
        assert_eq!(parse_assignment(" omega = 2.5 ", "--set"), Ok(("omega".to_string(), 2.5)));
        let refused = |t: &str| parse_assignment(t, "--at").unwrap_err();
        assert_eq!(refused("omega"), "--at omega: expected NAME=VALUE");
        assert_eq!(refused("omega=x"), "--at omega: 'x' is not a number");
        assert_eq!(refused("omega=1e400"), "--at omega: '1e400' is beyond the largest number, about 1.8e308");
        assert_eq!(refused("omega=-inf"), "--at omega: '-inf' is not a finite number");
        assert_eq!(refused("omega=NaN"), "--at omega: 'NaN' is not a finite number");
        let small =
            "--at omega: '1e-400' is nonzero but below the smallest number, about 4.9e-324 (it would read as 0)";
        assert_eq!(refused("omega=1e-400"), small);
        // Zero typed as zero, and the smallest subnormal, read as they are.
        for (typed, value) in [("0", 0.0), ("-0.0e-400", 0.0), ("0e5", 0.0), ("5e-324", 5e-324)] {
            assert_eq!(
                parse_assignment(&format!("omega={typed}"), "--at"),
                Ok(("omega".to_string(), value)),
                "{typed}"
            );
        }
    }
}
