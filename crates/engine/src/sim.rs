//! What every run is given: a scene (a file or a TOML text), parameter values
//! that override the scene's (`--set`), a preset, accuracy knobs and an
//! integrator ([`Sim`]); validated into a [`Setup`]. Where a simulation
//! starts ([`Start`]): the scene's initial state, a given state, or a cell of
//! a stored file, whose settings it then takes ([`Origin`]).

use crate::error::Result;
use crate::error::{Opt, RequestError, SceneLoadError, TEXT};
use scene::Named;
use scene::Scene;
use serde::Serialize;
use solver::contact::{Contact, Spring};
use solver::{Accuracy, Knob, Method, Preset};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Where a scene comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneSource {
    /// A TOML file.
    File(PathBuf),
    /// A TOML text (a notebook's scene, never written to a file).
    Text(String),
    /// The scene stored in an atlas or sweep file (`cell --from FILE`
    /// without a scene file).
    Stored(PathBuf),
}

/// Largest scene or study file read, in bytes: a scene is a page of TOML,
/// and a bound keeps a device (`/dev/zero`) or a wrong file from filling the
/// memory.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The text of the file `path`, read up to [`MAX_SCENE_BYTES`]; a longer
/// one is an error saying so. A named pipe or a socket is refused before it
/// is opened (opening a pipe waits for a writer, for ever), and so is a folder.
pub(crate) fn read_text(path: &std::path::Path) -> std::io::Result<String> {
    use std::io::Read;
    use std::os::unix::fs::FileTypeExt;
    let kind = std::fs::metadata(path)?.file_type();
    let what = if kind.is_fifo() {
        Some("a named pipe")
    } else if kind.is_socket() {
        Some("a socket")
    } else if kind.is_dir() {
        Some("a folder")
    } else {
        None
    };
    if let Some(what) = what {
        return Err(std::io::Error::other(format!("not a regular file ({what})")));
    }
    let mut text = String::new();
    std::fs::File::open(path)?.take(MAX_SCENE_BYTES + 1).read_to_string(&mut text)?;
    if text.len() as u64 > MAX_SCENE_BYTES {
        return Err(std::io::Error::other(format!(
            "longer than {MAX_SCENE_BYTES} bytes, the most a scene or study file may be"
        )));
    }
    Ok(text)
}

/// What the solver does not support in the structure of `scene` (such as a
/// quantity of `[quantities]` that reads a name that is neither a parameter
/// nor a built-in quantity), checked when the scene is loaded: the built-in
/// quantities follow from its masses, stops and contacts alone, the same
/// for every parameter value. Numbers that depend on the parameters are
/// each cell's to check.
fn check_structure(scene: &Scene) -> Result<(), scene::SceneError> {
    let Ok(model) = scene.evaluate(&[]) else { return Ok(()) };
    match solver::System::new(model) {
        Err(solver::SolverError::Unsupported { field, message }) => Err(scene::SceneError::field(field, message)),
        _ => Ok(()),
    }
}

impl SceneSource {
    /// The scene it holds.
    pub fn load(&self) -> Result<Scene, SceneLoadError> {
        let (text, origin) = match self {
            SceneSource::File(path) => (
                read_text(path).map_err(|cause| SceneLoadError::Read { path: path.clone(), cause })?,
                path.display().to_string(),
            ),
            // As long as a file may be: a text's errors quote it.
            SceneSource::Text(text) if text.len() as u64 > MAX_SCENE_BYTES => {
                let message = format!("{} bytes, more than a scene may be ({MAX_SCENE_BYTES})", text.len());
                return Err(SceneLoadError::Invalid {
                    origin: TEXT.to_string(),
                    cause: scene::SceneError::Syntax { message },
                });
            }
            SceneSource::Text(text) => (text.clone(), TEXT.to_string()),
            SceneSource::Stored(path) => (
                store::stored_scene(path).map_err(SceneLoadError::Stored)?,
                format!("{}: its stored scene", path.display()),
            ),
        };
        let scene = Scene::parse(&text).map_err(|cause| SceneLoadError::Invalid { origin: origin.clone(), cause })?;
        check_structure(&scene).map_err(|cause| SceneLoadError::Invalid { origin, cause })?;
        Ok(scene)
    }
}

