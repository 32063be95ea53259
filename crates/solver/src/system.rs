//! The linear system of a scene: `M x'' + C x' + K x = Σ_k (P_k sin kφ + Q_k cos kφ) + L`
//! (`φ = ω t + τ`, harmonics k = 1 … H, `L` the constant loads) plus stop
//! reactions, and each stop as a gap function `g(x) = n·x + c >= 0`.
//!
//! Frame stop below mass i: `n = e_i`, `c = -position`; above: `n = -e_i`,
//! `c = position`; pair stop `x_a - x_b <= gap`: `n = e_b - e_a`, `c = gap`.
//!
//! A friction contact between masses a and b acts on the relative coordinate
//! `n·x = x_a - x_b` with `n = e_a - e_b`: a force `F` on a and `-F` on b, with
//! `F = -f_k sgn(x_a' - x_b')` while slipping and `|F| <= f_s` while stuck.

use crate::contact::Contact;
use crate::error::SolverError;
use nalgebra::{DMatrix, DVector};
use scene::{Model, StopLaw};

/// A stop as a linear gap function of the positions.
#[derive(Debug, Clone)]
pub struct StopRow {
    /// Normal `n`: `g = n·x + c`.
    pub normal: DVector<f64>,
    /// Offset `c`.
    pub offset: f64,
    /// Rigid (restitution) or soft (stiffness and damping).
    pub law: StopLaw,
    /// `M^{-1} n`, the velocity change per unit impulse.
    pub inv_mass_normal: DVector<f64>,
    /// `nᵀ M^{-1} n`, the inverse effective mass of the contact.
    pub inv_effective_mass: f64,
    /// The normal's nonzero entries, for the gap and its rate.
    support: Support,
}

/// A Coulomb friction contact on the relative coordinate `n·x = x_a - x_b`.
#[derive(Debug, Clone)]
pub struct FrictionRow {
    /// `n = e_a - e_b`.
    pub normal: DVector<f64>,
    /// Kinetic force `f_k` (>= 0).
    pub kinetic: f64,
    /// Static limit `f_s` (>= f_k).
    pub static_limit: f64,
    /// The normal's nonzero entries, for the slip rate.
    support: Support,
}

/// The nonzero entries of a stop's or a friction contact's normal, `(index,
/// value)` in index order: one (a stop against the frame) or two (a stop
/// between two masses, a contact's `e_a − e_b`).
#[derive(Debug, Clone)]
struct Support(Vec<(usize, f64)>);

impl Support {
    fn of(normal: &DVector<f64>) -> Support {
        let entries: Vec<(usize, f64)> = normal.iter().copied().enumerate().filter(|&(_, n)| n != 0.0).collect();
        debug_assert!(entries.len() <= 2, "a normal of one or two masses");
        Support(entries)
    }

    /// `n·z` for a finite `z` (positions or velocities): the nonzero entries'
    /// products summed from +0 in index order, which is nalgebra's dense
    /// product bit for bit (its other terms are zeros, which leave a sum as
    /// it is, and two numbers add the same in either order, as its sum
    /// unrolled over eight masses or more may take them), without its loop
    /// over every mass: gaps and their rates are taken at every event, for
    /// every stop.
    fn dot(&self, z: &[f64]) -> f64 {
        self.0.iter().fold(0.0, |sum, &(i, n)| sum + n * z[i])
    }
}

/// Largest penetration of a stop in a state a cell may start from (a
/// previous cell's final state, a stored one): the fast preset's contact
/// tolerance. The solver's own states stay within ten contact tolerances of
/// every stop (standard: 1e-10), so that a state it produced is admissible.
pub const ADMISSIBLE_PENETRATION: f64 = 1e-9;

/// Largest magnitude of a number of a system or its initial state that the
/// solver answers for: the product of two such numbers (an energy, a
/// stiffness times a displacement) still fits a double. Beyond it, and below
/// its reciprocal for a number that is not zero, a cell is `unresolved` with
/// the number named ([`System::check_range`]), never a label computed from
/// overflowed or vanished values.
pub const LARGEST_MAGNITUDE: f64 = 1e150;

/// Largest ratio of the forcing frequency to the fastest free rate of the
/// masses ([`System::fastest_rate`]) that the solver answers for: beyond it a
/// state moves by less than one part in 1e9 of its own motion per forcing
/// period, and a record of thousands of periods cannot tell an orbit from a
/// state that has not moved ([`System::check_range`]).
pub const FASTEST_FORCING: f64 = 1e9;

