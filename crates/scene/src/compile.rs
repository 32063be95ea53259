//! Reading a scene file once ([`Scene::parse`]): its TOML parsed, every name
//! resolved and checked (HDF5's rules for the names that become groups,
//! uniqueness, the reserved names), every expression compiled, the
//! parameters put in an order that evaluates each after those it depends on,
//! and the sizes bounded ([`crate::MAX_MASSES`], [`crate::MAX_STOPS`],
//! [`crate::MAX_FRICTION`]).

use crate::expr::{self, Compiled, Names, Range, MAX_EXPRESSIONS};
use crate::schema::{self, Num, ParamSpec, SceneFile};
use crate::symbol;
use crate::{
    CompiledLaw, CompiledMass, Derived, LabelStops, Scales, Scene, SceneError, StopPlace, MAX_FRICTION, MAX_HARMONIC,
    MAX_MASSES, MAX_NAME_CHARS, MAX_STOPS,
};

impl Scene {
    /// Parses a scene from TOML text, resolving names and compiling expressions.
    pub fn parse(text: &str) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text)
            .map_err(|e| SceneError::Syntax { message: e.to_string().trim().replace('\n', " ") })?;
        at_most("masses", "masses", file.masses.len(), MAX_MASSES)?;
        at_most("stops", "stops", file.stops.len(), MAX_STOPS)?;
        at_most("friction", "friction contacts", file.friction.len(), MAX_FRICTION)?;
        // Counted before any is compiled (each takes time and memory): the
        // parameters and links, whose number is not limited otherwise.
        let is_expr = |n: &Num| matches!(n, Num::Expr(_));
        let written = file
            .parameters
            .values()
            .filter(|p| {
                is_expr(match p {
                    ParamSpec::Plain(n) => n,
                    ParamSpec::Ranged(r) => &r.value,
                })
            })
            .count()
            + file.links.iter().flat_map(|l| [&l.stiffness, &l.damping]).filter(|n| is_expr(n)).count();
        at_most(
            "parameters",
            "expressions (parameters and links; each about 20 KB once compiled)",
            written,
            MAX_EXPRESSIONS,
        )?;
        // Printed as they are by every front end (a terminal takes an escape
        // sequence as a command): the name one line, the description lines
        // of text.
        if let Some(c) = file.name.chars().find(|c| c.is_control()) {
            let why = format!("must be one line, without newlines or control characters, got {c:?}");
            return Err(SceneError::field("name", why));
        }
        if let Some(c) = file.description.chars().find(|&c| c.is_control() && !matches!(c, '\n' | '\r' | '\t')) {
            return Err(SceneError::field("description", format!("must not hold control characters, got {c:?}")));
        }
        let names: Vec<String> = file.parameters.keys().cloned().collect();
        let index = Names::new(&names);
        for n in &names {
            expr::valid_parameter_name(n).map_err(|why| SceneError::field(format!("parameters.{n}"), why))?;
        }
        let params = compile_params(&file, &index)?;
        let c = |n: &Num, f: String| Compiled::new(n, &index, &f);

        if file.masses.is_empty() {
            return Err(SceneError::field("masses", "a scene needs at least one mass"));
        }
        let mass_names: Vec<String> = file.masses.iter().map(|m| m.name.clone()).collect();
        unique(&mass_names, "masses")?;
        let masses = compile_masses(&file, &index)?;
        let links = compile_links(&file, &index, &mass_names)?;
        let stop_names: Vec<String> = file.stops.iter().map(|s| s.name.clone()).collect();
        unique(&stop_names, "stops")?;
        let stops = file
            .stops
            .iter()
            .enumerate()
            .map(|(i, st)| Ok((compile_stop(i, st, &index, &mass_names)?, compile_law(i, st, &index)?)))
            .collect::<Result<Vec<_>, SceneError>>()?;
        check_combination(&file, &stops.iter().map(|(_, l)| l.clone()).collect::<Vec<_>>())?;
        let friction = compile_friction(&file, &index, &mass_names)?;

        let labels = compile_labels(&file, &mass_names, &stop_names, &stops)?;

        let quantities = file
            .quantities
            .iter()
            .map(|(name, spec)| Derived::compile(name, spec, &names))
            .collect::<Result<_, SceneError>>()?;
        let scales = std::sync::Arc::new(Scales::of(&file.scales)?);
        let order = evaluation_order(&params);
        let scene = Scene {
            quantities,
            scales,
            source: text.to_string(),
            omega: c(&file.forcing.omega, "forcing.omega".into())?,
            tau: c(&file.forcing.phase, "forcing.phase".into())?,
            names,
            params,
            masses,
            links,
            stops,
            friction,
            labels,
            file,
            order,
        };
        // Evaluate the defaults once so that a broken scene fails at load time.
        scene.evaluate(&[])?;
        Ok(scene)
    }
}