/// The simulation options of every run, as given (not yet validated).
#[derive(Debug, Clone, PartialEq)]
pub struct Sim {
    /// The scene.
    pub scene: SceneSource,
    /// Parameter values replacing the scene's (`--set NAME=VALUE`), in order.
    pub set: Vec<(String, f64)>,
    /// The preset (`standard` when `None`; a stored cell's with [`Start::Cell`]).
    pub preset: Option<Preset>,
    /// Accuracy knobs replacing the preset's (`--accuracy KNOB=VALUE`), in order.
    pub accuracy: Vec<(Knob, f64)>,
    /// The integrator (`exact` when `None`; a stored cell's with [`Start::Cell`]).
    pub integrator: Option<Method>,
}

/// The refusal of a `--set` of `name`, a parameter that the run varies
/// itself (`what`: how, e.g. "also an axis of the run").
pub(crate) fn set_refused(name: &str, what: &str) -> crate::Error {
    RequestError::keyed(Opt::Set, name)
        .text(format!("{name} is {what}, which would override it; remove the "))
        .opt(Opt::Set)
        .into()
}

impl Sim {
    /// Refuses a `--set` of a parameter of `varied`, which the run varies
    /// itself (`what`: how), before any work: its value would be ignored.
    pub(crate) fn refuse_set_of(&self, varied: &[&str], what: &str) -> Result<()> {
        match self.set.iter().find(|(n, _)| varied.contains(&n.as_str())) {
            Some((n, _)) => Err(set_refused(n, what)),
            None => Ok(()),
        }
    }

    /// The files a run of these options from `start` reads, which no output
    /// of it may replace: the scene's file, or the file whose stored scene it
    /// takes, and the file of a stored cell it starts from.
    pub fn inputs<'a>(&'a self, start: &'a Start) -> Vec<&'a std::path::Path> {
        let scene = match &self.scene {
            SceneSource::File(path) | SceneSource::Stored(path) => Some(path.as_path()),
            SceneSource::Text(_) => None,
        };
        let cell = match start {
            Start::Cell { file, .. } => Some(file.as_path()),
            Start::Initial | Start::State(_) => None,
        };
        scene.into_iter().chain(cell).collect()
    }

    /// Options with the scene's own values, the `standard` preset and the exact flow.
    pub fn new(scene: SceneSource) -> Sim {
        Sim { scene, set: Vec::new(), preset: None, accuracy: Vec::new(), integrator: None }
    }

    /// Loads the scene and validates every option.
    pub fn setup(&self) -> Result<Setup> {
        self.setup_with(self.preset.unwrap_or(Preset::Standard), self.integrator.unwrap_or(Method::Exact), &[])
    }

    /// [`Sim::setup`] with the preset and integrator given, and `knobs` applied
    /// before the options' own.
    fn setup_with(&self, preset: Preset, method: Method, knobs: &[(Knob, f64)]) -> Result<Setup> {
        let scene = self.scene.load()?;
        for (k, (name, value)) in self.set.iter().enumerate() {
            check_finite(*value, || RequestError::keyed(Opt::Set, name))?;
            scene.check_parameter(name, "").map_err(|e| unknown(RequestError::keyed(Opt::Set, name), e))?;
            if let Some((_, first)) = self.set[..k].iter().find(|(n, _)| n == name) {
                let why = format!("given twice ({first} and {value}); give each parameter once");
                return Err(RequestError::keyed(Opt::Set, name).text(why).into());
            }
        }
        for (k, (knob, value)) in self.accuracy.iter().enumerate() {
            if let Some((_, first)) = self.accuracy[..k].iter().find(|(n, _)| n == knob) {
                let why = format!("given twice ({first} and {value}); give each knob once");
                return Err(RequestError::keyed(Opt::Accuracy, knob.name()).text(why).into());
            }
        }
        let mut accuracy = Accuracy::preset(preset);
        let mut accuracy_overrides = Vec::new();
        for &(k, v) in knobs.iter().chain(&self.accuracy) {
            check_finite(v, || RequestError::keyed(Opt::Accuracy, k.name()))?;
            accuracy.set(k, v)?;
            accuracy_overrides.push((k, v));
        }
        if method == Method::Rk4 {
            check_rk4_resolves_contacts(&scene, &self.set, &accuracy)?;
        }
        Ok(Setup { scene, overrides: self.set.clone(), accuracy, accuracy_overrides, preset, method })
    }
}

