//! Reading a finished file back before it is put in place.
//!
//! Before [`crate::Draft::finish`] renames the temporary file over the target,
//! it closes the file, opens it again and reads every dataset it wrote through
//! the library's own filters (inflate, Fletcher-32): the per-cell datasets of
//! every sweep are compared value for value (bit for bit) with the atlas they
//! were written from, every other dataset (label tables and codes, colours,
//! lines done, sections, hysteresis, legends, attractors, coordinates) with a
//! hash of the values written, kept by [`Expected`] as each was written. A
//! chunk that does not read (a checksum or inflate error, a file cut short
//! under the writer) or a dataset that reads back different is an
//! [`StoreError::Unverified`] naming it, and nothing is renamed.

use crate::checksum::{of_run, run_of, stored_bytes, Expected};
use crate::error::StoreError;
use crate::fields::Field;
use maps::Atlas;
use scene::Named;
use std::path::Path;

/// A dataset of the file about to be put at `path` that did not read back.
fn unverified(path: &Path, dataset: &str, message: String) -> StoreError {
    StoreError::Unverified {
        path: path.display().to_string(),
        dataset: dataset.trim_start_matches('/').to_string(),
        message,
    }
}

/// Reads the closed file `tmp` (to be renamed to `path`) back: the per-cell
/// datasets of `atlas`'s sweeps against the atlas, every other dataset
/// against `expected`. Returns each dataset's path and the
/// [`values_crc32`] of what it read.
pub(crate) fn file(
    tmp: &Path,
    path: &Path,
    atlas: &Atlas,
    expected: &Expected,
) -> Result<Vec<(String, u32)>, StoreError> {
    let f = hdf5::File::open(tmp).map_err(|e| unverified(path, "/", crate::error::plain(&e)))?;
    datasets(&f, path, atlas, expected)
}

/// [`file`] of the open file `f` (one in memory: [`crate::image`]).
pub(crate) fn datasets(
    f: &hdf5::File,
    path: &Path,
    atlas: &Atlas,
    expected: &Expected,
) -> Result<Vec<(String, u32)>, StoreError> {
    let failed = |dataset: &str, message: String| unverified(path, dataset, message);
    let m = &atlas.meta;
    let mut crcs = Vec::new();
    for map in &atlas.maps {
        for field in Field::all(m) {
            let name = format!("{}/{}", map.sweep.name(), field.name(m));
            let ds = f.dataset(&name).map_err(|e| failed(&name, crate::error::plain(&e)))?;
            match field.compare(m, &ds, &map.cells) {
                // The path, not the open dataset: an open dataset keeps the
                // chunks it read in the library's chunk cache (up to 1 MiB
                // each), and every per-cell dataset held open until the seal
                // added 70 MB to the main job's peak.
                Ok(Some(crc)) => crcs.push((ds.name(), crc)),
                Ok(None) => return Err(failed(&name, "its values differ from those written".into())),
                Err(e) => return Err(failed(&name, crate::error::plain(&e))),
            }
        }
    }
    crcs.extend(expected.read_back(f, failed)?);
    Ok(crcs)
}

/// Reads the closed file `tmp` back as [`file`] does and writes each
/// dataset's `values_crc32` into it, in one opening: the values verified are
/// the values sealed.
pub(crate) fn file_sealed(tmp: &Path, path: &Path, atlas: &Atlas, expected: &Expected) -> Result<(), StoreError> {
    let f = hdf5::File::open_rw(tmp).map_err(|e| unverified(path, "/", crate::error::plain(&e)))?;
    let crcs = datasets(&f, path, atlas, expected)?;
    seal_in(&f, path, &crcs)
}

/// Writes each dataset's `values_crc32` (see [`file`]) into the open file
/// `f` whose datasets they are.
pub(crate) fn seal_in(f: &hdf5::File, path: &Path, crcs: &[(String, u32)]) -> Result<(), StoreError> {
    let run = run_of(f);
    for (name, crc) in crcs {
        f.dataset(name)
            .and_then(|ds| crate::netcdf::attr_num(&ds, crate::layout::attr::VALUES_CRC32, of_run(*crc, run)))
            .map_err(|e| unverified(path, name, crate::error::plain(&e)))?;
    }
    Ok(())
}

