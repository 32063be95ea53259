//! Issue 60's independent oracle for the quantities: a plain integrator of
//! the equations of motion (classical Runge–Kutta, at least 4 000 steps a
//! forcing period and 500 per unit of the fastest spring's or contact's time
//! scale, every impact, contact and turning point placed by bisection on
//! re-integrated sub-steps), written here from the equations of
//! docs/models.md and not from the solver's closed-form flow, follows the
//! orbit of a periodic cell from the start of its window over its n periods.
//! Its largest |x| of every mass and largest normal speed before an impact
//! (rigid) or at the start of a contact (soft) of every stop equal the
//! solver's `max_abs_x_*` and `impact_speed_max_*` to 1e-8, on the cells of
//! six scenes; the solver's `max_abs_v_*` and a soft stop's
//! `contact_force_max_*` lie between the largest of its samples and 1e-6
//! above it.

use crate::common::system;
use scene::StopLaw;
use solver::DVector;
use solver::{run_cell_measured, Accuracy, Class, Method, System};

/// Steps per forcing period.
const STEPS: usize = 4000;

/// The soft stops in contact at full state `y`: a gap below zero whose
/// spring and dashpot push, `−k g − c ġ > 0`. A step keeps the contacts of
/// its start (a force that jumped inside a step would spoil its order); the
/// switches below end the step where they change.
fn contacts(sys: &System, y: &DVector<f64>) -> Vec<bool> {
    (0..sys.stops.len())
        .map(|i| match sys.stops[i].law {
            StopLaw::Soft { stiffness, damping } => {
                sys.gap(i, y) < 0.0 && -stiffness * sys.gap(i, y) - damping * sys.gap_rate(i, y) > 0.0
            }
            StopLaw::Rigid { .. } => false,
        })
        .collect()
}

/// The rate of full state `y` at time `t` with the soft stops `pressed` in
/// contact: `M v' = F(t) + L − C v − K x + Σ f_k n_k`, `f_k = −k g − c ġ`.
fn rate(sys: &System, t: f64, y: &DVector<f64>, pressed: &[bool]) -> DVector<f64> {
    let m = sys.dof();
    let (x, v) = (y.rows(0, m).into_owned(), y.rows(m, m).into_owned());
    let phase = sys.omega * t + sys.tau;
    let mut force = sys.load.clone() - &sys.damping * &v - &sys.stiffness * &x;
    for (k, [p, q]) in sys.harmonics.iter().enumerate() {
        let a = (k + 1) as f64 * phase;
        force += p * a.sin() + q * a.cos();
    }
    for (i, s) in sys.stops.iter().enumerate() {
        if let (StopLaw::Soft { stiffness, damping }, true) = (s.law, pressed[i]) {
            force += &s.normal * (-stiffness * sys.gap(i, y) - damping * sys.gap_rate(i, y));
        }
    }
    let mut out = DVector::zeros(2 * m);
    out.rows_mut(0, m).copy_from(&v);
    out.rows_mut(m, m).copy_from(&force.component_div(&sys.mass));
    out
}

