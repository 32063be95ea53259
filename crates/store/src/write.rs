//! Writing an atlas to HDF5 (see [`crate::layout`]): to a temporary file in the
//! target folder, renamed over the final name only once complete, so a crash
//! never leaves a half-written file under the final name.

use crate::error::StoreError;
use crate::layout::*;
use grid::{Atlas, CellData};
use hdf5::types::VarLenUnicode;
use hdf5::{Group, H5Type, Location};
use ndarray::{Array1, Array2, Array3};
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
}

fn text(s: &str) -> VarLenUnicode {
    // Strings with NUL cannot be stored; scene files never contain one.
    s.replace('\0', " ").parse().unwrap_or_default()
}

fn attr_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    loc.new_attr::<VarLenUnicode>().create(name)?.write_scalar(&text(value))
}

fn attr_num<T: H5Type + Copy>(loc: &Location, name: &str, value: T) -> hdf5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&value)
}

fn dataset<T: H5Type, D: ndarray::Dimension>(
    g: &Group,
    name: &str,
    data: &ndarray::Array<T, D>,
) -> hdf5::Result<hdf5::Dataset> {
    let shape: Vec<usize> = data.shape().iter().map(|&n| n.max(1)).collect();
    let chunk: Vec<usize> = shape.iter().enumerate().map(|(i, &n)| if i == 0 { n.min(4096) } else { n }).collect();
    g.new_dataset_builder().chunk(chunk).deflate(4).with_data(data).create(name)
}

/// The temporary path used while writing `path`: `.<stem>.partial.<ext>` beside
/// it (the extension is kept for writers that choose a format by it).
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    match path.extension() {
        Some(ext) => path.with_file_name(format!(".{stem}.partial.{}", ext.to_string_lossy())),
        None => path.with_file_name(format!(".{stem}.partial")),
    }
}

