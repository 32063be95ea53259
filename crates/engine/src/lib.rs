//! The runs of vibroatlas as a library: one typed request per kind of run
//! and one call that runs it. The command-line tool and the Python module
//! parse their arguments into these requests, call, and present the results.
//!
//! | call | request | result |
//! |---|---|---|
//! | [`cell()`] | [`Sim`] and a [`Start`] | [`Cell`] (`to_json`: `cell --json`) |
//! | [`sweep()`] | [`SweepRequest`] | [`Sweep`] (`to_json`: `sweep --json`) |
//! | [`atlas()`] | [`AtlasRequest`] | [`Executed`] (the atlas, the file written) |
//! | [`zoom()`] | [`ZoomRequest`] | [`Executed`] (a box of a stored atlas, computed again) |
//! | [`attractors()`] | [`AttractorsRequest`] | [`Attractors`] (`to_json`: `attractors --json`) |
//! | [`curve()`] | [`CurveRequest`] | [`FollowedCurve`] (`to_json`: `curve --json`) |
//! | [`merge()`] | [`MergeRequest`] | [`store::Merged`] (the atlas written) |
//! | [`study()`], then [`StudyPlan::run`] | the study file | one atlas and map per value, and their contact sheet |
//! | [`bench::bench()`] | [`bench::BenchRequest`] | [`bench::Bench`] (`to_json`: `bench --json`) |
//!
//! Long runs report to an [`Observer`] (a progress bar), which may also stop
//! them ([`Observer::cancelled`]: the run ends with [`Error::Cancelled`] and
//! writes no file); a run on another thread is followed through a [`Job`]. Every call fails with an [`Error`], whose causes are its
//! sources, printed as one line; a refused request is an [`Error::Request`]
//! ([`RequestError`]) naming the option at fault in the request's terms
//! ([`Opt`]: `set mu_k: …`), which each front end spells in its own words
//! ([`Words`], [`in_words`]: the command line's `--set mu_k: …`).
//!
//! The README's main job, the reference plane of the multi-stop scene with
//! both sweeps (here on a coarse grid, written to a file):
//!
//! ```no_run
//! use engine::prelude::*;
//! use grid::{Axis, SweepKind};
//!
//! let sim = Sim::new(SceneSource::File("configs/multi-stop.toml".into()));
//! let x = Axis::new("omega", 0.1, 3.05, 296);
//! let y = Axis::new("delta", 0.05, 2.0, 196);
//! let mut run = AtlasRequest::new(sim, x, y, vec![SweepKind::Up, SweepKind::Down]);
//! run.output = Some("out/reference.h5".into());
//! let done = atlas(&run, &Quiet)?;
//! println!("{} cells in {:.1} s", done.atlas.meta.plane.cells(), done.secs);
//! # Ok::<(), engine::Error>(())
//! ```
#![deny(missing_docs)]

mod atlas;
mod attractors;
mod basins;
pub mod bench;
mod cell;
mod curve;
mod error;
mod job;
mod merge;
mod orbit;
mod pictures;
mod plan;
mod record;
mod report;
mod sim;
mod study;
mod summary;
mod sweep;
mod trace;
mod zoom;

// What a run is asked to do, and the set-up every run shares.
pub use sim::{check_period, labels_of, parameters_of, Origin, SceneSource, Setup, Sim, Source, Start};
// One cell: its steady motion, its trace and sections, its pictures.
pub use cell::{cell, friction_names, Cell, CellReport};
pub use pictures::{draw_basins, portrait, section_panels};
pub use record::CellRecord;
pub use trace::{
    check_trace_samples, halt_text, sections, trace, window, window_periods, Row, Sections, Window,
    DEFAULT_SECTION_PERIODS, MAX_SECTION_PERIODS, MAX_TRACE_ROWS, MAX_TRACE_SAMPLES,
};
// Orbits, their branches and the bifurcation curves of two parameters.
pub use curve::{
    curve, curves, stored, stored_setup, Codim2, CurveReport, CurveReportPoint, CurveRequest, CurveSummary,
    CurvesReport, CurvesRequest, FollowedCurve, MapCurves, SideMotion, Sides, DEFAULT_STEPS, DEFAULT_WINDOW,
};
pub use orbit::{
    continuation, orbit, BranchBifurcation, BranchPoint, BranchReport, CellOrbit, ContinuationRequest, Critical,
    FollowedOrbit, Multiplier, OrbitImpact, OrbitReport, OrbitRequest,
};
// Lines and planes of cells, and their files.
pub use atlas::{atlas, AtlasOptions, AtlasRequest, AttractorCells};
pub use merge::{merge, MergeRequest};
pub use plan::{threads, Executed, Plan};
pub use study::{sheet_panel, study, StudyAtlas, StudyPlan};
pub use sweep::{sweep, Differing, Direction, Legs, Sweep, SweepPoint, SweepReport, SweepRequest};
pub use zoom::{
    check_size as check_zoom_size, parse_assignment, zoom, zoom_box, zoom_setup, ZoomRequest, MAX_ZOOM_CELLS,
};
// Coexisting attractors of a point, and the basins of a grid of states.
pub use attractors::{
    attractors, AttractorReport, Attractors, AttractorsReport, AttractorsRequest, SampleBox, MAX_SAMPLES,
};
pub use basins::{
    basins, components, proposed_axes, report as basins_report, BasinAttractorReport, BasinsReport, BasinsRequest,
    BoundaryReport, MAX_STARTS,
};
// What a stored file holds (`inspect`).
pub use summary::{
    reasons, AxisReport, ClassCounts, Extreme, HysteresisCounts, InspectReport, ParentReport, QuantityExtremes,
    QuantityReport, ReasonCount, Summary, SummaryReport, SweepCounts, SweepSummary, CLASSES,
};
// Progress, stopping, and errors.
pub use error::{
    causes, grid_error, in_words, unwritten_text, Error, Fields, Opt, RequestError, Result, SceneLoadError, Words,
};
pub use grid::{Begin, Observer, Quiet};
pub use job::Job;

/// What most callers use: the options of a run and where it starts, the
/// calls of the table above with their requests, and the observer, job and
/// error of every run (`use engine::prelude::*;`).
pub mod prelude {
    pub use crate::{
        atlas, attractors, basins, cell, curve, curves, merge, orbit, study, sweep, zoom, AtlasRequest,
        AttractorsRequest, BasinsRequest, CurveRequest, CurvesRequest, Error, Job, MergeRequest, Observer,
        OrbitRequest, Quiet, Result, SceneSource, Sim, Start, SweepRequest, ZoomRequest,
    };
}
