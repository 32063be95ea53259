//! Writing an atlas to HDF5 (see [`crate::layout`]): to a temporary file in the
//! target folder, renamed over the final name only once complete, so a crash
//! never leaves a half-written file under the final name.

use crate::chunked::Deflater;
use crate::error::StoreError;
use crate::fields::{self, Chunks, Field};
use crate::layout::*;
use crate::lock::partial_path;
use crate::netcdf::{self, attr_array, attr_num, attr_str};
use hdf5::Group;
use maps::{palette, Atlas};
use ndarray::{Array1, Array2, Array3};
use scene::Named;
use solver::{Count, Label};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// Run information written as root attributes.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// Command line that produced the file.
    pub command: String,
    /// Wall time of the computation, seconds.
    pub run_time_s: f64,
    /// Shard of a partial file.
    pub shard: Option<maps::Shard>,
    /// Earlier history lines (`TIME: command`, oldest first): those of the
    /// parts of a merge; the file adds its own.
    pub history: Vec<String>,
    /// The atlas a zoom computed a box of.
    pub parent: Option<Parent>,
}

/// The atlas a zoom refines (root attributes `parent`, `parent_labels_crc32`
/// and `parent_box`).
#[derive(Debug, Clone, PartialEq)]
pub struct Parent {
    /// The parent file, as given.
    pub path: String,
    /// [`labels_crc32`] of the parent's atlas: which parent's labels the box
    /// refines, even once the file is moved or replaced.
    pub labels_crc32: u32,
    /// The box: its two axes, `omega=0.6:1.2:61 delta=0.05:2:196`.
    pub region: String,
}

/// The CRC-32 of an atlas's labels: per sweep in order, per cell row-major,
/// its class name and each labelled mass's label (`-` for a cell not
/// computed), each text its byte length (u64, little-endian) then its bytes.
pub fn labels_crc32(atlas: &Atlas) -> u32 {
    let texts = atlas.maps.iter().flat_map(|m| m.cells.iter()).flat_map(|c| match c {
        Some(c) => std::iter::once(c.class.name().to_string()).chain(c.labels.iter().map(|l| l.to_string())).collect(),
        None => vec!["-".to_string()],
    });
    let texts: Vec<String> = texts.collect();
    netcdf::texts_crc32(texts.iter().map(|t| t.as_bytes()))
}

/// The git commit the binary was built from (`unknown` outside a checkout).
pub const GIT_COMMIT: &str = env!("VIBROATLAS_GIT_COMMIT");

/// Writes `atlas` to `path` (atomically, through a temporary file), its
/// datasets' chunks compressed on `threads` threads: a [`Draft`] created and
/// finished at once.
pub fn write(path: &Path, atlas: &Atlas, info: &RunInfo, threads: usize) -> Result<(), StoreError> {
    Draft::create(path, &atlas.meta, threads)?.finish(atlas, info)
}

/// An atlas file being written while its cells compute.
///
/// [`Draft::create`] writes into a temporary file beside `path` (see
/// [`partial_path`]) everything that depends only on the run's set-up: the
/// scene, accuracy and parameter attributes, the axes, and per sweep its
/// coordinates, dimensions and per-cell datasets (created empty, chunked by
/// whole lines and deflated, with their attributes). [`Draft::keep`] takes
/// each line as it is computed and writes, compressed, every chunk whose
/// lines are all kept. [`Draft::finish`] writes the rest (chunks of lines not
/// kept, label tables and codes, sections, legend, hysteresis, attractors,
/// the run's command and time) and renames the file over `path`. A draft
/// dropped unfinished removes its temporary file: a failed run never leaves
/// a half-written file under the final name.
pub struct Draft {
    path: PathBuf,
    tmp: PathBuf,
    /// Open while unfinished.
    file: Option<hdf5::File>,
    meta: maps::Meta,
    z: Deflater,
    chunks: Chunks,
    /// Per sweep, in the order of `meta.sweeps`.
    sweeps: Vec<Progress>,
    committed: bool,
}

/// How far the per-cell datasets of one sweep are written.
struct Progress {
    datasets: Vec<(Field, hdf5::Dataset)>,
    /// Lines kept.
    line_kept: Vec<bool>,
    /// Lines kept, per chunk (a chunk is written once all its lines are).
    kept: Vec<usize>,
}

impl Draft {
    /// Creates the temporary file of an atlas of `meta` to be written to
    /// `path`, compressing on `threads` threads at the end.
    pub fn create(path: &Path, meta: &maps::Meta, threads: usize) -> Result<Draft, StoreError> {
        crate::lock::check_folder(path)?;
        let chunks = Chunks::new(&meta.plane, Field::most_cell_bytes(meta));
        let mut draft = Draft {
            path: path.to_path_buf(),
            tmp: partial_path(path),
            file: None,
            meta: meta.clone(),
            z: Deflater { threads, ..Default::default() },
            chunks,
            sweeps: Vec::new(),
            committed: false,
        };
        // On failure the draft is dropped, which removes what was created.
        let (file, datasets) =
            create_file(&draft.tmp, meta, &chunks, &draft.z).map_err(|e| StoreError::hdf5(path, e))?;
        draft.file = Some(file);
        draft.sweeps = datasets
            .into_iter()
            .map(|datasets| Progress {
                datasets,
                line_kept: vec![false; meta.plane.lines()],
                kept: vec![0; chunks.count()],
            })
            .collect();
        Ok(draft)
    }

    /// Takes `line` of `sweep`, complete in `atlas` (whose set-up must be the
    /// draft's): writes the chunks of the per-cell datasets that it completes.
    /// A line kept twice is kept once.
    pub fn keep(&mut self, atlas: &Atlas, sweep: maps::SweepKind, line: usize) -> Result<(), StoreError> {
        let (Some(s), Some(map)) = (self.meta.sweeps.iter().position(|&k| k == sweep), atlas.map(sweep)) else {
            return Ok(());
        };
        let p = &mut self.sweeps[s];
        if p.line_kept.get(line) != Some(&false) {
            return Ok(());
        }
        p.line_kept[line] = true;
        let c = self.chunks.of_line(line);
        p.kept[c] += 1;
        if p.kept[c] == self.chunks.lines_in(c) {
            for (field, ds) in &p.datasets {
                let bytes = field.chunk(&self.meta, &self.chunks, &map.cells, c);
                fields::write(ds, &self.chunks, c, &bytes).map_err(|e| StoreError::hdf5(&self.path, e))?;
            }
        }
        Ok(())
    }

    /// Writes the rest of `atlas` (whose set-up must be the draft's) and the
    /// run's `info`, reads the file back (the store's `verify` module: every dataset
    /// through the library's filters, compared with what was written), then
    /// renames it over the target. A file that does not read back as written
    /// is [`StoreError::Unverified`], and nothing is renamed.
    pub fn finish(mut self, atlas: &Atlas, info: &RunInfo) -> Result<(), StoreError> {
        if atlas.meta != self.meta {
            return Err(StoreError::format(&self.path, "the atlas is not of the set-up the file was created for"));
        }
        let f = self.file.take().expect("an unfinished draft holds its file");
        self.remaining_chunks(atlas).map_err(|e| StoreError::hdf5(&self.path, e))?;
        fill_file(&f, atlas, info, &self.z).map_err(|e| StoreError::hdf5(&self.path, e))?;
        // Closing the file writes what the library still holds; the datasets
        // are closed first.
        self.sweeps.clear();
        drop(f);
        // The file's data goes to the disk while it is read back (from the
        // page cache): the sync before the rename then finds little to write.
        std::thread::scope(|s| {
            s.spawn(|| std::fs::File::open(&self.tmp).and_then(|f| f.sync_data()));
            crate::verify::file_sealed(&self.tmp, &self.path, atlas, &self.z.expected)
        })?;
        crate::commit(&self.tmp, &self.path)?;
        self.committed = true;
        Ok(())
    }

