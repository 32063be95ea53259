//! A parameter plane ([`atlas`]): fresh cells, or continuation chains up and
//! down, on threads, optionally one shard of it, with the coexisting
//! attractors of its cells; written to an HDF5 file through a journal.

use crate::error::Result;
use crate::error::{with_fields, Opt, RequestError};
use crate::plan::{Executed, Plan};
use crate::sim::Sim;
use grid::attractors::Sampling;
use grid::Observer;
use grid::{Along, Axis, Plane, Shard, SweepKind};
use std::path::PathBuf;

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
    /// empty); [`AtlasRequest::keep`] sets them from their text.
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

impl AtlasRequest {
    /// Keeps the quantities `text` names, as `--quantities` and Python's
    /// `quantities=` name them: `all`, `none`, or names separated by commas
    /// (each checked against the scene's when the atlas runs).
    pub fn keep(&mut self, text: &str) {
        self.quantities = match text.trim() {
            "all" => None,
            "none" => Some(Vec::new()),
            list => Some(list.split(',').map(|n| n.trim().to_string()).collect()),
        };
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
    plan.inputs = r.sim.scene.file().map(|f| vec![f.to_path_buf()]).unwrap_or_default();
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
        let dir = std::env::temp_dir().join(format!("vibroatlas-engine-cancel-{}", std::process::id()));
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
