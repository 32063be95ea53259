//! `vibroatlas._native`: the engine's runs for Python. Every call turns its
//! arguments into an engine request (on the calling thread, holding the
//! interpreter) and starts the run on a thread of its own; it hands back a
//! `Job` that Python waits on in short slices with the interpreter released,
//! so that Ctrl-C and progress bars work while the engine computes. The
//! Python package (`python/vibroatlas`) wraps these calls.
//!
//! Errors are one line, the engine's options named as Python's keyword
//! arguments (`Keywords`: `section_cap: …`, `resume=True`, a scene
//! parameter by its name): `SceneError` (a `ValueError`) for scene files and
//! texts, `OSError` for files, `ValueError` for everything else the caller
//! gave; a panic of the engine becomes a `RuntimeError`, never an abort of
//! the interpreter.

/// The allocator of the extension's own allocations: mimalloc, as the
/// `vibroatlas` binary's, so that a run from Python costs what it costs there.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use engine::{AtlasRequest, CurveRequest, Opt, SceneSource, Sim, Start, SweepRequest};
use grid::attractors::Sampling;
use grid::{Axis, SweepKind};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use scene::Named;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pyo3::create_exception!(
    _native,
    SceneError,
    PyValueError,
    "A scene file or text that cannot be read as a scene (the message names the field)."
);

/// The engine's options as keyword arguments: `section_cap`, `resume=True`,
/// a scene parameter by its name (`params` for all of them).
struct Keywords;

impl engine::Words for Keywords {
    fn option(&self, o: Opt) -> String {
        match o {
            Opt::Set => "params".into(),
            o if o.is_switch() => format!("{}=True", o.name()),
            o => o.name().into(),
        }
    }
    fn keyed(&self, o: Opt, key: &str) -> String {
        match o {
            Opt::Set => key.into(),
            Opt::Accuracy => format!("accuracy['{key}']"),
            o => format!("{} {key}", self.option(o)),
        }
    }
    fn given(&self, o: Opt, value: &str) -> String {
        format!("{}='{value}'", o.name())
    }
}

/// Why a run failed, as the Python exception it becomes.
#[derive(Debug, Clone)]
enum Failure {
    /// A scene that is not valid (`SceneError`).
    Scene(String),
    /// A file that cannot be read or written (`OSError`).
    File(String),
    /// Anything else the caller gave (`ValueError`).
    Value(String),
    /// The run was cancelled (`RuntimeError("cancelled")`).
    Cancelled,
    /// The engine panicked (`RuntimeError`).
    Panic(String),
}

impl Failure {
    /// The failure of an engine error: its kind from the chain of causes,
    /// its text in Python's words.
    fn of(e: &engine::Error) -> Failure {
        use engine::{Error, SceneLoadError};
        let text = engine::in_words(e, &Keywords);
        match e {
            Error::Cancelled => Failure::Cancelled,
            Error::Internal(m) => Failure::Panic(m.clone()),
            Error::Scene(SceneLoadError::Invalid { .. }) => Failure::Scene(text),
            Error::Scene(_) | Error::Unreadable { .. } | Error::Store(store::StoreError::Io { .. }) => {
                Failure::File(text)
            }
            e if io_failure(e) => Failure::File(text),
            _ => Failure::Value(text),
        }
    }

    fn into_py(self) -> PyErr {
        match self {
            Failure::Scene(m) => SceneError::new_err(m),
            Failure::File(m) => PyOSError::new_err(m),
            Failure::Value(m) => PyValueError::new_err(m),
            Failure::Cancelled => PyRuntimeError::new_err("cancelled"),
            Failure::Panic(m) => PyRuntimeError::new_err(format!("internal error of the engine: {m}")),
        }
    }
}