/// Refuses a scene with more than `max` entries in `field`, with one line.
fn at_most(field: &str, what: &str, count: usize, max: usize) -> Result<(), SceneError> {
    if count > max {
        return Err(SceneError::field(field, format!("at most {max} {what} are supported, got {count}")));
    }
    Ok(())
}

/// The order in which parameters are evaluated: each after the parameters
/// its expression depends on, the smallest index first among those ready
/// (Kahn's algorithm, linear in the parameters and their dependencies).
/// Parameters on a circular definition, or depending on one, are left out.
fn evaluation_order(params: &[(Compiled, Option<Range>)]) -> Vec<usize> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let n = params.len();
    let mut waiting: Vec<usize> = params.iter().map(|(c, _)| c.dependencies().len()).collect();
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, (c, _)) in params.iter().enumerate() {
        for &d in c.dependencies() {
            dependents[d].push(i);
        }
    }
    let mut ready: BinaryHeap<Reverse<usize>> = (0..n).filter(|&i| waiting[i] == 0).map(Reverse).collect();
    let mut order = Vec::with_capacity(n);
    while let Some(Reverse(i)) = ready.pop() {
        order.push(i);
        for &j in &dependents[i] {
            waiting[j] -= 1;
            if waiting[j] == 0 {
                ready.push(Reverse(j));
            }
        }
    }
    order
}

/// The `[labels]` tables: per labelled mass (by index, in order) the
/// stops counted as its p and q. Each names a stop that the mass strikes
/// (a frame stop on it, or a pair stop of it and another mass); `p` is
/// required, `q` may be left out (always 0) but is not `p` again, whose
/// impacts it would count twice.
fn compile_labels(
    file: &SceneFile,
    mass_names: &[String],
    stop_names: &[String],
    stops: &[(StopPlace, CompiledLaw)],
) -> Result<Vec<LabelStops>, SceneError> {
    let mut labels = Vec::new();
    for (name, spec) in &file.labels {
        let m = index_of(mass_names, name, || format!("labels.{name}"), "mass")?;
        let stop = |s: &str, k: &str| {
            let field = format!("labels.{name}.{k}");
            let i = index_of(stop_names, s, || field.clone(), "stop")?;
            let strikes = match &stops[i].0 {
                StopPlace::Frame { mass, .. } => *mass == m,
                StopPlace::Pair { first, second, .. } => *first == m || *second == m,
            };
            match strikes {
                true => Ok(i),
                false => Err(SceneError::field(
                    field,
                    format!("stop '{s}' does not act on mass '{name}': a label counts the mass's own impacts"),
                )),
            }
        };
        let Some(p) = spec.p.as_deref() else {
            return Err(SceneError::field(
                format!("labels.{name}.p"),
                "missing: the stop counted as p in the mass's n-p-q label",
            ));
        };
        let p = stop(p, "p")?;
        let q = spec.q.as_deref().map(|q| stop(q, "q")).transpose()?;
        if q == Some(p) {
            return Err(SceneError::field(
                format!("labels.{name}.q"),
                format!(
                    "'{}' is p's stop too: each of its impacts would count twice; leave q out for a mass with one stop",
                    stop_names[p]
                ),
            ));
        }
        labels.push(LabelStops { mass: m, p, q });
    }
    labels.sort_by_key(|l| l.mass);
    Ok(labels)
}

