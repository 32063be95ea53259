//! Reading datasets with their checks: a [`Checker`] bound to one file opens
//! a dataset only when its size in memory is bounded by its bytes in the file
//! ([`MAX_EXPANSION`]) and its shape is the grid's, and reads values and
//! texts only when they match the checksums vibroatlas wrote with them.

use crate::attrs;
use crate::checksum::{bytes_of, of_run, stored_bytes, text_bytes, values_crc32};
use crate::error::StoreError;
use crate::layout::attr;
use crate::netcdf;
use hdf5::types::VarLenUnicode;
use std::path::Path;

/// Largest uncompressed size of a dataset per byte it takes in the file:
/// deflate's own bound (1032) with a margin. A dataset whose values would
/// take more is refused before it is read: it is not one vibroatlas wrote
/// (its chunks missing, its shape forged), and reading it would allocate far
/// more than the file holds.
pub const MAX_EXPANSION: u64 = 1100;

/// Checks the datasets of one file before they are read: their shapes
/// against the grid and each other, their sizes against the file's own.
pub(crate) struct Checker<'a> {
    pub(crate) path: &'a Path,
    /// Every dataset with values carries its `values_crc32` (layout 3 on):
    /// one without it was replaced.
    pub(crate) sealed: bool,
    /// The file's run, which its `values_crc32` are bound to
    /// ([`crate::checksum::run_of`]).
    pub(crate) run: u32,
}

/// One axis of a dataset's expected shape: its length, what it counts, and
/// what says so (`rows`, `the grid has`).
#[derive(Clone, Copy)]
pub(crate) struct Dim<'a>(pub(crate) usize, pub(crate) &'a str, pub(crate) &'a str);

impl Checker<'_> {
    pub(crate) fn bad(&self, ds: &str, message: impl Into<String>) -> StoreError {
        StoreError::dataset(self.path, ds, message)
    }

    /// Dataset `name` of `g`, its uncompressed size bounded by its bytes in
    /// the file ([`MAX_EXPANSION`]).
    pub(crate) fn open(&self, g: &hdf5::Group, name: &str) -> Result<hdf5::Dataset, StoreError> {
        let ds = g.dataset(name).map_err(|e| self.bad(&format!("{}/{name}", g.name()), crate::error::plain(&e)))?;
        let elem = ds.dtype().map_err(|e| StoreError::hdf5(self.path, e))?.size() as u64;
        let bytes = (ds.size() as u64).saturating_mul(elem);
        let stored = ds.storage_size();
        if bytes > stored.saturating_mul(MAX_EXPANSION) {
            return Err(self.bad(
                &ds.name(),
                format!("{bytes} bytes of values stored in {stored} bytes of the file: not a dataset vibroatlas wrote"),
            ));
        }
        Ok(ds)
    }

    /// [`Checker::open`], then its shape checked against `want` (axis by
    /// axis when it has as many axes, else by its number of values).
    pub(crate) fn shaped(&self, g: &hdf5::Group, name: &str, want: &[Dim]) -> Result<hdf5::Dataset, StoreError> {
        let ds = self.open(g, name)?;
        let shape = ds.shape();
        if shape.len() == want.len() {
            for (&got, &Dim(n, what, says)) in shape.iter().zip(want) {
                if got != n {
                    return Err(self.bad(&ds.name(), format!("{got} {what}, {says} {n}")));
                }
            }
        } else {
            let n = want.iter().fold(1usize, |p, d| p.saturating_mul(d.0));
            if ds.size() != n {
                let dims: Vec<String> = want.iter().map(|d| d.0.to_string()).collect();
                return Err(
                    self.bad(&ds.name(), format!("{} values, expected {} ({})", ds.size(), n, dims.join(" x ")))
                );
            }
        }
        Ok(ds)
    }

    /// Reads `ds` whole (its size checked by [`Checker::open`]).
    /// The values of `ds`, checked against their `values_crc32` where it
    /// has one (files written before it have none).
    pub(crate) fn raw<T: hdf5::H5Type + Copy>(&self, ds: &hdf5::Dataset) -> Result<Vec<T>, StoreError> {
        let h = |e: hdf5::Error| self.bad(&ds.name(), crate::error::plain(&e));
        let v = ds.read_raw::<T>().map_err(h)?;
        // The checksum is of the values as stored: a dataset read as another
        // type (narrow flags read as u32) is checked in its own.
        if ds.dtype().and_then(|d| d.to_descriptor()).map_err(h)? == T::type_descriptor() {
            values_at(self, ds, bytes_of(&v))?;
        } else if let Some(stored) = stored_bytes(ds).map_err(h)? {
            values_at(self, ds, &stored)?;
        }
        Ok(v)
    }
}

/// The texts of the 1-D dataset `ds`, checked against their checksum
/// ([`attr::TEXT_CRC32`]; datasets written before it have none) and as UTF-8.
pub(crate) fn texts(ck: &Checker, ds: &hdf5::Dataset) -> Result<Vec<String>, StoreError> {
    crate::heap::check(ds).map_err(|e| ck.bad(&ds.name(), e))?;
    let raw = ds.read_raw::<VarLenUnicode>().map_err(|e| ck.bad(&ds.name(), crate::error::plain(&e)))?;
    if let Some(want) = attrs::optional::<u32>(ck.path, ds, attr::TEXT_CRC32)? {
        if netcdf::texts_crc32(raw.iter().map(|t| t.as_bytes())) != want {
            return Err(ck.bad(&ds.name(), format!("its texts {}", attrs::mismatch(attr::TEXT_CRC32))));
        }
    }
    values_at(ck, ds, &text_bytes(raw.iter().map(|t| t.as_str())))?;
    raw.iter()
        .map(|v| String::from_utf8(v.as_bytes().to_vec()))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| ck.bad(&ds.name(), "a text that is not UTF-8"))
}

/// Checks the values of `ds` (`bytes`, as read; texts as
/// [`text_bytes`]) against the checksum that binds them to
/// its path ([`attr::VALUES_CRC32`]; datasets written before it have none).
pub(crate) fn values_at(ck: &Checker, ds: &hdf5::Dataset, bytes: &[u8]) -> Result<(), StoreError> {
    match attrs::optional::<u32>(ck.path, ds, attr::VALUES_CRC32)? {
        Some(want) if of_run(values_crc32(&ds.name(), bytes), ck.run) != want => Err(ck.bad(
            &ds.name(),
            format!("its values (at this path) {}", attrs::mismatch(attr::VALUES_CRC32)),
        )),
        None if ck.sealed => Err(ck.bad(
            &ds.name(),
            format!(
                "its values have no checksum (attribute {}), which vibroatlas gives every dataset: it was replaced since vibroatlas wrote the file",
                attr::VALUES_CRC32
            ),
        )),
        _ => Ok(()),
    }
}

/// Checks the values of `ds` (`bytes`, as read) against their checksum
/// ([`attr::DATA_CRC32`]; datasets written before it, or deflated, have
/// none).
pub(crate) fn data(ck: &Checker, ds: &hdf5::Dataset, bytes: &[u8]) -> Result<(), StoreError> {
    match attrs::optional::<u32>(ck.path, ds, attr::DATA_CRC32)? {
        Some(want) if crc32fast::hash(bytes) != want => {
            Err(ck.bad(&ds.name(), format!("its values {}", attrs::mismatch(attr::DATA_CRC32))))
        }
        _ => Ok(()),
    }
}
