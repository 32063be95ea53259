//! The per-cell datasets of a sweep's group (each mass's n-p-q, class, flags,
//! symmetry, exponent, multiplier, final state, work counters): one list of
//! them, how each is created and how a cell fills it, cut into chunks of
//! whole lines so that a chunk can be written as soon as its lines are done.

use crate::checksum::bytes_of;
use crate::chunked::{deflate, Deflater, CHUNK_BYTES};
use crate::layout::*;
use crate::netcdf;
use hdf5::{Dataset, Group, H5Type};
use maps::{Along, CellData, Meta, Number, Plane};

/// Chunks a run of about this many per plane: the file's part left for the
/// end of a run is about one chunk per dataset (fewer chunks, more of it;
/// more chunks, more per-chunk overhead in the file).
const CHUNKS_PER_PLANE: usize = 32;

/// How the per-cell datasets of a plane are cut into chunks: blocks of whole
/// lines (rows; columns with along = y), the same for every dataset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Chunks {
    along: Along,
    nx: usize,
    ny: usize,
    /// Lines per chunk (the last chunk may hold fewer).
    lines_per_chunk: usize,
    lines: usize,
}

impl Chunks {
    /// The chunks of `plane` whose largest dataset holds `cell_bytes` per cell.
    pub(crate) fn new(plane: &Plane, cell_bytes: usize) -> Chunks {
        let (lines, line_len) = (plane.lines(), plane.line_len());
        let most = (CHUNK_BYTES / (line_len * cell_bytes).max(1)).max(1);
        let lines_per_chunk = lines.div_ceil(CHUNKS_PER_PLANE).clamp(1, most);
        Chunks { along: plane.along, nx: plane.x.count, ny: plane.y.count, lines_per_chunk, lines }
    }

    /// Number of chunks.
    pub(crate) fn count(&self) -> usize {
        self.lines.div_ceil(self.lines_per_chunk)
    }

    /// The chunk holding `line`.
    pub(crate) fn of_line(&self, line: usize) -> usize {
        line / self.lines_per_chunk
    }

    /// Lines in chunk `c`.
    pub(crate) fn lines_in(&self, c: usize) -> usize {
        self.lines_per_chunk.min(self.lines - c * self.lines_per_chunk)
    }

    /// Shape of a chunk over the plane, `[rows, columns]`.
    fn shape(&self) -> [usize; 2] {
        match self.along {
            Along::X => [self.lines_per_chunk, self.nx],
            Along::Y => [self.ny, self.lines_per_chunk],
        }
    }

    /// `(iy, ix)` of the first cell of chunk `c`.
    fn origin(&self, c: usize) -> (usize, usize) {
        match self.along {
            Along::X => (c * self.lines_per_chunk, 0),
            Along::Y => (0, c * self.lines_per_chunk),
        }
    }

    /// The values of chunk `c`, `per` to a cell, in the dataset's order (the
    /// chunk stored whole: cells beyond the plane's edge take `f(None, k)`).
    fn values<T>(
        &self,
        cells: &[Option<CellData>],
        c: usize,
        per: usize,
        f: impl Fn(Option<&CellData>, usize) -> T,
    ) -> Vec<T> {
        let [h, w] = self.shape();
        let (y0, x0) = self.origin(c);
        let mut v = Vec::with_capacity(h * w * per);
        for iy in y0..y0 + h {
            for ix in x0..x0 + w {
                let cell = if iy < self.ny && ix < self.nx { cells[iy * self.nx + ix].as_ref() } else { None };
                v.extend((0..per).map(|k| f(cell, k)));
            }
        }
        v
    }
}

/// The coordinate variables a per-cell dataset is attached to.
pub(crate) struct Scales<'a> {
    pub y: &'a Dataset,
    pub x: &'a Dataset,
    pub npq: &'a Dataset,
    pub component: &'a Dataset,
}

