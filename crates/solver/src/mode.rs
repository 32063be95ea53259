//! Modes: the linear system with a set of stops held (sticking) and each
//! friction contact slipping one way or stuck.
//!
//! Held stops and stuck friction contacts are linear constraints `G x = w`:
//! a held stop's row `n_j` with `w_j = -c_j`, a stuck contact's row
//! `n = e_a - e_b` with `w` the frozen relative displacement `p`. Positions are
//! `x = N q + x_c + E p` with `N` an orthonormal basis of `ker G`, `x_c` the
//! least-norm solution of the stop constraints and `E` that of the frozen
//! displacements. The reduced equations
//! `Nᵀ M N q'' + Nᵀ C N q' + Nᵀ K (N q + x_c + E p) = Nᵀ (Σ_k (P_k sin kφ + Q_k cos kφ) + f)`,
//! with `f` the constant forces (loads, and the kinetic friction
//! `-f_k sgn(x_a' - x_b') n` of slipping contacts), become the augmented linear
//! system `s' = Â s` with `s = [q; q'; p; sin φ; cos φ; …; sin Hφ; cos Hφ; 1]`,
//! `φ = ω t + τ` (`p` is constant; H the highest harmonic of the forcing).
//!
//! Soft stops are not constraints: a pressed one adds its spring and dashpot
//! along its normal to `K` and `C` (`k n nᵀ`, `c n nᵀ`) and its spring's
//! preload `-k c_g n` to `f` (`g = n·x + c_g`); its guard is its contact force
//! `-k g - c g'`, which ends the contact at zero. A *parting* soft stop (its
//! force fell to zero while the gap is still closed, which damping causes)
//! flows free with two guards: the overlap `-g` (the gap reopens at zero) and
//! `k g + c g'` (the force would push again at zero).
//!
//! The constraint forces `λ = (G Gᵀ)^{-1} G (M x'' + C x' + K x - P sin φ - f)`
//! are linear functionals of `s`: a held stop's reaction (released when it
//! crosses zero, the net force pulling the mass off the stop) and a stuck
//! contact's friction force `F` on mass a (the contact breaks away when
//! `|F|` exceeds `f_s`). Every event guard of a mode is a row `ℓ` with guard
//! value `ℓ·s >= 0`: gaps of free stops, reactions of held ones, `f_s ∓ F` of
//! stuck contacts, and `±(x_a' - x_b')` of slipping ones.
//!
//! A friction contact whose relative coordinate is already fixed by held stops
//! (a mass resting against the other's wall) is *locked*: its force is
//! indeterminate and taken as zero, the stop's reaction carries the load, and
//! the contact is decided again when the stop releases.

use crate::contact::{Contact, Spring};
use crate::error::SolverError;
use crate::spectral::{nonzero_entries, Spectral};
use crate::system::System;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use num_complex::Complex64 as C64;
use std::ops::AddAssign;
use std::sync::{Arc, OnceLock};

/// A row in the span of the constraint rows within this (relative to its
/// norm) is a combination of them: a friction contact whose relative
/// coordinate the held stops fix is locked.
const SPAN_TOL: f64 = 1e-9;

/// Largest condition number of `G Gᵀ` of a mode's constraints: beyond it the
/// constraints are taken as dependent (no such mode).
const MAX_CONDITION: f64 = 1e10;

/// The projector `I - Gᵀ(GGᵀ)⁻¹G` onto `ker G` has eigenvalues 0 and 1 only;
/// its eigenvectors with an eigenvalue above this span the kernel.
const PROJECTOR_SPLIT: f64 = 0.5;

/// A free stop whose normal has no component beyond this along the free
/// coordinates (a pair stop while its masses stick together) keeps a constant
/// gap: it gets no guard.
const CONSTRAINED_NORMAL: f64 = 1e-12;

/// What a guard watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuardKind {
    /// Gap of a free stop: contact when it reaches zero.
    Gap,
    /// Reaction of a held stop: release when it reaches zero.
    Reaction,
    /// Static margin `f_s ∓ F` of a stuck friction contact: breakaway at zero.
    Grip,
    /// Relative velocity (signed along the slip) of a slipping contact: the slip
    /// ends at zero (then the contact sticks or reverses).
    Slip,
    /// Gap of a free soft stop: its contact begins at zero. Located in time
    /// at rounding level like a force (a soft contact has no landing to
    /// tolerate: it begins exactly where the gap closes).
    Touch,
    /// Contact force `-k g - c g'` of a pressed soft stop: the contact ends at zero.
    Push,
    /// Overlap `-g` of a parting soft stop: its gap reopens at zero.
    Overlap,
    /// `k g + c g'` of a parting soft stop: its contact pushes again at zero.
    Return,
}

impl GuardKind {
    /// Whether the guard is a length (a gap), located to the contact tolerance;
    /// other guards are forces or velocities, located in time at rounding level.
    pub fn is_gap(self) -> bool {
        self == GuardKind::Gap
    }
}

/// What a guard belongs to: a stop (gaps and reactions) or a friction contact
/// (grips and slips), by its index into the system's stops or contacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Stop `k` of [`System::stops`].
    Stop(usize),
    /// Friction contact `i` of [`System::frictions`].
    Contact(usize),
}

