//! What an atlas holds, in numbers: its grid, per sweep the cells of each
//! class, label and reason, and its hysteresis ([`SummaryReport`], the
//! object `inspect --json` prints).

use grid::hysteresis::zones;
use grid::Atlas;
use scene::Named;
use serde::Serialize;
use solver::Class;
use std::collections::BTreeMap;

/// Why a sweep's unresolved cells are unresolved: each kind of reason and
/// how many cells, the most frequent first. A kind is a reason's text with
/// its numbers set apart; it is shown with each number as it varies over
/// its cells: the number where they all agree, else its range (`λT =
/// -2.103e-3 to -4.000e-4`), each end as one of the cells wrote it.
pub fn reasons(cells: &[Option<grid::CellData>]) -> Vec<(String, usize)> {
    let mut kinds: std::collections::BTreeMap<String, (usize, Vec<Range>)> = std::collections::BTreeMap::new();
    for r in cells.iter().flatten().filter_map(|c| c.reason.as_ref()) {
        let (template, numbers) = split_numbers(&r.to_string());
        let (n, ranges) = kinds.entry(template).or_insert_with(|| (0, numbers.iter().map(Range::of).collect()));
        *n += 1;
        for (range, number) in ranges.iter_mut().zip(&numbers) {
            range.take(number);
        }
    }
    let mut v: Vec<(String, usize)> =
        kinds.into_iter().map(|(template, (n, ranges))| (filled(&template, &ranges), n)).collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    v
}

/// A number of a reason as written (`-1.5e-3`) and its value.
type Number = (f64, String);

/// The least and the greatest of one number over the cells of a kind.
struct Range {
    low: Number,
    high: Number,
}

impl Range {
    fn of(n: &Number) -> Range {
        Range { low: n.clone(), high: n.clone() }
    }

    fn take(&mut self, n: &Number) {
        if n.0 < self.low.0 {
            self.low = n.clone();
        }
        if n.0 > self.high.0 {
            self.high = n.clone();
        }
    }

    fn text(&self) -> String {
        if self.low.1 == self.high.1 {
            self.low.1.clone()
        } else {
            format!("{} to {}", self.low.1, self.high.1)
        }
    }
}

/// `text` with every number (`-1.5e-3`, `400000`) written `…`, and the
/// numbers in order.
fn split_numbers(text: &str) -> (String, Vec<Number>) {
    let mut out = String::new();
    let mut numbers = Vec::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let sign = c == '-' && chars.peek().is_some_and(char::is_ascii_digit);
        if c.is_ascii_digit() || sign {
            let mut token = c.to_string();
            while let Some(&d) = chars.peek().filter(|&&d| d.is_ascii_digit() || ".eE".contains(d) || "+-".contains(d))
            {
                token.push(d);
                chars.next();
            }
            numbers.push((token.trim_end_matches(['.', 'e', 'E', '+', '-']).parse().unwrap_or(f64::NAN), token));
            out.push('…');
        } else {
            out.push(c);
        }
    }
    (out, numbers)
}

/// `template` with its `…` replaced by the ranges, in order.
fn filled(template: &str, ranges: &[Range]) -> String {
    let mut out = String::new();
    let mut ranges = ranges.iter();
    for c in template.chars() {
        match (c, c == '…') {
            (_, true) => out.push_str(&ranges.next().map_or("…".to_string(), Range::text)),
            (c, false) => out.push(c),
        }
    }
    out
}

/// What an atlas holds, in numbers ([`Summary::of`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Each sweep's, in the file's order.
    pub sweeps: Vec<SweepSummary>,
    /// Where up and down differ: the cells, and the size of each zone (the
    /// largest first), when the atlas has both.
    pub hysteresis: Option<(usize, Vec<usize>)>,
}

/// One sweep of an atlas, in numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSummary {
    /// The sweep.
    pub sweep: grid::SweepKind,
    /// Cells computed.
    pub computed: usize,
    /// Cells per class: periodic, quasiperiodic, chaotic, unresolved.
    pub classes: [usize; 4],
    /// Per labelled mass, each label and its cells, the most frequent first.
    pub labels: Vec<Vec<(String, u64)>>,
    /// Why its unresolved cells are unresolved ([`reasons`]).
    pub reasons: Vec<(String, usize)>,
}

