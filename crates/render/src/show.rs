//! What a map of an atlas shows ([`Show`]), chosen once for every front end:
//! `render --view WHAT --sweep SWEEP` ([`Show::of`]) and the explorer's one
//! word `SWEEP` or `WHAT:SWEEP` ([`Show::named`], [`Show::all`]) name the
//! same views, refused for the same reasons ([`NoSuchView`]), and drawn by
//! one call ([`draw`]).

use crate::map::{map, Overlay, View};
use crate::output::Out;
use crate::page::Page;
use crate::scalar::{difference_map, scalar_map};
use crate::RenderError;
use maps::{Atlas, Meta, Number, SweepKind};
use scene::Named;

/// What a map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Show {
    /// A map's view: one sweep's labels, or the hysteresis panel (cells
    /// where up and down differ, split between their two labels).
    Map(View),
    /// One number of a sweep's cells, on its diverging scale.
    Scalar(SweepKind, Number),
    /// A quantity of the motion, the up sweep's less the down sweep's
    /// ([`crate::difference_map`]).
    Difference(Number),
}

/// Why a view is none of an atlas's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NoSuchView {
    /// A sweep the file does not have.
    Sweep(SweepKind),
    /// Hysteresis, of a file without both up and down.
    Hysteresis,
    /// Neither the labels nor a number the file stores per cell.
    Number(String),
    /// Up less down of a number of the classification (λ, |μ|): only the
    /// quantities of the motion have one.
    Difference(Number),
}

/// The labels' name as `render --view` takes it.
pub const LABELS: &str = "labels";

impl Show {
    /// The view of `what` (the labels, [`LABELS`], or a number per cell:
    /// `lyapunov`, `multiplier`, a stored quantity) over `sweep` (a sweep
    /// of the file, its first by default, or `hysteresis`: the labels'
    /// three panels, or a quantity's up less down).
    pub fn of(m: &Meta, what: &str, sweep: Option<View>) -> Result<Show, NoSuchView> {
        let view = sweep.unwrap_or(View::Sweep(m.sweeps[0]));
        match view {
            View::Sweep(kind) if !m.sweeps.contains(&kind) => return Err(NoSuchView::Sweep(kind)),
            View::Hysteresis if !m.has_up_and_down() => return Err(NoSuchView::Hysteresis),
            _ if what == LABELS => return Ok(Show::Map(view)),
            _ => {}
        }
        let number = Number::named(m, what).ok_or_else(|| NoSuchView::Number(what.to_string()))?;
        match view {
            View::Sweep(sweep) => Ok(Show::Scalar(sweep, number)),
            View::Hysteresis if number.of_motion() => Ok(Show::Difference(number)),
            View::Hysteresis => Err(NoSuchView::Difference(number)),
        }
    }

    /// Its name in one word: a sweep or `hysteresis` (the labels),
    /// `NAME:SWEEP` (a number of a sweep), `NAME:hysteresis` (a quantity's
    /// up less down).
    pub fn name(self, m: &Meta) -> String {
        match self {
            Show::Map(view) => view.name().to_string(),
            Show::Scalar(sweep, number) => format!("{}:{}", number.name(m), sweep.name()),
            Show::Difference(number) => format!("{}:{}", number.name(m), View::Hysteresis.name()),
        }
    }

    /// Every view of an atlas of `m`: its sweeps, hysteresis with up and
    /// down, every number per cell of each sweep, and with up and down every
    /// quantity's up less down.
    pub fn all(m: &Meta) -> Vec<Show> {
        let mut all: Vec<Show> = m.sweeps.iter().map(|&s| Show::Map(View::Sweep(s))).collect();
        let both = m.has_up_and_down();
        all.extend(both.then_some(Show::Map(View::Hysteresis)));
        for number in Number::all(m) {
            all.extend(m.sweeps.iter().map(|&s| Show::Scalar(s, number)));
        }
        all.extend(Number::all(m).filter(|n| both && n.of_motion()).map(Show::Difference));
        all
    }