/// One per-cell dataset of a sweep's group.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Field {
    /// n, p, q of the label of mass `k` (u16; [`STUCK`] for S, 0 where not computed).
    Npq(usize),
    /// Class code (u8; [`NOT_COMPUTED`] where not computed).
    Class,
    /// Chatter and sticking bits per stop (u8 up to 4 stops, else u32).
    Flags,
    /// Symmetry code (u8).
    Symmetry,
    /// A number per cell: the largest Lyapunov exponent per unit time, the
    /// largest Floquet multiplier modulus, or a quantity of the steady
    /// motion ([`Meta::quantities`]) (f64, NaN: none).
    Number(Number),
    /// State at the end of the record (f64, `dim` per cell).
    FinalState,
    /// Forcing periods simulated (u64).
    Periods,
    /// Events handled (u64).
    Events,
}

impl Field {
    /// Every per-cell dataset of an atlas of `m`, in the file's order.
    pub(crate) fn all(m: &Meta) -> Vec<Field> {
        let masses = (0..m.masses.len()).map(Field::Npq);
        masses
            .chain([
                Field::Class,
                Field::Flags,
                Field::Symmetry,
                Field::Number(Number::Lyapunov),
                Field::Number(Number::Multiplier),
                Field::FinalState,
                Field::Periods,
                Field::Events,
            ])
            .chain((0..m.quantities.len()).map(|k| Field::Number(Number::Quantity(k))))
            .collect()
    }

    /// Bytes per cell of the largest per-cell dataset of `m`.
    pub(crate) fn most_cell_bytes(m: &Meta) -> usize {
        (8 * m.dim).max(8)
    }

    /// The dataset's name.
    pub(crate) fn name(self, m: &Meta) -> String {
        match self {
            Field::Npq(k) => label(&m.masses[k]),
            Field::Class => var::CLASS.into(),
            Field::Flags => var::FLAGS.into(),
            Field::Symmetry => var::SYMMETRY.into(),
            Field::Number(n) => n.name(m).into(),
            Field::FinalState => var::FINAL_STATE.into(),
            Field::Periods => var::PERIODS.into(),
            Field::Events => var::EVENTS.into(),
        }
    }

    /// Whether the flags of `m` fit in a byte (at most 4 stops: 4 chatter
    /// bits, 4 sticking bits).
    fn narrow_flags(m: &Meta) -> bool {
        m.stops.len() <= 4
    }

    /// The empty `flags` dataset: a byte per cell up to 4 stops, else a u32,
    /// with its CF flag masks and meanings.
    fn create_flags(g: &Group, name: &str, m: &Meta, plane: &[usize], chunk: &[usize]) -> hdf5::Result<Dataset> {
        let (masks, meanings) = flag_masks(&m.stops, sticking_shift(m.stops.len()));
        let d = if Field::narrow_flags(m) {
            let d = Deflater::chunked_empty::<u8>(g, name, plane, chunk)?;
            netcdf::attr_array(&d, "flag_masks", &masks.iter().map(|&v| v as u8).collect::<Vec<_>>())?;
            d
        } else {
            let d = Deflater::chunked_empty::<u32>(g, name, plane, chunk)?;
            netcdf::attr_array(&d, "flag_masks", &masks)?;
            d
        };
        netcdf::attr_str(&d, "flag_meanings", &meanings)?;
        netcdf::attr_str(&d, "bits", &flag_bits(&m.stops))?;
        Ok(d)
    }

    /// The `(y, x, 3)` dataset of `mass`'s labels' n, p, q.
    fn create_npq(
        g: &Group,
        name: &str,
        mass: &str,
        shape: [usize; 3],
        chunk: [usize; 3],
        s: &Scales,
    ) -> hdf5::Result<Dataset> {
        let d = Deflater::chunked_empty::<u16>(g, name, &shape, &chunk)?;
        netcdf::dims(&d, &[s.y, s.x, s.npq])?;
        netcdf::attr_str(&d, "long_name", &format!("n, p, q of {mass}'s label ({STUCK} = S, the mass sticks)"))?;
        netcdf::attr_str(&d, "units", "1")?;
        netcdf::attr_str(&d, "dims", "y, x, (n, p, q)")?;
        netcdf::attr_num(&d, "stuck_code", STUCK)?;
        Ok(d)
    }

