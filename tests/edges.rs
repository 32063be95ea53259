//! Labels at the edges of decisions (issue 28): an orbit is accepted once it
//! has converged, so that its symmetry is the converged orbit's; an orbit
//! longer than `n_max` that Newton confirms is a label. Each test checks the
//! program against a check of its own that does not go through the decision.

use crate::util::{record, run, system};
use solver::{run_cell, Accuracy, Class, Knob, Method, Preset, Symmetry, Unresolved};

/// Issue 28, item 3: dry friction, fk = 0.01, on the up leg of a down-up
/// sweep, ω = 6.85 (0.005 above the pitchfork at 6.845) starts from the AS
/// orbit of ω = 6.825 and converges slowly (multiplier 0.988) to the
/// symmetric orbit. It is `1-1-1 S` in `standard` and `precise` (it was AS:
/// 8e-6 off the symmetric orbit, it passed the repeat test while still
/// converging). The independent check: Newton's method on the half map (the
/// symmetric orbit, solved exactly) converges there to an orbit whose half map
/// multipliers all lie inside the unit circle, so the symmetric orbit is the
/// stable one the sweep must reach.
#[test]
fn the_friction_cell_above_the_pitchfork_is_symmetric() {
    let orbit = run(&["orbit", "configs/dry-friction.toml", "--set", "fk=0.01", "--set", "omega=6.85", "--json"]);
    let orbit: serde_json::Value = serde_json::from_slice(&orbit.stdout).unwrap();
    let half = orbit["half_map_multipliers"].as_array().expect("a symmetric orbit, solved on the half map");
    assert!(half.iter().all(|m| m["abs"].as_f64().unwrap() < 1.0), "{orbit}");
    for preset in ["standard", "precise"] {
        let out = run(&[
            "sweep",
            "configs/dry-friction.toml",
            "--axis",
            "omega=8:4.5:141",
            "--set",
            "fk=0.01",
            "--direction",
            "down-up",
            "--json",
            "--preset",
            preset,
        ]);
        let sweep: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        for leg in ["down", "up"] {
            let cell = sweep[leg]
                .as_array()
                .unwrap()
                .iter()
                .find(|c| (c["value"].as_f64().unwrap() - 6.85).abs() < 1e-9)
                .unwrap();
            assert_eq!(cell["labels"]["M1"], "1-1-1", "{preset} {leg}: {cell}");
            assert_eq!(cell["symmetry"], "S", "{preset} {leg}: {cell}");
        }
    }
}