/// Matrices of the equations of motion, built once per cell.
#[derive(Debug, Clone)]
pub struct System {
    /// The evaluated scene.
    pub model: Model,
    /// Masses (diagonal of M).
    pub mass: DVector<f64>,
    /// Damping matrix C.
    pub damping: DMatrix<f64>,
    /// Stiffness matrix K.
    pub stiffness: DMatrix<f64>,
    /// The forcing per harmonic of `φ = ω t + τ`: entry `k - 1` holds the
    /// amplitudes `[P_k, Q_k]` of `sin kφ` and `cos kφ` on each mass (H entries,
    /// H the highest order in the scene, at least 1).
    pub harmonics: Vec<[DVector<f64>; 2]>,
    /// Constant forces `L` on the masses (loads).
    pub load: DVector<f64>,
    /// Stops as gap rows.
    pub stops: Vec<StopRow>,
    /// Friction contacts.
    pub frictions: Vec<FrictionRow>,
    /// Forcing frequency ω.
    pub omega: f64,
    /// Forcing phase τ.
    pub tau: f64,
    /// Forcing period `2π/ω`.
    pub period: f64,
    /// The dimension of the stiffness matrix's null space (see [`System::rigid_modes`]).
    rigid: usize,
    /// Per quantity the scene defines, where its operands' values are found
    /// ([`crate::quantity`]).
    pub(crate) derived: Vec<Vec<usize>>,
}

/// The amplitudes `[P_k, Q_k]` of `sin kφ`, `cos kφ` per mass for k = 1 … H
/// (`φ = ω t + τ`): each mass's `force` on `sin φ`, and each harmonic
/// `a sin(k ω t + ψ) = a sin(kφ + ψ - kτ)` split into its sine and cosine parts.
fn harmonic_amplitudes(model: &Model) -> Vec<[DVector<f64>; 2]> {
    let m = model.masses.len();
    let orders = model.harmonic_orders() as usize;
    let mut out = vec![[DVector::zeros(m), DVector::zeros(m)]; orders];
    for (i, mass) in model.masses.iter().enumerate() {
        out[0][0][i] = mass.force;
        for h in &mass.harmonics {
            let (sn, cs) = (h.phase - f64::from(h.order) * model.tau).sin_cos();
            let [p, q] = &mut out[h.order as usize - 1];
            p[i] += h.amplitude * cs;
            q[i] += h.amplitude * sn;
        }
    }
    out
}

impl System {
    /// Assembles the matrices of a model.
    pub fn new(model: Model) -> Result<System, SolverError> {
        if model.stops.len() > 16 {
            return Err(SolverError::Unsupported {
                field: "stops".into(),
                message: format!("at most 16 stops are supported, got {}", model.stops.len()),
            });
        }
        if model.friction.len() > 8 {
            return Err(SolverError::Unsupported {
                field: "friction".into(),
                message: format!("at most 8 friction contacts are supported, got {}", model.friction.len()),
            });
        }
        let m = model.masses.len();
        let mass = DVector::from_iterator(m, model.masses.iter().map(|x| x.mass));
        let mut damping = DMatrix::zeros(m, m);
        let mut stiffness = DMatrix::zeros(m, m);
        for l in &model.links {
            let add = |mat: &mut DMatrix<f64>, v: f64| {
                mat[(l.a, l.a)] += v;
                if let Some(b) = l.b {
                    mat[(b, b)] += v;
                    mat[(l.a, b)] -= v;
                    mat[(b, l.a)] -= v;
                }
            };
            add(&mut damping, l.damping);
            add(&mut stiffness, l.stiffness);
        }
        let harmonics = harmonic_amplitudes(&model);
        let load = DVector::from_iterator(m, model.masses.iter().map(|x| x.load));
        let stops = model
            .stops
            .iter()
            .map(|s| {
                let (normal, offset) = s.geometry.gap_function(m);
                let normal = DVector::from_vec(normal);
                let inv_mass_normal = normal.component_div(&mass);
                let inv_effective_mass = normal.dot(&inv_mass_normal);
                let support = Support::of(&normal);
                StopRow { normal, offset, law: s.law, inv_mass_normal, inv_effective_mass, support }
            })
            .collect();
        let frictions = model
            .friction
            .iter()
            .map(|f| {
                let mut normal = DVector::zeros(m);
                normal[f.a] = 1.0;
                normal[f.b] = -1.0;
                let support = Support::of(&normal);
                FrictionRow { normal, kinetic: f.kinetic, static_limit: f.static_limit, support }
            })
            .collect();
        let period = model.period();
        let rigid = {
            let eig = stiffness.clone().symmetric_eigenvalues();
            let largest = eig.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            eig.iter().filter(|v| v.abs() <= 1e-12 * largest.max(f64::MIN_POSITIVE)).count()
        };
        let mut system = System {
            mass,
            damping,
            stiffness,
            harmonics,
            load,
            stops,
            frictions,
            omega: model.omega,
            tau: model.tau,
            period,
            rigid,
            model,
            derived: Vec::new(),
        };
        system.derived = crate::quantity::resolve(&system)?;
        Ok(system)
    }