    /// The view of an atlas of `m` named `name` ([`Show::name`]).
    pub fn named(m: &Meta, name: &str) -> Option<Show> {
        Show::all(m).into_iter().find(|s| s.name(m) == name)
    }
}

/// Draws `show` of `atlas` for labelled mass `mass` (label maps, with the
/// curves `curves` over them) or with `contours` levels (the numbers' maps).
pub fn draw<'o>(
    atlas: &Atlas,
    show: Show,
    mass: usize,
    curves: &[Overlay],
    contours: usize,
    page: &Page,
    out: impl Into<Out<'o>>,
) -> Result<(), RenderError> {
    match show {
        Show::Map(view) => map(atlas, view, mass, curves, page, out),
        Show::Scalar(sweep, number) => scalar_map(atlas, sweep, number, contours, page, out),
        Show::Difference(number) => difference_map(atlas, number, contours, page, out),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use maps::{Along, Axis, Plane, Quantity};

    fn meta(sweeps: &[SweepKind]) -> Meta {
        let q =
            |name: &str| Quantity { name: name.into(), symbol: "s".into(), long_name: "l".into(), units: "1".into() };
        Meta {
            scene_name: "multi-stop".into(),
            scene_toml: String::new(),
            overrides: Vec::new(),
            preset: solver::Preset::Standard,
            accuracy: Vec::new(),
            integrator: solver::Method::Exact,
            plane: Plane { x: Axis::new("omega", 0.2, 1.0, 3), y: Axis::new("delta", 0.4, 0.8, 2), along: Along::X },
            sweeps: sweeps.to_vec(),
            masses: vec!["M1".into()],
            state_masses: vec!["M1".into()],
            label_stops: Vec::new(),
            stops: vec!["A1".into()],
            stop_normals: Vec::new(),
            stop_laws: vec![scene::LawKind::Rigid],
            dim: 2,
            section_cap: 16,
            notation: Vec::new(),
            quantities: vec![q("power_in"), q("max_abs_x_M1")],
        }
    }

    /// Every view of an atlas reads back by its one-word name and by its
    /// two parts, `render --view WHAT --sweep SWEEP`; nothing else does.
    #[test]
    fn every_view_reads_back_by_its_name_and_its_parts() {
        let both = meta(&[SweepKind::Up, SweepKind::Down]);
        let all = Show::all(&both);
        // up, down, hysteresis; 4 numbers × 2 sweeps; 2 quantities' up less down.
        assert_eq!(all.len(), 3 + 8 + 2);
        for &show in &all {
            let name = show.name(&both);
            assert_eq!(Show::named(&both, &name), Some(show), "{name}");
            let (what, sweep) = name.rsplit_once(':').unwrap_or((LABELS, &name));
            assert_eq!(Show::of(&both, what, View::parse(sweep)), Ok(show), "{name}");
        }
        assert_eq!(Show::of(&both, LABELS, None), Ok(Show::Map(View::Sweep(SweepKind::Up))));
        assert_eq!(Show::named(&both, "labels:up"), None);
        let h = Some(View::Hysteresis);
        assert_eq!(Show::of(&both, "lyapunov", h), Err(NoSuchView::Difference(Number::Lyapunov)));
        assert_eq!(Show::of(&both, "bogus", None), Err(NoSuchView::Number("bogus".into())));
        let fresh = meta(&[SweepKind::Fresh]);
        assert_eq!(Show::of(&fresh, LABELS, h), Err(NoSuchView::Hysteresis));
        assert_eq!(
            Show::of(&fresh, "power_in", Some(View::Sweep(SweepKind::Up))),
            Err(NoSuchView::Sweep(SweepKind::Up))
        );
        assert_eq!(Show::all(&fresh).len(), 1 + 4);
        assert_eq!(Show::named(&fresh, "hysteresis"), None);
    }
}
