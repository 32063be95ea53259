//! Reading an atlas file back into memory (for merge, render, inspect, resume
//! checks and round-trip tests).

use crate::error::StoreError;
use crate::layout::*;
use crate::write::RunInfo;
use grid::{Along, Atlas, Axis, CellData, Map, Meta, Plane, Shard, SweepKind};
use hdf5::types::VarLenUnicode;
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

fn attr(f: &hdf5::Location, name: &str) -> hdf5::Result<String> {
    Ok(f.attr(name)?.read_scalar::<VarLenUnicode>()?.to_string())
}

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

/// Reads an atlas file.
pub fn read(path: &Path) -> Result<Loaded, StoreError> {
    let fmt = |m: String| StoreError::format(path, m);
    let h = |e: hdf5::Error| StoreError::hdf5(path, e);
    if !path.exists() {
        return Err(StoreError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, "no such file")));
    }
    if !path.is_file() {
        return Err(fmt("not a file (an atlas is one HDF5 file)".into()));
    }
    let f = hdf5::File::open(path).map_err(h)?;
    if attr(&f, attr::SOFTWARE).map_err(h)? != SOFTWARE {
        return Err(fmt("not a vibroatlas file".into()));
    }
    if f.attr(attr::X).is_err() {
        let what = if f.attr(curves::CONTENT_ATTR).is_ok() {
            " (a curve file: render an atlas with --curves FILE)"
        } else {
            ""
        };
        return Err(fmt(format!("not an atlas{what}")));
    }
    let axis = |name: &str| -> Result<Axis, StoreError> {
        let d = f.dataset(&format!("{AXES}/{name}")).map_err(h)?;
        Ok(Axis {
            name: name.to_string(),
            start: d.attr(attr::START).and_then(|a| a.read_scalar::<f64>()).map_err(h)?,
            stop: d.attr(attr::STOP).and_then(|a| a.read_scalar::<f64>()).map_err(h)?,
            count: d.size(),
        })
    };
    let x = axis(&attr(&f, attr::X).map_err(h)?)?;
    let y = axis(&attr(&f, attr::Y).map_err(h)?)?;
    let version = f.attr(attr::LAYOUT_VERSION).and_then(|a| a.read_scalar::<u64>()).unwrap_or(1);
    if version > LAYOUT_VERSION {
        return Err(fmt(format!(
            "layout version {version}, newer than this vibroatlas reads ({LAYOUT_VERSION}); use a newer vibroatlas"
        )));
    }
    let dim = f.attr(attr::DIM).and_then(|a| a.read_scalar::<u64>()).map_err(h)? as usize;
    let along = Along::parse(&attr(&f, attr::ALONG).map_err(h)?).map_err(|e| fmt(e.to_string()))?;
    let sweeps = list(&attr(&f, attr::SWEEPS).map_err(h)?)
        .iter()
        .map(|s| SweepKind::parse(s).ok_or_else(|| fmt(format!("unknown sweep '{s}'"))))
        .collect::<Result<Vec<_>, _>>()?;
    let masses = list(&attr(&f, attr::MASSES).map_err(h)?);
    // Layout 1 did not name the stops of each label.
    let n_masses = masses.len();
    let stops_of = |name: &str| {
        let v: Vec<String> = attr(&f, name).map(|s| s.split(',').map(str::to_string).collect()).unwrap_or_default();
        (0..n_masses).map(move |i| v.get(i).cloned().unwrap_or_default())
    };
    let label_stops = stops_of(attr::P_STOPS).zip(stops_of(attr::Q_STOPS)).map(|(p, q)| [p, q]).collect();
    let scene_toml = attr(&f, attr::SCENE).map_err(h)?;
    let notation = notation(&f, &scene_toml, [&x.name, &y.name]);
    let meta = Meta {
        scene_name: attr(&f, attr::SCENE_NAME).map_err(h)?,
        scene_toml: scene_toml.clone(),
        overrides: pairs(&attr(&f, attr::OVERRIDES).map_err(h)?).map_err(fmt)?,
        preset: attr(&f, attr::PRESET).map_err(h)?,
        accuracy: pairs(&attr(&f, attr::ACCURACY).map_err(h)?).map_err(fmt)?,
        integrator: attr(&f, attr::INTEGRATOR).map_err(h)?,
        plane: Plane { x, y, along },
        sweeps,
        masses,
        label_stops,
        // Layout 1 did not name the scene's masses.
        state_masses: attr(&f, attr::STATE_MASSES)
            .map(|s| list(&s))
            .unwrap_or_else(|_| (1..=dim / 2).map(|i| format!("mass{i}")).collect()),
        stops: list(&attr(&f, attr::STOPS).map_err(h)?),
        stop_normals: stop_normals(&f, &scene_toml, dim / 2).map_err(fmt)?,
        dim,
        section_cap: f.attr(attr::SECTION_CAP).and_then(|a| a.read_scalar::<u64>()).map_err(h)? as usize,
        notation,
    };
    let (nx, ny, dim) = (meta.plane.x.count, meta.plane.y.count, meta.dim);
    let n = nx * ny;
    let stops = meta.stops.len();
    let mut maps = Vec::new();
    for &sweep in &meta.sweeps {
        let g = f.group(sweep.name()).map_err(h)?;
        let raw_u8 = |name: &str| g.dataset(name).and_then(|d| d.read_raw::<u8>()).map_err(h);
        let raw_u64 = |name: &str| g.dataset(name).and_then(|d| d.read_raw::<u64>()).map_err(h);
        let class = raw_u8(var::CLASS)?;
        let sym = raw_u8(var::SYMMETRY)?;
        let flags = g.dataset(var::FLAGS).and_then(|d| d.read_raw::<u32>()).map_err(h)?;
        let fs = g.dataset(var::FINAL_STATE).and_then(|d| d.read_raw::<f64>()).map_err(h)?;
        // Files written before the stability datasets existed have none.
        let scalar =
            |name: &str| g.dataset(name).and_then(|d| d.read_raw::<f64>()).unwrap_or_else(|_| vec![f64::NAN; n]);
        let (lyapunov, multiplier) = (scalar(var::LYAPUNOV), scalar(var::MULTIPLIER));
        let finite = |v: f64| v.is_finite().then_some(v);
        let (periods, events) = (raw_u64(var::PERIODS)?, raw_u64(var::EVENTS)?);
        let labels = meta
            .masses
            .iter()
            .map(|m| g.dataset(&label(m)).and_then(|d| d.read_raw::<u16>()).map_err(h))
            .collect::<Result<Vec<_>, _>>()?;
        if class.len() != n || fs.len() != n * dim || labels.iter().any(|l| l.len() != 3 * n) {
            return Err(fmt(format!("datasets of /{} do not match the {ny} x {nx} grid", sweep.name())));
        }
        let section = |name: &str| -> Result<(Vec<f64>, Vec<u64>, usize), StoreError> {
            let s = g.group(&format!("{SECTIONS}/{name}")).map_err(h)?;
            let vd = s.dataset(var::VALUES).map_err(h)?;
            let cols = vd.shape().get(1).copied().unwrap_or(1);
            Ok((
                vd.read_raw::<f64>().map_err(h)?,
                s.dataset(var::OFFSETS).and_then(|d| d.read_raw::<u64>()).map_err(h)?,
                cols,
            ))
        };
        let rows = |sec: &(Vec<f64>, Vec<u64>, usize), i: usize| -> Vec<Vec<f64>> {
            let (v, o, cols) = sec;
            (o[i] as usize..o[i + 1] as usize).map(|r| v[r * cols..(r + 1) * cols].to_vec()).collect()
        };
        let period = section(PERIOD_SECTION)?;
        let impacts = meta.stops.iter().map(|s| section(s)).collect::<Result<Vec<_>, _>>()?;
        let cells = (0..n)
            .map(|i| {
                class_of(class[i]).map(|c| CellData {
                    class: c,
                    labels: labels.iter().map(|l| label_of(c, [l[3 * i], l[3 * i + 1], l[3 * i + 2]])).collect(),
                    chatter: flags_of(flags[i], stops).0,
                    sticking: flags_of(flags[i], stops).1,
                    symmetry: symmetry_of(sym[i]),
                    lyapunov: lyapunov.get(i).copied().and_then(finite),
                    multiplier: multiplier.get(i).copied().and_then(finite),
                    final_state: fs[i * dim..(i + 1) * dim].to_vec(),
                    periods: periods[i],
                    events: events[i],
                    period_section: rows(&period, i),
                    impact_sections: impacts.iter().map(|s| rows(s, i)).collect(),
                })
            })
            .collect();
        maps.push(Map { sweep, cells });
    }
    let shard = match attr(&f, attr::SHARD) {
        Ok(s) => Some(Shard::parse(&s).map_err(|e| fmt(e.to_string()))?),
        Err(_) => None,
    };
    let attractors = match f.group(ATTRACTORS) {
        Ok(g) => Some(read_attractors(&g, n, &meta.masses).map_err(h)?),
        Err(_) => None,
    };
    // Layout 1 had no history: its command is the whole of it.
    let command = attr(&f, attr::COMMAND).map_err(h)?;
    let created = attr(&f, attr::CREATED).map_err(h)?;
    let history = match attr(&f, attr::HISTORY) {
        Ok(text) => text.lines().map(str::to_string).collect(),
        Err(_) => vec![format!("{created}: {command}")],
    };
    Ok(Loaded {
        atlas: Atlas { meta, maps, attractors },
        info: RunInfo {
            command,
            run_time_s: f.attr(attr::RUN_TIME_S).and_then(|a| a.read_scalar::<f64>()).map_err(h)?,
            shard,
            history,
        },
        created: attr(&f, attr::CREATED).map_err(h)?,
    })
}

