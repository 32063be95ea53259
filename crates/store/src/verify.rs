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

use crate::error::StoreError;
use crate::fields::Field;
use grid::Atlas;
use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, H5Type};
use std::path::Path;
use std::sync::Mutex;

/// What the datasets written into a file should read back as (their paths
/// and hashes), collected while writing it.
#[derive(Debug, Default)]
pub(crate) struct Expected {
    entries: Mutex<Vec<Entry>>,
}

/// One dataset written: where, the hash and number of its values, and how
/// to read it back (typed as it was written).
#[derive(Debug)]
struct Entry {
    path: String,
    hash: u64,
    count: usize,
    read: fn(&Dataset) -> hdf5::Result<(u64, usize)>,
}

impl Expected {
    fn push(&self, ds: &Dataset, hash: u64, count: usize, read: fn(&Dataset) -> hdf5::Result<(u64, usize)>) {
        let entry = Entry { path: ds.name(), hash, count, read };
        self.entries.lock().unwrap_or_else(|p| p.into_inner()).push(entry);
    }

    /// Notes that `ds` was written with `values` (numbers, in the dataset's
    /// order).
    pub(crate) fn numbers<T: H5Type + Copy>(&self, ds: &Dataset, values: &[T]) {
        self.push(ds, hash(bytes_of(values)), values.len(), read_numbers::<T>);
    }

    /// Notes that `ds` was written with the texts `values` (as
    /// [`crate::netcdf::text`] stores them).
    pub(crate) fn texts(&self, ds: &Dataset, values: &[String]) {
        let stored: Vec<String> = values.iter().map(|v| crate::netcdf::text(v).to_string()).collect();
        self.push(ds, hash_texts(stored.iter().map(String::as_str)), values.len(), read_texts);
    }
}

fn read_numbers<T: H5Type + Copy>(ds: &Dataset) -> hdf5::Result<(u64, usize)> {
    let v = ds.read_raw::<T>()?;
    Ok((hash(bytes_of(&v)), v.len()))
}

fn read_texts(ds: &Dataset) -> hdf5::Result<(u64, usize)> {
    crate::heap::check(ds)?;
    let v = ds.read_raw::<VarLenUnicode>()?;
    Ok((hash_texts(v.iter().map(|t| t.as_str())), v.len()))
}

/// The bytes of plain numbers, as HDF5 stores them (native order).
pub(crate) fn bytes_of<T: Copy>(values: &[T]) -> &[u8] {
    // SAFETY: `T` is one of the plain numeric types HDF5 stores (integers and
    // floats without padding).
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), std::mem::size_of_val(values)) }
}

/// A 64-bit hash of `bytes` (words multiplied and rotated in: not for
/// adversaries, for a file that changed under its writer).
fn hash(bytes: &[u8]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h = 0xcbf2_9ce4_8422_2325 ^ bytes.len() as u64;
    let mut words = bytes.chunks_exact(8);
    for w in words.by_ref() {
        let word = u64::from_le_bytes([w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7]]);
        h = (h ^ word).wrapping_mul(PRIME).rotate_left(29);
    }
    for &b in words.remainder() {
        h = (h ^ u64::from(b)).wrapping_mul(PRIME);
    }
    h
}

fn hash_texts<'a>(texts: impl Iterator<Item = &'a str>) -> u64 {
    let mut all = Vec::new();
    for t in texts {
        all.extend_from_slice(&(t.len() as u64).to_le_bytes());
        all.extend_from_slice(t.as_bytes());
    }
    hash(&all)
}

/// Reads the closed file `tmp` (to be renamed to `path`) back: the per-cell
/// datasets of `atlas`'s sweeps against the atlas, every other dataset
/// against `expected`.
pub(crate) fn file(tmp: &Path, path: &Path, atlas: &Atlas, expected: &Expected) -> Result<(), StoreError> {
    let failed = |dataset: &str, message: String| StoreError::Unverified {
        path: path.display().to_string(),
        dataset: dataset.trim_start_matches('/').to_string(),
        message,
    };
    let f = hdf5::File::open(tmp).map_err(|e| failed("/", crate::error::plain(&e)))?;
    let m = &atlas.meta;
    for map in &atlas.maps {
        for field in Field::all(m) {
            let name = format!("{}/{}", map.sweep.name(), field.name(m));
            let ds = f.dataset(&name).map_err(|e| failed(&name, crate::error::plain(&e)))?;
            match field.compare(m, &ds, &map.cells) {
                Ok(true) => {}
                Ok(false) => return Err(failed(&name, "its values differ from those written".into())),
                Err(e) => return Err(failed(&name, crate::error::plain(&e))),
            }
        }
    }
    let entries = expected.entries.lock().unwrap_or_else(|p| p.into_inner());
    for e in entries.iter() {
        let ds = f.dataset(&e.path).map_err(|err| failed(&e.path, crate::error::plain(&err)))?;
        let (hash, count) = (e.read)(&ds).map_err(|err| failed(&e.path, crate::error::plain(&err)))?;
        if count != e.count {
            return Err(failed(&e.path, format!("{count} values read back, {} written", e.count)));
        }
        if hash != e.hash {
            return Err(failed(&e.path, "its values differ from those written".into()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_sees_every_byte_and_the_length() {
        let a: Vec<u8> = (0..=255).collect();
        let h = hash(&a);
        for i in [0, 7, 8, 100, 255] {
            let mut b = a.clone();
            b[i] ^= 1;
            assert_ne!(hash(&b), h, "byte {i}");
        }
        assert_ne!(hash(&a[..255]), h);
        assert_ne!(hash_texts(["ab", "c"].into_iter()), hash_texts(["a", "bc"].into_iter()));
    }
}
