//! Basin files (`vibroatlas basins -o FILE.h5`): a [`maps::BasinMap`] as a
//! self-describing netCDF-4/HDF5 file that xarray opens as a Dataset.
//!
//! Root attributes: `Conventions` (CF-1.8), `software`, `content` (`basins of
//! attraction`), `command`, `created`, `scene`, `phase` (the forcing phase at
//! the start, radians), the boundary measures (`basin_entropy`,
//! `boundary_basin_entropy`, `entropy_box`, `uncertainty_exponent`,
//! `fractal`) and `basins_crc32`, the CRC-32 of every value read back (an
//! edited id, point or label is an error on read, never another map).
//!
//! Datasets, along the dimensions named after the two state components
//! (`v_M2`, `x_M2`), `attractor`, `point`, `component` and `parameter`:
//! `basin [y, x]` (int32: the attractor's index, −1 for a start that
//! penetrates a stop; CF `flag_values` and `flag_meanings`), `periods [y, x]`
//! (forcing periods simulated), per attractor `attractor_class`,
//! `attractor_symmetry`, `attractor_reason` (empty where none), `labels_<mass>`,
//! `fraction`, `count`, `multiplier` and `lyapunov` (NaN where none),
//! `attractor_colour [attractor, rgb]` (the figures' colour, u8),
//! `attractor_start [attractor, component]` and `section [attractor, point,
//! component]` (NaN after an attractor's last point); `start [component]`
//! (the state outside the two axes, NaN for theirs) and `parameter_value [parameter]`.

use crate::error::{Hdf5Error, StoreError};
use crate::layout::attr;
use crate::netcdf;
use hdf5::H5Type;
use maps::basins::{BasinAttractor, BasinMap, INADMISSIBLE};
use maps::Axis;
use std::path::Path;

/// What the attribute `content` of a basin file says.
pub const CONTENT: &str = "basins of attraction";
/// Attribute: the CRC-32 of every value of the map as read (`values_crc32`).
const BASINS_CRC32: &str = "basins_crc32";

const BASIN: &str = "basin";
const PERIODS: &str = "periods";
const ATTRACTOR: &str = "attractor";
const POINT: &str = "point";
const COMPONENT: &str = "component";
const PARAMETER: &str = "parameter";
/// Root attributes: the components of the two axes, the labelled masses (`M1,M2`).
const X_AXIS: &str = "x";
const Y_AXIS: &str = "y";
const MASSES: &str = "masses";
/// Root attribute: `yes` where starts stopped early (`basins --early-stop`).
const EARLY: &str = "early_stop";

fn labels_of(mass: &str) -> String {
    format!("labels_{mass}")
}

/// Writes `map` to `path` atomically; `command` is provenance.
pub fn write_basins(path: &Path, map: &BasinMap, command: &str) -> Result<(), StoreError> {
    crate::write_atomically(path, |tmp| -> Result<(), Hdf5Error> {
        let f = netcdf::create_file(tmp)?;
        write_all(&f, map, command)?;
        Ok(f.flush()?)
    })
}

/// [`netcdf::deflated`] along the dimensions `dims`, with its long name.
fn dataset<T: H5Type + Copy>(
    g: &hdf5::Group,
    name: &str,
    values: Vec<T>,
    dims: &[&hdf5::Dataset],
    long_name: &str,
) -> hdf5::Result<hdf5::Dataset> {
    let shape: Vec<usize> = dims.iter().map(|d| d.size()).collect();
    let ds = netcdf::deflated(g, name, values, &shape)?;
    netcdf::dims(&ds, dims)?;
    netcdf::describe(&ds, long_name, "1")?;
    Ok(ds)
}

/// Texts along `dim`.
fn texts(g: &hdf5::Group, name: &str, values: &[String], dim: &hdf5::Dataset, long_name: &str) -> hdf5::Result<()> {
    let ds = netcdf::texts(g, name, values)?;
    netcdf::dims(&ds, &[dim])?;
    netcdf::attr_str(&ds, "long_name", long_name)
}

