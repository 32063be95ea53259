//! The engine's refusals in its own terms: the option of a request at fault
//! ([`Opt`], named after the request's field) and what is wrong, which may
//! name other options ([`RequestError`]). A front end spells the options in
//! its own words ([`Words`]): the command line as flags (`--section-cap`),
//! Python as keyword arguments (`section_cap`); the error's own `Display`
//! uses the request's field names ([`Fields`]).

use std::fmt;
use std::path::PathBuf;

/// What errors in a scene given as text name it.
pub(crate) const TEXT: &str = "scene text";

/// A scene that could not be read or parsed; its text names the file (or
/// `scene` for a text) and the field.
#[derive(Debug)]
pub enum SceneLoadError {
    /// The atlas holding the scene cannot be read.
    Stored(store::StoreError),
    /// The file cannot be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// The text is not a valid scene.
    Invalid {
        /// The file, or `scene text`.
        origin: String,
        /// What is wrong.
        cause: scene::SceneError,
    },
}

impl std::fmt::Display for SceneLoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneLoadError::Stored(cause) => write!(f, "{cause}"),
            SceneLoadError::Read { path, cause } => write!(f, "cannot read scene file {}: {cause}", path.display()),
            // A text has no file to name: its syntax errors say where in the text.
            SceneLoadError::Invalid { origin, cause: scene::SceneError::Syntax { message } } if origin == TEXT => {
                write!(f, "{TEXT}: {message}")
            }
            SceneLoadError::Invalid { origin, cause } => write!(f, "{origin}: {cause}"),
        }
    }
}

impl std::error::Error for SceneLoadError {}

/// An option of a run's request, as errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Opt {
    /// A scene parameter's value ([`crate::Sim::set`]; the parameter is its key).
    Set,
    /// An accuracy knob ([`crate::Sim::accuracy`]; the knob is its key).
    Accuracy,
    /// Worker threads.
    Threads,
    /// Section points kept per cell.
    SectionCap,
    /// An orbit's period in forcing periods.
    N,
    /// The file of a stored cell ([`crate::Start::Cell`]).
    From,
    /// The parameter values of a stored cell.
    At,
    /// A sweep of a stored file, or the sweeps of an atlas.
    Sweep,
    /// A given start state ([`crate::Start::State`]).
    State,
    /// The parameter of a sweep or a continuation.
    Axis,
    /// An atlas's x axis.
    X,
    /// An atlas's y axis.
    Y,
    /// The axis continuation chains follow.
    Along,
    /// A run's shard.
    Shard,
    /// The samples of an atlas's attractor search.
    Attractors,
    /// The cells of an atlas's attractor search.
    AttractorsWhere,
    /// The samples of an attractor search.
    Samples,
    /// The seed of an attractor search's sampling.
    Seed,
    /// The box of an attractor search's start states.
    Box,
    /// A curve's free parameters.
    Free,
    /// A curve's start.
    Start,
    /// A curve's last value of its stepped parameter.
    To,
    /// A curve's steps.
    Steps,
    /// A curve's search window.
    Window,
    /// A curve's bounds.
    Bounds,
    /// The most curves found.
    Max,
    /// The file written.
    Output,
    /// Curves stored into their atlas.
    Into,
    /// Continuing a run from its journal.
    Resume,
    /// Merging parts with shards missing.
    AllowMissing,
    /// The bench's grid size.
    Grid,
    /// The bench's repetitions.
    Repeat,
    /// The rounds of the bench's trade.
    TradeRepeat,
    /// The scene of the bench.
    Scene,
    /// Samples per forcing period of a cell's trace.
    TraceSamples,
    /// Forcing periods of a cell's Poincaré sections.
    SectionPeriods,
    /// The quantities of the steady motion an atlas stores.
    Quantities,
    /// One stored quantity of the steady motion (`inspect --quantity`).
    Quantity,
    /// The forcing phase at the start (`basins --phase`).
    Phase,
    /// The variable a sweep's diagram shows ([`crate::SweepRequest::variable`]).
    Variable,
}

