//! Basins of attraction over a plane of initial states ([`BasinMap`]): which
//! attractor each start of a grid reaches, the attractors with their basin
//! fractions, and the measures of the boundary between basins
//! ([`Entropy`], [`Uncertainty`]).
//!
//! A start is a full state `[x…, v…]` at the forcing phase `phase`: the two
//! components named by the axes (`x_M2`, `v_M2`) take the grid's values,
//! every other one its value in [`BasinMap::start`].

use crate::Axis;
use solver::Label;

/// The id of a start that penetrates a stop (no motion starts there).
pub const INADMISSIBLE: i32 = -1;

/// Starts per side of the boxes of a map's basin entropy ([`BasinMap::entropy`]).
pub const ENTROPY_BOX: usize = 5;

/// One attractor of a basin map.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinAttractor {
    /// Its class (`periodic`, `chaotic`, `quasi-periodic`, `unresolved`).
    pub class: String,
    /// Per labelled mass, its label.
    pub labels: Vec<Label>,
    /// The symmetry of a periodic orbit of a symmetric scene.
    pub symmetry: Option<String>,
    /// Why the motion is unresolved, where it is.
    pub reason: Option<String>,
    /// The largest Floquet multiplier modulus, when periodic.
    pub multiplier: Option<f64>,
    /// The largest Lyapunov exponent (per unit time), when not periodic.
    pub lyapunov: Option<f64>,
    /// The starts that reached it.
    pub count: u64,
    /// The first start (in row order) that reached it.
    pub start: Vec<f64>,
    /// Its period-section points (states at the start's phase plus whole
    /// forcing periods), as that start's motion gave them.
    pub section: Vec<Vec<f64>>,
}

/// Basins of attraction over a grid of initial states.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinMap {
    /// The scene's name.
    pub scene: String,
    /// Every parameter of the point's model, in scene order.
    pub parameters: Vec<(String, f64)>,
    /// The names of the labelled masses, in label order.
    pub masses: Vec<String>,
    /// The names of the state's components (`x_M1`, …, `v_M1`, …).
    pub components: Vec<String>,
    /// The state every start shares outside the two axes.
    pub start: Vec<f64>,
    /// The forcing phase `ω t + τ` at the start (radians).
    pub phase: f64,
    /// Whether starts were stopped once they reached a stable periodic
    /// attractor already found (their `periods` are then those followed).
    pub early: bool,
    /// The horizontal axis: a state component's values.
    pub x: Axis,
    /// The vertical axis: a state component's values.
    pub y: Axis,
    /// The attractor each start reached, row-major `[y][x]` (index into
    /// `attractors`, or [`INADMISSIBLE`]).
    pub ids: Vec<i32>,
    /// Forcing periods each start was simulated for.
    pub periods: Vec<u64>,
    /// The attractors, the largest basin first (ties: the first reached).
    pub attractors: Vec<BasinAttractor>,
}

impl BasinMap {
    /// The starts that are admissible (do not penetrate a stop).
    pub fn admissible(&self) -> u64 {
        self.ids.iter().filter(|&&i| i != INADMISSIBLE).count() as u64
    }

    /// The basin fraction of attractor `k`: its starts over the admissible ones.
    pub fn fraction(&self, k: usize) -> f64 {
        self.attractors[k].count as f64 / self.admissible().max(1) as f64
    }

    /// The colour of each attractor: its first label's
    /// ([`crate::palette::colour`]), darkened by a third for each earlier
    /// attractor of the same label (the mirror image of an asymmetric orbit,
    /// say), so that two attractors are never one colour.
    pub fn colours(&self) -> Vec<[u8; 3]> {
        let first = |k: usize| self.attractors[k].labels.first().copied().unwrap_or(Label::Unresolved);
        (0..self.attractors.len())
            .map(|k| {
                let twins = (0..k).filter(|&j| first(j) == first(k)).count() as i32;
                crate::palette::colour(first(k)).map(|c| (f64::from(c) * 0.65f64.powi(twins)).round() as u8)
            })
            .collect()
    }

    /// The basin entropy of the map on boxes of [`ENTROPY_BOX`] starts.
    pub fn entropy(&self) -> Entropy {
        entropy(&self.ids, self.x.count, ENTROPY_BOX)
    }

