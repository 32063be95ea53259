//! Issue 28, item 4: curves that stay on their branch. The grazing curve
//! that bounds 1-3-3 in the multi-stop scene, followed from δ = 0.7 down to
//! δ = 0.5 and up towards δ = 0.9 with two step settings each, passes the
//! same points (located to 1e-6 on either run's curve), and a step that
//! would take another orbit's grazing is refused.

use super::*;
use crate::orbit::solve_orbit;
use std::sync::OnceLock;

/// The shipped scene `file` (kept in `cell`) at `(ω, δ)`, `None` where the
/// scene refuses them.
fn scene_at(cell: &'static OnceLock<scene::Scene>, file: &str, omega: f64, delta: f64) -> Option<System> {
    let scene = cell.get_or_init(|| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs").join(file);
        scene::Scene::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
    });
    let model = scene.evaluate(&[("omega".to_string(), omega), ("delta".to_string(), delta)]).ok()?;
    System::new(model).ok()
}

/// The multi-stop scene at `(ω, δ)`.
fn plane(omega: f64, delta: f64) -> Option<System> {
    static SCENE: OnceLock<scene::Scene> = OnceLock::new();
    scene_at(&SCENE, "multi-stop.toml", omega, delta)
}

/// The tracing of `curve --kind grazing --start omega=0.3146,delta=0.7
/// --free omega,delta --to TO --steps STEPS --window WINDOW`.
fn tracing(to: f64, steps: usize, window: f64) -> Tracing {
    Tracing {
        kind: Bifurcation::Grazing,
        acc: Accuracy::default(),
        n: None,
        scale: [window, (to - 0.7f64).abs() / steps as f64],
        bounds: [[0.0, f64::INFINITY], [to.min(0.7), to.max(0.7)]],
        max_points: 10 * steps + 1,
    }
}

/// That curve.
fn grazing_curve(t: &Tracing, to: f64) -> Curve {
    let first = t.locate(&plane, 0.3146, 0.7, Start::Fresh).expect("the grazing at δ = 0.7");
    t.follow(&plane, first, to)
}

/// Every point of `x` but those past the end of `y` lies on the curve of `y`:
/// located again from the nearest point of `y` (its orbit carried from there,
/// as a step carries it)
/// on the line through it normal to `x`'s chord there, as long either way as
/// that point is far from it (a sixteenth of `y`'s units at least), it is
/// found within 1e-6.
fn lies_on(x: &Curve, y: &Curve, ty: &Tracing) {
    let scaled = |p: &CurvePoint| [p.a / ty.scale[0], p.b / ty.scale[1]];
    let distance = |p: &CurvePoint, q: &CurvePoint| (scaled(p)[0] - scaled(q)[0]).hypot(scaled(p)[1] - scaled(q)[1]);
    for (i, q) in x.points.iter().enumerate() {
        let (u, v) = (scaled(&x.points[i.saturating_sub(1)]), scaled(&x.points[(i + 1).min(x.points.len() - 1)]));
        let chord = (v[0] - u[0]).hypot(v[1] - u[1]);
        let normal = [-(v[1] - u[1]) / chord, (v[0] - u[0]) / chord];
        let r = y.points.iter().min_by(|r, s| distance(r, q).total_cmp(&distance(s, q))).unwrap();
        // Past the end of `y` (where it stopped) `y` reaches no point.
        if let [.., before, end] = &y.points[..] {
            let ahead = (scaled(q)[0] - scaled(end)[0]) * (scaled(end)[0] - scaled(before)[0])
                + (scaled(q)[1] - scaled(end)[1]) * (scaled(end)[1] - scaled(before)[1]);
            if std::ptr::eq(r, end) && ahead > 0.0 && y.ended.is_some() {
                continue;
            }
        }
        let unit = distance(r, q).max(1.0 / 16.0);
        let t = Tracing { scale: [ty.scale[0] * unit, ty.scale[1] * unit], ..ty.clone() };
        let found = t.locate_from(&plane, r, [q.a, q.b], normal);
        let p = found.unwrap_or_else(|m| panic!("({}, {}) from ({}, {}): {m}", q.a, q.b, r.a, r.b));
        let off = (p.a - q.a).abs().max((p.b - q.b).abs());
        assert!(off < 1e-6, "({}, {}) is not on the other curve: ({}, {}) there", q.a, q.b, p.a, p.b);
    }
}

