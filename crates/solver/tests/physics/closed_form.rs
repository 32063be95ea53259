//! Closed-form checks of the exact solver (issue 2).

use crate::common::{record, system};
use solver::reference::{free_amplitude, single_stop_impact_speeds};
use solver::{run_cell, Accuracy, Class, Method, Preset};

fn tight() -> Accuracy {
    Accuracy::preset(Preset::Precise)
        .with(solver::Knob::PeriodicTol, 1e-13)
        .and_then(|a| a.with(solver::Knob::MaxPeriods, 4000.0))
        .unwrap()
}

/// Issue 2: the no-impact steady-state amplitude of M1 equals 1/√((1-ω²)² + (2ζω)²).
#[test]
fn free_steady_state_amplitude() {
    for &(omega, zeta) in &[(0.5, 0.1), (1.3, 0.1), (2.5, 0.06), (0.9, 0.25)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("zeta", zeta), ("delta", 8.0)]);
        let cell = run_cell(&sys, &tight(), Method::Exact, &sys.model.initial_state());
        assert_eq!(cell.class, Class::Periodic);
        assert_eq!(cell.labels[0].to_string(), "1-0-0");
        let (x, v) = (cell.final_state[0], cell.final_state[2]);
        let amp = (x * x + (v / omega).powi(2)).sqrt();
        let exact = free_amplitude(omega, zeta);
        assert!((amp - exact).abs() < 1e-10, "omega {omega}: {amp} vs {exact}");
    }
}

/// Issue 2: the single-stop (1, n) orbits' impact speed equals the closed form.
#[test]
fn single_stop_impact_speed() {
    let cases = [
        (2.0, 0.0, 0.8, 1),
        (2.5, 0.0, 0.5, 1),
        (2.5, -0.1, 0.8, 1),
        (2.0, 0.1, 0.5, 1),
        (3.5, 0.0, 0.5, 2),
        (4.0, 0.0, 0.8, 2),
    ];
    for &(omega, sigma, r, n) in &cases {
        let sys = system("single-stop.toml", &[("omega", omega), ("sigma", sigma), ("r", r)]);
        let cell = run_cell(&sys, &tight(), Method::Exact, &sys.model.initial_state());
        assert_eq!(cell.n, Some(n as usize), "omega {omega} sigma {sigma} r {r}");
        assert_eq!(cell.impacts, vec![1]);
        let (rec, _) = record(&sys, &tight(), Method::Exact, &cell.final_state, n as usize);
        let v = rec.impacts[0].before[1];
        let roots = single_stop_impact_speeds(omega, sigma, r, n);
        let best = roots.iter().map(|x| (x - v).abs()).fold(f64::INFINITY, f64::min);
        assert!(best < 1e-9, "omega {omega} sigma {sigma} r {r}: V = {v}, roots {roots:?}");
        // And the rebound follows the restitution law.
        assert!((rec.impacts[0].after[1] + r * v).abs() < 1e-14);
    }
}

/// Issue 2: momentum is conserved and the restitution law holds at every
/// two-mass impact; kinetic energy never increases at an impact.
#[test]
fn impact_laws_hold_at_every_impact() {
    for &(omega, delta, mu_m) in &[(0.33, 0.6, 0.5), (0.295, 0.6, 0.25), (0.2, 0.6, 0.75), (1.1, 0.2, 0.05)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("delta", delta), ("mu_m", mu_m)]);
        let r = sys.model.parameter("R").unwrap();
        let (rec, _) = record(&sys, &Accuracy::default(), Method::Exact, &sys.model.initial_state(), 40);
        assert!(rec.impacts.len() > 20);
        let mut pair = 0;
        for imp in &rec.impacts {
            let (b, a) = (&imp.before, &imp.after);
            assert!(sys.kinetic_energy(a) <= sys.kinetic_energy(b) * (1.0 + 1e-14));
            if sys.model.stops[imp.stop].name == "A12" {
                pair += 1;
                let (pb, pa) = (sys.momentum(b), sys.momentum(a));
                assert!((pa - pb).abs() <= 1e-13 * (1.0 + pb.abs()), "momentum {pb} -> {pa}");
                let (rb, ra) = (b[2] - b[3], a[2] - a[3]);
                assert!((ra + r * rb).abs() <= 1e-13 * (1.0 + rb.abs()), "relative velocity {rb} -> {ra}");
            }
        }
        assert!(pair > 0, "omega {omega}: no two-mass impact");
    }
}