    /// The chunks of the per-cell datasets not written by [`Draft::keep`]
    /// (lines computed before, or not computed), compressed on the threads.
    fn remaining_chunks(&self, atlas: &Atlas) -> hdf5::Result<()> {
        let datasets: Vec<&[(Field, hdf5::Dataset)]> = self.sweeps.iter().map(|p| p.datasets.as_slice()).collect();
        let left = |s: usize, c: usize| self.sweeps[s].kept[c] < self.chunks.lines_in(c);
        write_chunks(&self.z, &self.chunks, atlas, &datasets, left)
    }
}

/// Writes the chunks `c` of sweep `s` for which `todo(s, c)` holds of the
/// per-cell datasets of each sweep of `atlas` (`datasets`, in the atlas's
/// sweep order), compressed on the deflater's threads.
fn write_chunks(
    z: &Deflater,
    chunks: &Chunks,
    atlas: &Atlas,
    datasets: &[&[(Field, hdf5::Dataset)]],
    todo: impl Fn(usize, usize) -> bool,
) -> hdf5::Result<()> {
    for (s, (map, sweep)) in atlas.maps.iter().zip(datasets).enumerate() {
        let todo: Vec<(&(Field, hdf5::Dataset), usize)> =
            sweep.iter().flat_map(|d| (0..chunks.count()).filter(|&c| todo(s, c)).map(move |c| (d, c))).collect();
        let bytes = z.map(todo.len(), |i| todo[i].0 .0.chunk(&atlas.meta, chunks, &map.cells, todo[i].1));
        for (((_, ds), c), b) in todo.iter().zip(bytes) {
            fields::write(ds, chunks, *c, &b)?;
        }
    }
    Ok(())
}

/// The atlas file of `atlas` and the run's `info`, written in memory (HDF5's
/// core driver: nothing on disk) on `threads` threads, read back and sealed
/// as [`Draft::finish`] reads back and seals a file, as the file's bytes:
/// what a reader of bytes (h5py, xarray through h5netcdf) opens as it opens
/// the file that [`Draft`] would write. Errors name the file `(in memory)`.
pub fn image(atlas: &Atlas, info: &RunInfo, threads: usize) -> Result<Vec<u8>, StoreError> {
    let here = Path::new("(in memory)");
    let z = Deflater { threads, ..Default::default() };
    let chunks = Chunks::new(&atlas.meta.plane, Field::most_cell_bytes(&atlas.meta));
    let written = || -> hdf5::Result<hdf5::File> {
        let (f, datasets) = in_memory(atlas, info, &chunks, &z)?;
        let sweeps: Vec<&[(Field, hdf5::Dataset)]> = datasets.iter().map(Vec::as_slice).collect();
        write_chunks(&z, &chunks, atlas, &sweeps, |_, _| true)?;
        Ok(f)
    };
    let f = written().map_err(|e| StoreError::hdf5(here, e))?;
    let crcs = crate::verify::datasets(&f, here, atlas, &z.expected)?;
    crate::verify::seal_in(&f, here, &crcs)?;
    crate::netcdf::file_image(&f).map_err(|e| StoreError::hdf5(here, e))
}

/// A new file held in memory by HDF5's core driver (nothing on disk) with
/// everything vibroatlas writes for `atlas` and the run's `info` but the
/// chunks of the per-cell datasets, which are created empty and returned.
/// In the oldest format that holds the file, not 1.10's as on disk: HDF5
/// 1.10's image of a file of format 1.10 (or 1.8) carries a superblock whose
/// checksum does not match ("incorrect metadata checksum" on open; Debian's
/// 1.10.8, through this crate and through h5py alike).
fn in_memory(atlas: &Atlas, info: &RunInfo, chunks: &Chunks, z: &Deflater) -> hdf5::Result<Created> {
    static FILES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = FILES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    // The core driver's name: no file of that name is created or read.
    let name = std::env::temp_dir().join(format!("vibroatlas-memory-{}-{k}.h5", std::process::id()));
    let f = hdf5::File::with_options().with_fapl(|p| p.core_filebacked(false).libver_earliest()).create(&name)?;
    let (f, datasets) = create_in(f, &atlas.meta, chunks, z)?;
    fill_file(&f, atlas, info, z)?;
    Ok((f, datasets))
}

/// Checks a finished atlas file as [`Draft::finish`] checks the file it
/// wrote before renaming it: the file `path`, `loaded` from it, is written
/// again into memory (nothing on disk) to learn what each of its datasets
/// must hold (its stored scene must parse and take its overrides at the
/// plane's four corners), then every dataset of the file is read through
/// the library's filters and compared (the per-cell datasets with the cells,
/// every other one with a hash of what the writer would write). A dataset
/// that does not read (a damaged object header, chunk index or checksum) or
/// reads other values is one [`StoreError::Dataset`] naming it. Curves
/// stored in the file are read, their checksum compared.
pub fn check_finished(path: &Path, loaded: &crate::Loaded) -> Result<(), StoreError> {
    verified(path, loaded).map(drop)
}

/// The scene an atlas `path` (its `meta` read) was computed with, parsed,
/// and evaluated as the run evaluated it: with its overrides, at the plane's
/// four corners. A scene no run could have computed the plane with (one that
/// does not parse, or whose parameters leave their ranges on the plane) is
/// one error naming the attribute: a run from the file would compute cells
/// that are not the file's, or none.
pub fn scene_of_run(path: &Path, m: &maps::Meta) -> Result<scene::Scene, StoreError> {
    let (x, y) = (&m.plane.x, &m.plane.y);
    let corners = [(x.start, y.start), (x.start, y.stop), (x.stop, y.start), (x.stop, y.stop)];
    scene::Scene::parse(&m.scene_toml)
        .and_then(|s| {
            corners.iter().try_for_each(|&(a, b)| {
                let mut at = m.overrides.clone();
                at.extend([(x.name.clone(), a), (y.name.clone(), b)]);
                s.evaluate(&at).map(drop)
            })?;
            Ok(s)
        })
        .map_err(|e| {
            StoreError::format(path, format!("attribute {}: not the scene of a run ({e})", crate::layout::attr::SCENE))
        })
}

/// [`check_finished`], saying whether the file holds curves (`curves --into`).
pub(crate) fn verified(path: &Path, loaded: &crate::Loaded) -> Result<bool, StoreError> {
    let atlas = &loaded.atlas;
    scene_of_run(path, &atlas.meta)?;
    let z = Deflater { threads: 1, ..Default::default() };
    let chunks = Chunks::new(&atlas.meta.plane, Field::most_cell_bytes(&atlas.meta));
    let (written, _) = in_memory(atlas, &loaded.info, &chunks, &z).map_err(|e| StoreError::hdf5(path, e))?;
    let actual = crate::heap::open(path)?;
    crate::verify::attributes(&written, &actual, path)?;
    let curves = crate::curve::held(path, &actual)?;
    drop((written, actual));
    crate::verify::file(path, path, atlas, &z.expected).map(drop).map_err(|e| match e {
        StoreError::Unverified { path, dataset, message } => StoreError::Dataset { path, dataset, message },
        e => e,
    })?;
    // Curves stored in the atlas (`curves --into`) carry their own checksum.
    if curves {
        crate::curve::read_curves(path)?;
    }
    Ok(curves)
}