    /// Creates the dataset in `g`, empty, chunked by `chunks` and deflated,
    /// with its dimensions and attributes.
    pub(crate) fn create(self, g: &Group, m: &Meta, chunks: &Chunks, s: &Scales) -> hdf5::Result<Dataset> {
        let name = self.name(m);
        let (ny, nx) = (m.plane.y.count, m.plane.x.count);
        let [h, w] = chunks.shape();
        let (plane, chunk) = ([ny, nx], [h, w]);
        let gridded = |d: &Dataset, long_name: &str| -> hdf5::Result<()> {
            netcdf::dims(d, &[s.y, s.x])?;
            netcdf::describe(d, long_name, "1")
        };
        let d = match self {
            Field::Npq(k) => Field::create_npq(g, &name, &m.masses[k], [ny, nx, 3], [h, w, 3], s)?,
            Field::Class => {
                let d = Deflater::chunked_empty::<u8>(g, &name, &plane, &chunk)?;
                gridded(&d, "kind of steady motion")?;
                netcdf::attr_str(&d, "codes", CLASS_CODES)?;
                netcdf::attr_array(&d, "flag_values", &[0u8, 1, 2, 3])?;
                netcdf::attr_str(&d, "flag_meanings", "periodic chaotic unresolved quasiperiodic")?;
                netcdf::attr_num(&d, "_FillValue", NOT_COMPUTED)?;
                d
            }
            Field::Flags => {
                let d = Field::create_flags(g, &name, m, &plane, &chunk)?;
                gridded(&d, "chattering and sticking at each stop (bit flags)")?;
                d
            }
            Field::Symmetry => {
                let d = Deflater::chunked_empty::<u8>(g, &name, &plane, &chunk)?;
                gridded(&d, "mirror symmetry of the periodic orbit (symmetric scenes)")?;
                netcdf::attr_str(&d, "codes", SYMMETRY_CODES)?;
                netcdf::attr_array(&d, "flag_values", &[0u8, 1, 2])?;
                netcdf::attr_str(&d, "flag_meanings", "none symmetric asymmetric")?;
                d
            }
            Field::FinalState => {
                let shape = [ny, nx, m.dim];
                let d = Deflater::chunked_empty::<f64>(g, &name, &shape, &[h, w, m.dim])?;
                netcdf::dims(&d, &[s.y, s.x, s.component])?;
                netcdf::describe(&d, "state at the end of the cell's record (a whole number of forcing periods)", "1")?;
                netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
                d
            }
            Field::Periods => {
                let d = Deflater::chunked_empty::<u64>(g, &name, &plane, &chunk)?;
                gridded(&d, "forcing periods simulated")?;
                d
            }
            Field::Events => {
                let d = Deflater::chunked_empty::<u64>(g, &name, &plane, &chunk)?;
                gridded(&d, "events handled")?;
                d
            }
            Field::Number(n) => {
                let d = Deflater::chunked_empty::<f64>(g, &name, &plane, &chunk)?;
                netcdf::dims(&d, &[s.y, s.x])?;
                netcdf::describe(&d, n.long_name(m), n.units(m))?;
                netcdf::attr_str(&d, "symbol", n.symbol(m))?;
                netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
                if !n.of_motion() {
                    let meaning = format!("{}; NaN: none", n.long_name(m));
                    netcdf::attr_str(&d, "meaning", &meaning)?;
                }
                d
            }
        };
        Ok(d)
    }

    /// What `to` makes of the dataset's values for `m`: the number of values
    /// per cell and each value of a cell (`None`: not computed).
    fn encode<E: Encode>(self, m: &Meta, to: E) -> E::Out {
        match self {
            Field::Npq(k) => to.values(3, |e, i| e.map_or(0, |e| npq_code(e.labels[k])[i])),
            Field::Class => to.values(1, |e, _| e.map_or(NOT_COMPUTED, |e| class_code(e.class))),
            Field::Flags => {
                let word = |e: Option<&CellData>| e.map_or(0u32, |e| flags_code(e.chatter, e.sticking, m.stops.len()));
                if Field::narrow_flags(m) {
                    to.values(1, |e, _| word(e) as u8)
                } else {
                    to.values(1, |e, _| word(e))
                }
            }
            Field::Symmetry => to.values(1, |e, _| e.map_or(0, |e| symmetry_code(e.symmetry))),
            Field::Number(n) => to.values(1, |e, _| e.map_or(f64::NAN, |e| n.stored(e))),
            Field::FinalState => to.values(m.dim, |e, k| e.map_or(f64::NAN, |e| e.final_state[k])),
            Field::Periods => to.values(1, |e, _| e.map_or(0, |e| e.periods)),
            Field::Events => to.values(1, |e, _| e.map_or(0, |e| e.events)),
        }
    }

