//! Pseudo-arclength continuation: follows a branch of periodic orbits around
//! folds, where natural continuation in the parameter must stop.
//!
//! The unknowns are `z = (x, p)`, the section state and the parameter, with
//! `F(z) = map_p(x) - x`. From a point with unit tangent `t` (the null vector of
//! `[F_x F_p]`, oriented like the previous one) the predictor is `z + ds t`, and
//! Newton's method corrects on `F(z) = 0`, `t·(z - z_pred) = 0`. `F_x = DP - I` is
//! the exact tangent map; `F_p` a forward difference in the parameter. The step
//! grows after easy corrections and halves after failed ones.
//!
//! Between consecutive points two test functions are watched: `det(DP - I)`,
//! which changes sign at a fold (SN: a multiplier through +1, where the
//! branch turns back), and `max|μ| - 1` (PD, PF, NS as in
//! [`crate::continuation`]). A sign change is located by bisection on the
//! secant between the points, each trial corrected onto the branch in the
//! hyperplane normal to the secant. A change of the impact pattern (grazing)
//! ends the branch, located the same way.

use crate::accuracy::Accuracy;
use crate::continuation::{psi, Branch, BranchPoint, Family, Located, PARAM_TOL};
use crate::floquet::Bifurcation;
use crate::newton::{evaluate, Failure, Solution};
use crate::orbit::{describe, Orbit, ORBIT_TOL};
use crate::simulate::Simulator;
use crate::Method;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64 as C64;

/// The residual and its Jacobian at `z = (x, p)`.
struct Linear {
    f: DVector<f64>,
    fx: DMatrix<f64>,
    fp: DVector<f64>,
}

fn split(z: &DVector<f64>) -> (DVector<f64>, f64) {
    let d = z.len() - 1;
    (z.rows(0, d).into_owned(), z[d])
}

fn join(x: &DVector<f64>, p: f64) -> DVector<f64> {
    let mut z = DVector::zeros(x.len() + 1);
    z.rows_mut(0, x.len()).copy_from(x);
    z[x.len()] = p;
    z
}

/// Evaluates `F`, `F_x`, `F_p` at `z`, keeping the pattern of `like`.
fn linearise(family: &Family, acc: &Accuracy, like: &Orbit, z: &DVector<f64>) -> Result<Linear, Failure> {
    let (x, p) = split(z);
    let image = |p: f64| {
        let sys = family(p).ok_or(Failure::Simulation)?;
        let mut sim = Simulator::new(&sys, *acc, Method::Exact, x.as_slice()).map_err(|_| Failure::Simulation)?;
        sim.track_tangent();
        let img = evaluate(&mut sim, &x, like.map).map_err(|_| Failure::Simulation)?;
        if img.pattern != like.solution.pattern {
            return Err(Failure::Pattern);
        }
        Ok(img)
    };
    let here = image(p)?;
    let h = 1e-7 * (1.0 + p.abs());
    let fp = match image(p + h) {
        Ok(img) => (img.value - &here.value) / h,
        Err(_) => (&here.value - image(p - h)?.value) / h,
    };
    let dim = x.len();
    Ok(Linear { f: &here.value - &x, fx: here.jacobian - DMatrix::identity(dim, dim), fp })
}

/// The bordered matrix `[[F_x, F_p], [rowᵀ]]`.
fn bordered(lin: &Linear, row: &DVector<f64>) -> DMatrix<f64> {
    let d = lin.f.len();
    let mut a = DMatrix::zeros(d + 1, d + 1);
    a.view_mut((0, 0), (d, d)).copy_from(&lin.fx);
    a.view_mut((0, d), (d, 1)).copy_from(&lin.fp);
    a.view_mut((d, 0), (1, d + 1)).copy_from(&row.transpose());
    a
}

/// The unit null vector of `[F_x F_p]`, oriented along `prev`.
fn tangent(lin: &Linear, prev: &DVector<f64>) -> Option<DVector<f64>> {
    let d = lin.f.len();
    let a = bordered(lin, prev);
    let mut rhs = DVector::zeros(d + 1);
    rhs[d] = 1.0;
    let t = a.lu().solve(&rhs)?;
    let n = t.norm();
    (n.is_finite() && n > 0.0).then(|| t / n)
}

/// Newton on `F(z) = 0`, `normal·(z - anchor) = 0`, from `anchor`.
fn correct(
    family: &Family,
    acc: &Accuracy,
    like: &Orbit,
    anchor: &DVector<f64>,
    normal: &DVector<f64>,
) -> Result<(DVector<f64>, Linear, usize), Failure> {
    let mut z = anchor.clone();
    let d = z.len() - 1;
    for it in 0..12 {
        let lin = linearise(family, acc, like, &z)?;
        let scale = 1.0 + z.rows(0, d).amax();
        if lin.f.amax() / scale <= ORBIT_TOL {
            return Ok((z, lin, it));
        }
        let a = bordered(&lin, normal);
        let mut rhs = DVector::zeros(d + 1);
        rhs.rows_mut(0, d).copy_from(&(-&lin.f));
        rhs[d] = -normal.dot(&(&z - anchor));
        let dz = a.lu().solve(&rhs).ok_or(Failure::Diverged)?;
        if !dz.iter().all(|v| v.is_finite()) || dz.amax() > 0.5 * scale {
            return Err(Failure::Diverged);
        }
        z += dz;
    }
    Err(Failure::Diverged)
}