impl Target {
    /// The stop or contact index.
    pub fn index(self) -> usize {
        match self {
            Target::Stop(k) | Target::Contact(k) => k,
        }
    }
}

/// One event function of a mode, `ℓ·s >= 0`.
#[derive(Debug, Clone)]
pub struct Guard {
    /// What it watches.
    pub kind: GuardKind,
    /// The stop or contact it belongs to (a stop for gaps and reactions, a
    /// contact for grips and slips).
    pub target: Target,
    /// Row `ℓ` over the augmented state.
    pub row: DVector<f64>,
    /// `|ℓ|` entrywise (for the guard's magnitude `|ℓ|·|s|`).
    pub row_abs: DVector<f64>,
    /// The nonzero entries of `ℓ` (index, value), ascending: a guard reads a few
    /// coordinates of the augmented state.
    pub entries: Vec<(usize, f64)>,
}

impl Guard {
    fn new(kind: GuardKind, index: usize, row: DVector<f64>) -> Guard {
        let target = match kind {
            GuardKind::Gap
            | GuardKind::Reaction
            | GuardKind::Touch
            | GuardKind::Push
            | GuardKind::Overlap
            | GuardKind::Return => Target::Stop(index),
            GuardKind::Grip | GuardKind::Slip => Target::Contact(index),
        };
        let row_abs = row.abs();
        let entries = nonzero_entries(row.as_slice());
        Guard { kind, target, row, row_abs, entries }
    }
}

/// Which linear system holds: the held stops, the state of each friction
/// contact and of each soft stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Key {
    /// Bit k: stop k holds its mass.
    pub held: u32,
    /// Bit i: friction contact i is stuck (its masses move together).
    pub stuck: u32,
    /// Bit i: friction contact i slips with `x_a' - x_b' < 0` (when not stuck).
    pub negative: u32,
    /// Bit k: soft stop k pushes (its gap is closed and its force positive).
    pub pressed: u32,
    /// Bit k: soft stop k is parting (its gap still closed, its force zero).
    pub parting: u32,
}

impl Key {
    /// Free flight, every contact slipping forwards: the key of a scene without
    /// held stops or friction.
    pub const FREE: Key = Key { held: 0, stuck: 0, negative: 0, pressed: 0, parting: 0 };

    /// Whether the mode has constraints (held stops or stuck contacts), so that
    /// a state must be projected onto them.
    pub fn constrained(self) -> bool {
        self.held != 0 || self.stuck != 0
    }
}

/// A linear mode: constraints, reduced coordinates, augmented matrix, guards.
///
/// Guard order (a contract with the integrators, which report the first
/// guard in this order among those that vanish at the same time): the gaps of
/// free stops by stop index, then the soft stops in contact by stop index (a
/// pressed one's force; a parting one's overlap, then its return), then the reactions of held stops by stop index,
/// then the grips of stuck contacts (`-F` side, then `+F`) by contact index,
/// then the slips of slipping contacts by contact index.
#[derive(Debug, Clone)]
pub struct Mode {
    /// The mode's key.
    pub key: Key,
    /// Rows `n` of the stuck (not locked) friction contacts, in the order of `p`.
    frozen: DMatrix<f64>,
    basis: DMatrix<f64>,
    offset: DVector<f64>,
    /// `E`: positions per unit frozen displacement.
    spread: DMatrix<f64>,
    /// Augmented matrix Â.
    pub aug: DMatrix<f64>,
    /// Spectral decomposition of Â over one forcing period (shared with every
    /// mode of the same Â and period, see [`Spectral::shared`]).
    pub spectral: Arc<Spectral>,
    /// Event guards, in the order above.
    pub guards: Vec<Guard>,
    /// Where the augmented state holds what.
    layout: Layout,
    /// `P = ∂s/∂y`, see [`Mode::project_matrix`].
    project_matrix: DMatrix<f64>,
    /// `L`, see [`Mode::lift_matrix`].
    lift_matrix: DMatrix<f64>,
    /// Per term of the spectral expansion, `L · V N^j W · P` (built on first use
    /// by tangent tracking).
    tangent_terms: OnceLock<Vec<DMatrix<C64>>>,
    /// What a saltation matrix takes of the mode alone (built on first use
    /// by tangent tracking): see [`Mode::guard_gradient`] and
    /// [`Mode::constraint_projection`].
    saltation: OnceLock<SaltationParts>,
}

/// Each guard's gradient `Pᵀ ℓ` in full coordinates, and `L P`.
#[derive(Debug, Clone)]
struct SaltationParts {
    gradients: Vec<DVector<f64>>,
    projection: DMatrix<f64>,
}

/// Whether `row` lies in the span of the rows of `g` (to [`SPAN_TOL`]).
fn in_span(g: &DMatrix<f64>, row: &DVector<f64>) -> bool {
    if g.nrows() == 0 {
        return false;
    }
    let Some(inv) = (g * g.transpose()).try_inverse() else { return false };
    let residual = row - g.transpose() * (inv * (g * row));
    residual.norm() <= SPAN_TOL * row.norm()
}