/// One classical Runge–Kutta step of length `h` from `y` at `t`, the
/// contacts of `y` kept.
fn step(sys: &System, t: f64, y: &DVector<f64>, h: f64) -> DVector<f64> {
    let pressed = contacts(sys, y);
    let f = |t: f64, y: &DVector<f64>| rate(sys, t, y, &pressed);
    let k1 = f(t, y);
    let k2 = f(t + h / 2.0, &(y + &k1 * (h / 2.0)));
    let k3 = f(t + h / 2.0, &(y + &k2 * (h / 2.0)));
    let k4 = f(t + h, &(y + &k3 * h));
    y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// The functions whose sign changes split a step: each stop's gap, each
/// pressed soft stop's force (a dashpot lets go before the gap opens), and
/// each mass's velocity (its turning points).
fn switches(sys: &System, y: &DVector<f64>) -> Vec<f64> {
    let m = sys.dof();
    let mut out: Vec<f64> = (0..sys.stops.len()).map(|i| sys.gap(i, y)).collect();
    for (i, s) in sys.stops.iter().enumerate() {
        out.push(match s.law {
            StopLaw::Soft { stiffness, damping } => -stiffness * sys.gap(i, y) - damping * sys.gap_rate(i, y),
            StopLaw::Rigid { .. } => 1.0,
        });
    }
    out.extend((0..m).map(|j| y[m + j]));
    out
}

/// What the integration measures: per mass its largest |x| (at its turning
/// points, placed by bisection) and its largest |v| at the steps' and
/// events' points (sampled, within `SAMPLED` of the peak between them), per
/// stop its largest normal speed at an impact or a contact's start and, for
/// a soft stop, its largest force at those points.
struct Measured {
    max_abs_x: Vec<f64>,
    max_abs_v: Vec<f64>,
    speed_max: Vec<f64>,
    force_max: Vec<f64>,
}

/// How far below a peak the largest of samples at least 1/4 000 of a
/// period apart may lie, relative to the peak's size: a smooth function
/// falls from its peak by at most `|f''| (h/2)² / 2`, about 1e-7 of it at
/// these steps.
const SAMPLED: f64 = 1e-6;

/// Follows `periods` forcing periods from `y0` at t = 0.
fn integrate(sys: &System, y0: &[f64], periods: usize) -> Measured {
    let m = sys.dof();
    // Steps of at most 1/500 of the fastest rate's time scale (a stiff
    // contact's, or a spring's), and at least STEPS a period.
    let mut fastest: f64 = (0..m).map(|j| sys.stiffness[(j, j)].abs() / sys.mass[j]).fold(0.0, f64::max);
    for s in &sys.stops {
        if let StopLaw::Soft { stiffness, .. } = s.law {
            fastest = fastest.max(stiffness * s.inv_effective_mass);
        }
    }
    let h = (sys.period / STEPS as f64).min(1.0 / (500.0 * fastest.sqrt().max(1e-300)));
    let mut y = DVector::from_column_slice(y0);
    let stops = sys.stops.len();
    let mut out = Measured {
        max_abs_x: vec![0.0; m],
        max_abs_v: vec![0.0; m],
        speed_max: vec![0.0; stops],
        force_max: vec![0.0; stops],
    };
    let see = |y: &DVector<f64>, out: &mut Measured| {
        for j in 0..m {
            out.max_abs_x[j] = out.max_abs_x[j].max(y[j].abs());
            out.max_abs_v[j] = out.max_abs_v[j].max(y[m + j].abs());
        }
        for (i, pressed) in contacts(sys, y).into_iter().enumerate() {
            if pressed {
                out.force_max[i] = out.force_max[i].max(sys.contact_force(i, y));
            }
        }
    };
    see(&y, &mut out);
    let end = periods as f64 * sys.period;
    let mut t = 0.0;
    while t < end - 1e-12 * end {
        let h = h.min(end - t);
        let before = switches(sys, &y);
        let next = step(sys, t, &y, h);
        let after = switches(sys, &next);
        // The first sign change within the step, by bisection on the
        // length of a sub-step from its start.
        let crossing = |k: usize| before[k] != 0.0 && before[k].signum() != after[k].signum();
        let Some(first) = (0..before.len())
            .filter(|&k| crossing(k))
            .map(|k| (k, locate(sys, t, &y, h, k, before[k])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
        else {
            (t, y) = (t + h, next);
            see(&y, &mut out);
            continue;
        };
        let (k, s) = first;
        y = step(sys, t, &y, s);
        t += s;
        see(&y, &mut out);
        if let Some(StopLaw::Rigid { restitution }) = sys.stops.get(k).map(|row| row.law) {
            let rate = sys.gap_rate(k, &y);
            if rate < 0.0 {
                // Newton's law: the normal velocity reversed, scaled by r.
                out.speed_max[k] = out.speed_max[k].max(-rate);
                let row = &sys.stops[k];
                let dv = &row.inv_mass_normal * (-(1.0 + restitution) * rate / row.inv_effective_mass);
                let mut v = y.rows_mut(m, m);
                v += dv;
                // An impact may give a mass its largest speed.
                see(&y, &mut out);
            }
        }
        // Step just past the switch, so that its sign has changed (a soft
        // stop's gap and force change together where it has no dashpot).
        let nudge = (1e-13 * sys.period).min(end - t);
        y = step(sys, t, &y, nudge);
        t += nudge;
        for (i, row) in sys.stops.iter().enumerate() {
            if matches!(row.law, StopLaw::Soft { .. }) && before[i] > 0.0 && sys.gap(i, &y) < 0.0 {
                out.speed_max[i] = out.speed_max[i].max(-sys.gap_rate(i, &y));
            }
        }
    }
    out
}

/// Where switch `k` (sign `sign` at the step's start) changes sign within a
/// step of length `h` from `y` at `t`: the sub-step length, to 1e-15 of `h`.
fn locate(sys: &System, t: f64, y: &DVector<f64>, h: f64, k: usize, sign: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, h);
    while hi - lo > 1e-15 * h.max(1.0) {
        let mid = 0.5 * (lo + hi);
        if switches(sys, &step(sys, t, y, mid))[k].signum() == sign.signum() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

#[test]
fn quantities_agree_with_an_independent_integration() {
    let cells: [(&str, &[(&str, f64)]); 6] = [
        ("single-stop.toml", &[]),
        ("multi-stop.toml", &[]),
        ("impact-damper.toml", &[]),
        ("soft-stop.toml", &[]),
        ("gear-backlash.toml", &[]),
        ("symmetric-stops.toml", &[]),
    ];
    // The gear at 0.85 and the symmetric stops at 1.5 and 1.49 have a peak
    // of contact force or |v| just before an event or a piece's end, which
    // the solver once missed (its |v| 1e-5 short at the impact).
    let omegas: [&[f64]; 6] = [
        &[0.6, 0.8, 1.2, 1.6, 2.0, 2.4],
        &[0.3, 0.5, 0.9, 1.4, 2.2, 2.8],
        &[1.3, 1.4, 1.5, 1.85, 1.95, 2.1],
        &[0.5, 0.9, 1.2, 1.5, 2.0, 2.6],
        &[0.5, 0.85, 1.0, 1.4, 1.6, 2.0, 2.7],
        &[1.5, 1.49, 1.3, 1.8],
    ];
    let acc = Accuracy::default();
    let mut checked = Vec::new();
    for ((file, sets), omegas) in cells.iter().zip(omegas) {
        let mut here = 0;
        for &omega in omegas {
            let mut all: Vec<(&str, f64)> = sets.to_vec();
            all.push(("omega", omega));
            let sys = system(file, &all);
            let (cell, _, q) = run_cell_measured(&sys, &acc, Method::Exact, &sys.model.initial_state(), 0, true);
            let (Class::Periodic, Some(n), Some(q)) = (cell.class, cell.n, q) else { continue };
            if cell.chatter.bits() != 0 || cell.sticking.bits() != 0 {
                continue;
            }
            let named: std::collections::BTreeMap<String, f64> =
                solver::quantity::named(&sys, &q).into_iter().collect();
            let got = integrate(&sys, &cell.window_start, n);
            let agree = |name: String, got: f64| {
                let want = named[&name];
                assert!((got - want).abs() < 1e-8 * want.max(1.0), "{file} ω {omega}: {name} {want} against {got}");
            };
            // A peak the samples bracket: the solver's is no lower than any
            // of them (to the integration's 1e-8) and above the largest by
            // no more than they may miss.
            let bounds = |name: String, sampled: f64| {
                let want = named[&name];
                assert!(
                    want >= sampled - 1e-8 * sampled.max(1.0) && want - sampled <= SAMPLED * sampled.max(1.0),
                    "{file} ω {omega}: {name} {want} against samples up to {sampled}"
                );
            };
            for (j, mass) in sys.model.masses.iter().enumerate() {
                agree(format!("max_abs_x_{}", mass.name), got.max_abs_x[j]);
                bounds(format!("max_abs_v_{}", mass.name), got.max_abs_v[j]);
            }
            for (k, stop) in sys.model.stops.iter().enumerate() {
                agree(format!("impact_speed_max_{}", stop.name), got.speed_max[k]);
                if matches!(sys.stops[k].law, StopLaw::Soft { .. }) {
                    bounds(format!("contact_force_max_{}", stop.name), got.force_max[k]);
                }
            }
            here += 1;
            checked.push(format!(
                "{file} ω {omega} ({})",
                cell.labels.iter().map(|l| l.label.to_string()).collect::<Vec<_>>().join(" ")
            ));
        }
        assert!(here >= 3, "{file}: {here} periodic cells without chatter or sticking checked");
    }
    assert!(checked.len() >= 24, "{} cells: {checked:?}", checked.len());
}
