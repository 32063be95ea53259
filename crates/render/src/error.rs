//! What a picture that could not be drawn or written says: [`RenderError`],
//! its cause kept as the error's source, and what an atlas lacks ([`Missing`]).

/// Wraps a drawing or scene error (the error's source).
pub(crate) fn err<E: std::error::Error + Send + Sync + 'static>(e: E) -> RenderError {
    RenderError::because("", e)
}

/// What an atlas lacks for the picture asked of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Missing {
    /// Its coexisting attractors (a map of their number).
    Attractors,
}

/// A picture could not be drawn or written: `render: ` and what failed,
/// with the error of the library or of the system that failed (plotters, the
/// scene, svg2pdf, the file system) as its [`source`](std::error::Error::source)
/// where there is one: `{:#}` (anyhow) prints `render: what: cause`.
#[derive(Debug)]
pub struct RenderError {
    /// What failed, without its cause's text (empty: the cause says it).
    what: String,
    /// The error that made it fail.
    cause: Option<Box<dyn std::error::Error + Send + Sync>>,
    /// What the atlas lacks, when that is why.
    missing: Option<Missing>,
}

impl RenderError {
    /// An error saying `message`.
    pub fn new(message: impl Into<String>) -> RenderError {
        RenderError { what: message.into(), cause: None, missing: None }
    }

    /// An error saying `what` failed because of `cause`.
    pub fn because(what: impl Into<String>, cause: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> RenderError {
        RenderError { what: what.into(), cause: Some(cause.into()), missing: None }
    }

    /// The atlas lacks `what` for the picture: `the file has no …`.
    pub fn lacks(what: Missing) -> RenderError {
        let name = match what {
            Missing::Attractors => "attractors",
        };
        RenderError { what: format!("the file has no {name}"), cause: None, missing: Some(what) }
    }

    /// What the atlas lacks, when that is why the picture was not drawn.
    pub fn missing(&self) -> Option<Missing> {
        self.missing
    }

    /// What failed, without its cause.
    pub fn what(&self) -> &str {
        &self.what
    }
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.what.as_str() {
            "" => f.write_str("render"),
            what => write!(f, "render: {what}"),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trade;

    /// A picture written where it cannot be: the system's error is the
    /// source, typed, and the chain reads `render: path: cause` on one line.
    #[test]
    fn a_failed_write_keeps_its_cause() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-render-cause-{}", std::process::id()));
        let path = dir.join("missing-folder").join("a.svg");
        let e = trade(&[("a".into(), 1.0, 0.5)], &path).unwrap_err();
        let cause = std::error::Error::source(&e).expect("a source");
        assert!(cause.downcast_ref::<std::io::Error>().is_some(), "{cause:?}");
        assert_eq!(e.to_string(), format!("render: {}", path.display()));
        let chain = format!("{e}: {cause}");
        assert!(chain.starts_with(&format!("render: {}: ", path.display())) && !chain.contains('\n'), "{chain}");
        assert!(std::error::Error::source(&RenderError::new("no such view")).is_none());
    }
}