fn write_all(f: &hdf5::File, map: &BasinMap, command: &str) -> hdf5::Result<()> {
    let created = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    for (name, value) in [
        (attr::CONVENTIONS, "CF-1.8"),
        (attr::SOFTWARE, crate::layout::SOFTWARE),
        (crate::layout::curves::CONTENT_ATTR, CONTENT),
        (attr::COMMAND, command),
        (attr::CREATED, created.as_str()),
        (attr::SCENE, map.scene.as_str()),
    ] {
        netcdf::attr_str(f, name, value)?;
    }
    netcdf::attr_str(f, X_AXIS, &map.x.name)?;
    netcdf::attr_str(f, Y_AXIS, &map.y.name)?;
    netcdf::attr_str(f, MASSES, &map.masses.join(","))?;
    netcdf::attr_num(f, "phase", map.phase)?;
    netcdf::attr_str(f, EARLY, if map.early { "yes" } else { "no" })?;
    let (e, u) = (map.entropy(), map.uncertainty());
    netcdf::attr_num(f, "basin_entropy", e.basin)?;
    netcdf::attr_num(f, "boundary_basin_entropy", e.boundary)?;
    netcdf::attr_num(f, "entropy_box", e.side as u64)?;
    netcdf::attr_num(f, "uncertainty_exponent", u.exponent)?;
    netcdf::attr_str(f, "fractal", if e.fractal() { "yes" } else { "no" })?;
    let x = netcdf::coordinate(f, &map.x.name, &map.x.values(), &format!("{} at the start", map.x.name))?;
    let y = netcdf::coordinate(f, &map.y.name, &map.y.values(), &format!("{} at the start", map.y.name))?;
    let n = map.attractors.len();
    let basin = dataset(f, BASIN, map.ids.clone(), &[&y, &x], "the attractor each start reaches")?;
    let flags: Vec<i32> = std::iter::once(INADMISSIBLE).chain(0..n as i32).collect();
    netcdf::attr_array(&basin, "flag_values", &flags)?;
    let meanings: Vec<String> =
        std::iter::once("inadmissible".to_string()).chain((0..n).map(|k| format!("attractor_{k}"))).collect();
    netcdf::attr_str(&basin, "flag_meanings", &meanings.join(" "))?;
    dataset(f, PERIODS, map.periods.clone(), &[&y, &x], "forcing periods simulated from each start")?;
    let at = netcdf::dimension(f, ATTRACTOR, n)?;
    let a = &map.attractors;
    let text = |g: fn(&BasinAttractor) -> String| a.iter().map(g).collect::<Vec<_>>();
    texts(f, "attractor_class", &text(|a| a.class.clone()), &at, "class of the motion")?;
    texts(f, "attractor_symmetry", &text(|a| a.symmetry.clone().unwrap_or_default()), &at, "symmetry of the orbit")?;
    texts(f, "attractor_reason", &text(|a| a.reason.clone().unwrap_or_default()), &at, "why it is unresolved")?;
    for (m, mass) in map.masses.iter().enumerate() {
        let labels: Vec<String> = a.iter().map(|a| a.labels[m].to_string()).collect();
        texts(f, &labels_of(mass), &labels, &at, &format!("label of {mass}"))?;
    }
    let rgb = netcdf::dimension(f, "rgb", 3)?;
    let colours = map.colours().concat();
    dataset(f, "attractor_colour", colours, &[&at, &rgb], "colour of its basin in the figures (RGB, 0 to 255)")?;
    let fractions: Vec<f64> = (0..n).map(|k| map.fraction(k)).collect();
    dataset(f, "fraction", fractions, &[&at], "share of the admissible starts that reach it")?;
    dataset(f, "count", a.iter().map(|a| a.count).collect(), &[&at], "starts that reach it")?;
    let or_nan = |v: Option<f64>| v.unwrap_or(f64::NAN);
    dataset(f, "multiplier", a.iter().map(|a| or_nan(a.multiplier)).collect(), &[&at], "largest |Floquet multiplier|")?;
    let lyapunov = a.iter().map(|a| or_nan(a.lyapunov)).collect();
    dataset(f, "lyapunov", lyapunov, &[&at], "largest Lyapunov exponent per unit time")?;
    let comp = netcdf::labels(f, COMPONENT, &map.components, "state component")?;
    dataset(f, "start", map.start.clone(), &[&comp], "the state outside the two axes")?;
    let starts: Vec<f64> = a.iter().flat_map(|a| a.start.iter().copied()).collect();
    dataset(f, "attractor_start", starts, &[&at, &comp], "the first start that reaches it")?;
    let points = a.iter().map(|a| a.section.len()).max().unwrap_or(0);
    let pt = netcdf::dimension(f, POINT, points)?;
    let dim = map.components.len();
    let mut section = vec![f64::NAN; n * points * dim];
    for (k, a) in a.iter().enumerate() {
        for (p, s) in a.section.iter().enumerate() {
            section[(k * points + p) * dim..][..dim].copy_from_slice(s);
        }
    }
    dataset(f, "section", section, &[&at, &pt, &comp], "period-section points (NaN after the last)")?;
    let names: Vec<String> = map.parameters.iter().map(|p| p.0.clone()).collect();
    let par = netcdf::labels(f, PARAMETER, &names, "parameter of the scene")?;
    dataset(f, "parameter_value", map.parameters.iter().map(|p| p.1).collect(), &[&par], "value of the parameter")?;
    netcdf::attr_num(f, BASINS_CRC32, values_crc32(map))?;
    netcdf::seal(f)
}

