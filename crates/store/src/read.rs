//! Reading an atlas file back into memory (for merge, render, inspect, resume
//! checks and round-trip tests).

use crate::error::{OtherKind, StoreError};
use crate::layout::*;
use crate::write::RunInfo;
use maps::{Along, Atlas, Axis, CellData, Map, Meta, Plane, Shard, SweepKind};
use scene::Named;
use solver::{Class, Unresolved};
use std::path::Path;

/// An atlas file's contents.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The atlas.
    pub atlas: Atlas,
    /// How it was produced.
    pub info: RunInfo,
    /// Creation time (RFC 3339).
    pub created: String,
}

use crate::attrs::{required, required_text as attr, text as attr_opt};
use crate::checked::{data, texts, Checker, Dim};

fn list(s: &str) -> Vec<String> {
    if s.is_empty() {
        Vec::new()
    } else {
        s.split(',').map(str::to_string).collect()
    }
}

fn pairs(s: &str) -> Result<Vec<(String, f64)>, String> {
    list(s)
        .iter()
        .map(|kv| {
            let (k, v) = kv.split_once('=').ok_or_else(|| format!("bad pair '{kv}'"))?;
            Ok((k.to_string(), v.parse::<f64>().map_err(|_| format!("bad number in '{kv}'"))?))
        })
        .collect()
}

/// Accuracy knobs as `k=v,k=v`, each a knob of the solver.
fn knobs(s: &str) -> Result<Vec<(solver::Knob, f64)>, String> {
    pairs(s)?
        .into_iter()
        .map(|(k, v)| solver::Knob::parse(&k).map(|k| (k, v)).ok_or_else(|| format!("unknown accuracy knob '{k}'")))
        .collect()
}

/// Largest state dimension a reader takes (twice the number of masses).
pub const MAX_DIM: usize = 4096;

/// Memory available to the process, bytes (`MemAvailable` of
/// /proc/meminfo; 4 GiB where it cannot be read): readers and runs bound
/// what they allocate by it.
pub fn available_memory() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map_or(4 << 30, |kb| kb.saturating_mul(1024))
}

/// One ragged section of a sweep, checked: `values [points, cols]` and
/// `offsets [cells + 1]`.
struct Section {
    values: hdf5::Dataset,
    offsets: hdf5::Dataset,
    points: usize,
    cols: usize,
}

/// The datasets of one sweep, opened and checked against the grid before
/// any is read.
struct SweepSets {
    class: hdf5::Dataset,
    symmetry: hdf5::Dataset,
    flags: hdf5::Dataset,
    final_state: hdf5::Dataset,
    lyapunov: Option<hdf5::Dataset>,
    multiplier: Option<hdf5::Dataset>,
    periods: hdf5::Dataset,
    events: hdf5::Dataset,
    labels: Vec<hdf5::Dataset>,
    /// The quantities of [`Meta::quantities`], in order.
    quantities: Vec<hdf5::Dataset>,
    /// The table of reasons, the per-cell codes (files since the reasons
    /// were stored) and the reasons with their numbers (files since those
    /// were stored).
    reasons: Option<Reasons>,
    period: Section,
    impacts: Vec<Section>,
}

impl SweepSets {
    /// Bytes that reading the sweep takes at most: its datasets as read and
    /// the cells made of them.
    fn bytes(&self, n: usize, dim: usize, masses: usize) -> u64 {
        let n = n as u64;
        let dim = dim as u64;
        let read =
            n * (1 + 1 + 4 + 8 + 8 + 8 + 8 + 6 * masses as u64 + 16 * self.quantities.len() as u64) + n * dim * 8;
        let cells = n
            * (std::mem::size_of::<Option<CellData>>() as u64
                + masses as u64 * std::mem::size_of::<solver::Label>() as u64
                + dim * 8);
        let sections: u64 = std::iter::once(&self.period)
            .chain(&self.impacts)
            .map(|s| {
                // Values and offsets as read, then each point as a row of its cell.
                let points = s.points as u64;
                points * s.cols as u64 * 16 + points * 24 + (n + 1) * 8 + n * 24
            })
            .sum();
        read.saturating_add(cells).saturating_add(sections)
    }
}

/// A sweep's stored reasons: the table of their texts, the per-cell codes
/// into it, and the reasons with their numbers ([`REASON_DETAIL`]; absent
/// from files written before it).
struct Reasons {
    table: hdf5::Dataset,
    codes: hdf5::Dataset,
    detail: Option<hdf5::Dataset>,
}

/// A sweep's reasons and its cells' codes into them, each code -1 or an
/// index of the table: each reason with its numbers where the file holds
/// them, else its text ([`Unresolved::Described`]).
fn reasons(ck: &Checker, r: &Reasons) -> Result<(Vec<Unresolved>, Vec<i32>), StoreError> {
    let text = texts(ck, &r.table)?;
    let c = ck.raw::<i32>(&r.codes)?;
    if let Some(bad) = c.iter().find(|&&c| c < -1 || c as i64 >= text.len() as i64) {
        return Err(ck.bad(&r.codes.name(), format!("code {bad} is not in the table of {} reasons", text.len())));
    }
    let Some(detail) = &r.detail else {
        return Ok((text.into_iter().map(|text| Unresolved::Described { text }).collect(), c));
    };
    let details = texts(ck, detail)?;
    if details.len() != text.len() {
        let why = format!("{} entries, but the table of reasons has {}", details.len(), text.len());
        return Err(ck.bad(&detail.name(), why));
    }
    let decoded = details
        .iter()
        .enumerate()
        .map(|(i, d)| {
            serde_json::from_str(d).map_err(|e| ck.bad(&detail.name(), format!("entry {i} is not a reason: {e}")))
        })
        .collect::<Result<_, _>>()?;
    Ok((decoded, c))
}

/// Whether `path` says it is a vibroatlas atlas (its root attributes
/// `software` and `x`), whether or not the rest of it reads: a file that
/// says so but does not read is a damaged atlas, not another program's
/// file.
pub fn is_atlas(path: &Path) -> bool {
    let says = || -> Result<bool, StoreError> {
        let f = crate::heap::open(path)?;
        Ok(attr_opt(path, &f, attr::SOFTWARE)?.as_deref() == Some(SOFTWARE) && f.attr(attr::X).is_ok())
    };
    path.is_file() && says().unwrap_or(false)
}

/// The scene text stored in an atlas or sweep file (its root's checked
/// attributes only: the cells are not read).
pub fn stored_scene(path: &Path) -> Result<String, StoreError> {
    if !path.is_file() {
        let why = if path.exists() { "not a file (an atlas is one HDF5 file)" } else { "no such file" };
        return Err(StoreError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, why)));
    }
    let f = crate::heap::open(path)?;
    crate::attrs::verify(path, &f)?;
    if attr_opt(path, &f, attr::SOFTWARE)?.as_deref() != Some(SOFTWARE) || f.attr(attr::X).is_err() {
        return Err(StoreError::format(path, "not an atlas"));
    }
    attr(path, &f, attr::SCENE)
}

