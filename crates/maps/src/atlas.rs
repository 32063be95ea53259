//! An atlas in memory: what was computed (scene, plane, settings) and, per
//! sweep, the cells of the plane (row-major, `None` where not computed, e.g. in
//! a shard). Stores, renderers and summaries all read this one structure.

use crate::cell::{label_counts, CellData};
use crate::hysteresis::mask;
use crate::plane::{Entries, Line, Plane};
use crate::sweep::SweepKind;

/// What an atlas is a map of; two atlases with equal `Meta` can be merged.
#[derive(Debug, Clone, PartialEq)]
pub struct Meta {
    /// Scene name.
    pub scene_name: String,
    /// Scene TOML text.
    pub scene_toml: String,
    /// Parameter overrides common to every cell.
    pub overrides: Vec<(String, f64)>,
    /// Accuracy preset.
    pub preset: solver::Preset,
    /// Accuracy knobs overridden, in the order given.
    pub accuracy: Vec<(solver::Knob, f64)>,
    /// Integrator.
    pub integrator: solver::Method,
    /// The plane.
    pub plane: Plane,
    /// Sweeps computed.
    pub sweeps: Vec<SweepKind>,
    /// Labelled masses, in label order.
    pub masses: Vec<String>,
    /// Every mass of the scene, in state order (`[x…, v…]`).
    pub state_masses: Vec<String>,
    /// Per labelled mass, the stops its p and q count (empty when none).
    pub label_stops: Vec<[String; 2]>,
    /// Stops, in scene order.
    pub stops: Vec<String>,
    /// Per stop, the normal `n` of its gap `g = n·x + c` over the positions of
    /// `state_masses` (the closing speed of an impact is `-n·v`).
    pub stop_normals: Vec<Vec<f64>>,
    /// Per stop, which contact law it obeys (its events are impacts or
    /// contacts: [`Meta::stop_events`]).
    pub stop_laws: Vec<scene::LawKind>,
    /// State dimension `2 × masses of the scene`.
    pub dim: usize,
    /// Largest number of points kept per section per cell.
    pub section_cap: usize,
    /// How the scene's parameters are written (symbols, long names), for
    /// [`Meta::symbol`] and [`Meta::long_name`]; empty: by their names.
    pub notation: Vec<crate::Notation>,
    /// The quantities measured in every cell (empty: none, `--quantities none`
    /// or a file written before them).
    pub quantities: Vec<crate::Quantity>,
}

/// The cells of one sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// Which sweep.
    pub sweep: SweepKind,
    /// `ny × nx` cells, row-major.
    pub cells: Vec<Option<CellData>>,
}

/// One attractor found in a cell (by `grid::attractors`).
#[derive(Debug, Clone, PartialEq)]
pub struct CellAttractor {
    /// The label of each labelled mass.
    pub labels: Vec<solver::Label>,
    /// The share of the cell's samples that reached it (its basin fraction).
    pub fraction: f64,
    /// Its first period-section points (at most [`FAMILY_POINTS`], states
    /// `[x…, v…]`), which tell it from another attractor of its labels in
    /// the neighbouring cells ([`crate::families`]); none in a file written
    /// before them.
    pub section: Vec<Vec<f64>>,
}

/// Period-section points kept per attractor of an atlas's cells.
pub const FAMILY_POINTS: usize = 8;

/// The coexisting attractors found in one cell, the largest basin first.
pub type CellAttractors = Vec<CellAttractor>;

/// Coexisting attractors sampled over a plane (`atlas --attractors K`).
#[derive(Debug, Clone, PartialEq)]
pub struct AttractorMap {
    /// Initial states sampled per cell, and their seed.
    pub samples: usize,
    /// Seed of the sampling.
    pub seed: u64,
    /// `ny × nx`, row-major: `None` where not sampled.
    pub cells: Vec<Option<CellAttractors>>,
}

/// A whole atlas.
#[derive(Debug, Clone, PartialEq)]
pub struct Atlas {
    /// What it is a map of.
    pub meta: Meta,
    /// One map per sweep, in `meta.sweeps` order.
    pub maps: Vec<Map>,
    /// Coexisting attractors per cell, when sampled.
    pub attractors: Option<AttractorMap>,
    /// The states its chains entered the plane with (a zoom's, from its
    /// parent); empty: every chain from the scene's initial state.
    pub entries: Entries,
}

