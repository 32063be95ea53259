//! Writing an atlas to HDF5 (see [`crate::layout`]): to a temporary file in the
//! target folder, renamed over the final name only once complete, so a crash
//! never leaves a half-written file under the final name.

use crate::chunked::Deflater;
use crate::error::StoreError;
use crate::layout::*;
use crate::netcdf::{self, attr_array, attr_num, attr_str};
use grid::{Atlas, CellData};
use hdf5::types::VarLenUnicode;
use hdf5::Group;
use ndarray::{Array1, Array2, Array3};
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
    pub shard: Option<grid::Shard>,
    /// Earlier history lines (`TIME: command`, oldest first): those of the
    /// parts of a merge; the file adds its own.
    pub history: Vec<String>,
}

/// The git commit the binary was built from (`unknown` outside a checkout).
pub const GIT_COMMIT: &str = env!("VIBROATLAS_GIT_COMMIT");

/// The temporary path used while writing `path`: `.<stem>.partial.<ext>` beside
/// it (the extension is kept for writers that choose a format by it).
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    match path.extension() {
        Some(ext) => path.with_file_name(format!(".{stem}.partial.{}", ext.to_string_lossy())),
        None => path.with_file_name(format!(".{stem}.partial")),
    }
}

/// Writes `atlas` to `path` (atomically, through a temporary file), its
/// datasets' chunks compressed on `threads` threads.
pub fn write(path: &Path, atlas: &Atlas, info: &RunInfo, threads: usize) -> Result<(), StoreError> {
    let z = Deflater { threads };
    crate::write_atomically(path, |tmp| write_file(tmp, atlas, info, z))
}