/// The constraints of a key: `G x = w`, the rows of the held stops (in stop
/// order), then those of the stuck contacts that held stops do not lock.
struct Constraints {
    /// Held stops.
    held: Vec<usize>,
    /// Stuck, not locked, friction contacts (the frozen displacements `p`).
    frozen: Vec<usize>,
    /// Friction contacts locked by the held stops (bit mask).
    locked: u32,
    /// `G`.
    g: DMatrix<f64>,
    /// Offsets `c` of the held stops.
    offsets: DVector<f64>,
}

impl Constraints {
    fn of(sys: &System, key: Key) -> Constraints {
        let m = sys.dof();
        let held: Vec<usize> = (0..sys.stops.len()).filter(|j| key.held & (1 << j) != 0).collect();
        let hs = held.len();
        let stop_rows = DMatrix::from_fn(hs, m, |r, c| sys.stops[held[r]].normal[c]);
        let locked = (0..sys.frictions.len())
            .filter(|&i| in_span(&stop_rows, &sys.frictions[i].normal))
            .fold(0u32, |acc, i| acc | (1 << i));
        let frozen: Vec<usize> = (0..sys.frictions.len()).filter(|i| key.stuck & !locked & (1 << i) != 0).collect();
        let g = DMatrix::from_fn(hs + frozen.len(), m, |r, c| {
            if r < hs {
                sys.stops[held[r]].normal[c]
            } else {
                sys.frictions[frozen[r - hs]].normal[c]
            }
        });
        let offsets = DVector::from_fn(hs, |r, _| sys.stops[held[r]].offset);
        Constraints { held, frozen, locked, g, offsets }
    }

    fn count(&self) -> usize {
        self.held.len() + self.frozen.len()
    }
}

/// Positions `x = N q + x_c + E p` in reduced coordinates.
struct Reduction {
    /// `N`, an orthonormal basis of `ker G`.
    basis: DMatrix<f64>,
    /// `x_c`, the least-norm solution of the stop constraints.
    offset: DVector<f64>,
    /// `E`, positions per unit frozen displacement.
    spread: DMatrix<f64>,
    /// `(G Gᵀ)⁻¹`.
    ggt_inv: DMatrix<f64>,
}

impl Reduction {
    /// `None` when the constraints are dependent or ill-conditioned.
    fn of(c: &Constraints, m: usize) -> Option<Reduction> {
        let (hs, hf, h) = (c.held.len(), c.frozen.len(), c.count());
        if h == 0 {
            return Some(Reduction {
                basis: DMatrix::identity(m, m),
                offset: DVector::zeros(m),
                spread: DMatrix::zeros(m, 0),
                ggt_inv: DMatrix::zeros(0, 0),
            });
        }
        let g = &c.g;
        let ggt = g * g.transpose();
        let ggt_inv = ggt.clone().try_inverse()?;
        let cond = ggt.norm() * ggt_inv.norm();
        if cond.is_nan() || cond >= MAX_CONDITION {
            return None;
        }
        let proj = DMatrix::identity(m, m) - g.transpose() * &ggt_inv * g;
        let eig = SymmetricEigen::new(proj);
        let mut idx: Vec<usize> = (0..m).filter(|&i| eig.eigenvalues[i] > PROJECTOR_SPLIT).collect();
        idx.sort_unstable();
        let cols: Vec<DVector<f64>> = idx.iter().map(|&i| eig.eigenvectors.column(i).into_owned()).collect();
        let basis = if cols.is_empty() { DMatrix::zeros(m, 0) } else { DMatrix::from_columns(&cols) };
        if basis.ncols() != m - h {
            return None;
        }
        let pinv = g.transpose() * &ggt_inv;
        let offset = -(pinv.columns(0, hs) * &c.offsets);
        let spread = pinv.columns(hs, hf).into_owned();
        Some(Reduction { basis, offset, spread, ggt_inv })
    }

    /// Free coordinates `r` (the columns of `N`).
    fn free(&self) -> usize {
        self.basis.ncols()
    }
}

/// The augmented state `s = [q; q'; p; sin φ; cos φ; …; sin Hφ; cos Hφ; 1]` of
/// a mode with `r` free coordinates, `hf` frozen displacements and `h`
/// harmonics.
#[derive(Debug, Clone, Copy)]
struct Layout {
    r: usize,
    hf: usize,
    h: usize,
}

impl Layout {
    fn dim(self) -> usize {
        2 * self.r + self.hf + 2 * self.h + 1
    }
    fn frozen(self) -> usize {
        2 * self.r
    }
    /// Index of `sin kφ` (k from 1); `cos kφ` follows it.
    fn sin(self, k: usize) -> usize {
        2 * self.r + self.hf + 2 * (k - 1)
    }
    fn cos(self, k: usize) -> usize {
        self.sin(k) + 1
    }
    fn constant(self) -> usize {
        self.dim() - 1
    }
}

/// The stiffness, damping and extra constant force of a mode: the links', and
/// for each pressed soft stop its spring and dashpot along the normal,
/// `k n nᵀ` and `c n nᵀ`, and its spring's preload `-k c_g n`; plus the loads.
/// (A mode with neither loads nor pressed stops borrows the system's matrices
/// and has no extra force.)
struct Forces<'s> {
    stiffness: std::borrow::Cow<'s, DMatrix<f64>>,
    damping: std::borrow::Cow<'s, DMatrix<f64>>,
    /// Loads and preloads, `None` when zero.
    extra: Option<DVector<f64>>,
}