impl Meta {
    /// Whether the atlas has an up and a down sweep (what hysteresis compares).
    pub fn has_up_and_down(&self) -> bool {
        self.sweeps.contains(&SweepKind::Up) && self.sweeps.contains(&SweepKind::Down)
    }
}

impl Atlas {
    /// An atlas with no cell computed yet.
    pub fn new(meta: Meta) -> Atlas {
        let n = meta.plane.cells();
        let maps = meta.sweeps.iter().map(|&sweep| Map { sweep, cells: vec![None; n] }).collect();
        Atlas { meta, maps, attractors: None, entries: Entries::default() }
    }

    /// The map of one sweep.
    pub fn map(&self, sweep: SweepKind) -> Option<&Map> {
        self.maps.iter().find(|m| m.sweep == sweep)
    }

    /// Puts a computed line in place.
    pub fn insert(&mut self, line: Line) {
        let plane = self.meta.plane.clone();
        let nx = plane.x.count;
        if let Some(map) = self.maps.iter_mut().find(|m| m.sweep == line.sweep) {
            for (pos, cell) in line.cells.into_iter().enumerate() {
                let (iy, ix) = plane.cell(line.index, pos);
                map.cells[iy * nx + ix] = Some(cell);
            }
        }
    }

    /// Whether each line of `sweep` is fully computed.
    pub fn lines_done(&self, sweep: SweepKind) -> Vec<bool> {
        let p = &self.meta.plane;
        let nx = p.x.count;
        match self.map(sweep) {
            Some(map) => (0..p.lines())
                .map(|l| {
                    (0..p.line_len()).all(|pos| {
                        let (iy, ix) = p.cell(l, pos);
                        map.cells[iy * nx + ix].is_some()
                    })
                })
                .collect(),
            None => vec![false; p.lines()],
        }
    }

    /// Whether every cell of every sweep is computed.
    pub fn complete(&self) -> bool {
        self.maps.iter().all(|m| m.cells.iter().all(Option::is_some))
    }

    /// Hysteresis mask (1 where up and down give different periodic labels), when
    /// both sweeps are present.
    pub fn hysteresis(&self) -> Option<Vec<u8>> {
        Some(mask(&self.map(SweepKind::Up)?.cells, &self.map(SweepKind::Down)?.cells))
    }

    /// The cell of the plane nearest to the parameter values `at` (every axis
    /// of more than one value named once): `(iy, ix)`.
    pub fn nearest(&self, at: &[(String, f64)]) -> Result<(usize, usize), String> {
        let p = &self.meta.plane;
        let index = |a: &crate::Axis| -> Result<usize, String> {
            match at.iter().find(|(n, _)| *n == a.name) {
                Some(&(_, v)) => a.nearest(v),
                None if a.count == 1 => Ok(0),
                None => Err(format!("give {} (the file's axes are {} and {})", a.name, p.x.name, p.y.name)),
            }
        };
        if let Some((n, _)) = at.iter().find(|(n, _)| *n != p.x.name && *n != p.y.name) {
            return Err(format!("'{n}' is not an axis of the file ({} and {})", p.x.name, p.y.name));
        }
        Ok((index(&p.y)?, index(&p.x)?))
    }

    /// The state cell `(iy, ix)` of `sweep` started from: the final state of
    /// the cell before it along its continuation chain, or for the first of
    /// a chain its entry; `None` for a fresh cell or a chain's first without
    /// an entry (they start from the scene's initial state).
    pub fn start_of(&self, sweep: SweepKind, iy: usize, ix: usize) -> Option<&[f64]> {
        let p = &self.meta.plane;
        let map = self.map(sweep)?;
        let (line, pos) = p.position(iy, ix);
        let prev = match sweep {
            SweepKind::Fresh => return None,
            SweepKind::Up => pos.checked_sub(1),
            SweepKind::Down => Some(pos + 1).filter(|&q| q < p.line_len()),
        };
        let Some(prev) = prev else { return self.entries.get(sweep, line) };
        let (jy, jx) = p.cell(line, prev);
        map.cells[jy * p.x.count + jx].as_ref().map(|c| c.final_state.as_slice())
    }

    /// Labels of mass `m` in a sweep with their cell counts, most frequent
    /// first (ties in the order of the labels' text).
    pub fn legend(&self, sweep: SweepKind, m: usize) -> Vec<(solver::Label, u64)> {
        label_counts(self.map(sweep).into_iter().flat_map(|map| map.cells.iter().flatten()), m)
    }
}