/// Whether an error of a file comes from the system (a file missing, a disk
/// full): the error or one of its causes is an I/O error.
fn io_failure(e: &(dyn std::error::Error + 'static)) -> bool {
    engine::causes(e)
        .any(|c| c.is::<std::io::Error>() || matches!(c.downcast_ref(), Some(store::StoreError::Io { .. })))
}

/// How a run ended, as Python gets it.
type Ended = Result<Outcome, Failure>;

/// What a run gives Python.
#[derive(Clone)]
enum Outcome {
    /// A result's value (the engine's serialisation of it).
    Value(serde_json::Value),
    /// An atlas computed without an output file: its file's bytes, written
    /// in memory, and the seconds it took.
    Atlas { image: Arc<Vec<u8>>, seconds: f64 },
}

impl From<serde_json::Value> for Outcome {
    fn from(v: serde_json::Value) -> Outcome {
        Outcome::Value(v)
    }
}

/// A run on a thread of its own.
#[pyclass(module = "vibroatlas._native")]
struct Job {
    job: Arc<engine::Job<Ended>>,
}

impl Job {
    /// Starts `work` on a new thread; its value or error becomes the outcome.
    fn start<T: Into<Outcome>>(work: impl FnOnce(&engine::Job<Ended>) -> engine::Result<T> + Send + 'static) -> Job {
        let job = Arc::new(engine::Job::new());
        let theirs = Arc::clone(&job);
        std::thread::spawn(move || {
            let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&theirs)));
            theirs.end(match ran {
                Ok(Ok(value)) => Ok(value.into()),
                Ok(Err(e)) => Err(Failure::of(&e)),
                Err(p) => Err(Failure::Panic(
                    p.downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| p.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "panic".into()),
                )),
            });
        });
        Job { job }
    }
}

#[pymethods]
impl Job {
    /// Waits up to `timeout` seconds with the interpreter released; True once
    /// the run has ended (done, failed or cancelled).
    fn wait(&self, py: Python<'_>, timeout: f64) -> PyResult<bool> {
        if !(timeout.is_finite() && timeout >= 0.0) {
            return Err(PyValueError::new_err(format!("timeout: expected seconds >= 0, got {timeout}")));
        }
        Ok(py.detach(|| self.job.wait(Some(Duration::from_secs_f64(timeout.min(1e6))))))
    }

    /// `(done, total)` units of work (cells; 0 total when not known).
    fn progress(&self) -> (u64, u64) {
        self.job.progress()
    }

    /// Asks the run to stop before its next cell; a cancelled atlas writes no file.
    fn cancel(&self) {
        self.job.cancel();
    }

    /// The run's result as Python objects (dicts, lists, numbers, text),
    /// waiting for it to end; raises its error.
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.detach(|| self.job.wait(None));
        match self.job.outcome() {
            Some(Ok(Outcome::Value(value))) => Ok(pythonize::pythonize(py, &value)?),
            Some(Ok(Outcome::Atlas { image, seconds })) => {
                let d = PyDict::new(py);
                d.set_item("image", PyBytes::new(py, &image))?;
                d.set_item("seconds", seconds)?;
                Ok(d.into_any())
            }
            Some(Err(f)) => Err(f.into_py()),
            None => Err(PyRuntimeError::new_err("the run has not ended")),
        }
    }
}

/// An enum option by its name ([`Named`], the command line's spelling), or a
/// `ValueError` naming the keyword, the names and the one meant where one is close.
fn named<T: Named>(key: &str, value: Option<String>) -> PyResult<Option<T>> {
    value.map(|v| T::parse(&v).ok_or_else(|| PyValueError::new_err(format!("{key}: {}", T::expected(&v))))).transpose()
}

/// The simulation options of every call but zoom, as the package passes
/// them (a dict): the scene as `(kind, value)`, its parameters, and the
/// preset, integrator and accuracy knobs (a dict of knob -> value, in
/// order) when given.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct SimArgs<'py> {
    scene: (String, String),
    params: Vec<(String, f64)>,
    #[pyo3(default)]
    preset: Option<String>,
    #[pyo3(default)]
    integrator: Option<String>,
    #[pyo3(default)]
    accuracy: Option<Bound<'py, PyDict>>,
}

