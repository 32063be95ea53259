//! A scene's numbers for one cell ([`Scene::evaluate`]): the parameters'
//! values with the overrides applied, each expression evaluated, and the
//! physics checked (ranges, signs, the mass ratio, the forcing frequency, an
//! initial state that does not press into a stop, a declared symmetry).

use crate::compile::index_of;
use crate::expr::Compiled;
use crate::{
    CompiledLaw, Friction, Harmonic, Link, Mass, Model, Scene, SceneError, Stop, StopGeometry, StopLaw, StopPlace,
    INITIAL_PENETRATION, MASS_RATIO_MIN, OMEGA_MIN,
};

/// A phase (radians) as the solver takes it: the value itself where
/// |x| ≤ 2π (kept bit for bit), else its residue modulo 2π in (−π, π],
/// reduced exactly. The C library's `sin` and `cos` reduce their argument
/// with as many digits of π as it needs, and `atan2` of the two gives the
/// angle back to an ulp; reducing with the double nearest 2π instead would
/// be off by |x| · 2.4e-16 (2e-6 at 1e10), and forming `ω t + x` with a
/// large x would round every event's phase. A phase that is not finite is
/// refused, naming `field`.
fn phase(x: f64, field: &dyn Fn() -> String) -> Result<f64, SceneError> {
    if !x.is_finite() {
        return Err(SceneError::field(field(), format!("a phase must be a finite number of radians, got {x}")));
    }
    if x.abs() <= std::f64::consts::TAU {
        return Ok(x);
    }
    let (sin, cos) = x.sin_cos();
    Ok(sin.atan2(cos))
}

/// Refuses a mass lighter than [`MASS_RATIO_MIN`] times the heaviest.
fn check_mass_ratio(masses: &[Mass]) -> Result<(), SceneError> {
    let heaviest = masses.iter().map(|m| m.mass).fold(0.0, f64::max);
    match masses.iter().position(|m| m.mass < MASS_RATIO_MIN * heaviest) {
        Some(i) => Err(SceneError::field(
            format!("masses[{i}].mass"),
            format!(
                "{:e} is less than {MASS_RATIO_MIN:e} times the heaviest mass ({heaviest:e}): the motion cannot be resolved in double precision",
                masses[i].mass
            ),
        )),
        None => Ok(()),
    }
}

impl Scene {
    /// Evaluates every value for the default parameters with `overrides` applied
    /// (an override replaces the parameter's expression), and checks the physics.
    pub fn evaluate(&self, overrides: &[(String, f64)]) -> Result<Model, SceneError> {
        let n = self.names.len();
        let mut values = vec![f64::NAN; n];
        let mut known = vec![false; n];
        for (name, v) in overrides {
            let i = index_of(&self.names, name, || format!("parameters.{name}"), "parameter")?;
            if !v.is_finite() {
                return Err(SceneError::field(format!("parameters.{name}"), format!("not a finite number, got {v}")));
            }
            values[i] = *v;
            known[i] = true;
        }
        // Resolve parameters defined by expressions in dependency order.
        for &i in &self.order {
            if !known[i] {
                values[i] = self.params[i].0.eval(&values, || format!("parameters.{}", self.names[i]))?;
                known[i] = true;
            }
        }
        if let Some(i) = known.iter().position(|k| !k) {
            return Err(SceneError::field(
                format!("parameters.{}", self.names[i]),
                "circular definition among parameters",
            ));
        }
        for (i, (_, range)) in self.params.iter().enumerate() {
            if let Some(r) = range {
                if !r.contains(values[i]) {
                    return Err(SceneError::field(
                        format!("parameters.{}", self.names[i]),
                        format!("must be in {r}, got {}", crate::number(values[i])),
                    ));
                }
            }
        }
        self.build(&values)
    }

