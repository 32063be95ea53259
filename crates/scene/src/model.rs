//! The numeric model of one cell: every expression evaluated, every value checked.
//!
//! Units are dimensionless throughout. The equations of motion are
//! `M x'' + C x' + K x = P sin(omega t + tau) + Σ_k (harmonic k) + L + friction +
//! stop reactions`, with `M` diagonal (the masses), `C`, `K` assembled from the
//! links, `L` the constant loads and each further harmonic a force
//! `amplitude sin(k omega t + phase)` at a whole multiple k of omega.

pub use crate::schema::Side;

/// A point mass.
#[derive(Debug, Clone, PartialEq)]
pub struct Mass {
    /// Name (`M1`).
    pub name: String,
    /// Mass (> 0).
    pub mass: f64,
    /// Amplitude of the harmonic force `force * sin(omega t + tau)` on it.
    pub force: f64,
    /// Constant force on it (a static or mean load).
    pub load: f64,
    /// Further harmonic forces on it.
    pub harmonics: Vec<Harmonic>,
    /// Initial displacement.
    pub x0: f64,
    /// Initial velocity.
    pub v0: f64,
}

/// A force `amplitude * sin(order * omega t + phase)` (`t` the absolute time,
/// so that `phase` is the harmonic's phase at `t = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Harmonic {
    /// Multiple of omega (1 to [`crate::MAX_HARMONIC`]).
    pub order: u32,
    /// Amplitude.
    pub amplitude: f64,
    /// Phase at `t = 0` (radians).
    pub phase: f64,
}

/// A spring and damper in parallel, from mass `a` to mass `b` or to the frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    /// First mass (index into [`Model::masses`]).
    pub a: usize,
    /// Second mass, or `None` for the frame.
    pub b: Option<usize>,
    /// Stiffness (>= 0).
    pub stiffness: f64,
    /// Damping coefficient (>= 0).
    pub damping: f64,
}

/// Where a rigid stop is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StopGeometry {
    /// A fixed stop: `x_mass >= position` (below) or `x_mass <= position` (above).
    Frame {
        /// Index of the mass.
        mass: usize,
        /// Which side of the mass the stop is on.
        side: Side,
        /// Position of the stop.
        position: f64,
    },
    /// Two masses that collide when `x_first - x_second` reaches `gap`.
    Pair {
        /// Index of the first mass.
        first: usize,
        /// Index of the second mass.
        second: usize,
        /// Clearance (>= 0).
        gap: f64,
    },
}

impl StopGeometry {
    /// The stop's gap as a linear function of the positions of `masses`
    /// masses, `g(x) = n·x + c >= 0`: `(n, c)`. A frame stop below mass i has
    /// `n = e_i`, `c = -position`; above, `n = -e_i`, `c = position`; a pair stop
    /// `x_a - x_b <= gap` has `n = e_b - e_a`, `c = gap`. The normal depends on
    /// the geometry's kind and masses only, never on parameter values.
    pub fn gap_function(&self, masses: usize) -> (Vec<f64>, f64) {
        let mut normal = vec![0.0; masses];
        let offset = match *self {
            StopGeometry::Frame { mass, side: Side::Below, position } => {
                normal[mass] = 1.0;
                -position
            }
            StopGeometry::Frame { mass, side: Side::Above, position } => {
                normal[mass] = -1.0;
                position
            }
            StopGeometry::Pair { first, second, gap } => {
                normal[first] = -1.0;
                normal[second] = 1.0;
                gap
            }
        };
        (normal, offset)
    }
}

/// How a stop acts when its gap `g` closes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StopLaw {
    /// Rigid: an impact with Newton's law, the normal velocity reversed and
    /// scaled by the coefficient of restitution in [0, 1].
    Rigid {
        /// Coefficient of restitution.
        restitution: f64,
    },
    /// Soft (compliant): beyond the clearance (`g < 0`) a spring and a dashpot
    /// push the gap open with the force `-stiffness g - damping g'` along the
    /// gap's normal while that force is positive (a contact never pulls).
    Soft {
        /// Contact stiffness (>= 0).
        stiffness: f64,
        /// Contact damping coefficient (>= 0; not both zero).
        damping: f64,
    },
}

