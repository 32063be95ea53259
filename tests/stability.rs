//! Exact Jacobians, Newton orbits, Floquet multipliers (issue 6).

use crate::util::{json_of, system};
use solver::{
    multipliers, solve, Accuracy, Complex64, DMatrix, DVector, Ignore, Limits, MapKind, Method, Simulator, System,
};

/// Newton's method for the orbits of these tests: to 1e-13, at most 20 steps.
const NEWTON: Limits = Limits { tol: 1e-13, max_iter: 20, max_step: 0.5, stall: None };

/// Converged stable state of a cell (plain simulation) and its period.
fn settled(sys: &System) -> (Vec<f64>, usize) {
    let acc = Accuracy::default();
    let cell = solver::run_cell(sys, &acc, Method::Exact, &sys.model.initial_state());
    (cell.final_state, cell.n.expect("periodic cell"))
}

/// Central finite differences of the n-period map at `x`.
fn finite_differences(sys: &System, x: &DVector<f64>, n: usize) -> DMatrix<f64> {
    let mut sim = Simulator::new(sys, Accuracy::default(), Method::Exact, x.as_slice()).unwrap();
    let mut image = |y: &DVector<f64>| {
        sim.restart(y.as_slice()).unwrap();
        for _ in 0..n {
            sim.run_period(&[], false, &mut Ignore).unwrap();
        }
        sim.state().clone()
    };
    let dim = x.len();
    let mut jac = DMatrix::zeros(dim, dim);
    for j in 0..dim {
        let h = 1e-6 * (1.0 + x[j].abs());
        let (mut a, mut b) = (x.clone(), x.clone());
        a[j] += h;
        b[j] -= h;
        jac.set_column(j, &((image(&a) - image(&b)) / (2.0 * h)));
    }
    jac
}

/// The exact n-period map Jacobian at the Newton fixed point from a settled state.
fn orbit(sys: &System, map: MapKind) -> solver::Solution {
    let (y, _) = settled(sys);
    let mut sim = Simulator::new(sys, Accuracy::default(), Method::Exact, &y).unwrap();
    solve(&mut sim, &DVector::from_vec(y), map, None, NEWTON).expect("Newton converges")
}

/// Issue 6: without impacts the multipliers are `exp(λ_i T)` of the linear
/// oscillator's eigenvalues, to 1e-12.
#[test]
fn linear_oscillator_multipliers_are_exponentials() {
    for (omega, zeta) in [(2.5, 0.1), (0.7, 0.05), (1.3, 0.3)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("delta", 50.0), ("zeta", zeta)]);
        let sol = orbit(&sys, MapKind::Periods(1));
        let m = sys.dof();
        let minv = DMatrix::from_diagonal(&sys.mass.map(|v| 1.0 / v));
        let mut a = DMatrix::zeros(2 * m, 2 * m);
        a.view_mut((0, m), (m, m)).fill_with_identity();
        a.view_mut((m, 0), (m, m)).copy_from(&(-&minv * &sys.stiffness));
        a.view_mut((m, m), (m, m)).copy_from(&(-&minv * &sys.damping));
        let mut want: Vec<Complex64> = a.complex_eigenvalues().iter().map(|l| (l * sys.period).exp()).collect();
        let got = multipliers(&sol.jacobian);
        assert_eq!(got.len(), want.len());
        for g in &got {
            // Pair each multiplier with the nearest exponential not yet taken.
            let i = (0..want.len()).min_by(|&i, &j| (g - want[i]).norm().total_cmp(&(g - want[j]).norm())).unwrap();
            let w = want.swap_remove(i);
            assert!((g - w).norm() < 1e-12, "ω = {omega}: {g} against {w}");
        }
    }
}

