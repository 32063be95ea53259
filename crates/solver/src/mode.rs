//! Modes: the linear system with a set of stops held (sticking) and each
//! friction contact slipping one way or stuck.
//!
//! Held stops and stuck friction contacts are linear constraints `G x = w`:
//! a held stop's row `n_j` with `w_j = -c_j`, a stuck contact's row
//! `n = e_a - e_b` with `w` the frozen relative displacement `p`. Positions are
//! `x = N q + x_c + E p` with `N` an orthonormal basis of `ker G`, `x_c` the
//! least-norm solution of the stop constraints and `E` that of the frozen
//! displacements. The reduced equations
//! `Nᵀ M N q'' + Nᵀ C N q' + Nᵀ K (N q + x_c + E p) = Nᵀ (P sin φ + f)`, with `f`
//! the constant kinetic friction forces `-f_k sgn(x_a' - x_b') n` of slipping
//! contacts, become the augmented linear system `s' = Â s` with
//! `s = [q; q'; p; sin φ; cos φ; 1]`, `φ = ω t + τ` (`p` is constant).
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

use crate::error::SolverError;
use crate::flow::spectral::{nonzero_entries, Spectral};
use crate::system::System;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use num_complex::Complex64 as C64;
use std::ops::AddAssign;
use std::sync::OnceLock;

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
}

impl GuardKind {
    /// Whether the guard is a length (a gap), located to the contact tolerance;
    /// other guards are forces or velocities, located in time at rounding level.
    pub fn is_gap(self) -> bool {
        self == GuardKind::Gap
    }
}

/// One event function of a mode, `ℓ·s >= 0`.
#[derive(Debug, Clone)]
pub struct Guard {
    /// What it watches.
    pub kind: GuardKind,
    /// Stop index (gap, reaction) or friction contact index (grip, slip).
    pub stop: usize,
    /// Row `ℓ` over the augmented state.
    pub row: DVector<f64>,
    /// `|ℓ|` entrywise (for the guard's magnitude `|ℓ|·|s|`).
    pub row_abs: DVector<f64>,
    /// The nonzero entries of `ℓ` (index, value), ascending: a guard reads a few
    /// coordinates of the augmented state.
    pub entries: Vec<(usize, f64)>,
}

impl Guard {
    fn new(kind: GuardKind, stop: usize, row: DVector<f64>) -> Guard {
        let row_abs = row.abs();
        let entries = nonzero_entries(row.as_slice());
        Guard { kind, stop, row, row_abs, entries }
    }
}

/// Which linear system holds: the held stops and the state of each friction contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Key {
    /// Bit k: stop k holds its mass.
    pub held: u32,
    /// Bit i: friction contact i is stuck (its masses move together).
    pub stuck: u32,
    /// Bit i: friction contact i slips with `x_a' - x_b' < 0` (when not stuck).
    pub negative: u32,
}

impl Key {
    /// Free flight, every contact slipping forwards: the key of a scene without
    /// held stops or friction.
    pub const FREE: Key = Key { held: 0, stuck: 0, negative: 0 };

    /// Whether the mode has constraints (held stops or stuck contacts), so that
    /// a state must be projected onto them.
    pub fn constrained(self) -> bool {
        self.held != 0 || self.stuck != 0
    }
}

/// A linear mode: constraints, reduced coordinates, augmented matrix, guards.
#[derive(Debug, Clone)]
pub struct Mode {
    /// The mode's key.
    pub key: Key,
    /// Friction contacts locked by held stops (bit mask).
    pub locked: u32,
    /// Rows `n` of the stuck (not locked) friction contacts, in the order of `p`.
    frozen: DMatrix<f64>,
    basis: DMatrix<f64>,
    offset: DVector<f64>,
    /// `E`: positions per unit frozen displacement.
    spread: DMatrix<f64>,
    /// Augmented matrix Â.
    pub aug: DMatrix<f64>,
    /// Spectral decomposition of Â over one forcing period.
    pub spectral: Spectral,
    /// Event guards.
    pub guards: Vec<Guard>,
    /// `P = ∂s/∂y`, see [`Mode::project_matrix`].
    project_matrix: DMatrix<f64>,
    /// `L`, see [`Mode::lift_matrix`].
    lift_matrix: DMatrix<f64>,
    /// Per term of the spectral expansion, `L · V N^j W · P` (built on first use
    /// by tangent tracking).
    tangent_terms: OnceLock<Vec<DMatrix<C64>>>,
}