    /// Chunk `c` of the dataset for `cells` (a sweep's `ny × nx` cells,
    /// row-major; `None`: not computed), deflated and checksummed.
    pub(crate) fn chunk(self, m: &Meta, chunks: &Chunks, cells: &[Option<CellData>], c: usize) -> Vec<u8> {
        self.encode(m, ChunkOf { chunks, cells, c })
    }

    /// Whether `ds`, read through the library's filters, holds the dataset
    /// of `cells`, bit for bit.
    /// The dataset `ds` of the file compared with the values of `cells`:
    /// the [`crate::checksum::values_crc32`] of what it read where equal.
    pub(crate) fn compare(self, m: &Meta, ds: &Dataset, cells: &[Option<CellData>]) -> hdf5::Result<Option<u32>> {
        self.encode(m, Compare { ds, cells })
    }
}

/// Makes something of a per-cell dataset's values ([`Field::encode`]).
trait Encode {
    type Out;
    /// `per` values to a cell, value `k` of a cell `f(cell, k)`.
    fn values<T: H5Type + Copy>(self, per: usize, f: impl Fn(Option<&CellData>, usize) -> T) -> Self::Out;
}

/// One chunk, deflated and checksummed.
struct ChunkOf<'a> {
    chunks: &'a Chunks,
    cells: &'a [Option<CellData>],
    c: usize,
}

impl Encode for ChunkOf<'_> {
    type Out = Vec<u8>;
    fn values<T: H5Type + Copy>(self, per: usize, f: impl Fn(Option<&CellData>, usize) -> T) -> Vec<u8> {
        deflate(&self.chunks.values(self.cells, self.c, per, f))
    }
}

/// The whole dataset compared with a dataset of the file.
struct Compare<'a> {
    ds: &'a Dataset,
    cells: &'a [Option<CellData>],
}

impl Encode for Compare<'_> {
    type Out = hdf5::Result<Option<u32>>;
    fn values<T: H5Type + Copy>(
        self,
        per: usize,
        f: impl Fn(Option<&CellData>, usize) -> T,
    ) -> hdf5::Result<Option<u32>> {
        let read = self.ds.read_raw::<T>()?;
        let same = read.len() == self.cells.len() * per
            && read.chunks(per.max(1)).zip(self.cells).all(|(r, cell)| {
                r.iter().enumerate().all(|(k, v)| bytes_of(std::slice::from_ref(v)) == bytes_of(&[f(cell.as_ref(), k)]))
            });
        Ok(same.then(|| crate::checksum::values_crc32(&self.ds.name(), bytes_of(&read))))
    }
}

/// CF flag masks and meanings of the flags dataset.
fn flag_masks(stops: &[String], shift: u32) -> (Vec<u32>, String) {
    let chatter = stops.iter().enumerate().map(|(k, s)| (1u32 << k, format!("{s}_chatters")));
    let stick = stops.iter().enumerate().map(|(k, s)| (1u32 << (k as u32 + shift), format!("{s}_sticks")));
    let (masks, names): (Vec<u32>, Vec<String>) = chatter.chain(stick).unzip();
    (masks, names.join(" "))
}