    fn build(&self, values: &[f64]) -> Result<Model, SceneError> {
        let ev = |c: &Compiled, f: &dyn Fn() -> String| c.eval(values, f);
        let omega = ev(&self.omega, &|| "forcing.omega".into())?;
        if omega.is_nan() || omega < OMEGA_MIN {
            return Err(SceneError::field(
                "forcing.omega",
                format!(
                    "must be at least {OMEGA_MIN:e} (under slower forcing every velocity is below the solver's stick velocity and contacts cannot be told from rest), got {}",
                    // 1e-7 as such, 0 and -2 plainly (`{:e}` writes 0e0 and -2e0).
                    if omega == 0.0 || omega.abs() >= 1e-3 { format!("{omega}") } else { format!("{omega:e}") }
                ),
            ));
        }
        let tau = phase(ev(&self.tau, &|| "forcing.phase".into())?, &|| "forcing.phase".into())?;
        let masses = self
            .masses
            .iter()
            .zip(&self.file.masses)
            .enumerate()
            .map(|(i, (m, spec))| {
                let mass = ev(&m.mass, &|| format!("masses[{i}].mass"))?;
                if mass <= 0.0 {
                    return Err(SceneError::field(format!("masses[{i}].mass"), format!("must be > 0, got {mass}")));
                }
                let harmonics = m
                    .harmonics
                    .iter()
                    .enumerate()
                    .map(|(j, (order, a, p))| {
                        let f = |k: &str| format!("masses[{i}].harmonics[{j}].{k}");
                        Ok(Harmonic {
                            order: *order,
                            amplitude: ev(a, &|| f("amplitude"))?,
                            phase: phase(ev(p, &|| f("phase"))?, &|| f("phase"))?,
                        })
                    })
                    .collect::<Result<Vec<_>, SceneError>>()?;
                Ok(Mass {
                    name: spec.name.clone(),
                    mass,
                    force: ev(&m.force, &|| format!("masses[{i}].force"))?,
                    load: ev(&m.load, &|| format!("masses[{i}].load"))?,
                    harmonics,
                    x0: ev(&m.x0, &|| format!("masses[{i}].x0"))?,
                    v0: ev(&m.v0, &|| format!("masses[{i}].v0"))?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        check_mass_ratio(&masses)?;
        let links = self
            .links
            .iter()
            .enumerate()
            .map(|(i, (a, b, k, c))| {
                Ok(Link {
                    a: *a,
                    b: *b,
                    stiffness: nonneg(k, values, &|| format!("links[{i}].stiffness"))?,
                    damping: nonneg(c, values, &|| format!("links[{i}].damping"))?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        let stops = self.build_stops(values)?;
        let friction = self.build_friction(values)?;
        let model = Model {
            name: self.file.name.clone(),
            symmetric: self.file.symmetric,
            omega,
            tau,
            masses,
            links,
            stops,
            friction,
            labels: self.labels.clone(),
            parameters: self.names.iter().cloned().zip(values.iter().copied()).collect(),
            quantities: self.quantities.clone(),
            scales: self.scales.clone(),
        };
        if model.symmetric {
            check_mirror(&model.stops)?;
            check_odd_forcing(&model.masses)?;
        }
        let x0: Vec<f64> = model.masses.iter().map(|m| m.x0).collect();
        // A rigid stop admits no initial penetration; a soft one's spring takes it up.
        let rigid = |s: &&Stop| match s.law {
            StopLaw::Rigid { .. } => true,
            StopLaw::Soft { .. } => false,
        };
        for (i, s) in model.stops.iter().enumerate().filter(|(_, s)| rigid(s)) {
            let g = model.gap(i, &x0);
            if g < -INITIAL_PENETRATION {
                return Err(SceneError::field(
                    "masses.x0",
                    format!("the initial state penetrates stop {} by {}", s.name, -g),
                ));
            }
        }
        Ok(model)
    }
    /// The stops at the parameter `values`: geometry and law (a restitution
    /// in [0, 1]; a soft stop's stiffness and damping not negative, not both zero).
    fn build_stops(&self, values: &[f64]) -> Result<Vec<Stop>, SceneError> {
        let ev = |c: &Compiled, f: &dyn Fn() -> String| c.eval(values, f);
        self.stops
            .iter()
            .zip(&self.file.stops)
            .enumerate()
            .map(|(i, ((place, law), spec))| {
                let f = |k: &str| format!("stops[{i}].{k}");
                let law = match law {
                    CompiledLaw::Rigid { restitution } => {
                        let restitution = ev(restitution, &|| f("restitution"))?;
                        if !(0.0..=1.0).contains(&restitution) {
                            return Err(SceneError::field(
                                f("restitution"),
                                format!("must be in [0, 1], got {}", crate::number(restitution)),
                            ));
                        }
                        StopLaw::Rigid { restitution }
                    }
                    CompiledLaw::Soft { stiffness, damping } => {
                        let stiffness = nonneg(stiffness, values, &|| f("stiffness"))?;
                        let damping = nonneg(damping, values, &|| f("damping"))?;
                        if stiffness == 0.0 && damping == 0.0 {
                            return Err(SceneError::field(
                                f("stiffness"),
                                format!(
                                    "soft stop {} has zero stiffness and zero damping: it would never act",
                                    spec.name
                                ),
                            ));
                        }
                        StopLaw::Soft { stiffness, damping }
                    }
                };
                let geometry = match place {
                    StopPlace::Frame { mass, side, position } => {
                        StopGeometry::Frame { mass: *mass, side: *side, position: ev(position, &|| f("position"))? }
                    }
                    StopPlace::Pair { first, second, gap } => {
                        StopGeometry::Pair { first: *first, second: *second, gap: nonneg(gap, values, &|| f("gap"))? }
                    }
                };
                Ok(Stop { name: spec.name.clone(), geometry, law })
            })
            .collect()
    }
    /// The friction contacts at the parameter `values`: static at least kinetic.
    fn build_friction(&self, values: &[f64]) -> Result<Vec<Friction>, SceneError> {
        self.friction
            .iter()
            .enumerate()
            .map(|(i, (a, b, k, s))| {
                let kinetic = nonneg(k, values, &|| format!("friction[{i}].kinetic"))?;
                let static_limit = s.eval(values, || format!("friction[{i}].static"))?;
                if static_limit < kinetic {
                    return Err(SceneError::field(
                        format!("friction[{i}].static"),
                        format!("must be >= the kinetic force {kinetic}, got {static_limit}"),
                    ));
                }
                Ok(Friction { a: *a, b: *b, kinetic, static_limit })
            })
            .collect()
    }
}

/// The value of `c` at the parameter `values` when it is not negative
/// (`field()` names the field of an error).
fn nonneg(c: &Compiled, values: &[f64], field: &dyn Fn() -> String) -> Result<f64, SceneError> {
    let v = c.eval(values, field)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(SceneError::field(field(), format!("must be >= 0, got {}", crate::number(v))))
    }
}

/// Checks that a scene declared `symmetric` is: every stop has a mirror image
/// under `x -> -x` among the stops (a frame stop at `p` on one side, one at `-p`
/// on the other side of the same mass; a pair stop `x_a - x_b <= g`, one with
/// the masses swapped), with the same law. Links and the first harmonic are odd
/// under the mirror with a half-period shift whatever their values; loads and
/// even harmonics are checked by [`check_odd_forcing`].
fn check_mirror(stops: &[Stop]) -> Result<(), SceneError> {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
    let same_law = |a: StopLaw, b: StopLaw| match (a, b) {
        (StopLaw::Rigid { restitution: r }, StopLaw::Rigid { restitution: s }) => close(r, s),
        (StopLaw::Soft { stiffness: k, damping: c }, StopLaw::Soft { stiffness: k2, damping: c2 }) => {
            close(k, k2) && close(c, c2)
        }
        _ => false,
    };
    for (i, s) in stops.iter().enumerate() {
        let mirrored = stops.iter().any(|t| {
            same_law(s.law, t.law)
                && match (&s.geometry, &t.geometry) {
                    (
                        StopGeometry::Frame { mass, side, position },
                        StopGeometry::Frame { mass: m2, side: s2, position: p2 },
                    ) => mass == m2 && side != s2 && close(*position, -*p2),
                    (
                        StopGeometry::Pair { first, second, gap },
                        StopGeometry::Pair { first: f2, second: s2, gap: g2 },
                    ) => first == s2 && second == f2 && close(*gap, *g2),
                    _ => false,
                }
        });
        if !mirrored {
            return Err(SceneError::field(
                "symmetric",
                format!(
                    "true, but stop {} (stops[{i}]) has no mirror image under x -> -x; set symmetric = false",
                    s.name
                ),
            ));
        }
    }
    Ok(())
}

/// Checks that the forcing of a scene declared `symmetric` is odd under a
/// half-period shift: no load, no harmonic of even order (with any
/// amplitude), which `x -> -x` would not map onto itself.
fn check_odd_forcing(masses: &[Mass]) -> Result<(), SceneError> {
    for (i, m) in masses.iter().enumerate() {
        if m.load != 0.0 {
            return Err(SceneError::field(
                format!("masses[{i}].load"),
                format!("{} breaks the mirror symmetry the scene declares (a load is even under x -> -x with a half-period shift); set symmetric = false", m.load),
            ));
        }
        if let Some(j) = m.harmonics.iter().position(|h| h.order % 2 == 0 && h.amplitude != 0.0) {
            return Err(SceneError::field(
                format!("masses[{i}].harmonics[{j}].order"),
                format!(
                    "{} (even) breaks the mirror symmetry the scene declares; set symmetric = false",
                    m.harmonics[j].order
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::phase;

    /// Large phases against their residues mod 2π computed with 100 digits
    /// of π (Python's decimal module): equal to an ulp; small ones kept bit
    /// for bit; a phase that is not finite refused, naming the field.
    #[test]
    fn phases_are_reduced_exactly() {
        let field = || "forcing.phase".to_string();
        for (x, residue) in [
            (62831853073.36665, 1.5707886731299447),
            (1.44e17, 2.2036341134760633),
            (1.4411518807593622e17, -6.770188667773585e-05),
            (-1e12, 0.6576247591367864),
        ] {
            let r = phase(x, &field).unwrap();
            assert!((r - residue).abs() <= 2.0 * f64::EPSILON, "{x}: {r} against {residue}");
        }
        for x in [0.0, -1.0, std::f64::consts::FRAC_PI_2, std::f64::consts::TAU, -std::f64::consts::TAU] {
            assert_eq!(phase(x, &field).unwrap().to_bits(), x.to_bits());
        }
        for x in [f64::NAN, f64::INFINITY] {
            let e = phase(x, &field).unwrap_err().to_string();
            assert!(e.starts_with("forcing.phase: a phase must be a finite number"), "{e}");
        }
    }
}
