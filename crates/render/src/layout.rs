//! The parts every figure is built of, measured in body text heights of its
//! [`Canvas`]: a title block and a footnote whose lines are wrapped to the
//! width of the figure, a grid of panels, and a chart whose label areas and
//! number of ticks follow the size of its text.

use crate::axis::tick;
use crate::error::{err, RenderError};
use crate::page::{Backend, Canvas};
use crate::rich::{self, Direction};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A chart of two continuous axes.
pub(crate) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Scale of a figure's title, of a panel's caption and of a footnote, to the
/// body text.
pub(crate) const TITLE: f64 = 1.15;
pub(crate) const CAPTION: f64 = 1.0;
pub(crate) const FOOT: f64 = 0.9;
/// Height of one line of text, in text heights.
const LINE: f64 = 1.3;

/// `text` broken into lines no wider than `width` pixels in `font`: a
/// clause (the text between `; `) is kept on one line where it fits on one,
/// else broken at spaces but not at an equation's `=` (a word longer than
/// the width stays whole).
pub(crate) fn wrap<DB: Backend>(area: &DrawingArea<DB, Shift>, text: &str, font: &FontDesc, width: u32) -> Vec<String> {
    let fits = |s: &str| area.estimate_text_size(s, &TextStyle::from(font.clone())).map_or(true, |(w, _)| w <= width);
    // What may not be broken: a clause that fits a line, else its words (an
    // equation, `f_k = 0.05`, `p = impacts`, one word).
    let mut units: Vec<String> = Vec::new();
    for clause in text.split_inclusive("; ").map(str::trim_end) {
        if fits(clause) {
            units.push(clause.to_string());
            continue;
        }
        for (i, word) in clause.split(' ').enumerate() {
            match units.last_mut() {
                Some(u) if i > 0 && (word == "=" || u.ends_with(" =")) => {
                    u.push(' ');
                    u.push_str(word);
                }
                _ => units.push(word.to_string()),
            }
        }
    }
    let mut lines: Vec<String> = Vec::new();
    for unit in units {
        match lines.last_mut() {
            Some(line) if fits(&format!("{line} {unit}")) => {
                line.push(' ');
                line.push_str(&unit);
            }
            _ => lines.push(unit),
        }
    }
    lines
}

/// Draws `text` at the top of `area`, centred and wrapped, at `scale` times
/// the body size; returns the area below it.
pub(crate) fn header<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    text: &str,
    scale: f64,
) -> Result<DrawingArea<DB, Shift>, RenderError> {
    let used = centred_lines(area, canvas, text, scale)?;
    Ok(area.split_vertically(used.min(area.dim_in_pixel().1)).1)
}

/// Draws `text` at the top of `area`, centred and wrapped to its width less
/// one em, at `scale` times the body size; returns the height it took (px).
fn centred_lines<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    text: &str,
    scale: f64,
) -> Result<u32, RenderError> {
    let w = area.dim_in_pixel().0;
    let font = canvas.font(scale);
    let lines = wrap(area, text, &font, w.saturating_sub(canvas.emu(1.0)));
    let step = canvas.text_px(scale) * LINE;
    for (i, line) in lines.iter().enumerate() {
        let y = canvas.em(0.4) + (step * i as f64).round() as i32;
        let at = Pos::new(HPos::Center, VPos::Top);
        rich::draw(area, canvas, line, (w as i32 / 2, y), at, scale, Direction::Across)?;
    }
    Ok((canvas.em(0.4) as f64 + step * lines.len() as f64 + canvas.em(0.2) as f64).round() as u32)
}

/// Draws `text` at the bottom of `area`, left-aligned and wrapped, at the
/// footnote size; returns the area above it.
pub(crate) fn footer<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    text: &str,
) -> Result<DrawingArea<DB, Shift>, RenderError> {
    let (w, h) = area.dim_in_pixel();
    let font = canvas.font(FOOT);
    let lines = wrap(area, text, &font, w.saturating_sub(canvas.emu(1.5)));
    let step = canvas.text_px(FOOT) * LINE;
    let used = (step * lines.len() as f64 + canvas.em(0.5) as f64).round() as u32;
    let (top, foot) = area.split_vertically(h.saturating_sub(used));
    for (i, line) in lines.iter().enumerate() {
        let y = (step * i as f64).round() as i32;
        let at = Pos::new(HPos::Left, VPos::Top);
        rich::draw(&foot, canvas, line, (canvas.em(0.6), y), at, FOOT, Direction::Across)?;
    }
    Ok(top)
}

