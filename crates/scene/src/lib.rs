//! Scene files for vibroatlas.
//!
//! A scene is data: masses, linear links (spring + damper), harmonic forcing,
//! rigid stops, friction contacts and the label map, in TOML, with every number
//! allowed to be an expression of named parameters. [`Scene::parse`] reads and
//! checks the file once; [`Scene::evaluate`] produces the numeric [`Model`] of one
//! cell for given parameter overrides.
//!
//! ```
//! let text = r#"
//! name = "oscillator"
//! [parameters]
//! omega = 0.5
//! zeta = { value = 0.1, range = "[0, inf)" }
//! [forcing]
//! omega = "omega"
//! [[masses]]
//! name = "M1"
//! mass = 1
//! force = 1
//! [[links]]
//! masses = ["M1"]
//! stiffness = 1
//! damping = "2*zeta"
//! "#;
//! let scene = scene::Scene::parse(text).unwrap();
//! let model = scene.evaluate(&[("zeta".into(), 0.2)]).unwrap();
//! assert_eq!(model.links[0].damping, 0.4);
//! assert!(scene.evaluate(&[("zeta".into(), -1.0)]).is_err());
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

mod derived;
mod error;
mod expr;
mod model;
mod named;
mod scales;
mod schema;
mod symbol;

pub use derived::{Derived, Operand, TAKEN_NAMES};
pub use error::SceneError;
pub use expr::MAX_EXPRESSION_CHARS;
pub use model::{Friction, Harmonic, LabelStops, LawKind, Link, Mass, Model, Side, Stop, StopGeometry, StopLaw};
pub use named::Named;
pub use scales::{Scale, Scales};
pub use symbol::{symbol_of, SYMBOL_MAX_CHARS};

use expr::{Compiled, Names, Range};
use schema::{Num, ParamSpec, SceneFile};

/// Compiled values of one `[[stops]]` entry.
#[derive(Debug, Clone)]
enum StopPlace {
    Frame { mass: usize, side: Side, position: Compiled },
    Pair { first: usize, second: usize, gap: Compiled },
}

/// The compiled law of one `[[stops]]` entry.
#[derive(Debug, Clone)]
enum CompiledLaw {
    Rigid { restitution: Compiled },
    Soft { stiffness: Compiled, damping: Compiled },
}

/// The compiled values of one `[[masses]]` entry.
#[derive(Debug, Clone)]
struct CompiledMass {
    mass: Compiled,
    force: Compiled,
    load: Compiled,
    x0: Compiled,
    v0: Compiled,
    /// Order, amplitude and phase of each further harmonic.
    harmonics: Vec<(u32, Compiled, Compiled)>,
}

/// Highest multiple of ω a harmonic of the forcing may have: each harmonic
/// adds two states to every mode of the solver.
pub const MAX_HARMONIC: u32 = 16;

/// Smallest forcing frequency a scene may have. Below it the forced velocities
/// (of order ω times the displacements) fall under the stick velocity of the
/// `standard` preset (1e-7), so that a slow approach to a stop cannot be told
/// from rest; the solver then ends such cells unresolved. Refused up front.
pub const OMEGA_MIN: f64 = 1e-6;

/// A phase (radians) as the solver takes it: the value itself where
/// |x| ≤ 2π (kept bit for bit), else its residue modulo 2π in (−π, π],
/// reduced exactly. The C library's `sin` and `cos` reduce their argument
/// with as many digits of π as it needs, and `atan2` of the two gives the
/// angle back to an ulp; reducing with the double nearest 2π instead would
/// be off by |x| · 2.4e-16 (2e-6 at 1e10), and forming `ω t + x` with a
/// large x would round every event's phase. A phase that is not finite is
/// refused, naming `field`.
fn phase(x: f64, field: &dyn Fn() -> String) -> Result<f64, SceneError> {
    if !x.is_finite() {
        return Err(SceneError::field(field(), format!("a phase must be a finite number of radians, got {x}")));
    }
    if x.abs() <= std::f64::consts::TAU {
        return Ok(x);
    }
    let (sin, cos) = x.sin_cos();
    Ok(sin.atan2(cos))
}