/// The classes of [`SweepSummary::classes`], in order.
pub const CLASSES: [Class; 4] = [Class::Periodic, Class::Quasiperiodic, Class::Chaotic, Class::Unresolved];

impl Summary {
    /// The summary of `atlas`.
    pub fn of(atlas: &Atlas) -> Summary {
        let p = &atlas.meta.plane;
        let sweeps = atlas
            .maps
            .iter()
            .map(|map| {
                let cells: Vec<_> = map.cells.iter().flatten().collect();
                SweepSummary {
                    sweep: map.sweep,
                    computed: cells.len(),
                    classes: CLASSES.map(|c| cells.iter().filter(|x| x.class == c).count()),
                    labels: (0..atlas.meta.masses.len())
                        .map(|mi| atlas.legend(map.sweep, mi).into_iter().map(|(l, n)| (l.to_string(), n)).collect())
                        .collect(),
                    reasons: reasons(&map.cells),
                }
            })
            .collect();
        let hysteresis =
            atlas.hysteresis().map(|h| (h.iter().map(|&v| v as usize).sum(), zones(&h, p.x.count, p.y.count)));
        Summary { sweeps, hysteresis }
    }

    /// Cells computed, every sweep together.
    pub fn computed(&self) -> usize {
        self.sweeps.iter().map(|s| s.computed).sum()
    }
}

/// The JSON of an atlas's summary: grid, sweeps with class and label
/// counts per mass and reasons, hysteresis cells and zone sizes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SummaryReport {
    /// The scene's name.
    pub scene: String,
    /// The accuracy preset.
    pub preset: &'static str,
    /// The integrator.
    pub integrator: &'static str,
    /// The x axis.
    pub x: AxisReport,
    /// The y axis.
    pub y: AxisReport,
    /// The axis continuation chains follow (`x` or `y`).
    pub along: &'static str,
    /// Cells of the plane.
    pub cells: usize,
    /// Labelled masses.
    pub masses: Vec<String>,
    /// Stops.
    pub stops: Vec<String>,
    /// Each sweep, in the file's order.
    pub sweeps: Vec<SweepCounts>,
    /// Where up and down differ, when the atlas has both.
    pub hysteresis: Option<HysteresisCounts>,
}

/// An axis: its parameter and values.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisReport {
    /// The parameter.
    pub name: String,
    /// First value.
    pub start: f64,
    /// Last value.
    pub stop: f64,
    /// Number of values.
    pub count: usize,
}

impl AxisReport {
    /// The report of an axis.
    pub fn of(a: &grid::Axis) -> AxisReport {
        AxisReport { name: a.name.clone(), start: a.start, stop: a.stop, count: a.count }
    }
}

/// One sweep in numbers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepCounts {
    /// `fresh`, `up` or `down`.
    pub sweep: &'static str,
    /// Cells computed.
    pub computed: usize,
    /// Cells per class.
    pub classes: ClassCounts,
    /// Per labelled mass, the cells of each label.
    pub labels: BTreeMap<String, BTreeMap<String, u64>>,
    /// Why its unresolved cells are unresolved, the most frequent first.
    pub reasons: Vec<ReasonCount>,
}

/// Cells per class.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClassCounts {
    /// Periodic.
    pub periodic: usize,
    /// Quasiperiodic.
    pub quasiperiodic: usize,
    /// Chaotic.
    pub chaotic: usize,
    /// Unresolved.
    pub unresolved: usize,
}

/// The cells of one kind of reason ([`reasons`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReasonCount {
    /// The reason, its numbers as they vary over its cells.
    pub reason: String,
    /// Its cells.
    pub cells: usize,
}

/// Where up and down differ.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HysteresisCounts {
    /// Cells.
    pub cells: usize,
    /// The size of each zone, the largest first.
    pub zones: Vec<usize>,
}

