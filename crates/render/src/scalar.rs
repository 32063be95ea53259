//! A continuous map of one number per cell: the largest Lyapunov exponent of
//! cells without a period, on a diverging scale centred at 0 (blue contracting,
//! white neutral, red chaotic), or the largest Floquet multiplier modulus of
//! periodic cells on a diverging scale centred at 1, where stability is lost.
//! Cells without the number are mid grey (apart from the white of neutral values); a labelled colour bar gives the
//! scale.

use crate::axis::tick;
use crate::error::{err, RenderError};
use crate::layout;
use crate::legend::{self, Entry, Swatch};
use crate::map::{sweep_cells, CellGrid};
use crate::output::{save, Out};
use crate::page::{Backend, Canvas, Page};
use maps::{Atlas, CellData, Meta, Number, SweepKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use scene::Named;

/// How a continuous map draws each number per cell ([`Number`]).
pub(crate) trait Drawn {
    /// What a cell without the number is (legend text).
    fn none(self) -> &'static str;
    /// Colour-bar label.
    fn unit(self, m: &Meta) -> String;
    /// The neutral value a diverging scale is centred on; none for a
    /// quantity of the steady motion, drawn on a sequential scale from its
    /// smallest value to its largest, or, where its values take both signs
    /// (an attenuation in dB, a mean position), on the diverging scale
    /// centred at 0 ([`Scaled::of`]).
    fn centre(self) -> Option<f64>;
}

impl Drawn for Number {
    fn none(self) -> &'static str {
        match self {
            Number::Lyapunov => "periodic",
            Number::Multiplier => "no period",
            Number::Quantity(_) => "none",
        }
    }

    fn unit(self, m: &Meta) -> String {
        match self {
            Number::Quantity(k) => m.quantities[k].with_units(&m.quantities[k].name),
            number => number.symbol(m).to_string(),
        }
    }

    fn centre(self) -> Option<f64> {
        match self {
            Number::Lyapunov => Some(0.0),
            Number::Multiplier => Some(1.0),
            Number::Quantity(_) => None,
        }
    }
}

/// Colour of cells without the number.
pub(crate) const NONE: RGBColor = RGBColor(190, 190, 190);

/// Blue (below the centre) to white (at it) to red (above), symmetric: `t`
/// in [-1, 1].
fn diverging(t: f64) -> RGBColor {
    let t = t.clamp(-1.0, 1.0);
    let (end, w) = if t < 0.0 { ([33.0, 102.0, 172.0], -t) } else { ([178.0, 24.0, 43.0], t) };
    let c = end.map(|e: f64| (255.0 + w * (e - 255.0)).round() as u8);
    RGBColor(c[0], c[1], c[2])
}

/// A sequential scale (viridis, perceptually uniform and legible in grey):
/// `t` in [0, 1].
fn sequential(t: f64) -> RGBColor {
    const STOPS: [[f64; 3]; 5] =
        [[68.0, 1.0, 84.0], [59.0, 82.0, 139.0], [33.0, 145.0, 140.0], [94.0, 201.0, 98.0], [253.0, 231.0, 37.0]];
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - k as f64;
    let c = [0, 1, 2].map(|i| (STOPS[k][i] + f * (STOPS[k + 1][i] - STOPS[k][i])).round() as u8);
    RGBColor(c[0], c[1], c[2])
}

/// The numbers of one sweep's cells on the map's scale.
pub(crate) struct Scaled {
    /// Per cell, its number (`None`: the cell has none, or was not computed).
    pub values: Vec<Option<f64>>,
    /// The ends of the colour bar.
    pub lo: f64,
    /// See `lo`.
    pub hi: f64,
    /// A diverging scale's neutral value (white) and how far from it the full
    /// colour lies; none for a sequential scale.
    diverging: Option<(f64, f64)>,
}

