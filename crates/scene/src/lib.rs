//! Scene files for vibroatlas.
//!
//! A scene is data: masses, linear links (spring + damper), harmonic forcing,
//! rigid stops, friction contacts and the label map, in TOML, with every number
//! allowed to be an expression of named parameters. [`Scene::parse`] reads and
//! checks the file once (module `compile`); [`Scene::evaluate`] produces the
//! numeric [`Model`] of one cell for given parameter overrides (module
//! `evaluate`). This module holds the compiled scene and what it answers
//! without evaluating: its names, symbols, ranges, stops' normals and laws.
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

mod compile;
mod derived;
mod error;
mod evaluate;
mod expr;
mod model;
mod named;
#[cfg(feature = "clap")]
mod named_arg;
mod scales;
mod schema;
mod symbol;

pub use derived::{Derived, Operand, TAKEN_NAMES};
pub use error::{excerpt, number, SceneError};
pub use expr::{MAX_EXPRESSIONS, MAX_EXPRESSION_CHARS};
pub use model::{Friction, Harmonic, LabelStops, LawKind, Link, Mass, Model, Side, Stop, StopGeometry, StopLaw};
pub use named::Named;
#[cfg(feature = "clap")]
pub use named_arg::{named_arg, NamedParser};
pub use scales::{Scale, Scales};
pub use symbol::{symbol_of, SYMBOL_MAX_CHARS};

use compile::index_of;
use expr::{Compiled, Range};
use schema::{ParamSpec, SceneFile};

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

/// Smallest ratio of a mass to the heaviest of its scene. Below it the modes
/// of the linear flow are ill-conditioned: the solver can only call its cells
/// unresolved, and from about 1e-14 rounding loses the light mass altogether.
pub const MASS_RATIO_MIN: f64 = 1e-9;

/// Longest name of a mass or stop, in characters.
pub const MAX_NAME_CHARS: usize = 64;

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
    labels: Vec<LabelStops>,
    /// The quantities it defines (`[quantities]`).
    quantities: std::sync::Arc<[Derived]>,
    /// Its physical scales (`[scales]`).
    scales: std::sync::Arc<Scales>,
    /// Parameters in an order that evaluates each after those it depends on
    /// (topological, smallest index first); those on or after a circular
    /// definition are left out.
    order: Vec<usize>,
}

impl Scene {
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
}