/// Attributes that say when and by which build a file was made, not what it
/// holds: a file rebuilt from its own content differs in them (the root's
/// text attributes are covered by their checksum, checked by every reader).
const MADE: &[&str] = &["created", "history", "source", "git_commit", "attributes_crc32"];

/// Attributes the HDF5 dimension-scale API keeps (object references, which
/// differ between two files however equal).
const SCALES: &[&str] = &["DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME", "_Netcdf4Dimid", "_Netcdf4Coordinates"];

/// The error of attribute `attribute` of `object` (a path in the file `path`)
/// whose value is not what vibroatlas writes for the file's content.
pub(crate) fn differs(path: &Path, object: &str, attribute: &str) -> StoreError {
    object_error(
        path,
        object,
        format!(
            "its attribute {attribute} differs from what vibroatlas writes for this content: the file is damaged or was changed"
        ),
    )
}

/// The error `message` of `object` (a path in the file `path`; `/` the root).
fn object_error(path: &Path, object: &str, message: String) -> StoreError {
    StoreError::Dataset {
        path: path.display().to_string(),
        dataset: if object == "/" { "/".into() } else { object.trim_start_matches('/').to_string() },
        message,
    }
}

/// Checks that every group, dataset and attribute of `expected` (a file
/// written afresh from what `actual` read back as) is in `actual` with the
/// same value: an attribute that a reader does not use (a unit, the CF
/// `flag_meanings` of codes) changed, damaged or deleted, or a dataset or
/// group deleted, is an error naming it. Attributes a user added to
/// `actual` are allowed; so are those of [`MADE`] and [`SCALES`], and a
/// file without the root's `reason_details` (one written before it).
pub(crate) fn attributes(expected: &hdf5::File, actual: &hdf5::File, path: &Path) -> Result<(), StoreError> {
    let fail = |object: &str, message: String| object_error(path, object, message);
    let mut pending = vec!["/".to_string()];
    while let Some(name) = pending.pop() {
        let (want, have): (hdf5::Location, hdf5::Location) = match expected.group(&name) {
            Ok(g) => {
                for child in g.member_names().map_err(|e| fail(&name, crate::error::plain(&e)))? {
                    pending.push(if name == "/" { format!("/{child}") } else { format!("{name}/{child}") });
                }
                let have = actual.group(&name).map_err(|_| fail(&name, "the group is missing".into()))?;
                (hdf5::Location::clone(&g), hdf5::Location::clone(&have))
            }
            Err(_) => {
                let ds = expected.dataset(&name).map_err(|e| fail(&name, crate::error::plain(&e)))?;
                let have = actual.dataset(&name).map_err(|_| fail(&name, "the dataset is missing".into()))?;
                (hdf5::Location::clone(&ds), hdf5::Location::clone(&have))
            }
        };
        let root = name == "/";
        for attr in want.attr_names().map_err(|e| fail(&name, crate::error::plain(&e)))? {
            if SCALES.contains(&attr.as_str()) || (root && MADE.contains(&attr.as_str())) {
                continue;
            }
            // A file written before `reason_details` has its details
            // without it (the root's attributes_crc32, checked when the
            // file was read, says it never had one).
            if root
                && attr == crate::layout::attr::REASON_DETAILS
                && !have.attr_names().is_ok_and(|n| n.contains(&attr))
            {
                continue;
            }
            let w =
                want.attr(&attr).and_then(|a| stored_bytes(&a)).map_err(|e| fail(&name, crate::error::plain(&e)))?;
            let Some(w) = w else { continue };
            let h = have.attr(&attr).map_err(|_| fail(&name, format!("its attribute {attr} is missing"))).and_then(
                |a| {
                    stored_bytes(&a).map_err(|e| {
                        fail(&name, format!("its attribute {attr} does not read ({})", crate::error::plain(&e)))
                    })
                },
            )?;
            if h.as_ref() != Some(&w) {
                return Err(differs(path, &name, &attr));
            }
        }
    }
    Ok(())
}