/// The CRC-32 of a map as a reader gets it: every text (its byte length,
/// u64 little-endian, then its bytes) and number (its IEEE or integer bits,
/// little-endian) in the order of the fields, each list its length first.
fn values_crc32(map: &BasinMap) -> u32 {
    let mut h = crc32fast::Hasher::new();
    let count = |n: usize, h: &mut crc32fast::Hasher| h.update(&(n as u64).to_le_bytes());
    let text = |t: &str, h: &mut crc32fast::Hasher| {
        count(t.len(), h);
        h.update(t.as_bytes());
    };
    let numbers = |v: &[f64], h: &mut crc32fast::Hasher| {
        count(v.len(), h);
        v.iter().for_each(|x| h.update(&x.to_le_bytes()));
    };
    text(&map.scene, &mut h);
    count(map.parameters.len(), &mut h);
    for (name, v) in &map.parameters {
        text(name, &mut h);
        h.update(&v.to_le_bytes());
    }
    for t in map.masses.iter().chain(&map.components) {
        text(t, &mut h);
    }
    numbers(&map.start, &mut h);
    numbers(&[map.phase], &mut h);
    h.update(&[u8::from(map.early)]);
    for axis in [&map.x, &map.y] {
        text(&axis.name, &mut h);
        numbers(&axis.values(), &mut h);
    }
    count(map.ids.len(), &mut h);
    map.ids.iter().for_each(|i| h.update(&i.to_le_bytes()));
    map.periods.iter().for_each(|p| h.update(&p.to_le_bytes()));
    count(map.attractors.len(), &mut h);
    for a in &map.attractors {
        for t in [&a.class, a.symmetry.as_deref().unwrap_or(""), a.reason.as_deref().unwrap_or("")] {
            text(t, &mut h);
        }
        a.labels.iter().for_each(|l| text(&l.to_string(), &mut h));
        numbers(&[a.multiplier.unwrap_or(f64::NAN), a.lyapunov.unwrap_or(f64::NAN)], &mut h);
        h.update(&a.count.to_le_bytes());
        numbers(&a.start, &mut h);
        count(a.section.len(), &mut h);
        a.section.iter().for_each(|s| numbers(s, &mut h));
    }
    h.finalize()
}

/// Whether `path` is a basin file (its root's `content` says so).
pub fn is_basins(path: &Path) -> bool {
    // Only a regular file is opened: a pipe would block the open.
    if !path.is_file() {
        return false;
    }
    let Ok(f) = crate::heap::open(path) else { return false };
    crate::attrs::text(path, &f, crate::layout::curves::CONTENT_ATTR).ok().flatten().as_deref() == Some(CONTENT)
}