/// Refuses RK4 with a step that does not resolve a soft stop's contact at
/// the scene's point: a fixed step must be at most a tenth of the contact's
/// period `2π/ω₀` (`ω₀` the larger of `√(k/m)` and `c/m`, m the contact's
/// effective mass `1/(nᵀM⁻¹n)`); beyond that RK4's contacts are wrong
/// without a sign (measured: |μ| 0.747 against 0.580 at k = 1e4 with the
/// default step, an unstable orbit at 1e8). The exact flow has no such limit.
fn check_rk4_resolves_contacts(scene: &Scene, set: &[(String, f64)], accuracy: &Accuracy) -> Result<()> {
    // A point the scene refuses is reported where the run evaluates it.
    let Ok(model) = scene.evaluate(set) else { return Ok(()) };
    for (k, stop) in model.stops.iter().enumerate() {
        let Some(Spring { stiffness, damping }) = stop.law.spring() else { continue };
        let (normal, _) = stop.geometry.gap_function(model.masses.len());
        let inverse: f64 = normal.iter().zip(&model.masses).map(|(n, m)| n * n / m.mass).sum();
        let rate = (stiffness * inverse).sqrt().max(damping * inverse);
        let period = std::f64::consts::TAU / rate;
        if accuracy.rk4_step() > period / 10.0 {
            let what = format!(
                "{} does not resolve the contact of soft stop {} (stops[{k}], period {period:.3e}): RK4's step must be at most a tenth of it ({:.1e}); lower it, or use the exact integrator",
                accuracy.rk4_step(),
                stop.name,
                period / 10.0
            );
            return Err(RequestError::keyed(Opt::Accuracy, "rk4_step").text(what).into());
        }
    }
    Ok(())
}

/// Refuses a value that is not finite (`option` names it).
fn check_finite(v: f64, option: impl FnOnce() -> RequestError) -> Result<()> {
    if !v.is_finite() {
        return Err(option().text(format!("not a finite number, got {v}")).into());
    }
    Ok(())
}

/// `option` refused by the scene (an unknown parameter): the scene's message.
pub(crate) fn unknown(option: RequestError, e: scene::SceneError) -> RequestError {
    match e {
        scene::SceneError::Field { message, .. } => option.text(message),
        other => option.because(other),
    }
}

/// A validated simulation set-up.
#[derive(Debug, Clone)]
pub struct Setup {
    /// The scene.
    pub scene: Scene,
    /// Parameter values replacing the scene's, in order.
    pub overrides: Vec<(String, f64)>,
    /// The tolerances and budgets.
    pub accuracy: Accuracy,
    /// The accuracy knobs as given (stored in files).
    pub accuracy_overrides: Vec<(Knob, f64)>,
    /// The preset the accuracy starts from.
    pub preset: Preset,
    /// The integrator.
    pub method: Method,
}

impl Setup {
    /// The grid's cell set-up, with sections of at most `section_cap` points.
    pub fn cell_setup(&self, section_cap: usize) -> Result<grid::CellSetup> {
        if section_cap > grid::MAX_SECTION_CAP {
            let what = format!("at most {}, got {section_cap}", grid::MAX_SECTION_CAP);
            return Err(RequestError::option(Opt::SectionCap).text(what).into());
        }
        Ok(grid::CellSetup {
            scene: self.scene.clone(),
            base: self.overrides.clone(),
            accuracy: self.accuracy,
            method: self.method,
            section_cap,
            quantities: Vec::new(),
        })
    }

    /// The system with the parameters `set` replacing their overrides.
    pub fn system_with(&self, set: &[(&str, f64)]) -> Result<solver::System> {
        let mut over = self.overrides.clone();
        over.retain(|(k, _)| !set.iter().any(|(n, _)| n == k));
        over.extend(set.iter().map(|&(n, v)| (n.to_string(), v)));
        Ok(solver::System::new(self.scene.evaluate(&over)?)?)
    }

    /// The system of the set-up.
    pub fn system(&self) -> Result<solver::System> {
        self.system_with(&[])
    }

    /// The parameters given, by their symbols, for titles (`ω = 0.33, δ =
    /// 0.6`), or `scene defaults`.
    pub fn described(&self) -> String {
        if self.overrides.is_empty() {
            return "scene defaults".to_string();
        }
        let each: Vec<String> = self.overrides.iter().map(|(k, v)| format!("{} = {v}", self.scene.symbol(k))).collect();
        each.join(", ")
    }
}

/// Checks an orbit period ([`Opt::N`]): 1 to 1000 forcing periods.
pub fn check_period(n: Option<usize>) -> Result<()> {
    match n {
        Some(n) if n == 0 || n > 1000 => {
            Err(RequestError::option(Opt::N).text(format!("expected a period between 1 and 1000, got {n}")).into())
        }
        _ => Ok(()),
    }
}

