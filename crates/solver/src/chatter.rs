//! Chatter: a geometric sequence of ever slower impacts at one stop.
//!
//! Under a force pressing a mass onto a stop, impact speeds decay like
//! `v_{k+1} ≈ R v_k` and flight times like `Δ_{k+1} ≈ R Δ_k`, so infinitely many
//! impacts accumulate at `t_∞ = t_k + Δ_k ρ/(1-ρ)` with `ρ = Δ_k/Δ_{k-1}`. Once a
//! sequence is recognised as geometric and slow, the remaining tail is replaced
//! by sticking (the constrained motion it converges to), which is where complete
//! chattering ends.

/// Tracks the last impacts at each stop.
#[derive(Debug, Clone, PartialEq)]
pub struct ChatterTracker {
    last: Vec<[(f64, f64); 3]>,
    count: Vec<usize>,
}

impl ChatterTracker {
    /// A tracker for `stops` stops.
    pub fn new(stops: usize) -> Self {
        ChatterTracker { last: vec![[(0.0, 0.0); 3]; stops], count: vec![0; stops] }
    }

    /// Forgets the sequence at `stop` (after sticking, or an impact elsewhere).
    pub fn reset(&mut self, stop: usize) {
        self.count[stop] = 0;
    }

    /// Records an impact at absolute time `t` with closing speed `v`; returns the
    /// predicted accumulation time when the last three impacts form a geometric
    /// sequence slower than `max_speed`.
    pub fn record(&mut self, stop: usize, t: f64, v: f64, max_speed: f64) -> Option<f64> {
        let l = &mut self.last[stop];
        l.rotate_left(1);
        l[2] = (t, v);
        self.count[stop] += 1;
        if self.count[stop] < 3 || v >= max_speed {
            return None;
        }
        let [(t0, v0), (t1, v1), (t2, v2)] = *l;
        let (r1, r2) = (v1 / v0, v2 / v1);
        let (d1, d2) = (t1 - t0, t2 - t1);
        let rho = d2 / d1;
        let geometric = r1 < 1.0 && r2 < 1.0 && (r1 - r2).abs() < 0.05 && (rho - r2).abs() < 0.1 && rho < 1.0;
        geometric.then(|| t2 + d2 * rho / (1.0 - rho))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_sequence_predicts_its_accumulation_point() {
        let mut c = ChatterTracker::new(1);
        // Bouncing ball under unit gravity, R = 0.5: flight time 2v, v halves each time.
        let (mut t, mut v) = (0.0, 1e-4);
        let mut pred = None;
        for _ in 0..3 {
            pred = c.record(0, t, v, 1e-3);
            t += 2.0 * v * 0.5;
            v *= 0.5;
        }
        // Impacts at 0, 1e-4, 1.5e-4, ... accumulate at 2e-4.
        let p = pred.expect("geometric");
        assert!((p - 2e-4).abs() < 1e-12, "{p}");
        assert!(c.record(0, 1.0, 1.0, 1e-3).is_none());
    }
}
