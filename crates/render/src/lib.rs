//! Pictures of atlases: coloured label maps, bifurcation diagrams, and contact
//! sheets of studies, as PNG, SVG or PDF (plotters; PDF through svg2pdf), to a
//! file in the format of its extension or to bytes in memory ([`Out`]), on
//! screen or at a printed size
//! ([`Page`]: every text at least 6 pt on the page).
#![deny(missing_docs)]

mod axis;
mod basins;
mod bifurcation;
mod branch;
mod contour;
mod error;
mod font;
mod layers;
mod layout;
mod legend;
mod map;
mod output;
mod page;
mod portrait;
mod rich;
mod scalar;
mod section;
mod show;
mod trade;

pub use basins::{basin_map, basins};
pub use bifurcation::{bifurcation, component_name, variable_of, Diagram, Impact};
pub use branch::branch;
pub use error::{Missing, RenderError};
pub use layers::{curve_style, label_legend, layer, Key, Layer};
pub use map::{attractor_map, family_map, family_of, map, sheet, Overlay, View};
/// A colour faded as the hysteresis view draws the cells where the sweeps agree.
pub use maps::palette::faded;
pub use output::{Format, Out};
pub use page::{Page, PageError, PageOption, PrintSize, DOUBLE_MM, MIN_TEXT_PT, SINGLE_MM};
pub use portrait::{portrait, Portrait};
pub use rich::runs as subscript_runs;
pub use scalar::{difference_map, scalar_map};
pub use section::{sections, Panel};
pub use show::{draw, NoSuchView, Show, LABELS};
pub use trade::trade;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_of_figure_options() {
        assert_eq!(Page::of(None, None, None), Ok(Page::screen()));
        assert_eq!(Page::of(None, Some(8.0), None), Err(PageError::WithoutSize(PageOption::FontSize)));
        assert_eq!(Page::of(None, None, Some(300)).unwrap_err().option(), PageOption::Dpi);
        assert_eq!(
            Page::of(Some("single"), Some(30.0), None).unwrap_err().to_string(),
            "must be in [6, 24] pt, got 30"
        );
        assert_eq!(Page::of(Some("single"), None, Some(10)).unwrap_err().to_string(), "must be in [72, 1200], got 10");
        assert_eq!(Page::of(Some("10x"), None, None).unwrap_err().option(), PageOption::Size);
        assert!(Page::of(Some("120x80"), Some(10.0), Some(600)).is_ok());
    }
}
