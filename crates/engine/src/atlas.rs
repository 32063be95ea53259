//! A parameter plane ([`atlas`]): fresh cells, or continuation chains up and
//! down, on threads, optionally one shard of it, with the coexisting
//! attractors of its cells; written to an HDF5 file through a journal.

use crate::error::Result;
use crate::error::{with_fields, Opt, RequestError};
use crate::plan::{Executed, Plan};
use crate::sim::{Sim, Start};
use grid::attractors::Sampling;
use grid::Observer;
use grid::{Along, Axis, Plane, Shard, SweepKind};
use std::path::{Path, PathBuf};

scene::named_enum! {
    /// Which cells get their coexisting attractors.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum AttractorCells {
        /// Every cell.
        All = "all",
        /// The cells where the up and down sweeps differ.
        Hysteresis = "hysteresis",
    }
}

/// An atlas to compute.
#[derive(Debug, Clone)]
pub struct AtlasRequest {
    /// The simulation options.
    pub sim: Sim,
    /// The axis along the lines (the columns).
    pub x: Axis,
    /// The other axis (the rows).
    pub y: Axis,
    /// Which axis the continuation chains follow.
    pub along: Along,
    /// The sweeps (fresh, or up and/or down).
    pub sweeps: Vec<SweepKind>,
    /// This run's shard of the lines, if any.
    pub shard: Option<Shard>,
    /// The coexisting attractors to find once the lines are done.
    pub attractors: Option<(Sampling, AttractorCells)>,
    /// Section points kept per cell.
    pub section_cap: usize,
    /// Worker threads.
    pub threads: usize,
    /// The file to write. A symbolic link's target is written.
    pub output: Option<PathBuf>,
    /// Continue from the journal beside the output (or do nothing when the
    /// output is already this run's finished file).
    pub resume: bool,
    /// What made the run (the file's `command` attribute).
    pub command: String,
    /// The quantities of the steady motion stored: `None` every one of the
    /// scene ([`solver::quantity::all_names`]), else those named (none when
    /// empty); [`AtlasOptions::apply`] sets them from their text.
    pub quantities: Option<Vec<String>>,
}

impl AtlasRequest {
    /// A request for `sweeps` of the plane `x` by `y` (chains along x), every
    /// other option at its default: no shard, attractors or output, sections
    /// of [`grid::DEFAULT_SECTION_CAP`] points, one thread per core.
    pub fn new(sim: Sim, x: Axis, y: Axis, sweeps: Vec<SweepKind>) -> AtlasRequest {
        AtlasRequest {
            sim,
            x,
            y,
            along: Along::X,
            sweeps,
            shard: None,
            attractors: None,
            section_cap: grid::DEFAULT_SECTION_CAP,
            threads: crate::threads(None).unwrap_or(1),
            output: None,
            resume: false,
            command: String::new(),
            quantities: None,
        }
    }
}

