//! Chunked, deflated, checksummed datasets whose chunks are compressed on
//! several threads.
//!
//! The HDF5 library runs its filters (deflate) on the calling thread, one
//! chunk after another: for a large atlas most of the time after the last
//! cell went there. Here the chunks of a dataset are deflated in parallel
//! (zlib streams at level 4, what HDF5's deflate filter writes and every
//! reader inflates) and handed to the library as they are, by direct chunk
//! writes (`H5Dwrite_chunk`), in chunk order from the calling thread. The data
//! read back is the same, value for value; only the compressed bytes may
//! differ from the library's own.
//!
//! Every chunked dataset also carries HDF5's Fletcher-32 checksum filter
//! after deflate (the order h5py and netCDF-C use), so that every reader
//! (the library itself, h5py, netCDF-C, xarray) verifies each chunk as it
//! reads it and refuses a corrupted one. A direct chunk write bypasses the
//! pipeline, so the chunks written here are what the pipeline would have
//! made: the filtered (deflated) bytes followed by their Fletcher-32 sum
//! ([`fletcher32`], as `H5Z_filter_fletcher32` computes it), little-endian,
//! with the filter mask 0 (every filter applied).

use crate::checksum::{bytes_of, Expected};
use flate2::{Compress, Compression, FlushCompress, Status};
use hdf5::{Dataset, Group, H5Type};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// Deflate level of every chunked dataset.
const LEVEL: u32 = 4;

/// Largest number of rows (first axis) of one chunk.
const CHUNK_ROWS: usize = 4096;

/// Largest size of one chunk before compression, bytes: a reader that wants
/// one cell inflates at most this much, and a large dataset has chunks for
/// every thread to deflate.
pub(crate) const CHUNK_BYTES: usize = 1 << 20;

/// Writes chunked datasets, deflating their chunks on `threads` threads, and
/// notes what each holds (for the read-back of [`crate::verify`]).
#[derive(Debug, Default)]
pub(crate) struct Deflater {
    /// Threads that compress (at least 1).
    pub threads: usize,
    /// What the datasets written hold.
    pub expected: Expected,
}

impl Deflater {
    /// Creates dataset `name` in `g` holding `data`, chunked by rows of the
    /// first axis (whole along the others; at most [`CHUNK_ROWS`] rows and
    /// [`CHUNK_BYTES`] bytes, at least one row), deflated and checksummed:
    /// its chunks deflated on the threads, written in order.
    pub(crate) fn dataset<T: H5Type + Copy + Send + Sync, D: ndarray::Dimension>(
        &self,
        g: &Group,
        name: &str,
        data: &ndarray::Array<T, D>,
    ) -> hdf5::Result<Dataset> {
        self.rows(g, name, data, true)
    }

    /// [`Deflater::dataset`] without compression: chunks of rows stored as
    /// they are, checksummed (the checksums computed on the threads).
    pub(crate) fn stored<T: H5Type + Copy + Send + Sync, D: ndarray::Dimension>(
        &self,
        g: &Group,
        name: &str,
        data: &ndarray::Array<T, D>,
    ) -> hdf5::Result<Dataset> {
        self.rows(g, name, data, false)
    }