crate::named_enum! {
    /// Which contact law a stop obeys, without its coefficients: the same for
    /// every parameter value, and recorded per stop in every file.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub enum LawKind {
        /// Impacts with a coefficient of restitution.
        Rigid = "rigid",
        /// A spring and a dashpot while the gap is closed.
        Soft = "soft",
    }
}

impl StopLaw {
    /// Which law this is.
    pub fn kind(&self) -> LawKind {
        match self {
            StopLaw::Rigid { .. } => LawKind::Rigid,
            StopLaw::Soft { .. } => LawKind::Soft,
        }
    }
}

/// A stop: where it is and how it acts.
#[derive(Debug, Clone, PartialEq)]
pub struct Stop {
    /// Name (`A12`).
    pub name: String,
    /// Geometry.
    pub geometry: StopGeometry,
    /// Rigid (restitution) or soft (stiffness and damping).
    pub law: StopLaw,
}

/// Coulomb friction between masses `a` and `b`.
#[derive(Debug, Clone, PartialEq)]
pub struct Friction {
    /// First mass.
    pub a: usize,
    /// Second mass.
    pub b: usize,
    /// Kinetic force (>= 0).
    pub kinetic: f64,
    /// Static limit (>= kinetic).
    pub static_limit: f64,
}

/// The stops counted in one mass's n-p-q label.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelStops {
    /// The labelled mass.
    pub mass: usize,
    /// Stop counted as p.
    pub p: usize,
    /// Stop counted as q, if any.
    pub q: Option<usize>,
}

/// A fully evaluated scene for one set of parameter values.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Scene name.
    pub name: String,
    /// Mirror symmetry `x -> -x` with a half-period shift.
    pub symmetric: bool,
    /// Forcing frequency (> 0).
    pub omega: f64,
    /// Forcing phase.
    pub tau: f64,
    /// Masses in state order.
    pub masses: Vec<Mass>,
    /// Links.
    pub links: Vec<Link>,
    /// Stops.
    pub stops: Vec<Stop>,
    /// Friction contacts.
    pub friction: Vec<Friction>,
    /// Label definitions, in mass order.
    pub labels: Vec<LabelStops>,
    /// Parameter values used, in scene order.
    pub parameters: Vec<(String, f64)>,
    /// The quantities the scene defines, computed after the built-in ones.
    pub quantities: std::sync::Arc<[crate::Derived]>,
    /// The scene's physical scales.
    pub scales: std::sync::Arc<crate::Scales>,
}

impl Model {
    /// Value of a parameter by name.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters.iter().find(|(n, _)| n == name).map(|&(_, v)| v)
    }

    /// Highest multiple of omega in the forcing (1 without further harmonics).
    pub fn harmonic_orders(&self) -> u32 {
        self.masses.iter().flat_map(|m| m.harmonics.iter().map(|h| h.order)).fold(1, u32::max)
    }

    /// Forcing period `2 pi / omega`.
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }

    /// The names of the labelled masses, in the order of their labels.
    pub fn labelled_masses(&self) -> Vec<String> {
        self.labels.iter().map(|l| self.masses[l.mass].name.clone()).collect()
    }

    /// Initial state `[x_1..x_m, v_1..v_m]`.
    pub fn initial_state(&self) -> Vec<f64> {
        let mut s: Vec<f64> = self.masses.iter().map(|m| m.x0).collect();
        s.extend(self.masses.iter().map(|m| m.v0));
        s
    }

    /// Signed distance to contact of a stop at positions `x` (>= 0 when admissible).
    pub fn gap(&self, stop: usize, x: &[f64]) -> f64 {
        let (normal, offset) = self.stops[stop].geometry.gap_function(x.len());
        normal.iter().zip(x).map(|(n, x)| n * x).sum::<f64>() + offset
    }
}
