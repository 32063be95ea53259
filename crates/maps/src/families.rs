//! Attractors followed across a plane ([`families`]): the attractors that
//! `atlas --attractors K` finds in each cell, matched from cell to cell into
//! families, so that one motion's basin fraction can be mapped over the plane.
//!
//! The rule: two attractors of neighbouring cells (left and right, or one
//! above the other) belong to one family when they have the same labels and,
//! among the attractors of those labels in the two cells, they are the
//! nearest pair: pairs are taken nearest first, each attractor in at most
//! one pair per neighbour, the distance being the Hausdorff distance (max
//! norm) between their stored period-section points (0 where either has none:
//! a motion without a period, or a file written before they were stored).
//! Families are the connected sets of attractors so paired, numbered by their
//! basin fraction summed over the plane, the largest first (ties: the first
//! cell, in row order).

use crate::{AttractorMap, CellAttractor};
use solver::Label;

/// The families of an [`AttractorMap`].
#[derive(Debug, Clone, PartialEq)]
pub struct Families {
    /// Per cell (row-major), the family of each of its attractors (`None`
    /// where the cell was not sampled).
    pub ids: Vec<Option<Vec<u32>>>,
    /// Per family, the labels of its attractors (one per labelled mass).
    pub labels: Vec<Vec<Label>>,
    /// Per family, the number of cells it is found in.
    pub cells: Vec<usize>,
}

impl Families {
    /// The basin fraction of `family` in every cell (row-major): NaN where
    /// the cell was not sampled, 0 where it was and the family is absent.
    pub fn fraction_map(&self, map: &AttractorMap, family: u32) -> Vec<f64> {
        map.cells
            .iter()
            .zip(&self.ids)
            .map(|(cell, ids)| match (cell, ids) {
                (Some(found), Some(ids)) => {
                    found.iter().zip(ids).filter(|(_, &id)| id == family).map(|(a, _)| a.fraction).sum()
                }
                _ => f64::NAN,
            })
            .collect()
    }
}

/// The Hausdorff distance (max norm) between two sets of section points; 0
/// where either is empty.
fn distance(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let d = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let one_way = |s: &[Vec<f64>], t: &[Vec<f64>]| {
        s.iter().map(|p| t.iter().map(|q| d(p, q)).fold(f64::INFINITY, f64::min)).fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// The root of `i` in the union-find forest `parent` (paths halved).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The families of the attractors of `map`, a plane of `nx` cells per row
/// (see the module doc for the rule).
pub fn families(map: &AttractorMap, nx: usize) -> Families {
    let empty: &[CellAttractor] = &[];
    let found = |i: usize| map.cells[i].as_deref().unwrap_or(empty);
    // Each attractor's index among all: the cell's offset plus its slot.
    let mut offset = Vec::with_capacity(map.cells.len() + 1);
    offset.push(0);
    for i in 0..map.cells.len() {
        offset.push(offset[i] + found(i).len());
    }
    let mut parent: Vec<usize> = (0..offset[map.cells.len()]).collect();
    for i in 0..map.cells.len() {
        let right = (nx > 0 && (i + 1) % nx != 0).then_some(i + 1);
        let above = Some(i + nx).filter(|&j| j < map.cells.len());
        for j in [right, above].into_iter().flatten() {
            let (a, b) = (found(i), found(j));
            let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
            for (k, x) in a.iter().enumerate() {
                for (l, y) in b.iter().enumerate().filter(|(_, y)| y.labels == x.labels) {
                    pairs.push((distance(&x.section, &y.section), k, l));
                }
            }
            pairs.sort_by(|p, q| p.0.total_cmp(&q.0).then((p.1, p.2).cmp(&(q.1, q.2))));
            let (mut used_a, mut used_b) = (vec![false; a.len()], vec![false; b.len()]);
            for (_, k, l) in pairs {
                if used_a[k] || used_b[l] {
                    continue;
                }
                (used_a[k], used_b[l]) = (true, true);
                let (ra, rb) = (root(&mut parent, offset[i] + k), root(&mut parent, offset[j] + l));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Families by their summed fraction, the largest first (ties: the first attractor).
    let n = parent.len();
    let mut total = vec![0.0; n];
    let mut cells = vec![0usize; n];
    for (i, &first) in offset[..map.cells.len()].iter().enumerate() {
        for (k, a) in found(i).iter().enumerate() {
            let r = root(&mut parent, first + k);
            total[r] += a.fraction;
            cells[r] += 1;
        }
    }
    let mut roots: Vec<usize> = (0..n).filter(|&r| parent[r] == r).collect();
    roots.sort_by(|&p, &q| total[q].total_cmp(&total[p]).then(p.cmp(&q)));
    let mut id = vec![0u32; n];
    for (f, &r) in roots.iter().enumerate() {
        id[r] = f as u32;
    }
    let mut labels = vec![Vec::new(); roots.len()];
    let ids = (0..map.cells.len())
        .map(|i| {
            map.cells[i].as_ref().map(|c| {
                c.iter()
                    .enumerate()
                    .map(|(k, a)| {
                        let f = id[root(&mut parent, offset[i] + k)];
                        if labels[f as usize].is_empty() {
                            labels[f as usize] = a.labels.clone();
                        }
                        f
                    })
                    .collect()
            })
        })
        .collect();
    Families { ids, labels, cells: roots.iter().map(|&r| cells[r]).collect() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(label: &str, fraction: f64, x: f64) -> CellAttractor {
        CellAttractor { labels: vec![label.parse().unwrap()], fraction, section: vec![vec![x, 0.0]] }
    }

    #[test]
    fn mirror_twins_are_followed_as_two_families_and_labels_never_mix() {
        // A row of three cells and one above the first: two 1-1-1 orbits
        // (near x = +1 and x = −1, drifting), a 2-2-2 in two cells; the
        // slots' order changes from cell to cell.
        let cells = vec![
            Some(vec![at("1-1-1", 0.6, 1.0), at("1-1-1", 0.4, -1.0)]),
            Some(vec![at("1-1-1", 0.5, -1.1), at("1-1-1", 0.3, 1.1), at("2-2-2", 0.2, 0.0)]),
            Some(vec![at("2-2-2", 1.0, 0.1)]),
            Some(vec![at("1-1-1", 0.8, -0.9), at("1-1-1", 0.2, 0.9)]),
            None,
            None,
        ];
        let map = AttractorMap { samples: 10, seed: 1, cells };
        let f = families(&map, 3);
        let ids: Vec<Option<Vec<u32>>> = f.ids.clone();
        // By summed fraction: the −1 twin 1.7, 2-2-2 1.2, the +1 twin 1.1.
        assert_eq!(ids[0], Some(vec![2, 0]));
        assert_eq!(ids[1], Some(vec![0, 2, 1]));
        assert_eq!(ids[2], Some(vec![1]));
        assert_eq!(ids[3], Some(vec![0, 2]));
        assert_eq!(ids[4], None);
        assert_eq!(f.cells, vec![3, 2, 3]);
        assert_eq!(f.labels[1], vec!["2-2-2".parse::<Label>().unwrap()]);
        let m = f.fraction_map(&map, 0);
        assert_eq!(&m[..4], &[0.4, 0.5, 0.0, 0.8]);
        assert!(m[4].is_nan() && m[5].is_nan());
    }
}