impl SummaryReport {
    /// The summary of `atlas` as its report.
    pub fn of(atlas: &Atlas) -> SummaryReport {
        let m = &atlas.meta;
        let p = &m.plane;
        let axis = AxisReport::of;
        let summary = Summary::of(atlas);
        let sweeps = summary
            .sweeps
            .iter()
            .map(|s| {
                let labels =
                    m.masses.iter().cloned().zip(s.labels.iter().map(|l| l.iter().cloned().collect())).collect();
                let [periodic, quasiperiodic, chaotic, unresolved] = s.classes;
                SweepCounts {
                    sweep: s.sweep.name(),
                    computed: s.computed,
                    classes: ClassCounts { periodic, quasiperiodic, chaotic, unresolved },
                    labels,
                    reasons: s
                        .reasons
                        .iter()
                        .map(|(reason, n)| ReasonCount { reason: reason.clone(), cells: *n })
                        .collect(),
                }
            })
            .collect();
        SummaryReport {
            scene: m.scene_name.clone(),
            preset: m.preset.name(),
            integrator: m.integrator.name(),
            x: axis(&p.x),
            y: axis(&p.y),
            along: p.along.name(),
            cells: p.cells(),
            masses: m.masses.clone(),
            stops: m.stops.clone(),
            sweeps,
            hysteresis: summary.hysteresis.map(|(cells, zones)| HysteresisCounts { cells, zones }),
        }
    }
}

/// The JSON of an atlas file (the contract of `inspect --json`): its
/// [`SummaryReport`] with the file's provenance (its path, when and by what
/// it was made, its history, run time and shard; a zoom's parent).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InspectReport {
    /// The atlas's summary.
    #[serde(flatten)]
    pub summary: SummaryReport,
    /// The file.
    pub file: String,
    /// When it was made.
    pub created: String,
    /// The command that made it.
    pub command: String,
    /// The commands that changed it since.
    pub history: Vec<String>,
    /// Seconds the run took.
    pub run_time_s: f64,
    /// The shard it holds (`K/N`), if one.
    pub shard: Option<String>,
    /// The atlas a zoom was computed in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parent: Option<ParentReport>,
    /// Whether the whole file was checked (`inspect --verify`): set by the caller.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verified: Option<bool>,
}

/// The atlas a zoom was computed in.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParentReport {
    /// Its file.
    pub file: String,
    /// The CRC-32 of its labels, in hex.
    pub labels_crc32: String,
    /// The box, as the zoom's axes.
    #[serde(rename = "box")]
    pub region: String,
}

impl InspectReport {
    /// The report of the file `path` read as `loaded`.
    pub fn of(path: &std::path::Path, loaded: &store::Loaded) -> InspectReport {
        let info = &loaded.info;
        InspectReport {
            summary: SummaryReport::of(&loaded.atlas),
            file: path.display().to_string(),
            created: loaded.created.clone(),
            command: info.command.clone(),
            history: info.history.clone(),
            run_time_s: info.run_time_s,
            shard: info.shard.map(|s| s.to_string()),
            parent: info.parent.as_ref().map(|p| ParentReport {
                file: p.path.clone(),
                labels_crc32: format!("{:08x}", p.labels_crc32),
                region: p.region.clone(),
            }),
            verified: None,
        }
    }

