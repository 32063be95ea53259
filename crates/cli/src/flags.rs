//! Library errors in the command line's words: the options the engine names
//! ([`engine::Opt`]) as flags, and the advice that names commands.

use engine::{Opt, Words};

/// Options as flags: `--section-cap`, `-o`.
pub struct Flags;

impl Words for Flags {
    fn option(&self, o: Opt) -> String {
        match o {
            Opt::Output => "-o".into(),
            o => format!("--{}", o.name().replace('_', "-")),
        }
    }
}

/// An error as its one line: each error of its chain (anyhow's `{:#}`) in
/// the command line's words.
pub fn message(e: &anyhow::Error) -> String {
    let parts: Vec<String> = e.chain().map(error_text).collect();
    parts.join(": ")
}

/// One error of a chain.
fn error_text(e: &(dyn std::error::Error + 'static)) -> String {
    use store::{OtherKind, Setting, StoreError};
    // The engine's error says what its library's error says (its sources
    // follow in the chain): look at that one.
    match e.downcast_ref::<engine::Error>() {
        Some(engine::Error::Request(r)) => return error_text(r),
        Some(engine::Error::Store(s)) => return error_text(s),
        Some(engine::Error::Render(r)) => return error_text(r),
        Some(engine::Error::Unwritten { cause, folder }) => {
            let cause: Vec<String> = engine::causes(cause.as_ref()).map(error_text).collect();
            return engine::unwritten_text(&cause.join(": "), folder);
        }
        _ => {}
    }
    if let Some(r) = e.downcast_ref::<engine::RequestError>() {
        return r.in_words(&Flags);
    }
    let advice = match e.downcast_ref::<StoreError>() {
        Some(StoreError::Kind { found: OtherKind::CurvesNotAtlas, path }) => {
            return format!("{path}: not an atlas (a curve file: render an atlas with --curves FILE)");
        }
        Some(StoreError::Kind { found: OtherKind::NoCurves, path }) => {
            return format!("{path}: not a vibroatlas curve file (vibroatlas curve -o FILE.h5) nor an atlas with curves (vibroatlas curves ATLAS --into)");
        }
        Some(StoreError::OtherRun { setting: Setting::Overrides, .. }) => " (--set)",
        Some(StoreError::OtherRun { setting: Setting::Grid, .. }) => " (axes or --along)",
        _ => "",
    };
    match e.downcast_ref::<render::RenderError>().and_then(|r| r.missing()) {
        Some(render::Missing::Attractors) => format!("{e}: make it with atlas --attractors K"),
        _ => format!("{e}{advice}"),
    }
}