impl<'s> Forces<'s> {
    fn of(sys: &'s System, key: Key) -> Forces<'s> {
        use std::borrow::Cow;
        let mut forces = Forces {
            stiffness: Cow::Borrowed(&sys.stiffness),
            damping: Cow::Borrowed(&sys.damping),
            extra: sys.load.iter().any(|&l| l != 0.0).then(|| sys.load.clone()),
        };
        let pressed = sys.stops.iter().enumerate().filter(|(k, _)| key.pressed & (1 << k) != 0);
        for stop in pressed.map(|(_, stop)| stop) {
            let Some(Spring { stiffness, damping }) = stop.law.spring() else { continue };
            let outer = &stop.normal * stop.normal.transpose();
            *forces.stiffness.to_mut() += &outer * stiffness;
            *forces.damping.to_mut() += &outer * damping;
            let preload = &stop.normal * (-stiffness * stop.offset);
            forces.extra = Some(match forces.extra.take() {
                Some(extra) => extra + preload,
                None => preload,
            });
        }
        forces
    }
}

/// The slipping friction contacts of a key (neither stuck nor locked), with
/// the sign of their relative velocity.
fn slipping(sys: &System, key: Key, locked: u32) -> Vec<(usize, f64)> {
    (0..sys.frictions.len())
        .filter(|i| (key.stuck | locked) & (1 << i) == 0)
        .map(|i| (i, if key.negative & (1 << i) != 0 { -1.0 } else { 1.0 }))
        .collect()
}

/// Kinetic friction of the slipping contacts: the constant force
/// `-Σ f_k sgn(x_a' - x_b') n`.
fn kinetic_force(sys: &System, slipping: &[(usize, f64)]) -> DVector<f64> {
    let mut kinetic = DVector::zeros(sys.dof());
    for &(i, sign) in slipping {
        let f = &sys.frictions[i];
        kinetic -= &f.normal * (sign * f.kinetic);
    }
    kinetic
}

/// The augmented matrix Â of the reduced equations
/// `Nᵀ M N q'' + Nᵀ C N q' + Nᵀ K (N q + x_c + E p) = Nᵀ (Σ_k (P_k sin kφ + Q_k cos kφ) + f)`.
fn augmented(
    sys: &System,
    forces: &Forces,
    red: &Reduction,
    kinetic: &DVector<f64>,
    lay: Layout,
) -> Result<DMatrix<f64>, SolverError> {
    let (r, hf, basis) = (lay.r, lay.hf, &red.basis);
    let mdiag = DMatrix::from_diagonal(&sys.mass);
    let mr = basis.transpose() * &mdiag * basis;
    let mr_inv = if r == 0 {
        DMatrix::zeros(0, 0)
    } else {
        mr.cholesky()
            .ok_or_else(|| SolverError::IllConditioned { message: "reduced mass matrix is not positive".into() })?
            .inverse()
    };
    let (stiffness, damping) = (forces.stiffness.as_ref(), forces.damping.as_ref());
    let kr = basis.transpose() * stiffness * basis;
    let cr = basis.transpose() * damping * basis;
    let mut fr = basis.transpose() * -(stiffness * &red.offset);
    if !sys.frictions.is_empty() {
        fr += basis.transpose() * kinetic;
    }
    if let Some(extra) = &forces.extra {
        fr += basis.transpose() * extra;
    }
    let mut aug = DMatrix::zeros(lay.dim(), lay.dim());
    for i in 0..r {
        aug[(i, r + i)] = 1.0;
    }
    aug.view_mut((r, 0), (r, r)).copy_from(&(-&mr_inv * &kr));
    aug.view_mut((r, r), (r, r)).copy_from(&(-&mr_inv * &cr));
    if hf > 0 {
        aug.view_mut((r, lay.frozen()), (r, hf)).copy_from(&(-&mr_inv * basis.transpose() * stiffness * &red.spread));
    }
    for (k, cosine, amplitudes) in sys.forcing_columns() {
        aug.view_mut((r, lay.sin(k) + usize::from(cosine)), (r, 1))
            .copy_from(&(&mr_inv * (basis.transpose() * amplitudes)));
    }
    for k in 1..=lay.h {
        let rate = k as f64 * sys.omega;
        aug[(lay.sin(k), lay.cos(k))] = rate;
        aug[(lay.cos(k), lay.sin(k))] = -rate;
    }
    aug.view_mut((r, lay.constant()), (r, 1)).copy_from(&(&mr_inv * &fr));
    Ok(aug)
}

/// The gap `n·x + c` of stop `k` in augmented coordinates; `None` when it
/// lies along constrained directions only (a pair stop while its masses stick
/// together), where it is constant and has no events.
fn gap_row(sys: &System, k: usize, red: &Reduction, lay: Layout) -> Option<DVector<f64>> {
    let stop = &sys.stops[k];
    let along = red.basis.transpose() * &stop.normal;
    if along.amax() < CONSTRAINED_NORMAL {
        return None;
    }
    let mut row = DVector::zeros(lay.dim());
    row.rows_mut(0, lay.r).copy_from(&along);
    if lay.hf > 0 {
        row.rows_mut(lay.frozen(), lay.hf).copy_from(&(red.spread.transpose() * &stop.normal));
    }
    row[lay.constant()] = stop.normal.dot(&red.offset) + stop.offset;
    Some(row)
}

/// The gaps of the free stops (neither held nor in soft contact): a rigid
/// stop's [`GuardKind::Gap`], a soft stop's [`GuardKind::Touch`].
fn gap_guards(sys: &System, key: Key, red: &Reduction, lay: Layout) -> Vec<Guard> {
    let closed = key.held | key.pressed | key.parting;
    (0..sys.stops.len())
        .filter(|k| closed & (1 << k) == 0)
        .filter_map(|k| {
            let kind = if sys.stops[k].law.impacts() { GuardKind::Gap } else { GuardKind::Touch };
            gap_row(sys, k, red, lay).map(|row| Guard::new(kind, k, row))
        })
        .collect()
}

/// The guards of the soft stops in contact, by stop index: a pressed stop's
/// force `-k g - c g'`, a parting stop's overlap `-g` and `k g + c g'`.
fn soft_guards(sys: &System, key: Key, red: &Reduction, lay: Layout) -> Vec<Guard> {
    let mut guards = Vec::new();
    for (k, stop) in sys.stops.iter().enumerate().filter(|(k, _)| (key.pressed | key.parting) & (1 << k) != 0) {
        let Some(Spring { stiffness, damping }) = stop.law.spring() else { continue };
        let Some(gap) = gap_row(sys, k, red, lay) else { continue };
        // g' = n·v: the gap's position part, moved to the velocities.
        let mut force = &gap * -stiffness;
        force.rows_mut(lay.r, lay.r).axpy(-damping, &gap.rows(0, lay.r), 1.0);
        if key.pressed & (1 << k) != 0 {
            guards.push(Guard::new(GuardKind::Push, k, force));
        } else {
            guards.push(Guard::new(GuardKind::Overlap, k, -gap));
            guards.push(Guard::new(GuardKind::Return, k, -force));
        }
    }
    guards
}

/// The constraint forces `λ = (G Gᵀ)⁻¹ G r(s)`, with the residual force
/// `r(s) = M N q'' + C N q' + K (N q + x_c + E p) - P sin φ - f` linear in
/// `s`: a row per constraint, over the augmented state.
fn constraint_forces(
    sys: &System,
    forces: &Forces,
    c: &Constraints,
    red: &Reduction,
    aug: &DMatrix<f64>,
    kinetic: &DVector<f64>,
    lay: Layout,
) -> DMatrix<f64> {
    let (m, r, hf, basis) = (sys.dof(), lay.r, lay.hf, &red.basis);
    let mdiag = DMatrix::from_diagonal(&sys.mass);
    let (stiffness, damping) = (forces.stiffness.as_ref(), forces.damping.as_ref());
    let mut res = &mdiag * basis * aug.rows(r, r);
    res.view_mut((0, 0), (m, r)).add_assign(&(stiffness * basis));
    res.view_mut((0, r), (m, r)).add_assign(&(damping * basis));
    if hf > 0 {
        res.view_mut((0, lay.frozen()), (m, hf)).add_assign(&(stiffness * &red.spread));
    }
    for (k, cosine, amplitudes) in sys.forcing_columns() {
        res.view_mut((0, lay.sin(k) + usize::from(cosine)), (m, 1)).add_assign(&(-amplitudes));
    }
    res.view_mut((0, lay.constant()), (m, 1)).add_assign(&(stiffness * &red.offset));
    if !sys.frictions.is_empty() {
        res.view_mut((0, lay.constant()), (m, 1)).add_assign(&(-kinetic));
    }
    if let Some(extra) = &forces.extra {
        res.view_mut((0, lay.constant()), (m, 1)).add_assign(&(-extra));
    }
    &red.ggt_inv * &c.g * res
}

/// The reactions of the held stops (release at zero) and the static margins
/// `f_s ∓ F` of the stuck contacts (breakaway at zero), from the constraint
/// forces `lambda`.
fn constraint_guards(sys: &System, c: &Constraints, lambda: &DMatrix<f64>, lay: Layout) -> Vec<Guard> {
    let mut guards = Vec::new();
    for (i, &j) in c.held.iter().enumerate() {
        guards.push(Guard::new(GuardKind::Reaction, j, lambda.row(i).transpose()));
    }
    for (i, &j) in c.frozen.iter().enumerate() {
        let force = lambda.row(c.held.len() + i).transpose();
        for sign in [-1.0, 1.0] {
            let mut row = &force * sign;
            row[lay.constant()] += sys.frictions[j].static_limit;
            guards.push(Guard::new(GuardKind::Grip, j, row));
        }
    }
    guards
}

/// The relative velocities of the slipping contacts, signed along their slip.
fn slip_guards(sys: &System, slipping: &[(usize, f64)], red: &Reduction, lay: Layout) -> Vec<Guard> {
    slipping
        .iter()
        .map(|&(i, sign)| {
            let mut row = DVector::zeros(lay.dim());
            row.rows_mut(lay.r, lay.r).copy_from(&(red.basis.transpose() * &sys.frictions[i].normal * sign));
            Guard::new(GuardKind::Slip, i, row)
        })
        .collect()
}

/// `P = ∂s/∂y` and `L`, the linear maps between full and augmented states
/// (`L` with `x_c` as the column of `1`).
fn maps(red: &Reduction, frozen: &DMatrix<f64>, m: usize, lay: Layout) -> (DMatrix<f64>, DMatrix<f64>) {
    let (r, hf) = (lay.r, lay.hf);
    let mut project = DMatrix::zeros(lay.dim(), 2 * m);
    project.view_mut((0, 0), (r, m)).copy_from(&red.basis.transpose());
    project.view_mut((r, m), (r, m)).copy_from(&red.basis.transpose());
    project.view_mut((lay.frozen(), 0), (hf, m)).copy_from(frozen);
    let mut lift = DMatrix::zeros(2 * m, lay.dim());
    lift.view_mut((0, 0), (m, r)).copy_from(&red.basis);
    lift.view_mut((m, r), (m, r)).copy_from(&red.basis);
    lift.view_mut((0, lay.frozen()), (m, hf)).copy_from(&red.spread);
    lift.view_mut((0, lay.constant()), (m, 1)).copy_from(&red.offset);
    (project, lift)
}

impl Mode {
    /// Builds the mode of `key`; `None` when its held stops' constraints are
    /// linearly dependent (no such mode).
    pub fn new(sys: &System, key: Key) -> Result<Option<Mode>, SolverError> {
        let cons = Constraints::of(sys, key);
        let Some(red) = Reduction::of(&cons, sys.dof()) else { return Ok(None) };
        let lay = Layout { r: red.free(), hf: cons.frozen.len(), h: sys.harmonic_orders() };
        let slipping = slipping(sys, key, cons.locked);
        let kinetic = kinetic_force(sys, &slipping);
        let forces = Forces::of(sys, key);
        let aug = augmented(sys, &forces, &red, &kinetic, lay)?;
        let mut guards = gap_guards(sys, key, &red, lay);
        guards.extend(soft_guards(sys, key, &red, lay));
        if cons.count() > 0 {
            let lambda = constraint_forces(sys, &forces, &cons, &red, &aug, &kinetic, lay);
            guards.extend(constraint_guards(sys, &cons, &lambda, lay));
        }
        guards.extend(slip_guards(sys, &slipping, &red, lay));
        let spectral = Spectral::shared(&aug, sys.period)?;
        let frozen = cons.g.rows(cons.held.len(), lay.hf).into_owned();
        let (project_matrix, lift_matrix) = maps(&red, &frozen, sys.dof(), lay);
        let Reduction { basis, offset, spread, .. } = red;
        Ok(Some(Mode {
            key,
            frozen,
            basis,
            offset,
            spread,
            aug,
            spectral,
            guards,
            layout: lay,
            project_matrix,
            lift_matrix,
            tangent_terms: OnceLock::new(),
            saltation: OnceLock::new(),
        }))
    }

