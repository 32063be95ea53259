//! HDF5 files of vibroatlas: the layout (every path in [`layout`]), writing
//! atomically, reading back, merging shards, and the resume journal.
//!
//! The files are self-describing and read by h5py or MATLAB with no project
//! code: see [`layout`] for the datasets and their codes.
//!
//! The API: [`write()`] (or a [`Draft`] filled line by line while a run
//! computes) and [`read()`] an atlas; [`merge()`] shards; a [`Journal`] of lines
//! for resuming; [`OutputLock`], [`check_output`] and [`write_atomically`]
//! guard outputs; curves go in their own files ([`write_curves`],
//! [`read_curves`]) or into an atlas ([`add_curves`]). Every error is a
//! [`StoreError`] naming the file (and the dataset).
//!
//! ```no_run
//! let loaded = store::read(std::path::Path::new("out/reference.h5"))?;
//! let up = loaded.atlas.map(maps::SweepKind::Up).expect("an up sweep");
//! let unresolved = up.cells.iter().flatten().filter(|c| c.reason.is_some()).count();
//! println!("{} cells, {unresolved} unresolved, made by {}", up.cells.len(), loaded.info.command);
//! # Ok::<(), store::StoreError>(())
//! ```
#![deny(missing_docs)]

mod attrs;
mod basins;
mod checked;
mod checksum;
mod chunked;
mod curve;
mod error;
mod fields;
mod heap;
mod journal;
pub mod layout;
mod lock;
mod merge;
mod netcdf;
mod read;
#[cfg(test)]
mod testing;
mod verify;
mod write;

pub use basins::{is_basins, read_basins, write_basins};
pub use checked::MAX_EXPANSION;
pub use curve::{add_curves, read_curves, write_curves, Curve};
pub use error::{Hdf5Error, JournalProblem, OtherKind, Setting, StoreError};
pub use journal::{fingerprint, Journal, SealedLine, Sealer};
pub use lock::{
    canonical_output, check_output, check_own_file, check_writable, commit, create_folder, journal_path, lock_path,
    partial_path, write_atomically, OutputLock,
};
pub use merge::{merge, Merged};
pub use read::{available_memory, is_atlas, read, stop_laws, stored_scene, Loaded, MAX_DIM};
pub use write::{check_finished, image, labels_crc32, pairs, scene_of_run, write, Draft, Parent, RunInfo, GIT_COMMIT};