/// Largest penetration of a stop by the initial state a scene writes: its
/// positions may touch a stop to rounding, never press into it. (Simulated
/// states are held to the solver's own, looser, admissibility.)
const INITIAL_PENETRATION: f64 = 1e-12;

/// Most masses a scene may have (issue 30). The solver decomposes each mode
/// (each set of held stops and stuck contacts) into its eigenvectors, at a cost
/// growing as the fourth power of the masses: measured on 2 shared cores, a
/// cell's first 20 periods take 0.7 s at 32 masses, 2 to 7 s at 64, 94 s at
/// 128 and 260 s at 192 (a scene with 300 masses did not finish one cell in
/// 120 s). Refused when the scene is loaded, with one line naming `masses`.
pub const MAX_MASSES: usize = 64;

/// Most stops a scene may have: the solver keeps the held stops of a mode in
/// a 16-bit set, and every combination may become a mode of its own.
pub const MAX_STOPS: usize = 16;

/// Most friction contacts a scene may have (the solver's stuck set, 8 bits).
pub const MAX_FRICTION: usize = 8;

/// A parsed and structurally checked scene, ready to be evaluated for any parameters.
#[derive(Debug, Clone)]
pub struct Scene {
    source: String,
    file: SceneFile,
    names: Vec<String>,
    params: Vec<(Compiled, Option<Range>)>,
    omega: Compiled,
    tau: Compiled,
    masses: Vec<CompiledMass>,
    links: Vec<(usize, Option<usize>, Compiled, Compiled)>,
    stops: Vec<(StopPlace, CompiledLaw)>,
    friction: Vec<(usize, usize, Compiled, Compiled)>,
    labels: Vec<(usize, Option<usize>, Option<usize>)>,
    /// The quantities it defines (`[quantities]`).
    quantities: std::sync::Arc<[Derived]>,
    /// Its physical scales (`[scales]`).
    scales: std::sync::Arc<Scales>,
    /// Parameters in an order that evaluates each after those it depends on
    /// (topological, smallest index first); those on or after a circular
    /// definition are left out.
    order: Vec<usize>,
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

fn index_of(names: &[String], name: &str, field: impl FnOnce() -> String, what: &str) -> Result<usize, SceneError> {
    names
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| SceneError::field(field(), format!("unknown {what} '{name}' (known: {})", names.join(", "))))
}

/// Smallest ratio of a mass to the heaviest of its scene. Below it the modes
/// of the linear flow are ill-conditioned: the solver can only call its cells
/// unresolved, and from about 1e-14 rounding loses the light mass altogether.
pub const MASS_RATIO_MIN: f64 = 1e-9;

/// Refuses a mass lighter than [`MASS_RATIO_MIN`] times the heaviest.
fn check_mass_ratio(masses: &[Mass]) -> Result<(), SceneError> {
    let heaviest = masses.iter().map(|m| m.mass).fold(0.0, f64::max);
    match masses.iter().position(|m| m.mass < MASS_RATIO_MIN * heaviest) {
        Some(i) => Err(SceneError::field(
            format!("masses[{i}].mass"),
            format!(
                "{:e} is less than {MASS_RATIO_MIN:e} times the heaviest mass ({heaviest:e}): the motion cannot be resolved in double precision",
                masses[i].mass
            ),
        )),
        None => Ok(()),
    }
}

/// Longest name of a mass or stop, in characters.
pub const MAX_NAME_CHARS: usize = 64;

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
        Num::Value(v) => Err(SceneError::field(field, format!("must be {range}, got {v}"))),
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