/// `area` split into `n` panels in rows of `cols`, left to right, top to bottom.
pub(crate) fn panels<DB: Backend>(area: &DrawingArea<DB, Shift>, n: usize, cols: usize) -> Vec<DrawingArea<DB, Shift>> {
    let cols = cols.clamp(1, n.max(1));
    let rows = n.div_ceil(cols).max(1);
    area.split_evenly((rows, cols)).into_iter().take(n).collect()
}

/// `area` split into `n` panels in as many columns as give the panels the
/// most room for their least size `least` (width, height in text heights):
/// side by side on a wide page, one above the other on a tall one.
pub(crate) fn grid<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    n: usize,
    least: (f64, f64),
) -> Vec<DrawingArea<DB, Shift>> {
    panels(area, n, grid_columns(area, canvas, n, least))
}

/// The columns [`grid`] lays `n` panels out in.
pub(crate) fn grid_columns<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    n: usize,
    least: (f64, f64),
) -> usize {
    let (w, h) = area.dim_in_pixel();
    let room = |cols: usize| {
        let rows = n.div_ceil(cols);
        let across = w as f64 / cols as f64 / canvas.em(least.0).max(1) as f64;
        let down = h as f64 / rows as f64 / canvas.em(least.1).max(1) as f64;
        across.min(down)
    };
    (1..=n.max(1)).fold(1, |best, c| if room(c) > room(best) * 1.05 { c } else { best })
}

/// What a chart shows: its caption, axis ranges and descriptions.
pub(crate) struct Axes<'t> {
    /// Caption above the chart (none: no caption).
    pub caption: Option<&'t str>,
    /// Horizontal range.
    pub x: (f64, f64),
    /// Vertical range.
    pub y: (f64, f64),
    /// Horizontal axis description.
    pub x_desc: &'t str,
    /// Vertical axis description.
    pub y_desc: &'t str,
    /// Whether the horizontal axis's tick values and description are drawn
    /// (false: tick marks only, for a panel stacked on another that shares
    /// its horizontal axis and names it).
    pub x_labels: bool,
    /// Characters of the widest vertical tick value the label area is sized
    /// for (`None`: from `y`); panels stacked on a shared axis take the
    /// widest of theirs, so that their plots line up.
    pub y_label_chars: Option<usize>,
}

/// Widest tick text of a range (characters), for the vertical label area:
/// ticks are round numbers, so one more digit than the step needs.
pub(crate) fn tick_chars(range: (f64, f64)) -> usize {
    let step = (range.1 - range.0).abs() / 5.0;
    let decimals = if step > 0.0 { (-step.log10().floor()).max(0.0) as usize + 1 } else { 1 };
    let whole = range.0.abs().max(range.1.abs()).max(1.0).log10().floor() as usize + 1;
    let text = whole + decimals + usize::from(range.0 < 0.0) + 1;
    text.min(tick(range.0).chars().count().max(tick(range.1).chars().count()))
}

/// `scale`, or less (down to the least text size) where `text` at `scale`
/// times the body size is longer than `width` pixels.
fn fitted_scale<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    text: &str,
    scale: f64,
    width: u32,
) -> f64 {
    let wide = area.estimate_text_size(text, &TextStyle::from(canvas.font(scale))).map_or(0, |s| s.0);
    if wide <= width || wide == 0 {
        scale
    } else {
        scale * width as f64 / wide as f64
    }
}

