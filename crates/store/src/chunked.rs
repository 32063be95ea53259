//! Chunked, deflated datasets whose chunks are compressed on several threads.
//!
//! The HDF5 library runs its filters (deflate) on the calling thread, one
//! chunk after another: for a large atlas most of the time after the last
//! cell went there. Here the chunks of a dataset are deflated in parallel
//! (zlib streams at level 4, what HDF5's deflate filter writes and every
//! reader inflates) and handed to the library as they are, by direct chunk
//! writes (`H5Dwrite_chunk`), in chunk order from the calling thread. The data
//! read back is the same, value for value; only the compressed bytes may
//! differ from the library's own.

use flate2::write::ZlibEncoder;
use flate2::Compression;
use hdf5::{Dataset, Group, H5Type};
use std::io::Write;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Deflate level of every chunked dataset.
const LEVEL: u32 = 4;

/// Largest number of rows (first axis) of one chunk.
const CHUNK_ROWS: usize = 4096;

/// Largest size of one chunk before compression, bytes: a reader that wants
/// one cell inflates at most this much, and a large dataset has chunks for
/// every thread to deflate.
pub(crate) const CHUNK_BYTES: usize = 1 << 20;

/// Writes chunked datasets, deflating their chunks on `threads` threads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Deflater {
    /// Threads that compress (at least 1).
    pub threads: usize,
}

impl Deflater {
    /// Creates dataset `name` in `g` holding `data`, chunked by rows of the
    /// first axis (whole along the others; at most [`CHUNK_ROWS`] rows and
    /// [`CHUNK_BYTES`] bytes, at least one row) and deflated: its chunks
    /// deflated on the threads, written in order.
    pub(crate) fn dataset<T: H5Type + Copy + Send + Sync, D: ndarray::Dimension>(
        &self,
        g: &Group,
        name: &str,
        data: &ndarray::Array<T, D>,
    ) -> hdf5::Result<Dataset> {
        let shape = data.shape();
        let row_bytes = shape[1..].iter().product::<usize>() * std::mem::size_of::<T>();
        let rows = shape.first().copied().unwrap_or(1).min(CHUNK_ROWS).min((CHUNK_BYTES / row_bytes.max(1)).max(1));
        let chunk: Vec<usize> = shape.iter().enumerate().map(|(i, &n)| if i == 0 { rows } else { n }).collect();
        let ds = Deflater::chunked_empty::<T>(g, name, shape, &chunk)?;
        if data.is_empty() {
            return Ok(ds);
        }
        let flat = data.as_standard_layout();
        let flat = flat.as_slice().expect("a standard layout is contiguous");
        let per_chunk = rows * shape[1..].iter().product::<usize>();
        let pieces: Vec<&[T]> = flat.chunks(per_chunk).collect();
        let compressed = self.deflate_all(&pieces, per_chunk);
        for (c, bytes) in compressed.into_iter().enumerate() {
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
        g.new_dataset_builder().chunk(chunk).deflate(LEVEL as u8).empty::<T>().shape(shape.to_vec()).create(name)
    }

    /// The zlib streams of `pieces`, each padded with zeros to `len` values
    /// (an edge chunk is stored whole), in order.
    fn deflate_all<T: Copy + Send + Sync>(&self, pieces: &[&[T]], len: usize) -> Vec<Vec<u8>> {
        self.map(pieces.len(), |c| deflate_padded(pieces[c], len))
    }

    /// `f(0), …, f(n - 1)` computed on the threads (each takes the next index
    /// as it frees), in order.
    pub(crate) fn map<R: Send + Default>(&self, n: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
        let next = AtomicUsize::new(0);
        let workers = self.threads.clamp(1, n.max(1));
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

/// The zlib stream of `values` as bytes.
pub(crate) fn deflate<T: Copy>(values: &[T]) -> Vec<u8> {
    deflate_padded(values, values.len())
}

/// The zlib stream of `values` as bytes, padded with zeros to `len` values.
fn deflate_padded<T: Copy>(values: &[T], len: usize) -> Vec<u8> {
    let size = std::mem::size_of::<T>();
    // SAFETY: `T` is one of the plain numeric types HDF5 stores (integers and
    // floats without padding); their in-memory bytes are the file's (native)
    // representation.
    let bytes = unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), std::mem::size_of_val(values)) };
    let mut z = ZlibEncoder::new(Vec::with_capacity(bytes.len() / 2 + 64), Compression::new(LEVEL));
    z.write_all(bytes).expect("writing into memory");
    z.write_all(&vec![0u8; (len - values.len()) * size]).expect("writing into memory");
    z.finish().expect("writing into memory")
}

/// Writes one deflated chunk at `offset` (its first element), bypassing the
/// library's filters.
pub(crate) fn write_chunk(ds: &Dataset, offset: &[u64], bytes: &[u8]) -> hdf5::Result<()> {
    // SAFETY: the dataset is open and chunked, `offset` has its rank, and
    // `bytes` holds one whole chunk after the dataset's filter (deflate).
    let status = unsafe {
        hdf5_sys::h5d::H5Dwrite_chunk(
            ds.id(),
            hdf5_sys::h5p::H5P_DEFAULT,
            0,
            offset.as_ptr(),
            bytes.len(),
            bytes.as_ptr().cast(),
        )
    };
    if status < 0 {
        return Err(hdf5::Error::from(format!("direct chunk write to {} failed", ds.name()).as_str()));
    }
    Ok(())
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
        let dir = std::env::temp_dir().join(format!("vibroatlas-chunked-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("chunks.h5");
        let f = hdf5::File::create(&path).unwrap();
        let z = Deflater { threads: 3 };
        let a = Array2::from_shape_fn((10_000, 3), |(i, k)| (i as f64 * 0.37 + k as f64).sin());
        let b = Array3::from_shape_fn((4097, 2, 4), |(i, j, k)| (i * 7 + j * 3 + k) as u16);
        let c = Array1::from((0..5000u64).map(|i| i * i).collect::<Vec<_>>());
        let e = Array2::<f64>::zeros((0, 5));
        z.dataset(&f, "a", &a).unwrap();
        z.dataset(&f, "b", &b).unwrap();
        Deflater { threads: 1 }.dataset(&f, "c", &c).unwrap();
        z.dataset(&f, "e", &e).unwrap();
        drop(f);
        let f = hdf5::File::open(&path).unwrap();
        assert_eq!(f.dataset("a").unwrap().read_2d::<f64>().unwrap(), a);
        assert_eq!(f.dataset("b").unwrap().read::<u16, ndarray::Ix3>().unwrap(), b);
        assert_eq!(f.dataset("c").unwrap().read_1d::<u64>().unwrap(), c);
        assert_eq!(f.dataset("e").unwrap().shape(), vec![0, 5]);
        let filters = f.dataset("a").unwrap().filters();
        assert!(filters.iter().any(|flt| matches!(flt, hdf5::filters::Filter::Deflate(_))), "{filters:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
