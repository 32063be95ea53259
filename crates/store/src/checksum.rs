//! Checksums of what vibroatlas writes: the CRC-32 of a dataset's values
//! bound to its path and to the file's run (`values_crc32`), the bytes they
//! are computed over (numbers as stored, texts with their lengths), and the
//! record of every dataset written ([`Expected`]) that the read-back before a
//! file is put in place checks ([`crate::verify`]).

use crate::error::StoreError;
use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, H5Type};
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
    read: fn(&Dataset) -> hdf5::Result<Read>,
}

/// A dataset read back: the hash and number of its values, and their
/// [`values_crc32`].
struct Read {
    hash: u64,
    count: usize,
    crc: u32,
}

/// The CRC-32 of the dataset at `path` whose values are `bytes`: its path
/// (byte length, u64 little-endian, then the bytes) and its values; the
/// first part of its `values_crc32` ([`of_run`] the rest; see
/// [`crate::layout::attr::VALUES_CRC32`]).
pub(crate) fn values_crc32(path: &str, bytes: &[u8]) -> u32 {
    let mut crc = crc32fast::Hasher::new();
    crc.update(&(path.len() as u64).to_le_bytes());
    crc.update(path.as_bytes());
    crc.update(bytes);
    crc.finalize()
}

/// [`values_crc32`] `crc` continued with the file's run (see [`run_of`]): a
/// dataset copied in from another run's file, however alike, does not pass.
pub(crate) fn of_run(crc: u32, run: u32) -> u32 {
    let mut h = crc32fast::Hasher::new_with_initial(crc);
    h.update(&run.to_le_bytes());
    h.finalize()
}

/// The run of a file: the CRC-32 of the root's `created` and `command` texts
/// (each its byte length, u64 little-endian, then its bytes; a missing one
/// empty): when and by what command the file was written.
pub(crate) fn run_of(f: &hdf5::File) -> u32 {
    let text = |name: &str| {
        f.attr(name).and_then(|a| a.read_scalar::<VarLenUnicode>()).map(|v| v.as_str().to_string()).unwrap_or_default()
    };
    let (created, command) = (text(crate::layout::attr::CREATED), text(crate::layout::attr::COMMAND));
    crate::netcdf::texts_crc32([created.as_bytes(), command.as_bytes()])
}

/// Texts as [`values_crc32`] takes them: each its byte length (u64,
/// little-endian), then its bytes.
pub(crate) fn text_bytes<'a>(texts: impl Iterator<Item = &'a str>) -> Vec<u8> {
    let mut all = Vec::new();
    for t in texts {
        all.extend_from_slice(&(t.len() as u64).to_le_bytes());
        all.extend_from_slice(t.as_bytes());
    }
    all
}

impl Expected {
    fn push(&self, ds: &Dataset, hash: u64, count: usize, read: fn(&Dataset) -> hdf5::Result<Read>) {
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

    /// Reads every dataset noted back from `f`: each dataset's path and the
    /// [`values_crc32`] of what it read, or the first that reads back
    /// otherwise than written (`failed`: the error naming it).
    pub(crate) fn read_back(
        &self,
        f: &hdf5::File,
        failed: impl Fn(&str, String) -> StoreError,
    ) -> Result<Vec<(String, u32)>, StoreError> {
        let entries = self.entries.lock().unwrap_or_else(|p| p.into_inner());
        let mut crcs = Vec::with_capacity(entries.len());
        for e in entries.iter() {
            let ds = f.dataset(&e.path).map_err(|err| failed(&e.path, crate::error::plain(&err)))?;
            let read = (e.read)(&ds).map_err(|err| failed(&e.path, crate::error::plain(&err)))?;
            if read.count != e.count {
                return Err(failed(&e.path, format!("{} values read back, {} written", read.count, e.count)));
            }
            if read.hash != e.hash {
                return Err(failed(&e.path, "its values differ from those written".into()));
            }
            crcs.push((e.path.clone(), read.crc));
        }
        Ok(crcs)
    }
}

fn read_numbers<T: H5Type + Copy>(ds: &Dataset) -> hdf5::Result<Read> {
    let v = ds.read_raw::<T>()?;
    Ok(Read { hash: hash(bytes_of(&v)), count: v.len(), crc: values_crc32(&ds.name(), bytes_of(&v)) })
}

fn read_texts(ds: &Dataset) -> hdf5::Result<Read> {
    crate::heap::check(ds)?;
    let v = ds.read_raw::<VarLenUnicode>()?;
    let bytes = text_bytes(v.iter().map(|t| t.as_str()));
    Ok(Read { hash: hash(&bytes), count: v.len(), crc: values_crc32(&ds.name(), &bytes) })
}

/// The bytes of plain numbers, as HDF5 stores them (native order).
pub(crate) fn bytes_of<T: Copy>(values: &[T]) -> &[u8] {
    // SAFETY: `T` is one of the plain numeric types HDF5 stores (integers and
    // floats without padding).
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), std::mem::size_of_val(values)) }
}

