//! The vibroatlas grid scheduler: planes of cells computed in parallel (fresh
//! tiles or continuation chains up and down), shards for clusters and
//! parameter studies. The only user of threads; no file I/O (the store and
//! the engine write results).
//!
//! The API: [`CellSetup`] runs one cell into the [`maps::CellData`] it keeps;
//! [`run()`] computes the lines of a [`maps::Plane`] into [`maps::Line`]s
//! ([`line()`] one of them, [`validate`] checks every cell's parameters first);
//! [`Study`] runs planes over a third parameter; every error a [`GridError`].
//! Modules whose functions share names: [`attractors`] (coexisting
//! attractors of a point), [`basins`] (the attractor each start of a grid
//! of initial states reaches), [`curves`] (bifurcation curves seeded from a
//! map), [`schedule`] (line costs, their order and shards). The data types
//! live in the `maps` crate and are re-exported here for the callers that
//! run planes.
//!
//! ```
//! use grid::{Along, Axis, CellSetup, Plane, Quiet, SweepKind};
//!
//! let scene = scene::Scene::parse(&std::fs::read_to_string("../../configs/multi-stop.toml").unwrap()).unwrap();
//! let setup = CellSetup {
//!     scene,
//!     base: Vec::new(),
//!     accuracy: solver::Accuracy::default(),
//!     method: solver::Method::Exact,
//!     section_cap: 0,
//!     quantities: Vec::new(),
//! };
//! let x = Axis::new("omega", 0.3, 0.36, 3);
//! let y = Axis::new("delta", 0.6, 0.6, 1);
//! let plane = Plane::new(x, y, Along::X).unwrap();
//! // The up sweep of the one line: each cell from the previous one's end state.
//! let line = grid::line(&plane, &setup, SweepKind::Up, 0, None, &Quiet).unwrap();
//! assert_eq!(line.cells[1].labels[0].to_string(), "1-4-4"); // M1 at omega = 0.33
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod attractors;
pub mod basins;
mod cell;
pub mod curves;
mod error;
mod observer;
mod run;
pub mod schedule;
mod study;
mod sweep;

pub use cell::{start_state, CellSetup};
pub use error::GridError;
pub use maps::{
    families, hysteresis, palette, read, Along, Atlas, AttractorMap, Axis, BasinAttractor, BasinMap, CellAttractor,
    CellAttractors, CellData, Entries, Families, FieldError, Lattice, Line, Map, Meta, Notation, Number, Plane,
    Quantity, Shard, SweepKind, Sweeps, DEFAULT_SECTION_CAP, FAMILY_POINTS, MAX_COUNT, MAX_SECTION_CAP, MAX_SHARDS,
};
pub use run::{line, run, validate};

/// A pool of `threads` workers (the grid's only threads).
fn pool(threads: usize) -> Result<rayon::ThreadPool, GridError> {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| GridError::field("threads", e.to_string()))
}
pub use observer::{Begin, Observer, Quiet};
pub use study::{Study, MAX_VALUES};
pub use sweep::{chain, chain_from};
