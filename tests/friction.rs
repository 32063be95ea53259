//! The dry-friction scene (issue 4): stick/slip against closed forms and RK4,
//! the published sequence of motions, and frictionless scenes left untouched.

use crate::util::{config, record, run, system};
use solver::{Accuracy, DVector, EventObserver, Method, Simulator, System};

/// Non-friction force on each mass, `P sin(ωt+τ) - K x - C v`.
fn free_forces(sys: &System, t: f64, y: &DVector<f64>) -> DVector<f64> {
    let m = sys.dof();
    let (x, v) = (y.rows(0, m), y.rows(m, m));
    &sys.harmonics[0][0] * (sys.omega * t + sys.tau).sin() - &sys.stiffness * x - &sys.damping * v
}

/// Mechanical energy `½ vᵀ M v + ½ xᵀ K x`.
fn energy(sys: &System, y: &DVector<f64>) -> f64 {
    let m = sys.dof();
    let x = y.rows(0, m);
    sys.kinetic_energy(y) + 0.5 * x.dot(&(&sys.stiffness * x))
}

/// Relative displacement and velocity of the friction contact (M1 - M2).
fn relative(y: &DVector<f64>) -> (f64, f64) {
    (y[0] - y[1], y[2] - y[3])
}

/// Every instant the simulation reports, in time order: the state before and
/// after it (equal except at impacts); and the requested samples alone.
#[derive(Default)]
struct Points(Vec<(f64, DVector<f64>, DVector<f64>)>, Vec<(f64, DVector<f64>)>);

impl EventObserver for Points {
    fn impact(&mut self, t: f64, _stop: usize, before: &DVector<f64>, after: &DVector<f64>) {
        self.0.push((t, before.clone(), after.clone()));
    }
    fn event(&mut self, t: f64, y: &DVector<f64>) {
        match self.0.last_mut() {
            // The event that handled an impact: its final state is the after-state.
            Some(last) if last.0.to_bits() == t.to_bits() => last.2 = y.clone(),
            _ => self.0.push((t, y.clone(), y.clone())),
        }
    }
    fn sample(&mut self, t: f64, y: &DVector<f64>) {
        self.0.push((t, y.clone(), y.clone()));
        self.1.push((t, y.clone()));
    }
}

fn simulate(sys: &System, y0: &[f64], periods: usize, samples: usize) -> Points {
    let mut sim = Simulator::new(sys, Accuracy::default(), Method::Exact, y0).unwrap();
    let times: Vec<f64> = (1..samples).map(|i| sys.period * i as f64 / samples as f64).collect();
    let mut points = Points::default();
    for _ in 0..periods {
        sim.run_period(&times, false, &mut points).unwrap();
    }
    points
}

/// While the masses stick, the friction force that holds them together,
/// `F = (M1 f2 - M2 f1)/(M1 + M2)` from the other forces, stays within f_s.
#[test]
fn stuck_friction_force_never_exceeds_the_static_limit() {
    for (omega, fk) in [(2.0, 0.1), (2.0, 0.05), (1.3, 0.1)] {
        let sys = system("dry-friction.toml", &[("omega", omega), ("fk", fk)]);
        let fs = sys.frictions[0].static_limit;
        let points = simulate(&sys, &sys.model.initial_state(), 40, 1000);
        let (m1, m2) = (sys.mass[0], sys.mass[1]);
        let mut stuck = 0;
        let mut largest = 0.0f64;
        // Samples fall between events: zero relative velocity there is sticking
        // (at an event it may be a reversal).
        for (t, y) in &points.1 {
            // Stuck, and not resting against a wall of the clearance (where the
            // wall's reaction carries the load).
            let b = sys.stops[0].offset;
            if relative(y).1.abs() < 1e-12 && relative(y).0.abs() < b - 1e-9 {
                let f = free_forces(&sys, *t, y);
                let force = (m1 * f[1] - m2 * f[0]) / (m1 + m2);
                largest = largest.max(force.abs());
                assert!(
                    force.abs() <= fs * (1.0 + 1e-9),
                    "ω = {omega}, fk = {fk}: |F| = {} > fs = {fs} at t = {t}",
                    force.abs()
                );
                stuck += 1;
            }
        }
        assert!(stuck >= 10, "ω = {omega}, fk = {fk}: only {stuck} stuck samples");
        // Sticking is used up to the limit, not far below it.
        assert!(largest > 0.5 * fs, "ω = {omega}, fk = {fk}: largest stuck force {largest}");
    }
}

