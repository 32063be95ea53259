//! What the API's routes read and answer, as serde types: each route's
//! query (its keys, each read into a type whose refusal names the key), the
//! zoom's JSON body, and each JSON answer. The routes (`api.rs`) check what
//! depends on the atlas (a view, a sweep, a mass, a cell of the plane) and
//! call the libraries; the answers' keys come out sorted, as serde_json's
//! maps sort them.

use crate::guard::short;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A refused or failed request: its status and message.
pub(crate) struct Refusal(pub StatusCode, pub String);

impl IntoResponse for Refusal {
    fn into_response(self) -> Response {
        crate::guard::error(self.0, &self.1)
    }
}

/// A 400: the request is wrong.
pub(crate) fn bad(message: impl Into<String>) -> Refusal {
    Refusal(StatusCode::BAD_REQUEST, message.into())
}

/// A 404: what it names is not there.
pub(crate) fn not_found(message: impl Into<String>) -> Refusal {
    Refusal(StatusCode::NOT_FOUND, message.into())
}

/// An answer as JSON, its keys sorted.
pub(crate) fn answer<T: Serialize>(t: &T) -> Result<axum::Json<serde_json::Value>, Refusal> {
    serde_json::to_value(t)
        .map(axum::Json)
        .map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, format!("the answer: {e}")))
}

// ---------------------------------------------------------------- queries

/// A request's query, each key once: a key given twice is refused rather
/// than read as one of its values, and a query that does not decode is one
/// JSON refusal like every other.
pub(crate) struct Params(Vec<(String, String)>);

impl<S: Send + Sync> axum::extract::FromRequestParts<S> for Params {
    type Rejection = Refusal;

    async fn from_request_parts(parts: &mut axum::http::request::Parts, _: &S) -> Result<Params, Refusal> {
        let pairs: Vec<(String, String)> = serde_urlencoded::from_str(parts.uri.query().unwrap_or(""))
            .map_err(|e| bad(format!("query: cannot decode it ({e})")))?;
        for (i, (key, _)) in pairs.iter().enumerate() {
            if pairs[..i].iter().any(|(k, _)| k == key) {
                return Err(bad(format!("{}: given twice", short(key))));
            }
        }
        Ok(Params(pairs))
    }
}

impl Params {
    /// Refuses every key: the route takes its one argument in its path (a
    /// job, a file) or its body (a zoom).
    pub fn none(&self) -> Result<(), Refusal> {
        match self.0.first() {
            None => Ok(()),
            Some((k, _)) => Err(bad(format!("{}: not a parameter of this request (it takes none)", short(k)))),
        }
    }

    /// The value of `key`, if given.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// The query read as a `T`, besides the `atlas` key and, where the
    /// route takes a cell of the plane, the plane's two parameters (`axes`,
    /// returned by name with their values as given): a key that is none of
    /// these is refused, naming what the route takes, and a value `T` does
    /// not take is refused, naming its key. A plane parameter is given as
    /// `at.NAME` (the page's form), or as `NAME` where that is not a key of
    /// the route (a parameter named `sweep` or `n` is given as `at.sweep`,
    /// `at.n`: the plain key is the route's own).
    pub fn read<T: for<'de> Deserialize<'de>>(&self, axes: &[&str]) -> Result<(T, Vec<(String, String)>), Refusal> {
        let keys = keys::<T>();
        let own = |k: &str| k == "atlas" || keys.contains(&k);
        let plane = |k: &str| match k.strip_prefix("at.") {
            Some(name) if axes.contains(&name) => Some(name.to_string()),
            _ => (!own(k) && axes.contains(&k)).then(|| k.to_string()),
        };
        if let Some((k, _)) = self.0.iter().filter(|(k, _)| !own(k) && plane(k).is_none()).min() {
            let named = axes.iter().map(|a| if own(a) { format!("at.{a}") } else { a.to_string() });
            let takes: Vec<String> = ["atlas"].iter().chain(keys).map(|k| k.to_string()).chain(named).collect();
            return Err(bad(format!("{}: not a parameter of this request (it takes {})", short(k), takes.join(", "))));
        }
        let mut at: Vec<(String, String)> = Vec::new();
        for (k, v) in &self.0 {
            if let Some(name) = plane(k) {
                if at.iter().any(|(n, _)| *n == name) {
                    return Err(bad(format!("{}: given twice (as {name} and at.{name})", short(&name))));
                }
                at.push((name, v.clone()));
            }
        }
        let rest: Vec<_> = self.0.iter().filter(|(k, _)| k != "atlas" && own(k)).collect();
        let encoded = serde_urlencoded::to_string(&rest).map_err(|e| bad(format!("query: {e}")))?;
        let t = serde_path_to_error::deserialize(serde_urlencoded::Deserializer::new(form_urlencoded::parse(
            encoded.as_bytes(),
        )))
        .map_err(|e| bad(format!("{}: {}", e.path(), e.inner())))?;
        Ok((t, at))
    }
}