/// The engine's simulation options of `a`.
fn sim(a: SimArgs<'_>) -> PyResult<Sim> {
    let SimArgs { scene, params, preset, integrator, accuracy } = a;
    let (kind, value) = scene;
    let source = match kind.as_str() {
        "path" => SceneSource::File(value.into()),
        "stored" => SceneSource::Stored(value.into()),
        "toml" => SceneSource::Text(value),
        "json" => {
            let table: toml::Table = serde_json::from_str(&value)
                .map_err(|e| SceneError::new_err(format!("scene: not a table of scene fields ({e})")))?;
            SceneSource::Text(toml::to_string(&table).map_err(|e| SceneError::new_err(format!("scene: {e}")))?)
        }
        other => return Err(PyValueError::new_err(format!("scene: unknown kind '{other}'"))),
    };
    let preset = named("preset", preset)?;
    let integrator = named("integrator", integrator)?;
    let mut knobs = Vec::new();
    for (k, v) in accuracy.iter().flat_map(|d| d.iter()) {
        let name: String = k.extract()?;
        let knob = solver::Knob::named(&name).map_err(|e| Failure::of(&e.into()).into_py())?;
        knobs.push((knob, v.extract()?));
    }
    Ok(Sim { scene: source, set: params, preset, accuracy: knobs, integrator })
}

/// An axis `(name, start, stop, count)`.
fn axis(t: (String, f64, f64, usize)) -> Axis {
    Axis::new(t.0, t.1, t.2, t.3)
}

/// Worker threads: those asked for, or every core.
fn threads(n: Option<usize>) -> PyResult<usize> {
    engine::threads(n).map_err(|e| PyValueError::new_err(engine::in_words(&e, &Keywords)))
}

/// The sweeps named by `text` (`up`, `both`, …), if given.
fn sweeps(text: Option<String>) -> PyResult<Option<Vec<SweepKind>>> {
    text.map(|t| SweepKind::parse_set(&t, "sweep").map_err(|e| PyValueError::new_err(e.to_string()))).transpose()
}

/// What a run that writes a file returns: the file and the seconds it took.
#[derive(serde::Serialize)]
struct Written {
    output: String,
    seconds: f64,
}

impl Written {
    fn value(output: String, seconds: f64) -> serde_json::Value {
        serde_json::to_value(Written { output, seconds }).unwrap_or_default()
    }
}

/// What an atlas run gives Python: its file and seconds where it wrote
/// one, else the file's bytes written in memory on `threads` threads.
fn written(output: Option<String>, run: &engine::Executed, threads: usize) -> engine::Result<Outcome> {
    Ok(match output {
        Some(output) => Written::value(output, run.secs).into(),
        None => Outcome::Atlas { image: Arc::new(run.image(threads)?), seconds: run.secs },
    })
}

/// A cell's Poincaré sections, as `cell --section-png` draws them.
#[derive(serde::Serialize)]
struct CellSections {
    title: String,
    periods: usize,
    panels: Vec<render::Panel>,
}

/// Parameter values by name, `[(name, value)]` (`--set`, `--at`).
type Assignments = Vec<(String, f64)>;

/// One cell: the value of `cell --json`, with `portrait` (what `cell
/// --portrait` draws) and `sections` (what `cell --section-png` draws) when
/// asked for. `stored`: `(file, at, sweep)`, the cell of a stored atlas run
/// again from the state it started from (`cell --from FILE --at … --sweep S`).
#[pyfunction]
#[pyo3(signature = (sim, *, state=None, stored=None, portrait=false, sections=false,
    section_periods=engine::DEFAULT_SECTION_PERIODS))]
fn cell(
    sim: SimArgs<'_>,
    state: Option<Vec<f64>>,
    stored: Option<(String, Assignments, Option<String>)>,
    portrait: bool,
    sections: bool,
    section_periods: usize,
) -> PyResult<Job> {
    let sim = self::sim(sim)?;
    let start = match (state, stored) {
        (Some(state), _) => Start::State(state),
        (None, None) => Start::Initial,
        (None, Some((file, at, sweep))) => {
            let sweep = named("sweep", sweep)?;
            Start::Cell { file: file.into(), at, sweep }
        }
    };
    Ok(Job::start(move |_| {
        let c = engine::cell(&sim, &start)?;
        let mut value = c.to_json();
        if portrait {
            value["portrait"] = json_of(&engine::portrait(&c))?;
        }
        if sections {
            let (panels, title) = engine::section_panels(&c, section_periods)?;
            value["sections"] = json_of(&CellSections { title, periods: section_periods, panels })?;
        }
        Ok(value)
    }))
}

