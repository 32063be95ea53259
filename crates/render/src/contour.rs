//! Contour lines of a continuous map (`render --view NAME --contours N`):
//! where the value, interpolated linearly between the centres of
//! neighbouring cells, equals a level (marching squares). A square with a
//! cell without a value has no line; a saddle (two opposite corners above
//! the level, two below) is resolved by the mean of its four corners.

/// The contour of `level` over a grid of `nx` × `ny` cell values (row
/// by row, `None` where a cell has none), as segments between points in
/// fractional cell indices `(ix, iy)`.
pub(crate) fn segments(values: &[Option<f64>], nx: usize, ny: usize, level: f64) -> Vec<[(f64, f64); 2]> {
    let mut out = Vec::new();
    for iy in 0..ny.saturating_sub(1) {
        for ix in 0..nx.saturating_sub(1) {
            // Corners counter-clockwise from the lower left.
            let at = [(ix, iy), (ix + 1, iy), (ix + 1, iy + 1), (ix, iy + 1)];
            let corner = |k: usize| values[at[k].1 * nx + at[k].0];
            let (Some(a), Some(b), Some(c), Some(d)) = (corner(0), corner(1), corner(2), corner(3)) else {
                continue;
            };
            let v = [a, b, c, d];
            let above = v.map(|c| c >= level);
            // Where the level crosses edge k (from corner k to corner k + 1).
            let cross = |k: usize| {
                let (a, b) = (k, (k + 1) % 4);
                let t = (level - v[a]) / (v[b] - v[a]);
                let (pa, pb) = (at[a], at[b]);
                (pa.0 as f64 + t * (pb.0 as f64 - pa.0 as f64), pa.1 as f64 + t * (pb.1 as f64 - pa.1 as f64))
            };
            let mut edges = (0..4).filter(|&k| above[k] != above[(k + 1) % 4]);
            let edges: [Option<usize>; 4] = std::array::from_fn(|_| edges.next());
            match edges {
                [Some(e0), Some(e1), None, _] => out.push([cross(e0), cross(e1)]),
                [Some(_), Some(_), Some(_), Some(_)] => {
                    // A saddle: the centre's side decides which corners join.
                    let centre_above = v.iter().sum::<f64>() / 4.0 >= level;
                    let (first, second) = if centre_above == above[0] { ((0, 3), (1, 2)) } else { ((0, 1), (2, 3)) };
                    out.push([cross(first.0), cross(first.1)]);
                    out.push([cross(second.0), cross(second.1)]);
                }
                _ => {}
            }
        }
    }
    out
}

/// At most `count` levels at round values (steps of 1, 2 or 5 times a
/// power of ten) strictly between `lo` and `hi`.
pub(crate) fn levels(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if count == 0 || hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Vec::new();
    }
    let raw = (hi - lo) / (count + 1) as f64;
    let exponent = raw.log10().floor() as i32;
    let power = 10f64.powi(exponent);
    let mantissa = [1.0, 2.0, 5.0, 10.0].into_iter().find(|m| m * power >= raw).unwrap_or(10.0);
    // k steps as a whole number of powers of ten, so that 0.6 is 6/10.
    let at = |k: i64| match exponent {
        e if e >= 0 => k as f64 * mantissa * power,
        e => k as f64 * mantissa / 10f64.powi(-e),
    };
    let first = (lo / (mantissa * power)).floor() as i64 + 1;
    // A step at least `raw` leaves at most `count + 1` levels below `hi`;
    // bounded so, values whose steps round to nothing (subnormal numbers,
    // whose power of ten is 0) give no level rather than no end.
    (first..first.saturating_add(count as i64 + 1))
        .map(at)
        .take_while(|&l| l < hi)
        .filter(|&l| l > lo)
        .take(count)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_s_contour_is_a_straight_line_where_it_equals_the_level() {
        // v = ix + 0.3 iy: the level 2.5 is the line ix = 2.5 - 0.3 iy.
        let (nx, ny) = (6, 5);
        let values: Vec<Option<f64>> = (0..nx * ny).map(|i| Some((i % nx) as f64 + 0.3 * (i / nx) as f64)).collect();
        let s = segments(&values, nx, ny, 2.5);
        // One unbroken line from the first row to the last.
        let rise: f64 = s.iter().map(|[a, b]| (b.1 - a.1).abs()).sum();
        assert!((rise - (ny - 1) as f64).abs() < 1e-12, "{s:?}");
        for p in s.iter().flatten() {
            assert!((p.0 - (2.5 - 0.3 * p.1)).abs() < 1e-12, "{p:?}");
        }
    }

    #[test]
    fn a_circle_s_contour_lies_near_it_and_a_cell_without_a_value_breaks_it() {
        let n = 41;
        let r = |x: f64, y: f64| ((x - 20.0).powi(2) + (y - 20.0).powi(2)).sqrt();
        let mut values: Vec<Option<f64>> = (0..n * n).map(|i| Some(r((i % n) as f64, (i / n) as f64))).collect();
        let s = segments(&values, n, n, 10.0);
        assert!(s.len() > 40, "{}", s.len());
        // Linear interpolation of r along an edge errs by at most h²/(8r).
        for p in s.iter().flatten() {
            assert!((r(p.0, p.1) - 10.0).abs() < 0.02, "{p:?}");
        }
        values[22 * n + 30] = None;
        let broken = segments(&values, n, n, 10.0);
        assert!(broken.len() < s.len());
        let near = |p: &(f64, f64)| (p.0 - 30.0).abs() < 1.0 && (p.1 - 22.0).abs() < 1.0;
        assert!(!broken.iter().flatten().any(near), "no line in the four squares of the cell without a value");
        assert!(s.iter().flatten().any(near));
    }

    #[test]
    fn levels_of_subnormal_values_end() {
        // 1e-320 to 5e-320: the step's power of ten is 0 in doubles.
        let l = levels(1e-320, 5e-320, 3);
        assert!(l.len() <= 3 && l.iter().all(|&v| v > 1e-320 && v < 5e-320), "{l:?}");
    }

    #[test]
    fn levels_are_round_and_inside() {
        assert_eq!(levels(-8.4, 10.9, 5), vec![-5.0, 0.0, 5.0, 10.0]);
        assert_eq!(levels(0.0, 1.0, 4), vec![0.2, 0.4, 0.6, 0.8]);
        assert_eq!(levels(0.0, 0.03, 2), vec![0.01, 0.02]);
        assert!(levels(1.0, 1.0, 3).is_empty() && levels(0.0, 1.0, 0).is_empty());
    }
}