/// The `/attractors` group of `n` cells and the labelled `masses`.
fn read_attractors(g: &hdf5::Group, n: usize, masses: &[String]) -> hdf5::Result<grid::AttractorMap> {
    let count = g.dataset(var::COUNT)?.read_raw::<u8>()?;
    let fraction = g.dataset(var::FRACTION)?.read_raw::<f64>()?;
    let slots = fraction.len() / n.max(1);
    let table: Vec<String> = g.dataset(LABEL)?.read_raw::<VarLenUnicode>()?.iter().map(|t| t.to_string()).collect();
    let codes = masses
        .iter()
        .map(|m| g.dataset(&label_code(m)).and_then(|d| d.read_raw::<i16>()))
        .collect::<hdf5::Result<Vec<_>>>()?;
    let text = |c: i16| table.get(c.max(0) as usize).cloned().unwrap_or_default();
    let cells = (0..n)
        .map(|i| {
            (count[i] > 0).then(|| {
                (0..(count[i] as usize).min(slots))
                    .map(|k| (codes.iter().map(|c| text(c[i * slots + k])).collect(), fraction[i * slots + k]))
                    .collect()
            })
        })
        .collect();
    let samples = g.attr(attr::SAMPLES).and_then(|a| a.read_scalar::<u64>())? as usize;
    let seed = g.attr(attr::SEED).and_then(|a| a.read_scalar::<u64>())?;
    Ok(grid::AttractorMap { samples, seed, cells })
}