/// The JSON value of a result (the engine's own serialisation).
fn json_of(v: &impl serde::Serialize) -> engine::Result<serde_json::Value> {
    serde_json::to_value(v).map_err(|e| engine::Error::Internal(e.to_string()))
}

/// A sweep along one parameter: the value of `sweep --json`.
#[pyfunction]
#[pyo3(signature = (sim, *, axis, direction=None, section_cap=None, threads=None, output=None))]
fn sweep(
    sim: SimArgs<'_>,
    axis: (String, f64, f64, usize),
    direction: Option<String>,
    section_cap: Option<usize>,
    threads: Option<usize>,
    output: Option<String>,
) -> PyResult<Job> {
    let sim = self::sim(sim)?;
    let mut r = SweepRequest::new(sim, self::axis(axis));
    r.direction = named("direction", direction)?;
    r.section_cap = section_cap.unwrap_or(r.section_cap);
    r.threads = self::threads(threads)?;
    r.output = output.map(Into::into);
    r.command = "vibroatlas.sweep (Python)".into();
    Ok(Job::start(move |shared| Ok(engine::sweep(&r, shared)?.to_json())))
}

/// An atlas: `{"output": path, "seconds": s}` written to `output`, else
/// `{"image": bytes, "seconds": s}`, its file written in memory. Its other
/// keywords are the atlas's options ([`engine::AtlasOptions`], each named as
/// its field), each refused naming it.
#[pyfunction]
#[pyo3(signature = (sim, *, x, y, section_cap=None, threads=None, output=None, **options))]
fn atlas(
    sim: SimArgs<'_>,
    x: (String, f64, f64, usize),
    y: (String, f64, f64, usize),
    section_cap: Option<usize>,
    threads: Option<usize>,
    output: Option<String>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Job> {
    let sim = self::sim(sim)?;
    let options: engine::AtlasOptions = match options {
        None => Default::default(),
        Some(d) => serde_path_to_error::deserialize(&mut pythonize::Depythonizer::from_object(d.as_any()))
            .map_err(|e| PyValueError::new_err(format!("{}: {}", e.path(), e.inner())))?,
    };
    let mut r = AtlasRequest::new(sim, axis(x), axis(y), Vec::new());
    options.apply(&mut r).map_err(|e| Failure::of(&e).into_py())?;
    r.section_cap = section_cap.unwrap_or(r.section_cap);
    r.threads = self::threads(threads)?;
    r.output = output.clone().map(Into::into);
    r.command = "vibroatlas.atlas (Python)".into();
    Ok(Job::start(move |shared| {
        let run = engine::atlas(&r, shared)?;
        written(output, &run, r.threads)
    }))
}

/// The coexisting attractors of one point: the value of `attractors --json`.
#[pyfunction]
#[pyo3(signature = (sim, *, samples=None, seed=None, r#box=None, threads=None))]
fn attractors(
    sim: SimArgs<'_>,
    samples: Option<usize>,
    seed: Option<u64>,
    r#box: Option<(f64, f64)>,
    threads: Option<usize>,
) -> PyResult<Job> {
    let sim = self::sim(sim)?;
    let mut r = engine::AttractorsRequest::new(sim);
    let d = r.sampling;
    let (x, v) = r#box.unwrap_or((d.x, d.v));
    r.sampling = Sampling { samples: samples.unwrap_or(d.samples), seed: seed.unwrap_or(d.seed), x, v };
    r.threads = self::threads(threads)?;
    Ok(Job::start(move |shared| Ok(engine::attractors(&r, shared)?.to_json())))
}

/// The basins of one point over a grid of two state components, written
/// to `output`: the value of `basins --json`.
#[pyfunction]
#[pyo3(signature = (sim, *, x, y, output, state=None, phase=None, threads=None, early_stop=false))]
#[allow(clippy::too_many_arguments)] // the keywords of va.basins
fn basins(
    sim: SimArgs<'_>,
    x: (String, f64, f64, usize),
    y: (String, f64, f64, usize),
    output: String,
    state: Option<Vec<f64>>,
    phase: Option<f64>,
    threads: Option<usize>,
    early_stop: bool,
) -> PyResult<Job> {
    let r = engine::BasinsRequest {
        sim: self::sim(sim)?,
        start: state.map_or(Start::Initial, Start::State),
        x: axis(x),
        y: axis(y),
        phase,
        threads: self::threads(threads)?,
        early: early_stop,
        output: Some(output.into()),
        command: "vibroatlas.basins (Python)".into(),
    };
    Ok(Job::start(move |shared| Ok(engine::basins_report(&engine::basins(&r, shared)?.0).to_json())))
}

/// A bifurcation curve: the value of `curve --json`.
#[pyfunction]
#[pyo3(signature = (sim, *, kind, free, start, to=None, steps=None, window=None, bounds=None, n=None,
    state=None, output=None))]