/// Issue 6: the exact Jacobian through impacts (and stick/slip) equals finite
/// differences of the simulated map, so the multipliers agree to 1e-6.
#[test]
fn jacobian_through_events_matches_finite_differences() {
    let cases: [(&str, Vec<(&str, f64)>); 4] = [
        ("single-stop.toml", vec![("omega", 2.5)]),
        ("single-stop.toml", vec![("omega", 1.7), ("zeta", 0.05)]),
        ("multi-stop.toml", vec![("omega", 0.33), ("delta", 0.6)]),
        ("dry-friction.toml", vec![("omega", 2.0), ("fk", 0.1)]),
    ];
    for (file, sets) in cases {
        let sys = system(file, &sets);
        let (_, n) = settled(&sys);
        let sol = orbit(&sys, MapKind::Periods(n));
        let fd = finite_differences(&sys, &sol.x, n);
        let err = (&sol.jacobian - &fd).amax() / (1.0 + fd.amax());
        assert!(err < 1e-6, "{file} {sets:?}: Jacobian differs from finite differences by {err:e}");
        let (a, b) = (multipliers(&sol.jacobian), multipliers(&fd));
        for (x, y) in a.iter().zip(&b) {
            assert!((x.norm() - y.norm()).abs() < 1e-6, "{file} {sets:?}: |μ| {} against {}", x.norm(), y.norm());
        }
    }
}

/// Issue 6: the largest Lyapunov exponent of a periodic orbit equals
/// `ln|μ_max| / (nT)`, to 1e-6.
#[test]
fn lyapunov_exponent_of_a_periodic_orbit() {
    // Orbits whose leading multiplier is real (with a complex leading pair a
    // finite average oscillates about the limit by O(1/periods)).
    for (file, sets) in [("multi-stop.toml", vec![("omega", 0.295), ("delta", 0.6)]), ("symmetric-stops.toml", vec![])]
    {
        let sys = system(file, &sets);
        let (_, n) = settled(&sys);
        let sol = orbit(&sys, MapKind::Periods(n));
        let mu = multipliers(&sol.jacobian);
        assert!(mu[0].im.abs() < 1e-12 && mu[0].norm() > mu[1].norm() + 0.05, "{file}: leading multipliers {mu:?}");
        let expected = mu[0].norm().ln() / (n as f64 * sys.period);
        let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, sol.x.as_slice()).unwrap();
        let lambda = solver::Exponent::measure(&mut sim, 200, 100 * n).unwrap().per_time();
        assert!((lambda - expected).abs() < 1e-6, "{file}: λ = {lambda} against ln|μ|/T = {expected}");
    }
}

/// Issue 5: the early look of `chaos_check` ends the record of a chaotic cell
/// at a third of the periods, with the same class and a positive exponent, and
/// leaves a cell that settles only after it (a slow periodic transient) exactly
/// as it was: the look runs on a copy of the trajectory.
#[test]
fn chaos_check_ends_chaotic_records_only() {
    let run = |omega: f64, delta: f64, check: usize| {
        let sys = system("multi-stop.toml", &[("omega", omega), ("delta", delta)]);
        let acc = Accuracy::default().with(solver::Knob::ChaosCheck, check as f64).unwrap();
        (solver::run_cell(&sys, &acc, Method::Exact, &sys.model.initial_state()), sys.period)
    };
    for (omega, delta) in [(1.05, 0.05), (1.1, 0.2)] {
        let ((full, period), (early, _)) = (run(omega, delta, 0), run(omega, delta, 100));
        for c in [&full, &early] {
            assert_eq!(c.class, solver::Class::Chaotic, "ω {omega}, δ {delta}");
            assert!(c.lyapunov.unwrap() * period > 0.05, "ω {omega}: λ {:?}", c.lyapunov);
        }
        assert!(full.periods > 600 && early.periods < 300, "ω {omega}: {} and {} periods", full.periods, early.periods);
    }
    let ((full, _), (early, _)) = (run(0.98, 0.34, 0), run(0.98, 0.34, 100));
    assert_eq!(full.n, Some(4));
    // The early look happened (its tangent periods are counted) and changed nothing else.
    assert!(early.periods >= full.periods + 100, "{} against {} periods", early.periods, full.periods);
    assert_eq!((&early.labels, &early.final_state, &early.impacts), (&full.labels, &full.final_state, &full.impacts));
}