fn write_file(path: &Path, atlas: &Atlas, info: &RunInfo, z: Deflater) -> hdf5::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    let (nx, ny, dim) = (p.x.count, p.y.count, m.dim);
    let f = hdf5::File::create(path)?;
    let created = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    attr_str(&f, attr::CONVENTIONS, "CF-1.8")?;
    attr_str(&f, "title", &format!("vibroatlas map of the {} scene over ({}, {})", m.scene_name, p.x.name, p.y.name))?;
    attr_str(&f, "source", &format!("vibroatlas {} (git {})", env!("CARGO_PKG_VERSION"), GIT_COMMIT))?;
    let mut history = info.history.clone();
    history.push(format!("{created}: {}", info.command));
    attr_str(&f, attr::HISTORY, &history.join("\n"))?;
    attr_str(&f, attr::SOFTWARE, SOFTWARE)?;
    attr_str(&f, "version", env!("CARGO_PKG_VERSION"))?;
    attr_str(&f, "git_commit", GIT_COMMIT)?;
    attr_num(&f, attr::LAYOUT_VERSION, LAYOUT_VERSION)?;
    attr_str(&f, attr::SCENE, &m.scene_toml)?;
    attr_str(&f, attr::SCENE_NAME, &m.scene_name)?;
    attr_str(&f, attr::PRESET, &m.preset)?;
    attr_str(&f, attr::ACCURACY, &pairs(&m.accuracy))?;
    attr_str(&f, "knobs", &knobs(m))?;
    attr_str(&f, attr::INTEGRATOR, &m.integrator)?;
    attr_str(&f, attr::COMMAND, &info.command)?;
    attr_str(&f, attr::CREATED, &created)?;
    attr_num(&f, attr::RUN_TIME_S, info.run_time_s)?;
    attr_str(&f, attr::X, &p.x.name)?;
    attr_str(&f, attr::Y, &p.y.name)?;
    attr_str(&f, attr::ALONG, p.along.name())?;
    attr_str(&f, attr::SWEEPS, &m.sweeps.iter().map(|s| s.name()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::OVERRIDES, &pairs(&m.overrides))?;
    attr_str(&f, attr::MASSES, &m.masses.join(","))?;
    attr_str(&f, attr::STATE_MASSES, &m.state_masses.join(","))?;
    attr_str(&f, attr::P_STOPS, &m.label_stops.iter().map(|s| s[0].as_str()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::Q_STOPS, &m.label_stops.iter().map(|s| s[1].as_str()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, attr::STOPS, &m.stops.join(","))?;
    attr_array(&f, attr::STOP_NORMALS, &m.stop_normals.concat())?;
    attr_num(&f, attr::DIM, dim as u64)?;
    attr_num(&f, attr::SECTION_CAP, m.section_cap as u64)?;
    if let Some(s) = info.shard {
        attr_str(&f, attr::SHARD, &s.to_string())?;
    }

    let axes = f.create_group(AXES)?;
    for axis in [&p.x, &p.y] {
        let d = axes.new_dataset_builder().with_data(&Array1::from(axis.values())).create(axis.name.as_str())?;
        attr_num(&d, attr::START, axis.start)?;
        attr_num(&d, attr::STOP, axis.stop)?;
    }
    // Root coordinates, for the root's gridded datasets (hysteresis).
    let root = Grid::new(&f, m)?;

    let shift = sticking_shift(m.stops.len());
    let components: Vec<String> =
        ["x", "v"].iter().flat_map(|q| m.state_masses.iter().map(move |n| format!("{q}_{n}"))).collect();
    for map in &atlas.maps {
        let g = f.create_group(map.sweep.name())?;
        let grid = Grid::new(&g, m)?;
        let cells = &map.cells;
        let cell = |iy: usize, ix: usize| cells[iy * nx + ix].as_ref();
        let npq = netcdf::labels(&g, NPQ, &["n".into(), "p".into(), "q".into()], "counts of a label n-p-q")?;
        let component = netcdf::labels(&g, COMPONENT, &components, "state component (position x, velocity v)")?;
        let mut impact_columns = vec!["phase".to_string()];
        impact_columns.extend(components.iter().cloned());
        let impact_column = netcdf::labels(
            &g,
            IMPACT_COLUMN,
            &impact_columns,
            "time within the forcing period (t mod T, column 'phase'), then the state before the impact",
        )?;
        netcdf::labels(&g, MASS, &m.masses, "labelled mass")?;

        // Label tables: every label of the sweep, any mass, in a fixed order
        // (`None`: a cell not computed).
        let label_at = |mi: usize, i: usize| cells[i].as_ref().map(|c| c.labels[mi]);
        let distinct: HashSet<Option<solver::Label>> =
            (0..m.masses.len()).flat_map(|mi| (0..cells.len()).map(move |i| label_at(mi, i))).collect();
        let text = |l: &Option<solver::Label>| l.map_or(NOT_COMPUTED_LABEL.to_string(), |l| l.to_string());
        let table = label_table(distinct.iter().map(text));
        let position: HashMap<&str, i16> = table.iter().enumerate().map(|(i, t)| (t.as_str(), i as i16)).collect();
        let index: HashMap<Option<solver::Label>, i16> =
            distinct.iter().map(|l| (*l, position.get(text(l).as_str()).copied().unwrap_or(0))).collect();
        let label_dim = netcdf::labels(&g, LABEL, &table, "label n-p-q, or C, Q, U")?;
        netcdf::attr_str(&label_dim, "comment", LABEL_COMMENT)?;
        let rgb = netcdf::dimension(&g, RGB, 3)?;
        let colours = Array2::from_shape_fn((table.len(), 3), |(i, k)| grid::palette::colour(&table[i])[k]);
        let d = g.new_dataset_builder().with_data(&colours).create(LABEL_COLOUR)?;
        netcdf::dims(&d, &[&label_dim, &rgb])?;
        netcdf::attr_str(&d, "long_name", "colour of each label in vibroatlas figures (RGB, 0-255)")?;
        let codes: Vec<i16> = (0..table.len() as i16).collect();
        for (mi, mass) in m.masses.iter().enumerate() {
            let a =
                Array3::from_shape_fn((ny, nx, 3), |(iy, ix, k)| cell(iy, ix).map_or(0, |c| npq_code(c.labels[mi])[k]));
            let d = z.dataset(&g, &label(mass), &a)?;
            netcdf::dims(&d, &[&grid.y, &grid.x, &npq])?;
            netcdf::attr_str(&d, "long_name", &format!("n, p, q of {mass}'s label ({} = S, the mass sticks)", STUCK))?;
            netcdf::attr_str(&d, "units", "1")?;
            netcdf::attr_str(&d, "dims", "y, x, (n, p, q)")?;
            netcdf::attr_num(&d, "stuck_code", STUCK)?;
            let code = Array2::from_shape_fn((ny, nx), |(iy, ix)| index[&label_at(mi, iy * nx + ix)]);
            let d = z.dataset(&g, &label_code(mass), &code)?;
            netcdf::dims(&d, &[&grid.y, &grid.x])?;
            netcdf::describe(&d, &format!("label of {mass}: index into the label coordinate"), "1")?;
            netcdf::attr_array(&d, "flag_values", &codes)?;
            netcdf::attr_str(&d, "flag_meanings", &table.join(" "))?;
        }
        let gridded = |d: &hdf5::Dataset, long_name: &str, units: &str| -> hdf5::Result<()> {
            netcdf::dims(d, &[&grid.y, &grid.x])?;
            netcdf::describe(d, long_name, units)
        };
        let class =
            Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(NOT_COMPUTED, |c| class_code(c.class)));
        let d = z.dataset(&g, var::CLASS, &class)?;
        gridded(&d, "kind of steady motion", "1")?;
        netcdf::attr_str(&d, "codes", CLASS_CODES)?;
        netcdf::attr_array(&d, "flag_values", &[0u8, 1, 2, 3])?;
        netcdf::attr_str(&d, "flag_meanings", "periodic chaotic unresolved quasiperiodic")?;
        netcdf::attr_num(&d, "_FillValue", NOT_COMPUTED)?;
        let flag =
            |iy: usize, ix: usize| cell(iy, ix).map_or(0u32, |c| flags_code(c.chatter, c.sticking, m.stops.len()));
        let (masks, meanings) = flag_masks(&m.stops, shift);
        let flags = if m.stops.len() <= 4 {
            let d = z.dataset(&g, var::FLAGS, &Array2::from_shape_fn((ny, nx), |(iy, ix)| flag(iy, ix) as u8))?;
            netcdf::attr_array(&d, "flag_masks", &masks.iter().map(|&v| v as u8).collect::<Vec<_>>())?;
            d
        } else {
            let d = z.dataset(&g, var::FLAGS, &Array2::from_shape_fn((ny, nx), |(iy, ix)| flag(iy, ix)))?;
            netcdf::attr_array(&d, "flag_masks", &masks)?;
            d
        };
        gridded(&flags, "chattering and sticking at each stop (bit flags)", "1")?;
        netcdf::attr_str(&flags, "flag_meanings", &meanings)?;
        netcdf::attr_str(&flags, "bits", &flag_bits(&m.stops))?;
        let sym = Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(0, |c| symmetry_code(c.symmetry)));
        let d = z.dataset(&g, var::SYMMETRY, &sym)?;
        gridded(&d, "mirror symmetry of the periodic orbit (symmetric scenes)", "1")?;
        netcdf::attr_str(&d, "codes", SYMMETRY_CODES)?;
        netcdf::attr_array(&d, "flag_values", &[0u8, 1, 2])?;
        netcdf::attr_str(&d, "flag_meanings", "none symmetric asymmetric")?;
        let scalar = |f: fn(&CellData) -> Option<f64>| {
            Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).and_then(f).unwrap_or(f64::NAN))
        };
        let d = z.dataset(&g, var::LYAPUNOV, &scalar(|c| c.lyapunov))?;
        gridded(&d, "largest Lyapunov exponent per unit time (cells without a period)", "1")?;
        netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
        netcdf::attr_str(
            &d,
            "meaning",
            "largest Lyapunov exponent per unit time of cells without a period (NaN: none)",
        )?;
        let d = z.dataset(&g, var::MULTIPLIER, &scalar(|c| c.multiplier))?;
        gridded(&d, "largest Floquet multiplier modulus (periodic cells)", "1")?;
        netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
        netcdf::attr_str(&d, "meaning", "largest Floquet multiplier modulus of periodic cells (NaN: none)")?;
        let fs =
            Array3::from_shape_fn((ny, nx, dim), |(iy, ix, k)| cell(iy, ix).map_or(f64::NAN, |c| c.final_state[k]));
        let d = z.dataset(&g, var::FINAL_STATE, &fs)?;
        netcdf::dims(&d, &[&grid.y, &grid.x, &component])?;
        netcdf::describe(&d, "state at the end of the cell's record (a whole number of forcing periods)", "1")?;
        netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
        let d = z.dataset(
            &g,
            var::PERIODS,
            &Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(0, |c| c.periods)),
        )?;
        gridded(&d, "forcing periods simulated", "1")?;
        let d = z.dataset(
            &g,
            var::EVENTS,
            &Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(0, |c| c.events)),
        )?;
        gridded(&d, "events handled", "1")?;
        let done: Vec<u8> = atlas.lines_done(map.sweep).into_iter().map(u8::from).collect();
        let lines = netcdf::dimension(&g, LINE, done.len())?;
        let d = z.dataset(&g, var::LINES_DONE, &Array1::from(done))?;
        netcdf::dims(&d, &[&lines])?;
        netcdf::attr_str(&d, "long_name", "1 where the line (row, or column with along = y) is computed")?;

        let sections = g.create_group(SECTIONS)?;
        write_section(
            z,
            &sections,
            PERIOD_SECTION,
            &component,
            cells.iter().map(|c| c.as_ref().map(|c| c.period_section.as_slice())),
            "state at t = kT (period section)",
        )?;
        for (k, stop) in m.stops.iter().enumerate() {
            write_section(
                z,
                &sections,
                stop,
                &impact_column,
                cells.iter().map(|c| c.as_ref().map(|c| c.impact_sections[k].as_slice())),
                &format!("time within the forcing period (t mod T) and state just before each impact at {stop}"),
            )?;
        }
    }

    if let Some(h) = atlas.hysteresis() {
        let d = z.dataset(
            &f,
            HYSTERESIS,
            &Array2::from_shape_vec((ny, nx), h).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?,
        )?;
        netcdf::dims(&d, &[&root.y, &root.x])?;
        netcdf::describe(&d, "1 where the up and down sweeps end on different periodic motions", "1")?;
        netcdf::attr_array(&d, "flag_values", &[0u8, 1])?;
        netcdf::attr_str(&d, "flag_meanings", "same_motion coexisting_motions")?;
    }
    if let Some(a) = &atlas.attractors {
        write_attractors(&f, m, a, z)?;
    }
    let legend = f.create_group(LEGEND)?;
    for map in &atlas.maps {
        let g = legend.create_group(map.sweep.name())?;
        for (mi, mass) in m.masses.iter().enumerate() {
            let mg = g.create_group(mass)?;
            let entries = atlas.legend(map.sweep, mi);
            let entry = netcdf::dimension(&mg, ENTRY, entries.len())?;
            let labels: Vec<VarLenUnicode> = entries.iter().map(|(l, _)| netcdf::text(l)).collect();
            let counts: Vec<u64> = entries.iter().map(|&(_, c)| c).collect();
            let d = mg.new_dataset_builder().with_data(&Array1::from(labels)).create("label")?;
            netcdf::dims(&d, &[&entry])?;
            let d = mg.new_dataset_builder().with_data(&Array1::from(counts)).create(var::COUNT)?;
            netcdf::dims(&d, &[&entry])?;
        }
    }
    f.flush()
}