/// Issue 2: the impact damper's free mass flies on an exact straight line
/// between impacts (zero eigenvalues handled exactly, not perturbed).
#[test]
fn free_mass_flight_is_exact() {
    let sys = system("impact-damper.toml", &[("omega", 1.0), ("delta", 0.5), ("mu", 0.2)]);
    let (rec, _) = record(&sys, &Accuracy::default(), Method::Exact, &[0.3, 0.0, 0.0, 0.7], 30);
    assert!(rec.impacts.len() > 20);
    for w in rec.impacts.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let dt = b.time - a.time;
        assert!((b.before[3] - a.after[3]).abs() < 1e-13, "velocity changed in flight");
        let x = a.after[1] + a.after[3] * dt;
        assert!((b.before[1] - x).abs() < 1e-11 * (1.0 + dt), "position off the line by {}", b.before[1] - x);
    }
}

/// The quantities of the window of a cell from `sys`'s initial state: its
/// orbit's n periods, else 16.
fn window_quantities(sys: &solver::System) -> std::collections::BTreeMap<String, f64> {
    let cell = run_cell(sys, &Accuracy::default(), Method::Exact, &sys.model.initial_state());
    let q = solver::quantity::measure(sys, &Accuracy::default(), &cell.final_state, cell.n.unwrap_or(16)).unwrap();
    solver::quantity::named(sys, &q).into_iter().collect()
}

/// The quantities of a cell's steady motion over its orbit's n periods.
fn quantities(sys: &solver::System, acc: &Accuracy) -> (solver::CellResult, std::collections::BTreeMap<String, f64>) {
    let cell = run_cell(sys, acc, Method::Exact, &sys.model.initial_state());
    let n = cell.n.unwrap_or_else(|| panic!("{}: not periodic ({:?})", sys.model.name, cell.class));
    let q = solver::quantity::measure(sys, acc, &cell.final_state, n).unwrap();
    (cell, solver::quantity::named(sys, &q).into_iter().collect())
}

/// Issue 60: the linear forced oscillator, its stops out of reach: M1's
/// largest |x| is the closed-form amplitude A = 1/|1 − ω² + 2iζω| to 1e-10;
/// its peak to peak 2A, its rms A/√2, its largest |v| Aω, its mean 0; the
/// input power equals the damping's dissipation per period.
#[test]
fn quantities_of_the_linear_oscillator() {
    for &(omega, zeta) in &[(0.5, 0.1), (1.3, 0.1), (2.5, 0.06), (0.9, 0.25)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("zeta", zeta), ("delta", 8.0)]);
        let (_, q) = quantities(&sys, &tight());
        let a = free_amplitude(omega, zeta);
        for (name, want) in [
            ("max_abs_x_M1", a),
            ("ptp_x_M1", 2.0 * a),
            ("rms_x_M1", a / 2f64.sqrt()),
            ("max_abs_v_M1", a * omega),
            ("rms_v_M1", a * omega / 2f64.sqrt()),
            ("mean_x_M1", 0.0),
        ] {
            assert!((q[name] - want).abs() < 1e-10, "omega {omega}: {name} {} against {want}", q[name]);
        }
        assert_eq!(q["impact_rate_A1"], 0.0);
        assert!(q["energy_residual"].abs() < 1e-9, "omega {omega}: residual {}", q["energy_residual"]);
        let period = 2.0 * std::f64::consts::PI / omega;
        let balance = q["power_in"] * period - q["dissipated_damping"];
        assert!(balance.abs() < 1e-10 * q["dissipated_damping"], "omega {omega}: {balance}");
    }
}

/// Issue 60: a quantity the scene defines, the damper's `attenuation`
/// (`[quantities]` of configs/impact-damper.toml, M1's amplitude against the
/// bare primary's, in dB): with the free mass at rest and its walls out of
/// reach, M1 is the bare primary, so 0 dB to the accuracy of its amplitude
/// (`precise`: 1e-9 of it).
#[test]
fn a_defined_quantity_of_the_bare_primary() {
    for &(omega, zeta) in &[(0.5, 0.1), (1.5, 0.1), (2.1, 0.1), (0.9, 0.25)] {
        let sys = system("impact-damper.toml", &[("omega", omega), ("zeta", zeta), ("delta", 100.0), ("v20", 0.0)]);
        let (_, q) = quantities(&sys, &Accuracy::preset(Preset::Precise));
        assert!((q["max_abs_x_M1"] - free_amplitude(omega, zeta)).abs() < 1e-9, "omega {omega}: {q:?}");
        assert!(q["attenuation"].abs() < 1e-8, "omega {omega}: attenuation {} dB", q["attenuation"]);
    }
}

