//! Coexisting attractors at one parameter point: initial states sampled in a
//! box, each cell classified, and the results grouped by the attractor they
//! reach, with the share of samples (the basin fraction) of each.
//!
//! Samples are states at the forcing phase of the scene (t = 0, the period
//! section): every attractor crosses that section, so sampling states there
//! reaches every attractor whose basin the box meets. Each position is uniform
//! in `[-x, x]` and each velocity in `[-v, v]` (dimensionless units of the
//! scene); a sample that penetrates a stop is drawn again. Sample `i` depends
//! only on the seed and `i` (SplitMix64), so the result is the same for any
//! number of threads.
//!
//! Two samples reach the same attractor when they have the same class, labels
//! and symmetry and, for periodic motions, the same set of period-section
//! points (each point of one within `1e-5 (1 + |y|)` of a point of the other,
//! max norm): mirror images of an asymmetric orbit, or two orbits of one label,
//! are told apart. Motions without a period are grouped by class and label.

use crate::cell::CellSetup;
use crate::error::GridError;
use crate::observer::Observer;
use maps::CellData;
use rayon::prelude::*;
use solver::contact::Contact;
use solver::Class;

/// How the initial states are drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    /// Number of initial states.
    pub samples: usize,
    /// Seed of the pseudo-random sequence.
    pub seed: u64,
    /// Half-width of the box of positions.
    pub x: f64,
    /// Half-width of the box of velocities.
    pub v: f64,
}

impl Default for Sampling {
    /// 64 states from seed 1 in the box |x| ≤ 2, |v| ≤ 2.
    fn default() -> Sampling {
        Sampling { samples: 64, seed: 1, x: 2.0, v: 2.0 }
    }
}

/// One attractor and the samples that reached it.
#[derive(Debug, Clone, PartialEq)]
pub struct Attractor {
    /// The first sample's cell that reached it (labels, section, stability).
    pub cell: CellData,
    /// The initial state of that sample.
    pub start: Vec<f64>,
    /// How many samples reached it.
    pub count: usize,
    /// Index of each sample that reached it.
    pub members: Vec<usize>,
}

/// SplitMix64: the `k`-th 64-bit output of the stream of `seed`.
fn splitmix(seed: u64, k: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9e3779b97f4a7c15u64.wrapping_mul(k.wrapping_add(1)));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
    z ^ (z >> 31)
}

/// Initial state of sample `i` (admissible for the system's stops).
pub fn sample(sys: &solver::System, s: &Sampling, i: usize) -> Vec<f64> {
    let m = sys.dof();
    let stream = splitmix(s.seed, i as u64);
    let unit = |k: u64| (splitmix(stream, k) >> 11) as f64 / (1u64 << 53) as f64;
    let mut draw = 0u64;
    loop {
        let y: Vec<f64> = (0..2 * m)
            .map(|j| {
                let half = if j < m { s.x } else { s.v };
                draw += 1;
                half * (2.0 * unit(draw) - 1.0)
            })
            .collect();
        if (0..sys.stops.len()).all(|k| sys.stops[k].law.yields() || sys.model.gap(k, &y[..m]) >= 0.0) || draw > 64_000
        {
            return y;
        }
    }
}

/// Whether two period sections are the same set of points.
fn same_orbit(a: &solver::Points, b: &solver::Points) -> bool {
    let near = |p: &[f64], q: &[f64]| p.iter().zip(q).all(|(x, y)| (x - y).abs() <= 1e-5 * (1.0 + x.abs()));
    a.len() == b.len() && a.iter().all(|p| b.iter().any(|q| near(p, q)))
}

/// Whether two cells reached the same attractor (see the module doc).
pub(crate) fn same(a: &CellData, b: &CellData) -> bool {
    a.class == b.class
        && a.labels == b.labels
        && a.symmetry == b.symmetry
        && (a.class != Class::Periodic || same_orbit(&a.period_section, &b.period_section))
}