/// Points of `x` and `y` at the same δ have the same ω within 1e-6; how many.
fn same_at_common_delta(x: &Curve, y: &Curve) -> usize {
    let mut common = 0;
    for p in &x.points {
        for q in y.points.iter().filter(|q| q.b.to_bits() == p.b.to_bits()) {
            assert!((p.a - q.a).abs() < 1e-6, "δ = {}: ω = {} and {}", p.b, p.a, q.a);
            common += 1;
        }
    }
    common
}

/// Every point continues the first point's orbit: its period, map and
/// impact pattern, and the stop it grazes.
fn one_orbit(c: &Curve) {
    let first = &c.points[0];
    assert!(!first.grazes.is_empty(), "the grazed stop is seen");
    for p in &c.points {
        assert!(line::same_orbit(&first.orbit, &p.orbit), "({}, {}) is on another orbit", p.a, p.b);
        assert!(p.grazes.is_empty() || p.grazes == first.grazes, "({}, {}) grazes {:?}", p.a, p.b, p.grazes);
    }
}

#[test]
fn grazing_curve_down_from_delta_07_passes_the_same_points_with_two_step_settings() {
    let (t1, t2) = (tracing(0.5, 4, 0.01), tracing(0.5, 4, 0.05));
    let (c1, c2) = (grazing_curve(&t1, 0.5), grazing_curve(&t2, 0.5));
    for c in [&c1, &c2] {
        one_orbit(c);
        // Down to δ = 0.5 itself, where the grazing is at ω = 0.47959.
        let end = c.points.last().unwrap();
        assert_eq!((end.b.to_bits(), c.ended.as_deref()), (0.5f64.to_bits(), None), "{:?}", c.ended);
        assert!((end.a - 0.479589).abs() < 1e-5, "ends at ω = {}", end.a);
    }
    // δ = 0.7, 0.65 and 0.5 in both.
    assert!(same_at_common_delta(&c1, &c2) >= 3);
    lies_on(&c1, &c2, &t2);
    lies_on(&c2, &c1, &t1);
}

#[test]
fn grazing_curve_up_from_delta_07_passes_the_same_points_with_two_step_settings() {
    let (t1, t2) = (tracing(0.9, 4, 0.01), tracing(0.9, 20, 0.05));
    let (c1, c2) = (grazing_curve(&t1, 0.9), grazing_curve(&t2, 0.9));
    for c in [&c1, &c2] {
        one_orbit(c);
        // Where the 1-3-3 orbit folds as it grazes (past δ ≈ 0.81776 it folds
        // before it grazes): the curve ends just before it, with the meeting.
        let end = c.points.last().unwrap();
        assert!((end.b - 0.81776).abs() < 2e-5 && (end.a - 0.28925).abs() < 1e-5, "({}, {})", end.a, end.b);
        assert!(c.ended.as_deref().is_some_and(|e| e.contains("grazing-SN")), "{:?}", c.ended);
        assert_eq!(c.codim2.last().map(|x| x.kind.as_str()), Some("grazing-SN"));
    }
    assert!(same_at_common_delta(&c1, &c2) >= 2);
    lies_on(&c1, &c2, &t2);
    lies_on(&c2, &c1, &t1);
}