impl Opt {
    /// The option's name: its request field (`section_cap`).
    pub fn name(self) -> &'static str {
        match self {
            Opt::Set => "set",
            Opt::Accuracy => "accuracy",
            Opt::Threads => "threads",
            Opt::SectionCap => "section_cap",
            Opt::N => "n",
            Opt::From => "from",
            Opt::At => "at",
            Opt::Sweep => "sweep",
            Opt::State => "state",
            Opt::Axis => "axis",
            Opt::X => "x",
            Opt::Y => "y",
            Opt::Along => "along",
            Opt::Shard => "shard",
            Opt::Attractors => "attractors",
            Opt::AttractorsWhere => "attractors_where",
            Opt::Samples => "samples",
            Opt::Seed => "seed",
            Opt::Box => "box",
            Opt::Free => "free",
            Opt::Start => "start",
            Opt::To => "to",
            Opt::Steps => "steps",
            Opt::Window => "window",
            Opt::Bounds => "bounds",
            Opt::Max => "max",
            Opt::Output => "output",
            Opt::Into => "into",
            Opt::Resume => "resume",
            Opt::AllowMissing => "allow_missing",
            Opt::Grid => "grid",
            Opt::Repeat => "repeat",
            Opt::TradeRepeat => "trade_repeat",
            Opt::Scene => "scene",
            Opt::TraceSamples => "trace_samples",
            Opt::SectionPeriods => "section_periods",
            Opt::Quantities => "quantities",
            Opt::Quantity => "quantity",
            Opt::Phase => "phase",
            Opt::Variable => "variable",
        }
    }

    /// Whether the option is a switch, given or not (`resume`).
    pub fn is_switch(self) -> bool {
        matches!(self, Opt::Resume | Opt::Into | Opt::AllowMissing)
    }
}

/// How a front end spells options in messages.
pub trait Words {
    /// The option `o`.
    fn option(&self, o: Opt) -> String;
    /// The option `o` for its `key` (a parameter, a knob, an axis's parameter).
    fn keyed(&self, o: Opt, key: &str) -> String {
        format!("{} {key}", self.option(o))
    }
    /// The option `o` given `value`.
    fn given(&self, o: Opt, value: &str) -> String {
        format!("{} {value}", self.option(o))
    }
}

/// The request's own words: its field names (`section_cap`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Fields;

impl Words for Fields {
    fn option(&self, o: Opt) -> String {
        o.name().to_string()
    }
}

/// A part of a message.
#[derive(Debug, Clone, PartialEq)]
enum Piece {
    Text(String),
    Opt(Opt),
    Keyed(Opt, String),
    Given(Opt, String),
}

impl Piece {
    fn in_words(&self, w: &dyn Words) -> String {
        match self {
            Piece::Text(t) => t.clone(),
            Piece::Opt(o) => w.option(*o),
            Piece::Keyed(o, k) => w.keyed(*o, k),
            Piece::Given(o, v) => w.given(*o, v),
        }
    }
}

/// A request the engine refuses, or advice on a run that failed: the option
/// at fault (when one is), then what is wrong, which may name options:
/// `section_cap: at most 100000, got 200000`. The error it wraps, if any, is
/// its [`source`](std::error::Error::source) (`{:#}` prints `option: cause`).
#[derive(Debug)]
pub struct RequestError {
    head: Option<Piece>,
    text: Vec<Piece>,
    cause: Option<Box<dyn std::error::Error + Send + Sync>>,
}

impl RequestError {
    /// An error of option `o`.
    pub fn option(o: Opt) -> RequestError {
        RequestError { head: Some(Piece::Opt(o)), text: Vec::new(), cause: None }
    }

    /// An error of option `o` for `key` (the parameter of `set`, the knob of `accuracy`).
    pub fn keyed(o: Opt, key: impl Into<String>) -> RequestError {
        RequestError { head: Some(Piece::Keyed(o, key.into())), text: Vec::new(), cause: None }
    }

    /// An error of option `o` given `value`.
    pub fn given(o: Opt, value: impl Into<String>) -> RequestError {
        RequestError { head: Some(Piece::Given(o, value.into())), text: Vec::new(), cause: None }
    }

    /// An error of no one option.
    pub fn message() -> RequestError {
        RequestError { head: None, text: Vec::new(), cause: None }
    }

    /// The message goes on with `text`.
    pub fn text(mut self, text: impl Into<String>) -> RequestError {
        self.text.push(Piece::Text(text.into()));
        self
    }

    /// The message goes on naming option `o`.
    pub fn opt(mut self, o: Opt) -> RequestError {
        self.text.push(Piece::Opt(o));
        self
    }

    /// The message goes on naming option `o` given `value`.
    pub fn opt_given(mut self, o: Opt, value: impl Into<String>) -> RequestError {
        self.text.push(Piece::Given(o, value.into()));
        self
    }

