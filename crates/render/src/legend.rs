//! Legends drawn beside or below the data, never over it: rows of a swatch
//! and a text, in as many columns as the legend's area holds, with headings
//! between groups of rows. A swatch is drawn as the marks it stands for:
//! a filled cell, a cell split between two labels, a hatched cell for a group
//! of labels (so it can never be taken for a listed label), a line with its
//! dash, a ring or a dot of the size drawn in the data.

use crate::error::{err, RenderError};
use crate::page::{Backend, Canvas};
use crate::rich::{self, Direction};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// What a legend row shows before its text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Swatch {
    /// No swatch: a heading.
    Heading,
    /// A cell filled in one colour.
    Fill(RGBColor),
    /// A cell split along its rising diagonal: the first colour above, the
    /// second below.
    Split(RGBColor, RGBColor),
    /// A group of labels: white, hatched in the colour.
    Hatch(RGBColor),
    /// A line of the colour, width (pt) and dash (pt on, pt off; off 0: solid).
    Line(RGBColor, f64, (f64, f64)),
    /// A ring of the colour and radius (pt).
    Ring(RGBColor, f64),
    /// A filled dot of the colour and radius (pt).
    Dot(RGBColor, f64),
}

/// One legend row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Entry {
    /// The swatch.
    pub swatch: Swatch,
    /// The text.
    pub text: String,
}

impl Entry {
    /// A row.
    pub fn new(swatch: Swatch, text: impl Into<String>) -> Entry {
        Entry { swatch, text: text.into() }
    }
}

/// Height of a legend row, in body text heights.
const ROW: f64 = 1.45;
/// Width of a swatch (line swatches are wider, to show their dash).
const SWATCH: f64 = 1.1;
const LINE_SWATCH: f64 = 3.2;

/// Width (px) of the widest row of `entries`, swatch included.
pub(crate) fn width<DB: Backend>(area: &DrawingArea<DB, Shift>, canvas: &Canvas, entries: &[Entry]) -> u32 {
    let font = canvas.font(1.0);
    entries
        .iter()
        .map(|e| {
            let text =
                area.estimate_text_size(&rich::plain(&e.text), &TextStyle::from(font.clone())).map_or(0, |s| s.0);
            text + canvas.emu(swatch_width(e.swatch) + 0.6)
        })
        .max()
        .unwrap_or(0)
        + canvas.emu(1.0)
}

fn swatch_width(s: Swatch) -> f64 {
    match s {
        Swatch::Heading => 0.0,
        Swatch::Line(..) => LINE_SWATCH,
        _ => SWATCH,
    }
}

/// Widths (px) of the columns of `entries` laid out `rows` to a column.
pub(crate) fn columns<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    entries: &[Entry],
    rows: usize,
) -> Vec<u32> {
    in_columns(entries, rows).into_iter().map(|c| width(area, canvas, c)).collect()
}

/// `entries` cut into columns of at most `rows` rows, a heading never the
/// last row of a column while rows follow it (it moves to the head of the
/// next column, over the rows it names).
fn in_columns(entries: &[Entry], rows: usize) -> Vec<&[Entry]> {
    let rows = rows.max(1);
    let mut out = Vec::new();
    let mut rest = entries;
    while !rest.is_empty() {
        let mut take = rows.min(rest.len());
        if take > 1 && take < rest.len() && rest[take - 1].swatch == Swatch::Heading {
            take -= 1;
        }
        let (column, tail) = rest.split_at(take);
        out.push(column);
        rest = tail;
    }
    out
}

/// Rows that fit in a column of height `height` (px).
pub(crate) fn rows(canvas: &Canvas, height: u32) -> usize {
    ((height as f64 - canvas.em(0.5) as f64) / (ROW * canvas.em(1.0) as f64)).floor().max(1.0) as usize
}

/// Height (px) of a legend of `rows` rows.
pub(crate) fn height(canvas: &Canvas, rows: usize) -> u32 {
    (rows as f64 * ROW * canvas.em(1.0) as f64).ceil() as u32 + canvas.emu(0.5)
}

/// Draws `entries` down `area` in columns of as many rows as its height
/// holds, each column as wide as its widest row; rows beyond its width are
/// left out (callers size their entries with [`rows`] and [`columns`]).
pub(crate) fn draw<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    entries: &[Entry],
) -> Result<(), RenderError> {
    let (w, h) = area.dim_in_pixel();
    let per_column = rows(canvas, h);
    let widths = columns(area, canvas, entries, per_column);
    let row_px = ROW * canvas.em(1.0) as f64;
    let mut left = 0;
    for (c, chunk) in in_columns(entries, per_column).into_iter().enumerate() {
        if c > 0 && left + widths[c] > w {
            break;
        }
        for (r, e) in chunk.iter().enumerate() {
            draw_row(area, canvas, e, (left as i32 + canvas.em(0.4), r), row_px)?;
        }
        left += widths[c];
    }
    Ok(())
}