/// At δ = 0.6 the corrector line of 4 steps and a window of 0.05 around the
/// secant prediction (ω = 0.3531) holds two grazings: the 1-3-3 orbit's at
/// ω = 0.35996, and, past it, that of the orbit with the new impact at
/// ω = 0.35439, nearer the prediction, which such a step once took. Carried
/// from the point before, the curve's orbit finds its own.
#[test]
fn a_step_that_would_take_another_orbits_grazing_is_refused() {
    let t = tracing(0.5, 4, 0.05);
    let first = t.locate(&plane, 0.3146, 0.7, Start::Fresh).unwrap();
    let next = t.locate_from(&plane, &first, [0.3146, 0.65], [1.0, 0.0]).unwrap();
    assert!((next.a - 0.333842061).abs() < 1e-8, "{}", next.a);
    let guess = 2.0 * next.a - first.a;
    let p = t.locate_from(&plane, &next, [guess, 0.6], [1.0, 0.0]).unwrap();
    assert!((p.a - 0.35996077).abs() < 1e-7, "the grazing found at δ = 0.6 is at ω = {}", p.a);
    assert!(line::same_orbit(&first.orbit, &p.orbit));
    // The other orbit's grazing is nearer the prediction: a step that took the
    // nearest would have taken it.
    assert!((0.354387705 - guess).abs() < (p.a - guess).abs());
    let c = t.follow(&plane, first, 0.5);
    let at = c.points.iter().find(|q| q.b.to_bits() == 0.6f64.to_bits()).expect("a natural step at δ = 0.6");
    assert!((at.a - p.a).abs() < 1e-9);
    assert!(c.points.iter().all(|q| (q.a - 0.354387705).abs() > 1e-4 || (q.b - 0.6).abs() > 1e-9));
}

/// The meeting of `c` with the fold of its orbit.
fn fold_meeting_of(c: &Curve) -> Codim2 {
    let m = c.codim2.last().filter(|m| m.kind == "grazing-SN");
    m.cloned().unwrap_or_else(|| panic!("no grazing-SN: {:?}", c.ended))
}

/// Where the 1-3-3 orbit folds as it grazes, the grazing curve followed up
/// from δ = 0.7 ends at one meeting, (0.2892524, 0.8177646), with 4 steps and
/// a window of 0.01 as with 40 and 0.05 (measured: within 3e-9). The meeting
/// is a fold of the grazing orbit: the curve's last point, just before it,
/// grazes with a multiplier within 2e-4 of +1; a hundredth of a step (1e-5 in
/// δ) before it the orbit grazes before it folds, as far past it it folds
/// first, on the line of constant δ, where the curve's tangent at the meeting
/// reaches that δ (the fold curve touches the grazing curve there).
#[test]
fn grazing_sn_meeting_is_the_same_with_two_step_settings_and_is_where_the_grazing_orbit_folds() {
    let (t1, t2) = (tracing(0.9, 4, 0.01), tracing(0.9, 40, 0.05));
    let (c1, c2) = (grazing_curve(&t1, 0.9), grazing_curve(&t2, 0.9));
    let (m1, m2) = (fold_meeting_of(&c1), fold_meeting_of(&c2));
    assert!((m1.a - m2.a).abs().max((m1.b - m2.b).abs()) < 1e-6, "{m1:?} and {m2:?}");
    assert!((m1.a - 0.2892524).abs() < 1e-6 && (m1.b - 0.8177646).abs() < 1e-6, "{m1:?}");
    let last = c1.points.last().unwrap();
    let f = meet::fold_test(&last.orbit);
    assert!((meet::FOLD_MARGIN..2.0 * meet::FOLD_MARGIN).contains(&f), "1 - μ = {f} at the last point");
    // The grazing curve's slope dω/dδ at the meeting.
    let slope = (m1.a - last.a) / (m1.b - last.b);
    let fold = Tracing { kind: Bifurcation::SaddleNode, scale: [1e-4, 1e-4], ..t1.clone() };
    let at = |d: f64| fold.locate_from(&plane, last, [m1.a, m1.b + d], [1.0, 0.0]);
    let before = at(-1e-5).expect_err("the orbit grazes first before the meeting");
    assert!(before.others.iter().any(|o| o.0 == Bifurcation::Grazing), "{before}");
    let past = at(1e-5).expect("the orbit folds first past the meeting");
    assert!((past.a - (m1.a + slope * 1e-5)).abs() < 1e-8, "the fold at δ = {} is at ω = {}", past.b, past.a);
}