/// Unforced and undamped, the only losses are friction and impacts: over each
/// interval between events the energy falls by exactly `f_k |Δ(x1 - x2)|`
/// (nothing while stuck), and no impact adds energy.
#[test]
fn friction_and_impacts_dissipate_exactly() {
    let text = std::fs::read_to_string(config("dry-friction.toml")).unwrap();
    let unforced = text.replace("force = \"1 - f20\"", "force = \"0\"");
    assert_ne!(unforced, text);
    let scene = scene::Scene::parse(&unforced).unwrap();
    let sets = [("zeta".to_string(), 0.0), ("fk".to_string(), 0.02), ("omega".to_string(), 3.0)];
    let sys = System::new(scene.evaluate(&sets).unwrap()).unwrap();
    let fk = sys.frictions[0].kinetic;
    let points = simulate(&sys, &[0.4, 0.0, 0.0, 0.0], 20, 16);
    let (mut slips, mut impacts) = (0, 0);
    for w in points.0.windows(2) {
        let ((_, _, a), (_, b, _)) = (&w[0], &w[1]);
        let loss = energy(&sys, a) - energy(&sys, b);
        let slid = (relative(b).0 - relative(a).0).abs();
        assert!(
            (loss - fk * slid).abs() <= 1e-10 * (1.0 + energy(&sys, a)),
            "loss {loss:e} against fk·slid {:e}",
            fk * slid
        );
        slips += usize::from(slid > 1e-9);
    }
    for (_, before, after) in &points.0 {
        assert!(energy(&sys, after) <= energy(&sys, before) + 1e-13);
        impacts += usize::from(relative(before).1 != relative(after).1 && relative(after).1 != 0.0);
    }
    assert!(slips > 20 && impacts > 5, "{slips} slip intervals, {impacts} impacts");
}

/// Distinct event instants: events closer than 1e-9 are one instant (a slip
/// that ends exactly at the static limit sticks for a rounding-level time in one
/// integrator and reverses at once in the other; the motion after is the same).
fn instants(events: &[(f64, DVector<f64>)]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for &(t, _) in events {
        if out.last().is_none_or(|&last| t - last > 1e-9) {
            out.push(t);
        }
    }
    out
}

/// Stick/slip and impact times of the exact flow and of RK4 (h = 1e-4) agree to
/// 1e-6 over 20 periods, on an orbit that sticks, slips both ways and impacts.
#[test]
fn exact_and_rk4_stick_slip_times_agree() {
    for (omega, fk) in [(2.0, 0.1), (7.5, 0.01)] {
        let sys = system("dry-friction.toml", &[("omega", omega), ("fk", fk)]);
        let acc = Accuracy::default().with(solver::Knob::Rk4Step, 1e-4).unwrap();
        let y0 = sys.model.initial_state();
        let (exact, _) = record(&sys, &acc, Method::Exact, &y0, 20);
        let (rk4, _) = record(&sys, &acc, Method::Rk4, &y0, 20);
        let (exact, rk4) = (instants(&exact.events), instants(&rk4.events));
        assert!(exact.len() > 40);
        assert_eq!(exact.len(), rk4.len(), "ω = {omega}: event counts");
        let worst = exact.iter().zip(&rk4).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-6, "ω = {omega}: largest event time difference {worst:e}");
    }
}

