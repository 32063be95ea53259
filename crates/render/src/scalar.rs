//! A continuous map of one number per cell: the largest Lyapunov exponent of
//! cells without a period, or the largest Floquet multiplier modulus of
//! periodic cells (where stability is lost, it crosses 1). Cells without the
//! number are light grey; a colour bar gives the scale.

use crate::map::{sweep_cells, CellGrid};
use crate::{err, font, RenderError};
use grid::{Atlas, CellData, SweepKind};
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::path::Path;

/// Which number a continuous map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Largest Lyapunov exponent per unit time.
    Lyapunov,
    /// Largest Floquet multiplier modulus.
    Multiplier,
}

impl Quantity {
    fn of(self, c: &CellData) -> Option<f64> {
        match self {
            Quantity::Lyapunov => c.lyapunov,
            Quantity::Multiplier => c.multiplier,
        }
    }

    fn title(self) -> &'static str {
        match self {
            Quantity::Lyapunov => "largest Lyapunov exponent (cells without a period)",
            Quantity::Multiplier => "largest |Floquet multiplier| (periodic cells)",
        }
    }
}

/// Draws `quantity` over the plane of one sweep of `atlas` to a PNG.
pub fn scalar_map(atlas: &Atlas, sweep: SweepKind, quantity: Quantity, path: &Path) -> Result<(), RenderError> {
    font::ensure()?;
    let m = &atlas.meta;
    let cells = sweep_cells(atlas, sweep)?;
    let values: Vec<Option<f64>> = cells.iter().map(|c| c.as_ref().and_then(|c| quantity.of(c))).collect();
    let (lo, hi) = values.iter().flatten().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo.is_finite() && hi > lo { (lo, hi) } else { (lo.min(0.0), lo.max(0.0) + 1.0) };
    let root = BitMapBackend::new(path, (1000, 760)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (left, right) = root.split_horizontally(860);
    let grid = CellGrid::of(m);
    let title = format!("{} ({}): {}", m.scene_name, sweep.name(), quantity.title());
    let mut chart = grid.chart(&left, &title, 15)?;
    chart
        .draw_series(values.iter().enumerate().map(|(i, v)| {
            let colour = v.map_or(RGBColor(225, 225, 225), |v| ViridisRGB.get_color_normalized(v, lo, hi));
            Rectangle::new(grid.rect(i), colour.filled())
        }))
        .map_err(err)?;
    // Colour bar.
    let mut bar = ChartBuilder::on(&right)
        .margin_top(60)
        .margin_bottom(55)
        .margin_right(70)
        .y_label_area_size(0)
        .right_y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?;
    bar.configure_mesh().disable_mesh().disable_x_axis().label_style(("sans-serif", 14)).draw().map_err(err)?;
    let n = 200;
    bar.draw_series((0..n).map(|k| {
        let (a, b) = (lo + (hi - lo) * k as f64 / n as f64, lo + (hi - lo) * (k + 1) as f64 / n as f64);
        Rectangle::new([(0.0, a), (1.0, b)], ViridisRGB.get_color_normalized(0.5 * (a + b), lo, hi).filled())
    }))
    .map_err(err)?;
    root.present().map_err(err)
}