/// The orbit of `like` (at the point `z`, the branch's unit tangent `t`
/// there) solved at the parameter value `value` by Newton's method at that
/// value, from the tangent's prediction there (from `z`'s state where the
/// tangent does not move the parameter); `None` where it does not converge
/// keeping `like`'s impact pattern.
fn at_value(
    family: &Family,
    acc: &Accuracy,
    like: &Orbit,
    z: &DVector<f64>,
    t: &DVector<f64>,
    value: f64,
) -> Option<Orbit> {
    let d = z.len() - 1;
    let mut anchor = if t[d].abs() > 1e-3 { z + t * ((value - z[d]) / t[d]) } else { z.clone() };
    anchor[d] = value;
    let mut along = DVector::zeros(d + 1);
    along[d] = 1.0;
    let (z, lin, it) = correct(family, acc, like, &anchor, &along).ok()?;
    orbit_at(family, acc, like, &z, &lin, it)
}

/// The orbit at a corrected point.
fn orbit_at(family: &Family, acc: &Accuracy, like: &Orbit, z: &DVector<f64>, lin: &Linear, it: usize) -> Option<Orbit> {
    let (x, p) = split(z);
    let sys = family(p)?;
    let dim = x.len();
    let solution = Solution {
        residual: lin.f.amax() / (1.0 + x.amax()),
        jacobian: &lin.fx + DMatrix::identity(dim, dim),
        pattern: like.solution.pattern.clone(),
        x,
        iterations: it,
    };
    Some(describe(&sys, acc, solution, like.map, like.n))
}

fn fold_test(lin: &Linear) -> f64 {
    lin.fx.determinant()
}

/// Bisection on the secant from `a` to `b` for the sign change of `test`
/// (evaluated on the corrected point); the located point's value and orbit.
fn bisect(
    family: &Family,
    acc: &Accuracy,
    like: &Orbit,
    a: &DVector<f64>,
    b: &DVector<f64>,
    test: &dyn Fn(&Linear, &Orbit) -> f64,
    sign_a: bool,
) -> Option<(f64, Orbit)> {
    let secant = b - a;
    let normal = &secant / secant.norm();
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut best = None;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let anchor = a + &secant * mid;
        let (z, lin, it) = correct(family, acc, like, &anchor, &normal).ok()?;
        let o = orbit_at(family, acc, like, &z, &lin, it)?;
        let p = z[z.len() - 1];
        if (test(&lin, &o) < 0.0) == sign_a {
            lo = mid;
        } else {
            hi = mid;
        }
        best = Some((p, o));
        if (hi - lo) * secant[secant.len() - 1].abs() <= PARAM_TOL * (1.0 + p.abs()) && (hi - lo) < 1e-9 {
            break;
        }
    }
    best
}

/// Where the impact pattern of `like` (at `z`, tangent `t`) changes within a
/// step `ds` along `t`: bisection on whether the corrector keeps the pattern.
/// The parameter value and the last orbit that kept it.
fn locate_grazing(
    family: &Family,
    acc: &Accuracy,
    like: &Orbit,
    z: &DVector<f64>,
    t: &DVector<f64>,
    ds: f64,
) -> (f64, Orbit) {
    let d = z.len() - 1;
    let (mut inside, mut outside) = (0.0f64, ds);
    let (mut v, mut o) = (z[d], like.clone());
    for _ in 0..60 {
        if (outside - inside) * t[d].abs() <= PARAM_TOL * (1.0 + v.abs()) {
            break;
        }
        let mid = 0.5 * (inside + outside);
        let kept = correct(family, acc, like, &(z + t * mid), t)
            .ok()
            .and_then(|(zm, lm, it)| Some((zm[d], orbit_at(family, acc, like, &zm, &lm, it)?)));
        match kept {
            Some(found) => {
                inside = mid;
                (v, o) = found;
            }
            None => outside = mid,
        }
    }
    (v, o)
}