    /// Whether every number of the system and of the state `y0` a cell starts
    /// from is finite and within [`LARGEST_MAGNITUDE`] (or zero, or at least
    /// its reciprocal): masses, link stiffnesses and dampings, forcing
    /// amplitudes, frequency and phase, stop positions and clearances,
    /// friction forces and the state. The first one that is not, named.
    pub fn check_range(&self, y0: &[f64]) -> Result<(), SolverError> {
        let model = &self.model;
        let mut numbers: Vec<(String, f64)> = vec![("omega".into(), model.omega), ("tau".into(), model.tau)];
        for m in &model.masses {
            numbers.push((format!("mass of {}", m.name), m.mass));
            numbers.push((format!("force on {}", m.name), m.force));
            numbers.push((format!("load on {}", m.name), m.load));
            for h in &m.harmonics {
                numbers.push((format!("harmonic {} on {}", h.order, m.name), h.amplitude));
            }
        }
        for (i, l) in model.links.iter().enumerate() {
            numbers.push((format!("stiffness of link {}", i + 1), l.stiffness));
            numbers.push((format!("damping of link {}", i + 1), l.damping));
        }
        for (s, row) in model.stops.iter().zip(&self.stops) {
            numbers.push((format!("position of stop {}", s.name), row.offset));
            if let Some(spring) = s.law.spring() {
                numbers.push((format!("stiffness of stop {}", s.name), spring.stiffness));
                numbers.push((format!("damping of stop {}", s.name), spring.damping));
            }
        }
        for (i, f) in model.friction.iter().enumerate() {
            numbers.push((format!("static friction limit of contact {}", i + 1), f.static_limit));
        }
        let names = model.masses.iter().map(|m| format!("x of {}", m.name));
        let names = names.chain(model.masses.iter().map(|m| format!("v of {}", m.name)));
        numbers.extend(names.zip(y0.iter().copied()));
        let outside =
            |v: f64| !v.is_finite() || v.abs() > LARGEST_MAGNITUDE || (v != 0.0 && v.abs() < 1.0 / LARGEST_MAGNITUDE);
        if let Some((what, v)) = numbers.into_iter().find(|&(_, v)| outside(v)) {
            return Err(SolverError::OutOfRange {
                message: format!(
                    "{what} = {v:e} is beyond the {LARGEST_MAGNITUDE:e} (or, not zero, within 1/{LARGEST_MAGNITUDE:e}) that double precision answers for; rescale the scene"
                ),
            });
        }
        let rate = self.fastest_rate();
        if rate > 0.0 && self.omega > FASTEST_FORCING * rate {
            return Err(SolverError::OutOfRange {
                message: format!(
                    "omega = {:e} is {:.1e} times the fastest free rate of the masses ({rate:.3e}): within a forcing period the state cannot change at double precision",
                    self.omega,
                    self.omega / rate
                ),
            });
        }
        Ok(())
    }

    /// The fastest rate of the free system, from each mass's own spring and
    /// damper: the largest of `sqrt(K_ii / m_i)` and `C_ii / m_i` (per unit
    /// time; 0 for masses held by nothing).
    pub fn fastest_rate(&self) -> f64 {
        (0..self.dof())
            .map(|i| (self.stiffness[(i, i)] / self.mass[i]).sqrt().max(self.damping[(i, i)] / self.mass[i]))
            .fold(0.0, f64::max)
    }

    /// Whether the masses have a rigid mode: the stiffness matrix is
    /// singular (a mass, or a group of masses, held by no spring), so that
    /// a motion without contacts may drift without bound.
    pub fn has_rigid_mode(&self) -> bool {
        self.rigid > 0
    }