    fn rows<T: H5Type + Copy + Send + Sync, D: ndarray::Dimension>(
        &self,
        g: &Group,
        name: &str,
        data: &ndarray::Array<T, D>,
        deflated: bool,
    ) -> hdf5::Result<Dataset> {
        let shape = data.shape();
        let row_bytes = shape[1..].iter().product::<usize>() * std::mem::size_of::<T>();
        let rows = shape.first().copied().unwrap_or(1).min(CHUNK_ROWS).min((CHUNK_BYTES / row_bytes.max(1)).max(1));
        let chunk: Vec<usize> = shape.iter().enumerate().map(|(i, &n)| if i == 0 { rows } else { n }).collect();
        let ds = if deflated {
            Deflater::chunked_empty::<T>(g, name, shape, &chunk)?
        } else {
            Deflater::stored_empty::<T>(g, name, shape, &chunk)?
        };
        if data.is_empty() {
            self.expected.numbers::<T>(&ds, &[]);
            return Ok(ds);
        }
        let flat = data.as_standard_layout();
        let flat = flat.as_slice().expect("a standard layout is contiguous");
        self.expected.numbers(&ds, flat);
        if !deflated {
            crate::netcdf::attr_num(&ds, crate::layout::attr::DATA_CRC32, crc32fast::hash(bytes_of(flat)))?;
        }
        let per_chunk = rows * shape[1..].iter().product::<usize>();
        let pieces: Vec<&[T]> = flat.chunks(per_chunk).collect();
        let filtered = self.map(pieces.len(), |c| {
            if deflated {
                deflate_padded(pieces[c], per_chunk)
            } else {
                stored_padded(pieces[c], per_chunk)
            }
        });
        for (c, bytes) in filtered.into_iter().enumerate() {
            let mut offset = vec![0u64; shape.len()];
            offset[0] = (c * rows) as u64;
            write_chunk(&ds, &offset, &bytes)?;
        }
        Ok(ds)
    }

    /// Creates dataset `name` of `shape` in `g`, with no data yet, in chunks
    /// of `chunk` (each axis at least 1), deflated.
    pub(crate) fn chunked_empty<T: H5Type>(
        g: &Group,
        name: &str,
        shape: &[usize],
        chunk: &[usize],
    ) -> hdf5::Result<Dataset> {
        // A dataset of no elements still needs a chunk of at least one.
        let chunk: Vec<usize> = chunk.iter().map(|&n| n.max(1)).collect();
        g.new_dataset_builder()
            .chunk(chunk)
            .deflate(LEVEL as u8)
            .fletcher32()
            .empty::<T>()
            .shape(shape.to_vec())
            .create(name)
    }

    /// Creates dataset `name` of `shape` in `g`, with no data yet, in chunks
    /// of `chunk` (each axis at least 1), stored as they are (no
    /// compression), checksummed.
    pub(crate) fn stored_empty<T: H5Type>(
        g: &Group,
        name: &str,
        shape: &[usize],
        chunk: &[usize],
    ) -> hdf5::Result<Dataset> {
        let chunk: Vec<usize> = chunk.iter().map(|&n| n.max(1)).collect();
        g.new_dataset_builder().chunk(chunk).fletcher32().empty::<T>().shape(shape.to_vec()).create(name)
    }

    /// `f(0), …, f(n - 1)` computed on the threads (each takes the next index
    /// as it frees), in order; on the calling thread where one would take
    /// them all (one thread, or one chunk: most datasets of a plane).
    pub(crate) fn map<R: Send + Default>(&self, n: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
        let workers = self.threads.clamp(1, n.max(1));
        if workers == 1 {
            return (0..n).map(f).collect();
        }
        let next = AtomicUsize::new(0);
        let done: Vec<Vec<(usize, R)>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..workers)
                .map(|_| {
                    scope.spawn(|| {
                        let mut mine = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            if i >= n {
                                break mine;
                            }
                            mine.push((i, f(i)));
                        }
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().expect("a compressing thread panicked")).collect()
        });
        let mut out: Vec<R> = (0..n).map(|_| R::default()).collect();
        for (i, r) in done.into_iter().flatten() {
            out[i] = r;
        }
        out
    }
}

/// One chunk of `values` as the dataset's filters (deflate, Fletcher-32)
/// write it: the zlib stream, then its checksum.
pub(crate) fn deflate<T: Copy>(values: &[T]) -> Vec<u8> {
    deflate_padded(values, values.len())
}

/// zlib compressors done with, for the next chunk to reset and use: a new
/// one allocates and zeroes its window and hash tables (some 400 KB), more
/// than most chunks hold (a plane's datasets are cut into about 32 chunks
/// each: 1.4 G of the 36.5 G instructions of a 74 × 49 atlas went to that
/// zeroing). As many as chunks were deflated at once. Shared, not one per
/// thread: the Python module, loaded by `dlopen`, has no room left for more
/// thread-local storage.
static COMPRESSORS: Mutex<Vec<Compress>> = Mutex::new(Vec::new());