/// Reads a basin file, every value checked against the file's checksums.
pub fn read_basins(path: &Path) -> Result<BasinMap, StoreError> {
    if !path.is_file() {
        return Err(StoreError::format(path, "no such basin file"));
    }
    let f = crate::heap::open(path)?;
    crate::attrs::verify(path, &f)?;
    if crate::attrs::text(path, &f, crate::layout::curves::CONTENT_ATTR)?.as_deref() != Some(CONTENT) {
        return Err(StoreError::format(path, format!("not a vibroatlas basin file (its content is not '{CONTENT}')")));
    }
    let ck = crate::checked::Checker { path, sealed: false, run: 0 };
    let numbers = |name: &str| -> Result<(Vec<f64>, Vec<usize>), StoreError> {
        let d = ck.open(&f, name)?;
        Ok((ck.raw::<f64>(&d)?, d.shape()))
    };
    let texts = |name: &str| ck.open(&f, name).and_then(|d| crate::checked::texts(&ck, &d));
    let basin = ck.open(&f, BASIN)?;
    let shape = basin.shape();
    let [ny, nx] = shape[..] else { return Err(ck.bad(BASIN, format!("{} axes, expected 2", shape.len()))) };
    let axis = |name: &str, count: usize| -> Result<Axis, StoreError> {
        let (v, _) = numbers(name)?;
        if v.len() != count || count == 0 {
            return Err(ck.bad(name, format!("{} values for {count} starts", v.len())));
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(ck.bad(name, "values that are not finite numbers".to_string()));
        }
        Axis::new(name, v[0], v[count - 1], count).checked(name).map_err(|e| ck.bad(name, e.message))
    };
    let name = |a: &str| crate::attrs::required_text(path, &f, a);
    let (y, x) = (axis(&name(Y_AXIS)?, ny)?, axis(&name(X_AXIS)?, nx)?);
    let ids = ck.raw::<i32>(&basin)?;
    let periods = ck.raw::<u64>(&ck.open(&f, PERIODS)?)?;
    let components = texts(COMPONENT)?;
    let class = texts("attractor_class")?;
    let n = class.len();
    let masses: Vec<String> = match name(MASSES)?.as_str() {
        "" => Vec::new(),
        list => list.split(',').map(str::to_string).collect(),
    };
    let labels: Vec<Vec<String>> = masses.iter().map(|m| texts(&labels_of(m))).collect::<Result<_, _>>()?;
    let (symmetry, reason) = (texts("attractor_symmetry")?, texts("attractor_reason")?);
    let count = ck.raw::<u64>(&ck.open(&f, "count")?)?;
    let (multiplier, lyapunov) = (numbers("multiplier")?.0, numbers("lyapunov")?.0);
    let (starts, _) = numbers("attractor_start")?;
    let (section, section_shape) = numbers("section")?;
    let (start, _) = numbers("start")?;
    let dim = components.len();
    let points = section_shape.get(1).copied().unwrap_or(0);
    let lengths = [
        ("periods", periods.len(), nx * ny),
        ("start", start.len(), dim),
        ("attractor_symmetry", symmetry.len(), n),
        ("attractor_reason", reason.len(), n),
        ("count", count.len(), n),
        ("multiplier", multiplier.len(), n),
        ("lyapunov", lyapunov.len(), n),
        ("attractor_start", starts.len(), n * dim),
        ("section", section.len(), n * points * dim),
    ];
    for (name, got, want) in lengths.into_iter().chain(labels.iter().map(|l| ("labels", l.len(), n))) {
        if got != want {
            return Err(ck.bad(name, format!("{got} values, expected {want}")));
        }
    }
    let names = texts(PARAMETER)?;
    let (values, _) = numbers("parameter_value")?;
    if values.len() != names.len() {
        return Err(ck.bad("parameter_value", format!("{} values for {} parameters", values.len(), names.len())));
    }
    let some = |v: f64| (!v.is_nan()).then_some(v);
    let attractors = (0..n)
        .map(|k| -> Result<BasinAttractor, StoreError> {
            let labels = labels
                .iter()
                .map(|l| l[k].parse().map_err(|e: String| ck.bad("labels", e)))
                .collect::<Result<Vec<_>, _>>()?;
            let section = section[k * points * dim..][..points * dim]
                .chunks(dim)
                .map(<[f64]>::to_vec)
                .take_while(|p| !p.iter().all(|v| v.is_nan()))
                .collect();
            Ok(BasinAttractor {
                class: class[k].clone(),
                labels,
                symmetry: (!symmetry[k].is_empty()).then(|| symmetry[k].clone()),
                reason: (!reason[k].is_empty()).then(|| reason[k].clone()),
                multiplier: some(multiplier[k]),
                lyapunov: some(lyapunov[k]),
                count: count[k],
                start: starts[k * dim..][..dim].to_vec(),
                section,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let map = BasinMap {
        scene: crate::attrs::required_text(path, &f, attr::SCENE)?,
        parameters: names.into_iter().zip(values).collect(),
        masses,
        components,
        start,
        phase: crate::attrs::required::<f64>(path, &f, "phase")?,
        early: crate::attrs::required_text(path, &f, EARLY)? == "yes",
        x,
        y,
        ids,
        periods,
        attractors,
    };
    if map.ids.iter().any(|&i| i < INADMISSIBLE || i >= n as i32) {
        return Err(ck.bad(BASIN, format!("an id outside -1 … {}", n as i64 - 1)));
    }
    match crate::attrs::optional::<u32>(path, &f, BASINS_CRC32)? {
        Some(crc) if crc == values_crc32(&map) => Ok(map),
        _ => Err(StoreError::format(
            path,
            format!("the basins are not those written ({})", crate::attrs::mismatch(BASINS_CRC32)),
        )),
    }
}