    /// The number of rigid modes: the dimension of the stiffness matrix's
    /// null space. Over a flow without contacts each gives its period map a
    /// multiplier 1 for the drift of its position, and a second one for its
    /// velocity where no damper holds it.
    pub fn rigid_modes(&self) -> usize {
        self.rigid
    }

    /// Whether no damper links the masses (every entry of the damping
    /// matrix zero): each free oscillation keeps its amplitude.
    pub fn undamped(&self) -> bool {
        self.damping.iter().all(|&c| c == 0.0)
    }

    /// Whether the scene dissipates no energy: no damper, every rigid stop
    /// elastic (restitution 1), no dashpot in a soft stop and no friction
    /// contact. Its period map then preserves volume in the state space: it
    /// has no attractor, and a motion on a torus neither reaches nor leaves
    /// the orbits locked on it.
    pub fn lossless(&self) -> bool {
        self.loses_at_most_at_impacts()
            && self.stops.iter().all(|s| match s.law {
                StopLaw::Rigid { restitution } => restitution >= 1.0,
                StopLaw::Soft { .. } => true,
            })
    }

    /// Whether the scene loses energy at its rigid stops' impacts alone
    /// (a restitution below 1): no damper, no friction contact, no dashpot
    /// in a soft stop, and not [`System::lossless`].
    pub fn loses_at_impacts_alone(&self) -> bool {
        self.loses_at_most_at_impacts() && !self.lossless()
    }

    /// Whether nothing but the rigid stops' impacts can take energy: no
    /// damper, no friction contact, no dashpot in a soft stop.
    fn loses_at_most_at_impacts(&self) -> bool {
        self.undamped()
            && self.frictions.is_empty()
            && self.stops.iter().all(|s| match s.law {
                StopLaw::Soft { damping, .. } => damping == 0.0,
                StopLaw::Rigid { .. } => true,
            })
    }

    /// Number of masses (degrees of freedom).
    pub fn dof(&self) -> usize {
        self.mass.len()
    }

    /// Gap of a stop at full state `y = [x; v]`.
    pub fn gap(&self, stop: usize, y: &DVector<f64>) -> f64 {
        let s = &self.stops[stop];
        s.support.dot(&y.as_slice()[..self.dof()]) + s.offset
    }

    /// Whether full state `y` may start a simulation of this system: of its
    /// dimension and penetrating no rigid stop by more than
    /// [`ADMISSIBLE_PENETRATION`] (a soft stop may be pressed in).
    pub fn admits(&self, y: &[f64]) -> bool {
        let m = self.dof();
        y.len() == 2 * m
            && (0..self.stops.len())
                .all(|k| self.stops[k].law.yields() || self.model.gap(k, &y[..m]) >= -ADMISSIBLE_PENETRATION)
    }

    /// Whether the scene has stops that act by a spring (soft stops).
    pub fn has_soft_stops(&self) -> bool {
        self.stops.iter().any(|s| s.law.spring().is_some())
    }

    /// Whether the scene has stops that act by impacts (rigid stops).
    pub fn has_rigid_stops(&self) -> bool {
        self.stops.iter().any(|s| s.law.impacts())
    }

    /// The coefficient of restitution of stop `k`'s impacts (0 for a stop
    /// without impacts).
    pub fn restitution(&self, k: usize) -> f64 {
        self.stops[k].law.restitution().unwrap_or(0.0)
    }

    /// Highest multiple of ω in the forcing (H >= 1).
    pub fn harmonic_orders(&self) -> usize {
        self.harmonics.len()
    }

    /// The forcing's columns that act, `(k, cosine, amplitudes)`: the
    /// amplitudes on `sin kφ` (`cosine` false) or `cos kφ` of harmonic k, a
    /// column without force left out (`sin φ` always kept: the matrices of a
    /// scene with one harmonic stay what they were, bit for bit).
    pub fn forcing_columns(&self) -> impl Iterator<Item = (usize, bool, &DVector<f64>)> {
        (1..).zip(&self.harmonics).flat_map(|(k, [p, q])| {
            let acts = |v: &DVector<f64>| v.iter().any(|&a| a != 0.0);
            let sine = (k == 1 || acts(p)).then_some((k, false, p));
            let cosine = acts(q).then_some((k, true, q));
            sine.into_iter().chain(cosine)
        })
    }