/// [`deflate`] of `values` padded with zeros to `len` values.
fn deflate_padded<T: Copy>(values: &[T], len: usize) -> Vec<u8> {
    let size = std::mem::size_of::<T>();
    let bytes = bytes_of(values);
    let mut out = Vec::with_capacity(bytes.len() / 2 + 64);
    let kept = COMPRESSORS.lock().unwrap_or_else(PoisonError::into_inner).pop();
    let mut z = kept.unwrap_or_else(|| Compress::new(Compression::new(LEVEL), true));
    z.reset();
    pour(&mut z, bytes, &mut out, FlushCompress::None);
    pour(&mut z, &vec![0u8; (len - values.len()) * size], &mut out, FlushCompress::Finish);
    COMPRESSORS.lock().unwrap_or_else(PoisonError::into_inner).push(z);
    checksummed(out)
}

/// Deflates all of `input` into `out` (grown as it fills), and with
/// [`FlushCompress::Finish`] ends the stream.
fn pour(z: &mut Compress, mut input: &[u8], out: &mut Vec<u8>, flush: FlushCompress) {
    loop {
        if out.len() == out.capacity() {
            out.reserve(out.capacity().max(64));
        }
        let before = z.total_in();
        let status = z.compress_vec(input, out, flush).expect("deflating into memory");
        input = &input[(z.total_in() - before) as usize..];
        let done = match flush {
            FlushCompress::Finish => status == Status::StreamEnd,
            _ => input.is_empty(),
        };
        if done {
            return;
        }
    }
}

/// One chunk of `values` padded with zeros to `len` values, as a dataset
/// with only the Fletcher-32 filter stores it: the bytes, then their checksum.
fn stored_padded<T: Copy>(values: &[T], len: usize) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(len * std::mem::size_of::<T>() + 4);
    bytes.extend_from_slice(bytes_of(values));
    bytes.resize(len * std::mem::size_of::<T>(), 0);
    checksummed(bytes)
}