    /// The JSON object of the file (the contract of `inspect --json`).
    pub fn to_json(&self) -> serde_json::Value {
        crate::report::to_value(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unresolved(reason: solver::Unresolved) -> Option<grid::CellData> {
        Some(grid::CellData {
            class: Class::Unresolved,
            labels: Vec::new(),
            chatter: solver::Mask::EMPTY,
            sticking: solver::Mask::EMPTY,
            symmetry: None,
            lyapunov: None,
            multiplier: None,
            final_state: Vec::new(),
            periods: 0,
            events: 0,
            period_section: solver::Points::default(),
            impact_sections: Vec::new(),
            reason: Some(Box::new(reason)),
            quantities: Vec::new(),
        })
    }

    /// Issue 40: reasons are shown with their numbers (each as it varies over
    /// the cells of its kind), not as templates.
    #[test]
    fn reasons_show_their_numbers() {
        let contracting = |growth| unresolved(solver::Unresolved::Contracting { growth, stuck: None });
        let cells = vec![
            contracting(-1.5e-3),
            None,
            contracting(-4e-2),
            contracting(-2e-3),
            unresolved(solver::Unresolved::Budget { max_events: 400_000 }),
        ];
        let transient = "a transient longer than max_periods x (1 + extensions)";
        assert_eq!(
            reasons(&cells),
            vec![
                (
                    format!(
                        "no period within the record, and the motion still contracts (λT = -4.000e-2 to -1.500e-3): {transient}"
                    ),
                    3
                ),
                ("event budget of 400000 events exhausted".to_string(), 1),
            ]
        );
    }
}

/// Where a number per cell (a quantity of the steady motion, the largest
/// multiplier or the Lyapunov exponent: [`grid::Number`]) is smallest and
/// largest over the plane of each sweep (`inspect --quantity NAME`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityReport {
    /// The number's name (`max_abs_x_M1`, `multiplier`).
    pub name: String,
    /// Its symbol (`max |x| M1`).
    pub symbol: String,
    /// Its long name.
    pub long_name: String,
    /// Its units.
    pub units: String,
    /// Per sweep, by name.
    pub sweeps: BTreeMap<String, QuantityExtremes>,
}

/// A quantity's extremes over one sweep's plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityExtremes {
    /// Cells where the quantity was measured.
    pub cells: usize,
    /// The smallest value and the first cell (row by row) that has it.
    pub min: Option<Extreme>,
    /// The largest value and the first cell (row by row) that has it.
    pub max: Option<Extreme>,
}

/// A value at a cell: the value and the cell's parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Extreme {
    /// The value.
    pub value: f64,
    /// The cell's parameters (the plane's two).
    pub at: BTreeMap<String, f64>,
}

impl QuantityReport {
    /// The extremes of quantity `name` of `atlas` over `sweep` (every sweep
    /// of the file when `None`); an error naming `quantity` (or `sweep`) when
    /// the file has no such quantity (or sweep).
    pub fn of(atlas: &Atlas, name: &str, sweep: Option<grid::SweepKind>) -> crate::Result<QuantityReport> {
        use crate::error::{Opt, RequestError};
        let m = &atlas.meta;
        let Some(number) = grid::Number::named(m, name) else {
            let stored: Vec<&str> = grid::Number::all(m).map(|n| n.name(m)).collect();
            let why = format!("'{name}' is not a number the file stores per cell ({})", stored.join(", "));
            return Err(RequestError::option(Opt::Quantity).text(why).into());
        };
        if let Some(s) = sweep.filter(|s| !m.sweeps.contains(s)) {
            let have: Vec<&str> = m.sweeps.iter().map(|k| k.name()).collect();
            let why = format!("the file has {}, not {}", have.join(", "), s.name());
            return Err(RequestError::option(Opt::Sweep).text(why).into());
        }
        let mut sweeps = BTreeMap::new();
        for map in atlas.maps.iter().filter(|map| sweep.is_none_or(|s| s == map.sweep)) {
            let values = map.cells.iter().enumerate().filter_map(|(i, c)| Some((i, number.value(c.as_ref()?)?)));
            // The cell index and value of the smallest and the largest so far.
            type Best = Option<(usize, f64)>;
            let (mut cells, mut min, mut max): (usize, Best, Best) = (0, None, None);
            for (i, v) in values {
                cells += 1;
                if min.is_none_or(|(_, m)| v < m) {
                    min = Some((i, v));
                }
                if max.is_none_or(|(_, m)| v > m) {
                    max = Some((i, v));
                }
            }
            let nx = m.plane.x.count;
            let extreme = |e: Option<(usize, f64)>| {
                e.map(|(i, value)| Extreme { value, at: m.plane.params(i / nx, i % nx).into_iter().collect() })
            };
            sweeps
                .insert(map.sweep.name().to_string(), QuantityExtremes { cells, min: extreme(min), max: extreme(max) });
        }
        Ok(QuantityReport {
            name: name.to_string(),
            symbol: number.symbol(m).to_string(),
            long_name: number.long_name(m).to_string(),
            units: number.units(m).to_string(),
            sweeps,
        })
    }

    /// The report as JSON (the object of `inspect --quantity NAME --json`).
    pub fn to_json(&self) -> serde_json::Value {
        crate::report::to_value(self)
    }
}