/// The keys of a query or body type: the fields its derived `Deserialize`
/// names (asked of a deserializer that only listens for them).
pub(crate) fn keys<T: for<'de> Deserialize<'de>>() -> &'static [&'static str] {
    struct Fields<'a>(&'a std::cell::Cell<&'static [&'static str]>);
    impl<'de> Deserializer<'de> for Fields<'_> {
        type Error = de::value::Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            self.0.set(fields);
            Err(de::Error::custom("its fields are known"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option unit
            unit_struct newtype_struct seq tuple tuple_struct map enum identifier ignored_any
        }
    }
    let fields = std::cell::Cell::new(&[][..]);
    let _ = T::deserialize(Fields(&fields));
    fields.get()
}

/// A text value's visitor: `parse` turns the text into the value or the
/// refusal's words.
struct FromText<F>(F, &'static str);

impl<'de, T, F: FnOnce(&str) -> Result<T, String>> Visitor<'de> for FromText<F> {
    type Value = T;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(self.1)
    }
    fn visit_str<E: de::Error>(self, t: &str) -> Result<T, E> {
        (self.0)(t).map_err(E::custom)
    }
}

/// A whole number from `LO` to `HI`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Count<const LO: usize, const HI: usize>(pub usize);

impl<'de, const LO: usize, const HI: usize> Deserialize<'de> for Count<LO, HI> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let parse = |t: &str| {
            t.parse::<usize>()
                .ok()
                .filter(|n| (LO..=HI).contains(n))
                .map(Count)
                .ok_or_else(|| format!("expected a whole number from {LO} to {HI}, got '{}'", short(t)))
        };
        d.deserialize_str(FromText(parse, "a whole number"))
    }
}

/// A whole number, its range the engine's to check.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Whole(pub usize);

impl<'de> Deserialize<'de> for Whole {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let parse =
            |t: &str| t.parse::<usize>().map(Whole).map_err(|_| format!("expected a whole number, got '{}'", short(t)));
        d.deserialize_str(FromText(parse, "a whole number"))
    }
}

/// A finite number.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Finite(pub f64);

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let parse = |t: &str| {
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .map(Finite)
                .ok_or_else(|| format!("'{}' is not a number", short(t)))
        };
        d.deserialize_str(FromText(parse, "a number"))
    }
}

/// A switch: `0` off, `1` on (absent: off).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Switch(pub bool);

impl<'de> Deserialize<'de> for Switch {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let parse = |t: &str| match t {
            "0" => Ok(Switch(false)),
            "1" => Ok(Switch(true)),
            _ => Err(format!("expected 0 or 1, got '{}'", short(t))),
        };
        d.deserialize_str(FromText(parse, "0 or 1"))
    }
}

/// A value of a named enum ([`scene::Named`]), refused with its names.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Name<T>(pub T);

impl<'de, T: scene::Named> Deserialize<'de> for Name<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let parse = |t: &str| T::parse(t).map(Name).ok_or_else(|| T::expected(&short(t)));
        d.deserialize_str(FromText(parse, "a name"))
    }
}

/// The query of a route that takes nothing but the atlas (`/api/atlas`,
/// `/api/curves`).
#[derive(Deserialize)]
pub(crate) struct Nothing {}

/// A view of the atlas, for one labelled mass (`/api/map`).
#[derive(Deserialize)]
pub(crate) struct ViewQuery {
    /// A sweep, `hysteresis`, `NAME:SWEEP` or `NAME:hysteresis` (the file's first sweep).
    pub view: Option<String>,
    /// A labelled mass (the first).
    pub mass: Option<String>,
}

/// A view's legend (`/api/legend`).
#[derive(Deserialize)]
pub(crate) struct LegendQuery {
    /// As [`ViewQuery::view`].
    pub view: Option<String>,
    /// As [`ViewQuery::mass`].
    pub mass: Option<String>,
    /// With the stored bifurcation curves' rows.
    #[serde(default)]
    pub curves: Switch,
}

