//! A map's cells and legend as data, for an interactive client that paints
//! them itself (`vibroatlas explore`): per cell the colour the figures give
//! it, and the legend rows the figures draw beside it. The same functions
//! choose both, so the page and `render` never disagree on a colour.

use crate::error::RenderError;
use crate::legend::{Entry, Swatch};
use crate::map::{count, label_paint, sweep_rows, Hysteresis, Overlay, Paint, View};
use crate::scalar::{Drawn, Scaled, NONE};
use crate::show::Show;
use maps::Atlas;
use plotters::style::RGBColor;

/// Rows of a legend on a screen, where it scrolls: every label up to the
/// figures' limit, then their families.
const SCREEN_ROWS: usize = 60;

/// A colour bar: its title, its ends, and colours evenly along it.
pub type Scale = (String, f64, f64, Vec<[u8; 3]>);

/// One legend row: its swatch, as the figures draw it, and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    /// `heading`, `fill`, `split` (first colour above the rising diagonal,
    /// second below), `hatch` (a group of labels), `line`, `ring` or `dot`.
    pub swatch: &'static str,
    /// Its colours, RGB.
    pub colours: Vec<[u8; 3]>,
    /// The text.
    pub text: String,
}

/// A layer of a map: per cell, row-major from the first value of y, the
/// colour drawn above its rising diagonal and the one below (the same but
/// for split cells), and the legend.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// Cells across (the x axis's values).
    pub nx: usize,
    /// Cells up (the y axis's values).
    pub ny: usize,
    /// RGB of each cell's upper-left half, 3 bytes per cell.
    pub above: Vec<u8>,
    /// RGB of each cell's lower-right half, 3 bytes per cell.
    pub below: Vec<u8>,
    /// The legend rows.
    pub legend: Vec<Key>,
    /// The colour bar of a scalar layer: its title, value range and the
    /// colours of 11 evenly spaced values from low to high.
    pub scale: Option<Scale>,
}

fn rgb(c: RGBColor) -> [u8; 3] {
    [c.0, c.1, c.2]
}

fn key(e: &Entry) -> Key {
    let (swatch, colours) = match e.swatch {
        Swatch::Heading => ("heading", vec![]),
        Swatch::Fill(c) => ("fill", vec![rgb(c)]),
        Swatch::Split(a, b) => ("split", vec![rgb(a), rgb(b)]),
        Swatch::Hatch(c) => ("hatch", vec![rgb(c)]),
        Swatch::Line(c, ..) => ("line", vec![rgb(c)]),
        Swatch::Ring(c, _) => ("ring", vec![rgb(c)]),
        Swatch::Dot(c, _) => ("dot", vec![rgb(c)]),
    };
    Key { swatch, colours, text: e.text.clone() }
}

/// The layer `show` of mass `mass` (an index into the atlas's masses) with
/// `curves` in its legend.
pub fn layer(atlas: &Atlas, show: Show, mass: usize, curves: &[Overlay]) -> Result<Layer, RenderError> {
    let m = &atlas.meta;
    if mass >= m.masses.len() {
        return Err(RenderError::new(format!("no mass {mass}: the atlas labels {}", m.masses.join(", "))));
    }
    let (nx, ny) = (m.plane.x.count, m.plane.y.count);
    let n = nx * ny;
    let (mut above, mut below) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
    let mut put = |p: Paint| {
        let (a, b) = match p {
            Paint::Fill(c) => (c, c),
            Paint::Split(a, b) => (a, b),
        };
        above.extend(rgb(a));
        below.extend(rgb(b));
    };
    let (legend, scale) = match show {
        Show::Map(View::Sweep(sweep)) => {
            let cells = crate::map::sweep_cells(atlas, sweep)?;
            let paint = label_paint(cells, mass);
            (0..n).filter_map(&paint).for_each(&mut put);
            (sweep_rows(&count(&[cells], mass), curves, SCREEN_ROWS), None)
        }
        Show::Map(View::Hysteresis) => {
            let h = Hysteresis::of(atlas, mass)?;
            (0..n).map(|i| h.paint(i)).for_each(&mut put);
            (h.rows(curves, SCREEN_ROWS), None)
        }
        Show::Scalar(sweep, quantity) => {
            let s = Scaled::of(atlas, sweep, quantity)?;
            let title = format!("{}: {}", quantity.unit(m), quantity.long_name(m));
            scalar_layer(&s, &mut put, quantity.none(), title)
        }
        Show::Difference(quantity) => {
            let s = Scaled::difference(atlas, quantity)?;
            scalar_layer(
                &s,
                &mut put,
                "none",
                format!("Δ {}: up less down: {}", quantity.unit(m), quantity.long_name(m)),
            )
        }
    };
    Ok(Layer { nx, ny, above, below, legend: legend.iter().map(key).collect(), scale })
}

/// Paints every cell of `s` with `put`; the legend (grey: `none`) and the
/// colour bar (`title`, its ends and eleven colours along it).
fn scalar_layer(s: &Scaled, put: &mut impl FnMut(Paint), none: &str, title: String) -> (Vec<Entry>, Option<Scale>) {
    (0..s.values.len()).map(|i| Paint::Fill(s.colour(i))).for_each(put);
    let (lo, hi) = (s.lo, s.hi);
    let stops = (0..=10).map(|k| rgb(s.colour_of(lo + (hi - lo) * k as f64 / 10.0))).collect();
    (vec![Entry::new(Swatch::Fill(NONE), none)], Some((title, lo, hi, stops)))
}

/// The legend rows the figures draw for `(label, cells)` counts in at most
/// `rows` rows, for a client that draws a map itself (`vibroatlas.plot`):
/// the most frequent labels told apart by colour, the rest in hatched
/// family groups (the counts are ordered here, most frequent first).
pub fn label_legend(counts: &[(solver::Label, u64)], rows: usize) -> Vec<Key> {
    let counts = maps::by_frequency(counts.iter().copied(), solver::Label::to_string);
    crate::map::label_entries(&counts, rows).iter().map(key).collect()
}

/// The colour, width (pt) and dash (pt on, pt off; off 0: solid) the
/// figures draw a bifurcation curve of `kind` with.
pub fn curve_style(kind: &str) -> ([u8; 3], f64, (f64, f64)) {
    let (c, width, dash) = crate::map::curve_style(kind);
    (rgb(c), width, dash)
}