/// Writes `atlas` to `path` (atomically, through a temporary file).
pub fn write(path: &Path, atlas: &Atlas, info: &RunInfo) -> Result<(), StoreError> {
    let tmp = partial_path(path);
    let result = write_file(&tmp, atlas, info).map_err(|e| StoreError::hdf5(path, e));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    crate::lock::commit(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

fn write_file(path: &Path, atlas: &Atlas, info: &RunInfo) -> hdf5::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    let (nx, ny, dim) = (p.x.count, p.y.count, m.dim);
    let f = hdf5::File::create(path)?;
    attr_str(&f, "software", SOFTWARE)?;
    attr_str(&f, "version", env!("CARGO_PKG_VERSION"))?;
    attr_str(&f, "scene", &m.scene_toml)?;
    attr_str(&f, "scene_name", &m.scene_name)?;
    attr_str(&f, "preset", &m.preset)?;
    attr_str(&f, "accuracy", &pairs(&m.accuracy))?;
    attr_str(&f, "integrator", &m.integrator)?;
    attr_str(&f, "command", &info.command)?;
    attr_str(&f, "created", &humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string())?;
    attr_num(&f, "run_time_s", info.run_time_s)?;
    attr_str(&f, "x", &p.x.name)?;
    attr_str(&f, "y", &p.y.name)?;
    attr_str(&f, "along", p.along.name())?;
    attr_str(&f, "sweeps", &m.sweeps.iter().map(|s| s.name()).collect::<Vec<_>>().join(","))?;
    attr_str(&f, "overrides", &pairs(&m.overrides))?;
    attr_str(&f, "masses", &m.masses.join(","))?;
    attr_str(&f, "stops", &m.stops.join(","))?;
    attr_num(&f, "dim", dim as u64)?;
    attr_num(&f, "section_cap", m.section_cap as u64)?;
    if let Some(s) = info.shard {
        attr_str(&f, "shard", &s.to_string())?;
    }

    let axes = f.create_group(AXES)?;
    for axis in [&p.x, &p.y] {
        let d = axes.new_dataset_builder().with_data(&Array1::from(axis.values())).create(axis.name.as_str())?;
        attr_str(&d, "CLASS", "DIMENSION_SCALE")?;
        attr_str(&d, "NAME", &axis.name)?;
        attr_num(&d, "start", axis.start)?;
        attr_num(&d, "stop", axis.stop)?;
    }

    let shift = sticking_shift(m.stops.len());
    for map in &atlas.maps {
        let g = f.create_group(map.sweep.name())?;
        let cells = &map.cells;
        for (mi, mass) in m.masses.iter().enumerate() {
            let a = Array3::from_shape_fn((ny, nx, 3), |(iy, ix, k)| {
                cells[iy * nx + ix].as_ref().map_or(0, |c| c.labels[mi][k])
            });
            let d = dataset(&g, &label(mass), &a)?;
            attr_str(&d, "dims", "y, x, (n, p, q)")?;
            attr_num(&d, "stuck_code", STUCK)?;
        }
        let class = Array2::from_shape_fn((ny, nx), |(iy, ix)| {
            cells[iy * nx + ix].as_ref().map_or(NOT_COMPUTED, |c| class_code(c.class))
        });
        let d = dataset(&g, "class", &class)?;
        attr_str(&d, "codes", CLASS_CODES)?;
        let flag =
            |iy: usize, ix: usize| cells[iy * nx + ix].as_ref().map_or(0u32, |c| c.chatter | (c.sticking << shift));
        let flags = if m.stops.len() <= 4 {
            dataset(&g, "flags", &Array2::from_shape_fn((ny, nx), |(iy, ix)| flag(iy, ix) as u8))?
        } else {
            dataset(&g, "flags", &Array2::from_shape_fn((ny, nx), |(iy, ix)| flag(iy, ix)))?
        };
        attr_str(&flags, "bits", &flag_bits(&m.stops))?;
        let sym = Array2::from_shape_fn((ny, nx), |(iy, ix)| {
            cells[iy * nx + ix].as_ref().map_or(0, |c| symmetry_code(c.symmetry))
        });
        let d = dataset(&g, "symmetry", &sym)?;
        attr_str(&d, "codes", SYMMETRY_CODES)?;
        let scalar = |f: fn(&CellData) -> Option<f64>| {
            Array2::from_shape_fn((ny, nx), |(iy, ix)| cells[iy * nx + ix].as_ref().and_then(f).unwrap_or(f64::NAN))
        };
        let d = dataset(&g, "lyapunov", &scalar(|c| c.lyapunov))?;
        attr_str(&d, "meaning", "largest Lyapunov exponent per unit time of cells without a period (NaN: none)")?;
        let d = dataset(&g, "multiplier", &scalar(|c| c.multiplier))?;
        attr_str(&d, "meaning", "largest Floquet multiplier modulus of periodic cells (NaN: none)")?;
        let fs = Array3::from_shape_fn((ny, nx, dim), |(iy, ix, k)| {
            cells[iy * nx + ix].as_ref().map_or(f64::NAN, |c| c.final_state[k])
        });
        dataset(&g, "final_state", &fs)?;
        dataset(
            &g,
            "periods",
            &Array2::from_shape_fn((ny, nx), |(iy, ix)| cells[iy * nx + ix].as_ref().map_or(0, |c| c.periods)),
        )?;
        dataset(
            &g,
            "events",
            &Array2::from_shape_fn((ny, nx), |(iy, ix)| cells[iy * nx + ix].as_ref().map_or(0, |c| c.events)),
        )?;
        let done: Vec<u8> = atlas.lines_done(map.sweep).into_iter().map(u8::from).collect();
        dataset(&g, "lines_done", &Array1::from(done))?;

        let sections = g.create_group(SECTIONS)?;
        write_section(
            &sections,
            PERIOD_SECTION,
            dim,
            cells.iter().map(|c| c.as_ref().map(|c| c.period_section.as_slice())),
        )?;
        for (k, stop) in m.stops.iter().enumerate() {
            write_section(
                &sections,
                stop,
                dim + 1,
                cells.iter().map(|c| c.as_ref().map(|c| c.impact_sections[k].as_slice())),
            )?;
        }
    }

    if let Some(h) = atlas.hysteresis() {
        dataset(
            &f,
            HYSTERESIS,
            &Array2::from_shape_vec((ny, nx), h).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?,
        )?;
    }
    let legend = f.create_group(LEGEND)?;
    for map in &atlas.maps {
        let g = legend.create_group(map.sweep.name())?;
        for (mi, mass) in m.masses.iter().enumerate() {
            let mg = g.create_group(mass)?;
            let entries = atlas.legend(map.sweep, mi);
            let labels: Vec<VarLenUnicode> = entries.iter().map(|(l, _)| text(l)).collect();
            let counts: Vec<u64> = entries.iter().map(|&(_, c)| c).collect();
            mg.new_dataset_builder().with_data(&Array1::from(labels)).create("label")?;
            mg.new_dataset_builder().with_data(&Array1::from(counts)).create("count")?;
        }
    }
    f.flush()
}

fn write_section<'a>(
    g: &Group,
    name: &str,
    cols: usize,
    cells: impl Iterator<Item = Option<&'a [Vec<f64>]>>,
) -> hdf5::Result<()> {
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
    dataset(&s, "values", &a)?;
    dataset(&s, "offsets", &Array1::from(offsets))?;
    Ok(())
}

/// `k=v,k=v` text of parameter pairs.
pub fn pairs(p: &[(String, f64)]) -> String {
    p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(",")
}
