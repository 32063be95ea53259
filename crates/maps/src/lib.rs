//! Atlases as data: the parameter [`Axis`] values of a [`Plane`], its cells'
//! records ([`CellData`]) gathered per sweep into the [`Map`]s of an
//! [`Atlas`] described by its [`Meta`], the [`Shard`]s a cluster splits it
//! into, the zones where the sweeps differ ([`hysteresis`]), how parameters
//! are written ([`Notation`]) and the fixed colour of every label
//! ([`palette`]). No threads and no I/O: the grid computes these values, the
//! store writes and reads them, the renderer draws them.
//!
//! ```
//! use maps::{Along, Axis, Plane};
//!
//! let plane = Plane::new(Axis::parse("omega=0.5:2:4", "x")?, Axis::new("delta", 0.1, 1.0, 3), Along::X)?;
//! assert_eq!((plane.cells(), plane.lines(), plane.line_len()), (12, 3, 4));
//! assert_eq!(plane.params(2, 1), vec![("omega".to_string(), 1.0), ("delta".to_string(), 1.0)]);
//! assert!(Plane::new(Axis::new("omega", 2.0, 1.0, 3), Axis::new("delta", 0.1, 1.0, 3), Along::X).is_err());
//! # Ok::<(), maps::FieldError>(())
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

mod atlas;
mod axis;
pub mod basins;
mod cell;
pub mod code;
mod error;
mod families;
pub mod hysteresis;
mod notation;
pub mod palette;
mod plane;
mod shard;
mod sweep;

pub use atlas::{Atlas, AttractorMap, CellAttractor, CellAttractors, Map, Meta, FAMILY_POINTS};
pub use axis::{Axis, Lattice, MAX_COUNT};
pub use basins::{BasinAttractor, BasinMap};
pub use cell::{by_frequency, label_counts, runs, CellData, Number, Quantity, DEFAULT_SECTION_CAP, MAX_SECTION_CAP};
pub use error::{read, FieldError};
pub use families::{families, Families};
pub use notation::Notation;
pub use plane::{Along, Entries, Line, Plane};
pub use shard::{Shard, MAX_SHARDS};
pub use sweep::{SweepKind, Sweeps};