/// The options of an atlas that every front end gives by name: each field
/// is the command line's flag (`--attractors-where`; its doc comment the
/// flag's help) and the Python keyword (`attractors_where=`), read by clap
/// (with the feature `clap`) and by serde, and set on the request by
/// [`AtlasOptions::apply`]. A new option of an atlas is a field here and its
/// line in `apply` (with its `Opt` if the engine refuses values of it).
#[derive(Debug, Clone, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct AtlasOptions {
    /// fresh (independent cells), up, down (continuation), or both (up and down).
    #[cfg_attr(feature = "clap", arg(long, value_parser = scene::named_arg::<grid::Sweeps>(), default_value_t = grid::Sweeps::Fresh))]
    #[serde(deserialize_with = "named")]
    pub sweep: grid::Sweeps,
    /// Axis the continuation chains follow: x (rows) or y (columns).
    #[cfg_attr(feature = "clap", arg(long, value_parser = scene::named_arg::<Along>(), default_value_t = Along::X))]
    #[serde(deserialize_with = "named")]
    pub along: Along,
    /// Compute only shard K of N (whole lines); merge the parts with `vibroatlas merge`.
    #[cfg_attr(feature = "clap", arg(long, value_name = "K/N"))]
    pub shard: Option<String>,
    /// Also find the coexisting attractors of the cells from K sampled initial
    /// states each (stored in the file's attractors group).
    #[cfg_attr(feature = "clap", arg(long, value_name = "K"))]
    pub attractors: Option<usize>,
    /// Cells whose attractors are sampled: all (the default), or hysteresis
    /// (where up and down differ; needs --sweep both). Only with --attractors.
    #[cfg_attr(feature = "clap", arg(long, value_name = "all|hysteresis", value_parser = scene::named_arg::<AttractorCells>()))]
    #[serde(deserialize_with = "named_some")]
    pub attractors_where: Option<AttractorCells>,
    /// Seed of the attractor sampling (default 1). Only with --attractors.
    #[cfg_attr(feature = "clap", arg(long, value_name = "S"))]
    pub seed: Option<u64>,
    /// Continue an interrupted run from its journal.
    #[cfg_attr(feature = "clap", arg(long))]
    pub resume: bool,
    /// The quantities of the steady motion stored per cell: all, none, or
    /// names separated by commas (max_abs_x_M1,power_in; docs/models.md).
    #[cfg_attr(feature = "clap", arg(long, default_value = "all", value_name = "all|none|NAME,…"))]
    pub quantities: String,
    /// Accepted and ignored, for scripts that pass it: an output that exists
    /// and is not a regular file (a device, a pipe) is always refused.
    #[cfg_attr(feature = "clap", arg(long))]
    pub force: bool,
}

impl Default for AtlasOptions {
    /// Fresh cells, chains along x, no shard, no attractors (seed 1 when
    /// asked, of every cell), no resume, every quantity.
    fn default() -> AtlasOptions {
        AtlasOptions {
            sweep: grid::Sweeps::Fresh,
            along: Along::X,
            shard: None,
            attractors: None,
            attractors_where: None,
            seed: None,
            resume: false,
            quantities: "all".into(),
            force: false,
        }
    }
}

/// A value of a named enum read by serde: its name, or the refusal that
/// lists the names (`expected fresh, up, down or both, got 'sideways'`).
fn named<'de, D: serde::Deserializer<'de>, T: scene::Named>(d: D) -> std::result::Result<T, D::Error> {
    let text = <String as serde::Deserialize>::deserialize(d)?;
    T::parse(&text).ok_or_else(|| serde::de::Error::custom(T::expected(&text)))
}

/// [`named`], of an option that may be left out.
fn named_some<'de, D: serde::Deserializer<'de>, T: scene::Named>(d: D) -> std::result::Result<Option<T>, D::Error> {
    named(d).map(Some)
}

impl AtlasOptions {
    /// Sets the options on `r`: its sweeps, chains, shard (`K/N`, refused
    /// naming [`Opt::Shard`]), attractor search, resume and quantities.
    pub fn apply(&self, r: &mut AtlasRequest) -> Result<()> {
        r.sweeps = self.sweep.kinds();
        r.along = self.along;
        let shard = self.shard.as_deref().map(Shard::parse).transpose();
        r.shard = shard.map_err(|e| crate::grid_error(e, &[("shard", Opt::Shard)]))?;
        if self.attractors.is_none() {
            // The search's own options, without the search, would be ignored.
            let given = [(Opt::Seed, self.seed.is_some()), (Opt::AttractorsWhere, self.attractors_where.is_some())];
            if let Some((o, _)) = given.into_iter().find(|(_, given)| *given) {
                return Err(RequestError::option(o)
                    .text("tunes the attractor search; give ")
                    .opt(Opt::Attractors)
                    .into());
            }
        }
        r.attractors = self.attractors.map(|samples| {
            let seed = self.seed.unwrap_or(Sampling::default().seed);
            let sampling = Sampling { samples, seed, ..Default::default() };
            (sampling, self.attractors_where.unwrap_or(AttractorCells::All))
        });
        r.resume = self.resume;
        r.quantities = match self.quantities.trim() {
            "all" => None,
            "none" => Some(Vec::new()),
            list => Some(list.split(',').map(|n| n.trim().to_string()).collect()),
        };
        Ok(())
    }
}