/// The coexisting attractors of the sampled cells (`/attractors`, see
/// [`crate::layout`]): their count per cell, and per attractor slot the label
/// code of each mass and the basin fraction.
fn write_attractors(f: &hdf5::File, m: &grid::Meta, a: &grid::AttractorMap, z: Deflater) -> hdf5::Result<()> {
    let (nx, ny) = (m.plane.x.count, m.plane.y.count);
    let g = f.create_group(ATTRACTORS)?;
    netcdf::attr_num(&g, attr::SAMPLES, a.samples as u64)?;
    netcdf::attr_num(&g, attr::SEED, a.seed)?;
    let grid = Grid::new(&g, m)?;
    let slots = a.cells.iter().flatten().map(Vec::len).max().unwrap_or(0).max(1);
    let slot = netcdf::dimension(&g, ATTRACTOR, slots)?;
    let texts = a.cells.iter().flatten().flatten().flat_map(|(labels, _)| labels.iter());
    let table = label_table(texts.cloned());
    let label_dim = netcdf::labels(&g, LABEL, &table, "label n-p-q, or C, Q, U")?;
    netcdf::attr_str(&label_dim, "comment", LABEL_COMMENT)?;
    let cell = |iy: usize, ix: usize| a.cells[iy * nx + ix].as_ref();
    let count = Array2::from_shape_fn((ny, nx), |(iy, ix)| cell(iy, ix).map_or(0u8, |c| c.len().min(255) as u8));
    let d = z.dataset(&g, var::COUNT, &count)?;
    netcdf::dims(&d, &[&grid.y, &grid.x])?;
    netcdf::describe(&d, "number of coexisting attractors found (0: cell not sampled)", "1")?;
    let fraction = Array3::from_shape_fn((ny, nx, slots), |(iy, ix, k)| {
        cell(iy, ix).and_then(|c| c.get(k)).map_or(f64::NAN, |e| e.1)
    });
    let d = z.dataset(&g, var::FRACTION, &fraction)?;
    netcdf::dims(&d, &[&grid.y, &grid.x, &slot])?;
    netcdf::describe(&d, "share of the sampled initial states that reach the attractor (basin fraction)", "1")?;
    netcdf::attr_num(&d, "_FillValue", f64::NAN)?;
    for (mi, mass) in m.masses.iter().enumerate() {
        let index = |t: &String| table.iter().position(|l| l == t).unwrap_or(0) as i16;
        let code = Array3::from_shape_fn((ny, nx, slots), |(iy, ix, k)| {
            cell(iy, ix).and_then(|c| c.get(k)).map_or(-1, |e| index(&e.0[mi]))
        });
        let d = z.dataset(&g, &label_code(mass), &code)?;
        netcdf::dims(&d, &[&grid.y, &grid.x, &slot])?;
        netcdf::describe(
            &d,
            &format!("label of {mass} on each attractor: index into the label coordinate (-1: none)"),
            "1",
        )?;
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
    fn new(g: &Group, m: &grid::Meta) -> hdf5::Result<Grid> {
        let p = &m.plane;
        Ok(Grid {
            x: netcdf::coordinate(g, &p.x.name, &p.x.values(), &format!("parameter {}", p.x.name))?,
            y: netcdf::coordinate(g, &p.y.name, &p.y.values(), &format!("parameter {}", p.y.name))?,
        })
    }
}

/// The labels of a sweep in a fixed order: periodic labels by (n, p, q), then
/// C, Q, U, then `not-computed`.
fn label_table(texts: impl Iterator<Item = String>) -> Vec<String> {
    let mut set: Vec<String> = texts.collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    let key = |l: &String| -> (u8, Vec<u32>) {
        let nums: Option<Vec<u32>> =
            l.split('-').map(|t| if t == "S" { Some(u32::MAX) } else { t.parse().ok() }).collect();
        match (l.as_str(), nums) {
            (_, Some(v)) if v.len() == 3 => (0, v),
            ("C", _) => (1, Vec::new()),
            ("Q", _) => (2, Vec::new()),
            ("U", _) => (3, Vec::new()),
            _ => (4, Vec::new()),
        }
    };
    set.sort_by_key(key);
    set
}

/// CF flag masks and meanings of the flags dataset.
fn flag_masks(stops: &[String], shift: u32) -> (Vec<u32>, String) {
    let chatter = stops.iter().enumerate().map(|(k, s)| (1u32 << k, format!("{s}_chatters")));
    let stick = stops.iter().enumerate().map(|(k, s)| (1u32 << (k as u32 + shift), format!("{s}_sticks")));
    let (masks, names): (Vec<u32>, Vec<String>) = chatter.chain(stick).unzip();
    (masks, names.join(" "))
}

/// One ragged section (CSR): `values [point, column]` and `offsets [cell_edge]`,
/// cell `i = iy*nx + ix` owning rows `offsets[i]..offsets[i+1]`.
fn write_section<'a>(
    z: Deflater,
    g: &Group,
    name: &str,
    columns: &hdf5::Dataset,
    cells: impl Iterator<Item = Option<&'a [Vec<f64>]>>,
    long_name: &str,
) -> hdf5::Result<()> {
    let cols = columns.size();
    let s = g.create_group(name)?;
    let mut offsets = vec![0u64];
    let mut values: Vec<f64> = Vec::new();
    for rows in cells {
        for r in rows.unwrap_or(&[]) {
            values.extend_from_slice(r);
        }
        offsets.push((values.len() / cols) as u64);
    }
    let n = values.len() / cols;
    let a = Array2::from_shape_vec((n, cols), values).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    let point = netcdf::dimension(&s, POINT, n)?;
    let edge = netcdf::dimension(&s, CELL_EDGE, offsets.len())?;
    let d = z.dataset(&s, var::VALUES, &a)?;
    netcdf::dims(&d, &[&point, columns])?;
    netcdf::describe(&d, long_name, "1")?;
    let d = z.dataset(&s, var::OFFSETS, &Array1::from(offsets))?;
    netcdf::dims(&d, &[&edge])?;
    netcdf::attr_str(&d, "long_name", "CSR offsets: cell i = iy*nx + ix owns rows offsets[i]..offsets[i+1] of values")?;
    Ok(())
}

/// Every accuracy knob of the run (`k=v,…`): the preset's with the overrides applied.
fn knobs(m: &grid::Meta) -> String {
    let mut acc = solver::Accuracy::preset(solver::Preset::parse(&m.preset).unwrap_or(solver::Preset::Standard));
    for (k, v) in &m.accuracy {
        // The overrides were validated when the run started.
        let _ = acc.set(k, *v);
    }
    let number = |v: f64| if v.fract() == 0.0 && v.abs() < 1e15 { format!("{v}") } else { format!("{v:e}") };
    acc.knobs().iter().map(|(k, v)| format!("{k}={}", number(*v))).collect::<Vec<_>>().join(",")
}

/// `k=v,k=v` text of parameter pairs.
pub fn pairs(p: &[(String, f64)]) -> String {
    p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(",")
}
