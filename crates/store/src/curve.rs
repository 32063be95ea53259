//! Bifurcation curves (`vibroatlas curve -o FILE.h5`, `vibroatlas curves`)
//! as self-describing netCDF-4/HDF5 files: root attributes `software`
//! (vibroatlas), `content` (`bifurcation curves`), `command`, `created`,
//! `scene`; one group `curve_<k>` per curve with attributes `kind` (PD, SN, PF,
//! NS, grazing), `free` (`A,B`), `ended`, the curve's points as two coordinate
//! arrays named after the free parameters along the dimension `point`, and
//! its codimension-two points as `codim2_<A>`, `codim2_<B>` and `codim2_kind`
//! along `codim2`. An atlas may hold its curves in a `curves` group laid out
//! the same way (`vibroatlas curves ATLAS --into`); [`read_curves`] reads
//! either. The holder's attribute `curves_crc32` covers every number and
//! text of its curves, their number and their order: an edited point, a curve
//! scaled, deleted or swapped is an error on read, never another curve. An
//! atlas's root names the curves it holds (text attribute `curves`, their
//! `curves_crc32`, under the root's own checksum): their group deleted, or
//! replaced by another atlas's, is an error too.

use crate::error::{Hdf5Error, OtherKind, StoreError};
use crate::layout::attr;
use crate::layout::curves::*;
use crate::netcdf;
use scene::Named;
use std::path::Path;

/// A bifurcation curve in the plane of two parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// Kind of bifurcation (`PD`, `SN`, `PF`, `NS`, `grazing`).
    pub kind: String,
    /// The two free parameters (A, B).
    pub free: [String; 2],
    /// Points `(a, b)` in order along the curve.
    pub points: Vec<(f64, f64)>,
    /// Codimension-two points `(kind, a, b)`.
    pub codim2: Vec<(String, f64, f64)>,
    /// Why the curve ends.
    pub ended: String,
}

/// Writes `curves` to `path` atomically; `command` and `scene` are provenance.
pub fn write_curves(path: &Path, curves: &[Curve], command: &str, scene: &str) -> Result<(), StoreError> {
    crate::write_atomically(path, |tmp| -> Result<(), Hdf5Error> {
        let f = netcdf::create_file(tmp)?;
        netcdf::attr_str(&f, attr::CONVENTIONS, "CF-1.8")?;
        netcdf::attr_str(&f, attr::SCENE, scene)?;
        write_all(&f, curves, command)?;
        Ok(f.flush()?)
    })
}

/// Stores `curves` in the atlas at `path` as its `curves` group, replacing
/// one there: the atlas is copied, the group written into the copy, and the
/// copy renamed over it (locked meanwhile, as every output).
pub fn add_curves(path: &Path, curves: &[Curve], command: &str) -> Result<(), StoreError> {
    let _lock = crate::OutputLock::acquire(path)?;
    crate::write_atomically(path, |tmp| -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        std::fs::copy(path, tmp)?;
        let add = || -> hdf5::Result<()> {
            let f = hdf5::File::open_rw(tmp)?;
            if f.link_exists(GROUP) {
                f.unlink(GROUP)?;
            }
            write_all(&f.create_group(GROUP)?, curves, command)?;
            // The root names them, under its own checksum.
            netcdf::replace_str(&f, attr::CURVES, &values_crc32(curves).to_string())?;
            netcdf::seal(&f)?;
            f.flush()
        };
        Ok(add().map_err(Hdf5Error::from)?)
    })
}

/// Provenance attributes and one group per curve, in `g`.
fn write_all(g: &hdf5::Group, curves: &[Curve], command: &str) -> hdf5::Result<()> {
    let created = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    for (name, value) in [
        (attr::SOFTWARE, crate::layout::SOFTWARE),
        (CONTENT_ATTR, CONTENT),
        (attr::COMMAND, command),
        (attr::CREATED, created.as_str()),
    ] {
        netcdf::attr_str(g, name, value)?;
    }
    for (k, c) in curves.iter().enumerate() {
        write_one(&g.create_group(&curve(k))?, c)?;
    }
    netcdf::attr_num(g, CURVES_CRC32, values_crc32(curves))?;
    netcdf::seal(g)
}