/// Samples `sampling.samples` initial states at the parameters `params` and
/// groups the cells by attractor, most samples first (ties: first reached).
pub fn find(
    setup: &CellSetup,
    params: &[(String, f64)],
    sampling: &Sampling,
    threads: usize,
    progress: &dyn Observer,
) -> Result<Vec<Attractor>, GridError> {
    Ok(find_all(setup, &[params.to_vec()], sampling, threads, progress)?.remove(0))
}

/// [`find`] at each of `points`, every (point, sample) pair in one pool;
/// `progress` hears of every sample done and may stop the search before any
/// sample ([`GridError::Cancelled`]).
pub fn find_all(
    setup: &CellSetup,
    points: &[Vec<(String, f64)>],
    sampling: &Sampling,
    threads: usize,
    progress: &dyn Observer,
) -> Result<Vec<Vec<Attractor>>, GridError> {
    let systems = points.iter().map(|p| setup.system(p)).collect::<Result<Vec<_>, _>>()?;
    let setup = setup.comparing();
    let pool = crate::pool(threads)?;
    let k = sampling.samples.max(1);
    // Points in batches, each grouped once its samples are done: the cells
    // of at most BATCH samples are held at a time, however large the plane.
    let batch = (BATCH / k).max(1);
    let mut out = Vec::with_capacity(points.len());
    for first in (0..points.len()).step_by(batch) {
        let these = first..(first + batch).min(points.len());
        let cells: Vec<(Vec<f64>, CellData)> = pool.install(|| {
            (these.start * k..these.end * k)
                .into_par_iter()
                .map(|j| {
                    if progress.cancelled() {
                        return Err(GridError::Cancelled);
                    }
                    let (p, i) = (j / k, j % k);
                    let y0 = sample(&systems[p], sampling, i);
                    let cell = setup.run(&points[p], Some(&y0)).map(|c| (y0, c));
                    progress.advance(1);
                    cell
                })
                .collect::<Result<Vec<_>, _>>()
        })?;
        let mut it = cells.into_iter();
        for _ in these {
            out.push(group(it.by_ref().take(k)));
        }
    }
    Ok(out)
}

/// Samples computed before their points are grouped (bounds the memory of
/// a search over many points).
const BATCH: usize = 65_536;

/// Groups the sampled cells of one point by attractor (see the module doc).
fn group(cells: impl Iterator<Item = (Vec<f64>, CellData)>) -> Vec<Attractor> {
    let mut found: Vec<Attractor> = Vec::new();
    for (i, (start, cell)) in cells.into_iter().enumerate() {
        match found.iter_mut().find(|a| same(&a.cell, &cell)) {
            Some(a) => {
                a.count += 1;
                a.members.push(i);
            }
            None => found.push(Attractor { cell, start, count: 1, members: vec![i] }),
        }
    }
    found.sort_by(|a, b| b.count.cmp(&a.count).then(a.members[0].cmp(&b.members[0])));
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_splitmix64_and_spread() {
        // The published SplitMix64 stream of seed 1234567 (Vigna's reference
        // implementation, splitmix64.c): the samples of a seed are those of
        // the generator, whatever the thread that draws them.
        let reference = [6457827717110365317u64, 3203168211198807973, 9817491932198370423];
        assert_eq!([0, 1, 2].map(|k| splitmix(1234567, k)), reference);
        let s = Sampling { samples: 0, seed: 7, x: 2.0, v: 3.0 };
        let u: Vec<u64> = (0..1000).map(|k| splitmix(s.seed, k)).collect();
        let mean = u.iter().map(|&x| (x >> 11) as f64 / (1u64 << 53) as f64).sum::<f64>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
        let points = |rows: &[[f64; 2]]| solver::Points::from_rows(rows).unwrap();
        assert!(same_orbit(&points(&[[1.0, 2.0], [3.0, 4.0]]), &points(&[[3.0, 4.0], [1.0, 2.0 + 1e-9]])));
        assert!(!same_orbit(&points(&[[1.0, 2.0]]), &points(&[[-1.0, 2.0]])));
    }
}