/// Issue 6: the Newton fixed point (from a perturbed start, also valid for an
/// orbit simulation reaches only slowly) reproduces the impact phases of the
/// orbit reached by long plain simulation, to 1e-10.
#[test]
fn newton_fixed_point_reproduces_simulated_impact_phases() {
    let sys = system("multi-stop.toml", &[("omega", 0.33), ("delta", 0.6)]);
    let acc = Accuracy::default()
        .with(solver::Knob::Newton, 0.0)
        .and_then(|a| a.with(solver::Knob::MaxPeriods, 3e3))
        .and_then(|a| a.with(solver::Knob::PeriodicTol, 1e-13))
        .unwrap();
    let cell = solver::run_cell(&sys, &acc, Method::Exact, &sys.model.initial_state());
    assert_eq!(cell.n, Some(1));
    let phases = |x: &[f64]| {
        let (rec, _) = crate::util::record(&sys, &Accuracy::default(), Method::Exact, x, 1);
        rec.impacts.iter().map(|i| (i.stop, i.time)).collect::<Vec<_>>()
    };
    let simulated = phases(&cell.final_state);
    let mut start = DVector::from_vec(cell.final_state.clone());
    start.iter_mut().for_each(|v| *v *= 1.0 + 1e-3);
    let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, start.as_slice()).unwrap();
    let sol = solve(&mut sim, &start, MapKind::Periods(1), None, NEWTON).unwrap();
    let solved = phases(sol.x.as_slice());
    assert_eq!(simulated.len(), solved.len());
    assert!(simulated.len() >= 8);
    for (a, b) in simulated.iter().zip(&solved) {
        assert_eq!(a.0, b.0);
        assert!((a.1 - b.1).abs() < 1e-10, "impact time {} against {}", a.1, b.1);
    }
}