pub(crate) fn index_of(
    names: &[String],
    name: &str,
    field: impl FnOnce() -> String,
    what: &str,
) -> Result<usize, SceneError> {
    names
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| SceneError::field(field(), format!("unknown {what} '{name}' (known: {})", names.join(", "))))
}

/// Why `name` cannot name a mass or stop, if it cannot: names become HDF5
/// group and dataset names (`/up/impact_sections/A1`, `label_code_M1`), so
/// they follow HDF5's and netCDF's rules for a path component.
fn name_problem(name: &str) -> Option<String> {
    if name.is_empty() {
        return Some("must not be empty".into());
    }
    if name == "." || name == ".." {
        return Some(format!("'{name}' is not a valid name (HDF5 group names cannot be '.' or '..')"));
    }
    if name.contains('/') {
        return Some(format!("'{name}' must not contain '/' (it separates HDF5 groups)"));
    }
    if name.contains(',') {
        return Some(format!("'{name}' must not contain ',' (it separates the names of a list in the file)"));
    }
    if name.chars().any(char::is_control) {
        return Some(format!("{name:?} must not contain control characters"));
    }
    if name.trim() != name {
        return Some(format!("'{name}' must not begin or end with spaces"));
    }
    let chars = name.chars().count();
    if chars > MAX_NAME_CHARS {
        return Some(format!("at most {MAX_NAME_CHARS} characters, got {chars}"));
    }
    None
}

/// Why `name` cannot name a mass (`masses`) or a stop (`stops`) of a file's
/// layout, if it cannot: a sweep holds `label_<mass>`, `label_code_<mass>`
/// and `label_colour`, and `sections/<stop>` beside `sections/period`.
fn reserved(name: &str, field: &str) -> Option<String> {
    let clash = match field {
        "masses" => name == "colour" || name.starts_with("code_"),
        _ => name == "period",
    };
    clash.then(|| {
        let what = if field == "masses" { "'colour' or begin with 'code_'" } else { "'period'" };
        format!("'{name}' is reserved: a file names its own datasets with it (a name must not be {what})")
    })
}

fn unique(names: &[String], field: &str) -> Result<(), SceneError> {
    for (i, n) in names.iter().enumerate() {
        if let Some(problem) = name_problem(n).or_else(|| reserved(n, field)) {
            return Err(SceneError::field(format!("{field}[{i}].name"), problem));
        }
        if names[..i].contains(n) {
            return Err(SceneError::field(format!("{field}[{i}].name"), format!("duplicate name '{n}'")));
        }
    }
    Ok(())
}

/// The compiled parameters of a scene file, with their ranges.
fn compile_params(file: &SceneFile, index: &Names) -> Result<Vec<(Compiled, Option<Range>)>, SceneError> {
    file.parameters
        .iter()
        .map(|(name, spec)| {
            let field = format!("parameters.{name}");
            let (num, range) = match spec {
                ParamSpec::Plain(n) => (n, None),
                ParamSpec::Ranged(r) => {
                    if let Some(t) = &r.symbol {
                        symbol::check_symbol(t, &format!("{field}.symbol"))?;
                    }
                    if let Some(t) = &r.long_name {
                        symbol::check_long_name(t, &format!("{field}.long_name"))?;
                    }
                    (&r.value, r.range.as_deref().map(|t| Range::parse(t, &field)).transpose()?)
                }
            };
            Ok((Compiled::new(num, index, &field)?, range))
        })
        .collect()
}

/// The order of a harmonic: a whole number from 1 to [`MAX_HARMONIC`],
/// written as a number.
fn harmonic_order(order: &Num, field: &str) -> Result<u32, SceneError> {
    let range =
        format!("a whole number from 1 to {MAX_HARMONIC} (the multiple of omega; the forcing period stays 2 pi/omega)");
    match *order {
        Num::Value(v) if v.fract() == 0.0 && (1.0..=f64::from(MAX_HARMONIC)).contains(&v) => Ok(v as u32),
        Num::Value(v) => Err(SceneError::field(field, format!("must be {range}, got {}", crate::number(v)))),
        Num::Expr(ref e) => Err(SceneError::field(field, format!("must be {range} written as a number, got '{e}'"))),
    }
}