    /// Augmented state of full state `y = [x; v]` at forcing phase `phase = ω t + τ`.
    /// Components normal to held stops and relative velocities of stuck contacts
    /// are dropped (projection onto the constraints).
    pub fn project(&self, y: &DVector<f64>, phase: f64) -> DVector<f64> {
        let mut s = DVector::zeros(0);
        self.project_into(y, phase, &mut s);
        s
    }

    /// [`Mode::project`] into `s` (resized to the mode's dimension; no
    /// allocation once sized in a mode without constraints).
    pub fn project_into(&self, y: &DVector<f64>, phase: f64, s: &mut DVector<f64>) {
        let m = self.basis.nrows();
        let (lay, r, hf) = (self.layout, self.layout.r, self.layout.hf);
        let dim = lay.dim();
        if s.len() != dim {
            *s = DVector::zeros(dim);
        }
        for k in 1..=lay.h {
            // `1.0 * φ` is φ exactly: the first harmonic is `sin_cos(phase)`.
            (s[lay.sin(k)], s[lay.cos(k)]) = crate::spectral::sin_cos(k as f64 * phase);
        }
        s[lay.constant()] = 1.0;
        if !self.key.constrained() {
            // Free of constraints the reduced coordinates are the full state.
            s.rows_mut(0, 2 * m).copy_from(&y.rows(0, 2 * m));
            return;
        }
        let x = y.rows(0, m) - &self.offset;
        s.rows_mut(0, r).copy_from(&(self.basis.transpose() * x));
        s.rows_mut(r, r).copy_from(&(self.basis.transpose() * y.rows(m, m)));
        if hf > 0 {
            // The frozen displacements: the stuck contacts' relative coordinates.
            s.rows_mut(2 * r, hf).copy_from(&(&self.frozen * y.rows(0, m)));
        }
    }