/// Reads an atlas file. Every dataset is checked before it is used: its
/// shape against the grid and the other datasets, its size against the
/// file's (see [`crate::checked::MAX_EXPANSION`]), the sections' offsets against their
/// values; the whole against the memory available. A bad file is one
/// [`StoreError::Dataset`] naming the dataset (`up/flags: 59 rows, the grid
/// has 60`).
pub fn read(path: &Path) -> Result<Loaded, StoreError> {
    let fmt = |m: String| StoreError::format(path, m);
    let h = |e: hdf5::Error| StoreError::hdf5(path, e);
    if !path.exists() {
        return Err(StoreError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, "no such file")));
    }
    if !path.is_file() {
        return Err(fmt("not a file (an atlas is one HDF5 file)".into()));
    }
    let f = crate::heap::open(path)?;
    crate::attrs::verify(path, &f)?;
    let version = crate::attrs::optional::<u64>(path, &f, attr::LAYOUT_VERSION)?.unwrap_or(1);
    // Layout 3 by its version, or by its axis's checksum (a version lowered
    // by hand does not make a file of layout 3 one of layout 2).
    let x_checked = attr_opt(path, &f, attr::X)?
        .is_some_and(|x| f.dataset(&format!("{AXES}/{x}")).is_ok_and(|d| d.attr(attr::VALUES_CRC32).is_ok()));
    let ck = Checker { path, sealed: version >= 3 || x_checked, run: crate::checksum::run_of(&f) };
    // From layout 3 on the root's texts always have their checksum: one
    // deleted would let them be changed unseen.
    if ck.sealed && f.attr(attr::ATTRIBUTES_CRC32).is_err() {
        return Err(fmt(format!(
            "attribute {} of / is missing, which vibroatlas writes on every file of layout 3: the file was changed since vibroatlas wrote it",
            attr::ATTRIBUTES_CRC32
        )));
    }
    if attr_opt(path, &f, attr::SOFTWARE)?.as_deref() != Some(SOFTWARE) {
        return Err(fmt("not a vibroatlas file".into()));
    }
    // Curve and basin files say what they hold; an atlas does not.
    if let Some(content) = attr_opt(path, &f, curves::CONTENT_ATTR)? {
        let found = match content.as_str() {
            crate::basins::CONTENT => OtherKind::BasinsNotAtlas,
            _ => OtherKind::CurvesNotAtlas,
        };
        return Err(StoreError::Kind { path: path.display().to_string(), found });
    }
    if f.attr(attr::X).is_err() {
        return Err(fmt("not an atlas".into()));
    }
    // Curves the root names are there (their values: `read_curves`).
    if !f.link_exists(curves::GROUP) && crate::curve::named_by_root(path, &f)?.is_some() {
        return Err(crate::curve::curves_missing(path));
    }
    // A file another program wrote from an atlas (xarray's to_netcdf keeps
    // the attributes, not the layout): said so, not as a missing dataset.
    let x = attr(path, &f, attr::X)?;
    if !f.link_exists(AXES) || !f.group(AXES).is_ok_and(|g| g.link_exists(&x)) {
        return Err(fmt(format!(
            "not an atlas as vibroatlas writes it: it has the attributes of one but no {AXES}/{x} (written again by another program, such as xarray's to_netcdf?); open it with xarray, or use the file vibroatlas wrote"
        )));
    }
    let meta = read_meta(&ck, &f)?;
    let (nx, ny) = (meta.plane.x.count, meta.plane.y.count);
    let n = nx * ny;
    let (rows, columns) = (Dim(ny, "rows", "the grid has"), Dim(nx, "columns", "the grid has"));

    // Every dataset opened and checked before any is read.
    let sets = meta.sweeps.iter().map(|&sweep| open_sweep(&ck, &f, &meta, sweep)).collect::<Result<Vec<_>, _>>()?;
    let need: u64 = sets.iter().map(|s| s.bytes(n, meta.dim, meta.masses.len())).fold(0u64, u64::saturating_add);
    let have = available_memory();
    if need > have {
        return Err(fmt(format!(
            "reading it needs about {:.1} GiB, more than the {:.1} GiB of memory available",
            need as f64 / (1u64 << 30) as f64,
            have as f64 / (1u64 << 30) as f64
        )));
    }

    // The text tables that the file's readers (xarray, h5py) decode its codes by.
    for &sweep in &meta.sweeps {
        let g = f.group(sweep.name()).map_err(h)?;
        let mut labels = None;
        for table in [LABEL, NPQ, COMPONENT, IMPACT_COLUMN, MASS] {
            if g.link_exists(table) {
                let read = texts(&ck, &ck.open(&g, table)?)?;
                if table == LABEL {
                    labels = Some(read);
                }
            }
        }
        described_as_written(&ck, &f, &g, &meta, labels.as_deref())?;
        for mass in &meta.masses {
            let at = format!("{LEGEND}/{}/{mass}/label", sweep.name());
            if f.link_exists(&at) {
                texts(&ck, &ck.open(&f, &at)?)?;
            }
        }
    }
    let mut maps = Vec::new();
    for (&sweep, s) in meta.sweeps.iter().zip(&sets) {
        maps.push(Map { sweep, cells: read_cells(&ck, s, &meta)? });
    }
    // A cell never keeps more section points than the run's cap.
    for map in &maps {
        let kept = |c: &maps::CellData| {
            c.impact_sections.iter().map(solver::Points::len).fold(c.period_section.len(), usize::max)
        };
        if let Some(most) = map.cells.iter().flatten().map(kept).max().filter(|&k| k > meta.section_cap) {
            return Err(fmt(format!(
                "attribute {}: {}, but sweep {} keeps {most} section points in a cell: the file is damaged or was changed",
                attr::SECTION_CAP,
                meta.section_cap,
                map.sweep.name()
            )));
        }
    }
    let shard = match attr_opt(path, &f, attr::SHARD)? {
        Some(s) => Some(Shard::parse(&s).map_err(|e| fmt(e.to_string()))?),
        None => None,
    };
    let attractors = match f.group(ATTRACTORS) {
        Ok(g) => Some(read_attractors(&ck, &g, [rows, columns], &meta.masses)?),
        Err(_) => None,
    };
    // From layout 3 on the root says whether the file has attractors, and how sampled.
    let said = attr_opt(path, &f, attr::ATTRACTOR_SAMPLING)?;
    let found = attractors.as_ref().map(crate::write::sampling_text);
    if ck.sealed && said != found {
        let say = |s: &Option<String>| s.clone().unwrap_or_else(|| "none".into());
        return Err(fmt(format!(
            "attribute {} of / says attractors {}, the file holds {}: the file is damaged or was changed",
            attr::ATTRACTOR_SAMPLING,
            say(&said),
            say(&found)
        )));
    }
    // Layout 1 had no history: its command is the whole of it.
    let command = attr(path, &f, attr::COMMAND)?;
    let created = attr(path, &f, attr::CREATED)?;
    let history = match attr_opt(path, &f, attr::HISTORY)? {
        Some(text) => text.lines().map(str::to_string).collect(),
        None => vec![format!("{created}: {command}")],
    };
    let parent = parent(path, &f)?;
    let entries = entries(&ck, &f, &meta, parent.is_some())?;
    Ok(Loaded {
        atlas: Atlas { meta, maps, attractors, entries },
        info: RunInfo { command, run_time_s: required::<f64>(path, &f, attr::RUN_TIME_S)?, shard, history, parent },
        created,
    })
}