/// Draws one row, its swatch's left edge at `x`, in row `r` of its column.
fn draw_row<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    e: &Entry,
    (x, r): (i32, usize),
    row_px: f64,
) -> Result<(), RenderError> {
    let y = canvas.em(0.25) + (r as f64 * row_px + row_px / 2.0).round() as i32;
    let text_x = x + canvas.em(swatch_width(e.swatch) + if e.swatch == Swatch::Heading { 0.0 } else { 0.5 });
    swatch(area, canvas, e.swatch, (x, y))?;
    let at = Pos::new(HPos::Left, VPos::Center);
    rich::draw(area, canvas, &e.text, (text_x, y), at, 1.0, Direction::Across)
}

/// Draws a swatch whose left edge is `x`, centred on `y`.
fn swatch<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    s: Swatch,
    (x, y): (i32, i32),
) -> Result<(), RenderError> {
    let half = canvas.em(0.45);
    let (x0, y0, x1, y1) = (x, y - half, x + 2 * half, y + half);
    let edge = BLACK.mix(0.6).stroke_width(canvas.pt(0.4));
    match s {
        Swatch::Heading => {}
        Swatch::Fill(c) => area.draw(&Rectangle::new([(x0, y0), (x1, y1)], c.filled())).map_err(err)?,
        Swatch::Split(up, down) => {
            area.draw(&Polygon::new(vec![(x0, y1), (x0, y0), (x1, y0)], up.filled())).map_err(err)?;
            area.draw(&Polygon::new(vec![(x0, y1), (x1, y0), (x1, y1)], down.filled())).map_err(err)?;
        }
        Swatch::Hatch(c) => {
            area.draw(&Rectangle::new([(x0, y0), (x1, y1)], WHITE.filled())).map_err(err)?;
            let step = (2 * half / 3).max(3);
            let style = c.stroke_width(canvas.pt(0.6));
            let mut k = -2 * half;
            while k <= 2 * half {
                // Segments of slope -1 clipped to the square.
                let (a, b) = ((x0 + k).max(x0), (x0 + k + 2 * half).min(x1));
                if a < b {
                    area.draw(&PathElement::new(vec![(a, y1 - (a - x0 - k)), (b, y1 - (b - x0 - k))], style))
                        .map_err(err)?;
                }
                k += step;
            }
        }
        Swatch::Line(c, width, dash) => {
            let len = canvas.em(LINE_SWATCH);
            line(area, canvas, &[(x, y), (x + len, y)], c, width, dash)?;
            return Ok(());
        }
        Swatch::Ring(c, r) => {
            area.draw(&Circle::new((x + half, y), canvas.pt(r), c.stroke_width(canvas.pt(0.6)))).map_err(err)?;
            return Ok(());
        }
        Swatch::Dot(c, r) => {
            area.draw(&Circle::new((x + half, y), canvas.pt(r), c.filled())).map_err(err)?;
            return Ok(());
        }
    }
    if s != Swatch::Heading {
        area.draw(&Rectangle::new([(x0, y0), (x1, y1)], edge)).map_err(err)?;
    }
    Ok(())
}

/// Draws a polyline (in the area's coordinates) with a white halo, width
/// (pt) and dash (pt).
pub(crate) fn line<DB: Backend, CT: plotters::coord::CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    canvas: &Canvas,
    points: &[CT::From],
    colour: RGBColor,
    width: f64,
    dash: (f64, f64),
) -> Result<(), RenderError>
where
    CT::From: Clone,
{
    let halo = WHITE.stroke_width(canvas.pt(width + 1.2));
    area.draw(&PathElement::new(points.to_vec(), halo)).map_err(err)?;
    let style = colour.stroke_width(canvas.pt(width));
    if dash.1 <= 0.0 {
        area.draw(&PathElement::new(points.to_vec(), style)).map_err(err)
    } else {
        let dashed = plotters::element::DashedPathElement::new(
            points.iter().cloned(),
            canvas.pt(dash.0),
            canvas.pt(dash.1),
            style,
        );
        area.draw(&dashed).map_err(err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A heading that would end a column opens the next one, over the rows
    /// it names (the hysteresis legend's "up / down (cells)" stood at the foot
    /// of the labels' column, its pairs in the next); a heading alone in a
    /// one-row column, or as the last entry, stays where it is.
    #[test]
    fn a_heading_never_ends_a_column_before_its_rows() {
        let row = |t: &str| Entry::new(Swatch::Fill(RGBColor(0, 0, 0)), t);
        let head = |t: &str| Entry::new(Swatch::Heading, t);
        let entries = vec![head("labels"), row("a"), row("b"), row("c"), head("pairs"), row("a / b"), row("c / d")];
        let texts = |cols: Vec<&[Entry]>| -> Vec<Vec<String>> {
            cols.into_iter().map(|c| c.iter().map(|e| e.text.clone()).collect()).collect()
        };
        assert_eq!(texts(in_columns(&entries, 5)), [vec!["labels", "a", "b", "c"], vec!["pairs", "a / b", "c / d"]]);
        assert_eq!(texts(in_columns(&entries, 4)), [vec!["labels", "a", "b", "c"], vec!["pairs", "a / b", "c / d"]]);
        assert_eq!(texts(in_columns(&entries, 1)).len(), 7);
        assert_eq!(texts(in_columns(&[row("a"), head("end")], 2)), [vec!["a", "end"]]);
    }
}