/// Writes filtered chunk `c` of a dataset of `chunks` (its first element at
/// the chunk's origin), bypassing the library's filters.
pub(crate) fn write(ds: &Dataset, chunks: &Chunks, c: usize, bytes: &[u8]) -> hdf5::Result<()> {
    let (iy, ix) = chunks.origin(c);
    let mut offset = vec![iy as u64, ix as u64];
    offset.resize(ds.ndim(), 0);
    crate::chunked::write_chunk(ds, &offset, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use maps::Axis;

    fn plane(nx: usize, ny: usize, along: Along) -> Plane {
        let x = Axis::parse(&format!("omega=0.1:3:{nx}"), "x").unwrap();
        let y = Axis::parse(&format!("delta=0.1:2:{ny}"), "y").unwrap();
        Plane::new(x, y, along).unwrap()
    }

    /// Chunks are blocks of whole lines covering every line once, about
    /// [`CHUNKS_PER_PLANE`] of them, each at most [`CHUNK_BYTES`].
    #[test]
    fn chunks_are_blocks_of_whole_lines() {
        for (p, bytes) in [
            (plane(96, 96, Along::X), 32),
            (plane(37, 20, Along::Y), 32),
            (plane(5, 3, Along::X), 8),
            (plane(1000, 1000, Along::X), 32),
            (plane(40_000, 70, Along::Y), 8),
        ] {
            let c = Chunks::new(&p, bytes);
            let mut seen = vec![0usize; p.lines()];
            for k in 0..c.count() {
                let first = (0..p.lines()).find(|&l| c.of_line(l) == k).unwrap();
                let n = (0..p.lines()).filter(|&l| c.of_line(l) == k).count();
                assert_eq!(n, c.lines_in(k), "chunk {k} of {p:?}");
                for s in seen.iter_mut().skip(first).take(n) {
                    *s += 1;
                }
                // The chunk's origin is its first line's first cell.
                assert_eq!(c.origin(k), p.cell(first, 0));
            }
            assert!(seen.iter().all(|&s| s == 1), "{p:?}");
            let [h, w] = c.shape();
            assert!(h * w * bytes <= CHUNK_BYTES || c.lines_per_chunk == 1, "{p:?}");
            assert!([h, w].contains(&p.line_len()), "a chunk holds whole lines");
            assert!(c.count() <= CHUNKS_PER_PLANE.max(p.lines().div_ceil(c.lines_per_chunk)));
        }
        // 1000 lines of 32 kB: 32 lines (1 MiB) to a chunk; 96 lines: 3.
        assert_eq!(Chunks::new(&plane(1000, 1000, Along::X), 32).lines_per_chunk, 32);
        assert_eq!(Chunks::new(&plane(96, 96, Along::X), 32).lines_per_chunk, 3);
    }

    /// A chunk's values run row-major over its block, `per` to a cell, cells
    /// beyond the plane's edge taken as not computed.
    #[test]
    fn chunk_values_follow_the_block() {
        let (nx, ny) = (4, 5);
        let p = plane(nx, ny, Along::Y);
        let c = Chunks { lines_per_chunk: 3, ..Chunks::new(&p, 8) };
        let cell = |i: usize| CellData {
            class: solver::Class::Chaotic,
            labels: Vec::new(),
            chatter: Default::default(),
            sticking: Default::default(),
            symmetry: None,
            lyapunov: None,
            multiplier: None,
            final_state: Vec::new(),
            periods: i as u64,
            events: 0,
            period_section: solver::Points::default(),
            impact_sections: Vec::new(),
            reason: None,
            quantities: Vec::new(),
        };
        // Every cell but (2, 3) computed; its periods are its index iy*nx + ix.
        let cells: Vec<Option<CellData>> = (0..nx * ny).map(|i| (i != 2 * nx + 3).then(|| cell(i))).collect();
        // Chunk 1 holds columns 3..6 of the 4 columns: 4 and 5 lie beyond the edge.
        assert_eq!(c.origin(1), (0, 3));
        let v = c.values(&cells, 1, 2, |e, k| e.map_or(-1, |e| 10 * e.periods as i64 + k as i64));
        assert_eq!(v.len(), ny * 3 * 2);
        for iy in 0..ny {
            let row = &v[iy * 6..iy * 6 + 6];
            let own = if iy == 2 { [-1, -1] } else { [10 * (iy * nx + 3) as i64, 10 * (iy * nx + 3) as i64 + 1] };
            assert_eq!(row, &[own[0], own[1], -1, -1, -1, -1], "row {iy}");
        }
    }
}