    /// The uncertainty exponent of the map's boundaries.
    pub fn uncertainty(&self) -> Uncertainty {
        uncertainty(&self.ids, self.x.count)
    }
}

/// Basin entropy `S_b` and boundary basin entropy `S_bb` (Daza, Wagemakers,
/// Georgeot, Guéry-Odelin and Sanjuán, Sci. Rep. 6, 31416, 2016): the map is
/// cut into boxes of `side` × `side` starts; in box `i`, with `p_ij` the
/// share of its starts that reach attractor `j`, `S_i = −Σ_j p_ij ln p_ij`.
/// `S_b` is the mean of `S_i` over all boxes, `S_bb` over the boxes that meet
/// a boundary (`S_i > 0`). `S_bb > ln 2` proves the boundary fractal (their
/// "ln 2 criterion"); below it the test is silent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entropy {
    /// Starts per side of a box.
    pub side: usize,
    /// Basin entropy `S_b` (nats).
    pub basin: f64,
    /// Boundary basin entropy `S_bb` (nats; 0 without a boundary).
    pub boundary: f64,
    /// Boxes counted (those holding no inadmissible start).
    pub boxes: usize,
    /// Of those, the boxes that meet a boundary.
    pub boundary_boxes: usize,
}

impl Entropy {
    /// Whether the ln 2 criterion proves the boundary fractal.
    pub fn fractal(&self) -> bool {
        self.boundary > std::f64::consts::LN_2
    }
}

/// [`Entropy`] of the id map `ids` (`nx` starts per row) on boxes of `side`
/// starts (whole boxes only; a box with an inadmissible start is left out).
pub fn entropy(ids: &[i32], nx: usize, side: usize) -> Entropy {
    let side = side.max(1);
    let ny = ids.len().checked_div(nx).unwrap_or(0);
    let (mut sum, mut sum_boundary, mut boxes, mut boundary_boxes) = (0.0, 0.0, 0, 0);
    let mut counts: Vec<(i32, usize)> = Vec::new();
    for by in 0..ny / side {
        for bx in 0..nx / side {
            counts.clear();
            let cells = (0..side).flat_map(|r| (0..side).map(move |c| (by * side + r) * nx + bx * side + c));
            for i in cells {
                match counts.iter_mut().find(|(id, _)| *id == ids[i]) {
                    Some(c) => c.1 += 1,
                    None => counts.push((ids[i], 1)),
                }
            }
            if counts.iter().any(|&(id, _)| id == INADMISSIBLE) {
                continue;
            }
            let n = (side * side) as f64;
            let s: f64 = counts.iter().map(|&(_, c)| c as f64 / n).map(|p| -p * p.ln()).sum();
            sum += s;
            boxes += 1;
            if counts.len() > 1 {
                sum_boundary += s;
                boundary_boxes += 1;
            }
        }
    }
    Entropy {
        side,
        basin: if boxes > 0 { sum / boxes as f64 } else { f64::NAN },
        boundary: if boundary_boxes > 0 { sum_boundary / boundary_boxes as f64 } else { 0.0 },
        boxes,
        boundary_boxes,
    }
}

/// The uncertainty exponent `α` of the boundary (McDonald, Grebogi, Ott and
/// Yorke, Physica D 17, 125, 1985), from the grid itself: a start is
/// ε-uncertain when one of the four starts `ε` away from it along the axes
/// (ε = k grid steps, k = 1, 2, 4, … up to an eighth of the grid) reaches
/// another attractor; the uncertain share `f(ε)` scales as `ε^α`, and `α`
/// is the least-squares slope of `ln f` against `ln k`. A smooth boundary
/// gives `α = 1`, a fractal one `α < 1` (its box-counting dimension is
/// `d − α`, d = 2). The starts counted are the same at every distance: those
/// at least the largest distance from the grid's edge, admissible, with their
/// four neighbours admissible.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// The distances, in grid steps.
    pub steps: Vec<usize>,
    /// The uncertain share of starts at each distance.
    pub fractions: Vec<f64>,
    /// The exponent α (NaN without a boundary, or with fewer than three distances).
    pub exponent: f64,
}