impl Scene {
    /// Parses a scene from TOML text, resolving names and compiling expressions.
    pub fn parse(text: &str) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text)
            .map_err(|e| SceneError::Syntax { message: e.to_string().trim().replace('\n', " ") })?;
        at_most("masses", "masses", file.masses.len(), MAX_MASSES)?;
        at_most("stops", "stops", file.stops.len(), MAX_STOPS)?;
        at_most("friction", "friction contacts", file.friction.len(), MAX_FRICTION)?;
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
        let mass = |name: &str, field: String| index_of(&mass_names, name, || field, "mass");
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

        let mut labels = Vec::new();
        for (name, spec) in &file.labels {
            let m = mass(name, format!("labels.{name}"))?;
            let stop = |s: &Option<String>, k: &str| {
                s.as_deref().map(|s| index_of(&stop_names, s, || format!("labels.{name}.{k}"), "stop")).transpose()
            };
            labels.push((m, stop(&spec.p, "p")?, stop(&spec.q, "q")?));
        }
        labels.sort_by_key(|l| l.0);

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

    /// The normal `n` of each stop's gap `g = n·x + c` over the positions of
    /// the masses ([`StopGeometry::gap_function`]): structural, the same for
    /// every parameter value.
    pub fn stop_normals(&self) -> Vec<Vec<f64>> {
        self.stops
            .iter()
            .map(|(place, _)| {
                let geometry = match *place {
                    StopPlace::Frame { mass, side, .. } => StopGeometry::Frame { mass, side, position: 0.0 },
                    StopPlace::Pair { first, second, .. } => StopGeometry::Pair { first, second, gap: 0.0 },
                };
                geometry.gap_function(self.masses.len()).0
            })
            .collect()
    }

    /// Which contact law each stop obeys, in stop order: structural, the
    /// same for every parameter value.
    pub fn stop_laws(&self) -> Vec<LawKind> {
        let kind = |law: &CompiledLaw| match law {
            CompiledLaw::Rigid { .. } => LawKind::Rigid,
            CompiledLaw::Soft { .. } => LawKind::Soft,
        };
        self.stops.iter().map(|(_, law)| kind(law)).collect()
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.file.name
    }

    /// The scene's description (equations, source), as written in the file.
    pub fn description(&self) -> &str {
        &self.file.description
    }

    /// The TOML text the scene was parsed from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The names of the scene's parameters, in alphabetical order.
    pub fn parameter_names(&self) -> &[String] {
        &self.names
    }

    /// How figures and files write parameter `name`: the `symbol` it declares,
    /// else [`symbol_of`] its name (`omega` → `ω`, `mu_k` → `μ_k`, `fk` → `fk`);
    /// a name that is no parameter of the scene gets [`symbol_of`] too.
    pub fn symbol(&self, name: &str) -> String {
        match self.file.parameters.get(name) {
            Some(ParamSpec::Ranged(r)) if r.symbol.is_some() => r.symbol.clone().unwrap_or_default(),
            _ => symbol_of(name),
        }
    }

    /// What parameter `name` is, in a few words: the `long_name` it declares,
    /// else the first line of its `doc`; `None` when it has neither (or is no
    /// parameter of the scene).
    pub fn long_name(&self, name: &str) -> Option<&str> {
        match self.file.parameters.get(name) {
            Some(ParamSpec::Ranged(r)) => r.long_name.as_deref().or_else(|| symbol::long_name_of_doc(&r.doc)),
            _ => None,
        }
    }

    /// Whether parameter `name` is a plain number (not an expression of others).
    pub fn is_plain(&self, name: &str) -> bool {
        self.names.iter().position(|n| n == name).is_some_and(|i| matches!(self.params[i].0, Compiled::Value(_)))
    }

    /// The ends `[lo, hi]` of the range parameter `name` declares (open or
    /// closed, infinite where unbounded); `None` when it declares none or is
    /// no parameter of the scene.
    pub fn range(&self, name: &str) -> Option<[f64; 2]> {
        let i = self.names.iter().position(|n| n == name)?;
        self.params[i].1.as_ref().map(Range::bounds)
    }

    /// Checks that `name` is a parameter of the scene.
    pub fn check_parameter(&self, name: &str, field: &str) -> Result<(), SceneError> {
        index_of(&self.names, name, || field.to_string(), "parameter").map(|_| ())
    }

    /// Evaluates every value for the default parameters with `overrides` applied
    /// (an override replaces the parameter's expression), and checks the physics.
    pub fn evaluate(&self, overrides: &[(String, f64)]) -> Result<Model, SceneError> {
        let n = self.names.len();
        let mut values = vec![f64::NAN; n];
        let mut known = vec![false; n];
        for (name, v) in overrides {
            let i = index_of(&self.names, name, || format!("parameters.{name}"), "parameter")?;
            if !v.is_finite() {
                return Err(SceneError::field(format!("parameters.{name}"), format!("not a finite number, got {v}")));
            }
            values[i] = *v;
            known[i] = true;
        }
        // Resolve parameters defined by expressions in dependency order.
        for &i in &self.order {
            if !known[i] {
                values[i] = self.params[i].0.eval(&values, || format!("parameters.{}", self.names[i]))?;
                known[i] = true;
            }
        }
        if let Some(i) = known.iter().position(|k| !k) {
            return Err(SceneError::field(
                format!("parameters.{}", self.names[i]),
                "circular definition among parameters",
            ));
        }
        for (i, (_, range)) in self.params.iter().enumerate() {
            if let Some(r) = range {
                if !r.contains(values[i]) {
                    return Err(SceneError::field(
                        format!("parameters.{}", self.names[i]),
                        format!("must be in {r}, got {}", values[i]),
                    ));
                }
            }
        }
        self.build(&values)
    }

    fn build(&self, values: &[f64]) -> Result<Model, SceneError> {
        let ev = |c: &Compiled, f: &dyn Fn() -> String| c.eval(values, f);
        let omega = ev(&self.omega, &|| "forcing.omega".into())?;
        if omega.is_nan() || omega < OMEGA_MIN {
            return Err(SceneError::field(
                "forcing.omega",
                format!(
                    "must be at least {OMEGA_MIN:e} (under slower forcing every velocity is below the solver's stick velocity and contacts cannot be told from rest), got {omega:e}"
                ),
            ));
        }
        let tau = phase(ev(&self.tau, &|| "forcing.phase".into())?, &|| "forcing.phase".into())?;
        let masses = self
            .masses
            .iter()
            .zip(&self.file.masses)
            .enumerate()
            .map(|(i, (m, spec))| {
                let mass = ev(&m.mass, &|| format!("masses[{i}].mass"))?;
                if mass <= 0.0 {
                    return Err(SceneError::field(format!("masses[{i}].mass"), format!("must be > 0, got {mass}")));
                }
                let harmonics = m
                    .harmonics
                    .iter()
                    .enumerate()
                    .map(|(j, (order, a, p))| {
                        let f = |k: &str| format!("masses[{i}].harmonics[{j}].{k}");
                        Ok(Harmonic {
                            order: *order,
                            amplitude: ev(a, &|| f("amplitude"))?,
                            phase: phase(ev(p, &|| f("phase"))?, &|| f("phase"))?,
                        })
                    })
                    .collect::<Result<Vec<_>, SceneError>>()?;
                Ok(Mass {
                    name: spec.name.clone(),
                    mass,
                    force: ev(&m.force, &|| format!("masses[{i}].force"))?,
                    load: ev(&m.load, &|| format!("masses[{i}].load"))?,
                    harmonics,
                    x0: ev(&m.x0, &|| format!("masses[{i}].x0"))?,
                    v0: ev(&m.v0, &|| format!("masses[{i}].v0"))?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        check_mass_ratio(&masses)?;
        let links = self
            .links
            .iter()
            .enumerate()
            .map(|(i, (a, b, k, c))| {
                Ok(Link {
                    a: *a,
                    b: *b,
                    stiffness: nonneg(k, values, &|| format!("links[{i}].stiffness"))?,
                    damping: nonneg(c, values, &|| format!("links[{i}].damping"))?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        let stops = self.build_stops(values)?;
        let friction = self.build_friction(values)?;
        let model = Model {
            name: self.file.name.clone(),
            symmetric: self.file.symmetric,
            omega,
            tau,
            masses,
            links,
            stops,
            friction,
            labels: self.labels.iter().map(|&(mass, p, q)| LabelStops { mass, p, q }).collect(),
            parameters: self.names.iter().cloned().zip(values.iter().copied()).collect(),
            quantities: self.quantities.clone(),
            scales: self.scales.clone(),
        };
        if model.symmetric {
            check_mirror(&model.stops)?;
            check_odd_forcing(&model.masses)?;
        }
        let x0: Vec<f64> = model.masses.iter().map(|m| m.x0).collect();
        // A rigid stop admits no initial penetration; a soft one's spring takes it up.
        let rigid = |s: &&Stop| match s.law {
            StopLaw::Rigid { .. } => true,
            StopLaw::Soft { .. } => false,
        };
        for (i, s) in model.stops.iter().enumerate().filter(|(_, s)| rigid(s)) {
            let g = model.gap(i, &x0);
            if g < -INITIAL_PENETRATION {
                return Err(SceneError::field(
                    "masses.x0",
                    format!("the initial state penetrates stop {} by {}", s.name, -g),
                ));
            }
        }
        Ok(model)
    }
    /// The stops at the parameter `values`: geometry and law (a restitution
    /// in [0, 1]; a soft stop's stiffness and damping not negative, not both zero).
    fn build_stops(&self, values: &[f64]) -> Result<Vec<Stop>, SceneError> {
        let ev = |c: &Compiled, f: &dyn Fn() -> String| c.eval(values, f);
        self.stops
            .iter()
            .zip(&self.file.stops)
            .enumerate()
            .map(|(i, ((place, law), spec))| {
                let f = |k: &str| format!("stops[{i}].{k}");
                let law = match law {
                    CompiledLaw::Rigid { restitution } => {
                        let restitution = ev(restitution, &|| f("restitution"))?;
                        if !(0.0..=1.0).contains(&restitution) {
                            return Err(SceneError::field(
                                f("restitution"),
                                format!("must be in [0, 1], got {restitution}"),
                            ));
                        }
                        StopLaw::Rigid { restitution }
                    }
                    CompiledLaw::Soft { stiffness, damping } => {
                        let stiffness = nonneg(stiffness, values, &|| f("stiffness"))?;
                        let damping = nonneg(damping, values, &|| f("damping"))?;
                        if stiffness == 0.0 && damping == 0.0 {
                            return Err(SceneError::field(
                                f("stiffness"),
                                format!(
                                    "soft stop {} has zero stiffness and zero damping: it would never act",
                                    spec.name
                                ),
                            ));
                        }
                        StopLaw::Soft { stiffness, damping }
                    }
                };
                let geometry = match place {
                    StopPlace::Frame { mass, side, position } => {
                        StopGeometry::Frame { mass: *mass, side: *side, position: ev(position, &|| f("position"))? }
                    }
                    StopPlace::Pair { first, second, gap } => {
                        StopGeometry::Pair { first: *first, second: *second, gap: nonneg(gap, values, &|| f("gap"))? }
                    }
                };
                Ok(Stop { name: spec.name.clone(), geometry, law })
            })
            .collect()
    }
    /// The friction contacts at the parameter `values`: static at least kinetic.
    fn build_friction(&self, values: &[f64]) -> Result<Vec<Friction>, SceneError> {
        self.friction
            .iter()
            .enumerate()
            .map(|(i, (a, b, k, s))| {
                let kinetic = nonneg(k, values, &|| format!("friction[{i}].kinetic"))?;
                let static_limit = s.eval(values, || format!("friction[{i}].static"))?;
                if static_limit < kinetic {
                    return Err(SceneError::field(
                        format!("friction[{i}].static"),
                        format!("must be >= the kinetic force {kinetic}, got {static_limit}"),
                    ));
                }
                Ok(Friction { a: *a, b: *b, kinetic, static_limit })
            })
            .collect()
    }
}

/// The value of `c` at the parameter `values` when it is not negative
/// (`field()` names the field of an error).
fn nonneg(c: &Compiled, values: &[f64], field: &dyn Fn() -> String) -> Result<f64, SceneError> {
    let v = c.eval(values, field)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(SceneError::field(field(), format!("must be >= 0, got {v}")))
    }
}

/// Checks that a scene declared `symmetric` is: every stop has a mirror image
/// under `x -> -x` among the stops (a frame stop at `p` on one side, one at `-p`
/// on the other side of the same mass; a pair stop `x_a - x_b <= g`, one with
/// the masses swapped), with the same law. Links and the first harmonic are odd
/// under the mirror with a half-period shift whatever their values; loads and
/// even harmonics are checked by [`check_odd_forcing`].
fn check_mirror(stops: &[Stop]) -> Result<(), SceneError> {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
    let same_law = |a: StopLaw, b: StopLaw| match (a, b) {
        (StopLaw::Rigid { restitution: r }, StopLaw::Rigid { restitution: s }) => close(r, s),
        (StopLaw::Soft { stiffness: k, damping: c }, StopLaw::Soft { stiffness: k2, damping: c2 }) => {
            close(k, k2) && close(c, c2)
        }
        _ => false,
    };
    for (i, s) in stops.iter().enumerate() {
        let mirrored = stops.iter().any(|t| {
            same_law(s.law, t.law)
                && match (&s.geometry, &t.geometry) {
                    (
                        StopGeometry::Frame { mass, side, position },
                        StopGeometry::Frame { mass: m2, side: s2, position: p2 },
                    ) => mass == m2 && side != s2 && close(*position, -*p2),
                    (
                        StopGeometry::Pair { first, second, gap },
                        StopGeometry::Pair { first: f2, second: s2, gap: g2 },
                    ) => first == s2 && second == f2 && close(*gap, *g2),
                    _ => false,
                }
        });
        if !mirrored {
            return Err(SceneError::field(
                "symmetric",
                format!(
                    "true, but stop {} (stops[{i}]) has no mirror image under x -> -x; set symmetric = false",
                    s.name
                ),
            ));
        }
    }
    Ok(())
}

/// Checks that the forcing of a scene declared `symmetric` is odd under a
/// half-period shift: no load, no harmonic of even order (with any
/// amplitude), which `x -> -x` would not map onto itself.
fn check_odd_forcing(masses: &[Mass]) -> Result<(), SceneError> {
    for (i, m) in masses.iter().enumerate() {
        if m.load != 0.0 {
            return Err(SceneError::field(
                format!("masses[{i}].load"),
                format!("{} breaks the mirror symmetry the scene declares (a load is even under x -> -x with a half-period shift); set symmetric = false", m.load),
            ));
        }
        if let Some(j) = m.harmonics.iter().position(|h| h.order % 2 == 0 && h.amplitude != 0.0) {
            return Err(SceneError::field(
                format!("masses[{i}].harmonics[{j}].order"),
                format!(
                    "{} (even) breaks the mirror symmetry the scene declares; set symmetric = false",
                    m.harmonics[j].order
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod name_tests {
    use super::{name_problem, phase, MAX_NAME_CHARS};

    /// Large phases against their residues mod 2π computed with 100 digits
    /// of π (Python's decimal module): equal to an ulp; small ones kept bit
    /// for bit; a phase that is not finite refused, naming the field.
    #[test]
    fn phases_are_reduced_exactly() {
        let field = || "forcing.phase".to_string();
        for (x, residue) in [
            (62831853073.36665, 1.5707886731299447),
            (1.44e17, 2.2036341134760633),
            (1.4411518807593622e17, -6.770188667773585e-05),
            (-1e12, 0.6576247591367864),
        ] {
            let r = phase(x, &field).unwrap();
            assert!((r - residue).abs() <= 2.0 * f64::EPSILON, "{x}: {r} against {residue}");
        }
        for x in [0.0, -1.0, std::f64::consts::FRAC_PI_2, std::f64::consts::TAU, -std::f64::consts::TAU] {
            assert_eq!(phase(x, &field).unwrap().to_bits(), x.to_bits());
        }
        for x in [f64::NAN, f64::INFINITY] {
            let e = phase(x, &field).unwrap_err().to_string();
            assert!(e.starts_with("forcing.phase: a phase must be a finite number"), "{e}");
        }
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
