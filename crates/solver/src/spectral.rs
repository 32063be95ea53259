//! Exact solution of a linear autonomous system `s' = Â s` by a clustered
//! spectral decomposition.
//!
//! The augmented state of a mode is `s = [q; q'; sin φ; cos φ; 1]` with
//! `φ = ω t + τ`, so harmonic and constant forcing are part of `Â` and the flow
//! is `s(u) = e^{Â u} s(0)`. Eigenvalues closer than a tolerance are grouped
//! into clusters; on each cluster's invariant subspace (basis `V_c`, dual rows
//! `W_c`) the matrix acts as `μ_c I + N_c`, hence
//!
//! ```text
//! e^{Â u} = Σ_c V_c e^{μ_c u} Σ_j (u^j / j!) N_c^j W_c .
//! ```
//!
//! For a defective eigenvalue (a free mass: `x'' = 0`; undamped resonance) `N_c`
//! is nilpotent and the sum is finite, so rigid-body drift and secular growth are
//! exact polynomials, never perturbed eigenvalues. For nearly equal but distinct
//! eigenvalues `N_c` is tiny and the series is summed until it is below rounding
//! over the horizon. Conjugate clusters are folded: a cluster in the upper half
//! plane contributes `2 Re(...)`, a real cluster `Re(...)`.
//!
//! A cluster whose `N_c` is tiny (the slow forcing pair `±iω` merged with the
//! constant state when ω is far below the natural frequencies) is summed in its
//! own time scale `ν_c`, a power of two near `‖N_c‖`:
//! `Σ_j ((ν u)^j / j!) (N_c/ν)^j`. Over a period of `2π/ω` the plain terms
//! `u^j / j!` and `N_c^j` overflow and underflow f64 (ω = 1e-7: `u^40 ≈ 1e312`),
//! and the scaled ones stay of order one. Scaling by a power of two is exact,
//! so every product is the plain one bit for bit wherever the plain one was
//! representable.

use crate::error::SolverError;
use nalgebra::{ComplexField, DMatrix, DVector, Schur};
use num_complex::Complex64 as C64;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

/// Decompositions kept per thread before the memo of [`Spectral::shared`] is
/// emptied (about 1.5 KB each for a two-mass scene: at most some 25 MB a thread).
const MEMO_ENTRIES: usize = 16_384;

thread_local! {
    /// [`Spectral::new`]'s results on this thread, by the bits of its inputs.
    static MEMO: RefCell<HashMap<Vec<u64>, Arc<Spectral>>> = RefCell::new(HashMap::new());
}

/// `‖N_c‖` below which a cluster is summed in its own time scale ν.
const TINY_N: f64 = 1.0 / 256.0;

/// One term `weight · e^{μ u} (ν u)^j / j!` of the expansion.
#[derive(Debug, Clone, Copy)]
pub struct Term {
    /// Cluster eigenvalue μ.
    pub lambda: C64,
    /// Power j of `(ν u)^j / j!`.
    pub power: usize,
    /// The cluster's time scale ν (a power of two; 1 unless `N_c` is tiny).
    scale: f64,
    /// 1 for a real cluster, 2 for an upper-half-plane cluster (conjugate folded).
    pub weight: f64,
    /// 1 / j!.
    inv_factorial: f64,
    /// The cluster's highest power: the next term, if any, starts another cluster.
    last: bool,
    /// The term is exactly constant in time (μ = 0, j = 0): the constant state,
    /// a rigid offset.
    pub constant: bool,
}

impl Term {
    /// Where the term is `w ν u` (eigenvalue 0, first power: a rigid mode's
    /// drift), the factor `w ν` that turns a coefficient β into the rate
    /// `Re(w ν β)` per unit time at which it moves a functional; `None` for
    /// any other term.
    pub fn drift(&self) -> Option<f64> {
        (self.power == 1 && self.lambda == C64::new(0.0, 0.0)).then_some(self.weight * self.scale)
    }

    /// The term's polynomial factor `(ν u)^j / j!` at time `u` (1 for
    /// `j = 0`).
    fn poly(&self, u: f64) -> f64 {
        if self.power == 0 {
            1.0
        } else {
            (self.scale * u).powi(self.power as i32) * self.inv_factorial
        }
    }
}

#[derive(Debug, Clone)]
struct Cluster {
    v: DMatrix<C64>,
    /// `W_cᵀ`: column r is the dual row r, contiguous for [`Spectral::modal_into`].
    wt: DMatrix<C64>,
    n: DMatrix<C64>,
    powers: usize,
}