/// Follows `start` (the orbit at `values[0]`) by pseudo-arclength across the
/// range of `values`, with their spacing as the largest step, for at most 20
/// times as many points.
pub fn follow_arclength(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit) -> Branch {
    let (p0, p_end) = (values[0], values[values.len() - 1]);
    let (lo, hi) = (p0.min(p_end), p0.max(p_end));
    let ds_max = (p_end - p0).abs() / (values.len() - 1).max(1) as f64;
    let mut branch = Branch { points: vec![BranchPoint { value: p0, orbit: start.clone() }], ..Branch::default() };
    let mut z = join(&start.solution.x, p0);
    let d = z.len() - 1;
    let mut guide = DVector::zeros(d + 1);
    guide[d] = (p_end - p0).signum();
    let Ok(mut lin) = linearise(family, acc, &start, &z) else {
        branch.ended = Some("the start orbit could not be linearised".into());
        return branch;
    };
    let Some(mut t) = tangent(&lin, &guide) else {
        branch.ended = Some("no tangent at the start".into());
        return branch;
    };
    let mut orbit = start;
    let mut ds = ds_max;
    while branch.points.len() < 20 * values.len() {
        let anchor = &z + &t * ds;
        match correct(family, acc, &orbit, &anchor, &t) {
            Ok((z_new, lin_new, it)) => {
                let Some(o) = orbit_at(family, acc, &orbit, &z_new, &lin_new, it) else {
                    branch.ended = Some(format!("the scene is not valid at {:.9}", z_new[d]));
                    break;
                };
                let Some(t_new) = tangent(&lin_new, &t) else {
                    branch.ended = Some(format!("no tangent at {:.9}", z_new[d]));
                    break;
                };
                let p = z_new[d];
                let fold = (fold_test(&lin) < 0.0) != (fold_test(&lin_new) < 0.0);
                let stability = (psi(&orbit) < 0.0) != (psi(&o) < 0.0);
                if fold {
                    let test = |l: &Linear, _: &Orbit| fold_test(l);
                    if let Some((v, at)) = bisect(family, acc, &orbit, &z, &z_new, &test, fold_test(&lin) < 0.0) {
                        let one = C64::new(1.0, 0.0);
                        let critical = at
                            .map_multipliers
                            .iter()
                            .copied()
                            .min_by(|a, b| (a - one).norm().total_cmp(&(b - one).norm()))
                            .unwrap_or(one);
                        branch.bifurcations.push(Located::new(Bifurcation::SaddleNode, v, &at, critical));
                    }
                } else if stability {
                    let test = |_: &Linear, o: &Orbit| psi(o);
                    if let Some((v, at)) = bisect(family, acc, &orbit, &z, &z_new, &test, psi(&orbit) < 0.0) {
                        branch.bifurcations.push(Located::stability(v, &at));
                    }
                }
                if p < lo - 1e-12 * (1.0 + lo.abs()) || p > hi + 1e-12 * (1.0 + hi.abs()) {
                    // Past the range: the branch ends on the edge it crossed,
                    // its orbit solved there at that value (from the last
                    // point's), and what was found beyond is not reported.
                    let edge = if p > hi { hi } else { lo };
                    branch.bifurcations.retain(|b| (lo..=hi).contains(&b.value));
                    match at_value(family, acc, &orbit, &z, &t, edge) {
                        Some(o) => branch.points.push(BranchPoint { value: edge, orbit: o }),
                        None => {
                            let why = format!(
                                "the orbit was not solved at the edge of the range, {edge}, keeping its impacts"
                            );
                            branch.ended = Some(why);
                            return branch;
                        }
                    }
                    // Back where it started: past a fold, or turned round
                    // without one (the continuation reversed on itself).
                    if (p > hi) != (p_end > p0) {
                        let fold = branch.bifurcations.iter().any(|b| b.kind == Bifurcation::SaddleNode);
                        branch.ended = Some(if fold {
                            format!("turned back at the fold and left the range at its start, {edge}")
                        } else {
                            format!("turned back to the start of the range, {edge}, without a fold located")
                        });
                    }
                    return branch;
                }
                branch.points.push(BranchPoint { value: p, orbit: o.clone() });
                (z, lin, t, orbit) = (z_new, lin_new, t_new, o);
                if it <= 3 {
                    ds = (ds * 1.5).min(ds_max);
                }
            }
            Err(why) if ds > ds_max / 1024.0 => {
                ds *= 0.5;
                if why == Failure::Simulation && ds <= ds_max / 1024.0 {
                    branch.ended = Some(format!("the simulation failed near {:.9}", z[d]));
                    break;
                }
            }
            Err(why) => {
                if why == Failure::Pattern {
                    // The event sequence changes within this smallest step: grazing.
                    let (v, o) = locate_grazing(family, acc, &orbit, &z, &t, ds);
                    branch.bifurcations.push(Located::at_leading(Bifurcation::Grazing, v, &o));
                    branch.ended = Some(format!("the impact pattern changes at {v:.9} (grazing)"));
                } else {
                    branch.ended = Some(format!("the corrector failed at {:.9}", z[d]));
                }
                return branch;
            }
        }
    }
    if branch.ended.is_none() && branch.points.len() >= 20 * values.len() {
        branch.ended = Some("point budget exhausted before leaving the range".into());
    }
    branch
}