/// Issue 4: lowering ω gives the fundamental sequence 1-1-1 → 1-2-2 → 1-3-3 →
/// 1-4-4 → 1-5-5, each 1-p-p symmetric before it turns asymmetric.
#[test]
fn down_sweep_shows_the_fundamental_sequence() {
    let out = run(&["sweep", "configs/dry-friction.toml", "--axis", "omega=8:1.45:132", "--json", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // (p, symmetric) of the fundamental motions 1-p-p, in sweep order.
    let mut seen: Vec<(u32, bool)> = Vec::new();
    for point in v["points"].as_array().unwrap() {
        let label = point["labels"]["M1"].as_str().unwrap();
        let parts: Vec<&str> = label.split('-').collect();
        if parts[0] == "1" && parts[1] == parts[2] {
            let entry = (parts[1].parse().unwrap(), point["symmetry"] == "S");
            if seen.last() != Some(&entry) {
                seen.push(entry);
            }
        }
    }
    let ps: Vec<u32> = seen.iter().map(|e| e.0).collect();
    assert!(ps.windows(2).all(|w| w[0] <= w[1]), "p must grow as ω falls: {seen:?}");
    for p in 1..=5 {
        assert!(ps.contains(&p), "1-{p}-{p} missing: {seen:?}");
        // The symmetric orbit turns asymmetric (pitchfork), never back.
        let syms: Vec<bool> = seen.iter().filter(|e| e.0 == p).map(|e| e.1).collect();
        assert!(syms.windows(2).all(|w| w[0] || !w[1]), "1-{p}-{p}: {syms:?}");
    }
    assert_eq!(seen[..2], [(1, true), (1, false)], "1-1-1 S then AS: {seen:?}");
}

/// A snapshot, not a contract: the JSON of the commands in
/// `tests/data/snapshot.commands` (cells, sweeps, orbits and continuations of
/// the frictionless scenes, both integrators) as the tool printed them when the
/// snapshot was last recorded. It fails on any change of output, to the last
/// bit, so that no change goes unnoticed; a change that is meant (a new default,
/// a fixed bug) is recorded again, and its commit says why:
///
/// ```sh
/// while read -r c; do target/release/vibroatlas $c --json; done < tests/data/snapshot.commands > tests/data/snapshot.jsonl
/// ```
///
/// Recorded again when `chaos_check = 100` became standard (issue 19): the
/// exponents of the impact damper's chaotic cells (measured over 100 periods)
/// and the final states after them changed, no label did. Recorded again
/// when the exponent became an estimate with its interval (issue 28): the
/// impact damper's exponents at ω = 0.7 and 0.8 changed in their last bit
/// (the mean growth per period divided by T, instead of the sum by K T).
/// Recorded again when every cell and sweep point gained `quantities`
/// (issue 60): every other key and value of every line is unchanged; and
/// when the impact damper's scene defined `attenuation` (issue 60): its two
/// lines gained that one quantity, nothing else changed. Recorded again
/// when `energy_residual` came to be measured against the energy at stake
/// instead of the net input (issue 62's audit of lossless cells): that value
/// of every line changed at rounding level (all below 2.3e-15), nothing else.
/// Recorded again when a velocity's peak just before an impact was found
/// (the meter had read the speed at the impact): `max_abs_v_M1` of two lines
/// of the symmetric stops rose, by up to 3.6e-5 relative, nothing else.
/// Recorded again when the rigid stops gained `hold_impulse_…` and
/// `hold_force_max_…` (65 lines gained them) and an impact's impulse came
/// to count the end of a chatter sequence it ends (the mass at rest, not
/// its rebound): `impulse_A1` and `impulse_A12` of one line fell, by up to
/// 6.1e-5 relative, nothing else. Recorded again when the hold after a cut
/// chatter sequence came to be counted from where its bounces would
/// accumulate (a referee's find, tests/quantities.rs): the held-stop
/// quantities of one line (the multi-stop cell ω = 0.2, δ = 0.6) moved by up
/// to 6.5e-4 relative, its other quantities at rounding level (the quadrature
/// split there), nothing else.
#[test]
fn outputs_match_the_recorded_snapshot() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let commands = std::fs::read_to_string(root.join("tests/data/snapshot.commands")).unwrap();
    let expected = std::fs::read_to_string(root.join("tests/data/snapshot.jsonl")).unwrap();
    let mut got = String::new();
    for line in commands.lines() {
        let mut args: Vec<&str> = line.split_whitespace().collect();
        args.push("--json");
        let out = run(&args);
        assert!(out.status.success(), "{line}: {}", String::from_utf8_lossy(&out.stderr));
        got.push_str(&String::from_utf8(out.stdout).unwrap());
    }
    for (i, (a, b)) in got.lines().zip(expected.lines()).enumerate() {
        assert_eq!(a, b, "command {}: {}", i + 1, commands.lines().nth(i).unwrap());
    }
    assert_eq!(got.lines().count(), expected.lines().count());
}

/// Issue 4: chattering at the clearance ends in complete chattering (M1 held
/// against M2's wall, `1-S-S`) at low ω with strong friction, while with
/// fk = 0.01 nothing sticks over the upper range.
#[test]
fn complete_chattering_at_the_clearance() {
    let c = crate::util::cell_json(&["configs/dry-friction.toml", "--set", "fk=0.1", "--set", "omega=1.0"]);
    assert_eq!(c["labels"]["M1"], "1-S-S", "{c}");
    assert_eq!(c["sticking"]["right"], true);
    assert_eq!(c["chatter"]["left"], true);
    for omega in ["omega=2", "omega=5", "omega=7.5"] {
        let c = crate::util::cell_json(&["configs/dry-friction.toml", "--set", omega]);
        assert_eq!(c["friction_stick"]["M1-M2"], false, "{omega}: {c}");
        assert_eq!(c["sticking"]["right"], false, "{omega}");
    }
}

/// Issues 4 and 6: the symmetric 1-1-1 orbit's pitchfork found by `continue`
/// (a −1 of the half map) lies in the sweep step where the labels turn from
/// S to AS.
#[test]
fn pitchfork_of_continue_matches_the_sweep() {
    let cont = crate::util::run(&["continue", "configs/dry-friction.toml", "--axis", "omega=7.5:6.5:21", "--json"]);
    let cont: serde_json::Value = serde_json::from_slice(&cont.stdout).unwrap();
    let pf: Vec<f64> = cont["bifurcations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b["kind"] == "PF")
        .map(|b| b["value"].as_f64().unwrap())
        .collect();
    assert_eq!(pf.len(), 1, "{}", cont["bifurcations"]);
    let out =
        crate::util::run(&["sweep", "configs/dry-friction.toml", "--axis", "omega=6.86:6.83:31", "--json", "--quiet"]);
    let sweep: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let points: Vec<(f64, String)> = sweep["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["value"].as_f64().unwrap(), p["symmetry"].as_str().unwrap_or("-").to_string()))
        .collect();
    let step = points.windows(2).find(|w| w[0].1 == "S" && w[1].1 == "AS").expect("S then AS in the sweep");
    assert!(pf[0] <= step[0].0 && pf[0] >= step[1].0, "PF at {}, sweep step [{}, {}]", pf[0], step[1].0, step[0].0);
}