/// The compiled values of each mass.
fn compile_masses(file: &SceneFile, index: &Names) -> Result<Vec<CompiledMass>, SceneError> {
    let c = |n: &Num, f: String| Compiled::new(n, index, &f);
    file.masses
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let harmonics = m
                .harmonics
                .iter()
                .enumerate()
                .map(|(j, h)| {
                    let f = |k: &str| format!("masses[{i}].harmonics[{j}].{k}");
                    Ok((
                        harmonic_order(&h.order, &f("order"))?,
                        c(&h.amplitude, f("amplitude"))?,
                        c(&h.phase, f("phase"))?,
                    ))
                })
                .collect::<Result<Vec<_>, SceneError>>()?;
            Ok(CompiledMass {
                mass: c(&m.mass, format!("masses[{i}].mass"))?,
                force: c(&m.force, format!("masses[{i}].force"))?,
                load: c(&m.load, format!("masses[{i}].load"))?,
                x0: c(&m.x0, format!("masses[{i}].x0"))?,
                v0: c(&m.v0, format!("masses[{i}].v0"))?,
                harmonics,
            })
        })
        .collect()
}

/// The links: masses (one: to the frame; two), stiffness and damping.
type Links = Vec<(usize, Option<usize>, Compiled, Compiled)>;

/// The compiled links of a scene file.
fn compile_links(file: &SceneFile, index: &Names, mass_names: &[String]) -> Result<Links, SceneError> {
    let c = |n: &Num, f: String| Compiled::new(n, index, &f);
    let mass = |name: &str, field: String| index_of(mass_names, name, || field, "mass");
    file.links
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let f = format!("links[{i}].masses");
            let (a, b) = match l.masses.as_slice() {
                [a] => (mass(a, f)?, None),
                [a, b] => {
                    let (a, b) = (mass(a, f.clone())?, mass(b, f.clone())?);
                    if a == b {
                        return Err(SceneError::field(f, "a link cannot tie a mass to itself"));
                    }
                    (a, Some(b))
                }
                _ => return Err(SceneError::field(f, "give one mass (to the frame) or two")),
            };
            Ok((a, b, c(&l.stiffness, format!("links[{i}].stiffness"))?, c(&l.damping, format!("links[{i}].damping"))?))
        })
        .collect()
}

/// The law of stop `i` of a scene file: `restitution` (rigid) or `stiffness`
/// and `damping` (soft), never both.
fn compile_law(i: usize, s: &schema::StopSpec, index: &Names) -> Result<CompiledLaw, SceneError> {
    let c = |n: &Num, f: String| Compiled::new(n, index, &f);
    let f = |k: &str| format!("stops[{i}].{k}");
    let zero = Num::Value(0.0);
    match (&s.restitution, &s.stiffness, &s.damping) {
        (Some(r), None, None) => Ok(CompiledLaw::Rigid { restitution: c(r, f("restitution"))? }),
        (None, None, None) => Err(SceneError::field(
            format!("stops[{i}]"),
            format!("stop {} needs `restitution` (a rigid stop) or `stiffness` and `damping` (a soft stop)", s.name),
        )),
        (None, k, d) => Ok(CompiledLaw::Soft {
            stiffness: c(k.as_ref().unwrap_or(&zero), f("stiffness"))?,
            damping: c(d.as_ref().unwrap_or(&zero), f("damping"))?,
        }),
        (Some(_), _, _) => Err(SceneError::field(
            f("restitution"),
            format!(
                "stop {} has both `restitution` (a rigid stop) and `stiffness`/`damping` (a soft stop); give one law",
                s.name
            ),
        )),
    }
}