/// A cell by its indices (`/api/at`).
#[derive(Deserialize)]
pub(crate) struct AtQuery {
    /// The column, 0 to the x axis's count less one.
    pub ix: Option<String>,
    /// The row.
    pub iy: Option<String>,
}

/// A stored cell: its sweep, beside the plane's two parameters (`/api/cell`,
/// the portrait, `/api/basins/plan`).
#[derive(Deserialize)]
pub(crate) struct CellQuery {
    /// The sweep (the file's first).
    pub sweep: Option<String>,
}

/// A stored cell's orbit (`/api/orbit`).
#[derive(Deserialize)]
pub(crate) struct OrbitQuery {
    /// As [`CellQuery::sweep`].
    pub sweep: Option<String>,
    /// The period to solve for (the cell's own).
    pub n: Option<Whole>,
}

/// Most forcing periods of a cell's sections on the page (a few seconds).
pub(crate) const MAX_PERIODS: usize = 100_000;
/// Most start states of an attractor search on the page.
pub(crate) const MAX_SAMPLES: usize = 4096;

/// A stored cell's sections (`/api/cell/sections.png`).
#[derive(Deserialize)]
pub(crate) struct SectionsQuery {
    /// As [`CellQuery::sweep`].
    pub sweep: Option<String>,
    /// Forcing periods simulated (1000).
    pub periods: Option<Count<1, MAX_PERIODS>>,
}

/// The attractors of a stored cell's parameters (`/api/attractors`).
#[derive(Deserialize)]
pub(crate) struct AttractorsQuery {
    /// As [`CellQuery::sweep`].
    pub sweep: Option<String>,
    /// Start states sampled (64).
    pub samples: Option<Count<1, MAX_SAMPLES>>,
}

/// The basins of a stored cell's parameters (`/api/basins`).
#[derive(Deserialize)]
pub(crate) struct BasinsQuery {
    /// As [`CellQuery::sweep`].
    pub sweep: Option<String>,
    /// The grid's first state component, `COMPONENT=START:STOP:COUNT`.
    pub basin_x: Option<String>,
    /// Its second.
    pub basin_y: Option<String>,
    /// The forcing phase of the starts (the scene's τ).
    pub phase: Option<Finite>,
}

/// A zoom's estimate (`/api/zoom/plan`).
#[derive(Deserialize)]
pub(crate) struct ZoomPlanQuery {
    /// The box's x axis, `NAME=START:STOP:COUNT`.
    pub x: Option<String>,
    /// Its y axis.
    pub y: Option<String>,
    /// The sweeps (the parent's).
    pub sweep: Option<String>,
    /// Parameters set beside the box, `NAME=VALUE,NAME=VALUE`.
    pub set: Option<String>,
}

/// A view drawn as a figure (`/api/figure`).
#[derive(Deserialize)]
pub(crate) struct FigureQuery {
    /// As [`ViewQuery::view`].
    pub view: Option<String>,
    /// As [`ViewQuery::mass`].
    pub mass: Option<String>,
    /// png (default), svg or pdf.
    pub format: Option<Name<render::Format>>,
    /// `screen` (default) or a print size.
    pub size: Option<String>,
    /// With the stored bifurcation curves.
    #[serde(default)]
    pub curves: Switch,
}

/// The JSON body of `POST /api/zoom`: the box as [`ZoomPlanQuery`]'s, of
/// atlas `atlas` (0, the file given).
#[derive(Deserialize)]
pub(crate) struct ZoomBody {
    /// The atlas zoomed into.
    pub atlas: Option<u64>,
    /// As [`ZoomPlanQuery::x`].
    pub x: Option<String>,
    /// As [`ZoomPlanQuery::y`].
    pub y: Option<String>,
    /// As [`ZoomPlanQuery::sweep`].
    pub sweep: Option<String>,
    /// As [`ZoomPlanQuery::set`].
    pub set: Option<String>,
}