    /// The indices of `sin kφ` and `cos kφ` in the augmented state for each
    /// harmonic k = 1 … H of the forcing.
    pub fn harmonic_indices(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (1..=self.layout.h).map(|k| (self.layout.sin(k), self.layout.cos(k)))
    }

    /// The linear map `y ↦ s` of [`Mode::project`] without its constant rows
    /// (`sin φ`, `cos φ`, `1` do not depend on `y`): `∂s/∂y`.
    pub fn project_matrix(&self) -> &DMatrix<f64> {
        &self.project_matrix
    }

    /// The linear map `s ↦ y` of [`Mode::lift_into`] (with `x_c` as the column of `1`).
    pub fn lift_matrix(&self) -> &DMatrix<f64> {
        &self.lift_matrix
    }

    /// The gradient `∇h = Pᵀ ℓ` of guard `g` in full coordinates (`Pᵀ * ℓ`,
    /// the product of nalgebra's operators, built once per mode).
    pub fn guard_gradient(&self, g: usize) -> &DVector<f64> {
        &self.saltation_parts().gradients[g]
    }

    /// `L P` (`L * P`): a full state projected onto the mode's constraints,
    /// in full coordinates (built once per mode).
    pub fn constraint_projection(&self) -> &DMatrix<f64> {
        &self.saltation_parts().projection
    }