/// The impact damper at `(ω, δ)`.
fn damper(omega: f64, delta: f64) -> Option<System> {
    static SCENE: OnceLock<scene::Scene> = OnceLock::new();
    scene_at(&SCENE, "impact-damper.toml", omega, delta)
}

/// Issue 64: the strong resonance 1:3 on the Neimark–Sacker curve of the
/// impact damper's symmetric 1-1-1 orbit, followed in (ω, δ) from δ = 2 up
/// to δ = 5, is where the orbit solved there anew (Newton from the curve's
/// point before it) has its pair of multipliers of the period map at
/// e^{±2πi/3}: its angle within 1e-4 of 2π/3, its modulus within 1e-4 of 1
/// (the point is interpolated between two points of the curve; measured
/// 1.9e-5 and 5.2e-5, at ω = 1.57225, δ = 4.66947).
#[test]
fn a_resonance_on_a_neimark_sacker_curve_is_where_its_multipliers_are_cube_roots_of_one() {
    let t = Tracing {
        kind: Bifurcation::NeimarkSacker,
        acc: Accuracy::default(),
        n: None,
        scale: [0.02, 0.15],
        bounds: [[0.0, f64::INFINITY], [2.0, 5.0]],
        max_points: 200,
    };
    let first = t.locate(&damper, 1.7948, 2.0, Start::Fresh).expect("the NS at δ = 2");
    let curve = t.follow(&damper, first, 5.0);
    let r = curve.codim2.iter().find(|c| c.kind == "1:3").unwrap_or_else(|| panic!("no 1:3: {:?}", curve.codim2));
    let before = curve.points.iter().rfind(|p| p.b <= r.b).expect("a point before it");
    let o = &before.orbit;
    let sys = damper(r.a, r.b).unwrap();
    let at = solve_orbit(&sys, &t.acc, &o.solution.x, o.map, o.n, Some(&o.solution.pattern)).expect("its orbit");
    let pair = at
        .multipliers
        .iter()
        .filter(|z| z.im > 0.0)
        .min_by(|x, y| (x.norm() - 1.0).abs().total_cmp(&(y.norm() - 1.0).abs()))
        .expect("a complex pair");
    let third = std::f64::consts::TAU / 3.0;
    assert!((pair.arg() - third).abs() < 1e-4 && (pair.norm() - 1.0).abs() < 1e-4, "μ = {pair} at {r:?}");
}

/// A second multiplier that crossed the unit circle between two points is
/// named by its kind where it lay outside: a real one past −1 on one side
/// that met another inside and left the real line as a pair is a doubling
/// (an independent simulator's multipliers of the single stop's 3-2-0 orbit
/// on its grazing curve, ζ = 0.05, at ω = 2.6991 and 2.7207), a pair
/// outside on either side a Neimark–Sacker, a real one past +1 a fold; and
/// as many outside at both points is no crossing.
#[test]
fn a_crossing_is_named_by_the_multiplier_outside_the_circle() {
    let z = C64::new;
    let doubling = [z(-1.008, 0.0), z(-0.202, 0.0)];
    let pair = [z(-0.428, 0.146), z(-0.428, -0.146)];
    let (t, kind) = crossed(&doubling, &pair).expect("a crossing");
    assert_eq!(kind, Bifurcation::PeriodDoubling);
    assert!((0.0..0.05).contains(&t), "{t}");
    assert_eq!(crossed(&pair, &doubling).map(|c| c.1), Some(Bifurcation::PeriodDoubling));
    let torus = [z(0.6, 0.85), z(0.6, -0.85)];
    assert_eq!(crossed(&pair, &torus).map(|c| c.1), Some(Bifurcation::NeimarkSacker));
    assert_eq!(
        crossed(&[z(1.02, 0.0), z(0.3, 0.0)], &[z(0.98, 0.0), z(0.3, 0.0)]).map(|c| c.1),
        Some(Bifurcation::SaddleNode)
    );
    assert_eq!(crossed(&doubling, &[z(-1.2, 0.0), z(-0.1, 0.0)]), None);
    assert_eq!(crossed(&doubling, &pair[..1]), None);
}