impl Drop for Draft {
    fn drop(&mut self) {
        if !self.committed {
            // Datasets and file closed before the file is removed.
            self.sweeps.clear();
            drop(self.file.take());
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The file of [`Draft::create`]: what depends only on `m`; and per sweep
/// its per-cell datasets.
type Created = (hdf5::File, Vec<Vec<(Field, hdf5::Dataset)>>);

fn create_file(path: &Path, m: &maps::Meta, chunks: &Chunks, z: &Deflater) -> hdf5::Result<Created> {
    create_in(crate::netcdf::create_file(path)?, m, chunks, z)
}

/// [`create_file`] into the file `f`, new.
fn create_in(f: hdf5::File, m: &maps::Meta, chunks: &Chunks, z: &Deflater) -> hdf5::Result<Created> {
    let p = &m.plane;
    attr_str(&f, attr::CONVENTIONS, "CF-1.8")?;
    attr_str(&f, "title", &format!("vibroatlas map of the {} scene over ({}, {})", m.scene_name, p.x.name, p.y.name))?;
    attr_str(&f, "source", &format!("vibroatlas {} (git {})", env!("CARGO_PKG_VERSION"), GIT_COMMIT))?;
    attr_str(&f, attr::SOFTWARE, SOFTWARE)?;
    attr_str(&f, "version", env!("CARGO_PKG_VERSION"))?;
    attr_str(&f, "git_commit", GIT_COMMIT)?;
    // Layout 4 only where its one addition is used: an axis on a lattice.
    let lattice = p.x.lattice.is_some() || p.y.lattice.is_some();
    attr_num(&f, attr::LAYOUT_VERSION, if lattice { LAYOUT_VERSION } else { 3 })?;
    attr_str(&f, attr::SCENE, &m.scene_toml)?;
    attr_str(&f, attr::SCENE_NAME, &m.scene_name)?;
    attr_str(&f, attr::PRESET, m.preset.name())?;
    attr_str(&f, attr::ACCURACY, &pairs(&m.accuracy))?;
    attr_str(&f, "knobs", &knobs(m))?;
    attr_str(&f, attr::INTEGRATOR, m.integrator.name())?;
    attr_str(&f, attr::X, &p.x.name)?;
    attr_str(&f, attr::Y, &p.y.name)?;
    attr_str(&f, attr::ALONG, p.along.name())?;
    attr_str(&f, attr::SWEEPS, &m.sweeps.iter().map(|s| s.name()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::OVERRIDES, &pairs(&m.overrides))?;
    attr_str(&f, attr::MASSES, &m.masses.join(","))?;
    attr_str(&f, attr::STATE_MASSES, &m.state_masses.join(","))?;
    if !m.quantities.is_empty() {
        attr_str(&f, attr::QUANTITIES, &m.quantities.iter().map(|q| q.name.as_str()).collect::<Vec<_>>().join(","))?;
    }
    attr_str(&f, attr::P_STOPS, &m.label_stops.iter().map(|s| s[0].as_str()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::Q_STOPS, &m.label_stops.iter().map(|s| s[1].as_str()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::STOPS, &m.stops.join(","))?;
    attr_array(&f, attr::STOP_NORMALS, &m.stop_normals.concat())?;
    attr_str(&f, attr::STOP_LAWS, &m.stop_laws.iter().map(|l| l.name()).collect::<Vec<_>>().join(","))?;
    attr_num(&f, attr::DIM, m.dim as u64)?;
    attr_num(&f, attr::SECTION_CAP, m.section_cap as u64)?;

    let axes = f.create_group(AXES)?;
    for axis in [&p.x, &p.y] {
        let values = axis.values();
        let d = axes.new_dataset_builder().with_data(&Array1::from(values.clone())).create(axis.name.as_str())?;
        z.expected.numbers(&d, &values);
        attr_num(&d, attr::START, axis.start)?;
        attr_num(&d, attr::STOP, axis.stop)?;
        if let Some(l) = &axis.lattice {
            attr_array(&d, attr::LATTICE_START, &l.levels.iter().map(|l| l.0).collect::<Vec<_>>())?;
            attr_array(&d, attr::LATTICE_STOP, &l.levels.iter().map(|l| l.1).collect::<Vec<_>>())?;
            attr_array(&d, attr::LATTICE_COUNT, &l.levels.iter().map(|l| l.2 as u64).collect::<Vec<_>>())?;
        }
        // Its ends and lattice under a checksum: they decide the values a zoom takes.
        netcdf::seal(&d)?;
    }
    // Root coordinates, for the root's gridded datasets (hysteresis).
    Grid::new(&f, m, z)?;
    let datasets =
        m.sweeps.iter().map(|s| create_sweep(&f.create_group(s.name())?, m, chunks, z)).collect::<hdf5::Result<_>>()?;
    Ok((f, datasets))
}

/// The state components (`x_M1, …, v_M1, …`).
fn components(m: &maps::Meta) -> Vec<String> {
    ["x", "v"].iter().flat_map(|q| m.state_masses.iter().map(move |n| format!("{q}_{n}"))).collect()
}

/// A sweep's group of [`Draft::create`]: coordinates, dimensions, and its
/// per-cell datasets, empty (returned, to be filled chunk by chunk).
fn create_sweep(g: &Group, m: &maps::Meta, chunks: &Chunks, z: &Deflater) -> hdf5::Result<Vec<(Field, hdf5::Dataset)>> {
    let grid = Grid::new(g, m, z)?;
    let components = components(m);
    let labels = |name: &str, values: &[String], long_name: &str| -> hdf5::Result<hdf5::Dataset> {
        let d = netcdf::labels(g, name, values, long_name)?;
        z.expected.texts(&d, values);
        Ok(d)
    };
    let npq = labels(NPQ, &["n".into(), "p".into(), "q".into()], "counts of a label n-p-q")?;
    let component = labels(COMPONENT, &components, "state component (position x, velocity v)")?;
    let mut impact_columns = vec!["phase".to_string()];
    impact_columns.extend(components.iter().cloned());
    labels(
        IMPACT_COLUMN,
        &impact_columns,
        "time within the forcing period (t mod T, column 'phase'), then the state before the impact",
    )?;
    labels(MASS, &m.masses, "labelled mass")?;
    netcdf::dimension(g, RGB, 3)?;
    let scales = fields::Scales { y: &grid.y, x: &grid.x, npq: &npq, component: &component };
    Field::all(m).into_iter().map(|field| Ok((field, field.create(g, m, chunks, &scales)?))).collect()
}

/// The results of [`Draft::finish`] but the per-cell datasets, into the file
/// of [`create_file`].
fn fill_file(f: &hdf5::File, atlas: &Atlas, info: &RunInfo, z: &Deflater) -> hdf5::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    let (nx, ny) = (p.x.count, p.y.count);
    let created = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    let mut history = info.history.clone();
    history.push(format!("{created}: {}", info.command));
    attr_str(f, attr::HISTORY, &history.join("\n"))?;
    attr_str(f, attr::COMMAND, &info.command)?;
    attr_str(f, attr::CREATED, &created)?;
    attr_num(f, attr::RUN_TIME_S, info.run_time_s)?;
    if let Some(s) = info.shard {
        attr_str(f, attr::SHARD, &s.to_string())?;
    }
    if let Some(parent) = &info.parent {
        attr_str(f, attr::PARENT, &parent.path)?;
        attr_str(f, attr::PARENT_LABELS_CRC32, &format!("{:08x}", parent.labels_crc32))?;
        attr_str(f, attr::PARENT_BOX, &parent.region)?;
    }
    let mut detailed = Vec::new();
    for map in &atlas.maps {
        if fill_sweep(&f.group(map.sweep.name())?, atlas, map, info.parent.is_some(), z)? {
            detailed.push(map.sweep.name());
        }
    }
    if !detailed.is_empty() {
        attr_str(f, attr::REASON_DETAILS, &detailed.join(","))?;
    }
    if let Some(h) = atlas.hysteresis() {
        let d = z.dataset(
            f,
            HYSTERESIS,
            &Array2::from_shape_vec((ny, nx), h).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?,
        )?;
        netcdf::dims(&d, &[&f.dataset(&p.y.name)?, &f.dataset(&p.x.name)?])?;
        netcdf::describe(&d, "1 where the up and down sweeps end on different periodic motions", "1")?;
        netcdf::attr_array(&d, "flag_values", &[0u8, 1])?;
        netcdf::attr_str(&d, "flag_meanings", "same_motion coexisting_motions")?;
    }
    if let Some(a) = &atlas.attractors {
        write_attractors(f, m, a, z)?;
        attr_str(f, attr::ATTRACTOR_SAMPLING, &sampling_text(a))?;
    }
    let legend = f.create_group(LEGEND)?;
    for map in &atlas.maps {
        let g = legend.create_group(map.sweep.name())?;
        for (mi, mass) in m.masses.iter().enumerate() {
            let mg = g.create_group(mass)?;
            let entries = atlas.legend(map.sweep, mi);
            let entry = netcdf::dimension(&mg, ENTRY, entries.len())?;
            let labels: Vec<String> = entries.iter().map(|(l, _)| l.to_string()).collect();
            let counts: Vec<u64> = entries.iter().map(|&(_, c)| c).collect();
            let d = netcdf::texts(&mg, "label", &labels)?;
            z.expected.texts(&d, &labels);
            netcdf::dims(&d, &[&entry])?;
            let d = mg.new_dataset_builder().with_data(&Array1::from(counts.clone())).create(var::COUNT)?;
            z.expected.numbers(&d, &counts);
            netcdf::dims(&d, &[&entry])?;
        }
    }
    // Every text attribute of the root is written: their checksum.
    netcdf::seal(f)?;
    f.flush()
}

/// A sweep's results but its per-cell datasets, into its group `g` of
/// [`create_sweep`]: its label table and codes, lines done and sections.
/// A zoom's (`zoom`) continuation sweep has its `entry_state` always, all
/// NaN where every chain starts from the scene's initial state (its readers
/// require it). Returns whether its reasons were written with their
/// numbers ([`write_reasons`]).
fn fill_sweep(g: &Group, atlas: &Atlas, map: &maps::Map, zoom: bool, z: &Deflater) -> hdf5::Result<bool> {
    let m = &atlas.meta;
    let p = &m.plane;
    let (nx, ny) = (p.x.count, p.y.count);
    let cells = &map.cells;
    let grid = Grid { x: g.dataset(&p.x.name)?, y: g.dataset(&p.y.name)? };

    // Label tables: every label of the sweep, any mass, in a fixed order
    // (`None`: a cell not computed).
    let label_at = |mi: usize, i: usize| cells[i].as_ref().map(|c| c.labels[mi]);
    let labels = LabelTable::of((0..m.masses.len()).flat_map(|mi| (0..cells.len()).map(move |i| label_at(mi, i))));
    let (label_dim, table) = labels.write(g, z)?;
    let colours =
        Array2::from_shape_fn((table.len(), 3), |(i, k)| labels.labels[i].map_or(palette::BLANK, palette::colour)[k]);
    let d = g.new_dataset_builder().with_data(&colours).create(LABEL_COLOUR)?;
    z.expected.numbers(&d, colours.as_slice().expect("a new array is contiguous"));
    netcdf::dims(&d, &[&label_dim, &g.dataset(RGB)?])?;
    netcdf::attr_str(&d, "long_name", "colour of each label in vibroatlas figures (RGB, 0-255)")?;
    let codes: Vec<i16> = (0..table.len() as i16).collect();
    for (mi, mass) in m.masses.iter().enumerate() {
        let code = Array2::from_shape_vec((ny, nx), labels.codes((0..cells.len()).map(|i| label_at(mi, i))))
            .map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
        let d = z.dataset(g, &label_code(mass), &code)?;
        netcdf::dims(&d, &[&grid.y, &grid.x])?;
        netcdf::describe(&d, &format!("label of {mass}: index into the label coordinate"), "1")?;
        netcdf::attr_array(&d, "flag_values", &codes)?;
        netcdf::attr_str(&d, attr::FLAG_MEANINGS, &table.join(" "))?;
    }
    let detailed = write_reasons(g, cells, &grid, z)?;
    let done: Vec<u8> = atlas.lines_done(map.sweep).into_iter().map(u8::from).collect();
    let lines = netcdf::dimension(g, LINE, done.len())?;
    let d = z.dataset(g, var::LINES_DONE, &Array1::from(done))?;
    netcdf::dims(&d, &[&lines])?;
    netcdf::attr_str(&d, "long_name", "1 where the line (row, or column with along = y) is computed")?;
    if map.sweep != maps::SweepKind::Fresh && (zoom || !atlas.entries.0.is_empty()) {
        let entry = Array2::from_shape_fn((p.lines(), m.dim), |(l, k)| {
            atlas.entries.get(map.sweep, l).map_or(f64::NAN, |s| s[k])
        });
        let d = z.dataset(g, var::ENTRY_STATE, &entry)?;
        netcdf::dims(&d, &[&lines, &g.dataset(COMPONENT)?])?;
        netcdf::attr_str(
            &d,
            "long_name",
            "state the line's chain entered the plane with (NaN: the scene's initial state)",
        )?;
    }

    let sections = g.create_group(SECTIONS)?;
    write_section(
        z,
        &sections,
        PERIOD_SECTION,
        &g.dataset(COMPONENT)?,
        cells.iter().map(|c| c.as_ref().map(|c| &c.period_section)),
        "state at t = kT (period section)",
    )?;
    let impact_column = g.dataset(IMPACT_COLUMN)?;
    for (k, stop) in m.stops.iter().enumerate() {
        write_section(
            z,
            &sections,
            stop,
            &impact_column,
            cells.iter().map(|c| c.as_ref().map(|c| &c.impact_sections[k])),
            &format!("time within the forcing period (t mod T) and state just before each impact at {stop}"),
        )?;
    }
    Ok(detailed)
}

/// Why the unresolved cells of a sweep are unresolved: the table of their
/// distinct reasons (a string coordinate of their texts, sorted; empty when
/// every cell is resolved), beside it each reason with its numbers
/// ([`REASON_DETAIL`], JSON; where some reason has numbers), and per cell an
/// index into it (-1: resolved, or not computed). Two reasons whose texts
/// agree but whose numbers do not (the text rounds them) are two entries of
/// the same text. Returns whether the details were written.
fn write_reasons(g: &Group, cells: &[Option<maps::CellData>], grid: &Grid, z: &Deflater) -> hdf5::Result<bool> {
    // Each cell's reason as JSON, once.
    let encoded: Vec<Option<String>> = cells
        .iter()
        .map(|c| {
            let reason = c.as_ref().and_then(|c| c.reason.as_ref());
            reason.map(serde_json::to_string).transpose()
        })
        .collect::<Result<_, _>>()
        .map_err(|e| hdf5::Error::from(format!("a reason as JSON: {e}").as_str()))?;
    let reasons = cells.iter().zip(&encoded).filter_map(|(c, e)| Some((c.as_ref()?.reason.as_ref()?, e.as_deref()?)));
    let mut table = std::collections::BTreeSet::new();
    let mut numbers = false;
    for (r, e) in reasons {
        numbers |= !matches!(**r, solver::Unresolved::Described { .. });
        table.insert((r.to_string(), e));
    }
    let index: HashMap<&str, i32> = table.iter().enumerate().map(|(i, (_, e))| (*e, i as i32)).collect();
    let (texts, details): (Vec<String>, Vec<String>) = table.iter().map(|(t, e)| (t.clone(), e.to_string())).unzip();
    let reason_dim = netcdf::labels(g, REASON, &texts, "why cells are unresolved")?;
    z.expected.texts(&reason_dim, &texts);
    // Only reasons with numbers have a detail to add: a sweep without one
    // (every cell resolved, or reasons read from a file without details) is
    // written as before.
    if numbers {
        let detail = netcdf::texts(g, REASON_DETAIL, &details)?;
        netcdf::dims(&detail, &[&reason_dim])?;
        attr_str(&detail, "long_name", "why cells are unresolved, with the numbers: JSON with kind and its fields")?;
        z.expected.texts(&detail, &details);
    }
    let (ny, nx) = (grid.y.size(), grid.x.size());
    let code = Array2::from_shape_fn((ny, nx), |(iy, ix)| encoded[iy * nx + ix].as_deref().map_or(-1, |e| index[e]));
    let d = z.dataset(g, REASON_CODE, &code)?;
    netcdf::dims(&d, &[&grid.y, &grid.x])?;
    netcdf::describe(
        &d,
        "why the cell is unresolved: index into the reason coordinate (-1: resolved, or not computed)",
        "1",
    )?;
    Ok(numbers)
}

/// The root's `attractor_sampling` of an atlas with attractors.
pub(crate) fn sampling_text(a: &maps::AttractorMap) -> String {
    format!("{} samples per cell, seed {}", a.samples, a.seed)
}

/// The coexisting attractors of the sampled cells (`/attractors`, see
/// [`crate::layout`]): their count per cell, and per attractor slot the label
/// code of each mass and the basin fraction.
fn write_attractors(f: &hdf5::File, m: &maps::Meta, a: &maps::AttractorMap, z: &Deflater) -> hdf5::Result<()> {
    let (nx, ny) = (m.plane.x.count, m.plane.y.count);
    let g = f.create_group(ATTRACTORS)?;
    netcdf::attr_num(&g, attr::SAMPLES, a.samples as u64)?;
    netcdf::attr_num(&g, attr::SEED, a.seed)?;
    let grid = Grid::new(&g, m, z)?;
    let slots = a.cells.iter().flatten().map(Vec::len).max().unwrap_or(0).max(1);
    let slot = netcdf::dimension(&g, ATTRACTOR, slots)?;
    let labels = LabelTable::of(a.cells.iter().flatten().flatten().flat_map(|at| at.labels.iter().map(|l| Some(*l))));
    labels.write(&g, z)?;
    let cell = |iy: usize, ix: usize| a.cells[iy * nx + ix].as_ref();
    let count = Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(0u8, |c| c.len().min(255) as u8));
    let d = z.dataset(&g, var::COUNT, &count)?;
    netcdf::dims(&d, &[&grid.y, &grid.x])?;
    netcdf::describe(&d, "number of coexisting attractors found (0: cell not sampled)", "1")?;
    let fraction = Array3::from_shape_fn((ny, nx, slots), |(iy, ix, k)| {
        cell(iy, ix).and_then(|c| c.get(k)).map_or(f64::NAN, |e| e.fraction)
    });
    let d = z.dataset(&g, var::FRACTION, &fraction)?;
    netcdf::dims(&d, &[&grid.y, &grid.x, &slot])?;
    netcdf::describe(&d, "share of the sampled initial states that reach the attractor (basin fraction)", "1")?;
    netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
    for (mi, mass) in m.masses.iter().enumerate() {
        let index = |l: &Label| labels.code[&Some(*l)];
        let code = Array3::from_shape_fn((ny, nx, slots), |(iy, ix, k)| {
            cell(iy, ix).and_then(|c| c.get(k)).map_or(-1, |e| index(&e.labels[mi]))
        });
        let d = z.dataset(&g, &label_code(mass), &code)?;
        netcdf::dims(&d, &[&grid.y, &grid.x, &slot])?;
        netcdf::describe(
            &d,
            &format!("label of {mass} on each attractor: index into the label coordinate (-1: none)"),
            "1",
        )?;
    }
    // Each attractor's first period-section points, which match it to the
    // attractors of the neighbouring cells (maps::families).
    let points = a.cells.iter().flatten().flatten().map(|at| at.section.len()).max().unwrap_or(0).max(1);
    let point = netcdf::dimension(&g, POINT, points)?;
    let component = netcdf::dimension(&g, COMPONENT, m.dim.max(1))?;
    let section = ndarray::Array5::from_shape_fn((ny, nx, slots, points, m.dim.max(1)), |(iy, ix, k, p, c)| {
        cell(iy, ix).and_then(|cell| cell.get(k)).and_then(|at| at.section.get(p)).map_or(f64::NAN, |s| s[c])
    });
    let d = z.dataset(&g, var::SECTION, &section)?;
    netcdf::dims(&d, &[&grid.y, &grid.x, &slot, &point, &component])?;
    netcdf::describe(&d, "the attractor's first period-section points, [x..., v...] (NaN after its last)", "1")?;
    netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
    write_families(&g, m, a, z, &grid, &slot, &labels)
}

/// The families of the attractors (`maps::families`): per attractor slot its
/// family, per family the labels of its attractors and its basin fraction
/// over the plane.
fn write_families(
    g: &Group,
    m: &maps::Meta,
    a: &maps::AttractorMap,
    z: &Deflater,
    grid: &Grid,
    slot: &hdf5::Dataset,
    labels: &LabelTable,
) -> hdf5::Result<()> {
    let (nx, ny) = (m.plane.x.count, m.plane.y.count);
    let f = maps::families(a, nx);
    let slots = slot.size();
    let id = Array3::from_shape_fn((ny, nx, slots), |(iy, ix, k)| {
        f.ids[iy * nx + ix].as_ref().and_then(|c| c.get(k)).map_or(-1, |&v| v as i32)
    });
    let d = z.dataset(g, var::FAMILY, &id)?;
    netcdf::dims(&d, &[&grid.y, &grid.x, slot])?;
    netcdf::describe(&d, "the family of the attractor, followed from cell to cell (-1: none)", "1")?;
    let families = f.labels.len().max(1);
    let family = netcdf::dimension(g, FAMILY_DIM, families)?;
    let maps: Vec<Vec<f64>> = (0..f.labels.len() as u32).map(|k| f.fraction_map(a, k)).collect();
    let fraction =
        Array3::from_shape_fn((families, ny, nx), |(k, iy, ix)| maps.get(k).map_or(f64::NAN, |map| map[iy * nx + ix]));
    let d = z.dataset(g, var::FAMILY_FRACTION, &fraction)?;
    netcdf::dims(&d, &[&family, &grid.y, &grid.x])?;
    netcdf::describe(&d, "basin fraction of the family in each cell (0: absent, NaN: cell not sampled)", "1")?;
    netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
    for (mi, mass) in m.masses.iter().enumerate() {
        let code = Array1::from_shape_fn(families, |k| f.labels.get(k).map_or(-1, |l| labels.code[&Some(l[mi])]));
        let d = z.dataset(g, &family_label_code(mass), &code)?;
        netcdf::dims(&d, &[&family])?;
        netcdf::describe(&d, &format!("label of {mass} on the family: index into the label coordinate"), "1")?;
    }
    Ok(())
}

/// The coordinate variables of a group's plane (dimension scales named after
/// the parameters).
struct Grid {
    x: hdf5::Dataset,
    y: hdf5::Dataset,
}

impl Grid {
    /// The coordinates of `m`'s plane in `g`, each with its parameter's CF
    /// `long_name` (`parameter <name>` when the scene gives none) and
    /// `symbol` ([`maps::Meta::symbol`]).
    fn new(g: &Group, m: &maps::Meta, z: &Deflater) -> hdf5::Result<Grid> {
        let p = &m.plane;
        let axis = |a: &maps::Axis| -> hdf5::Result<hdf5::Dataset> {
            let long_name = m.long_name(&a.name).map_or_else(|| generic_long_name(&a.name), str::to_string);
            let values = a.values();
            let d = netcdf::coordinate(g, &a.name, &values, &long_name)?;
            z.expected.numbers(&d, &values);
            attr_str(&d, attr::SYMBOL, &m.symbol(&a.name))?;
            netcdf::seal(&d)?;
            Ok(d)
        };
        Ok(Grid { x: axis(&p.x)?, y: axis(&p.y)? })
    }
}

/// The `long_name` of the coordinate of a parameter whose scene says neither
/// `long_name` nor `doc`.
pub(crate) fn generic_long_name(name: &str) -> String {
    format!("parameter {name}")
}

/// A label table of the file (its `label` coordinate): the labels in a fixed
/// order — periodic ones by (n, p, q) (`S` after every number), then C, Q,
/// U, then `None` (a cell not computed) — and the code of each, its index.
struct LabelTable {
    labels: Vec<Option<Label>>,
    code: HashMap<Option<Label>, i16>,
}

impl LabelTable {
    /// The table of the labels `labels` (each once).
    fn of(labels: impl Iterator<Item = Option<Label>>) -> LabelTable {
        let labels: HashSet<Option<Label>> = maps::runs(labels).map(|(l, _)| l).collect();
        let mut labels: Vec<Option<Label>> = labels.into_iter().collect();
        let count = |c: Count| match c {
            Count::Impacts(k) => k,
            Count::Stuck => u32::MAX,
        };
        labels.sort_by_key(|l| match *l {
            Some(Label::Periodic { n, p, q }) => (0, [n, count(p), count(q)]),
            Some(Label::Chaotic) => (1, [0; 3]),
            Some(Label::Quasiperiodic) => (2, [0; 3]),
            Some(Label::Unresolved) => (3, [0; 3]),
            None => (4, [0; 3]),
        });
        let code = labels.iter().enumerate().map(|(i, l)| (*l, i as i16)).collect();
        LabelTable { labels, code }
    }

    /// The code of each of `labels` (each in the table), in order.
    fn codes(&self, labels: impl Iterator<Item = Option<Label>>) -> Vec<i16> {
        maps::runs(labels).flat_map(|(l, n)| std::iter::repeat_n(self.code[&l], n as usize)).collect()
    }

    /// Writes the table as the `label` coordinate of `g` (`not-computed` for
    /// `None`), its texts recorded for the read-back; the coordinate and
    /// its texts.
    fn write(&self, g: &Group, z: &Deflater) -> hdf5::Result<(hdf5::Dataset, Vec<String>)> {
        let texts: Vec<String> =
            self.labels.iter().map(|l| l.map_or(NOT_COMPUTED_LABEL.to_string(), |l| l.to_string())).collect();
        let dim = netcdf::labels(g, LABEL, &texts, "label n-p-q, or C, Q, U")?;
        z.expected.texts(&dim, &texts);
        netcdf::attr_str(&dim, "comment", LABEL_COMMENT)?;
        Ok((dim, texts))
    }
}

/// One ragged section (CSR): `values [point, column]` and `offsets [cell_edge]`,
/// cell `i = iy*nx + ix` owning rows `offsets[i]..offsets[i+1]`.
fn write_section<'a>(
    z: &Deflater,
    g: &Group,
    name: &str,
    columns: &hdf5::Dataset,
    cells: impl Iterator<Item = Option<&'a solver::Points>>,
    long_name: &str,
) -> hdf5::Result<()> {
    let cols = columns.size();
    let s = g.create_group(name)?;
    let cells: Vec<Option<&solver::Points>> = cells.collect();
    let mut offsets = Vec::with_capacity(cells.len() + 1);
    offsets.push(0u64);
    let mut values: Vec<f64> = Vec::with_capacity(cells.iter().flatten().map(|p| p.values().len()).sum());
    for points in cells {
        if let Some(p) = points.filter(|p| !p.is_empty()) {
            if p.width() != cols {
                return Err(format!("{name}: points of {} values, {cols} expected", p.width()).as_str().into());
            }
            values.extend_from_slice(p.values());
        }
        offsets.push((values.len() / cols) as u64);
    }
    let n = values.len() / cols;
    let a = Array2::from_shape_vec((n, cols), values).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    let point = netcdf::dimension(&s, POINT, n)?;
    let edge = netcdf::dimension(&s, CELL_EDGE, offsets.len())?;
    // Full-precision states hardly compress (deflate kept 84 % of their
    // bytes, at 50 MB/s a thread): the values are stored as they are, in
    // checksummed chunks.
    let d = z.stored(&s, var::VALUES, &a)?;
    netcdf::dims(&d, &[&point, columns])?;
    netcdf::describe(&d, long_name, "1")?;
    let d = z.dataset(&s, var::OFFSETS, &Array1::from(offsets))?;
    netcdf::dims(&d, &[&edge])?;
    netcdf::attr_str(&d, "long_name", "CSR offsets: cell i = iy*nx + ix owns rows offsets[i]..offsets[i+1] of values")?;
    Ok(())
}

/// Every accuracy knob of the run (`k=v,…`): the preset's with the overrides applied.
fn knobs(m: &maps::Meta) -> String {
    let mut acc = solver::Accuracy::preset(m.preset);
    for &(k, v) in &m.accuracy {
        // The overrides were validated when the run started.
        let _ = acc.set(k, v);
    }
    let number = |v: f64| if v.fract() == 0.0 && v.abs() < 1e15 { format!("{v}") } else { format!("{v:e}") };
    acc.knobs().iter().map(|(k, v)| format!("{k}={}", number(*v))).collect::<Vec<_>>().join(",")
}

/// `k=v,k=v` text of parameter pairs.
pub fn pairs<K: std::fmt::Display>(p: &[(K, f64)]) -> String {
    p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(",")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::scratch;
    use maps::{Along, Axis, Plane, SweepKind};

    /// The scene of [`meta`]: one mass M1 above its stop A at δ.
    const SCENE: &str = r#"
name = "test"
[parameters]
omega = 1.0
delta = 0.5
[forcing]
omega = "omega"
[[masses]]
name = "M1"
mass = 1
force = 1
x0 = 1
[[links]]
masses = ["M1"]
stiffness = 1
[[stops]]
name = "A"
mass = "M1"
side = "below"
position = "delta"
restitution = 0.8
"#;

    fn meta() -> maps::Meta {
        let x = Axis::parse("omega=0.5:2:5", "x").unwrap();
        let y = Axis::parse("delta=0.1:1:3", "y").unwrap();
        maps::Meta {
            scene_name: "test".into(),
            scene_toml: SCENE.into(),
            overrides: Vec::new(),
            preset: solver::Preset::Standard,
            accuracy: Vec::new(),
            integrator: solver::Method::Exact,
            plane: Plane::new(x, y, Along::X).unwrap(),
            sweeps: vec![SweepKind::Up],
            masses: vec!["M1".into()],
            state_masses: vec!["M1".into()],
            label_stops: vec![["A".into(), "A".into()]],
            stops: vec!["A".into()],
            stop_normals: vec![vec![1.0]],
            stop_laws: vec![scene::LawKind::Rigid],
            dim: 2,
            section_cap: 4,
            notation: Vec::new(),
            quantities: ["max_abs_x_M1", "power_in"]
                .map(|name| maps::Quantity {
                    name: name.into(),
                    symbol: "q".into(),
                    long_name: format!("the test's {name}"),
                    units: "1".into(),
                })
                .into(),
        }
    }

    /// The run of a test's files.
    fn run_info() -> RunInfo {
        RunInfo { command: "test".into(), run_time_s: 0.0, shard: None, history: Vec::new(), parent: None }
    }

    /// [`meta`] on the plane of axes `x` and `y`, lines along x.
    fn meta_on(x: &str, y: &str) -> maps::Meta {
        let (x, y) = (Axis::parse(x, "x").unwrap(), Axis::parse(y, "y").unwrap());
        maps::Meta { plane: Plane::new(x, y, Along::X).unwrap(), ..meta() }
    }

    /// A cell whose every value tells where it is (cell `i`, sweep `s`).
    fn cell(i: usize) -> maps::CellData {
        let n = 1 + (i % 3) as u32;
        maps::CellData {
            class: solver::Class::Periodic,
            labels: vec![solver::Label::Periodic { n, p: solver::Count::Impacts(i as u32), q: solver::Count::Stuck }],
            chatter: Default::default(),
            sticking: Default::default(),
            symmetry: None,
            lyapunov: None,
            multiplier: Some(i as f64 / 7.0),
            final_state: vec![i as f64, -(i as f64)],
            periods: 1000 + i as u64,
            events: 2000 + i as u64,
            period_section: solver::Points::from_rows(vec![[i as f64, 0.5]; i % 3]).unwrap(),
            impact_sections: vec![solver::Points::from_rows(vec![[0.25, i as f64, 1.0]; i % 2]).unwrap()],
            reason: i.is_multiple_of(5).then(|| Box::new(reason(i))),
            // A quantity a motion could not give (NaN) in every seventh cell.
            quantities: vec![if i.is_multiple_of(7) { f64::NAN } else { i as f64 * 0.25 }, -(i as f64)],
        }
    }

    /// The up sweep of `m` with every line computed, each cell [`cell`].
    fn every_cell(m: maps::Meta) -> Atlas {
        let p = m.plane.clone();
        let mut atlas = Atlas::new(m);
        for l in 0..p.lines() {
            let cells = (0..p.line_len()).map(|pos| {
                let (iy, ix) = p.cell(l, pos);
                cell(iy * p.x.count + ix)
            });
            atlas.insert(maps::Line { sweep: SweepKind::Up, index: l, cells: cells.collect() });
        }
        atlas
    }

    /// A reason with numbers of cell `i`: distances that one text rounds
    /// alike (1.0e-7 for every odd cell, two table entries of one text),
    /// infinite ones, nested and failed reasons.
    fn reason(i: usize) -> solver::Unresolved {
        use solver::Unresolved;
        let distance = if i.is_multiple_of(2) { f64::INFINITY } else { 1e-7 * (1.0 + (i % 7) as f64 * 1e-9) };
        match i % 3 {
            0 => Unresolved::Unsettled { periods: 2251, multiplier: 0.99, distance, left: None },
            1 => Unresolved::NoExponent { halt: Box::new(Unresolved::Budget { max_events: i }), measured: None },
            _ => Unresolved::Failed(solver::SolverError::OutOfRange { message: format!("x = {i}e300") }),
        }
    }

    /// The per-cell datasets hold each cell's values where the cell is,
    /// whether their chunks were written as lines were kept (in any order,
    /// some never), all at the end, or into memory ([`image`], whose bytes
    /// make a file that passes the whole-file check); along x and along y.
    #[test]
    fn kept_lines_and_the_end_write_the_same_cells() {
        let dir = scratch("keep");
        let info = run_info();
        for along in [Along::X, Along::Y] {
            let x = Axis::parse("omega=0.5:2:70", "x").unwrap();
            let y = Axis::parse("delta=0.1:1:40", "y").unwrap();
            let m = maps::Meta { plane: Plane::new(x, y, along).unwrap(), ..meta() };
            let p = m.plane.clone();
            let mut atlas = Atlas::new(m.clone());
            // Every line but every fifth computed.
            let computed: Vec<usize> = (0..p.lines()).filter(|l| l % 5 != 2).collect();
            for &l in &computed {
                let cells = (0..p.line_len()).map(|pos| {
                    let (iy, ix) = p.cell(l, pos);
                    cell(iy * p.x.count + ix)
                });
                atlas.insert(maps::Line { sweep: SweepKind::Up, index: l, cells: cells.collect() });
            }
            let kept = dir.join("kept.h5");
            let mut draft = Draft::create(&kept, &m, 2).unwrap();
            for &l in computed.iter().rev() {
                draft.keep(&atlas, SweepKind::Up, l).unwrap();
                draft.keep(&atlas, SweepKind::Up, l).unwrap();
            }
            draft.finish(&atlas, &info).unwrap();
            let end = dir.join("end.h5");
            write(&end, &atlas, &info, 3).unwrap();
            // The same file written in memory, its bytes put on disk here.
            let memory = dir.join("memory.h5");
            std::fs::write(&memory, image(&atlas, &info, 2).unwrap()).unwrap();
            check_finished(&memory, &crate::read(&memory).unwrap()).unwrap();
            for path in [&kept, &end, &memory] {
                let f = hdf5::File::open(path).unwrap();
                let periods = f.dataset("up/periods").unwrap().read_2d::<u64>().unwrap();
                let state = f.dataset("up/final_state").unwrap().read::<f64, ndarray::Ix3>().unwrap();
                let npq = f.dataset("up/label_M1").unwrap().read::<u16, ndarray::Ix3>().unwrap();
                let class = f.dataset("up/class").unwrap().read_2d::<u8>().unwrap();
                // Reasons go through their table and codes, and read back per cell
                // with their numbers; the table's texts are theirs.
                let reasons: Vec<String> = f
                    .dataset("up/reason")
                    .unwrap()
                    .read_1d::<hdf5::types::VarLenUnicode>()
                    .unwrap()
                    .iter()
                    .map(|t| t.to_string())
                    .collect();
                let codes = f.dataset("up/reason_code").unwrap().read_2d::<i32>().unwrap();
                let unsettled = reasons.iter().filter(|t| t.contains("still about 1.0e-7 from it")).count();
                assert!(unsettled >= 2, "{unsettled} entries of one text for distances that it rounds alike");
                let back = crate::read(path).unwrap().atlas;
                let back = &back.map(SweepKind::Up).unwrap().cells;
                for iy in 0..p.y.count {
                    for ix in 0..p.x.count {
                        let i = iy * p.x.count + ix;
                        let done = computed.contains(&p.position(iy, ix).0);
                        let at = format!("{along:?} ({iy}, {ix}) of {}", path.display());
                        assert_eq!(periods[[iy, ix]], if done { 1000 + i as u64 } else { 0 }, "{at}");
                        assert_eq!(class[[iy, ix]], if done { 0 } else { NOT_COMPUTED }, "{at}");
                        if done {
                            assert_eq!([state[[iy, ix, 0]], state[[iy, ix, 1]]], [i as f64, -(i as f64)], "{at}");
                            let want = [1 + (i % 3) as u16, i as u16, STUCK];
                            assert_eq!([npq[[iy, ix, 0]], npq[[iy, ix, 1]], npq[[iy, ix, 2]]], want, "{at}");
                            assert_eq!(back[i].as_ref().unwrap().reason, cell(i).reason, "{at}");
                            if let Some(r) = &cell(i).reason {
                                assert_eq!(reasons[codes[[iy, ix]] as usize], r.to_string(), "{at}");
                            }
                        } else {
                            assert!(state[[iy, ix, 0]].is_nan(), "{at}");
                        }
                    }
                }
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The read-back compares every value of every per-cell dataset: a file
    /// read back against an atlas one value of which differs (an integer
    /// of one value a cell, the last component of a state) is refused,
    /// naming that dataset; against its own atlas it passes.
    #[test]
    fn the_read_back_sees_one_value_changed() {
        let dir = scratch("read-back");
        let m = meta_on("omega=0.5:2:9", "delta=0.1:1:7");
        let p = m.plane.clone();
        let atlas = every_cell(m);
        let path = dir.join("a.h5");
        write(&path, &atlas, &run_info(), 2).unwrap();
        let none = crate::checksum::Expected::default();
        assert!(crate::verify::file(&path, &path, &atlas, &none).is_ok());
        let last = p.x.count * p.y.count - 1;
        type Change = fn(&mut maps::CellData);
        let changes: [(&str, Change); 2] = [
            ("up/periods", |c| c.periods += 1),
            ("up/final_state", |c| c.final_state[1] = f64::from_bits(c.final_state[1].to_bits() ^ 1)),
        ];
        for (dataset, change) in changes {
            let mut other = atlas.clone();
            let cells = &mut other.maps[0].cells;
            change(cells[last].as_mut().unwrap());
            match crate::verify::file(&path, &path, &other, &none) {
                Err(StoreError::Unverified { dataset: d, .. }) => assert_eq!(d, dataset),
                e => panic!("{dataset}: {:?}", e.map(|c| c.len())),
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Reasons known by their text alone (read from a file written before
    /// the details) are written as before, without [`REASON_DETAIL`], and
    /// read back as they were; one reason with numbers among them brings
    /// the details of all, each read back as it was.
    #[test]
    fn reasons_without_numbers_are_written_as_before() {
        let dir = scratch("reasons");
        let info = run_info();
        let m = meta_on("omega=0.5:2:4", "delta=0.1:0.2:2");
        let described = |text: &str| solver::Unresolved::Described { text: text.into() };
        for numbers in [false, true] {
            let mut atlas = Atlas::new(m.clone());
            let cells = (0..4).map(|i| maps::CellData {
                reason: match i {
                    0 => Some(Box::new(described("an older file's reason (λT = 1.0e-3)"))),
                    2 if numbers => Some(Box::new(reason(2))),
                    _ => None,
                },
                ..cell(i)
            });
            atlas.insert(maps::Line { sweep: SweepKind::Up, index: 0, cells: cells.collect() });
            let path = dir.join("reasons.h5");
            write(&path, &atlas, &info, 1).unwrap();
            let f = hdf5::File::open(&path).unwrap();
            assert_eq!(f.link_exists("up/reason_detail"), numbers);
            assert_eq!(f.dataset("up/reason").unwrap().size(), if numbers { 2 } else { 1 });
            let back = crate::read(&path).unwrap().atlas;
            let reasons = |a: &Atlas| -> Vec<_> {
                a.map(SweepKind::Up).unwrap().cells.iter().map(|c| c.as_ref().and_then(|c| c.reason.clone())).collect()
            };
            assert_eq!(reasons(&back), reasons(&atlas));
            assert!(reasons(&back)[0].is_some());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A draft dropped unfinished leaves neither its temporary file nor a
    /// change to the file it was to replace; finished, it replaces it.
    #[test]
    fn an_unfinished_draft_leaves_the_target_as_it_was() {
        let dir = scratch("draft");
        let out = dir.join("a.h5");
        std::fs::write(&out, "the previous file").unwrap();
        let draft = Draft::create(&out, &meta(), 2).unwrap();
        assert!(partial_path(&out).exists(), "the draft writes beside the target");
        drop(draft);
        assert!(!partial_path(&out).exists(), "a dropped draft removes its temporary file");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "the previous file");

        // Finished with no line computed: every cell reads as not computed.
        let info = run_info();
        let atlas = Atlas::new(meta());
        let mut draft = Draft::create(&out, &meta(), 2).unwrap();
        draft.keep(&atlas, SweepKind::Down, 0).unwrap();
        let other = maps::Meta { section_cap: 8, ..meta() };
        let err = Draft::create(&dir.join("b.h5"), &other, 1).unwrap().finish(&atlas, &info).unwrap_err().to_string();
        assert!(err.contains("not of the set-up"), "{err}");
        assert!(!dir.join("b.h5").exists() && !partial_path(&dir.join("b.h5")).exists());
        draft.finish(&atlas, &info).unwrap();
        assert!(!partial_path(&out).exists());
        let f = hdf5::File::open(&out).unwrap();
        let class = f.dataset("up/class").unwrap().read_2d::<u8>().unwrap();
        assert_eq!(class.shape(), &[3, 5]);
        assert!(class.iter().all(|&c| c == NOT_COMPUTED));
        let state = f.dataset("up/final_state").unwrap().read::<f64, ndarray::Ix3>().unwrap();
        assert!(state.iter().all(|v| v.is_nan()));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A temporary file removed under its writer: the error says so in the
    /// system's words, naming the file, on one line (not the library's text).
    #[test]
    fn a_file_removed_under_its_draft_says_so_plainly() {
        let dir = scratch("removed");
        let info = run_info();
        let out = dir.join("o.h5");
        let draft = Draft::create(&out, &meta(), 1).unwrap();
        std::fs::remove_file(partial_path(&out)).unwrap();
        let err = draft.finish(&Atlas::new(meta()), &info).unwrap_err().to_string();
        let want = format!(
            "{}: the file written does not read back as written ({}: No such file or directory); it was not put in place",
            out.display(),
            partial_path(&out).display()
        );
        assert_eq!(err, want);
        assert!(!out.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A temporary file cut short under its writer does not read back as
    /// written: finishing it is [`StoreError::Unverified`] naming the first
    /// dataset that failed, and nothing is put under the final name.
    #[test]
    fn a_file_cut_short_under_its_draft_is_not_put_in_place() {
        let dir = scratch("cut");
        let info = run_info();
        let m = meta_on("omega=0.5:2:70", "delta=0.1:1:40");
        let p = m.plane.clone();
        let atlas = every_cell(m.clone());
        let out = dir.join("cut.h5");
        let mut draft = Draft::create(&out, &m, 2).unwrap();
        for l in 0..p.lines() {
            draft.keep(&atlas, SweepKind::Up, l).unwrap();
        }
        std::fs::OpenOptions::new().write(true).open(partial_path(&out)).unwrap().set_len(100).unwrap();
        let err = draft.finish(&atlas, &info).unwrap_err();
        assert!(matches!(err, StoreError::Unverified { .. }), "{err}");
        assert!(err.to_string().contains("does not read back as written"), "{err}");
        assert!(!out.exists() && !partial_path(&out).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