/// Refuses the combination of stop laws and friction the solver does not
/// simulate: soft stops in a scene with friction contacts (one line naming
/// the first soft stop).
fn check_combination(file: &SceneFile, laws: &[CompiledLaw]) -> Result<(), SceneError> {
    let Some(soft) = laws.iter().position(|l| matches!(l, CompiledLaw::Soft { .. })) else { return Ok(()) };
    let name = &file.stops[soft].name;
    if !file.friction.is_empty() {
        return Err(SceneError::field(
            format!("stops[{soft}]"),
            format!("soft stop {name} in a scene with friction contacts: soft stops and friction are not supported together"),
        ));
    }
    Ok(())
}

/// Stop `i` of a scene file: where it is (a frame stop on one mass, or a
/// pair stop between two).
fn compile_stop(i: usize, s: &schema::StopSpec, index: &Names, mass_names: &[String]) -> Result<StopPlace, SceneError> {
    let c = |n: &Num, f: String| Compiled::new(n, index, &f);
    let mass = |name: &str, field: String| index_of(mass_names, name, || field, "mass");
    let f = |k: &str| format!("stops[{i}].{k}");
    let place = match (&s.mass, &s.masses) {
        (Some(m), None) => {
            if s.gap.is_some() {
                return Err(SceneError::field(f("gap"), "a frame stop has a position, not a gap"));
            }
            StopPlace::Frame {
                mass: mass(m, f("mass"))?,
                side: s.side.ok_or_else(|| SceneError::field(f("side"), "missing: \"below\" or \"above\""))?,
                position: c(
                    s.position.as_ref().ok_or_else(|| SceneError::field(f("position"), "missing"))?,
                    f("position"),
                )?,
            }
        }
        (None, Some(ms)) => {
            if s.side.is_some() || s.position.is_some() {
                return Err(SceneError::field(f("masses"), "a pair stop has a gap, not a side or position"));
            }
            let [a, b] = ms.as_slice() else {
                return Err(SceneError::field(f("masses"), "a pair stop names exactly two masses"));
            };
            let (first, second) = (mass(a, f("masses"))?, mass(b, f("masses"))?);
            if first == second {
                return Err(SceneError::field(f("masses"), "a stop cannot be between a mass and itself"));
            }
            StopPlace::Pair {
                first,
                second,
                gap: c(s.gap.as_ref().ok_or_else(|| SceneError::field(f("gap"), "missing"))?, f("gap"))?,
            }
        }
        _ => {
            return Err(SceneError::field(
                format!("stops[{i}]"),
                "give either `mass` (a frame stop) or `masses` (a pair stop)",
            ))
        }
    };
    Ok(place)
}

/// The friction contacts: two masses, kinetic and static coefficients.
type Frictions = Vec<(usize, usize, Compiled, Compiled)>;