    /// A soft stop's contact force `−k g − c ġ` at full state `y` (force;
    /// positive while it pushes its mass out); 0 at a rigid stop.
    pub fn contact_force(&self, stop: usize, y: &DVector<f64>) -> f64 {
        self.stops[stop].law.spring().map_or(0.0, |spring| spring.force(self.gap(stop, y), self.gap_rate(stop, y)))
    }

    /// Rate of change of a stop's gap at full state `y` (negative when closing).
    pub fn gap_rate(&self, stop: usize, y: &DVector<f64>) -> f64 {
        self.stops[stop].support.dot(&y.as_slice()[self.dof()..])
    }

    /// Forcing phase `ω t + τ` at absolute time `t`, reduced to `[0, 2π)`.
    pub fn phase_at(&self, t: f64) -> f64 {
        (self.omega * t + self.tau).rem_euclid(std::f64::consts::TAU)
    }

    /// The name of friction contact `i`: its masses', `M1-M2`.
    pub fn friction_name(&self, i: usize) -> String {
        let (m, f) = (&self.model.masses, &self.model.friction[i]);
        format!("{}-{}", m[f.a].name, m[f.b].name)
    }

    /// Relative velocity `x_a' - x_b'` of friction contact `i` at full state `y`.
    pub fn slip_rate(&self, i: usize, y: &DVector<f64>) -> f64 {
        self.frictions[i].support.dot(&y.as_slice()[self.dof()..])
    }

    /// Kinetic energy `½ vᵀ M v`.
    pub fn kinetic_energy(&self, y: &DVector<f64>) -> f64 {
        let m = self.dof();
        (0..m).map(|i| 0.5 * self.mass[i] * y[m + i] * y[m + i]).sum()
    }

    /// Momentum `Σ M_i v_i`.
    pub fn momentum(&self, y: &DVector<f64>) -> f64 {
        let m = self.dof();
        (0..m).map(|i| self.mass[i] * y[m + i]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{system, system_of};
    use proptest::prelude::*;

    /// A chain of seventeen masses (nalgebra's dense product sums eight at
    /// a time in eight lanes, the rest one by one): M0 and M8 meeting at a
    /// stop (one lane), M3 and M7 at a friction contact (two lanes of one
    /// pass), and a stop against the frame on M16 (the rest).
    fn chain() -> System {
        let mut toml =
            String::from("name = \"chain\"\n[parameters]\nomega = { value = 1.0 }\n[forcing]\nomega = \"omega\"\n");
        for i in 0..17 {
            toml += &format!(
                "[[masses]]\nname = \"M{i}\"\nmass = 1\nforce = 1\n[[links]]\nmasses = [\"M{i}\"]\nstiffness = 1\n"
            );
        }
        toml += "[[stops]]\nname = \"ends\"\nmasses = [\"M0\", \"M8\"]\ngap = 0.5\nrestitution = 0.8\n";
        toml += "[[stops]]\nname = \"wall\"\nmass = \"M16\"\nside = \"above\"\nposition = 1\nrestitution = 0.8\n";
        toml += "[[friction]]\nmasses = [\"M3\", \"M7\"]\nkinetic = 0.1\nstatic = 0.2\n";
        system_of(&toml, &[])
    }

    proptest! {
        /// The gaps, their rates and the slip rates over the normals'
        /// nonzero entries are nalgebra's dense products bit for bit, on
        /// the shipped scenes with stops between masses, against the frame
        /// and friction, and on the chain of seventeen, signed zeros
        /// included.
        #[test]
        fn the_sums_over_the_support_are_the_dense_products(
            z in proptest::collection::vec(prop_oneof![-1e3f64..1e3, -1e-12f64..1e-12, Just(0.0), Just(-0.0)], 34)
        ) {
            let systems = [system("multi-stop.toml", &[]), system("dry-friction.toml", &[]), system("single-stop.toml", &[]), chain()];
            for sys in &systems {
                let m = sys.dof();
                let y = DVector::from_column_slice(&z[..2 * m]);
                for (k, s) in sys.stops.iter().enumerate() {
                    let gap = s.normal.dot(&y.rows(0, m)) + s.offset;
                    prop_assert_eq!(sys.gap(k, &y).to_bits(), gap.to_bits());
                    prop_assert_eq!(sys.gap_rate(k, &y).to_bits(), s.normal.dot(&y.rows(m, m)).to_bits());
                }
                for (i, f) in sys.frictions.iter().enumerate() {
                    prop_assert_eq!(sys.slip_rate(i, &y).to_bits(), f.normal.dot(&y.rows(m, m)).to_bits());
                }
            }
        }
    }
}