/// `bytes` followed by their Fletcher-32 checksum, little-endian: what HDF5's
/// Fletcher-32 filter appends to a chunk.
fn checksummed(mut bytes: Vec<u8>) -> Vec<u8> {
    let sum = fletcher32(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    bytes
}

/// HDF5's Fletcher-32 checksum of `data` (`H5_checksum_fletcher32`): the
/// bytes taken as big-endian 16-bit words (an odd last byte as the high byte
/// of a word), the sum of the words and the sum of their running sums, each
/// modulo 65535 as ones' complement folding leaves it (65535 for a multiple
/// of 65535 that is not 0: folding never makes a positive sum 0, and both
/// sums are 0 only for bytes that are all 0), the second in the high half.
pub(crate) fn fletcher32(data: &[u8]) -> u32 {
    const M: u64 = 65535;
    // Words per block: the sums stay far below 2^64 within one.
    const BLOCK: usize = 1 << 16;
    let (mut sum1, mut sum2, mut any) = (0u64, 0u64, 0u8);
    let (words, last) = data.split_at(data.len() & !1);
    for block in words.chunks(2 * BLOCK) {
        for w in block.chunks_exact(2) {
            any |= w[0] | w[1];
            sum1 += u64::from(w[0]) << 8 | u64::from(w[1]);
            sum2 += sum1;
        }
        sum1 %= M;
        sum2 %= M;
    }
    if let [b] = last {
        any |= b;
        sum1 += u64::from(*b) << 8;
        sum2 += sum1;
    }
    if any == 0 {
        return 0;
    }
    let fold = |s: u64| ((s + M - 1) % M + 1) as u32;
    (fold(sum2) << 16) | fold(sum1)
}

/// Writes one filtered chunk (deflated or not, checksummed) at `offset` (its
/// first element), bypassing the library's filters.
pub(crate) fn write_chunk(ds: &Dataset, offset: &[u64], bytes: &[u8]) -> hdf5::Result<()> {
    // SAFETY: the dataset is open and chunked, `offset` has its rank, and
    // `bytes` holds one whole chunk after the dataset's filters. The call is
    // made under the library's lock, and a failure brings the library's
    // error stack (with the system's error, such as a full disk).
    hdf5::h5call!(hdf5_sys::h5d::H5Dwrite_chunk(
        ds.id(),
        hdf5_sys::h5p::H5P_DEFAULT,
        0,
        offset.as_ptr(),
        bytes.len(),
        bytes.as_ptr().cast(),
    ))
    .map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{Array1, Array2, Array3};

    /// Chunks deflated on several threads read back through the library's own
    /// deflate filter as the values written: several full chunks and an edge
    /// chunk, integer and float types, one to three dimensions, and no rows.
    #[test]
    fn parallel_chunks_read_back_through_the_library() {
        let dir = crate::testing::scratch("chunked");
        let path = dir.join("chunks.h5");
        let f = hdf5::File::create(&path).unwrap();
        let z = Deflater { threads: 3, ..Default::default() };
        let a = Array2::from_shape_fn((10_000, 3), |(i, k)| (i as f64 * 0.37 + k as f64).sin());
        let b = Array3::from_shape_fn((4097, 2, 4), |(i, j, k)| (i * 7 + j * 3 + k) as u16);
        let c = Array1::from((0..5000u64).map(|i| i * i).collect::<Vec<_>>());
        let e = Array2::<f64>::zeros((0, 5));
        z.dataset(&f, "a", &a).unwrap();
        z.dataset(&f, "b", &b).unwrap();
        Deflater { threads: 1, ..Default::default() }.dataset(&f, "c", &c).unwrap();
        z.dataset(&f, "e", &e).unwrap();
        drop(f);
        let f = hdf5::File::open(&path).unwrap();
        assert_eq!(f.dataset("a").unwrap().read_2d::<f64>().unwrap(), a);
        assert_eq!(f.dataset("b").unwrap().read::<u16, ndarray::Ix3>().unwrap(), b);
        assert_eq!(f.dataset("c").unwrap().read_1d::<u64>().unwrap(), c);
        assert_eq!(f.dataset("e").unwrap().shape(), vec![0, 5]);
        let filters = f.dataset("a").unwrap().filters();
        assert!(filters.iter().any(|flt| matches!(flt, hdf5::filters::Filter::Deflate(_))), "{filters:?}");
        let filters = f.dataset("a").unwrap().filters();
        assert!(filters.iter().any(|flt| matches!(flt, hdf5::filters::Filter::Fletcher32)), "{filters:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Chunk `offset` of `ds` as stored (after the filters), and where it lies
    /// in the file.
    fn stored_chunk(ds: &Dataset, offset: &[u64]) -> (Vec<u8>, u64) {
        let (mut mask, mut addr, mut size) = (0u32, 0u64, 0u64);
        // SAFETY: an open chunked dataset, offsets of its rank, a buffer of the chunk's size.
        unsafe {
            let info =
                hdf5_sys::h5d::H5Dget_chunk_info_by_coord(ds.id(), offset.as_ptr(), &mut mask, &mut addr, &mut size);
            assert!(info >= 0);
            let mut buf = vec![0u8; size as usize];
            let read = hdf5_sys::h5d::H5Dread_chunk(
                ds.id(),
                hdf5_sys::h5p::H5P_DEFAULT,
                offset.as_ptr(),
                &mut mask,
                buf.as_mut_ptr().cast(),
            );
            assert!(read >= 0);
            assert_eq!(mask, 0, "every filter applied");
            (buf, addr)
        }
    }

    /// The Fletcher-32 sum is HDF5's: the library's own pipeline (deflate,
    /// then Fletcher-32) stores each chunk followed by [`fletcher32`] of its
    /// bytes, little-endian, and chunks written here read back through the
    /// library, which refuses one whose bytes changed in the file.
    #[test]
    fn chunks_carry_the_library_s_checksum_and_a_changed_byte_is_refused() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-fletcher-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sums.h5");
        assert_eq!(fletcher32(&[]), 0);
        // H5_checksum_fletcher32 as the library writes it, folding as it goes.
        let reference = |data: &[u8]| -> u32 {
            let (mut sum1, mut sum2) = (0u32, 0u32);
            let mut words = data.chunks_exact(2);
            loop {
                let mut n = 0;
                for w in words.by_ref().take(360) {
                    sum1 += u32::from(w[0]) << 8 | u32::from(w[1]);
                    sum2 += sum1;
                    n += 1;
                }
                if n == 0 {
                    break;
                }
                sum1 = (sum1 & 0xffff) + (sum1 >> 16);
                sum2 = (sum2 & 0xffff) + (sum2 >> 16);
            }
            if let [last] = words.remainder() {
                sum1 += u32::from(*last) << 8;
                sum2 += sum1;
                sum1 = (sum1 & 0xffff) + (sum1 >> 16);
                sum2 = (sum2 & 0xffff) + (sum2 >> 16);
            }
            sum1 = (sum1 & 0xffff) + (sum1 >> 16);
            sum2 = (sum2 & 0xffff) + (sum2 >> 16);
            (sum2 << 16) | sum1
        };
        let mut seed = 12345u64;
        for n in [0usize, 1, 2, 3, 359 * 2, 720, 721, 722, 5001, 131_072, 131_073, 400_001] {
            for kind in 0..4 {
                let data: Vec<u8> = (0..n)
                    .map(|i| match kind {
                        0 => 0,
                        1 => 0xff,
                        2 => u8::from(i % 977 == 0),
                        _ => {
                            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                            (seed >> 56) as u8
                        }
                    })
                    .collect();
                assert_eq!(fletcher32(&data), reference(&data), "{n} bytes of kind {kind}");
            }
        }
        // Odd lengths, and more than 360 words (the folding).
        for n in [1usize, 3, 719, 722, 5001] {
            let data: Vec<u8> = (0..n).map(|i| (i * 131 % 251) as u8).collect();
            let mut sum1 = 0u64;
            let mut sum2 = 0u64;
            for w in data.chunks(2) {
                sum1 = (sum1 + (u64::from(w[0]) << 8 | u64::from(*w.get(1).unwrap_or(&0)))) % 65535;
                sum2 = (sum2 + sum1) % 65535;
            }
            let f = fletcher32(&data);
            // The folded sums are the sums modulo 65535, written as 1..=65535.
            assert_eq!(u64::from(f & 0xffff) % 65535, sum1, "{n}");
            assert_eq!(u64::from(f >> 16) % 65535, sum2, "{n}");
        }
        {
            let f = hdf5::File::create(&path).unwrap();
            let a = Array2::from_shape_fn((3000, 3), |(i, k)| (i as f64 * 0.37 + k as f64).sin());
            let lib =
                f.new_dataset_builder().chunk([1000, 3]).deflate(4).fletcher32().with_data(&a).create("lib").unwrap();
            for c in 0..3u64 {
                let (bytes, _) = stored_chunk(&lib, &[c * 1000, 0]);
                let (data, sum) = bytes.split_at(bytes.len() - 4);
                assert_eq!(sum, fletcher32(data).to_le_bytes(), "chunk {c}");
            }
            let z = Deflater { threads: 2, ..Default::default() };
            z.dataset(&f, "ours", &a).unwrap();
            z.stored(&f, "plain", &a).unwrap();
        }
        let f = hdf5::File::open(&path).unwrap();
        for name in ["ours", "plain"] {
            assert_eq!(f.dataset(name).unwrap().read_2d::<f64>().unwrap()[[2999, 2]], (2999.0f64 * 0.37 + 2.0).sin());
        }
        let at: Vec<u64> = ["ours", "plain"].iter().map(|n| stored_chunk(&f.dataset(n).unwrap(), &[0, 0]).1).collect();
        drop(f);
        for (name, addr) in ["ours", "plain"].iter().zip(at) {
            let mut bytes = std::fs::read(&path).unwrap();
            bytes[addr as usize + 40] ^= 0x10;
            let bad = dir.join(format!("bad-{name}.h5"));
            std::fs::write(&bad, bytes).unwrap();
            let f = hdf5::File::open(&bad).unwrap();
            let err = f.dataset(name).unwrap().read_2d::<f64>().unwrap_err().to_string();
            assert!(err.contains("Fletcher32") || err.contains("filter"), "{name}: {err}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