/// The atlas a zoom refined (root attributes `parent`, `parent_labels_crc32`, `parent_box`).
fn parent(path: &Path, f: &hdf5::File) -> Result<Option<crate::write::Parent>, StoreError> {
    let Some(parent) = attr_opt(path, f, attr::PARENT)? else { return Ok(None) };
    let crc = attr(path, f, attr::PARENT_LABELS_CRC32)?;
    let labels_crc32 = u32::from_str_radix(&crc, 16).map_err(|_| {
        StoreError::format(
            path,
            format!("attribute {}: '{crc}' is not 8 hexadecimal digits", attr::PARENT_LABELS_CRC32),
        )
    })?;
    Ok(Some(crate::write::Parent { path: parent, labels_crc32, region: attr(path, f, attr::PARENT_BOX)? }))
}

/// The states a zoom's chains entered its plane with (its continuation
/// sweeps' `entry_state`, which a file with a parent must have): NaN rows
/// are chains from the scene's initial state.
fn entries(ck: &Checker, f: &hdf5::File, meta: &Meta, zoom: bool) -> Result<maps::Entries, StoreError> {
    let mut entries = maps::Entries::default();
    let lines = meta.plane.lines();
    for &sweep in meta.sweeps.iter().filter(|&&s| s != SweepKind::Fresh) {
        let at = format!("{}/{}", sweep.name(), var::ENTRY_STATE);
        if !f.link_exists(&at) {
            if zoom {
                return Err(
                    ck.bad(&at, "missing, which a zoom's file has: the file was changed since vibroatlas wrote it")
                );
            }
            continue;
        }
        let g = f.group(sweep.name()).map_err(|e| StoreError::hdf5(ck.path, e))?;
        let d = ck.shaped(
            &g,
            var::ENTRY_STATE,
            &[Dim(lines, "lines", "the plane has"), Dim(meta.dim, "components", "the state has")],
        )?;
        let values = ck.raw::<f64>(&d)?;
        for (line, state) in values.chunks(meta.dim).enumerate() {
            if state.iter().all(|v| v.is_finite()) {
                entries.0.insert((sweep, line), state.to_vec());
            }
        }
    }
    Ok(entries)
}

/// What xarray and h5py read a sweep group `g` of the atlas `f` (of `meta`)
/// by, as vibroatlas wrote it (issue 42, R5): its coordinates' `units`,
/// `long_name` and `symbol`, those of the root's coordinate of the same
/// axis (checked by its `attributes_crc32`), and then their own checksum;
/// each label code's CF `flag_meanings`, its sweep's label table (`labels`,
/// where the sweep has one). A difference is the error `inspect --verify`
/// gives for it, naming the attribute.
fn described_as_written(
    ck: &Checker,
    f: &hdf5::File,
    g: &hdf5::Group,
    meta: &Meta,
    labels: Option<&[String]>,
) -> Result<(), StoreError> {
    let differs = |object: &str, attribute: &str| crate::verify::differs(ck.path, object, attribute);
    for axis in [&meta.plane.x.name, &meta.plane.y.name] {
        if !g.link_exists(axis) || !f.link_exists(axis) {
            continue;
        }
        let (own, root) = (ck.open(g, axis)?, ck.open(f, axis)?);
        for name in [attr::UNITS, attr::LONG_NAME, attr::SYMBOL] {
            if attr_opt(ck.path, &own, name)? != attr_opt(ck.path, &root, name)? {
                return Err(differs(&own.name(), name));
            }
        }
        crate::attrs::verify(ck.path, &own)?;
    }
    let Some(labels) = labels else { return Ok(()) };
    let table = labels.join(" ");
    for mass in &meta.masses {
        let name = label_code(mass);
        if !g.link_exists(&name) {
            continue;
        }
        let d = ck.open(g, &name)?;
        if attr_opt(ck.path, &d, attr::FLAG_MEANINGS)?.is_some_and(|m| m != table) {
            return Err(differs(&d.name(), attr::FLAG_MEANINGS));
        }
    }
    Ok(())
}

/// The axis `name` of the `/axes` group: 1 to `MAX_COUNT` values, finite ends.
fn read_axis(ck: &Checker, axes: &hdf5::Group, name: &str) -> Result<Axis, StoreError> {
    let d = ck.open(axes, name)?;
    crate::attrs::verify(ck.path, &d)?;
    let at = format!("{AXES}/{name}");
    let count = d.size();
    if count == 0 || count > maps::MAX_COUNT {
        return Err(ck.bad(&at, format!("{count} values; an axis has 1 to {}", maps::MAX_COUNT)));
    }
    let end = |which: &str| -> Result<f64, StoreError> {
        let v = required::<f64>(ck.path, &d, which)?;
        if !v.is_finite() {
            return Err(ck.bad(&at, format!("attribute {which} is {v}, not a finite number")));
        }
        Ok(v)
    };
    // Values that are numbers (a span beyond the largest number makes them
    // NaN and infinite, which no drawing or search can place).
    let mut axis =
        Axis::new(name, end(attr::START)?, end(attr::STOP)?, count).checked(&at).map_err(|e| ck.bad(&at, e.message))?;
    if let Some(counts) = crate::attrs::values::<u64>(ck.path, &d, attr::LATTICE_COUNT)? {
        let ends = |which: &str| -> Result<Vec<f64>, StoreError> {
            let v = crate::attrs::values::<f64>(ck.path, &d, which)?.unwrap_or_default();
            if v.len() != counts.len() || v.iter().any(|x| !x.is_finite()) {
                let what = format!(
                    "attribute {which}: {} finite values expected, one per level of {}",
                    counts.len(),
                    attr::LATTICE_COUNT
                );
                return Err(ck.bad(&at, what));
            }
            Ok(v)
        };
        let (starts, stops) = (ends(attr::LATTICE_START)?, ends(attr::LATTICE_STOP)?);
        if counts.is_empty() || counts.iter().any(|c| !(2..=maps::MAX_COUNT as u64).contains(c)) {
            let what = format!(
                "attribute {}: {counts:?}; each level has 2 to {} values",
                attr::LATTICE_COUNT,
                maps::MAX_COUNT
            );
            return Err(ck.bad(&at, what));
        }
        let levels = (0..counts.len()).map(|k| (starts[k], stops[k], counts[k] as usize)).collect();
        axis.lattice = Some(maps::Lattice { levels });
    }
    // The values stored are the axis's, bit for bit: an edited end is not a new grid.
    let stored = ck.raw::<f64>(&d)?;
    if stored.iter().zip(axis.values()).any(|(a, b)| a.to_bits() != b.to_bits()) {
        return Err(ck.bad(
            &at,
            format!(
                "its values are not those of its attributes {}, {} and its {count} points: the file is damaged or was changed",
                attr::START,
                attr::STOP
            ),
        ));
    }
    Ok(axis)
}