/// Where a simulation starts.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Start {
    /// The scene's initial state.
    #[default]
    Initial,
    /// A given state (x of every mass, then v).
    State(Vec<f64>),
    /// A cell of a stored file: the one nearest the given parameter values, of
    /// `sweep` (the file's first when `None`). Its parameters are added to the
    /// overrides and, unless given, the file's preset, knobs and integrator are used.
    Cell {
        /// The atlas or sweep file.
        file: PathBuf,
        /// Parameter values (`--at`), the nearest cell is taken.
        at: Vec<(String, f64)>,
        /// Which sweep of the file.
        sweep: Option<grid::SweepKind>,
    },
}

/// Where a simulation starts, resolved (see [`Sim::setup_from`]).
#[derive(Debug, Clone)]
pub struct Origin {
    /// The state the stored cell started from (the final state of the cell
    /// before it along its sweep), or `None` (the scene's initial state).
    pub cell_start: Option<Vec<f64>>,
    /// The state to start a new simulation from (the stored cell's final
    /// state, at a whole forcing period; or the given state).
    pub state: Vec<f64>,
    /// What was taken, as the results report it (`from`).
    pub source: Source,
    /// The section cap of the stored run (its cells' work includes their
    /// sections), `None` for a given state.
    pub section_cap: Option<usize>,
    /// A warning for the user (the scene differs from the stored one).
    pub warning: Option<String>,
    /// Which stored cell `--at` took, where it is not at the values given
    /// (the nearest on the file's grid), e.g. `the stored cell nearest to
    /// omega=1 is omega=1.0101010101010102,delta=0.5`.
    pub note: Option<String>,
}

/// Where a simulation started, as results report it (their `from`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Source {
    /// A cell of a stored atlas: the file, its sweep, the cell's parameter
    /// values, its labels and its reason.
    Stored {
        /// The file.
        file: String,
        /// The sweep.
        sweep: &'static str,
        /// The cell's parameter values (its axes).
        cell: BTreeMap<String, f64>,
        /// The stored labels per mass.
        labels: BTreeMap<String, String>,
        /// The stored reason of an unresolved cell.
        reason: Option<String>,
    },
    /// A given state.
    Given {
        /// The state `[x…, v…]`.
        state: Vec<f64>,
    },
}

impl Origin {
    /// Whether the simulation re-runs a stored cell.
    pub fn is_stored_cell(&self) -> bool {
        self.section_cap.is_some()
    }
}

impl Sim {
    /// Validates the options and where the simulation starts.
    pub fn setup_from(&self, start: &Start) -> Result<(Setup, Option<Origin>)> {
        match start {
            Start::Initial => Ok((self.setup()?, None)),
            Start::State(state) => {
                let s = self.setup()?;
                let origin = given_state(&s.scene.evaluate(&s.overrides)?, state)?;
                Ok((s, Some(origin)))
            }
            Start::Cell { file, at, sweep } => self.stored_cell(file, at, *sweep),
        }
    }

