//! Hysteresis: cells where the up- and down-sweeps end on different periodic
//! motions (both periodic, labels differ), i.e. where two motions coexist.
//! Zones are the 4-connected components of that mask.

use crate::cell::CellData;
use solver::Class;

/// 1 where both sweeps are periodic with different labels, else 0.
pub fn mask(up: &[Option<CellData>], down: &[Option<CellData>]) -> Vec<u8> {
    up.iter()
        .zip(down)
        .map(|pair| match pair {
            (Some(u), Some(d)) => {
                (u.class == Class::Periodic && d.class == Class::Periodic && u.labels != d.labels) as u8
            }
            _ => 0,
        })
        .collect()
}

/// Sizes of the 4-connected zones of a `ny × nx` mask, largest first.
pub fn zones(mask: &[u8], nx: usize, ny: usize) -> Vec<usize> {
    let mut seen = vec![false; mask.len()];
    let mut sizes = Vec::new();
    for start in 0..mask.len() {
        if mask[start] == 0 || seen[start] {
            continue;
        }
        let mut stack = vec![start];
        seen[start] = true;
        let mut size = 0;
        while let Some(i) = stack.pop() {
            size += 1;
            let (y, x) = (i / nx, i % nx);
            let mut push = |j: usize| {
                if mask[j] != 0 && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            };
            if x > 0 {
                push(i - 1);
            }
            if x + 1 < nx {
                push(i + 1);
            }
            if y > 0 {
                push(i - nx);
            }
            if y + 1 < ny {
                push(i + nx);
            }
        }
        sizes.push(size);
    }
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zones_are_connected_components() {
        let m = [1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0];
        assert_eq!(zones(&m, 4, 3), vec![2, 2, 1]);
    }
}