/// The options of the grid's fields.
const FIELDS: &[(&str, Opt)] =
    &[("x", Opt::X), ("y", Opt::Y), ("along", Opt::Along), ("shard", Opt::Shard), ("threads", Opt::Threads)];

/// Computes an atlas, reporting to `observer` (and writes it when asked).
pub fn atlas(r: &AtlasRequest, observer: &dyn Observer) -> Result<Executed> {
    let s = r.sim.setup()?;
    let plane = Plane::new(r.x.clone(), r.y.clone(), r.along).map_err(|e| crate::grid_error(e, FIELDS))?;
    let mut plan = Plan::new(&s, r.section_cap, plane, r.sweeps.clone(), r.threads)?;
    plan.shard = r.shard;
    plan.output = r.output.as_deref().map(store::canonical_output).transpose()?;
    plan.resume = r.resume;
    plan.inputs = r.sim.inputs(&Start::Initial).into_iter().map(Path::to_path_buf).collect();
    plan.command = r.command.clone();
    if let Some(names) = &r.quantities {
        plan.keep_quantities(names)?;
    }
    if let Some((sampling, cells)) = r.attractors {
        if sampling.samples == 0 || sampling.samples > 100_000 {
            let why = format!("expected 1 to 100000 samples per cell, got {}", sampling.samples);
            return Err(RequestError::option(Opt::Attractors).text(why).into());
        }
        plan.attractors = Some((sampling, cells == AttractorCells::Hysteresis));
    }
    plan.check().map_err(|e| with_fields(e, FIELDS))?;
    plan.execute(observer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Observer, SceneSource};
    use std::sync::atomic::{AtomicU64, Ordering};

    /// Stops the run once `after` cells are done.
    struct StopAfter {
        after: u64,
        done: AtomicU64,
    }
    impl Observer for StopAfter {
        fn advance(&self, cells: u64) {
            self.done.fetch_add(cells, Ordering::Relaxed);
        }
        fn cancelled(&self) -> bool {
            self.done.load(Ordering::Relaxed) >= self.after
        }
    }

    /// A cancelled atlas ends with `Error::Cancelled` within a cell of
    /// the request on each worker, and leaves no output, partial file or
    /// journal; the same request not cancelled writes its file.
    #[test]
    fn a_cancelled_atlas_stops_and_leaves_nothing() {
        // One folder however often the tests run (emptied first), not one a run.
        let dir = std::env::temp_dir().join("vibroatlas-engine-cancel");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("a.h5");
        let sim = Sim::new(SceneSource::File("../../configs/multi-stop.toml".into()));
        let x = Axis::new("omega", 0.2, 2.5, 40);
        let y = Axis::new("delta", 0.1, 1.5, 20);
        let mut r = AtlasRequest::new(sim, x, y, vec![SweepKind::Up, SweepKind::Down]);
        r.threads = 2;
        r.output = Some(out.clone());
        let stop = StopAfter { after: 50, done: AtomicU64::new(0) };
        let e = atlas(&r, &stop).unwrap_err();
        assert!(matches!(e, crate::Error::Cancelled), "{e}");
        // Each of the two workers finishes at most the cell it is computing.
        assert!(stop.done.load(Ordering::Relaxed) <= 52, "{} cells", stop.done.load(Ordering::Relaxed));
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert!(left.is_empty(), "left behind: {left:?}");
        let done = atlas(&r, &crate::Quiet).unwrap();
        assert_eq!(done.atlas.maps.iter().map(|m| m.cells.iter().flatten().count()).sum::<usize>(), 1600);
        assert!(out.is_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