/// Whether `row` lies in the span of the rows of `g` (to rounding).
fn in_span(g: &DMatrix<f64>, row: &DVector<f64>) -> bool {
    if g.nrows() == 0 {
        return false;
    }
    let Some(inv) = (g * g.transpose()).try_inverse() else { return false };
    let residual = row - g.transpose() * (inv * (g * row));
    residual.norm() <= 1e-9 * row.norm()
}

impl Mode {
    /// Builds the mode of `key`; `None` when its held stops' constraints are
    /// linearly dependent (no such mode).
    pub fn new(sys: &System, key: Key) -> Result<Option<Mode>, SolverError> {
        let m = sys.dof();
        let held_list: Vec<usize> = (0..sys.stops.len()).filter(|j| key.held & (1 << j) != 0).collect();
        let hs = held_list.len();
        let stop_rows = DMatrix::from_fn(hs, m, |r, c| sys.stops[held_list[r]].normal[c]);
        let locked = (0..sys.frictions.len())
            .filter(|&i| in_span(&stop_rows, &sys.frictions[i].normal))
            .fold(0u32, |acc, i| acc | (1 << i));
        let frozen: Vec<usize> = (0..sys.frictions.len()).filter(|i| key.stuck & !locked & (1 << i) != 0).collect();
        let hf = frozen.len();
        let h = hs + hf;
        let g = DMatrix::from_fn(h, m, |r, c| {
            if r < hs {
                sys.stops[held_list[r]].normal[c]
            } else {
                sys.frictions[frozen[r - hs]].normal[c]
            }
        });
        let c = DVector::from_fn(hs, |r, _| sys.stops[held_list[r]].offset);
        let (basis, offset, spread, ggt_inv) = if h == 0 {
            (DMatrix::identity(m, m), DVector::zeros(m), DMatrix::zeros(m, 0), DMatrix::zeros(0, 0))
        } else {
            let ggt = &g * g.transpose();
            let Some(ggt_inv) = ggt.clone().try_inverse() else {
                return Ok(None);
            };
            let cond = ggt.norm() * ggt_inv.norm();
            if cond.is_nan() || cond >= 1e10 {
                return Ok(None);
            }
            let proj = DMatrix::identity(m, m) - g.transpose() * &ggt_inv * &g;
            let eig = SymmetricEigen::new(proj);
            let mut idx: Vec<usize> = (0..m).filter(|&i| eig.eigenvalues[i] > 0.5).collect();
            idx.sort_unstable();
            let cols: Vec<DVector<f64>> = idx.iter().map(|&i| eig.eigenvectors.column(i).into_owned()).collect();
            let basis = if cols.is_empty() { DMatrix::zeros(m, 0) } else { DMatrix::from_columns(&cols) };
            if basis.ncols() != m - h {
                return Ok(None);
            }
            let pinv = g.transpose() * &ggt_inv;
            let offset = -(pinv.columns(0, hs) * &c);
            let spread = pinv.columns(hs, hf).into_owned();
            (basis, offset, spread, ggt_inv)
        };
        let r = basis.ncols();
        let dim = 2 * r + hf + 3;
        let (sin, cos, one) = (dim - 3, dim - 2, dim - 1);
        let mdiag = DMatrix::from_diagonal(&sys.mass);
        let mr = basis.transpose() * &mdiag * &basis;
        let mr_inv = if r == 0 {
            DMatrix::zeros(0, 0)
        } else {
            mr.cholesky()
                .ok_or_else(|| SolverError::IllConditioned { message: "reduced mass matrix is not positive".into() })?
                .inverse()
        };
        // Slipping contacts with the sign of their relative velocity, and their
        // kinetic friction: a constant force.
        let slipping: Vec<(usize, f64)> = (0..sys.frictions.len())
            .filter(|i| (key.stuck | locked) & (1 << i) == 0)
            .map(|i| (i, if key.negative & (1 << i) != 0 { -1.0 } else { 1.0 }))
            .collect();
        let mut kinetic = DVector::zeros(m);
        for &(i, sign) in &slipping {
            let f = &sys.frictions[i];
            kinetic -= &f.normal * (sign * f.kinetic);
        }
        let kr = basis.transpose() * &sys.stiffness * &basis;
        let cr = basis.transpose() * &sys.damping * &basis;
        let pr = basis.transpose() * &sys.forcing;
        let mut fr = basis.transpose() * -(&sys.stiffness * &offset);
        if !sys.frictions.is_empty() {
            fr += basis.transpose() * &kinetic;
        }
        let mut aug = DMatrix::zeros(dim, dim);
        for i in 0..r {
            aug[(i, r + i)] = 1.0;
        }
        aug.view_mut((r, 0), (r, r)).copy_from(&(-&mr_inv * &kr));
        aug.view_mut((r, r), (r, r)).copy_from(&(-&mr_inv * &cr));
        if hf > 0 {
            aug.view_mut((r, 2 * r), (r, hf)).copy_from(&(-&mr_inv * basis.transpose() * &sys.stiffness * &spread));
        }
        aug.view_mut((r, sin), (r, 1)).copy_from(&(&mr_inv * &pr));
        aug.view_mut((r, one), (r, 1)).copy_from(&(&mr_inv * &fr));
        aug[(sin, cos)] = sys.omega;
        aug[(cos, sin)] = -sys.omega;

        let mut guards = Vec::new();
        for (k, stop) in sys.stops.iter().enumerate() {
            if key.held & (1 << k) == 0 {
                // A gap along constrained directions only (a pair stop while its
                // masses stick together) is constant: it has no events.
                let along = basis.transpose() * &stop.normal;
                if along.amax() < 1e-12 {
                    continue;
                }
                let mut row = DVector::zeros(dim);
                row.rows_mut(0, r).copy_from(&along);
                if hf > 0 {
                    row.rows_mut(2 * r, hf).copy_from(&(spread.transpose() * &stop.normal));
                }
                row[one] = stop.normal.dot(&offset) + stop.offset;
                guards.push(Guard::new(GuardKind::Gap, k, row));
            }
        }
        if h > 0 {
            // Residual force r(s) = M N q'' + C N q' + K (N q + x_c + E p) - P sin φ - f, linear in s.
            let mut res = &mdiag * &basis * aug.rows(r, r);
            res.view_mut((0, 0), (m, r)).add_assign(&(&sys.stiffness * &basis));
            res.view_mut((0, r), (m, r)).add_assign(&(&sys.damping * &basis));
            if hf > 0 {
                res.view_mut((0, 2 * r), (m, hf)).add_assign(&(&sys.stiffness * &spread));
            }
            res.view_mut((0, sin), (m, 1)).add_assign(&(-&sys.forcing));
            res.view_mut((0, one), (m, 1)).add_assign(&(&sys.stiffness * &offset));
            if !sys.frictions.is_empty() {
                res.view_mut((0, one), (m, 1)).add_assign(&(-&kinetic));
            }
            let lambda = &ggt_inv * &g * res;
            for (i, &j) in held_list.iter().enumerate() {
                guards.push(Guard::new(GuardKind::Reaction, j, lambda.row(i).transpose()));
            }
            for (i, &j) in frozen.iter().enumerate() {
                let force = lambda.row(hs + i).transpose();
                for sign in [-1.0, 1.0] {
                    let mut row = &force * sign;
                    row[one] += sys.frictions[j].static_limit;
                    guards.push(Guard::new(GuardKind::Grip, j, row));
                }
            }
        }
        for &(i, sign) in &slipping {
            let mut row = DVector::zeros(dim);
            row.rows_mut(r, r).copy_from(&(basis.transpose() * &sys.frictions[i].normal * sign));
            guards.push(Guard::new(GuardKind::Slip, i, row));
        }
        let spectral = Spectral::new(&aug, sys.period)?;
        let frozen = g.rows(hs, hf).into_owned();
        // The linear maps between full and augmented states.
        let mut project_matrix = DMatrix::zeros(dim, 2 * m);
        project_matrix.view_mut((0, 0), (r, m)).copy_from(&basis.transpose());
        project_matrix.view_mut((r, m), (r, m)).copy_from(&basis.transpose());
        project_matrix.view_mut((2 * r, 0), (hf, m)).copy_from(&frozen);
        let mut lift_matrix = DMatrix::zeros(2 * m, dim);
        lift_matrix.view_mut((0, 0), (m, r)).copy_from(&basis);
        lift_matrix.view_mut((m, r), (m, r)).copy_from(&basis);
        lift_matrix.view_mut((0, 2 * r), (m, hf)).copy_from(&spread);
        lift_matrix.view_mut((0, one), (m, 1)).copy_from(&offset);
        Ok(Some(Mode {
            key,
            locked,
            frozen,
            basis,
            offset,
            spread,
            aug,
            spectral,
            guards,
            project_matrix,
            lift_matrix,
            tangent_terms: OnceLock::new(),
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
        let r = self.basis.ncols();
        let hf = self.frozen.nrows();
        let dim = 2 * r + hf + 3;
        if s.len() != dim {
            *s = DVector::zeros(dim);
        }
        let (sn, cs) = phase.sin_cos();
        s[dim - 3] = sn;
        s[dim - 2] = cs;
        s[dim - 1] = 1.0;
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

    /// The linear map `y ↦ s` of [`Mode::project`] without its constant rows
    /// (`sin φ`, `cos φ`, `1` do not depend on `y`): `∂s/∂y`.
    pub fn project_matrix(&self) -> &DMatrix<f64> {
        &self.project_matrix
    }

    /// The linear map `s ↦ y` of [`Mode::lift`] (with `x_c` as the column of `1`).
    pub fn lift_matrix(&self) -> &DMatrix<f64> {
        &self.lift_matrix
    }

    /// State-transition matrix `∂y(h)/∂y(0) = L e^{Â h} P` of a flow segment of
    /// duration `h` in full coordinates.
    pub fn transition(&self, h: f64) -> DMatrix<f64> {
        let terms = self.tangent_terms.get_or_init(|| {
            let (l, p) =
                (self.lift_matrix().map(|v| C64::new(v, 0.0)), self.project_matrix().map(|v| C64::new(v, 0.0)));
            self.spectral.coefficients().iter().map(|c| &l * c * &p).collect()
        });
        let mut f = vec![C64::new(0.0, 0.0); terms.len()];
        self.spectral.factors(h, &mut f);
        let n = self.basis.nrows() * 2;
        let mut out = DMatrix::zeros(n, n);
        for (t, ft) in terms.iter().zip(&f) {
            out.zip_apply(t, |o, z| *o += ft.re * z.re - ft.im * z.im);
        }
        out
    }

    /// Full state `[x; v]` of an augmented state.
    pub fn lift(&self, s: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(2 * self.basis.nrows());
        self.lift_into(s, &mut y);
        y
    }

    /// [`Mode::lift`] into `y` (of length `2m`; no allocation in a mode without
    /// constraints).
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