/// The CRC-32 of `curves` as a reader gets them: their number, then per
/// curve its kind, free parameters and end (each text its byte length, u64
/// little-endian, then its bytes), its points and its codimension-two points
/// (each list its length, then every number's IEEE bits little-endian, a
/// kind's text before its two numbers).
fn values_crc32(curves: &[Curve]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    let count = |n: usize, h: &mut crc32fast::Hasher| h.update(&(n as u64).to_le_bytes());
    let text = |t: &str, h: &mut crc32fast::Hasher| {
        h.update(&(t.len() as u64).to_le_bytes());
        h.update(t.as_bytes());
    };
    count(curves.len(), &mut h);
    for c in curves {
        for t in [&c.kind, &c.free[0], &c.free[1], &c.ended] {
            text(t, &mut h);
        }
        count(c.points.len(), &mut h);
        for (a, b) in &c.points {
            h.update(&a.to_le_bytes());
            h.update(&b.to_le_bytes());
        }
        count(c.codim2.len(), &mut h);
        for (k, a, b) in &c.codim2 {
            text(k, &mut h);
            h.update(&a.to_le_bytes());
            h.update(&b.to_le_bytes());
        }
    }
    h.finalize()
}

fn write_one(g: &hdf5::Group, curve: &Curve) -> hdf5::Result<()> {
    netcdf::attr_str(g, KIND, &curve.kind)?;
    netcdf::attr_str(g, ENDED, &curve.ended)?;
    netcdf::attr_str(g, FREE, &curve.free.join(","))?;
    netcdf::seal(g)?;
    let point = netcdf::dimension(g, POINT, curve.points.len())?;
    for (k, name) in curve.free.iter().enumerate() {
        let v: Vec<f64> = curve.points.iter().map(|p| if k == 0 { p.0 } else { p.1 }).collect();
        let d = netcdf::deflated(g, name, v, &[curve.points.len()])?;
        netcdf::dims(&d, &[&point])?;
        netcdf::describe(&d, &format!("parameter {name} along the {} curve", curve.kind), "1")?;
    }
    let codim = netcdf::dimension(g, CODIM2, curve.codim2.len())?;
    for (k, name) in curve.free.iter().enumerate() {
        let v: Vec<f64> = curve.codim2.iter().map(|p| if k == 0 { p.1 } else { p.2 }).collect();
        let d = netcdf::deflated(g, &codim2(name), v, &[curve.codim2.len()])?;
        netcdf::dims(&d, &[&codim])?;
        netcdf::describe(&d, &format!("parameter {name} at the codimension-two points"), "1")?;
    }
    let kinds: Vec<String> = curve.codim2.iter().map(|p| p.0.clone()).collect();
    let d = netcdf::texts(g, CODIM2_KIND, &kinds)?;
    netcdf::dims(&d, &[&codim])?;
    netcdf::attr_str(&d, "long_name", "kinds of the two bifurcations that meet")
}

/// Reads every curve of a curve file.
pub fn read_curves(path: &Path) -> Result<Vec<Curve>, StoreError> {
    if !path.is_file() {
        return Err(StoreError::format(path, "no such curve file"));
    }
    let f = crate::heap::open(path)?;
    let content = |g: &hdf5::Group| -> Result<Option<String>, StoreError> {
        crate::attrs::verify(path, g)?;
        crate::attrs::text(path, g, CONTENT_ATTR)
    };
    let holder: hdf5::Group = if content(&f)?.as_deref() == Some(CONTENT) {
        (*f).clone()
    } else {
        match f.group(GROUP) {
            Ok(g) if content(&g)?.as_deref() == Some(CONTENT) => g,
            _ if named_by_root(path, &f)?.is_some() => return Err(curves_missing(path)),
            _ => return Err(StoreError::Kind { path: path.display().to_string(), found: OtherKind::NoCurves }),
        }
    };
    // Curves are written apart from the atlas's writer, without values_crc32.
    let ck = crate::checked::Checker { path, sealed: false, run: 0 };
    let mut out = Vec::new();
    while let Ok(g) = holder.group(&curve(out.len())) {
        out.push(read_one(&ck, &g)?);
    }
    let holder_name = if holder.name() == "/" { "/".to_string() } else { holder.name() };
    let named = if holder.name() == "/" { None } else { named_by_root(path, &f)? };
    match crate::attrs::optional::<u32>(path, &holder, CURVES_CRC32)? {
        Some(crc) if named.is_some_and(|named| named != crc.to_string()) => Err(StoreError::format(
            path,
            format!(
                "the curves of {holder_name} are not those the attribute {} of / names (their group was replaced \
                 since vibroatlas stored them)",
                attr::CURVES
            ),
        )),
        Some(crc) if crc == values_crc32(&out) => Ok(out),
        Some(_) => Err(StoreError::format(
            path,
            format!(
                "the curves of {holder_name} are not those written (a point, a curve or their order changed since; \
                 attribute {CURVES_CRC32})"
            ),
        )),
        None => Err(StoreError::format(
            path,
            format!(
                "the curves of {holder_name} carry no {CURVES_CRC32} (deleted, or written by a vibroatlas before \
                 curves were checked): run curves or curve again"
            ),
        )),
    }
}

