//! Poincaré sections of a classified cell.
//!
//! σ_II, the period section, is the state at `t = kT` (stroboscopic): the
//! classifier keeps those points. σ_I^s, the impact section of stop s, is the
//! state just before each impact on s, with its forcing phase `t mod T`; it is
//! recorded by re-simulating the classified window with [`ImpactRecorder`]
//! ([`record_window`], called by [`crate::run_cell_with_sections`]),
//! so nothing is stored unless asked.

use crate::simulate::{Both, EventObserver, Simulator};
use nalgebra::DVector;

/// Points of one section, each of the same number of values, kept row
/// after row in one vector: what an atlas holds of every cell until its
/// file is written (one allocation per section, not one per point: on the
/// main job's plane 730 000 allocations fewer, and its heap's peak 125 MB
/// rather than 142).
#[derive(Debug, Clone, Default)]
pub struct Points {
    width: usize,
    values: Vec<f64>,
}

impl Points {
    /// No points yet, each to be of `width` values.
    pub fn new(width: usize) -> Points {
        Points { width, values: Vec::new() }
    }

    /// The points `rows`, which must all have the length of the first; `None`
    /// where one does not.
    pub fn from_rows<R: AsRef<[f64]>>(rows: impl IntoIterator<Item = R>) -> Option<Points> {
        let mut points: Option<Points> = None;
        for row in rows {
            let row = row.as_ref();
            let p = points.get_or_insert_with(|| Points::new(row.len()));
            if row.len() != p.width {
                return None;
            }
            p.values.extend_from_slice(row);
        }
        let mut points = points.unwrap_or_default();
        points.values.shrink_to_fit();
        Some(points)
    }

    /// Values per point (0 for points never given one).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.width).unwrap_or(0)
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The points in order.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.values.chunks_exact(self.width.max(1))
    }

    /// The points, each a vector of its own (for a result that shows them
    /// as such, or a caller that keeps a few).
    pub fn to_rows(&self) -> Vec<Vec<f64>> {
        self.iter().map(<[f64]>::to_vec).collect()
    }

    /// Every value, point after point.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// The same points (no points are the same whatever their width).
impl PartialEq for Points {
    fn eq(&self, other: &Points) -> bool {
        self.values == other.values && (self.is_empty() || self.width == other.width)
    }
}

impl<'a> IntoIterator for &'a Points {
    type Item = &'a [f64];
    type IntoIter = std::slice::ChunksExact<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// A list of points, as a list of lists of numbers (the shape of the
/// journal's lines).
impl serde::Serialize for Points {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

impl<'de> serde::Deserialize<'de> for Points {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Points, D::Error> {
        let rows = Vec::<Vec<f64>>::deserialize(d)?;
        Points::from_rows(rows).ok_or_else(|| serde::de::Error::custom("points of different lengths"))
    }
}

/// Records up to `cap` impacts per stop: `[phase, x…, v…]` just before impact.
#[derive(Debug, Clone)]
pub struct ImpactRecorder {
    period: f64,
    cap: usize,
    /// Per stop, the recorded points.
    pub rows: Vec<Points>,
}

impl ImpactRecorder {
    /// A recorder for a system with forcing period `period` and full states
    /// of `dim` values, whose stops will see `impacts` impacts each: room for
    /// as many points as each will keep, so that the sections are kept as
    /// they are.
    pub fn new(period: f64, cap: usize, dim: usize, impacts: &[u32]) -> Self {
        let room = |n: u32| Points { width: dim + 1, values: Vec::with_capacity(cap.min(n as usize) * (dim + 1)) };
        ImpactRecorder { period, cap, rows: impacts.iter().map(|&n| room(n)).collect() }
    }
}

impl EventObserver for ImpactRecorder {
    fn impact(&mut self, time: f64, stop: usize, before: &DVector<f64>, _after: &DVector<f64>) {
        let rows = &mut self.rows[stop];
        if rows.len() < self.cap {
            rows.values.push(time.rem_euclid(self.period));
            rows.values.extend(before.iter());
        }
    }
}

/// Impact sections of a window of `periods` forcing periods from full state
/// `start` (a classified window with `impacts` impacts per stop), simulated
/// again by `sim`, at most `cap` points per stop; empty when there is no window
/// or it cannot be simulated. The simulation stops once every stop has all the
/// points it will get.
/// The simulation is observed by `also` too; with the sections, the periods
/// it ran (`None` where the window could not be simulated to that point).
pub(crate) fn record_window(
    sim: &mut Simulator<'_>,
    start: &[f64],
    periods: usize,
    impacts: &[u32],
    cap: usize,
    also: &mut dyn EventObserver,
) -> (Vec<Points>, Option<usize>) {
    let sys = sim.system();
    let mut rec = ImpactRecorder::new(sys.period, cap, start.len(), impacts);
    if periods == 0 || sim.restart(start).is_err() {
        return (rec.rows, None);
    }
    let complete = |rec: &ImpactRecorder| rec.rows.iter().zip(impacts).all(|(r, &n)| r.len() >= cap.min(n as usize));
    let mut ran = 0;
    while ran < periods && !complete(&rec) {
        if sim.run_period(&[], false, &mut Both(&mut rec, also)).is_err() {
            return (rec.rows, None);
        }
        ran += 1;
    }
    (rec.rows, Some(ran))
}

#[cfg(test)]
mod tests {
    use super::Points;

    /// Points keep their rows in order and read as the lists of numbers they
    /// were (the journal's shape, bit for bit); rows of different lengths are
    /// refused; no points equal no points whatever their width.
    #[test]
    fn points_are_their_rows() {
        let rows = vec![vec![0.1, -2.5, 1e-300], vec![3.0, f64::MIN_POSITIVE, -0.0]];
        let p = Points::from_rows(&rows).unwrap();
        assert_eq!((p.len(), p.width(), p.is_empty()), (2, 3, false));
        assert_eq!(p.to_rows(), rows);
        let text = serde_json::to_string(&p).unwrap();
        assert_eq!(text, serde_json::to_string(&rows).unwrap());
        let back: Points = serde_json::from_str(&text).unwrap();
        assert!(back.values().iter().zip(p.values()).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(back, p);
        assert!(Points::from_rows([vec![1.0, 2.0], vec![3.0]]).is_none());
        let refused = serde_json::from_str::<Points>("[[1,2],[3]]").unwrap_err().to_string();
        assert!(refused.contains("points of different lengths"), "{refused}");
        assert_eq!(Points::new(5), Points::default());
        assert_ne!(Points::from_rows([[1.0, 2.0]]).unwrap(), Points::from_rows([[1.0], [2.0]]).unwrap());
    }
}