#[allow(clippy::too_many_arguments)] // the keywords of va.curve
fn curve(
    sim: SimArgs<'_>,
    kind: String,
    free: (String, String),
    start: Vec<(String, f64)>,
    to: Option<f64>,
    steps: Option<usize>,
    window: Option<f64>,
    bounds: Option<(f64, f64)>,
    n: Option<usize>,
    state: Option<Vec<f64>>,
    output: Option<String>,
) -> PyResult<Job> {
    let sim = self::sim(sim)?;
    let kind =
        named::<solver::Bifurcation>("kind", Some(kind))?.ok_or_else(|| PyValueError::new_err("kind: required"))?;
    let mut r = CurveRequest::new(sim, kind, [free.0, free.1], start);
    r.to = to;
    r.steps = steps.unwrap_or(r.steps);
    r.window = window.unwrap_or(r.window);
    r.bounds = bounds.map(|(lo, hi)| [lo, hi]);
    r.n = n;
    r.state = state;
    r.output = output.map(Into::into);
    r.command = "vibroatlas.curve (Python)".into();
    Ok(Job::start(move |shared| Ok(engine::curve(&r, shared)?.to_json())))
}

/// A box of a stored atlas computed again (`vibroatlas zoom`): as
/// [`atlas`], `{"output", "seconds"}` written to `output`, else `{"image",
/// "seconds"}`.
#[pyfunction]
#[pyo3(signature = (parent, *, x, y, sweep=None, set=Vec::new(), threads=None, output=None))]
fn zoom(
    parent: String,
    x: (String, f64, f64, usize),
    y: (String, f64, f64, usize),
    sweep: Option<String>,
    set: Vec<(String, f64)>,
    threads: Option<usize>,
    output: Option<String>,
) -> PyResult<Job> {
    let mut r = engine::ZoomRequest::new(&parent, axis(x), axis(y));
    r.sweeps = sweeps(sweep)?;
    r.set = set;
    r.threads = self::threads(threads)?;
    r.output = output.clone().map(Into::into);
    r.command = "vibroatlas.zoom (Python)".into();
    Ok(Job::start(move |shared| {
        let run = engine::zoom(&r, shared)?;
        written(output, &run, r.threads)
    }))
}

/// The interactive atlas of a file, served on 127.0.0.1 from a thread of
/// this process until [`Explorer::stop`].
#[pyclass(module = "vibroatlas._native")]
struct Explorer {
    server: Mutex<Option<explore::Server>>,
    url: String,
}

#[pymethods]
impl Explorer {
    /// Serves the atlas `path` on `port` (0: a free one).
    #[new]
    #[pyo3(signature = (path, port = 0, threads = None))]
    fn new(path: String, port: u16, threads: Option<usize>) -> PyResult<Explorer> {
        let threads = engine::threads(threads).map_err(|e| Failure::of(&e).into_py())?;
        let r = explore::ExploreRequest { file: path.into(), port, threads };
        let server = explore::serve(&r).map_err(|e| {
            // The error and each of its causes, as the command line says it.
            let text = engine::causes(&e).map(ToString::to_string).collect::<Vec<_>>().join(": ");
            match &e {
                explore::ExploreError::Port { .. } | explore::ExploreError::Atlas(_) => PyOSError::new_err(text),
                _ => PyValueError::new_err(text),
            }
        })?;
        let url = server.url().to_string();
        Ok(Explorer { server: Mutex::new(Some(server)), url })
    }