/// The stops' normals of a file (stops × masses), or, in files written before
/// they were stored, those of its scene.
fn stop_normals(f: &hdf5::File, scene_toml: &str, masses: usize) -> Result<Vec<Vec<f64>>, String> {
    if let Ok(flat) = f.attr(attr::STOP_NORMALS).and_then(|a| a.read_raw::<f64>()) {
        if masses == 0 || flat.len() % masses != 0 {
            return Err(format!("{}: {} values, not a multiple of {masses} masses", attr::STOP_NORMALS, flat.len()));
        }
        return Ok(flat.chunks(masses).map(<[f64]>::to_vec).collect());
    }
    let scene = scene::Scene::parse(scene_toml).map_err(|e| format!("the stored scene: {e}"))?;
    Ok(scene.stop_normals())
}

/// How the parameters are written: as the stored scene says (in files
/// written before scenes declared symbols, by their names:
/// [`scene::symbol_of`]), and each axis as its root coordinate's `symbol` and
/// `long_name` say, where it has them (files written before them do not; the
/// `long_name` `parameter <name>` says nothing more than the name).
fn notation(f: &hdf5::File, scene_toml: &str, axes: [&str; 2]) -> Vec<grid::Notation> {
    let mut notation = scene::Scene::parse(scene_toml).map(|s| grid::Notation::of_scene(&s)).unwrap_or_default();
    for name in axes {
        let Ok(symbol) = f.dataset(name).and_then(|d| attr(&d, attr::SYMBOL)) else {
            continue;
        };
        let long_name = f
            .dataset(name)
            .and_then(|d| attr(&d, attr::LONG_NAME))
            .ok()
            .filter(|l| *l != crate::write::generic_long_name(name));
        match notation.iter_mut().find(|n| n.name == name) {
            Some(n) => {
                n.symbol = symbol;
                n.long_name = long_name;
            }
            None => notation.push(grid::Notation { name: name.to_string(), symbol, long_name }),
        }
    }
    notation
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::write::{write, RunInfo};

    /// An atlas of `scene_toml` (the dry-friction scene, or one like it)
    /// over (omega, fk), nothing computed.
    fn atlas(scene_toml: &str) -> Atlas {
        let scene = scene::Scene::parse(scene_toml).unwrap();
        let plane = Plane::new(
            Axis::parse("omega=1:8:4", "--x").unwrap(),
            Axis::parse("fk=0.01:0.1:3", "--y").unwrap(),
            Along::X,
        )
        .unwrap();
        Atlas::new(Meta {
            scene_name: scene.name().into(),
            scene_toml: scene_toml.into(),
            overrides: Vec::new(),
            preset: "standard".into(),
            accuracy: Vec::new(),
            integrator: "exact".into(),
            plane,
            sweeps: vec![SweepKind::Up, SweepKind::Down],
            masses: vec!["M1".into()],
            state_masses: vec!["M1".into(), "M2".into()],
            label_stops: vec![["right".into(), "left".into()]],
            stops: vec!["right".into(), "left".into()],
            stop_normals: scene.stop_normals(),
            dim: 4,
            section_cap: 16,
            notation: grid::Notation::of_scene(&scene),
        })
    }

    fn text(d: &hdf5::Dataset, name: &str) -> String {
        attr(d, name).unwrap()
    }

    /// The axis coordinates of every group carry their parameter's `symbol`
    /// and `long_name`, and the file reads back into the same notation; a
    /// file written before them (no `symbol`, `long_name = "parameter
    /// <name>"`) reads by its scene, or by the names' Greek rule.
    #[test]
    fn axes_carry_symbols_and_long_names_and_older_files_still_read() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-notation-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/dry-friction.toml");
        let toml = std::fs::read_to_string(path).unwrap();
        let info = RunInfo { command: "test".into(), run_time_s: 0.0, shard: None, history: Vec::new() };
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
                    f.dataset(&format!("{g}{name}")).unwrap().delete_attr(attr::SYMBOL).unwrap();
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
}