/// Issue 60: the single-stop (1, n) orbits at ζ = 0: the impact speed is the
/// closed form's V to 1e-10 and the impulse per period (1 + r) V / n; every
/// joule put in is lost in the impacts.
#[test]
fn quantities_of_single_stop_orbits() {
    for &(omega, sigma, r, n) in &[(2.0, 0.0, 0.8, 1), (2.5, -0.1, 0.8, 1), (2.0, 0.1, 0.5, 1), (3.5, 0.0, 0.5, 2)] {
        let sys = system("single-stop.toml", &[("omega", omega), ("sigma", sigma), ("r", r)]);
        let (cell, q) = quantities(&sys, &tight());
        assert_eq!(cell.n, Some(n as usize));
        let roots = single_stop_impact_speeds(omega, sigma, r, n);
        let v = q["impact_speed_max_A"];
        let best = roots.iter().map(|x| (x - v).abs()).fold(f64::INFINITY, f64::min);
        assert!(best < 1e-10, "omega {omega}: V = {v}, roots {roots:?}");
        assert_eq!(q["impact_speed_mean_A"].to_bits(), v.to_bits());
        assert!((q["impulse_A"] - (1.0 + r) * v / n as f64).abs() < 1e-10, "{}", q["impulse_A"]);
        assert!((q["impact_rate_A"] - 1.0 / n as f64).abs() < 1e-15);
        assert!(q["energy_residual"].abs() < 1e-9, "residual {}", q["energy_residual"]);
        assert_eq!(q["dissipated_damping"], 0.0);
        let lost = 0.5 * (1.0 - r * r) * v * v / n as f64;
        assert!((q["dissipated_impacts"] - lost).abs() < 1e-9 * lost, "{} against {lost}", q["dissipated_impacts"]);
    }
}

/// Issue 60: the energy balances on a periodic cell of every shipped scene
/// (their default parameters, and a few more cells): what the forcing puts
/// in over the orbit, the damping, impacts, soft contacts and friction take
/// out, to 1e-9 of the input.
#[test]
fn energy_balances_on_every_shipped_scene() {
    let cases: [(&str, &[(&str, f64)]); 9] = [
        ("multi-stop.toml", &[]),
        ("multi-stop.toml", &[("omega", 1.0), ("delta", 1.2)]),
        ("single-stop.toml", &[("zeta", 0.05)]),
        ("impact-damper.toml", &[]),
        ("symmetric-stops.toml", &[]),
        ("dry-friction.toml", &[]),
        ("soft-stop.toml", &[]),
        ("gear-backlash.toml", &[]),
        ("multi-stop.toml", &[("omega", 0.2), ("delta", 0.6)]),
    ];
    for (scene, sets) in cases {
        let sys = system(scene, sets);
        let cell = run_cell(&sys, &Accuracy::default(), Method::Exact, &sys.model.initial_state());
        let n = cell.n.unwrap_or_else(|| panic!("{scene} {sets:?}: {:?}, not periodic", cell.class));
        let q: std::collections::BTreeMap<String, f64> = solver::quantity::named(
            &sys,
            &solver::quantity::measure(&sys, &Accuracy::default(), &cell.final_state, n).unwrap(),
        )
        .into_iter()
        .collect();
        assert!(q["energy_residual"].abs() < 1e-9, "{scene} {sets:?}: residual {} ({q:?})", q["energy_residual"]);
        assert!(q["power_in"] > 0.0, "{scene} {sets:?}: {q:?}");
    }
}