/// A chart on `area` with the axes `a`: label areas and tick counts sized to
/// the canvas's text, no grid, ticks without `-0`.
pub(crate) fn chart<'b, DB: Backend>(
    area: &'b DrawingArea<DB, Shift>,
    canvas: &Canvas,
    a: &Axes,
) -> Result<Chart<'b, DB>, RenderError> {
    // The caption at its size, or smaller down to the least text size where
    // that fits it on one line, else wrapped at the least size; the plot
    // below it, with room for the top tick value, which stands half a text
    // height above the plot.
    let top = match a.caption {
        Some(caption) => {
            let width = area.dim_in_pixel().0.saturating_sub(canvas.emu(1.0));
            let scale = fitted_scale(area, canvas, caption, CAPTION, width);
            centred_lines(area, canvas, caption, scale)? + canvas.emu(0.7)
        }
        None => canvas.emu(0.5),
    };
    let y_area = canvas.em(0.62 * a.y_label_chars.unwrap_or_else(|| tick_chars(a.y)) as f64 + 2.2);
    let mut chart = ChartBuilder::on(area)
        .margin(canvas.em(0.5))
        .margin_top(top)
        .margin_right(canvas.em(1.2))
        .x_label_area_size(canvas.em(if a.x_labels { 2.8 } else { 0.6 }))
        .y_label_area_size(y_area)
        .build_cartesian_2d(a.x.0..a.x.1, a.y.0..a.y.1)
        .map_err(err)?;
    let (w, h) = chart.plotting_area().dim_in_pixel();
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let x_ticks = (w as f64 / (canvas.em(0.62 * tick_chars(a.x) as f64 + 1.2) as f64).max(1.0)).floor() as usize;
    let y_ticks = (h as f64 / canvas.em(2.0).max(1) as f64).floor() as usize;
    let spine = BLACK.stroke_width(canvas.pt(0.6));
    chart
        .configure_mesh()
        .disable_mesh()
        .axis_style(spine)
        .x_labels(x_ticks.clamp(2, 10))
        .y_labels(y_ticks.clamp(3, 10))
        .x_label_formatter(&|v| if a.x_labels { tick(*v) } else { String::new() })
        .y_label_formatter(&|v| tick(*v))
        .label_style(canvas.font(1.0))
        .set_all_tick_mark_size(canvas.em(0.35))
        .draw()
        .map_err(err)?;
    // The descriptions, with their subscripts: the horizontal one centred at
    // the foot of its label area, the vertical one up the left of its own.
    let base = area.get_base_pixel();
    let (left, right, bottom) = (xs.start - base.0, xs.end - base.0, ys.end - base.1);
    let middle = (ys.start + ys.end) / 2 - base.1;
    if a.x_labels {
        let at = ((left + right) / 2, bottom + canvas.em(2.7));
        rich::draw(area, canvas, a.x_desc, at, Pos::new(HPos::Center, VPos::Bottom), 1.0, Direction::Across)?;
    }
    let scale = fitted_scale(area, canvas, &rich::plain(a.y_desc), 1.0, h);
    let at = (left - y_area + canvas.em(0.1), middle);
    rich::draw(area, canvas, a.y_desc, at, Pos::new(HPos::Center, VPos::Top), scale, Direction::Up)?;
    Ok(chart)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A footnote's clause goes to the next line whole rather than split
    /// across two ("no impacts at / A2"); a clause wider than a line is
    /// broken at spaces.
    #[test]
    fn wrap_keeps_clauses_whole() {
        crate::font::ensure().unwrap();
        let mut svg = String::new();
        let area = SVGBackend::with_string(&mut svg, (400, 100)).into_drawing_area();
        let font: FontDesc = (crate::font::FAMILY, 12.0).into_font();
        let text = "multi-stop; preset standard; scene defaults; no impacts at A2";
        let width = |s: &str| area.estimate_text_size(s, &TextStyle::from(font.clone())).unwrap().0;
        // Wide enough for all but the last clause's last word on the first line.
        let w = width("multi-stop; preset standard; scene defaults; no impacts at");
        let lines = wrap(&area, text, &font, w);
        assert_eq!(lines, ["multi-stop; preset standard; scene defaults;", "no impacts at A2"]);
        assert_eq!(wrap(&area, text, &font, 10 * w).len(), 1);
        let eq = wrap(&area, "a title with f_k = 0.0509", &font, width("a title with f_k ="));
        assert_eq!(eq, ["a title with", "f_k = 0.0509"], "an equation broken at its =");
        let long = "a clause much wider than the line; b";
        let narrow = wrap(&area, long, &font, width("a clause much"));
        assert!(narrow.len() > 2, "{narrow:?}");
        assert_eq!(narrow.join(" "), long, "words lost or reordered");
        assert!(narrow.iter().all(|l| width(l) <= width("a clause much")), "{narrow:?}");
        assert!(lines.iter().all(|l| width(l) <= w));
    }
}