/// Issue 6: a period doubling seen in a sweep (1-3-2 at ω = 1.1825, 2-6-4 at
/// 1.18, δ = 0.2) is located by `continue` within that sweep step, with a
/// multiplier at −1.
#[test]
fn continue_locates_the_period_doubling_of_a_sweep() {
    let sweep = json_of(&[
        "sweep",
        "configs/multi-stop.toml",
        "--set",
        "delta=0.2",
        "--axis",
        "omega=1.19:1.175:7",
        "--json",
        "--quiet",
    ]);
    let labels: Vec<(f64, String)> = sweep["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["value"].as_f64().unwrap(), p["labels"]["M1"].as_str().unwrap().to_string()))
        .collect();
    let step = labels.windows(2).find(|w| w[0].1 == "1-3-2" && w[1].1 == "2-6-4").expect("1-3-2 → 2-6-4 in the sweep");
    let cont = json_of(&[
        "continue",
        "configs/multi-stop.toml",
        "--set",
        "delta=0.2",
        "--axis",
        "omega=1.2:1.17:13",
        "--json",
    ]);
    let pd: Vec<&serde_json::Value> =
        cont["bifurcations"].as_array().unwrap().iter().filter(|b| b["kind"] == "PD").collect();
    assert_eq!(pd.len(), 1, "{cont}");
    let v = pd[0]["value"].as_f64().unwrap();
    assert!(v <= step[0].0 && v >= step[1].0, "PD at {v}, sweep step [{}, {}]", step[1].0, step[0].0);
    let critical = &pd[0]["critical"];
    assert!((critical["re"].as_f64().unwrap() + 1.0).abs() < 1e-6, "{critical}");
    // The branch is stable before and unstable after.
    let branch = cont["branch"].as_array().unwrap();
    assert_eq!(branch[0]["stable"], true);
    assert_eq!(branch.last().unwrap()["stable"], false);
}

/// Issue 6: the impact damper's symmetric period-one double-impact orbit loses
/// stability by a Neimark–Sacker bifurcation; past it the impacts are
/// quasi-periodic, and further on chaotic.
#[test]
fn impact_damper_neimark_sacker_then_torus_then_chaos() {
    let sets = ["--set", "R=0.8", "--set", "mu=0.2", "--set", "zeta=0.1", "--set", "delta=2.0"];
    let mut args = vec!["continue", "configs/impact-damper.toml"];
    args.extend_from_slice(&sets);
    args.extend_from_slice(&["--axis", "omega=1.3:1.6:31", "--json"]);
    let cont = json_of(&args);
    let first = &cont["branch"][0];
    assert_eq!(first["labels"]["M2"], "1-1-1");
    assert_eq!(first["symmetry"], "S");
    let ns = cont["bifurcations"].as_array().unwrap().iter().find(|b| b["kind"] == "NS").expect("an NS point");
    let v = ns["value"].as_f64().unwrap();
    let c = &ns["critical"];
    assert!((c["abs"].as_f64().unwrap() - 1.0).abs() < 1e-6, "{c}");
    let arg = c["arg"].as_f64().unwrap().abs();
    assert!(arg > 0.1 && (arg - std::f64::consts::PI).abs() > 0.1, "a complex pair: arg {arg}");
    // Follow the attractor up in ω (a sweep continues from each cell's end state).
    let mut args = vec!["sweep", "configs/impact-damper.toml"];
    args.extend_from_slice(&sets);
    args.extend_from_slice(&["--axis", "omega=1.3:1.6:31", "--json", "--quiet"]);
    let sweep = json_of(&args);
    let class_at = |w: f64| {
        let distance = |p: &&serde_json::Value| (p["value"].as_f64().unwrap() - w).abs();
        let p = sweep["points"].as_array().unwrap().iter().min_by(|a, b| distance(a).total_cmp(&distance(b))).unwrap();
        p["class"].as_str().unwrap().to_string()
    };
    // Grid step 0.01: the last point before the NS value, the first after it.
    assert_eq!(class_at(v - 0.006), "periodic");
    assert_eq!(class_at(v + 0.006), "quasiperiodic", "just past the NS point at {v}");
    assert_eq!(class_at(v + 0.05), "chaotic");
    // A fresh cell too (the free mass thrown, so that it impacts from the start):
    // quasi-periodic just past the NS point, chaotic further on, with its exponent.
    let cell = |w: f64| {
        let omega = format!("omega={w}");
        let mut args = vec!["cell", "configs/impact-damper.toml", "--set", omega.as_str(), "--set", "v20=2"];
        args.extend_from_slice(&sets);
        args.push("--json");
        json_of(&args)
    };
    // A fresh cell's transient may also end on a drifting, non-impacting motion:
    // ω = 1.6 is well inside the chaotic band.
    assert!(v + 0.02 < 1.6);
    let (q, c) = (cell(v + 0.01), cell(1.6));
    assert_eq!(q["class"], "quasiperiodic", "{q}");
    assert_eq!(q["labels"]["M2"], "Q");
    assert!(q["lyapunov"].as_f64().unwrap().abs() * 2.0 * std::f64::consts::PI / (v + 0.01) < 0.01);
    assert_eq!(c["class"], "chaotic", "{c}");
    assert!(c["lyapunov"].as_f64().unwrap() > 0.05, "{c}");
}

/// Issue 6: `continue` stops at the fold of the undamped single-stop (1,1)
/// orbit (a saddle-node, a multiplier at +1) where the closed form puts it, to
/// 1e-8 in the parameter.
#[test]
fn continue_locates_the_closed_form_fold() {
    let cont = json_of(&["continue", "configs/single-stop.toml", "--axis", "sigma=0:-1.5:31", "--json"]);
    let sn: Vec<&serde_json::Value> =
        cont["bifurcations"].as_array().unwrap().iter().filter(|b| b["kind"] == "SN").collect();
    assert_eq!(sn.len(), 1, "{}", cont["bifurcations"]);
    let expected = solver::reference::single_stop_fold_sigma(2.5, 0.8, 1);
    let got = sn[0]["value"].as_f64().unwrap();
    assert!((got - expected).abs() < 1e-8, "fold at {got}, closed form {expected}");
    assert!((sn[0]["critical"]["re"].as_f64().unwrap() - 1.0).abs() < 0.05);
}

/// Issue 6: pseudo-arclength continuation goes around that fold: it locates it
/// at the closed-form value and follows the unstable branch back.
#[test]
fn arclength_goes_around_the_fold() {
    let cont = json_of(&["continue", "configs/single-stop.toml", "--axis", "sigma=0:-1.5:31", "--arclength", "--json"]);
    let expected = solver::reference::single_stop_fold_sigma(2.5, 0.8, 1);
    let sn = cont["bifurcations"].as_array().unwrap().iter().find(|b| b["kind"] == "SN").expect("a fold");
    let got = sn["value"].as_f64().unwrap();
    assert!((got - expected).abs() < 1e-8, "fold at {got}, closed form {expected}");
    let branch = cont["branch"].as_array().unwrap();
    let values: Vec<f64> = branch.iter().map(|p| p["value"].as_f64().unwrap()).collect();
    let turn = values.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
    assert!(turn > 0 && turn + 5 < values.len(), "the branch turns back: {values:?}");
    assert!(values[turn] >= expected - 1e-9, "never past the fold");
    // Stable before the fold, unstable after it.
    assert_eq!(branch[1]["stable"], true);
    assert_eq!(branch[turn + 3]["stable"], false);
    assert!(values[turn + 5] > values[turn + 1], "the parameter grows again on the unstable branch");
}

/// A pseudo-arclength branch ends on the edge of its range, not a step past
/// it (the audit: `omega=2.5:2.6:2` ended at 2.6178): its last point is at
/// 2.6, its orbit the one natural continuation solves there.
#[test]
fn arclength_ends_on_the_edge_of_its_range() {
    let branch = |extra: &[&str]| {
        let mut args = vec!["continue", "configs/single-stop.toml", "--axis", "omega=2.5:2.6:2", "--json"];
        args.extend_from_slice(extra);
        json_of(&args)["branch"].as_array().unwrap().last().unwrap().clone()
    };
    let (arc, natural) = (branch(&["--arclength"]), branch(&[]));
    assert_eq!(arc["value"].as_f64(), Some(2.6), "{arc}");
    let state = |p: &serde_json::Value| -> Vec<f64> {
        p["fixed_point"].as_array().unwrap_or_else(|| panic!("{p}")).iter().map(|v| v.as_f64().unwrap()).collect()
    };
    for (a, b) in state(&arc).iter().zip(state(&natural)) {
        assert!((a - b).abs() < 1e-9, "{arc} against {natural}");
    }
    // One that turns back to where it started says so (the re-audit: a
    // 4-4-0 branch of the damped single stop reversed on itself and ended
    // silently at its start).
    let args = ["continue", "configs/single-stop.toml", "--set", "zeta=0.05", "--set", "sigma=0.1", "--set", "r=0.66"];
    let back = json_of(&[&args[..], &["--axis", "omega=2.5:2.4:11", "--arclength", "--json"]].concat());
    let ended = back["ended"].as_str().unwrap_or_else(|| panic!("{back}"));
    assert!(ended.starts_with("turned back to the start of the range, 2.5"), "{ended}");
}

/// Issue 20: `curve` follows the fold of the undamped single-stop (1,1) orbit
/// in the (σ, ω) plane; at every ω it passes through the closed-form fold.
#[test]
fn fold_curve_matches_the_closed_form() {
    let start = solver::reference::single_stop_fold_sigma(2.5, 0.8, 1);
    let j = single_stop_fold(&format!("sigma={start},omega=2.5"), "sigma,omega", "2.8", "3", "1");
    let points = j["points"].as_array().unwrap();
    assert_eq!(points.len(), 4, "{j}");
    for p in points {
        let (sigma, omega) = (p["sigma"].as_f64().unwrap(), p["omega"].as_f64().unwrap());
        let expected = solver::reference::single_stop_fold_sigma(omega, 0.8, 1);
        assert!((sigma - expected).abs() < 1e-7, "ω = {omega}: fold at σ = {sigma}, closed form {expected}");
    }
    assert_eq!(j["kind"], "SN");
    assert_eq!(j["free"], serde_json::json!(["sigma", "omega"]));
}

/// Issue 20: the pitchfork of the dry-friction 1-1-1 orbit followed in the
/// (ω, fk) plane passes through the published values at fk = 0.01, 0.05 and
/// 0.1 (ω = 6.844, 6.81, 6.745), where it breaks the symmetry.
#[test]
fn pitchfork_curve_passes_through_the_published_values() {
    let j = json_of(&crate::util::pitchfork("0.1", "9", &["--json"]));
    let points = j["points"].as_array().unwrap();
    assert_eq!(points.len(), 10, "{j}");
    for (fk, omega) in [(0.01, 6.844), (0.05, 6.81), (0.1, 6.745)] {
        let p = points.iter().find(|p| (p["fk"].as_f64().unwrap() - fk).abs() < 1e-9).unwrap();
        assert!((p["omega"].as_f64().unwrap() - omega).abs() < 3e-3, "fk = {fk}: {p}");
        assert_eq!(p["labels"]["above"]["symmetry"], "S", "{p}");
        assert_eq!(p["labels"]["below"]["symmetry"], "AS", "{p}");
    }
}

/// Issue 20: the grazing curve that bounds 1-3-3 in the multi-stop scene passes
/// through the published grazing point at δ = 0.7 (ω ≈ 0.3147), 1-3-3 above it
/// and 1-4-4 below, and goes on to larger δ.
#[test]
fn grazing_curve_passes_through_the_published_point() {
    let j = json_of(&[
        "curve",
        "configs/multi-stop.toml",
        "--kind",
        "grazing",
        "--start",
        "omega=0.3147,delta=0.7",
        "--free",
        "omega,delta",
        "--to",
        "0.8",
        "--steps",
        "4",
        "--window",
        "0.01",
        "--json",
    ]);
    let points = j["points"].as_array().unwrap();
    assert_eq!(points.len(), 5, "{j}");
    let first = &points[0];
    assert!((first["omega"].as_f64().unwrap() - 0.3147).abs() < 3e-4, "{first}");
    assert_eq!(first["labels"]["above"]["M1"], "1-3-3");
    assert_eq!(first["labels"]["below"]["M1"], "1-4-4");
    let omegas: Vec<f64> = points.iter().map(|p| p["omega"].as_f64().unwrap()).collect();
    assert!(omegas.windows(2).all(|w| w[1] < w[0] && w[0] - w[1] < 0.02), "{omegas:?}");
}

/// A curve of an orbit that coexists with the one a cell from the scene's
/// initial state reaches starts from `--state`: the damped single stop's
/// flight without impacts (1-0-0) grazes where its amplitude
/// 1/√((1 − ω²)² + (2ζω)²) reaches the stop, σ; at ζ = 0.05, σ = 0.5 a 1-1-0
/// wins from the scene's start on both ends of the first line, so no grazing
/// is found there, while from a state on the flight (its closed form at
/// t = 0, ω = 1.73) every point lies on the closed-form grazing to 1e-10. A
/// state of the wrong length is refused naming `--state`.
#[test]
fn a_curve_starts_from_a_given_state_on_a_coexisting_orbit() {
    let (zeta, omega) = (0.05f64, 1.73f64);
    let d = (1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2);
    let state = format!("--state={},{}", (1.0 - omega * omega) / d, 2.0 * zeta * omega * omega / d);
    let args = |extra: &[&str]| {
        let mut a = vec!["curve", "configs/single-stop.toml", "--set", "zeta=0.05", "--kind", "grazing"];
        a.extend(["--start", "omega=1.73,sigma=0.5", "--free", "omega,sigma", "--to", "0.6", "--steps", "4", "--json"]);
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let fresh = json_of(&args(&[]).iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(fresh["points"].as_array().map(Vec::len), Some(0), "{fresh}");
    let given = args(&[state.as_str()]);
    let j = json_of(&given.iter().map(String::as_str).collect::<Vec<_>>());
    let points = j["points"].as_array().unwrap();
    assert_eq!(points.len(), 5, "{j}");
    for p in points {
        let (w, sigma) = (p["omega"].as_f64().unwrap(), p["sigma"].as_f64().unwrap());
        let amplitude = 1.0 / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
        assert!((amplitude - sigma).abs() < 1e-10, "ω = {w}: amplitude {amplitude}, σ = {sigma}");
    }
    let short = args(&["--state=0.1"]);
    let out = crate::util::run(&short.iter().map(String::as_str).collect::<Vec<_>>());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.starts_with("error: --state: the scene's state has 2 numbers") && err.lines().count() == 1, "{err}");
}

/// Issue 28: without `--to` a curve is followed both ways from its start,
/// within the scene's range of B: the dry-friction pitchfork down to fk = 0,
/// where fk's range ends, and up until its 10 × 2 + 1 points run out; one
/// curve in order of fk, both ends said.
#[test]
fn a_curve_without_to_is_followed_both_ways_within_the_scene() {
    let j = json_of(&[
        "curve",
        "configs/dry-friction.toml",
        "--kind",
        "pf",
        "--start",
        "omega=6.845,fk=0.01",
        "--free",
        "omega,fk",
        "--steps",
        "2",
        "--json",
    ]);
    let fk: Vec<f64> = j["points"].as_array().unwrap().iter().map(|p| p["fk"].as_f64().unwrap()).collect();
    assert!(fk[0].abs() < 1e-12 && fk.windows(2).all(|w| w[0] < w[1]), "{fk:?}");
    assert!(fk.iter().any(|f| (f - 0.01).abs() < 1e-12), "the start is a point: {fk:?}");
    assert_eq!(fk.len(), 22, "{j}");
    assert_eq!(j["ended"], "reached fk = 0; 21 points");
}

/// Issue 20: the Neimark–Sacker curve of the impact damper's symmetric 1-1-1
/// in (ω, δ) passes through the NS point `continue` finds at δ = 2, with the
/// symmetric orbit below it and quasi-periodic motion above.
#[test]
fn neimark_sacker_curve_passes_through_the_located_point() {
    let cont = json_of(&["continue", "configs/impact-damper.toml", "--axis", "omega=1.3:2.3:101", "--json"]);
    let ns =
        cont["bifurcations"].as_array().unwrap().iter().find(|b| b["kind"] == "NS").unwrap()["value"].as_f64().unwrap();
    let j = json_of(&[
        "curve",
        "configs/impact-damper.toml",
        "--kind",
        "ns",
        "--start",
        &format!("omega={ns},delta=2"),
        "--free",
        "omega,delta",
        "--to",
        "2.2",
        "--steps",
        "4",
        "--window",
        "0.02",
        "--json",
    ]);
    let points = j["points"].as_array().unwrap();
    assert_eq!(points.len(), 5, "{j}");
    assert!((points[0]["omega"].as_f64().unwrap() - ns).abs() < 1e-8);
    assert_eq!(points[0]["labels"]["below"]["M2"], "1-1-1");
    assert_eq!(points[0]["labels"]["above"]["M2"], "Q");
}

/// Issue 20: the fold of the single-stop (1,1) orbit followed in (ω, σ) from
/// ω = 2.1 towards larger σ. Natural steps in σ stop short of the top of the
/// curve; pseudo-arclength goes on, every point on the closed-form fold, and
/// the curve ends where the fold's orbit grazes the stop between impacts: an
/// SN-grazing codimension-two point at the ω where the closed-form orbit's
/// overshoot changes sign (found here by bisection).
#[test]
fn fold_curve_is_followed_to_its_meeting_with_a_grazing() {
    let sigma0 = solver::reference::single_stop_fold_sigma(2.1, 0.8, 1);
    let j = single_stop_fold(&format!("omega=2.1,sigma={sigma0}"), "omega,sigma", "-0.2", "6", "0.05");
    let points = j["points"].as_array().unwrap();
    for p in points {
        let (omega, sigma) = (p["omega"].as_f64().unwrap(), p["sigma"].as_f64().unwrap());
        let expected = solver::reference::single_stop_fold_sigma(omega, 0.8, 1);
        assert!((sigma - expected).abs() < 1e-9, "ω = {omega}: σ = {sigma}, closed form {expected}");
    }
    // The natural steps reach σ = -0.354 at most (the next, -0.303, is above the curve).
    let top = points.iter().map(|p| p["sigma"].as_f64().unwrap()).fold(f64::MIN, f64::max);
    assert!(top > -0.34, "the curve was followed past its natural steps: top σ = {top}");
    let (mut lo, mut hi) = (2.0, 2.05);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if solver::reference::single_stop_fold_overshoot(mid, 0.8) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let codim2 = j["codim2"].as_array().unwrap();
    assert_eq!(codim2.len(), 1, "{j}");
    assert_eq!(codim2[0]["kind"], "SN-grazing");
    let omega = codim2[0]["omega"].as_f64().unwrap();
    assert!((omega - lo).abs() < 1e-4, "SN-grazing at ω = {omega}, closed form {lo}");
    assert!(j["ended"].as_str().unwrap().contains("SN-grazing"), "{j}");
}

/// `curve --json` of the single-stop fold (r = 0.8) from `start` in the plane
/// of `free`, to `to` in `steps` steps, with a window `window`.
fn single_stop_fold(start: &str, free: &str, to: &str, steps: &str, window: &str) -> serde_json::Value {
    let to = format!("--to={to}");
    json_of(&[
        "curve",
        "configs/single-stop.toml",
        "--kind",
        "sn",
        "--start",
        start,
        "--free",
        free,
        &to,
        "--steps",
        steps,
        "--window",
        window,
        "--json",
    ])
}

/// An orbit solved on a multiple of its own period says so: the state after
/// its least period is back at the fixed point (a 1-1-0 asked for with n = 3
/// closes after 1 period, a 2-1-0 asked for with n = 4 after 2), and an orbit
/// of its own period has `least_period == n`.
#[test]
fn an_orbit_solved_on_a_multiple_of_its_period_names_its_least_period() {
    let acc = Accuracy::default();
    let once = system("single-stop.toml", &[("omega", 2.5)]);
    let y = once.model.initial_state();
    let o = solver::orbit_of_cell(&once, &acc, &y, Some(3)).unwrap();
    assert_eq!((o.n, o.least_period, o.labels[0].to_string()), (3, 1, "3-3-0".to_string()));
    let twice = system("single-stop.toml", &[("omega", 3.2), ("sigma", 0.1), ("zeta", 0.05)]);
    let y = twice.model.initial_state();
    let own = solver::orbit_of_cell(&twice, &acc, &y, None).unwrap();
    assert_eq!((own.n, own.least_period, own.labels[0].to_string()), (2, 2, "2-1-0".to_string()));
    let four = solver::orbit_of_cell(&twice, &acc, &y, Some(4)).unwrap();
    assert_eq!((four.n, four.least_period), (4, 2));
    // Through the CLI: the JSON field and the text's note.
    let j = json_of(&["orbit", "configs/single-stop.toml", "--set", "omega=2.5", "--n", "2", "--json"]);
    assert_eq!((j["n"].as_u64(), j["least_period"].as_u64()), (Some(2), Some(1)), "{j}");
}