impl ZoomBody {
    /// The body read: an object of [`ZoomBody`]'s fields, each refused by
    /// its name.
    pub fn read(bytes: &[u8]) -> Result<ZoomBody, Refusal> {
        let body: serde_json::Value =
            serde_json::from_slice(bytes).map_err(|e| bad(format!("the body is not JSON ({e})")))?;
        let fields = keys::<ZoomBody>();
        let Some(object) = body.as_object() else {
            return Err(bad(r#"the body: expected an object {"atlas": ID, "x": "NAME=A:B:N", "y": "NAME=C:D:M"}"#));
        };
        if let Some(k) = object.keys().find(|k| !fields.contains(&k.as_str())) {
            return Err(bad(format!("{}: not a field of a zoom ({})", short(k), fields.join(", "))));
        }
        // Read again from the bytes, where a field given twice is seen.
        let mut fields = serde_json::Deserializer::from_slice(bytes);
        serde_path_to_error::deserialize(&mut fields).map_err(|e| {
            let inner = e.inner().to_string();
            // serde_json's words, without its position in the body.
            let inner = inner.rsplit_once(" at line ").map_or(inner.as_str(), |(text, _)| text);
            match inner.strip_prefix("duplicate field `").and_then(|n| n.strip_suffix('`')) {
                Some(name) => bad(format!("{}: given twice", short(name))),
                None => bad(format!("{}: {}", e.path(), crate::guard::brief(inner))),
            }
        })
    }
}

// ---------------------------------------------------------------- answers

/// `/api/atlas`: what the page draws the atlas with.
#[derive(Serialize)]
pub(crate) struct AtlasAnswer<'a> {
    /// Its id on this server (0: the file given).
    pub id: usize,
    /// Its file.
    pub file: String,
    /// The atlas it was zoomed from, and the box.
    pub parent: Option<Parent<'a>>,
    /// The boxes from the explored file to it.
    pub boxes: &'a [String],
    /// The scene's name.
    pub scene: &'a str,
    /// The run's preset.
    pub preset: &'static str,
    /// The plane's axes.
    pub x: AxisAnswer<'a>,
    /// The y axis.
    pub y: AxisAnswer<'a>,
    /// `x` or `y`: which axis the chains follow.
    pub along: &'static str,
    /// The sweeps.
    pub sweeps: Vec<&'static str>,
    /// The labelled masses.
    pub masses: &'a [String],
    /// Every view (`/api/map`'s `view`).
    pub views: Vec<String>,
    /// Per sweep and labelled mass, every label with its cells and colour.
    pub labels: BTreeMap<&'static str, BTreeMap<&'a str, Vec<LabelRow>>>,
    /// The parameters the run set (`--set`), with their symbols.
    pub settings: Vec<Setting<'a>>,
}

/// A zoom's parent: its id and the box zoomed.
#[derive(Serialize)]
pub(crate) struct Parent<'a> {
    /// The parent atlas's id.
    pub id: usize,
    /// The box, `NAME=A:B:N NAME=C:D:M`.
    #[serde(rename = "box")]
    pub region: &'a str,
}

/// An axis of the plane, with its symbol as text and as runs of plain and
/// subscript text.
#[derive(Serialize)]
pub(crate) struct AxisAnswer<'a> {
    /// The parameter.
    pub name: &'a str,
    /// Its symbol (`ω`, `μ_k`).
    pub symbol: String,
    /// The symbol as (text, subscript) runs.
    pub symbol_runs: Vec<(String, bool)>,
    /// Its long name.
    pub long_name: Option<&'a str>,
    /// The first value.
    pub start: f64,
    /// The last.
    pub stop: f64,
    /// Values.
    pub count: usize,
    /// Every value.
    pub values: Vec<f64>,
}

/// One label of a sweep's legend.
#[derive(Serialize)]
pub(crate) struct LabelRow {
    /// The label.
    pub label: String,
    /// Its cells.
    pub count: u64,
    /// Its colour, RGB.
    pub colour: [u8; 3],
}

/// A parameter the run set.
#[derive(Serialize)]
pub(crate) struct Setting<'a> {
    /// Its name.
    pub name: &'a str,
    /// Its symbol.
    pub symbol: String,
    /// Its value.
    pub value: f64,
}

/// `/api/legend`: a view's legend rows and its colour bar.
#[derive(Serialize)]
pub(crate) struct LegendAnswer {
    /// The rows.
    pub legend: Vec<KeyRow>,
    /// The colour bar of a continuous view.
    pub scale: Option<ScaleAnswer>,
}

/// One legend row (`render::Key`).
#[derive(Serialize)]
pub(crate) struct KeyRow {
    /// How its swatch is drawn.
    pub swatch: &'static str,
    /// Its colours.
    pub colours: Vec<[u8; 3]>,
    /// Its text.
    pub text: String,
}

/// A colour bar: its title, ends and colours evenly along it.
#[derive(Serialize)]
pub(crate) struct ScaleAnswer {
    /// The title.
    pub title: String,
    /// The low end.
    pub lo: f64,
    /// The high end.
    pub hi: f64,
    /// The colours.
    pub colours: Vec<[u8; 3]>,
}