/// A rigid stop's holding force and momentum, against Newton's law. The
/// single stop above the mass at σ holds it at rest while `cos ωt − σ`
/// pushes it on (ζ = 0.1, ω = 0.4, σ = 0.2, r = 0.5: `1-S-0`), so its
/// largest holding force is `1 − σ`; and over an orbit the mean force on
/// every mass vanishes, so the stops' impulses per period (impacts' and
/// holding reactions') equal `T (K x̄ − L)` along their normals, mass by
/// mass: on single-stop, multi-stop (held on both stops, on one and
/// impacting) and damper orbits (whose walls' impulses on the free mass
/// cancel), to 1e-9 of the largest impulse. Before the rest of a chatter sequence
/// counted in its impact's impulse, the single stop's balance was off by
/// 4.3e-5 of 4.04.
#[test]
fn the_stops_hold_and_strike_with_the_momentum_of_the_mean_forces() {
    let sys = system("single-stop.toml", &[("zeta", 0.1), ("omega", 0.4), ("sigma", 0.2), ("r", 0.5)]);
    let (cell, q) = quantities(&sys, &Accuracy::default());
    assert_eq!(cell.labels[0].to_string(), "1-S-0");
    assert!((q["hold_force_max_A"] - 0.8).abs() < 1e-14, "{q:?}");
    let cases: [(&str, &[(&str, f64)]); 7] = [
        ("single-stop.toml", &[("zeta", 0.1), ("omega", 0.4), ("sigma", 0.2), ("r", 0.5)]),
        ("single-stop.toml", &[("zeta", 0.05), ("omega", 2.0), ("sigma", 0.1)]),
        ("multi-stop.toml", &[("omega", 0.2), ("delta", 0.6)]),
        ("multi-stop.toml", &[("omega", 0.3), ("delta", 0.3)]),
        ("multi-stop.toml", &[("omega", 1.0), ("delta", 1.2)]),
        ("impact-damper.toml", &[]),
        ("symmetric-stops.toml", &[]),
    ];
    for (scene, sets) in cases {
        let sys = system(scene, sets);
        let (cell, q) = quantities(&sys, &Accuracy::default());
        assert!(cell.n.is_some(), "{scene} {sets:?}: {:?}", cell.class);
        let mean = nalgebra::DVector::from_iterator(
            sys.dof(),
            sys.model.masses.iter().map(|m| q[&format!("mean_x_{}", m.name)]),
        );
        let expected = (&sys.stiffness * &mean - &sys.load) * sys.period;
        let (mut pushed, mut scale) = (nalgebra::DVector::zeros(sys.dof()), expected.amax());
        for (stop, row) in sys.model.stops.iter().zip(&sys.stops) {
            let impulse = q[&format!("impulse_{}", stop.name)] + q[&format!("hold_impulse_{}", stop.name)];
            pushed += &row.normal * impulse;
            scale = scale.max(impulse);
        }
        assert!((&pushed - &expected).amax() < 1e-9 * scale, "{scene} {sets:?}: {pushed} against {expected}");
        assert!(scale > 0.0, "{scene} {sets:?}");
    }
}

/// Without rigid stops no event dissipates: a soft contact takes its energy
/// by its dashpot and, when it parts, by the spring energy it lets go, never
/// by a jump. The soft stop (with and without contact damping) and the gear
/// pair (whose mesh springs have no dashpot) show `dissipated_impacts`
/// exactly 0, and the gear `dissipated_contacts` exactly 0 too, while their
/// balances still close; before, the rounding of a state evaluated twice at
/// each segment's end read as 1.5e-12 of impact and 1.3e-27 of contact
/// dissipation.
#[test]
fn without_rigid_stops_nothing_is_dissipated_by_impacts() {
    type Case = (&'static str, &'static [(&'static str, f64)], bool);
    let cases: [Case; 4] = [
        ("soft-stop.toml", &[], false),
        ("soft-stop.toml", &[("zeta_c", 0.0)], true),
        ("gear-backlash.toml", &[], true),
        ("gear-backlash.toml", &[("f1", 0.3), ("omega", 0.8)], true),
    ];
    for (scene, sets, lossless_contacts) in cases {
        let q = window_quantities(&system(scene, sets));
        assert_eq!(q["dissipated_impacts"], 0.0, "{scene} {sets:?}: {q:?}");
        if lossless_contacts {
            assert_eq!(q["dissipated_contacts"], 0.0, "{scene} {sets:?}: {q:?}");
        } else {
            assert!(q["dissipated_contacts"] > 0.0, "{scene} {sets:?}: {q:?}");
        }
        assert!(q["energy_residual"].abs() < 1e-9, "{scene} {sets:?}: residual {} ({q:?})", q["energy_residual"]);
    }
}

/// The balance of a motion that puts in nothing net is measured against
/// the energy at stake, not the net input: the undamped single stop on a
/// free orbit below its stop (ω = 1/2, every free oscillation closing after
/// a period: the forcing's input over it is zero to rounding) and the gear
/// pair unforced and undamped (no input at all, the energy it holds
/// conserved through its tooth impacts, R = 1) are zero to rounding. They
/// read 1.0 and 9.4e291, their rounding divided by a net input of 2.7e-16
/// and by the least positive double.
#[test]
fn a_lossless_motion_balances_to_rounding() {
    let cases: [(&str, &[(&str, f64)]); 2] = [
        ("single-stop.toml", &[("omega", 0.5), ("sigma", 1.2)]),
        ("gear-backlash.toml", &[("fm", 0.0), ("f1", 0.0), ("zeta", 0.0)]),
    ];
    for (scene, sets) in cases {
        let q = window_quantities(&system(scene, sets));
        assert!(q["power_in"].abs() < 1e-12, "{scene}: nothing net put in: {q:?}");
        assert!(q["energy_residual"].abs() < 1e-12, "{scene} {sets:?}: residual {} ({q:?})", q["energy_residual"]);
    }
}