    /// The error that made the option wrong (its source).
    pub fn because(mut self, cause: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> RequestError {
        self.cause = Some(cause.into());
        self
    }

    /// The option at fault, if one is.
    pub fn at_fault(&self) -> Option<Opt> {
        match &self.head {
            Some(Piece::Opt(o) | Piece::Keyed(o, _) | Piece::Given(o, _)) => Some(*o),
            _ => None,
        }
    }

    /// The message (without its cause) in a front end's words.
    pub fn in_words(&self, w: &dyn Words) -> String {
        let text: String = self.text.iter().map(|p| p.in_words(w)).collect();
        match &self.head {
            Some(head) if text.is_empty() => head.in_words(w),
            Some(head) => format!("{}: {text}", head.in_words(w)),
            None => text,
        }
    }
}

impl fmt::Display for RequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.in_words(&Fields))
    }
}

impl std::error::Error for RequestError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

/// Everything an engine call can fail with. A refused request names the
/// option at fault ([`Error::Request`]); the errors of the libraries below
/// keep their own types; every cause is a [`source`](std::error::Error::source),
/// so that a front end prints the chain as one line ([`in_words`]) and tells
/// the kinds apart by matching, not by text.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A request the engine refuses, naming the option at fault.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The scene cannot be read or is not valid.
    #[error(transparent)]
    Scene(#[from] SceneLoadError),
    /// A file the run reads or writes, and what is wrong with it (nothing
    /// more than its cause when `what` is empty).
    #[error("{}{}{what}", path.display(), if what.is_empty() { "" } else { ": " })]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        what: String,
        /// The error that made it wrong, if any.
        #[source]
        cause: Option<Box<dyn std::error::Error + Send + Sync>>,
    },
    /// A file that cannot be read (`what`: which kind, `study`).
    #[error("cannot read {what} file {}", path.display())]
    Unreadable {
        /// What the file holds.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        cause: std::io::Error,
    },
    /// The scene's parameters, with the request's values, do not make a
    /// valid model.
    #[error(transparent)]
    Model(#[from] scene::SceneError),
    /// No periodic orbit was found (`at`: where, when the call has several
    /// points; the solver's reason is printed in the message, not chained).
    #[error("{}{cause}", at.as_deref().unwrap_or(""))]
    Orbit {
        /// Where: `at omega = 0.3: `.
        at: Option<String>,
        /// Why.
        cause: solver::OrbitError,
    },
    /// A plane, sweep or study the grid refuses, or a cell it cannot run.
    #[error(transparent)]
    Grid(grid::GridError),
    /// The solver refuses the scene.
    #[error(transparent)]
    Solver(#[from] solver::SolverError),
    /// The store cannot read or write a file.
    #[error(transparent)]
    Store(#[from] store::StoreError),
    /// A figure cannot be drawn.
    #[error(transparent)]
    Render(#[from] render::RenderError),
    /// The simulation of a cell's trace or sections stopped (`what`: which).
    #[error("{what}: {why}")]
    Halted {
        /// What was being simulated (`sections`).
        what: &'static str,
        /// Why it stopped, with the time and state.
        why: String,
    },
    /// A folder that cannot be made.
    #[error("cannot create {}", path.display())]
    Uncreatable {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        cause: std::io::Error,
    },
    /// A study that failed before its first atlas was written, and the
    /// folder it had created for its files, removed (its message is the
    /// cause's, then what was removed: a front end words the cause's chain
    /// as its own, [`crate::causes`]).
    #[error("{}", unwritten_text(&chain_text(cause.as_ref()), folder))]
    Unwritten {
        /// Why the study failed.
        cause: Box<Error>,
        /// The folder removed.
        folder: PathBuf,
    },
    /// The observer asked the run to stop ([`crate::Observer::cancelled`]).
    #[error("cancelled")]
    Cancelled,
    /// The engine broke a promise of its own (a worker thread panicked, two
    /// runs of one grid differ): a bug to report, not a bad request.
    #[error("{0}")]
    Internal(String),
}

/// What engine calls return.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<grid::GridError> for Error {
    /// A cancelled grid run is [`Error::Cancelled`]; every other grid error
    /// is [`Error::Grid`].
    fn from(e: grid::GridError) -> Error {
        match e {
            grid::GridError::Cancelled => Error::Cancelled,
            e => Error::Grid(e),
        }
    }
}

impl From<grid::FieldError> for Error {
    fn from(e: grid::FieldError) -> Error {
        Error::Grid(e.into())
    }
}

impl Error {
    /// The option at fault, when the request was refused for one.
    pub fn at_fault(&self) -> Option<Opt> {
        match self {
            Error::Request(r) => r.at_fault(),
            _ => None,
        }
    }

    /// An error of the file `path`: `what` is wrong with it, because of `cause`.
    pub(crate) fn file(
        path: &std::path::Path,
        what: impl Into<String>,
        cause: Option<Box<dyn std::error::Error + Send + Sync>>,
    ) -> Error {
        Error::File { path: path.to_path_buf(), what: what.into(), cause }
    }
}

/// An error and each of its causes ([`source`](std::error::Error::source)), in order.
pub fn causes<'a>(
    e: &'a (dyn std::error::Error + 'static),
) -> impl Iterator<Item = &'a (dyn std::error::Error + 'static)> {
    std::iter::successors(Some(e), |c| c.source())
}