/// `/api/at`: a cell's stored record in every sweep.
#[derive(Serialize)]
pub(crate) struct AtAnswer {
    /// Its column.
    pub ix: usize,
    /// Its row.
    pub iy: usize,
    /// Its parameters.
    pub parameters: BTreeMap<String, f64>,
    /// Per sweep, its record (null where not computed).
    pub sweeps: BTreeMap<&'static str, Option<engine::CellRecord>>,
}

/// `/api/attractors`: the object of `attractors --json`, with each
/// attractor's colour and the basins' picture.
#[derive(Serialize)]
pub(crate) struct AttractorsAnswer {
    /// `attractors --json`.
    #[serde(flatten)]
    pub found: serde_json::Value,
    /// Each attractor's colour.
    pub colours: Vec<[u8; 3]>,
    /// The basins of the samples, a PNG in base64.
    pub basins_png: String,
}

/// `/api/basins/plan`: the basin map proposed for a cell and its estimate.
#[derive(Serialize)]
pub(crate) struct BasinsPlan {
    /// The proposed x axis, `COMPONENT=START:STOP:COUNT`.
    pub x: String,
    /// The y axis.
    pub y: String,
    /// The state components a basin axis may take.
    pub components: Vec<String>,
    /// Starts of the proposed map.
    pub starts: usize,
    /// Most starts the page computes.
    pub max_starts: usize,
    /// The server's threads.
    pub threads: usize,
    /// Seconds per start on one thread, as timed.
    pub seconds_per_start: f64,
    /// The estimate for the map.
    pub seconds: f64,
}

/// `/api/basins`: the object of `basins --json`, with each attractor's
/// colour, the map and its time.
#[derive(Serialize)]
pub(crate) struct BasinsAnswer {
    /// `basins --json`.
    #[serde(flatten)]
    pub found: serde_json::Value,
    /// Each attractor's colour.
    pub colours: Vec<[u8; 3]>,
    /// The map, a PNG in base64.
    pub png: String,
    /// Its time, s.
    pub seconds: f64,
}

/// `/api/zoom/plan`: a zoom's estimate.
#[derive(Serialize)]
pub(crate) struct ZoomPlan {
    /// Cells of the box.
    pub cells: usize,
    /// Its sweeps.
    pub sweeps: usize,
    /// The server's threads.
    pub threads: usize,
    /// Seconds per cell on one thread, as timed.
    pub seconds_per_cell: f64,
    /// What the probe spent besides computing.
    pub overhead_seconds: f64,
    /// The estimate.
    pub seconds: f64,
}

/// `POST /api/zoom`: the job started.
#[derive(Serialize)]
pub(crate) struct Started {
    /// Its id (`/api/jobs/ID`).
    pub job: usize,
}

/// `/api/jobs/ID`: a zoom's state.
#[derive(Serialize)]
pub(crate) struct JobAnswer {
    /// queued, running, done, failed or cancelled.
    pub state: &'static str,
    /// The share of its cells done.
    pub progress: f64,
    /// Seconds computed.
    pub seconds: f64,
    /// The zoom's atlas, once done.
    pub child: Option<usize>,
    /// Its page.
    pub url: Option<String>,
    /// Why it failed.
    pub error: Option<String>,
}

/// `DELETE /api/jobs/ID`: whether it was stopped, and its state.
#[derive(Serialize)]
pub(crate) struct Cancelled {
    /// Whether it was queued or running.
    pub cancelled: bool,
    /// Its state now.
    pub state: &'static str,
}

/// `/api/curves`: the stored bifurcation curves over the atlas's plane.
#[derive(Serialize)]
pub(crate) struct CurvesAnswer {
    /// The curves.
    pub curves: Vec<CurveAnswer>,
}

/// One curve, drawn as the figures draw it.
#[derive(Serialize)]
pub(crate) struct CurveAnswer {
    /// Its kind.
    pub kind: String,
    /// Its colour.
    pub colour: [u8; 3],
    /// Its width, pt.
    pub width_pt: f64,
    /// Its dash and gap, pt.
    pub dash_pt: [f64; 2],
    /// Its points on the plane.
    pub points: Vec<(f64, f64)>,
    /// Its codimension-two points.
    pub marks: Vec<(f64, f64)>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A query type's keys are its fields, in order; a body's too.
    #[test]
    fn keys_are_the_fields() {
        assert_eq!(keys::<LegendQuery>(), ["view", "mass", "curves"]);
        assert_eq!(keys::<Nothing>(), [] as [&str; 0]);
        assert_eq!(keys::<ZoomBody>(), ["atlas", "x", "y", "sweep", "set"]);
    }