    /// [`Sim::setup_from`] for a cell of a stored file.
    fn stored_cell(
        &self,
        file: &std::path::Path,
        at: &[(String, f64)],
        sweep: Option<grid::SweepKind>,
    ) -> Result<(Setup, Option<Origin>)> {
        if at.is_empty() {
            return Err(RequestError::option(Opt::From)
                .text("give the cell's parameter values with ")
                .opt(Opt::At)
                .into());
        }
        if let Some((i, (k, _))) = at.iter().enumerate().find(|(i, (k, _))| at[..*i].iter().any(|(j, _)| j == k)) {
            let first = at.iter().find(|(j, _)| j == k).map_or(0.0, |p| p.1);
            return Err(RequestError::keyed(Opt::At, k)
                .text(format!("given twice ({first} and {}); give each parameter once", at[i].1))
                .into());
        }
        let loaded = store::read(file)?;
        let atlas = &loaded.atlas;
        let m = &atlas.meta;
        let sweep = match sweep {
            Some(kind) if !m.sweeps.contains(&kind) => {
                let have: Vec<&str> = m.sweeps.iter().map(|k| k.name()).collect();
                let what = format!("{} has {}, not {}", file.display(), have.join(", "), kind.name());
                return Err(RequestError::option(Opt::Sweep).text(what).into());
            }
            Some(kind) => kind,
            None => m.sweeps[0],
        };
        let (iy, ix) = atlas.nearest(at).map_err(|e| RequestError::option(Opt::At).text(e))?;
        let cell = atlas.map(sweep).and_then(|map| map.cells[iy * m.plane.x.count + ix].as_ref()).ok_or_else(|| {
            RequestError::option(Opt::At).text(format!("the cell was not computed in {} (a shard?)", file.display()))
        })?;
        // The file's settings, unless given.
        let preset = self.preset.unwrap_or(m.preset);
        let method = self.integrator.unwrap_or(m.integrator);
        let mut s = self.setup_with(preset, method, &m.accuracy)?;
        let params = m.plane.params(iy, ix);
        if let Some((k, _)) = s.overrides.iter().find(|(k, _)| params.iter().any(|(p, _)| p == k)) {
            return Err(RequestError::keyed(Opt::Set, k)
                .text("the cell of ")
                .opt(Opt::From)
                .text(format!(" fixes {k} (an axis of {}); choose the cell with ", file.display()))
                .opt(Opt::At)
                .into());
        }
        let mut overrides = m.overrides.clone();
        overrides.extend(params.iter().cloned());
        // The file's values alone first: a scene they do not fit is the
        // file's fault; a value given with --set that the scene refuses is
        // refused as it is without --from, naming the scene's field.
        s.scene.evaluate(&overrides).map_err(|e| {
            let what = format!("{}: its cell's parameters do not fit this scene (made from another?)", file.display());
            RequestError::option(Opt::From).text(what).because(e)
        })?;
        overrides.extend(s.overrides.iter().filter(|(k, _)| !params.iter().any(|(p, _)| p == k)).cloned());
        s.overrides = overrides;
        let model = s.scene.evaluate(&s.overrides)?;
        if 2 * model.masses.len() != m.dim {
            let what =
                format!("{} has states of {} numbers, the scene {}", file.display(), m.dim, 2 * model.masses.len());
            return Err(RequestError::option(Opt::From).text(what).into());
        }
        let warning = (s.scene.source() != m.scene_toml)
            .then(|| format!("the scene differs from the one stored in {}", file.display()));
        let source = Source::Stored {
            file: file.display().to_string(),
            sweep: sweep.name(),
            cell: params.iter().cloned().collect(),
            labels: m.masses.iter().zip(&cell.labels).map(|(n, l)| (n.clone(), l.to_string())).collect(),
            reason: cell.reason.as_ref().map(ToString::to_string),
        };
        let named = |v: &[(String, f64)]| v.iter().map(|(n, x)| format!("{n}={x}")).collect::<Vec<_>>().join(",");
        let elsewhere = at.iter().any(|(n, x)| params.iter().any(|(p, y)| p == n && x != y));
        let note = elsewhere.then(|| format!("the stored cell nearest to {} is {}", named(at), named(&params)));
        let origin = Origin {
            cell_start: atlas.start_of(sweep, iy, ix).map(<[f64]>::to_vec),
            state: cell.final_state.clone(),
            source,
            section_cap: Some(m.section_cap),
            warning,
            note,
        };
        Ok((s, Some(origin)))
    }
}

/// A given start state, checked against the scene: one number per mass for x
/// and for v, no stop penetrated.
pub(crate) fn given_state(model: &scene::Model, state: &[f64]) -> Result<Origin> {
    if state.iter().any(|v| !v.is_finite()) {
        return Err(RequestError::option(Opt::State).text("expected finite numbers").into());
    }
    let dim = 2 * model.masses.len();
    if state.len() != dim {
        let what = format!("the scene's state has {dim} numbers (x of every mass, then v), got {}", state.len());
        return Err(RequestError::option(Opt::State).text(what).into());
    }
    let x: Vec<f64> = state[..dim / 2].to_vec();
    for (k, stop) in model.stops.iter().enumerate().filter(|(_, s)| !s.law.yields()) {
        let g = model.gap(k, &x);
        if g < -solver::ADMISSIBLE_PENETRATION {
            return Err(RequestError::option(Opt::State)
                .text(format!("penetrates stop {} by {}", stop.name, -g))
                .into());
        }
    }
    let source = Source::Given { state: state.to_vec() };
    Ok(Origin { cell_start: None, state: state.to_vec(), source, section_cap: None, warning: None, note: None })
}

/// Labels by mass, `{"M1": "1-4-4", …}` (the contract of `cell`, `orbit`
/// and `continue`).
pub fn labels_of(labels: &[solver::MassLabel]) -> BTreeMap<String, String> {
    labels.iter().map(|l| (l.mass.clone(), l.to_string())).collect()
}

/// The parameters of a system by name.
pub fn parameters_of(sys: &solver::System) -> BTreeMap<String, f64> {
    sys.model.parameters.iter().map(|(k, v)| (k.clone(), *v)).collect()
}