/// An error as one line in a front end's words: the error, then each of its
/// causes, joined by `: `; a [`RequestError`] in `w`.
pub fn in_words(e: &Error, w: &dyn Words) -> String {
    let one = |c: &(dyn std::error::Error + 'static)| match c.downcast_ref::<Error>() {
        Some(Error::Request(r)) => r.in_words(w),
        _ => c.downcast_ref::<RequestError>().map_or_else(|| c.to_string(), |r| r.in_words(w)),
    };
    causes(e).map(one).collect::<Vec<_>>().join(": ")
}

/// The text of an [`Error::Unwritten`] whose cause reads `cause` (its chain,
/// in a front end's words).
pub fn unwritten_text(cause: &str, folder: &std::path::Path) -> String {
    format!("{cause}; nothing was written: {}, which the study had created, is removed", folder.display())
}

/// The text of an error and its causes, joined by `: `: for a message that
/// goes on after it.
pub(crate) fn chain_text(e: &(dyn std::error::Error + 'static)) -> String {
    causes(e).map(ToString::to_string).collect::<Vec<_>>().join(": ")
}

/// A grid error in the engine's words: the field it names (`x`, `x omega`,
/// `shard`) becomes the option that `fields` maps it to (`Opt::X` keyed
/// `omega`); any other grid error stays as it is.
pub fn grid_error(e: impl Into<grid::GridError>, fields: &[(&str, Opt)]) -> Error {
    let e = e.into();
    if let grid::GridError::Field(grid::FieldError { field, message }) = &e {
        let (head, key) = field.split_once(' ').map_or((field.as_str(), None), |(h, k)| (h, Some(k)));
        if let Some(&(_, o)) = fields.iter().find(|(f, _)| *f == head) {
            let r = match key {
                Some(k) => RequestError::keyed(o, k),
                None => RequestError::option(o),
            };
            return r.text(message.clone()).into();
        }
    }
    e.into()
}

/// A grid error of a plane's set-up in the engine's words ([`grid_error`]),
/// or any other error unchanged.
pub(crate) fn with_fields(e: Error, fields: &[(&str, Opt)]) -> Error {
    match e {
        Error::Grid(g) => grid_error(g, fields),
        e => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Flags;
    impl Words for Flags {
        fn option(&self, o: Opt) -> String {
            format!("--{}", o.name().replace('_', "-"))
        }
    }

    #[test]
    fn a_refusal_names_its_options_in_each_front_ends_words() {
        let e = RequestError::keyed(Opt::Set, "omega").text("also an axis; remove the ").opt(Opt::Set);
        assert_eq!(e.to_string(), "set omega: also an axis; remove the set");
        assert_eq!(e.in_words(&Flags), "--set omega: also an axis; remove the --set");
        assert_eq!(e.at_fault(), Some(Opt::Set));
        let e = RequestError::given(Opt::AttractorsWhere, "hysteresis").text("needs ").opt_given(Opt::Sweep, "both");
        assert_eq!(e.in_words(&Flags), "--attractors-where hysteresis: needs --sweep both");
        let e = RequestError::message().text("grid: use more ").opt(Opt::Shard).text(" parts");
        assert_eq!((e.in_words(&Flags).as_str(), e.at_fault()), ("grid: use more --shard parts", None));
    }

    #[test]
    fn a_cause_is_the_source_and_ends_the_line() {
        let cause = scene::SceneError::field("parameters.fk", "must be in [0, inf), got -5");
        let e = Error::from(RequestError::option(Opt::To).because(cause));
        assert!(std::error::Error::source(&e).and_then(|c| c.downcast_ref::<scene::SceneError>()).is_some());
        assert_eq!(chain_text(&e), "to: parameters.fk: must be in [0, inf), got -5");
        assert_eq!(in_words(&e, &Flags), "--to: parameters.fk: must be in [0, inf), got -5");
    }

    #[test]
    fn grid_fields_become_options() {
        let e =
            grid_error(grid::GridError::field("x omega", "the count must be 1 to 1000000, got 0"), &[("x", Opt::Axis)]);
        assert_eq!(in_words(&e, &Flags), "--axis omega: the count must be 1 to 1000000, got 0");
        let e = grid_error(grid::GridError::field("values", "give at least one value"), &[("x", Opt::X)]);
        assert_eq!(in_words(&e, &Flags), "values: give at least one value");
    }
}