/// The checksum of the curves that the root of the atlas `f` says its
/// `curves` group holds (attribute [`attr::CURVES`]); `None` where it says
/// none (an atlas without curves, or whose curves were stored before the
/// attribute).
pub(crate) fn named_by_root(path: &Path, f: &hdf5::File) -> Result<Option<String>, StoreError> {
    crate::attrs::text(path, f, attr::CURVES)
}

/// Whether the atlas `f` holds curves (`curves --into`): its `curves`
/// group, or its root naming them.
pub(crate) fn held(path: &Path, f: &hdf5::File) -> Result<bool, StoreError> {
    Ok(f.link_exists(GROUP) || named_by_root(path, f)?.is_some())
}

/// What an atlas whose root names its curves but holds no `curves` group says.
pub(crate) fn curves_missing(path: &Path) -> StoreError {
    StoreError::format(
        path,
        format!(
            "its attribute {} says it holds bifurcation curves, but its {GROUP} group is missing: the file was \
             changed since vibroatlas wrote it",
            attr::CURVES
        ),
    )
}

/// One curve's group, its datasets checked before they are used: sizes
/// against the file ([`crate::checked::MAX_EXPANSION`]), the two coordinates of
/// the points and of the codimension-two points of one length each.
fn read_one(ck: &crate::checked::Checker, g: &hdf5::Group) -> Result<Curve, StoreError> {
    crate::attrs::verify(ck.path, g)?;
    let attr = |name: &str| crate::attrs::required_text(ck.path, g, name);
    let free: Vec<String> = attr(FREE)?.split(',').map(str::to_string).collect();
    let [a, b] = [free.first().cloned().unwrap_or_default(), free.get(1).cloned().unwrap_or_default()];
    let read = |name: &str| ck.open(g, name).and_then(|d| Ok((ck.raw::<f64>(&d)?, d.name())));
    let (va, vb) = (read(&a)?, read(&b)?);
    let (ca, cb) = (read(&codim2(&a))?, read(&codim2(&b))?);
    let kinds_set = ck.open(g, CODIM2_KIND)?;
    let kinds = crate::checked::texts(ck, &kinds_set)?;
    for ((x, y), what) in [((&va, &vb), "points"), ((&ca, &cb), "codimension-two points")] {
        if x.0.len() != y.0.len() {
            return Err(ck.bad(&y.1, format!("{} {what}, but {} has {}", y.0.len(), x.1, x.0.len())));
        }
    }
    if kinds.len() != ca.0.len() {
        return Err(
            ck.bad(&kinds_set.name(), format!("{} kinds for {} codimension-two points", kinds.len(), ca.0.len()))
        );
    }
    // What a curve of vibroatlas holds: two parameters, points that are
    // numbers, kinds of bifurcation by their names.
    if a.is_empty() || b.is_empty() || a == b {
        return Err(ck.bad(&g.name(), format!("attribute {FREE} is '{}', not two parameters", free.join(","))));
    }
    for (values, name) in [&va, &vb, &ca, &cb] {
        if let Some(x) = values.iter().find(|x| !x.is_finite()) {
            return Err(ck.bad(name, format!("holds {x}, not a finite number")));
        }
    }
    let kind = attr(KIND)?;
    if !is_kind(&kind) {
        return Err(ck.bad(&g.name(), format!("attribute {KIND} is '{}', not a kind of bifurcation", shown(&kind))));
    }
    if let Some(k) = kinds.iter().find(|k| !is_meeting(k)) {
        return Err(ck.bad(&kinds_set.name(), format!("'{}' is no kind of codimension-two point", shown(k))));
    }
    Ok(Curve {
        kind,
        free: [a, b],
        points: va.0.into_iter().zip(vb.0).collect(),
        codim2: kinds.into_iter().zip(ca.0).zip(cb.0).map(|((k, x), y)| (k, x, y)).collect(),
        ended: crate::attrs::text(ck.path, g, ENDED)?.unwrap_or_default(),
    })
}

