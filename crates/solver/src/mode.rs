//! Modes: the linear system with a set of stops held (sticking).
//!
//! With held stops `G x = -c` (rows `n_j`, offsets `c_j`), positions are
//! `x = N q + x_c` with `N` an orthonormal basis of `ker G` and `x_c` the
//! least-norm solution. The reduced equations
//! `Nᵀ M N q'' + Nᵀ C N q' + Nᵀ K N q = Nᵀ (P sin φ - K x_c)` become the augmented
//! linear system `s' = Â s` with `s = [q; q'; sin φ; cos φ; 1]`, `φ = ω t + τ`.
//!
//! The reactions of held stops, `λ = (G Gᵀ)^{-1} G (M x'' + C x' + K x - P sin φ)`,
//! are linear functionals of `s`: a held stop is released when its reaction
//! crosses zero (the net force pulls the mass off the stop). Every event guard
//! of a mode (the gaps of free stops, the reactions of held ones) is a row `ℓ`
//! with guard value `ℓ·s`.

use crate::error::SolverError;
use crate::flow::spectral::Spectral;
use crate::system::System;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::ops::AddAssign;

/// What a guard watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuardKind {
    /// Gap of a free stop: contact when it reaches zero.
    Gap,
    /// Reaction of a held stop: release when it reaches zero.
    Reaction,
}

/// One event function of a mode, `ℓ·s >= 0`.
#[derive(Debug, Clone)]
pub struct Guard {
    /// Gap or reaction.
    pub kind: GuardKind,
    /// Stop index.
    pub stop: usize,
    /// Row `ℓ` over the augmented state.
    pub row: DVector<f64>,
}

/// A linear mode: held stops, reduced coordinates, augmented matrix, guards.
#[derive(Debug, Clone)]
pub struct Mode {
    /// Bit mask of held stops.
    pub held: u32,
    basis: DMatrix<f64>,
    offset: DVector<f64>,
    /// Augmented matrix Â.
    pub aug: DMatrix<f64>,
    /// Spectral decomposition of Â over one forcing period.
    pub spectral: Spectral,
    /// Event guards.
    pub guards: Vec<Guard>,
}

impl Mode {
    /// Builds the mode with stops `held` held; `None` when their constraints are
    /// linearly dependent (no such mode).
    pub fn new(sys: &System, held: u32) -> Result<Option<Mode>, SolverError> {
        let m = sys.dof();
        let held_list: Vec<usize> = (0..sys.stops.len()).filter(|j| held & (1 << j) != 0).collect();
        let h = held_list.len();
        let g = DMatrix::from_fn(h, m, |r, c| sys.stops[held_list[r]].normal[c]);
        let c = DVector::from_fn(h, |r, _| sys.stops[held_list[r]].offset);
        let (basis, offset, ggt_inv) = if h == 0 {
            (DMatrix::identity(m, m), DVector::zeros(m), DMatrix::zeros(0, 0))
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
            let offset = -(g.transpose() * &ggt_inv * &c);
            (basis, offset, ggt_inv)
        };
        let r = basis.ncols();
        let dim = 2 * r + 3;
        let (sin, cos, one) = (2 * r, 2 * r + 1, 2 * r + 2);
        let mdiag = DMatrix::from_diagonal(&sys.mass);
        let mr = basis.transpose() * &mdiag * &basis;
        let mr_inv = if r == 0 {
            DMatrix::zeros(0, 0)
        } else {
            mr.cholesky()
                .ok_or_else(|| SolverError::IllConditioned { message: "reduced mass matrix is not positive".into() })?
                .inverse()
        };
        let kr = basis.transpose() * &sys.stiffness * &basis;
        let cr = basis.transpose() * &sys.damping * &basis;
        let pr = basis.transpose() * &sys.forcing;
        let fr = basis.transpose() * -(&sys.stiffness * &offset);
        let mut aug = DMatrix::zeros(dim, dim);
        for i in 0..r {
            aug[(i, r + i)] = 1.0;
        }
        aug.view_mut((r, 0), (r, r)).copy_from(&(-&mr_inv * &kr));
        aug.view_mut((r, r), (r, r)).copy_from(&(-&mr_inv * &cr));
        aug.view_mut((r, sin), (r, 1)).copy_from(&(&mr_inv * &pr));
        aug.view_mut((r, one), (r, 1)).copy_from(&(&mr_inv * &fr));
        aug[(sin, cos)] = sys.omega;
        aug[(cos, sin)] = -sys.omega;

        let mut guards = Vec::new();
        for (k, stop) in sys.stops.iter().enumerate() {
            if held & (1 << k) == 0 {
                let mut row = DVector::zeros(dim);
                row.rows_mut(0, r).copy_from(&(basis.transpose() * &stop.normal));
                row[one] = stop.normal.dot(&offset) + stop.offset;
                guards.push(Guard { kind: GuardKind::Gap, stop: k, row });
            }
        }
        if h > 0 {
            // Residual force r(s) = M N q'' + C N q' + K (N q + x_c) - P sin φ, linear in s.
            let mut res = &mdiag * &basis * aug.rows(r, r);
            res.view_mut((0, 0), (m, r)).add_assign(&(&sys.stiffness * &basis));
            res.view_mut((0, r), (m, r)).add_assign(&(&sys.damping * &basis));
            res.view_mut((0, sin), (m, 1)).add_assign(&(-&sys.forcing));
            res.view_mut((0, one), (m, 1)).add_assign(&(&sys.stiffness * &offset));
            let lambda = &ggt_inv * &g * res;
            for (i, &j) in held_list.iter().enumerate() {
                guards.push(Guard { kind: GuardKind::Reaction, stop: j, row: lambda.row(i).transpose() });
            }
        }
        let spectral = Spectral::new(&aug, sys.period)?;
        Ok(Some(Mode { held, basis, offset, aug, spectral, guards }))
    }

    /// Augmented state of full state `y = [x; v]` at forcing phase `phase = ω t + τ`.
    /// Components normal to held stops are dropped (projection onto the constraint).
    pub fn project(&self, y: &DVector<f64>, phase: f64) -> DVector<f64> {
        let m = self.basis.nrows();
        let r = self.basis.ncols();
        let mut s = DVector::zeros(2 * r + 3);
        let x = y.rows(0, m) - &self.offset;
        s.rows_mut(0, r).copy_from(&(self.basis.transpose() * x));
        s.rows_mut(r, r).copy_from(&(self.basis.transpose() * y.rows(m, m)));
        let (sn, cs) = phase.sin_cos();
        s[2 * r] = sn;
        s[2 * r + 1] = cs;
        s[2 * r + 2] = 1.0;
        s
    }

    /// Full state `[x; v]` of an augmented state.
    pub fn lift(&self, s: &DVector<f64>) -> DVector<f64> {
        let m = self.basis.nrows();
        let r = self.basis.ncols();
        if self.held == 0 {
            return s.rows(0, 2 * m).into_owned();
        }
        let mut y = DVector::zeros(2 * m);
        y.rows_mut(0, m).copy_from(&(&self.basis * s.rows(0, r) + &self.offset));
        y.rows_mut(m, m).copy_from(&(&self.basis * s.rows(r, r)));
        y
    }
}