/// Clustered spectral decomposition of an augmented mode matrix.
#[derive(Debug, Clone)]
pub struct Spectral {
    dim: usize,
    clusters: Vec<Cluster>,
    terms: Vec<Term>,
    /// Largest eigenvalue modulus (angular rate of the fastest mode).
    fastest: f64,
}

/// The modal coefficients of one initial state: `s(u) = Σ_t Re(f_t(u) Y_t)`.
#[derive(Debug, Clone, Default)]
pub struct Modal {
    dim: usize,
    y: Vec<C64>,
}

/// An orthonormal basis (as complex columns) of the `k`-dimensional near
/// null space of `m`: the right singular vectors of its `k` smallest singular
/// values.
fn null_space<T: ComplexField<RealField = f64>>(
    m: &DMatrix<T>,
    k: usize,
    to_c64: impl Fn(T) -> C64,
) -> Option<DMatrix<C64>> {
    let svd = m.clone().try_svd(false, true, f64::EPSILON, 10_000)?;
    let vt = svd.v_t?;
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
    let cols: Vec<DVector<C64>> = order[..k].iter().map(|&i| vt.row(i).adjoint().map(&to_c64)).collect();
    Some(DMatrix::from_columns(&cols))
}

fn ill(msg: impl Into<String>) -> SolverError {
    SolverError::IllConditioned { message: msg.into() }
}