/// A 64-bit hash of `bytes` (words multiplied and rotated in: not for
/// adversaries, for a file that changed under its writer). Four lanes take
/// every fourth word, so that their multiplications overlap; each step is
/// one-to-one in the word, so a change of one word changes its lane, and the
/// lanes are folded in one-to-one too.
fn hash(bytes: &[u8]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let step = |h: u64, word: u64| (h ^ word).wrapping_mul(PRIME).rotate_left(29);
    let word = |w: &[u8]| u64::from_le_bytes([w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7]]);
    let mut lanes = [0xcbf2_9ce4_8422_2325 ^ bytes.len() as u64, 1, 2, 3];
    let mut blocks = bytes.chunks_exact(32);
    for b in blocks.by_ref() {
        for (k, lane) in lanes.iter_mut().enumerate() {
            *lane = step(*lane, word(&b[8 * k..]));
        }
    }
    let mut h = lanes.into_iter().fold(0, step);
    let mut words = blocks.remainder().chunks_exact(8);
    for w in words.by_ref() {
        h = step(h, word(w));
    }
    for &b in words.remainder() {
        h = (h ^ u64::from(b)).wrapping_mul(PRIME);
    }
    h
}

fn hash_texts<'a>(texts: impl Iterator<Item = &'a str>) -> u64 {
    hash(&text_bytes(texts))
}

/// The values of a dataset or an attribute as stored: numbers as their bytes
/// in their own type, texts as [`text_bytes`] takes them; `None` for a type
/// vibroatlas does not write as values (references, compounds).
pub(crate) fn stored_bytes(c: &hdf5::Container) -> hdf5::Result<Option<Vec<u8>>> {
    use hdf5::types::{FloatSize, IntSize, TypeDescriptor as T, VarLenAscii};
    fn raw<V: H5Type + Copy>(c: &hdf5::Container) -> hdf5::Result<Vec<u8>> {
        Ok(bytes_of(&c.read_raw::<V>()?).to_vec())
    }
    Ok(Some(match c.dtype()?.to_descriptor()? {
        T::VarLenUnicode => text_bytes(c.read_raw::<VarLenUnicode>()?.iter().map(|t| t.as_str())),
        T::VarLenAscii => text_bytes(c.read_raw::<VarLenAscii>()?.iter().map(|t| t.as_str())),
        T::Float(FloatSize::U8) => raw::<f64>(c)?,
        T::Float(FloatSize::U4) => raw::<f32>(c)?,
        T::Integer(IntSize::U1) => raw::<i8>(c)?,
        T::Unsigned(IntSize::U1) => raw::<u8>(c)?,
        T::Integer(IntSize::U2) => raw::<i16>(c)?,
        T::Unsigned(IntSize::U2) => raw::<u16>(c)?,
        T::Integer(IntSize::U4) => raw::<i32>(c)?,
        T::Unsigned(IntSize::U4) => raw::<u32>(c)?,
        T::Integer(IntSize::U8) => raw::<i64>(c)?,
        T::Unsigned(IntSize::U8) => raw::<u64>(c)?,
        _ => return Ok(None),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_sees_every_byte_and_the_length() {
        let a: Vec<u8> = (0..=255).collect();
        let h = hash(&a);
        for i in [0, 7, 8, 31, 32, 100, 255] {
            let mut b = a.clone();
            b[i] ^= 1;
            assert_ne!(hash(&b), h, "byte {i}");
        }
        assert_ne!(hash(&a[..255]), h);
        // Words swapped between lanes, and a block's words in another order.
        let mut swapped = a.clone();
        swapped[..16].rotate_left(8);
        assert_ne!(hash(&swapped), h);
        let mut moved = a.clone();
        moved.rotate_left(32);
        assert_ne!(hash(&moved), h);
        assert_ne!(hash_texts(["ab", "c"].into_iter()), hash_texts(["a", "bc"].into_iter()));
    }
}