impl Scaled {
    /// The numbers `quantity` of the cells of `sweep`.
    pub fn of(atlas: &Atlas, sweep: SweepKind, quantity: Number) -> Result<Scaled, RenderError> {
        let cells = sweep_cells(atlas, sweep)?;
        let values: Vec<Option<f64>> = cells.iter().map(|c| c.as_ref().and_then(|c| quantity.value(c))).collect();
        if let Some(centre) = quantity.centre() {
            return Ok(Scaled::about(values, centre));
        }
        let lo = values.iter().flatten().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().flatten().copied().fold(f64::NEG_INFINITY, f64::max);
        // Values of both signs: their sign is read at a glance (white at 0,
        // blue below, red above).
        if lo < 0.0 && hi > 0.0 {
            return Ok(Scaled::about(values, 0.0));
        }
        let (lo, hi) = match (lo.is_finite(), hi > lo) {
            (true, true) => (lo, hi),
            (true, false) => (lo - 0.5, lo + 0.5),
            (false, _) => (0.0, 1.0),
        };
        Ok(Scaled { values, lo, hi, diverging: None })
    }

    /// Quantity `quantity` of the up sweep's cells less that of the down
    /// sweep's, on a diverging scale centred at 0 (`None` where either has
    /// none): where the two legs' motions differ, by how much.
    pub fn difference(atlas: &Atlas, quantity: Number) -> Result<Scaled, RenderError> {
        let (up, down) = (sweep_cells(atlas, SweepKind::Up)?, sweep_cells(atlas, SweepKind::Down)?);
        let value = |c: &Option<CellData>| c.as_ref().and_then(|c| quantity.value(c));
        let values: Vec<Option<f64>> = up.iter().zip(down.iter()).map(|(u, d)| Some(value(u)? - value(d)?)).collect();
        Ok(Scaled::about(values, 0.0))
    }

    /// `values` on the diverging scale centred at `centre`, full colour at
    /// the value farthest from it (at 1 from it where all are at it).
    fn about(values: Vec<Option<f64>>, centre: f64) -> Scaled {
        let reach = values.iter().flatten().map(|v| (v - centre).abs()).fold(0.0, f64::max);
        let reach = if reach > 0.0 { reach } else { 1.0 };
        Scaled { values, lo: centre - reach, hi: centre + reach, diverging: Some((centre, reach)) }
    }

    /// The colour of cell `i`.
    pub fn colour(&self, i: usize) -> RGBColor {
        self.values[i].map_or(NONE, |v| self.colour_of(v))
    }

    /// The colour of the value `v`.
    pub fn colour_of(&self, v: f64) -> RGBColor {
        match self.diverging {
            Some((centre, reach)) => diverging((v - centre) / reach),
            None => sequential((v - self.lo) / (self.hi - self.lo)),
        }
    }
}

/// Draws `quantity` over the plane of one sweep of `atlas` at the size of
/// `page` (to `out`: [`Out`]), with contour lines at up to
/// `contours` round levels (steps of 1, 2 or 5 times a power of ten, marked
/// on the colour bar; 0: none).
pub fn scalar_map<'o>(
    atlas: &Atlas,
    sweep: SweepKind,
    quantity: Number,
    contours: usize,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    let scaled = Scaled::of(atlas, sweep, quantity)?;
    let text = Texts {
        title: format!("{} sweep: {}", sweep.name(), quantity.long_name(m)),
        unit: quantity.unit(m),
        none: quantity.none().into(),
        levels: crate::contour::levels(scaled.lo, scaled.hi, contours),
    };
    save_map(m, &scaled, &text, page, out.into())
}