/// The compiled friction contacts of a scene file.
fn compile_friction(file: &SceneFile, index: &Names, mass_names: &[String]) -> Result<Frictions, SceneError> {
    let c = |n: &Num, f: String| Compiled::new(n, index, &f);
    let mass = |name: &str, field: String| index_of(mass_names, name, || field, "mass");
    file.friction
        .iter()
        .enumerate()
        .map(|(i, fr)| {
            let f = format!("friction[{i}].masses");
            let [a, b] = fr.masses.as_slice() else {
                return Err(SceneError::field(f, "friction acts between exactly two masses"));
            };
            let (a, b) = (mass(a, f.clone())?, mass(b, f.clone())?);
            if a == b {
                return Err(SceneError::field(f, "friction cannot act between a mass and itself"));
            }
            Ok((
                a,
                b,
                c(&fr.kinetic, format!("friction[{i}].kinetic"))?,
                c(&fr.static_limit, format!("friction[{i}].static"))?,
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::name_problem;
    use crate::{Scene, MAX_NAME_CHARS};

    /// Two masses on springs, each with a frame stop, and a pair stop
    /// between them; `labels` is the scene's `[labels]` part.
    fn with_labels(labels: &str) -> Result<Scene, String> {
        let scene = format!(
            r#"name = "t"
[parameters]
[forcing]
omega = 1
[[masses]]
name = "X"
mass = 1
force = 1
[[masses]]
name = "Y"
mass = 1
[[links]]
masses = ["X"]
stiffness = 1
[[links]]
masses = ["Y"]
stiffness = 1
[[stops]]
name = "up"
mass = "X"
side = "above"
position = 1
restitution = 0.8
[[stops]]
name = "low"
mass = "Y"
side = "below"
position = -1
restitution = 0.8
[[stops]]
name = "XY"
masses = ["X", "Y"]
gap = 1
restitution = 0.8
{labels}"#
        );
        Scene::parse(&scene).map_err(|e| e.to_string())
    }

    /// The scene's name and description are printed as they are: an escape
    /// or a NUL in them is refused (a terminal would take an escape sequence
    /// as a command), a description's lines kept.
    #[test]
    fn a_scene_s_name_and_description_hold_no_control_characters() {
        let base = with_labels("").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(base.name(), "t");
        let scene = |head: &str| {
            let text = format!("{head}\n[parameters]\n[forcing]\nomega = 1\n[[masses]]\nname = \"X\"\nmass = 1\nforce = 1\n[[links]]\nmasses = [\"X\"]\nstiffness = 1\n");
            Scene::parse(&text).map_err(|e| e.to_string())
        };
        assert!(scene("name = \"t\"\ndescription = \"two lines,\\r\\nand a\\ttab\"").is_ok());
        refused(
            scene,
            &[
                ("name = \"a\\u001b[31mb\"", "name: must be one line"),
                ("name = \"a\\u0000b\"", "name: must be one line"),
                ("name = \"two\\nlines\"", "name: must be one line"),
                ("name = \"t\"\ndescription = \"a\\u001b[2Jb\"", "description: must not hold control characters"),
            ],
        );
    }

    /// Each text of `cases` refused by `parse` with an error containing its message.
    fn refused(parse: impl Fn(&str) -> Result<Scene, String>, cases: &[(&str, &str)]) {
        for (text, said) in cases {
            let err = parse(text).expect_err(text);
            assert!(err.contains(said), "{text}: {err}");
        }
    }

    /// A label counts its mass's own impacts: p is given, names a stop the
    /// mass strikes (its frame stop or a pair stop of it), and q is not p's
    /// stop again (each impact would count twice). An empty `[labels.X]`
    /// labelled every motion `n-0-0`; `q = p` counted one impact as `1-1-1`;
    /// another mass's stop gave X that mass's count.
    #[test]
    fn a_label_counts_its_own_masses_impacts_once() {
        for good in
            ["[labels.X]\np = \"up\"", "[labels.X]\np = \"XY\"\nq = \"up\"", "[labels.Y]\np = \"XY\"\nq = \"low\""]
        {
            assert!(with_labels(good).is_ok(), "{good}: {:?}", with_labels(good).err());
        }
        refused(
            with_labels,
            &[
                ("[labels.X]", "labels.X.p: missing"),
                ("[labels.X]\nq = \"up\"", "labels.X.p: missing"),
                ("[labels.X]\np = \"up\"\nq = \"up\"", "labels.X.q: 'up' is p's stop too"),
                ("[labels.Y]\np = \"up\"", "labels.Y.p: stop 'up' does not act on mass 'Y'"),
                ("[labels.X]\np = \"up\"\nq = \"low\"", "labels.X.q: stop 'low' does not act on mass 'X'"),
                ("[labels.X]\np = \"side\"", "labels.X.p: unknown stop 'side'"),
                ("[labels.Z]\np = \"up\"", "labels.Z: unknown mass 'Z'"),
            ],
        );
    }

    #[test]
    fn names_follow_hdf5_group_rules() {
        for good in ["A1", "M", "left stop", "δ-stop", "a.b", "..x"] {
            assert_eq!(name_problem(good), None, "{good}");
        }
        let long = "x".repeat(MAX_NAME_CHARS + 1);
        for bad in ["", ".", "..", "a/b", "/", "a\nb", "tab\t", " A1", "A1 ", "M,1", long.as_str()] {
            assert!(name_problem(bad).is_some(), "{bad:?}");
        }
        assert_eq!(name_problem(&"é".repeat(MAX_NAME_CHARS)), None);
    }
}
