//! The vibroatlas grid scheduler: parameter axes, planes of cells computed in
//! parallel (fresh tiles or continuation chains up and down), hysteresis,
//! shards for clusters and parameter studies. The only user of threads; no file
//! I/O (the store and the engine write results).
//!
//! The API: the types at the crate root (a [`Plane`] of two [`Axis`] values,
//! its [`Line`]s computed by [`Plane::run`] into an [`Atlas`] of [`Map`]s of
//! [`CellData`], described by its [`Meta`]; [`CellSetup`] runs one cell;
//! [`Shard`], [`Study`]; every error a [`GridError`]), and five modules whose
//! functions share names: [`attractors`] (coexisting attractors of a point),
//! [`curves`] (bifurcation curves seeded from a map), [`hysteresis`] (zones
//! where the sweeps differ), [`palette`] (the fixed colour of each label) and
//! [`schedule`] (line costs, their order and shards).
//!
//! ```
//! use grid::{Along, Axis, CellSetup, Plane, Silent, SweepKind};
//!
//! let scene = scene::Scene::parse(&std::fs::read_to_string("../../configs/multi-stop.toml").unwrap()).unwrap();
//! let setup = CellSetup {
//!     scene,
//!     base: Vec::new(),
//!     accuracy: solver::Accuracy::default(),
//!     method: solver::Method::Exact,
//!     section_cap: 0,
//! };
//! let x = Axis::new("omega", 0.3, 0.36, 3);
//! let y = Axis::new("delta", 0.6, 0.6, 1);
//! let plane = Plane::new(x, y, Along::X).unwrap();
//! // The up sweep of the one line: each cell from the previous one's end state.
//! let line = plane.line(&setup, SweepKind::Up, 0, None, &Silent).unwrap();
//! assert_eq!(line.cells[1].labels[0].to_string(), "1-4-4"); // M1 at omega = 0.33
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

mod atlas;
pub mod attractors;
mod axis;
mod cell;
pub mod curves;
mod error;
pub mod hysteresis;
mod notation;
pub mod palette;
mod plane;
pub mod schedule;
mod shard;
mod study;
mod sweep;

pub use atlas::{Atlas, AttractorMap, CellAttractors, Map, Meta};
pub use axis::{Axis, Lattice, MAX_COUNT};
pub use cell::{start_state, CellData, CellSetup, MAX_SECTION_CAP};
pub use error::GridError;
pub use notation::{stop_events, Notation};
pub use plane::{Along, Entries, Line, Plane};
pub use shard::{Shard, MAX_SHARDS};
pub use study::{Study, MAX_VALUES};
pub use sweep::{chain, chain_from, Progress, Silent, SweepKind};