/// Whether `k` names a kind of bifurcation as curves store it (`PD`, `grazing`).
fn is_kind(k: &str) -> bool {
    solver::Bifurcation::ALL.iter().any(|b| b.name() == k)
}

/// Whether `k` names a codimension-two point as curves store it: the curve's
/// kind and the one it meets (`PD-SN`), or a strong resonance (`1:3`, `1:4`).
fn is_meeting(k: &str) -> bool {
    matches!(k, "1:3" | "1:4") || k.split_once('-').is_some_and(|(x, y)| is_kind(x) && is_kind(y))
}

/// A text from a file as an error shows it: its first 40 characters.
fn shown(text: &str) -> String {
    scene::excerpt(text, 40)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two() -> Vec<Curve> {
        let c = |kind: &str, s: f64| Curve {
            kind: kind.into(),
            free: ["omega".into(), "delta".into()],
            points: (0..5).map(|i| (1.0 + s * f64::from(i), 0.5 - 0.1 * f64::from(i))).collect(),
            codim2: vec![("PD-SN".into(), 1.0 + s, 0.4)],
            ended: "left the plane".into(),
        };
        vec![c("PD", 0.1), c("grazing", 0.2)]
    }

    /// A curve file changed after it was written, as h5py would change it
    /// (the chunks' own checksums written anew), reads as an error naming
    /// the checksum, never as other curves: a point edited, a curve scaled,
    /// a codimension-two point moved, a curve deleted, two swapped, the
    /// checksum deleted (issue 61, F1).
    #[test]
    fn changed_curves_are_refused() {
        let dir = crate::testing::scratch("curves-crc");
        let path = dir.join("c.h5");
        type Change = fn(&hdf5::File);
        let changes: [(&str, Change); 6] = [
            ("a point", |f| {
                let d = f.dataset("curve_0/omega").unwrap();
                let mut v: Vec<f64> = d.read_raw().unwrap();
                v[2] += 1e-12;
                d.write_raw(&v).unwrap();
            }),
            ("a curve scaled", |f| {
                let d = f.dataset("curve_1/delta").unwrap();
                let v: Vec<f64> = d.read_raw::<f64>().unwrap().iter().map(|x| x * 1.01).collect();
                d.write_raw(&v).unwrap();
            }),
            ("a codimension-two point", |f| {
                let d = f.dataset("curve_0/codim2_delta").unwrap();
                d.write_raw(&[0.41]).unwrap();
            }),
            ("a curve deleted", |f| f.unlink("curve_1").unwrap()),
            ("two curves swapped", |f| {
                for (from, to) in [("curve_0", "swap"), ("curve_1", "curve_0"), ("swap", "curve_1")] {
                    f.link_hard(from, to).unwrap();
                    f.unlink(from).unwrap();
                }
            }),
            ("the checksum deleted", |f| f.delete_attr(CURVES_CRC32).unwrap()),
        ];
        write_curves(&path, &two(), "test", "scene").unwrap();
        assert_eq!(read_curves(&path).unwrap(), two());
        for (what, change) in changes {
            write_curves(&path, &two(), "test", "scene").unwrap();
            change(&hdf5::File::open_rw(&path).unwrap());
            let e = read_curves(&path).map(|_| ()).unwrap_err().to_string();
            assert!(e.contains(CURVES_CRC32), "{what}: {e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