/// [`Uncertainty`] of the id map `ids` with `nx` starts per row.
pub fn uncertainty(ids: &[i32], nx: usize) -> Uncertainty {
    let ny = ids.len().checked_div(nx).unwrap_or(0);
    let mut steps = Vec::new();
    let mut k = 1;
    while 8 * k <= nx.min(ny) {
        steps.push(k);
        k *= 2;
    }
    // One set of starts for every distance: those a largest step from the edge.
    let margin = steps.last().copied().unwrap_or(0);
    let fractions: Vec<f64> = steps
        .iter()
        .map(|&k| {
            let (mut counted, mut uncertain) = (0usize, 0usize);
            for iy in margin..ny - margin {
                for ix in margin..nx - margin {
                    let i = iy * nx + ix;
                    let near = [i - k, i + k, i - k * nx, i + k * nx];
                    if ids[i] == INADMISSIBLE || near.iter().any(|&j| ids[j] == INADMISSIBLE) {
                        continue;
                    }
                    counted += 1;
                    uncertain += usize::from(near.iter().any(|&j| ids[j] != ids[i]));
                }
            }
            if counted > 0 {
                uncertain as f64 / counted as f64
            } else {
                f64::NAN
            }
        })
        .collect();
    let points: Vec<(f64, f64)> =
        steps.iter().zip(&fractions).filter(|(_, f)| **f > 0.0).map(|(&k, &f)| ((k as f64).ln(), f.ln())).collect();
    let exponent = if points.len() >= 3 && points.len() == steps.len() { slope(&points) } else { f64::NAN };
    Uncertainty { steps, fractions, exponent }
}

/// The least-squares slope of `points`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map of `n` × `n` starts split by `basin(x, y)` (coordinates in [0, 1)).
    fn map(n: usize, basin: impl Fn(f64, f64) -> i32) -> Vec<i32> {
        (0..n * n).map(|i| basin((i % n) as f64 / n as f64, (i / n) as f64 / n as f64)).collect()
    }

    #[test]
    fn a_straight_boundary_has_exponent_one_and_little_entropy() {
        // A boundary along a line: the uncertain share is exactly
        // proportional to ε (two rows of width k per unit length).
        let ids = map(256, |x, _| i32::from(x >= 0.5));
        let u = uncertainty(&ids, 256);
        assert_eq!(u.steps, vec![1, 2, 4, 8, 16, 32]);
        assert!((u.exponent - 1.0).abs() < 0.02, "{u:?}");
        // Boxes of 8 on a boundary at a box edge: no box is mixed.
        let e = entropy(&ids, 256, 8);
        assert_eq!((e.boxes, e.boundary_boxes, e.basin, e.boundary), (1024, 0, 0.0, 0.0));
        // Shifted by half a box: each of the 32 boundary boxes is half and half.
        let ids = map(256, |x, _| i32::from(x >= 0.5 + 4.0 / 256.0));
        let e = entropy(&ids, 256, 8);
        assert_eq!(e.boundary_boxes, 32);
        assert!((e.boundary - std::f64::consts::LN_2).abs() < 1e-12 && !e.fractal(), "{e:?}");
        assert!((e.basin - std::f64::consts::LN_2 * 32.0 / 1024.0).abs() < 1e-12);
    }

    #[test]
    fn a_riddled_map_is_fractal_with_exponent_near_zero() {
        // Three basins drawn at random start by start: every box is mixed
        // (S_bb near ln 3 > ln 2) and the uncertain share does not fall with ε.
        let mut s = 12345u64;
        let ids: Vec<i32> = (0..128 * 128)
            .map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((s >> 33) % 3) as i32
            })
            .collect();
        let e = entropy(&ids, 128, 5);
        assert!(e.fractal() && (e.boundary - 3f64.ln()).abs() < 0.1, "{e:?}");
        let u = uncertainty(&ids, 128);
        assert!(u.exponent.abs() < 0.05, "{u:?}");
    }

    #[test]
    fn one_basin_has_no_boundary_and_inadmissible_starts_are_left_out() {
        let ids = map(64, |x, _| if x < 0.25 { INADMISSIBLE } else { 0 });
        let u = uncertainty(&ids, 64);
        assert!(u.fractions.iter().all(|&f| f == 0.0) && u.exponent.is_nan(), "{u:?}");
        let e = entropy(&ids, 64, 4);
        assert_eq!((e.boxes, e.boundary_boxes), (16 * 12, 0));
    }
}