    fn query(q: &str) -> Params {
        Params(serde_urlencoded::from_str(q).unwrap())
    }

    /// Values are read into their types, each refusal naming its key;
    /// unknown keys are refused with what the route takes; the plane's
    /// parameters come back as given.
    #[test]
    fn a_query_names_the_key_it_refuses() {
        let (s, at) = query("sweep=up&periods=20&omega=2").read::<SectionsQuery>(&["omega", "sigma"]).ok().unwrap();
        assert_eq!((s.sweep.as_deref(), s.periods.map(|p| p.0)), (Some("up"), Some(20)));
        assert_eq!(at, [("omega".to_string(), "2".to_string())]);
        let refused = |q: &str, axes: &[&str]| query(q).read::<SectionsQuery>(axes).err().unwrap().1;
        assert_eq!(refused("periods=0", &[]), "periods: expected a whole number from 1 to 100000, got '0'");
        assert_eq!(refused("periods=x&sweep=up", &[]), "periods: expected a whole number from 1 to 100000, got 'x'");
        assert_eq!(
            refused("perods=3&omega=1", &["omega", "sigma"]),
            "perods: not a parameter of this request (it takes atlas, sweep, periods, omega, sigma)"
        );
        let figure = |q: &str| query(q).read::<FigureQuery>(&[]).err().unwrap().1;
        assert_eq!(figure("format=bmp"), "format: expected png, svg or pdf, got 'bmp'");
        assert_eq!(figure("curves=2"), "curves: expected 0 or 1, got '2'");
        let phase = query("phase=inf").read::<BasinsQuery>(&[]).err().unwrap().1;
        assert_eq!(phase, "phase: 'inf' is not a number");
    }

    /// A plane parameter named as a key of the route (`sweep`, `periods`) is
    /// given as `at.NAME`, the plain key staying the route's; any plane
    /// parameter may be (the page's form), once.
    #[test]
    fn a_plane_parameter_named_as_a_key_is_given_under_at() {
        let axes = ["sweep", "periods"];
        let (s, at) =
            query("sweep=down&at.sweep=0.5&at.periods=2&periods=7").read::<SectionsQuery>(&axes).ok().unwrap();
        assert_eq!((s.sweep.as_deref(), s.periods.map(|p| p.0)), (Some("down"), Some(7)));
        assert_eq!(at, [("sweep".to_string(), "0.5".to_string()), ("periods".to_string(), "2".to_string())]);
        let (_, at) = query("at.omega=1&sigma=2").read::<SectionsQuery>(&["omega", "sigma"]).ok().unwrap();
        assert_eq!(at, [("omega".to_string(), "1".to_string()), ("sigma".to_string(), "2".to_string())]);
        let refused = |q: &str, axes: &[&str]| query(q).read::<SectionsQuery>(axes).err().unwrap().1;
        assert_eq!(refused("omega=1&at.omega=1", &["omega", "sigma"]), "omega: given twice (as omega and at.omega)");
        assert_eq!(
            refused("at.delta=1", &["sweep", "sigma"]),
            "at.delta: not a parameter of this request (it takes atlas, sweep, periods, at.sweep, sigma)"
        );
    }

    /// The zoom's body: each field refused by its name.
    #[test]
    fn a_zoom_body_names_the_field_it_refuses() {
        let refused = |b: &str| ZoomBody::read(b.as_bytes()).err().unwrap().1;
        assert_eq!(refused(r#"{"x": 5}"#), "x: invalid type: integer `5`, expected a string");
        assert_eq!(refused(r#"{"atlas": -1}"#), "atlas: invalid value: integer `-1`, expected u64");
        assert_eq!(refused(r#"{"bogus": 1}"#), "bogus: not a field of a zoom (atlas, x, y, sweep, set)");
        assert_eq!(refused(r#"{"x": "omega=1:2:3", "x": "omega=1:2:3"}"#), "x: given twice");
        assert!(refused("[1]").starts_with("the body: expected an object"));
        let b = ZoomBody::read(br#"{"x": "omega=1:2:3", "atlas": 2}"#).ok().unwrap();
        assert_eq!((b.atlas, b.x.as_deref(), b.y), (Some(2), Some("omega=1:2:3"), None));
    }
}