/// Draws quantity `quantity` of the up sweep less that of the down sweep, on
/// a diverging scale centred at 0 (grey where either sweep has no value):
/// where hysteresis changes it, and by how much; contour lines as
/// [`scalar_map`]'s, but for the level 0 (where the legs agree, the
/// difference is 0 or rounding).
pub fn difference_map<'o>(
    atlas: &Atlas,
    quantity: Number,
    contours: usize,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    let m = &atlas.meta;
    let scaled = Scaled::difference(atlas, quantity)?;
    let text = Texts {
        title: format!("up sweep less down sweep: {}", quantity.long_name(m)),
        unit: format!("Δ {}", quantity.unit(m)),
        none: "none".into(),
        levels: crate::contour::levels(scaled.lo, scaled.hi, contours).into_iter().filter(|&l| l != 0.0).collect(),
    };
    save_map(m, &scaled, &text, page, out.into())
}

/// Draws the continuous map of `scaled` with `text` at the size of `page`
/// to `out`.
fn save_map(m: &Meta, scaled: &Scaled, text: &Texts, page: &Page, out: Out<'_>) -> Result<(), RenderError> {
    let canvas = Canvas::of(page, &out, (1060, 800), |w| if w < 120.0 { 0.95 * w } else { 0.65 * w })?;
    save!(out, canvas, |root| draw(&root, &canvas, m, scaled, text))
}

/// The words of a continuous map: its title, its colour bar's label, and
/// what grey stands for; and the levels of its contour lines.
struct Texts {
    title: String,
    unit: String,
    none: String,
    levels: Vec<f64>,
}

fn draw<DB: Backend>(
    root: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    m: &Meta,
    scaled: &Scaled,
    text: &Texts,
) -> Result<(), RenderError> {
    let (lo, hi) = (scaled.lo, scaled.hi);
    root.fill(&WHITE).map_err(err)?;
    let body = layout::header(root, canvas, &text.title, layout::TITLE)?;
    let body = layout::footer(&body, canvas, &crate::map::settings_text(m))?;
    let (w, h) = body.dim_in_pixel();
    let (left, right) = body.split_horizontally(w.saturating_sub(canvas.emu(8.0)));
    // What grey stands for, under the colour bar.
    let (right, key) = right.split_vertically(h.saturating_sub(legend::height(canvas, 1)));
    legend::draw(&key, canvas, &[Entry::new(Swatch::Fill(NONE), &text.none)])?;
    let grid = CellGrid::of(m);
    let chart = grid.chart(&left, canvas, m, "")?;
    let plot = chart.plotting_area();
    for i in 0..scaled.values.len() {
        plot.draw(&Rectangle::new(grid.rect(i), scaled.colour(i).filled())).map_err(err)?;
    }
    let levels = &text.levels;
    let line = BLACK.stroke_width(canvas.pt(0.6));
    for &level in levels {
        for [a, b] in crate::contour::segments(&scaled.values, m.plane.x.count, m.plane.y.count, level) {
            plot.draw(&PathElement::new(vec![grid.at(a.0, a.1), grid.at(b.0, b.1)], line)).map_err(err)?;
        }
    }
    let mut bar = ChartBuilder::on(&right)
        .margin_top(canvas.em(1.0))
        .margin_bottom(canvas.em(1.0))
        .margin_right(canvas.em(0.5))
        .y_label_area_size(0)
        .right_y_label_area_size(canvas.em(6.0))
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(&text.unit)
        .y_label_formatter(&|v| tick(*v))
        .label_style(canvas.font(1.0))
        .axis_desc_style(canvas.font(1.0))
        .axis_style(BLACK.stroke_width(canvas.pt(0.6)))
        .set_all_tick_mark_size(canvas.em(0.35))
        .draw()
        .map_err(err)?;
    let n = 200;
    bar.draw_series((0..n).map(|k| {
        let (a, b) = (lo + (hi - lo) * k as f64 / n as f64, lo + (hi - lo) * (k + 1) as f64 / n as f64);
        Rectangle::new([(0.0, a), (1.0, b)], scaled.colour_of(0.5 * (a + b)).filled())
    }))
    .map_err(err)?;
    // The levels on the colour bar.
    bar.draw_series(levels.iter().map(|&l| PathElement::new(vec![(0.0, l), (1.0, l)], line))).map_err(err)?;
    Ok(())
}
