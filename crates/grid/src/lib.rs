//! The vibroatlas grid scheduler: parameter axes, planes of cells computed in
//! parallel (fresh tiles or continuation chains up and down), hysteresis,
//! shards for clusters and parameter studies. The only user of threads; no file
//! I/O (the store and the CLI write results).
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod atlas;
pub mod attractors;
pub mod axis;
pub mod cell;
pub mod curves;
pub mod error;
pub mod hysteresis;
pub mod notation;
pub mod palette;
pub mod plane;
pub mod schedule;
pub mod shard;
pub mod study;
pub mod sweep;

pub use atlas::{Atlas, AttractorMap, CellAttractors, Map, Meta};
pub use axis::Axis;
pub use cell::{start_state, CellData, CellSetup};
pub use error::GridError;
pub use notation::Notation;
pub use plane::{Along, Line, Plane};
pub use shard::Shard;
pub use study::Study;
pub use sweep::{chain, chain_from, Progress, Silent, SweepKind};
