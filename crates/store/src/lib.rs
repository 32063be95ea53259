//! HDF5 files of vibroatlas: the layout (every path in [`layout`]), writing
//! atomically, reading back, merging shards, and the resume journal.
//!
//! The files are self-describing and read by h5py or MATLAB with no project
//! code: see [`layout`] for the datasets and their codes.
#![deny(missing_docs)]

mod chunked;
pub mod curve;
pub mod error;
mod fields;
pub mod journal;
pub mod layout;
pub mod lock;
pub mod merge;
mod netcdf;
pub mod read;
mod verify;
pub mod write;

pub use curve::{add_curves, read_curves, write_curves, Curve};
pub use error::StoreError;
pub use journal::{fingerprint, journal_path, Journal, SealedLine, Sealer};
pub use lock::{check_output, check_writable, commit, lock_path, write_atomically, OutputLock};
pub use merge::{merge, Merged};
pub use read::{available_memory, read, Loaded};
pub use write::{partial_path, write, Draft, RunInfo};
