//! Text with subscripts, as a paper writes symbols: in `x_M1`, `f_k` or
//! `μ_k` the `_` and the run of letters and digits after it become a
//! subscript (three quarters of the text's size, never below the canvas's
//! least size, its baseline lowered by a fifth of the text's size). Only an
//! underscore between a letter or digit and a letter or digit starts one, so
//! other text is drawn as written.

use crate::error::{err, RenderError};
use crate::page::{Backend, Canvas};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;

/// Size of a subscript, to its text.
const SUB: f64 = 0.75;
/// How far a subscript's baseline is lowered, in its text's size.
const DROP: f64 = 0.2;

/// The runs of `text`: its pieces in order, each with whether it is a subscript.
pub fn runs(text: &str) -> Vec<(&str, bool)> {
    let word = |c: Option<char>| c.is_some_and(char::is_alphanumeric);
    let mut out = Vec::new();
    let (mut start, mut sub) = (0, false);
    let mut chars = text.char_indices().peekable();
    let mut prev = None;
    while let Some((i, c)) = chars.next() {
        if sub && !c.is_alphanumeric() {
            out.push((&text[start..i], true));
            (start, sub) = (i, false);
        }
        if c == '_' && !sub && word(prev) && word(chars.peek().map(|p| p.1)) {
            if i > start {
                out.push((&text[start..i], false));
            }
            (start, sub) = (i + 1, true);
        }
        prev = Some(c);
    }
    if start < text.len() {
        out.push((&text[start..], sub));
    }
    out
}

/// `text` as a reader sees it, subscripts inline (`x_M1` → `xM1`): what a
/// PDF's text layer holds.
pub(crate) fn plain(text: &str) -> String {
    runs(text).into_iter().map(|r| r.0).collect()
}

/// Which way a text runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Direction {
    /// Left to right.
    Across,
    /// Bottom to top (a vertical axis's description).
    Up,
}

/// Draws `text` with its subscripts at `at` (pixels of `area`), anchored by
/// `pos` along and across its direction, at `scale` times the body size.
pub(crate) fn draw<DB: Backend>(
    area: &DrawingArea<DB, Shift>,
    canvas: &Canvas,
    text: &str,
    at: (i32, i32),
    pos: Pos,
    scale: f64,
    direction: Direction,
) -> Result<(), RenderError> {
    let (base, small) = (canvas.font(scale), canvas.font(scale * SUB));
    let size = canvas.text_px(scale);
    let width =
        |t: &str, font: &FontDesc| area.estimate_text_size(t, &TextStyle::from(font.clone())).map_or(0, |s| s.0 as i32);
    // Each piece with its advance, and the space that leads it (which a
    // vector format would drop from the start of a text element).
    let pieces: Vec<(&str, bool, i32, i32)> = runs(text)
        .into_iter()
        .map(|(t, sub)| {
            let font = if sub { &small } else { &base };
            let shown = t.trim_start();
            let w = width(t, font);
            (shown, sub, w - width(shown, font), w)
        })
        .collect();
    let total: i32 = pieces.iter().map(|p| p.3).sum();
    let lead = match pos.h_pos {
        HPos::Left => 0,
        HPos::Center => total / 2,
        HPos::Right => total,
    };
    // The top of the base text, across the direction of the text.
    let top = match pos.v_pos {
        VPos::Top => 0.0,
        VPos::Center => -0.5 * size,
        VPos::Bottom => -size,
    };
    let mut along = -lead;
    for (i, &(t, sub, space, w)) in pieces.iter().enumerate() {
        // A text before a subscript ends where the subscript begins: drawn
        // from its end, so that a viewer that sets it narrower than
        // estimated (kerning, in a vector format) leaves no gap there.
        let to_end = direction == Direction::Across && pieces.get(i + 1).is_some_and(|p| p.1);
        let (font, offset) = if sub {
            // Baselines about 0.8 of a size below the top: lowered by DROP.
            (&small, top + 0.8 * size * (1.0 - SUB) + DROP * size)
        } else {
            (&base, top)
        };
        let (font, point) = match direction {
            Direction::Across if to_end => (font.clone(), (at.0 + along + w, at.1 + offset.round() as i32)),
            Direction::Across => (font.clone(), (at.0 + along + space, at.1 + offset.round() as i32)),
            Direction::Up => {
                (font.clone().transform(FontTransform::Rotate270), (at.0 + offset.round() as i32, at.1 - along - space))
            }
        };
        let style = font.into_text_style(area).pos(Pos::new(if to_end { HPos::Right } else { HPos::Left }, VPos::Top));
        area.draw(&Text::new(t.to_string(), point, style)).map_err(err)?;
        along += w;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::runs;

    #[test]
    fn an_underscore_between_word_characters_starts_a_subscript() {
        assert_eq!(runs("x_M1 at t = kT"), [("x", false), ("M1", true), (" at t = kT", false)]);
        assert_eq!(runs("f_s/f_k"), [("f", false), ("s", true), ("/f", false), ("k", true)]);
        assert_eq!(runs("μ_k = 0.3"), [("μ", false), ("k", true), (" = 0.3", false)]);
        assert_eq!(runs("ω"), [("ω", false)]);
        for plain in ["_x", "x_", "a _b", "snake_ case", ""] {
            assert_eq!(runs(plain).into_iter().map(|r| r.0).collect::<String>(), plain, "{plain}");
            assert!(runs(plain).iter().all(|r| !r.1), "{plain}: {:?}", runs(plain));
        }
    }
}