/// Groups of eigenvalue indices closer than `tol` to one another
/// (union-find), in order of their smallest index.
fn clusters(eig: &[C64], tol: f64) -> Vec<Vec<usize>> {
    let dim = eig.len();
    let mut parent: Vec<usize> = (0..dim).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for i in 0..dim {
        for j in 0..i {
            if (eig[i] - eig[j]).norm() <= tol {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_of = vec![usize::MAX; dim];
    for i in 0..dim {
        let r = root(&mut parent, i);
        if group_of[r] == usize::MAX {
            group_of[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[group_of[r]].push(i);
    }
    groups
}

/// The invariant subspace of each real or upper-half-plane cluster: its mean
/// eigenvalue, its weight (1 real, 2 upper: the conjugate is folded) and a
/// basis, the null space of `((A - μ I)/scale)^k`. Lower clusters are the
/// conjugates of upper ones and must match them in number.
fn subspaces(
    a: &DMatrix<f64>,
    eig: &[C64],
    groups: &[Vec<usize>],
    tol: f64,
    scale: f64,
) -> Result<Vec<(C64, f64, DMatrix<C64>)>, SolverError> {
    let dim = a.nrows();
    let id = DMatrix::<f64>::identity(dim, dim);
    let ac = a.map(|x| C64::new(x, 0.0));
    let mut kept: Vec<(C64, f64, DMatrix<C64>)> = Vec::new();
    let (mut upper, mut lower) = (0usize, 0usize);
    for g in groups {
        let k = g.len();
        let mu = g.iter().map(|&i| eig[i]).sum::<C64>() / k as f64;
        // The shifted matrix is scaled to unit size before it is powered, so
        // that its null space keeps full precision.
        if mu.im.abs() <= tol {
            let shifted = (a - &id * mu.re) / scale;
            let mut p = shifted.clone();
            for _ in 1..k {
                p = &p * &shifted;
            }
            let v = null_space(&p, k, |x| C64::new(x, 0.0)).ok_or_else(|| ill("SVD did not converge"))?;
            kept.push((C64::new(mu.re, 0.0), 1.0, v));
        } else if mu.im > 0.0 {
            upper += k;
            let shifted = (&ac - DMatrix::<C64>::identity(dim, dim) * mu) / C64::new(scale, 0.0);
            let mut p = shifted.clone();
            for _ in 1..k {
                p = &p * &shifted;
            }
            let v = null_space(&p, k, |z| z).ok_or_else(|| ill("SVD did not converge"))?;
            kept.push((mu, 2.0, v));
        } else {
            lower += k;
        }
    }
    if upper != lower {
        return Err(ill("eigenvalues are not in conjugate pairs"));
    }
    Ok(kept)
}

/// The inverse of the full basis: the kept clusters' columns, then the
/// conjugates of the upper ones. Its rows are the clusters' dual rows `W_c`.
fn dual_rows(kept: &[(C64, f64, DMatrix<C64>)], dim: usize) -> Result<DMatrix<C64>, SolverError> {
    let mut cols: Vec<DVector<C64>> = Vec::with_capacity(dim);
    for (_, _, v) in kept {
        cols.extend(v.column_iter().map(|c| c.into_owned()));
    }
    for (_, weight, v) in kept {
        if *weight > 1.0 {
            cols.extend(v.column_iter().map(|c| c.map(|x| x.conj())));
        }
    }
    if cols.len() != dim {
        return Err(ill("invariant subspaces do not span the state space"));
    }
    DMatrix::from_columns(&cols).try_inverse().ok_or_else(|| ill("invariant subspaces are linearly dependent"))
}

/// How a cluster's nilpotent part `N_c` is summed over `[0, horizon]`: the
/// powers kept and the time scale ν (a power of two near `‖N_c‖` for a tiny
/// one, see the module doc; 1 otherwise). `n` is zeroed when it is below
/// rounding and divided by ν when scaled.
fn series(n: &mut DMatrix<C64>, horizon: f64, scale: f64) -> Result<(usize, f64), SolverError> {
    if n.iter().all(|x| x.norm() <= 1e-13 * scale) {
        n.fill(C64::new(0.0, 0.0));
        return Ok((1, 1.0));
    }
    let mut nu = 1.0;
    let nn = n.norm();
    if nn < TINY_N {
        nu = f64::powi(2.0, nn.log2().ceil() as i32);
        *n /= C64::new(nu, 0.0);
    }
    let (nn, horizon) = (nn / nu, horizon * nu);
    let k = n.nrows();
    let mut p = DMatrix::<C64>::identity(k, k);
    let mut j = 1;
    let mut coeff = 1.0;
    loop {
        p = &*n * &p;
        coeff *= horizon / j as f64;
        if p.norm() * coeff <= 1e-17 * (1.0 + nn * horizon) {
            return Ok((j, nu));
        }
        j += 1;
        if j > 60 {
            return Err(ill("cluster series does not converge over the period"));
        }
    }
}

impl Spectral {
    /// [`Spectral::new`], remembered on this thread: the cells of a plane that
    /// share a forcing frequency share their modes' matrices (a fresh sweep
    /// along ω meets every ω again on the next line), and a decomposition is
    /// a pure function of the bits of `a` and `horizon`, so a remembered one is
    /// the new one bit for bit. Failures are not remembered.
    pub fn shared(a: &DMatrix<f64>, horizon: f64) -> Result<Arc<Spectral>, SolverError> {
        let bits = std::iter::once(horizon).chain(a.iter().copied()).map(f64::to_bits);
        let key: Vec<u64> = std::iter::once(a.nrows() as u64).chain(bits).collect();
        if let Some(hit) = MEMO.with(|m| m.borrow().get(&key).cloned()) {
            return Ok(hit);
        }
        let made = Arc::new(Spectral::new(a, horizon)?);
        MEMO.with(|m| {
            let mut m = m.borrow_mut();
            if m.len() >= MEMO_ENTRIES {
                m.clear();
            }
            m.insert(key, Arc::clone(&made));
        });
        Ok(made)
    }

    /// Decomposes `a`; the expansion is accurate to rounding for `0 <= u <= horizon`.
    pub fn new(a: &DMatrix<f64>, horizon: f64) -> Result<Spectral, SolverError> {
        let dim = a.nrows();
        let scale = a.amax().max(1.0);
        let eig = Schur::try_new(a.clone(), f64::EPSILON, 10_000)
            .ok_or_else(|| ill("Schur decomposition did not converge"))?
            .complex_eigenvalues();
        // Clusters are judged against the spectral radius, not the size of the
        // entries: a stiff light mass has entries ~1e4 but must not merge the
        // slow forcing pair ±iω with the constant state.
        let radius = eig.iter().map(|l| l.norm()).fold(1.0, f64::max);
        let tol = 1e-5 * radius;
        let eig: Vec<C64> = eig.iter().copied().collect();
        let kept = subspaces(a, &eig, &clusters(&eig, tol), tol, scale)?;
        let inv = dual_rows(&kept, dim)?;
        let ac = a.map(|x| C64::new(x, 0.0));
        let mut clusters = Vec::with_capacity(kept.len());
        let mut terms = Vec::new();
        let mut offset = 0;
        let mut rebuilt = DMatrix::<f64>::zeros(dim, dim);
        for (_, weight, v) in kept {
            let k = v.ncols();
            let w = inv.rows(offset, k).into_owned();
            offset += k;
            let b = &w * &ac * &v;
            let mu = if weight > 1.0 { b.trace() / k as f64 } else { C64::new(b.trace().re / k as f64, 0.0) };
            // A zero eigenvalue is exactly zero (the constant state, a free mass):
            // rounding in its trace goes to N, where it is below rounding anyway.
            let zero = mu.norm() <= 1e-13 * radius;
            let mu = if zero { C64::new(0.0, 0.0) } else { mu };
            let mut n = &b - DMatrix::<C64>::identity(k, k) * mu;
            rebuilt += (&v * &b * &w).map(|x| x.re * weight);
            let (powers, nu) = series(&mut n, horizon, scale)?;
            let mut inv_factorial = 1.0;
            for j in 0..powers {
                if j > 0 {
                    inv_factorial /= j as f64;
                }
                let (last, constant) = (j + 1 == powers, zero && j == 0);
                terms.push(Term { lambda: mu, power: j, scale: nu, weight, inv_factorial, last, constant });
            }
            clusters.push(Cluster { v, wt: w.transpose(), n, powers });
        }
        let err = (&rebuilt - a).amax();
        if err.is_nan() || err > 1e-9 * scale {
            return Err(ill(format!("spectral reconstruction error {err:e}")));
        }
        let fastest = terms.iter().map(|t| t.lambda.norm()).fold(0.0, f64::max);
        Ok(Spectral { dim, clusters, terms, fastest })
    }

    /// Terms of the expansion, in the order used by [`Modal`] and [`Spectral::factors`].
    pub fn terms(&self) -> &[Term] {
        &self.terms
    }

    /// Largest modulus of the terms' eigenvalues (the fastest mode's rate).
    pub fn fastest(&self) -> f64 {
        self.fastest
    }

    /// Modal coefficients `Y_t = V_c N_c^j W_c s0` of an initial state.
    pub fn modal(&self, s0: &DVector<f64>) -> Modal {
        let mut m = Modal::default();
        self.modal_into(s0.as_slice(), &mut m);
        m
    }

    /// [`Spectral::modal`] into a reused buffer (no allocation once warm).
    pub fn modal_into(&self, s0: &[f64], out: &mut Modal) {
        let dim = self.dim;
        out.dim = dim;
        out.y.clear();
        out.y.resize(self.terms.len() * dim, C64::new(0.0, 0.0));
        let mut rows = out.y.chunks_exact_mut(dim);
        let mut d = [C64::new(0.0, 0.0); 16];
        let mut e = [C64::new(0.0, 0.0); 16];
        let s0 = &s0[..dim];
        for c in &self.clusters {
            let k = c.v.ncols();
            let (d, e) = (&mut d[..k], &mut e[..k]);
            // Column-major storage: column j of a matrix is its j-th chunk.
            for (dr, row) in d.iter_mut().zip(c.wt.as_slice().chunks_exact(dim)) {
                *dr = C64::new(0.0, 0.0);
                for (&wj, &x) in row.iter().zip(s0) {
                    *dr += wj * x;
                }
            }
            for j in 0..c.powers {
                if j > 0 {
                    e.fill(C64::new(0.0, 0.0));
                    for (col, &dq) in c.n.as_slice().chunks_exact(k).zip(d.iter()) {
                        for (er, &nr) in e.iter_mut().zip(col) {
                            *er += nr * dq;
                        }
                    }
                    d.copy_from_slice(e);
                }
                let row = rows.next().expect("one row per term");
                for (col, &dq) in c.v.as_slice().chunks_exact(dim).zip(d.iter()) {
                    for (yi, &vi) in row.iter_mut().zip(col) {
                        *yi += vi * dq;
                    }
                }
            }
        }
    }

    /// The matrix coefficient `V_c N_c^j W_c` of every term, so that the
    /// state-transition matrix is `e^{Â u} = Σ_t Re(f_t(u) · coefficient_t)`
    /// with the factors of [`Spectral::factors`].
    pub fn coefficients(&self) -> Vec<DMatrix<C64>> {
        let mut out = Vec::with_capacity(self.terms.len());
        for c in &self.clusters {
            let mut nw = c.wt.transpose();
            for j in 0..c.powers {
                if j > 0 {
                    nw = &c.n * nw;
                }
                out.push(&c.v * &nw);
            }
        }
        out
    }

    /// Fills `out[t] = weight_t e^{μ_t u} u^j / j!` for every term: the
    /// numbers of [`Spectral::factors_and_bounds`], bit for bit.
    pub fn factors(&self, u: f64, out: &mut [C64]) {
        debug_assert_eq!(out.len(), self.terms.len(), "one factor per term");
        let (mut lambda, mut e) = (C64::new(f64::NAN, f64::NAN), C64::new(0.0, 0.0));
        for (term, o) in self.terms.iter().zip(out.iter_mut()) {
            if term.lambda != lambda {
                lambda = term.lambda;
                (_, e) = exponential(lambda, u);
            }
            *o = e * (term.weight * term.poly(u));
        }
    }

    /// [`Spectral::factors`] at `u` and, in the same pass (one exponential per
    /// term), upper bounds of `|weight e^{μ s} s^j/j!|` over `s ∈ [u, b]`.
    pub fn factors_and_bounds(&self, u: f64, b: f64, out: &mut [C64], bounds: &mut [f64]) {
        // The exponential of the previous term's eigenvalue: the powers of one
        // cluster share it (the NaN of the first never equals an eigenvalue).
        let (mut lambda, mut r, mut e) = (C64::new(f64::NAN, f64::NAN), 1.0, C64::new(0.0, 0.0));
        for ((term, o), bound) in self.terms.iter().zip(out.iter_mut()).zip(bounds.iter_mut()) {
            let re = term.lambda.re;
            if term.lambda != lambda {
                lambda = term.lambda;
                (r, e) = exponential(lambda, u);
            }
            let grow = if re > 0.0 { (re * b).exp() } else { r };
            *o = e * (term.weight * term.poly(u));
            *bound = term.weight * grow * term.poly(b);
        }
    }
}

/// `e^{λu}`, with its modulus `e^{Re λ u}`: one `exp` and one `sincos` of
/// libm, none where their argument is zero (`e^0 = 1`, `sin(±0) = ±0`,
/// `cos 0 = 1`, all exact: a constant term, an undamped mode, and every
/// eigenvalue at the start of an advance, a tenth of the step loop's
/// evaluations). libm's `sincos` is its `sin` and `cos`, bit for bit, so
/// this is `λu`'s complex exponential as `num_complex` takes it.
#[inline]
fn exponential(lambda: C64, u: f64) -> (f64, C64) {
    let (a, b) = (lambda.re * u, lambda.im * u);
    let r = if a == 0.0 { 1.0 } else { a.exp() };
    let (sn, cs) = if b == 0.0 { (b, 1.0) } else { sin_cos(b) };
    (r, C64::new(r * cs, r * sn))
}

/// `(sin x, cos x)` in one libm `sincos`: the numbers of `sin` and `cos`,
/// bit for bit, at about half the cost of the two (each of which saves and
/// restores the rounding mode). Out of line so that the two stay in one
/// block, where the compiler makes them one call; `f64::sin_cos` inlined
/// into a caller that stores them apart is two.
#[inline(never)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}

impl Modal {
    /// The size of each term's coefficient `Y_t` (its largest entry's
    /// modulus): zero for a term the initial state does not excite.
    pub fn magnitudes(&self) -> impl Iterator<Item = f64> + '_ {
        self.y.chunks_exact(self.dim.max(1)).map(|y| y.iter().fold(0.0, |m: f64, c| m.max(c.norm())))
    }

    /// The state at the time whose factors are `f`.
    pub fn state(&self, f: &[C64]) -> DVector<f64> {
        let mut s = DVector::zeros(self.dim);
        self.state_into(f, s.as_mut_slice());
        s
    }

    /// [`Modal::state`] into a slice.
    pub fn state_into(&self, f: &[C64], out: &mut [f64]) {
        out.fill(0.0);
        for (y, &ft) in self.y.chunks_exact(self.dim).zip(f) {
            for (si, yi) in out.iter_mut().zip(y) {
                *si += ft.re * yi.re - ft.im * yi.im;
            }
        }
    }

    /// Coefficients `β_t = row · Y_t` of a linear functional of the state.
    pub fn functional(&self, row: &[f64]) -> Vec<C64> {
        let mut out = vec![C64::new(0.0, 0.0); self.y.len() / self.dim.max(1)];
        self.functional_into(&nonzero_entries(row), &mut out);
        out
    }

    /// [`Modal::functional`] into a slice (one entry per term), from the
    /// functional's nonzero entries (index, value), ascending. The zero entries
    /// a dense product would add are `±0` (the state is finite), which leave a
    /// sum that starts at `+0` unchanged: the result is the dense one bit for bit.
    pub fn functional_into(&self, entries: &[(usize, f64)], out: &mut [C64]) {
        for (y, o) in self.y.chunks_exact(self.dim).zip(out.iter_mut()) {
            *o = entries.iter().map(|&(i, b)| y[i] * b).sum();
        }
    }
}

/// The nonzero entries (index, value) of `row`, ascending: what
/// [`Modal::functional_into`] reads of a functional.
pub fn nonzero_entries(row: &[f64]) -> Vec<(usize, f64)> {
    row.iter().copied().enumerate().filter(|&(_, v)| v != 0.0).collect()
}

/// Coefficients of the time derivative of `Σ_t Re(f_t β_t)`,
/// `β'_{c,j} = μ_c β_{c,j} + ν_c β_{c,j+1}`, into `out`.
#[inline]
pub fn differentiate_into(terms: &[Term], beta: &[C64], out: &mut [C64]) {
    for (t, (o, term)) in out.iter_mut().zip(&terms[..beta.len()]).enumerate() {
        let next = match beta.get(t + 1) {
            Some(&b) if !term.last => b,
            _ => C64::new(0.0, 0.0),
        };
        *o = term.lambda * beta[t] + next * term.scale;
    }
}

/// `Σ_t Re(f_t β_t)`.
pub fn evaluate(f: &[C64], beta: &[C64]) -> f64 {
    f.iter().zip(beta).map(|(a, b)| a.re * b.re - a.im * b.im).sum()
}

/// `Σ_t |β_t| bound_t`, with `moduli[t] = |β_t|`.
pub fn bound(bounds: &[f64], moduli: &[f64]) -> f64 {
    bounds.iter().zip(moduli).map(|(b, x)| b * x).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn augmented(a: &DMatrix<f64>, b: &[f64], b0: &[f64], omega: f64) -> DMatrix<f64> {
        let d = a.nrows();
        let mut m = DMatrix::zeros(d + 3, d + 3);
        m.view_mut((0, 0), (d, d)).copy_from(a);
        for i in 0..d {
            m[(i, d)] = b[i];
            m[(i, d + 2)] = b0[i];
        }
        m[(d, d + 1)] = omega;
        m[(d + 1, d)] = -omega;
        m
    }

    fn check_against_expm(m: &DMatrix<f64>, horizon: f64) {
        let sp = Spectral::new(m, horizon).unwrap();
        let s0 = DVector::from_fn(m.nrows(), |i, _| 0.3 + 0.1 * i as f64);
        let modal = sp.modal(&s0);
        let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
        for &u in &[0.0, 0.37, 1.0, horizon / 2.0, horizon] {
            sp.factors(u, &mut f);
            let exact = (m * u).exp() * &s0;
            let got = modal.state(&f);
            let err = (&got - &exact).amax() / exact.amax().max(1.0);
            assert!(err < 1e-11, "u = {u}: relative error {err:e}\n{got}\n{exact}");
        }
    }

    /// A remembered decomposition is the fresh one bit for bit (their debug
    /// forms print every float in full), and is handed out again for the same
    /// inputs only: another horizon or one changed entry decomposes anew.
    #[test]
    fn shared_decompositions_are_the_fresh_ones() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, -0.2]);
        let m = augmented(&a, &[0.0, 1.0], &[0.0, 0.0], 0.33);
        let first = Spectral::shared(&m, 19.0).unwrap();
        assert_eq!(format!("{:?}", *first), format!("{:?}", Spectral::new(&m, 19.0).unwrap()));
        assert!(Arc::ptr_eq(&first, &Spectral::shared(&m, 19.0).unwrap()));
        assert!(!Arc::ptr_eq(&first, &Spectral::shared(&m, 19.5).unwrap()));
        let mut other = m.clone();
        other[(1, 1)] = -0.2000000000000001;
        let changed = Spectral::shared(&other, 19.0).unwrap();
        assert!(!Arc::ptr_eq(&first, &changed));
        assert_eq!(format!("{:?}", *changed), format!("{:?}", Spectral::new(&other, 19.0).unwrap()));
    }

    #[test]
    fn damped_oscillator_matches_matrix_exponential() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, -0.2]);
        check_against_expm(&augmented(&a, &[0.0, 1.0], &[0.0, 0.0], 0.33), 19.0);
    }

    #[test]
    fn identical_uncoupled_oscillators_are_exact() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, -0.2, 0.0, 0.0, -1.0, 0.0, -0.2],
        );
        check_against_expm(&augmented(&a, &[0.0, 0.0, 1.0, 0.0], &[0.0; 4], 2.5), 2.6);
    }

    #[test]
    fn free_mass_with_constant_force_is_a_polynomial() {
        // x'' = 0.5 (constant force): Jordan block of size 3 with the constant state.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let m = augmented(&a, &[0.0, 0.0], &[0.0, 0.5], 1.3);
        check_against_expm(&m, 5.0);
        let sp = Spectral::new(&m, 5.0).unwrap();
        let s0 = DVector::from_vec(vec![0.1, -0.2, 0.0, 1.0, 1.0]);
        let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
        sp.factors(4.0, &mut f);
        let x = sp.modal(&s0).state(&f)[0];
        assert!((x - (0.1 - 0.2 * 4.0 + 0.25 * 16.0)).abs() < 1e-13);
    }

    #[test]
    fn undamped_resonance_grows_linearly() {
        // x'' + x = sin t: x(t) = (sin t - t cos t)/2 from rest.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        let m = augmented(&a, &[0.0, 1.0], &[0.0, 0.0], 1.0);
        check_against_expm(&m, 6.3);
        let sp = Spectral::new(&m, 6.3).unwrap();
        let s0 = DVector::from_vec(vec![0.0, 0.0, 0.0, 1.0, 1.0]);
        let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
        let t: f64 = 5.0;
        sp.factors(t, &mut f);
        let x = sp.modal(&s0).state(&f)[0];
        assert!((x - (t.sin() - t * t.cos()) / 2.0).abs() < 1e-12);
    }

    #[test]
    fn stiff_light_mass_under_slow_forcing_is_exact() {
        // mu_m = 0.01, mu_k = 0.99: M2 (mass 0.0101, stiffness 99) oscillates at
        // about 99 rad/s while the forcing turns at 0.02.
        let (a2, k2) = (0.01 / 0.99, 0.99 / 0.01);
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, -0.02, 0.0, 0.0, -k2 / a2, 0.0, -0.0002 / a2],
        );
        let m = augmented(&a, &[0.0, 0.0, 1.0, 0.0], &[0.0; 4], 0.02);
        check_against_expm(&m, 0.5);
        let sp = Spectral::new(&m, 314.0).unwrap();
        let s0 = DVector::from_vec(vec![1e-6, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0]);
        let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
        sp.factors(0.0, &mut f);
        let back = sp.modal(&s0).state(&f);
        assert!((&back - &s0).amax() < 1e-13, "{back}");
    }

    #[test]
    fn critically_damped_oscillator_is_exact() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, -2.0]);
        check_against_expm(&augmented(&a, &[0.0, 1.0], &[0.0, 0.3], 0.7), 9.0);
    }

    #[test]
    fn derivative_coefficients_match_finite_differences() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let m = augmented(&a, &[0.0, 0.7], &[0.0, 0.5], 1.3);
        let sp = Spectral::new(&m, 5.0).unwrap();
        let s0 = DVector::from_vec(vec![0.1, -0.2, 0.3, (1.0f64 - 0.09).sqrt(), 1.0]);
        let modal = sp.modal(&s0);
        let row = DVector::from_vec(vec![1.0, 0.0, 0.0, 0.0, 0.0]);
        let beta = modal.functional(row.as_slice());
        let mut d1 = vec![C64::new(0.0, 0.0); beta.len()];
        differentiate_into(sp.terms(), &beta, &mut d1);
        let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
        let (u, h) = (2.0, 1e-6);
        sp.factors(u + h, &mut f);
        let p = evaluate(&f, &beta);
        sp.factors(u - h, &mut f);
        let q = evaluate(&f, &beta);
        sp.factors(u, &mut f);
        assert!(((p - q) / (2.0 * h) - evaluate(&f, &d1)).abs() < 1e-8);
    }
}