/// The names of the scene's masses, one per two state components (layout 1
/// did not name them: `mass1`, …).
fn state_masses(path: &Path, f: &hdf5::File, dim: usize) -> Result<Vec<String>, StoreError> {
    let names = match attr_opt(path, f, attr::STATE_MASSES)? {
        Some(s) => list(&s),
        None => (1..=dim / 2).map(|i| format!("mass{i}")).collect(),
    };
    if names.len() * 2 != dim {
        return Err(StoreError::format(
            path,
            format!(
                "attribute {}: {} masses, but the state dimension {} is {dim}",
                attr::STATE_MASSES,
                names.len(),
                attr::DIM
            ),
        ));
    }
    Ok(names)
}

/// The description of the atlas in `f`: its plane, sweeps, masses, stops
/// and settings, every attribute checked.
fn read_meta(ck: &Checker, f: &hdf5::File) -> Result<Meta, StoreError> {
    let path = ck.path;
    let fmt = |m: String| StoreError::format(path, m);
    let h = |e: hdf5::Error| StoreError::hdf5(path, e);
    let axes = f.group(AXES).map_err(h)?;
    let axis = |name: &str| read_axis(ck, &axes, name);
    let x = axis(&attr(path, f, attr::X)?)?;
    let y = axis(&attr(path, f, attr::Y)?)?;
    let version = crate::attrs::optional::<u64>(path, f, attr::LAYOUT_VERSION)?.unwrap_or(1);
    if version > LAYOUT_VERSION {
        return Err(fmt(format!(
            "layout version {version}, newer than this vibroatlas reads ({LAYOUT_VERSION}); use a newer vibroatlas"
        )));
    }
    let dim = required::<u64>(path, f, attr::DIM)?;
    if dim == 0 || dim % 2 != 0 || dim > MAX_DIM as u64 {
        return Err(fmt(format!("attribute {}: {dim}; the state dimension is even, 2 to {MAX_DIM}", attr::DIM)));
    }
    let dim = dim as usize;
    let along = maps::read::<Along>(&attr(path, f, attr::ALONG)?, "along").map_err(|e| fmt(e.to_string()))?;
    let sweeps = list(&attr(path, f, attr::SWEEPS)?)
        .iter()
        .map(|s| {
            SweepKind::parse(s).ok_or_else(|| {
                fmt(format!("attribute {} of /: unknown sweep '{s}' (the sweeps are fresh, up, down)", attr::SWEEPS))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    if sweeps.is_empty() {
        return Err(fmt(format!(
            "attribute {} of /: empty; an atlas has one sweep at least (fresh, up, down)",
            attr::SWEEPS
        )));
    }
    if let Some(twice) = sweeps.iter().enumerate().find(|(i, s)| sweeps[..*i].contains(s)) {
        return Err(fmt(format!("attribute {}: sweep {} is listed twice", attr::SWEEPS, twice.1.name())));
    }
    if let Some(missing) = sweeps.iter().find(|s| !f.link_exists(s.name())) {
        let what =
            format!("attribute {} of /: names sweep {}, whose group the file lacks", attr::SWEEPS, missing.name());
        return Err(fmt(what));
    }
    if let Some(extra) = SweepKind::ALL.iter().find(|s| !sweeps.contains(s) && f.link_exists(s.name())) {
        let what = format!("holds sweep {}, which its attribute {} does not name", extra.name(), attr::SWEEPS);
        return Err(fmt(what));
    }
    let masses = list(&attr(path, f, attr::MASSES)?);
    // Layout 1 did not name the stops of each label.
    let n_masses = masses.len();
    let stops_of = |name: &str| -> Result<Vec<String>, StoreError> {
        let v: Vec<String> =
            attr_opt(path, f, name)?.map(|s| s.split(',').map(str::to_string).collect()).unwrap_or_default();
        Ok((0..n_masses).map(move |i| v.get(i).cloned().unwrap_or_default()).collect())
    };
    let label_stops: Vec<[String; 2]> =
        stops_of(attr::P_STOPS)?.into_iter().zip(stops_of(attr::Q_STOPS)?).map(|(p, q)| [p, q]).collect();
    let scene_toml = attr(path, f, attr::SCENE)?;
    // Parsed once: it fixes the normals, laws and notation read below.
    let scene = scene::Scene::parse(&scene_toml);
    let notation = notation(path, f, scene.as_ref().ok(), [&x.name, &y.name])?;
    let stops = list(&attr(path, f, attr::STOPS)?);
    let state_masses = state_masses(path, f, dim)?;
    let stop_normals = stop_normals(path, f, scene.as_ref(), dim / 2)?;
    if stop_normals.len() != stops.len() || stop_normals.iter().any(|n| n.len() != dim / 2) {
        return Err(fmt(format!(
            "attribute {}: {} normals for {} stops of {} masses",
            attr::STOP_NORMALS,
            stop_normals.len(),
            stops.len(),
            dim / 2
        )));
    }
    let stop_laws = laws_of(attr_opt(path, f, attr::STOP_LAWS)?.as_deref(), scene.as_ref()).map_err(fmt)?;
    if stop_laws.len() != stops.len() {
        return Err(fmt(format!("attribute {}: {} laws for {} stops", attr::STOP_LAWS, stop_laws.len(), stops.len())));
    }
    for (mass, pq) in masses.iter().zip(&label_stops) {
        for (what, name) in [attr::P_STOPS, attr::Q_STOPS].into_iter().zip(pq) {
            if !name.is_empty() && !stops.contains(name) {
                let name = scene::excerpt(name, 40);
                return Err(fmt(format!(
                    "attribute {what}: the stop of mass {mass} is {name}, which is not among the stops"
                )));
            }
        }
    }
    for (what, names) in [(attr::MASSES, &masses), (attr::STOPS, &stops)] {
        if let Some(twice) = names.iter().enumerate().find_map(|(i, n)| names[..i].contains(n).then_some(n)) {
            return Err(fmt(format!("attribute {what}: {twice} is named twice")));
        }
    }
    let quantities = quantities(path, f, &sweeps)?;
    // None that is an axis of the plane (which a run refuses). A parameter
    // may be set twice, the last value taken: a stored cell's file's value,
    // then the one given to a run from it (`sweep --from … --set`).
    let overrides = pairs(&attr(path, f, attr::OVERRIDES)?).map_err(fmt)?;
    if let Some((name, _)) = overrides.iter().find(|(n, _)| [&x, &y].into_iter().any(|a| a.count > 1 && a.name == *n)) {
        return Err(fmt(format!("attribute {}: {name} is an axis of the plane", attr::OVERRIDES)));
    }
    let preset = {
        let name = attr(path, f, attr::PRESET)?;
        solver::Preset::parse(&name).ok_or_else(|| fmt(format!("unknown preset '{name}'")))?
    };
    // Knobs a run takes (within their limits, on the preset's values).
    let accuracy = knobs(&attr(path, f, attr::ACCURACY)?).map_err(fmt)?;
    let mut run = solver::Accuracy::preset(preset);
    for &(k, v) in &accuracy {
        run.set(k, v).map_err(|e| match e {
            solver::SolverError::Accuracy { field, message } => {
                fmt(format!("attribute {}: {field}: {message}", attr::ACCURACY))
            }
            e => fmt(format!("attribute {}: {e}", attr::ACCURACY)),
        })?;
    }
    Ok(Meta {
        scene_name: attr(path, f, attr::SCENE_NAME)?,
        scene_toml: scene_toml.clone(),
        overrides,
        preset,
        accuracy,
        integrator: {
            let name = attr(path, f, attr::INTEGRATOR)?;
            solver::Method::parse(&name).ok_or_else(|| fmt(format!("unknown integrator '{name}'")))?
        },
        plane: Plane { x, y, along },
        sweeps,
        masses,
        label_stops,
        state_masses,
        stops,
        stop_normals,
        stop_laws,
        dim,
        section_cap: {
            // Read as signed, so that a negative value is refused rather than converted to 0.
            let cap = required::<i64>(path, f, attr::SECTION_CAP)?;
            usize::try_from(cap).ok().filter(|&c| c <= maps::MAX_SECTION_CAP).ok_or_else(|| {
                fmt(format!("attribute {}: {cap}; it is 0 to {}", attr::SECTION_CAP, maps::MAX_SECTION_CAP))
            })?
        },
        notation,
        quantities,
    })
}

/// The quantities each sweep stores (none for a file before them), their
/// symbol, long name and units read from the first sweep's variables.
fn quantities(path: &Path, f: &hdf5::File, sweeps: &[SweepKind]) -> Result<Vec<maps::Quantity>, StoreError> {
    let names = list(&attr_opt(path, f, attr::QUANTITIES)?.unwrap_or_default());
    let first = f.group(sweeps[0].name()).map_err(|e| StoreError::hdf5(path, e))?;
    names
        .into_iter()
        .map(|name| {
            let d = first.dataset(&name).map_err(|_| {
                StoreError::format(
                    path,
                    format!("attribute {} of /: names {name}, which {} lacks", attr::QUANTITIES, sweeps[0].name()),
                )
            })?;
            let text = |key: &str| crate::attrs::required_text(path, &d, key);
            Ok(maps::Quantity { symbol: text("symbol")?, long_name: text("long_name")?, units: text("units")?, name })
        })
        .collect()
}

/// The datasets of one sweep, opened and checked against the grid.
fn open_sweep(ck: &Checker, f: &hdf5::File, meta: &Meta, sweep: SweepKind) -> Result<SweepSets, StoreError> {
    let h = |e: hdf5::Error| StoreError::hdf5(ck.path, e);
    // The sweeps whose reasons were written with their numbers.
    let detailed = list(&attr_opt(ck.path, f, attr::REASON_DETAILS)?.unwrap_or_default());
    let (nx, ny, dim) = (meta.plane.x.count, meta.plane.y.count, meta.dim);
    let n = nx * ny;
    let (rows, columns) = (Dim(ny, "rows", "the grid has"), Dim(nx, "columns", "the grid has"));
    let g = f.group(sweep.name()).map_err(h)?;
    let plane = |name: &str| ck.shaped(&g, name, &[rows, columns]);
    // Files written before the stability datasets existed have none; a file
    // of layout 3 has them.
    let optional = |name: &str| match (g.link_exists(name), ck.sealed) {
        (true, _) => plane(name).map(Some),
        (false, true) => Err(ck.bad(
            &format!("{}/{name}", sweep.name()),
            "missing, which every file of layout 3 has: the file was changed since vibroatlas wrote it",
        )),
        (false, false) => Ok(None),
    };
    let section = |name: &str, cols: usize| -> Result<Section, StoreError> {
        let s = g.group(&format!("{SECTIONS}/{name}")).map_err(h)?;
        let offsets = ck.shaped(&s, var::OFFSETS, &[Dim(n + 1, "entries", "the grid's cells + 1 are")])?;
        let values = ck.open(&s, var::VALUES)?;
        let shape = values.shape();
        if shape.len() != 2 || shape[1] != cols {
            return Err(ck.bad(&values.name(), format!("shape {shape:?}, expected [points, {cols}]")));
        }
        Ok(Section { points: shape[0], cols, values, offsets })
    };
    Ok(SweepSets {
        class: plane(var::CLASS)?,
        symmetry: plane(var::SYMMETRY)?,
        flags: plane(var::FLAGS)?,
        final_state: ck.shaped(&g, var::FINAL_STATE, &[rows, columns, Dim(dim, "components", "the state has")])?,
        lyapunov: optional(var::LYAPUNOV)?,
        multiplier: optional(var::MULTIPLIER)?,
        periods: plane(var::PERIODS)?,
        events: plane(var::EVENTS)?,
        labels: meta
            .masses
            .iter()
            .map(|m| ck.shaped(&g, &label(m), &[rows, columns, Dim(3, "counts", "n, p, q are")]))
            .collect::<Result<_, _>>()?,
        quantities: meta.quantities.iter().map(|q| plane(&q.name)).collect::<Result<_, _>>()?,
        reasons: if g.link_exists(REASON_CODE) {
            let table = ck.open(&g, REASON)?;
            if table.ndim() != 1 || table.size() > n {
                return Err(
                    ck.bad(&table.name(), format!("shape {:?}: not a table of at most {n} reasons", table.shape()))
                );
            }
            let detail = match (g.link_exists(REASON_DETAIL), detailed.iter().any(|s| s == sweep.name())) {
                (true, _) => Some(ck.open(&g, REASON_DETAIL)?),
                (false, false) => None,
                (false, true) => {
                    return Err(ck.bad(
                        &format!("{}/{REASON_DETAIL}", sweep.name()),
                        format!(
                        "missing, which the attribute {} of / names: the file was changed since vibroatlas wrote it",
                        attr::REASON_DETAILS
                    ),
                    ))
                }
            };
            Some(Reasons { table, codes: plane(REASON_CODE)?, detail })
        } else {
            None
        },
        period: section(PERIOD_SECTION, dim)?,
        impacts: meta.stops.iter().map(|s| section(s, dim + 1)).collect::<Result<_, _>>()?,
    })
}

/// The cells of one sweep, read from its checked datasets.
fn read_cells(ck: &Checker, s: &SweepSets, meta: &Meta) -> Result<Vec<Option<CellData>>, StoreError> {
    let fmt = |m: String| StoreError::format(ck.path, m);
    let (nx, ny, dim) = (meta.plane.x.count, meta.plane.y.count, meta.dim);
    let n = nx * ny;
    let n_stops = meta.stops.len();
    let class = ck.raw::<u8>(&s.class)?;
    if let Some(i) = class.iter().position(|&c| class_of(c).is_none() && c != NOT_COMPUTED) {
        return Err(ck.bad(
            &s.class.name(),
            format!("code {} at ({}, {}) is not a class (0 to 3, or {NOT_COMPUTED})", class[i], i / nx, i % nx),
        ));
    }
    let sym = ck.raw::<u8>(&s.symmetry)?;
    let flags = ck.raw::<u32>(&s.flags)?;
    let fs = ck.raw::<f64>(&s.final_state)?;
    // A computed cell's state is a number (the next cell of its chain, and
    // any run from it, starts there).
    if let Some(i) =
        (0..n).find(|&i| class_of(class[i]).is_some() && fs[i * dim..(i + 1) * dim].iter().any(|v| !v.is_finite()))
    {
        return Err(ck.bad(
            &s.final_state.name(),
            format!("the state of cell ({}, {}) holds numbers that are not finite", i / nx, i % nx),
        ));
    }
    let scalar = |d: &Option<hdf5::Dataset>| d.as_ref().map_or_else(|| Ok(vec![f64::NAN; n]), |d| ck.raw::<f64>(d));
    let (lyapunov, multiplier) = (scalar(&s.lyapunov)?, scalar(&s.multiplier)?);
    let finite = |v: f64| v.is_finite().then_some(v);
    let (periods, events) = (ck.raw::<u64>(&s.periods)?, ck.raw::<u64>(&s.events)?);
    let labels = s.labels.iter().map(|d| ck.raw::<u16>(d)).collect::<Result<Vec<_>, _>>()?;
    // A periodic cell's period is at least one; any other class stores no counts.
    for (d, l) in s.labels.iter().zip(&labels) {
        let wrong = (0..n).find(|&i| match class_of(class[i]) {
            Some(Class::Periodic) => l[3 * i] == 0,
            Some(_) => l[3 * i..3 * i + 3] != [0, 0, 0],
            None => false,
        });
        if let Some(i) = wrong {
            let (c, npq) = (class_of(class[i]).map_or("", Class::name), &l[3 * i..3 * i + 3]);
            return Err(ck.bad(
                &d.name(),
                format!("cell ({}, {}) is {c} with counts {npq:?}, which no label has", i / nx, i % nx),
            ));
        }
    }
    let quantities = s.quantities.iter().map(|d| ck.raw::<f64>(d)).collect::<Result<Vec<_>, _>>()?;
    let section = |sec: &Section| -> Result<(Vec<f64>, Vec<usize>, usize), StoreError> {
        let offsets = ck.raw::<u64>(&sec.offsets)?;
        let at = sec.offsets.name();
        if offsets[0] != 0 {
            return Err(ck.bad(&at, format!("starts at {}, not 0", offsets[0])));
        }
        for (i, w) in offsets.windows(2).enumerate() {
            if w[1] < w[0] {
                return Err(ck.bad(&at, format!("entry {} ({}) is below entry {i} ({})", i + 1, w[1], w[0])));
            }
            if w[1] > sec.points as u64 {
                return Err(
                    ck.bad(&at, format!("entry {} is {}, beyond the {} points of values", i + 1, w[1], sec.points))
                );
            }
        }
        if offsets[n] != sec.points as u64 {
            return Err(ck.bad(&at, format!("ends at {}, but values has {} points", offsets[n], sec.points)));
        }
        let values = ck.raw::<f64>(&sec.values)?;
        data(ck, &sec.values, crate::checksum::bytes_of(&values))?;
        Ok((values, offsets.into_iter().map(|o| o as usize).collect(), sec.cols))
    };
    // Rows of the section's width: never refused.
    let rows = |sec: &(Vec<f64>, Vec<usize>, usize), i: usize| -> solver::Points {
        let (v, o, cols) = sec;
        solver::Points::from_rows((o[i]..o[i + 1]).map(|r| &v[r * cols..(r + 1) * cols])).unwrap_or_default()
    };
    let period = section(&s.period)?;
    let impacts = s.impacts.iter().map(section).collect::<Result<Vec<_>, _>>()?;
    let reasons = s.reasons.as_ref().map(|r| reasons(ck, r)).transpose()?;
    let reason =
        |i: usize| reasons.as_ref().and_then(|(table, codes)| table.get(usize::try_from(codes[i]).ok()?).cloned());
    let mut cells = Vec::new();
    cells.try_reserve_exact(n).map_err(|_| fmt(format!("{n} cells do not fit in memory")))?;
    cells.extend((0..n).map(|i| {
        class_of(class[i]).map(|c| CellData {
            class: c,
            labels: labels.iter().map(|l| label_of(c, [l[3 * i], l[3 * i + 1], l[3 * i + 2]])).collect(),
            chatter: flags_of(flags[i], n_stops).0,
            sticking: flags_of(flags[i], n_stops).1,
            symmetry: symmetry_of(sym[i]),
            lyapunov: finite(lyapunov[i]),
            multiplier: finite(multiplier[i]),
            final_state: fs[i * dim..(i + 1) * dim].to_vec(),
            periods: periods[i],
            events: events[i],
            period_section: rows(&period, i),
            impact_sections: impacts.iter().map(|s| rows(s, i)).collect(),
            reason: reason(i).map(Box::new),
            quantities: quantities.iter().map(|q| q[i]).collect(),
        })
    }));
    Ok(cells)
}

/// The `/attractors` group of a plane of `[rows, columns]` and the labelled
/// `masses`, checked: every dataset on the grid, the same slots for the
/// fractions and the codes, every count within the slots and every code in
/// the label table.
fn read_attractors(
    ck: &Checker,
    g: &hdf5::Group,
    [rows, columns]: [Dim; 2],
    masses: &[String],
) -> Result<maps::AttractorMap, StoreError> {
    let n = rows.0 * columns.0;
    let count_set = ck.shaped(g, var::COUNT, &[rows, columns])?;
    let fraction_set = ck.open(g, var::FRACTION)?;
    let slots = match fraction_set.shape().as_slice() {
        [_, _, k] => *k,
        shape => return Err(ck.bad(&fraction_set.name(), format!("shape {shape:?}, expected [rows, columns, slots]"))),
    };
    let slot = Dim(slots, "slots", "fraction has");
    let fraction_set = ck.shaped(g, var::FRACTION, &[rows, columns, slot])?;
    let table_set = ck.open(g, LABEL)?;
    let code_sets =
        masses.iter().map(|m| ck.shaped(g, &label_code(m), &[rows, columns, slot])).collect::<Result<Vec<_>, _>>()?;
    let count = ck.raw::<u8>(&count_set)?;
    let fraction = ck.raw::<f64>(&fraction_set)?;
    let table = texts(ck, &table_set)?;
    let mut codes = Vec::new();
    for d in &code_sets {
        let c = ck.raw::<i16>(d)?;
        if let Some(bad) = c.iter().find(|&&c| c < -1 || c as i64 >= table.len() as i64) {
            return Err(ck.bad(&d.name(), format!("code {bad} is not in the label table of {} labels", table.len())));
        }
        codes.push(c);
    }
    if let Some(i) = count.iter().position(|&c| c as usize > slots) {
        return Err(ck.bad(
            &count_set.name(),
            format!("{} attractors at ({}, {}), more than the {slots} slots", count[i], i / columns.0, i % columns.0),
        ));
    }
    let labels = table
        .iter()
        .map(|t| t.parse::<solver::Label>().map_err(|e| ck.bad(&table_set.name(), e)))
        .collect::<Result<Vec<_>, _>>()?;
    let label = |c: i16| usize::try_from(c).ok().and_then(|c| labels.get(c).copied());
    // Each attractor's first section points (files before them have none).
    let (section, points, dim) = match g.link_exists(var::SECTION) {
        false => (Vec::new(), 0, 0),
        true => {
            let d = ck.open(g, var::SECTION)?;
            let (points, dim) = match d.shape().as_slice() {
                [_, _, _, p, c] => (*p, *c),
                shape => {
                    return Err(ck.bad(
                        &d.name(),
                        format!("shape {shape:?}, expected [rows, columns, slots, points, components]"),
                    ))
                }
            };
            let d = ck.shaped(
                g,
                var::SECTION,
                &[rows, columns, slot, Dim(points, "points", "section has"), Dim(dim, "components", "section has")],
            )?;
            (ck.raw::<f64>(&d)?, points, dim)
        }
    };
    let section_of = |i: usize, k: usize| -> Vec<Vec<f64>> {
        if section.is_empty() {
            return Vec::new();
        }
        let at = &section[(i * slots + k) * points * dim..][..points * dim];
        at.chunks(dim).take_while(|p| !p.iter().all(|v| v.is_nan())).map(<[f64]>::to_vec).collect()
    };
    let mut cells = Vec::with_capacity(n);
    for i in 0..n {
        let mut found = Vec::with_capacity(count[i] as usize);
        for k in 0..count[i] as usize {
            let of_masses =
                codes.iter().map(|c| label(c[i * slots + k])).collect::<Option<Vec<_>>>().ok_or_else(|| {
                    ck.bad(&table_set.name(), format!("attractor {k} of cell {i} has a mass without a label"))
                })?;
            found.push(maps::CellAttractor {
                labels: of_masses,
                fraction: fraction[i * slots + k],
                section: section_of(i, k),
            });
        }
        cells.push((count[i] > 0).then_some(found));
    }
    let samples = required::<u64>(ck.path, g, attr::SAMPLES)? as usize;
    let seed = required::<u64>(ck.path, g, attr::SEED)?;
    // Each fraction is a count of the samples over their number, and the
    // counts of a cell add up to at most that number.
    let whole = |f: f64| {
        let k = (f * samples as f64).round();
        (k >= 1.0 && k / samples as f64 == f).then_some(k as usize)
    };
    for (i, found) in cells.iter().enumerate() {
        let Some(found) = found else { continue };
        let counts: Option<Vec<usize>> = found.iter().map(|a| whole(a.fraction)).collect();
        if counts.is_none_or(|c| c.iter().sum::<usize>() > samples) {
            return Err(ck.bad(
                &fraction_set.name(),
                format!(
                    "the fractions of cell ({}, {}) are not counts of its {samples} samples (attribute {}): the file is damaged or was changed",
                    i / columns.0,
                    i % columns.0,
                    attr::SAMPLES
                ),
            ));
        }
    }
    Ok(maps::AttractorMap { samples, seed, cells })
}

/// The stops' normals of a file (stops × masses), or, in files written before
/// they were stored, those of its scene.
fn stop_normals(
    path: &Path,
    f: &hdf5::File,
    scene: Result<&scene::Scene, &scene::SceneError>,
    masses: usize,
) -> Result<Vec<Vec<f64>>, StoreError> {
    let fmt = |m: String| StoreError::format(path, m);
    if let Some(flat) = crate::attrs::values::<f64>(path, f, attr::STOP_NORMALS)? {
        if masses == 0 || flat.len() % masses != 0 {
            return Err(fmt(format!(
                "{}: {} values, not a multiple of {masses} masses",
                attr::STOP_NORMALS,
                flat.len()
            )));
        }
        let normals: Vec<Vec<f64>> = flat.chunks(masses).map(<[f64]>::to_vec).collect();
        // The stored scene (checksummed with the root's texts) fixes them.
        if let Ok(scene) = scene {
            if scene.stop_normals() != normals {
                return Err(fmt(format!(
                    "attribute {}: not the normals of the stored scene's stops: the file is damaged or was changed",
                    attr::STOP_NORMALS
                )));
            }
        }
        return Ok(normals);
    }
    let scene = scene.map_err(|e| fmt(format!("the stored scene: {e}")))?;
    Ok(scene.stop_normals())
}

/// Which contact law each stop of a file obeys: its `stop_laws` attribute
/// (`stored`, comma-separated names), which must be the laws of the stored
/// scene `scene_toml`; in files written before it was stored, those of the
/// scene. The error names the attribute and what is wrong with it.
pub fn stop_laws(stored: Option<&str>, scene_toml: &str) -> Result<Vec<scene::LawKind>, String> {
    laws_of(stored, scene::Scene::parse(scene_toml).as_ref())
}

/// [`stop_laws`] of the stored scene, parsed (or why it does not parse).
fn laws_of(
    stored: Option<&str>,
    scene: Result<&scene::Scene, &scene::SceneError>,
) -> Result<Vec<scene::LawKind>, String> {
    let Some(text) = stored else {
        return scene.map(|s| s.stop_laws()).map_err(|e| format!("the stored scene: {e}"));
    };
    let laws = list(text)
        .iter()
        .map(|name| {
            scene::LawKind::parse(name)
                .ok_or_else(|| format!("attribute {}: {}", attr::STOP_LAWS, scene::LawKind::expected(name)))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // The stored scene (checksummed with the root's texts) fixes them.
    match scene {
        Ok(scene) if scene.stop_laws() != laws => Err(format!(
            "attribute {}: not the laws of the stored scene's stops: the file is damaged or was changed",
            attr::STOP_LAWS
        )),
        _ => Ok(laws),
    }
}

/// How the parameters are written: as the stored scene says (in files
/// written before scenes declared symbols, by their names:
/// [`scene::symbol_of`]), and each axis as its root coordinate's `symbol` and
/// `long_name` say, where it has them (files written before them do not; the
/// `long_name` `parameter <name>` says nothing more than the name).
fn notation(
    path: &Path,
    f: &hdf5::File,
    scene: Option<&scene::Scene>,
    axes: [&str; 2],
) -> Result<Vec<maps::Notation>, StoreError> {
    let mut notation = scene.map(maps::Notation::of_scene).unwrap_or_default();
    for name in axes {
        let Ok(d) = f.dataset(name) else { continue };
        crate::attrs::verify(path, &d)?;
        let Some(symbol) = attr_opt(path, &d, attr::SYMBOL)? else {
            continue;
        };
        let long_name = attr_opt(path, &d, attr::LONG_NAME)?.filter(|l| *l != crate::write::generic_long_name(name));
        match notation.iter_mut().find(|n| n.name == name) {
            Some(n) => {
                n.symbol = symbol;
                n.long_name = long_name;
            }
            None => notation.push(maps::Notation { name: name.to_string(), symbol, long_name }),
        }
    }
    Ok(notation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::write::{write, RunInfo};

    /// An atlas of `scene_toml` (the dry-friction scene, or one like it)
    /// over (omega, fk), nothing computed.
    fn atlas(scene_toml: &str) -> Atlas {
        let scene = scene::Scene::parse(scene_toml).unwrap();
        let plane =
            Plane::new(Axis::parse("omega=1:8:4", "x").unwrap(), Axis::parse("fk=0.01:0.1:3", "y").unwrap(), Along::X)
                .unwrap();
        Atlas::new(Meta {
            scene_name: scene.name().into(),
            scene_toml: scene_toml.into(),
            overrides: Vec::new(),
            preset: solver::Preset::Standard,
            accuracy: Vec::new(),
            integrator: solver::Method::Exact,
            plane,
            sweeps: vec![SweepKind::Up, SweepKind::Down],
            masses: vec!["M1".into()],
            state_masses: vec!["M1".into(), "M2".into()],
            label_stops: vec![["right".into(), "left".into()]],
            stops: vec!["right".into(), "left".into()],
            stop_normals: scene.stop_normals(),
            stop_laws: scene.stop_laws(),
            dim: 4,
            section_cap: 16,
            notation: maps::Notation::of_scene(&scene),
            quantities: Vec::new(),
        })
    }

    fn text(d: &hdf5::Dataset, name: &str) -> String {
        attr(Path::new("test"), d, name).unwrap()
    }

    /// The axis coordinates of every group carry their parameter's `symbol`
    /// and `long_name`, and the file reads back into the same notation; a
    /// file written before them (no `symbol`, `long_name = "parameter
    /// <name>"`) reads by its scene, or by the names' Greek rule.
    #[test]
    fn axes_carry_symbols_and_long_names_and_older_files_still_read() {
        let dir = crate::testing::scratch("notation");
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/dry-friction.toml");
        let toml = std::fs::read_to_string(path).unwrap();
        let info = RunInfo { command: "test".into(), run_time_s: 0.0, shard: None, history: Vec::new(), parent: None };
        let out = dir.join("a.h5");
        let a = atlas(&toml);
        write(&out, &a, &info, 1).unwrap();
        {
            let f = hdf5::File::open(&out).unwrap();
            for g in ["", "up/", "down/"] {
                let (omega, fk) = (f.dataset(&format!("{g}omega")).unwrap(), f.dataset(&format!("{g}fk")).unwrap());
                assert_eq!(text(&omega, attr::SYMBOL), "ω", "{g}");
                assert_eq!(text(&omega, attr::LONG_NAME), "forcing frequency", "{g}");
                assert_eq!(text(&fk, attr::SYMBOL), "f_k", "{g}");
                assert_eq!(text(&fk, attr::LONG_NAME), "kinetic friction force", "{g}");
                assert_eq!(text(&fk, "units"), "1", "{g}");
            }
        }
        let back = read(&out).unwrap().atlas;
        assert_eq!(back.meta, a.meta);
        assert_eq!(back.meta.symbol("fk"), "f_k");
        assert_eq!(back.meta.symbol("fs_ratio"), "f_s/f_k", "not an axis: from the stored scene");
        assert_eq!(back.meta.long_name("zeta"), Some("damping ratio of M1"));

        // A scene that declares nothing, written as before: no symbol, the
        // generic long name.
        let plain: String = toml
            .lines()
            .map(|l| match l.find(", symbol = ") {
                Some(i) => format!("{} }}", &l[..i]),
                None => l.to_string(),
            })
            .map(|l| l.replace(", doc = \"kinetic friction force\"", ""))
            .collect::<Vec<_>>()
            .join("\n");
        let old = dir.join("old.h5");
        let a = atlas(&plain);
        assert_eq!(a.meta.long_name("fk"), None);
        write(&old, &a, &info, 1).unwrap();
        {
            let f = hdf5::File::open_rw(&old).unwrap();
            assert_eq!(text(&f.dataset("up/fk").unwrap(), attr::LONG_NAME), "parameter fk");
            for g in ["", "up/", "down/"] {
                for name in ["omega", "fk"] {
                    // Written before symbols, and before the checksum of the texts.
                    let d = f.dataset(&format!("{g}{name}")).unwrap();
                    d.delete_attr(attr::SYMBOL).unwrap();
                    d.delete_attr(attr::ATTRIBUTES_CRC32).unwrap();
                }
            }
        }
        let back = read(&old).unwrap().atlas;
        assert_eq!(back.meta, a.meta);
        assert_eq!(back.meta.symbol("omega"), "ω");
        assert_eq!(back.meta.symbol("fk"), "fk");
        assert_eq!(back.meta.symbol("mu_k"), "μ_k");
        assert_eq!(back.meta.long_name("fk"), None);
        assert_eq!(back.meta.long_name("omega"), Some("forcing frequency"), "the doc");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Each stop's law comes from the file's `stop_laws`, held to the stored
    /// scene's; a file written before it has its scene's.
    #[test]
    fn stop_laws_are_the_stored_scenes() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
        let soft = std::fs::read_to_string(root.join("soft-stop.toml")).unwrap();
        let rigid = std::fs::read_to_string(root.join("single-stop.toml")).unwrap();
        assert_eq!(stop_laws(None, &soft), Ok(vec![scene::LawKind::Soft]));
        assert_eq!(stop_laws(Some("soft"), &soft), Ok(vec![scene::LawKind::Soft]));
        assert_eq!(stop_laws(None, &rigid), Ok(vec![scene::LawKind::Rigid]));
        let changed = stop_laws(Some("rigid"), &soft).unwrap_err();
        assert!(changed.starts_with("attribute stop_laws: not the laws of the stored scene's stops"), "{changed}");
        let unknown = stop_laws(Some("sotf"), &soft).unwrap_err();
        assert_eq!(unknown, "attribute stop_laws: expected rigid or soft, got 'sotf' (did you mean 'soft'?)");
        assert!(stop_laws(None, "not a scene").unwrap_err().starts_with("the stored scene: "));
    }
}