    fn saltation_parts(&self) -> &SaltationParts {
        self.saltation.get_or_init(|| {
            let transposed = self.project_matrix().transpose();
            SaltationParts {
                gradients: self.guards.iter().map(|g| &transposed * &g.row).collect(),
                projection: self.lift_matrix() * self.project_matrix(),
            }
        })
    }

    /// State-transition matrix `∂y(h)/∂y(0) = L e^{Â h} P` of a flow segment of
    /// duration `h` in full coordinates.
    pub fn transition(&self, h: f64) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(0, 0);
        self.transition_into(h, &mut Vec::new(), &mut out);
        out
    }

    /// [`Mode::transition`] into `out`, the flow's factors into `f` (both
    /// resized as needed: no allocation once sized for the mode).
    pub fn transition_into(&self, h: f64, f: &mut Vec<C64>, out: &mut DMatrix<f64>) {
        f.clear();
        f.resize(self.spectral.terms().len(), C64::new(0.0, 0.0));
        self.spectral.factors(h, f);
        self.transition_of(f, out);
    }

    /// [`Mode::transition`] into `out` from the flow's factors `f` at its
    /// duration ([`crate::spectral::Spectral::factors`]; those an exact
    /// advance ended with are the same, bit for bit).
    pub fn transition_of(&self, f: &[C64], out: &mut DMatrix<f64>) {
        let terms = self.tangent_terms.get_or_init(|| {
            let (l, p) =
                (self.lift_matrix().map(|v| C64::new(v, 0.0)), self.project_matrix().map(|v| C64::new(v, 0.0)));
            self.spectral.coefficients().iter().map(|c| &l * c * &p).collect()
        });
        let n = self.basis.nrows() * 2;
        if out.shape() == (n, n) {
            out.fill(0.0);
        } else {
            *out = DMatrix::zeros(n, n);
        }
        for (t, ft) in terms.iter().zip(f.iter()) {
            out.zip_apply(t, |o, z| *o += ft.re * z.re - ft.im * z.im);
        }
    }