#[cfg(test)]
mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Issue 5: the exact flow composes, `flow(t1 + t2) = flow(t2) ∘ flow(t1)`,
        /// for damped two-mass systems with a free or bound second mass.
        #[test]
        fn flow_composes(k2 in 0.0f64..50.0, c1 in 0.0f64..1.0, c2 in 0.0f64..5.0, m2 in 0.05f64..20.0,
                         omega in 0.05f64..5.0, t1 in 0.0f64..3.0, t2 in 0.0f64..3.0,
                         x in prop::array::uniform4(-1.0f64..1.0)) {
            let a = DMatrix::from_row_slice(4, 4, &[
                0.0, 0.0, 1.0, 0.0,
                0.0, 0.0, 0.0, 1.0,
                -1.0, 0.0, -c1, 0.0,
                0.0, -k2 / m2, 0.0, -c2 / m2,
            ]);
            let mut m = DMatrix::zeros(7, 7);
            m.view_mut((0, 0), (4, 4)).copy_from(&a);
            m[(2, 4)] = 1.0;
            m[(4, 5)] = omega;
            m[(5, 4)] = -omega;
            let sp = Spectral::new(&m, 6.0).unwrap();
            let s0 = DVector::from_vec(vec![x[0], x[1], x[2], x[3], 0.3, 0.9539392014169456, 1.0]);
            let mut f = vec![C64::new(0.0, 0.0); sp.terms().len()];
            sp.factors(t1, &mut f);
            let mid = sp.modal(&s0).state(&f);
            sp.factors(t2, &mut f);
            let two = sp.modal(&mid).state(&f);
            sp.factors(t1 + t2, &mut f);
            let one = sp.modal(&s0).state(&f);
            prop_assert!((&one - &two).amax() <= 1e-11 * (1.0 + one.amax()), "{} vs {}", one, two);
        }

        /// One `sincos` is libm's `sin` and `cos` bit for bit (the two
        /// taken apart, each behind a `black_box` so that the compiler
        /// cannot make them one call), and `e^{λu}` is `num_complex`'s:
        /// the zero arguments it answers without libm included.
        #[test]
        fn one_sincos_is_sin_and_cos(x in prop_oneof![-1e7f64..1e7, -10.0f64..10.0, -1e-8f64..1e-8, Just(0.0), Just(-0.0)],
                                     re in prop_oneof![-2.0f64..2.0, Just(0.0), Just(-0.0)],
                                     im in prop_oneof![-5.0f64..5.0, Just(0.0), Just(-0.0)],
                                     u in prop_oneof![-20.0f64..20.0, Just(0.0), Just(-0.0)]) {
            let (s, c) = sin_cos(x);
            let apart = (std::hint::black_box(x).sin(), std::hint::black_box(x).cos());
            prop_assert_eq!((s.to_bits(), c.to_bits()), (apart.0.to_bits(), apart.1.to_bits()));
            let lambda = C64::new(re, im);
            let (r, e) = exponential(lambda, u);
            let want = (lambda * u).exp();
            prop_assert_eq!((e.re.to_bits(), e.im.to_bits()), (want.re.to_bits(), want.im.to_bits()));
            prop_assert_eq!(r.to_bits(), std::hint::black_box(re * u).exp().to_bits());
        }

        /// [`Spectral::factors`] is [`Spectral::factors_and_bounds`]'s
        /// factors bit for bit (what `Workspace::factors_at` relies on),
        /// at an advance's start too.
        #[test]
        fn the_factors_are_those_with_the_bounds(omega in 0.05f64..5.0, c in 0.0f64..1.0, u in prop_oneof![0.0f64..6.0, Just(0.0)]) {
            let mut m = DMatrix::zeros(5, 5);
            m[(0, 1)] = 1.0;
            m[(1, 0)] = -1.0;
            m[(1, 1)] = -c;
            m[(1, 2)] = 1.0;
            m[(2, 3)] = omega;
            m[(3, 2)] = -omega;
            let sp = Spectral::new(&m, 6.0).unwrap();
            let n = sp.terms().len();
            let (mut f, mut g, mut b) = (vec![C64::new(0.0, 0.0); n], vec![C64::new(0.0, 0.0); n], vec![0.0; n]);
            sp.factors(u, &mut f);
            sp.factors_and_bounds(u, 6.0, &mut g, &mut b);
            let bits = |v: &[C64]| v.iter().map(|z| (z.re.to_bits(), z.im.to_bits())).collect::<Vec<_>>();
            prop_assert_eq!(bits(&f), bits(&g));
        }
    }
}