    /// The page's address.
    #[getter]
    fn url(&self) -> String {
        self.url.clone()
    }

    /// The cell last clicked in the page, `(file, sweep, [(name, value)])`,
    /// or `None` before a click (or once stopped).
    #[getter]
    fn selected(&self) -> Option<(String, String, Assignments)> {
        let server = self.server.lock().unwrap_or_else(|p| p.into_inner());
        let s = server.as_ref()?.selected()?;
        Some((s.file.display().to_string(), s.sweep, s.at))
    }

    /// Whether it still serves.
    #[getter]
    fn running(&self) -> bool {
        self.server.lock().unwrap_or_else(|p| p.into_inner()).is_some()
    }

    /// Stops serving (running zooms cancelled, their files removed).
    fn stop(&self, py: Python<'_>) {
        let server = self.server.lock().unwrap_or_else(|p| p.into_inner()).take();
        if let Some(s) = server {
            py.detach(|| s.stop());
        }
    }
}

/// A legend row for Python: swatch, colours (RGB), text.
type LegendRow = (&'static str, Vec<(u8, u8, u8)>, String);

/// The legend rows `vibroatlas render` draws for label counts `(label,
/// cells)` in at most `rows` rows: `(swatch, colours, text)`, the swatch
/// `fill` (a named label) or `hatch` (a family group), colours RGB 0-255.
/// A text that is not a label (a file's `not-computed`) is left out: those
/// cells are blank, as the figures draw them.
#[pyfunction]
fn legend(counts: Vec<(String, u64)>, rows: usize) -> Vec<LegendRow> {
    let labels: Vec<(solver::Label, u64)> =
        counts.into_iter().filter_map(|(text, n)| text.parse().ok().map(|l| (l, n))).collect();
    render::label_legend(&labels, rows)
        .into_iter()
        .map(|k| (k.swatch, k.colours.into_iter().map(|[r, g, b]| (r, g, b)).collect(), k.text))
        .collect()
}

/// `colours` (RGB 0-255) faded toward white as the hysteresis view draws
/// the cells where the sweeps agree (`render::faded`).
#[pyfunction]
fn faded(colours: Vec<(u8, u8, u8)>) -> Vec<(u8, u8, u8)> {
    colours.into_iter().map(|(r, g, b)| render::faded([r, g, b])).map(|[r, g, b]| (r, g, b)).collect()
}

/// The pieces of `text` in order, each with whether the figures draw it as
/// a subscript (`x_M1`: `x`, then `M1` lowered).
#[pyfunction]
fn subscript_runs(text: &str) -> Vec<(String, bool)> {
    render::subscript_runs(text).into_iter().map(|(t, sub)| (t.to_string(), sub)).collect()
}

/// What the figures call the events at each stop of a file: `contacts`
/// (soft stops) or `impacts`, from its `stop_laws` attribute `laws` (in files
/// written before it, from its stored scene `scene`).
#[pyfunction]
#[pyo3(signature = (laws, scene))]
fn stop_events(laws: Option<&str>, scene: &str) -> PyResult<Vec<&'static str>> {
    let laws = store::stop_laws(laws, scene).map_err(PyValueError::new_err)?;
    Ok(laws.into_iter().map(solver::contact::events).collect())
}

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add_class::<Job>()?;
    m.add_function(wrap_pyfunction!(cell, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(atlas, m)?)?;
    m.add_function(wrap_pyfunction!(attractors, m)?)?;
    m.add_function(wrap_pyfunction!(basins, m)?)?;
    m.add_function(wrap_pyfunction!(curve, m)?)?;
    m.add_function(wrap_pyfunction!(zoom, m)?)?;
    m.add_function(wrap_pyfunction!(faded, m)?)?;
    m.add_function(wrap_pyfunction!(legend, m)?)?;
    m.add_function(wrap_pyfunction!(subscript_runs, m)?)?;
    m.add_function(wrap_pyfunction!(stop_events, m)?)?;
    m.add_class::<Explorer>()?;
    Ok(())
}