    /// Full state `[x; v]` of an augmented state, into `y` (of length `2m`).
    pub fn lift_into(&self, s: &DVector<f64>, y: &mut DVector<f64>) {
        let m = self.basis.nrows();
        let r = self.basis.ncols();
        let hf = self.frozen.nrows();
        if !self.key.constrained() {
            y.copy_from(&s.rows(0, 2 * m));
            return;
        }
        let mut x = &self.basis * s.rows(0, r) + &self.offset;
        if hf > 0 {
            x += &self.spread * s.rows(2 * r, hf);
        }
        y.rows_mut(0, m).copy_from(&x);
        y.rows_mut(m, m).copy_from(&(&self.basis * s.rows(r, r)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::system;

    fn kinds(mode: &Mode) -> Vec<(GuardKind, Target)> {
        mode.guards.iter().map(|g| (g.kind, g.target)).collect()
    }

    /// `s = [x; v; sin φ; cos φ; 1]` of a free single mass: the matrix of
    /// `x'' + 2ζx' + x = sin φ` and `φ' = ω`, written out by hand.
    #[test]
    fn the_free_mode_is_the_equation_of_motion() {
        let (zeta, omega) = (0.1, 2.5);
        let sys = system("single-stop.toml", &[("zeta", zeta), ("omega", omega), ("sigma", 0.3)]);
        let mode = Mode::new(&sys, Key::FREE).unwrap().unwrap();
        #[rustfmt::skip]
        let expected = DMatrix::from_row_slice(5, 5, &[
            0.0, 1.0, 0.0, 0.0, 0.0,
            -1.0, -2.0 * zeta, 1.0, 0.0, 0.0,
            0.0, 0.0, 0.0, omega, 0.0,
            0.0, 0.0, -omega, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0, 0.0,
        ]);
        assert!((&mode.aug - expected).amax() < 1e-15, "{}", mode.aug);
        // One guard: the gap σ - x of the stop above the mass.
        assert_eq!(kinds(&mode), vec![(GuardKind::Gap, Target::Stop(0))]);
        assert_eq!(mode.guards[0].row.as_slice(), &[-1.0, 0.0, 0.0, 0.0, 0.3]);
        assert_eq!(mode.guards[0].entries, vec![(0, -1.0), (4, 0.3)]);
    }

    /// M1 held on A1 (`x1 = -δ`, at rest): its reaction is the force the stop
    /// must supply, `k1 x1 + c1 x1' - P1 sin φ` (M1's own equation, M2 free),
    /// and the mode keeps M2's motion free.
    #[test]
    fn a_held_stop_has_the_reaction_of_newtons_law() {
        let (zeta, delta, phase) = (0.1, 0.6, 0.7);
        let sys = system("multi-stop.toml", &[("zeta", zeta), ("delta", delta)]);
        let mode = Mode::new(&sys, Key { held: 1, ..Key::FREE }).unwrap().unwrap();
        assert_eq!(
            kinds(&mode),
            vec![
                (GuardKind::Gap, Target::Stop(1)),
                (GuardKind::Gap, Target::Stop(2)),
                (GuardKind::Reaction, Target::Stop(0))
            ]
        );
        let y = DVector::from_vec(vec![-delta, 0.2, 0.0, -0.3]);
        let s = mode.project(&y, phase);
        let mut back = DVector::zeros(4);
        mode.lift_into(&s, &mut back);
        assert!((&back - &y).amax() < 1e-15, "an admissible state is its own projection: {back}");
        let reaction = mode.guards[2].row.dot(&s);
        let expected = 1.0 * -delta + 2.0 * zeta * 0.0 - 1.0 * phase.sin();
        assert!((reaction - expected).abs() < 1e-14, "{reaction} vs {expected}");
        // Projection drops what violates the constraint: M1's velocity and offset.
        mode.lift_into(&mode.project(&DVector::from_vec(vec![-delta + 0.1, 0.2, 0.5, -0.3]), phase), &mut back);
        assert!((&back - &DVector::from_vec(vec![-delta, 0.2, 0.0, -0.3])).amax() < 1e-15, "{back}");
    }

    /// Dry friction (M1 between M2's walls at ±b): guards come in the
    /// documented order, a stuck contact has two grips, a contact that a held
    /// stop fixes is locked (no grip, no slip), and holding both walls at once
    /// is no mode.
    #[test]
    fn guards_follow_the_documented_order_and_locked_contacts_have_none() {
        let sys = system("dry-friction.toml", &[]);
        let free = Mode::new(&sys, Key::FREE).unwrap().unwrap();
        assert_eq!(
            kinds(&free),
            vec![
                (GuardKind::Gap, Target::Stop(0)),
                (GuardKind::Gap, Target::Stop(1)),
                (GuardKind::Slip, Target::Contact(0))
            ]
        );
        let stuck = Mode::new(&sys, Key { stuck: 1, ..Key::FREE }).unwrap().unwrap();
        // Stuck, M1 moves with M2: the walls' gaps are constant and have no guard.
        assert_eq!(kinds(&stuck), vec![(GuardKind::Grip, Target::Contact(0)), (GuardKind::Grip, Target::Contact(0))]);
        // The two grips are f_s - F and f_s + F: they sum to 2 f_s.
        let s = stuck.project(&DVector::from_vec(vec![0.01, 0.0, 0.3, 0.3]), 0.4);
        let margins: f64 = stuck.guards.iter().map(|g| g.row.dot(&s)).sum();
        let force = stuck.guards[1].row.dot(&s) - sys.frictions[0].static_limit;
        assert!((margins - 2.0 * sys.frictions[0].static_limit).abs() <= 1e-14 * (1.0 + force.abs()));
        let held = Mode::new(&sys, Key { held: 1, stuck: 1, ..Key::FREE }).unwrap().unwrap();
        // Held on the right wall the left gap is 2b, constant: a reaction only.
        assert_eq!(kinds(&held), vec![(GuardKind::Reaction, Target::Stop(0))]);
        assert!(Mode::new(&sys, Key { held: 3, ..Key::FREE }).unwrap().is_none());
    }

    /// The transition matrix `L e^{Âh} P` is the derivative of the flow: it
    /// matches central finite differences of lift ∘ flow ∘ project.
    #[test]
    fn the_transition_matrix_is_the_derivative_of_the_flow() {
        let sys = system("multi-stop.toml", &[("omega", 0.8)]);
        for key in [Key::FREE, Key { held: 1, ..Key::FREE }] {
            let mode = Mode::new(&sys, key).unwrap().unwrap();
            let (h, phase) = (0.9, 0.2);
            let y = DVector::from_vec(vec![-0.6, 0.1, 0.0, 0.2]);
            let flow = |y: &DVector<f64>| {
                let s = mode.project(y, phase);
                let mut f = vec![C64::new(0.0, 0.0); mode.spectral.terms().len()];
                mode.spectral.factors(h, &mut f);
                let end = mode.spectral.modal(&s).state(&f);
                let mut out = DVector::zeros(4);
                mode.lift_into(&end, &mut out);
                out
            };
            let t = mode.transition(h);
            for j in 0..4 {
                let e = DVector::from_fn(4, |i, _| if i == j { 1e-6 } else { 0.0 });
                let column = (flow(&(&y + &e)) - flow(&(&y - &e))) / 2e-6;
                assert!((column - t.column(j)).amax() < 1e-7, "{key:?} column {j}");
            }
        }
    }
}