/// Issue 28, item 5: a record that contracts onto an orbit of period 60,
/// beyond `n_max` = 32 (multi-stop, ω = 1.10426, δ = 2), was `U` naming the
/// period; Newton confirms it and the cell is labelled with it. Independent
/// checks: the same cell searched with `n_max` = 64 (period detection in the
/// record, no Newton confirmation) has the same period and labels; and plain
/// simulation from the cell's final state returns there after 60 periods
/// (within `periodic_tol`, never after fewer), with the cell's impacts per
/// stop.
#[test]
fn a_confirmed_long_period_is_a_label() {
    let sys = system("multi-stop.toml", &[("omega", 1.1042553191489362), ("delta", 2.0)]);
    let acc = Accuracy::preset(Preset::Standard);
    let cell = run_cell(&sys, &acc, Method::Exact, &sys.model.initial_state());
    assert_eq!((cell.class, cell.n), (Class::Periodic, Some(60)), "{:?}", cell.reason);
    assert_eq!(cell.symmetry, None::<Symmetry>);
    let wide = acc.with(Knob::NMax, 64.0).unwrap();
    let oracle = run_cell(&sys, &wide, Method::Exact, &sys.model.initial_state());
    assert_eq!((oracle.class, oracle.n), (Class::Periodic, Some(60)));
    assert_eq!(cell.labels, oracle.labels);
    let y0 = cell.final_state.clone();
    let scale = 1.0 + y0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = |y: &[f64]| y.iter().zip(&y0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
    let (rec, sim) = record(&sys, &acc, Method::Exact, &y0, 60);
    assert!(off(sim.state().as_slice()) <= acc.periodic_tol(), "{:e}", off(sim.state().as_slice()));
    let mut impacts = vec![0u32; sys.stops.len()];
    for i in &rec.impacts {
        impacts[i.stop] += 1;
    }
    assert_eq!(impacts, cell.impacts);
    for n in 1..60 {
        let (_, sim) = record(&sys, &acc, Method::Exact, &y0, n);
        assert!(off(sim.state().as_slice()) > acc.periodic_tol(), "returns after {n} periods");
    }
}

/// Row `j` (of 80) of issue 40's referee atlas (`atlas configs/multi-stop.toml
/// --x omega=0.1:3.05:120 --y delta=0.05:2:80 --sweep both`): its δ, and the
/// `sweep --json` of that row in `direction`, which continues along ω as the
/// atlas does.
fn referee_row(j: usize, direction: &str) -> (f64, serde_json::Value) {
    let delta = 0.05 + (2.0 - 0.05) * j as f64 / 79.0;
    let out = run(&[
        "sweep",
        "configs/multi-stop.toml",
        "--axis",
        "omega=0.1:3.05:120",
        "--set",
        &format!("delta={delta:?}"),
        "--direction",
        direction,
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (delta, serde_json::from_slice(&out.stdout).unwrap())
}

/// Issue 40, a wrong reason: a record whose exponent looked undecided and
/// turned out contracting once its measurement was doubled was labelled `U`
/// ("a transient longer than max_periods x (1 + extensions)") without any
/// extension spent. Multi-stop, the up chain along ω = 0.1…3.05 (120 values)
/// at δ = 1.5804, its cell ω = 1.5874 (the referee's up (1.5874, 1.5804)):
/// with extensions it is 21-21-16. Independent checks: from the same start
/// state, without extensions, a record twice as long (max_periods 1200)
/// finds the same orbit; and without extensions, at the preset's record, the
/// orbit its contracting section points are searched for (Newton's method
/// on the 21-period map) is the same too (it was the transient's `U`).
#[test]
fn a_record_found_contracting_after_its_doublings_is_extended() {
    let (delta, sweep) = referee_row(62, "up");
    let points = sweep["points"].as_array().unwrap();
    let cell = &points[60];
    assert_eq!((cell["labels"]["M1"].as_str(), cell["class"].as_str()), (Some("21-21-16"), Some("periodic")), "{cell}");
    let start: Vec<f64> = serde_json::from_value(points[59]["final_state"].clone()).unwrap();
    let omega = cell["value"].as_f64().unwrap();
    let sys = system("multi-stop.toml", &[("omega", omega), ("delta", delta)]);
    let acc = Accuracy::preset(Preset::Standard).with(solver::Knob::Extensions, 0.0).unwrap();
    let long = run_cell(&sys, &acc.with(solver::Knob::MaxPeriods, 1200.0).unwrap(), Method::Exact, &start);
    assert_eq!((long.class, long.n), (Class::Periodic, Some(21)), "{:?}", long.reason);
    assert_eq!(long.labels.iter().map(|l| l.to_string()).collect::<Vec<_>>(), ["21-21-16", "21-0-21"]);
    // Without extensions, at the preset's record, the contracting record is
    // no longer a verdict either: Newton's method finds the orbit its section
    // points contract onto.
    let short = run_cell(&sys, &acc, Method::Exact, &start);
    assert_eq!((short.class, short.n), (Class::Periodic, Some(21)), "{:?}", short.reason);
    assert_eq!(short.labels, long.labels);
}

/// Issue 40: the periodic cells of the referee's 120 × 80 both-sweep atlas
/// of the reference plane (`atlas configs/multi-stop.toml --x
/// omega=0.1:3.05:120 --y delta=0.05:2:80 --sweep both`) that were `U` or
/// `Q`, each labelled with the orbit that a reference run of thousands of
/// periods settles on: long periods beyond `n_max` and beyond the 128 of the
/// record's own search (163, 224), phase-locked orbits on a torus (`Q`
/// before: 163-163-117, 97-97-45, 122-204-122), undecided ones (`U` before).
/// Each cell is computed in its own row's sweep (the atlas's continuation
/// along ω), and checked independently of the decision: plain simulation
/// from the cell's final state returns there after n periods (within
/// `periodic_tol`), with the label's impacts on M1's stops, and not after
/// any proper divisor of n.
#[test]
fn long_and_locked_orbits_at_the_edges_are_labelled() {
    // (sweep, δ index of 80, ω index of 120, label of M1)
    let cells = [
        ("up", 51, 49, "163-163-117"),
        ("down", 51, 49, "163-163-117"),
        ("up", 52, 49, "97-97-45"),
        ("down", 22, 48, "122-204-122"),
        ("down", 65, 35, "7-5-7"),
        ("up", 57, 52, "43-43-24"),
        ("up", 73, 42, "48-44-38"),
        ("up", 53, 54, "124-124-120"),
        ("up", 61, 54, "224-224-134"),
    ];
    let acc = Accuracy::preset(Preset::Standard);
    for (direction, j, i, label) in cells {
        let (delta, sweep) = referee_row(j, direction);
        // Points in sweep order: the down sweep starts at the top of ω.
        let k = if direction == "up" { i } else { 119 - i };
        let cell = &sweep["points"][k];
        let at = format!("{direction} (ω, δ) = ({:.4}, {delta:.4})", cell["value"].as_f64().unwrap());
        assert_eq!(cell["labels"]["M1"].as_str(), Some(label), "{at}: {cell}");
        let n: usize = label.split('-').next().unwrap().parse().unwrap();
        assert_eq!(cell["n"].as_u64(), Some(n as u64), "{at}");
        let sys = system("multi-stop.toml", &[("omega", cell["value"].as_f64().unwrap()), ("delta", delta)]);
        let y0: Vec<f64> = serde_json::from_value(cell["final_state"].clone()).unwrap();
        let scale = 1.0 + y0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let off = |y: &[f64]| y.iter().zip(&y0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
        let (rec, sim) = record(&sys, &acc, Method::Exact, &y0, n);
        assert!(off(sim.state().as_slice()) <= acc.periodic_tol(), "{at}: {:e}", off(sim.state().as_slice()));
        let mut impacts = vec![0u64; sys.stops.len()];
        for hit in &rec.impacts {
            impacts[hit.stop] += 1;
        }
        // M1's label counts impacts on its p stop (A12) and its q stop (A1).
        let count = |k: usize| label.split('-').nth(k).unwrap().parse::<u64>().unwrap();
        assert_eq!((impacts[2], impacts[0]), (count(1), count(2)), "{at}: impacts per stop {impacts:?}");
        for d in (1..n).filter(|&d| n.is_multiple_of(d)) {
            let (_, sim) = record(&sys, &acc, Method::Exact, &y0, d);
            assert!(off(sim.state().as_slice()) > acc.periodic_tol(), "{at}: returns after {d} periods");
        }
    }
}

/// Issue 40: a torus whose section points lie on no closed curve in their
/// principal plane (the curve loops about its centroid in that projection)
/// was `U` with its exponent about 0 and its rotation number converged
/// (0.2043165, ± 5e-7 over 1 600 periods, 50 times better than over the
/// last 400); the rotation number alone now tells it: `Q`. The referee's up
/// (1.4387, 1.3335). Independent check, the reference for a `Q`
/// cell: 3 000 plain periods from the cell's final state never come back
/// within `periodic_tol` of a state of theirs, at any lag up to 1 000
/// periods.
#[test]
fn a_torus_told_by_its_rotation_number_is_quasiperiodic() {
    let (delta, sweep) = referee_row(52, "up");
    let cell = &sweep["points"][54];
    let omega = cell["value"].as_f64().unwrap();
    assert_eq!(cell["class"].as_str(), Some("quasiperiodic"), "(ω, δ) = ({omega:.4}, {delta:.4}): {cell}");
    let sys = system("multi-stop.toml", &[("omega", omega), ("delta", delta)]);
    let acc = Accuracy::preset(Preset::Standard);
    let y0: Vec<f64> = serde_json::from_value(cell["final_state"].clone()).unwrap();
    let mut sim = solver::Simulator::new(&sys, acc, Method::Exact, &y0).unwrap();
    let states: Vec<Vec<f64>> =
        (0..3000).map(|_| sim.run_period(&[], false, &mut solver::Ignore).unwrap().end.as_slice().to_vec()).collect();
    let scale = 1.0 + y0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
    let nearest = (1..=1000)
        .map(|lag| (lag..states.len()).map(|k| off(&states[k], &states[k - lag])).fold(f64::INFINITY, f64::min))
        .fold(f64::INFINITY, f64::min);
    assert!(nearest > acc.periodic_tol(), "a return within {nearest:e}");
}

/// Issue 40, a wrong `U` in the reference: at `precise` (plain simulation,
/// `periodic_tol` 1e-9) the record of multi-stop at ω = 2.7362, δ = 0.05 (a
/// cell of the trade's 48 × 48 grid) repeats with period 1 after 2 251
/// periods while its orbit's multiplier (0.9922) says the state is still
/// 1.3e-7 from it, beyond 100 × `periodic_tol`: the cell was `U` ("contracts
/// too slowly to have reached it") with 749 periods of its record left,
/// enough to reach the orbit in about 120. The record now goes on and the
/// cell is 1-1-1. Independent checks: `standard` (Newton's method finishes
/// the convergence there) has the same orbit and multiplier; plain
/// simulation from the final state returns there after one period; and a
/// record that ends before the orbit is reached (`max_periods` 2 300) still
/// says why, with the distance.
#[test]
fn an_orbit_found_too_far_is_reached_within_the_record() {
    let sys = system("multi-stop.toml", &[("omega", 2.7361702127659573), ("delta", 0.05)]);
    let y0 = sys.model.initial_state();
    let acc = Accuracy::preset(Preset::Precise);
    let cell = run_cell(&sys, &acc, Method::Exact, &y0);
    assert_eq!((cell.class, cell.n), (Class::Periodic, Some(1)), "{:?}", cell.reason);
    let oracle = run_cell(&sys, &Accuracy::preset(Preset::Standard), Method::Exact, &y0);
    assert_eq!((oracle.class, oracle.n, &oracle.labels), (Class::Periodic, Some(1), &cell.labels));
    let (mu, mu_oracle) = (cell.multiplier.unwrap(), oracle.multiplier.unwrap());
    assert!(mu < 0.999 && (mu - mu_oracle).abs() < 1e-8, "{mu} against {mu_oracle}");
    let y1 = &cell.final_state;
    let scale = 1.0 + y1.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (_, sim) = record(&sys, &acc, Method::Exact, y1, 1);
    let off = sim.state().iter().zip(y1).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
    assert!(off <= acc.periodic_tol(), "{off:e}");
    let short = acc.with(Knob::MaxPeriods, 2300.0).unwrap().with(Knob::Extensions, 0.0).unwrap();
    let cut = run_cell(&sys, &short, Method::Exact, &y0);
    assert_eq!(cut.class, Class::Unresolved);
    let far = |d: f64| d.is_finite() && d > 100.0 * acc.periodic_tol();
    assert!(matches!(cut.reason, Some(Unresolved::Unsettled { distance, .. }) if far(distance)), "{:?}", cut.reason);
}

/// Issue 62: a motion that sticks is one flight from its release, so its
/// period is where that flight sticks again. Checked against
/// `scripts/sticking_reference.py`, the single stop in 30- and 36-digit
/// arithmetic (mpmath), which does not go through the solver. At ω =
/// 2.87179, ζ = 0.05517 the flight grows by about e^12.7, within
/// `standard`'s precision: the program's `13-S-0` is the reference's, a
/// flight sticking in the 13th period after the release's. At ζ = 0.04828
/// it grows by about e^50: the program said `71-S-0` before, and is now
/// `C` with a positive exponent; the reference's flight sticks elsewhere
/// (in the 60th period, the same at 30 and at 36 digits), where no
/// double-precision flight reaches.
#[test]
fn a_sticking_orbit_is_the_references_where_its_flight_is_within_the_precision() {
    let omega = "2.871794871794872";
    let reference = |zeta: &str, digits: &str| -> serde_json::Value {
        let out = std::process::Command::new("/usr/bin/python3")
            .args(["scripts/sticking_reference.py", "--zeta", zeta, "--omega", omega, "--digits", digits, "--json"])
            .output()
            .expect("/usr/bin/python3 (scripts/setup.sh installs it with python3-mpmath)");
        assert!(
            out.status.success(),
            "{} (scripts/setup.sh installs python3-mpmath)",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let cell = |zeta: &str, state: &str| {
        let (omega, zeta) = (format!("omega={omega}"), format!("zeta={zeta}"));
        crate::util::cell_json(&["configs/single-stop.toml", "--set", &omega, "--set", &zeta, state])
    };
    let within = "0.055172413793103454";
    let cell_within = cell(within, "--state=-0.0001689237107093955,-0.025930756446427783");
    assert_eq!(
        (cell_within["class"].as_str(), cell_within["n"].as_u64()),
        (Some("periodic"), Some(13)),
        "{cell_within}"
    );
    assert_eq!(reference(within, "30")[0]["stick_period"].as_u64(), Some(13));

    let beyond = "0.048275862068965524";
    let cell_beyond = cell(beyond, "--state=-0.5941731892288273,0.019580824143751216");
    assert_eq!(cell_beyond["class"].as_str(), Some("chaotic"), "{cell_beyond}");
    assert!(cell_beyond["lyapunov"].as_f64().is_some_and(|l| l > 0.1), "{cell_beyond}");
    let (low, high) = (reference(beyond, "30"), reference(beyond, "36"));
    assert_eq!(low[0]["stick_period"], high[0]["stick_period"], "{low} against {high}");
    assert_ne!(high[0]["stick_period"].as_u64(), Some(71), "{high}");
}
