//! The explorer's HTTP API (docs/explore.md): JSON objects and, for a
//! view's colours, bytes. Every answer comes from the libraries (engine,
//! render, store); a bad request is a 4xx with `{"error": "…"}` naming what is
//! wrong, never a crash of the server.

use crate::guard::{self, short};
use crate::state::{phase, share, stop, Job, NotQueued, Opened, Phase, Request, State, BUSY_LIMIT, ZOOM_QUEUE};
use axum::extract::{Path, State as Shared};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use base64::prelude::{Engine as _, BASE64_STANDARD};
use engine::{CellRecord, SceneSource, Sim, Start};
use grid::{Axis, Number, SweepKind};
use render::{Show, View};
use scene::Named;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::sync::Arc;

type St = Arc<State>;

/// Most forcing periods of a cell's sections on the page (a few seconds).
const MAX_PERIODS: usize = 100_000;
/// Most start states of an attractor search on the page.
const MAX_SAMPLES: usize = 4096;
/// Most starts of a basin map the page computes (500 × 500).
const MAX_BASIN_STARTS: usize = 250_000;
/// Starts per side the page proposes for a basin map.
const BASIN_SIDE: usize = 100;

/// A request's query, each key once: a key given twice is refused rather
/// than read as one of its values, and a query that does not decode is one
/// JSON refusal like every other.
pub(crate) struct Params(HashMap<String, String>);

impl<S: Send + Sync> axum::extract::FromRequestParts<S> for Params {
    type Rejection = Refusal;

    async fn from_request_parts(parts: &mut axum::http::request::Parts, _: &S) -> Result<Params, Refusal> {
        let pairs: Vec<(String, String)> = serde_urlencoded::from_str(parts.uri.query().unwrap_or(""))
            .map_err(|e| bad(format!("query: cannot decode it ({e})")))?;
        let mut q = HashMap::with_capacity(pairs.len());
        for (key, value) in pairs {
            if q.contains_key(&key) {
                return Err(bad(format!("{}: given twice", short(&key))));
            }
            q.insert(key, value);
        }
        Ok(Params(q))
    }
}

/// A refused or failed request: its status and message.
pub(crate) struct Refusal(StatusCode, String);

impl IntoResponse for Refusal {
    fn into_response(self) -> Response {
        guard::error(self.0, &self.1)
    }
}

fn bad(message: impl Into<String>) -> Refusal {
    Refusal(StatusCode::BAD_REQUEST, message.into())
}

fn not_found(message: impl Into<String>) -> Refusal {
    Refusal(StatusCode::NOT_FOUND, message.into())
}

/// An engine error as one line (each cause of its chain, a refusal in the
/// API's words: the request's fields).
fn message(e: &engine::Error) -> String {
    engine::in_words(e, &engine::Fields)
}

fn failed(e: engine::Error) -> Refusal {
    Refusal(StatusCode::UNPROCESSABLE_ENTITY, message(&e))
}

/// The page's routes, each behind [`guard::screen`] for a server on `port`.
pub(crate) fn router(state: St, port: u16) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/explore.js", get(|| asset(include_str!("../assets/explore.js"), "text/javascript; charset=utf-8")))
        .route("/explore.css", get(|| asset(include_str!("../assets/explore.css"), "text/css; charset=utf-8")))
        .route("/api/atlas", get(atlas))
        .route("/api/map", get(map))
        .route("/api/legend", get(legend))
        .route("/api/at", get(at))
        .route("/api/cell", get(cell))
        .route("/api/orbit", get(orbit))
        .route("/api/cell/portrait.png", get(portrait))
        .route("/api/cell/sections.png", get(sections))
        .route("/api/attractors", get(attractors))
        .route("/api/basins/plan", get(basins_plan))
        .route("/api/basins", get(basins))
        .route("/api/zoom", axum::routing::post(zoom))
        .route("/api/zoom/plan", get(zoom_plan))
        .route("/api/jobs/{id}", get(job).delete(cancel))
        .route("/api/figure", get(figure))
        .route("/api/curves", get(curves))
        .route("/api/files/{id}", get(file))
        .fallback(|| async { not_found("no such page or API route (see docs/explore.md)") })
        .method_not_allowed_fallback(|| async {
            Refusal(StatusCode::METHOD_NOT_ALLOWED, "this route does not take that method (see docs/explore.md)".into())
        })
        .with_state(state)
        .layer(axum::extract::DefaultBodyLimit::max(guard::MAX_BODY))
        .layer(axum::middleware::from_fn_with_state(guard::Allowed::on(port), guard::screen))
}

async fn page() -> Response {
    asset(include_str!("../assets/index.html"), "text/html; charset=utf-8").await
}

async fn asset(text: &'static str, kind: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind), (header::CACHE_CONTROL, "no-cache")], text).into_response()
}

/// Runs blocking work (a simulation, a file) off the server's threads, on
/// the runtime's bounded pool; with [`BUSY_LIMIT`] requests already there,
/// a 503.
async fn blocking<T: Send + 'static>(
    state: &State,
    f: impl FnOnce() -> Result<T, Refusal> + Send + 'static,
) -> Result<T, Refusal> {
    use std::sync::atomic::Ordering;
    if state.busy.fetch_add(1, Ordering::Relaxed) >= BUSY_LIMIT {
        state.busy.fetch_sub(1, Ordering::Relaxed);
        return Err(Refusal(
            StatusCode::SERVICE_UNAVAILABLE,
            format!("the explorer is computing {BUSY_LIMIT} requests already; ask again once they are done"),
        ));
    }
    let done = tokio::task::spawn_blocking(f)
        .await
        .unwrap_or_else(|e| Err(Refusal(StatusCode::INTERNAL_SERVER_ERROR, format!("the work failed: {e}"))));
    state.busy.fetch_sub(1, Ordering::Relaxed);
    done
}

/// The atlas of the `atlas` parameter (0, the file given, by default).
fn opened(state: &State, q: &HashMap<String, String>) -> Result<(usize, Arc<Opened>), Refusal> {
    let id = match q.get("atlas") {
        None => 0,
        Some(t) => t.parse::<usize>().map_err(|_| bad(format!("atlas: expected an atlas id, got '{t}'")))?,
    };
    state.atlas(id).map(|a| (id, a)).ok_or_else(|| not_found(format!("atlas: no atlas {id}")))
}

/// Refuses a parameter the route does not take, one that a misspelling
/// (`veiw=up`) would otherwise leave unread: the route's `keys`, and with
/// `plane` the parameters of that atlas's axes (a cell's `omega=…&delta=…`).
fn only(q: &HashMap<String, String>, keys: &[&str], plane: Option<&Opened>) -> Result<(), Refusal> {
    let axes = plane.map(|o| [o.atlas.meta.plane.x.name.as_str(), o.atlas.meta.plane.y.name.as_str()]);
    let known = |k: &str| keys.contains(&k) || axes.is_some_and(|a| a.contains(&k));
    match q.keys().filter(|k| !known(k)).min() {
        None => Ok(()),
        Some(k) => {
            let mut takes: Vec<&str> = keys.to_vec();
            takes.extend(axes.iter().flatten());
            Err(bad(format!("{}: not a parameter of this request (it takes {})", short(k), takes.join(", "))))
        }
    }
}

/// Refuses an atlas whose file was replaced or removed since it was read:
/// its cells on the page would no longer be the file's.
fn unchanged(o: &Opened) -> Result<(), Refusal> {
    if o.unchanged() {
        return Ok(());
    }
    Err(changed(o))
}

/// The 409 of a file that changed since it was read.
fn changed(o: &Opened) -> Refusal {
    Refusal(
        StatusCode::CONFLICT,
        format!(
            "{}: the file changed or was removed since the explorer read it; start explore again to see it",
            o.path.display()
        ),
    )
}

/// A whole number of the parameter `name` in `lo..=hi` (`default` when absent).
fn count(q: &HashMap<String, String>, name: &str, default: usize, lo: usize, hi: usize) -> Result<usize, Refusal> {
    match q.get(name) {
        None => Ok(default),
        Some(t) => t
            .parse::<usize>()
            .ok()
            .filter(|n| (lo..=hi).contains(n))
            .ok_or_else(|| bad(format!("{name}: expected a whole number from {lo} to {hi}, got '{}'", short(t)))),
    }
}

/// A switch parameter: absent or `0` off, `1` on.
fn switch(q: &HashMap<String, String>, name: &str) -> Result<bool, Refusal> {
    match q.get(name).map(String::as_str) {
        None | Some("0") => Ok(false),
        Some("1") => Ok(true),
        Some(t) => Err(bad(format!("{name}: expected 0 or 1, got '{}'", short(t)))),
    }
}

/// The labelled mass of the `mass` parameter (the first by default).
fn mass(o: &Opened, q: &HashMap<String, String>) -> Result<usize, Refusal> {
    let masses = &o.atlas.meta.masses;
    match q.get("mass") {
        None => Ok(0),
        Some(m) => masses
            .iter()
            .position(|n| n == m)
            .ok_or_else(|| bad(format!("mass: no labelled mass {m}; the atlas labels {}", masses.join(", ")))),
    }
}

/// The sweep of the `sweep` parameter (the file's first by default).
fn sweep(o: &Opened, q: &HashMap<String, String>) -> Result<SweepKind, Refusal> {
    let sweeps = &o.atlas.meta.sweeps;
    match q.get("sweep") {
        None => Ok(sweeps[0]),
        Some(s) => SweepKind::parse(s).filter(|k| sweeps.contains(k)).ok_or_else(|| {
            let have: Vec<&str> = sweeps.iter().map(|k| k.name()).collect();
            bad(format!("sweep: '{s}' is not a sweep of the atlas ({})", have.join(", ")))
        }),
    }
}

/// The views of an atlas: its sweeps, hysteresis with up and down, and the
/// numbers of each sweep: `multiplier`, `lyapunov` and every stored quantity
/// of the steady motion, each as `NAME:SWEEP`; with up and down, every
/// stored quantity's up less down, `NAME:hysteresis`.
fn views(o: &Opened) -> Vec<String> {
    let m = &o.atlas.meta;
    let mut v: Vec<String> = m.sweeps.iter().map(|s| s.name().to_string()).collect();
    if m.has_up_and_down() {
        v.push("hysteresis".into());
    }
    for q in Number::all(m) {
        v.extend(m.sweeps.iter().map(|s| format!("{}:{}", q.name(m), s.name())));
    }
    if m.has_up_and_down() {
        v.extend(Number::all(m).filter(|q| q.of_motion()).map(|q| format!("{}:hysteresis", q.name(m))));
    }
    v
}

/// The view of the `view` parameter: a sweep, `hysteresis`, `NAME:SWEEP`
/// of a number per cell (`multiplier`, `lyapunov`, a stored quantity), or
/// `NAME:hysteresis` of a stored quantity.
fn show(o: &Opened, q: &HashMap<String, String>) -> Result<Show, Refusal> {
    let m = &o.atlas.meta;
    let name = q.get("view").cloned().unwrap_or_else(|| m.sweeps[0].name().to_string());
    let refused = || bad(format!("view: '{}' is not a view of the atlas ({})", short(&name), views(o).join(", ")));
    if let Some((number, "hysteresis")) = name.rsplit_once(':') {
        return match Number::named(m, number) {
            Some(quantity) if quantity.of_motion() && m.has_up_and_down() => Ok(Show::Difference(quantity)),
            _ => Err(refused()),
        };
    }
    if let Some((number, s)) = name.rsplit_once(':') {
        let sweep = SweepKind::parse(s).filter(|k| m.sweeps.contains(k)).ok_or_else(refused)?;
        let quantity = Number::named(m, number).ok_or_else(refused)?;
        return Ok(Show::Scalar(sweep, quantity));
    }
    match View::parse(&name) {
        Some(View::Sweep(s)) if m.sweeps.contains(&s) => Ok(Show::Map(View::Sweep(s))),
        Some(View::Hysteresis) if views(o).iter().any(|v| v == "hysteresis") => Ok(Show::Map(View::Hysteresis)),
        _ => Err(refused()),
    }
}

fn axis_json(a: &Axis, o: &Opened) -> Value {
    let m = &o.atlas.meta;
    let symbol = m.symbol(&a.name);
    let runs: Vec<Value> = render::subscript_runs(&symbol).into_iter().map(|(t, sub)| json!([t, sub])).collect();
    json!({
        "name": a.name,
        "symbol": symbol,
        "symbol_runs": runs,
        "long_name": m.long_name(&a.name),
        "start": a.start,
        "stop": a.stop,
        "count": a.count,
        "values": a.values(),
    })
}

async fn atlas(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (id, o) = opened(&state, &q)?;
    only(&q, &["atlas"], None)?;
    let m = &o.atlas.meta;
    let labels: serde_json::Map<String, Value> = m
        .sweeps
        .iter()
        .map(|&s| {
            let per_mass: serde_json::Map<String, Value> = m
                .masses
                .iter()
                .enumerate()
                .map(|(mi, name)| {
                    let rows: Vec<Value> = o
                        .atlas
                        .legend(s, mi)
                        .into_iter()
                        .map(|(l, n)| json!({"label": l.to_string(), "count": n, "colour": grid::palette::colour(l)}))
                        .collect();
                    (name.clone(), Value::from(rows))
                })
                .collect();
            (s.name().to_string(), Value::from(per_mass))
        })
        .collect();
    Ok(Json(json!({
        "id": id,
        "file": o.path.display().to_string(),
        "parent": o.parent.as_ref().map(|(p, region)| json!({"id": p, "box": region})),
        "boxes": o.boxes,
        "scene": m.scene_name,
        "preset": m.preset.name(),
        "x": axis_json(&m.plane.x, &o),
        "y": axis_json(&m.plane.y, &o),
        "along": m.plane.along.name(),
        "sweeps": m.sweeps.iter().map(|s| s.name()).collect::<Vec<_>>(),
        "masses": m.masses,
        "views": views(&o),
        "labels": labels,
        "settings": m.overrides.iter().map(|(k, v)| json!({"name": k, "symbol": m.symbol(k), "value": v})).collect::<Vec<_>>(),
    })))
}

async fn map(Shared(state): Shared<St>, Params(q): Params) -> Result<Response, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "view", "mass"], None)?;
    let (show, mass) = (show(&o, &q)?, mass(&o, &q)?);
    let layer =
        blocking(&state, move || render::layer(&o.atlas, show, mass, &[]).map_err(|e| bad(e.to_string()))).await?;
    let mut bytes = layer.above;
    bytes.extend(layer.below);
    Ok(([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response())
}

async fn legend(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "view", "mass", "curves"], None)?;
    let (show, mass) = (show(&o, &q)?, mass(&o, &q)?);
    let curves = if switch(&q, "curves")? { overlays(&state, &o) } else { Vec::new() };
    let layer =
        blocking(&state, move || render::layer(&o.atlas, show, mass, &curves).map_err(|e| bad(e.to_string()))).await?;
    let rows: Vec<Value> =
        layer.legend.iter().map(|k| json!({"swatch": k.swatch, "colours": k.colours, "text": k.text})).collect();
    let scale =
        layer.scale.map(|(title, lo, hi, colours)| json!({"title": title, "lo": lo, "hi": hi, "colours": colours}));
    Ok(Json(json!({"legend": rows, "scale": scale})))
}

/// The cell `(iy, ix)` of the `ix`, `iy` parameters.
fn cell_index(o: &Opened, q: &HashMap<String, String>) -> Result<(usize, usize), Refusal> {
    let p = &o.atlas.meta.plane;
    let index = |name: &str, count: usize| -> Result<usize, Refusal> {
        let t = q.get(name).ok_or_else(|| bad(format!("{name}: missing")))?;
        t.parse::<usize>()
            .ok()
            .filter(|&i| i < count)
            .ok_or_else(|| bad(format!("{name}: expected 0 to {}, got '{t}'", count - 1)))
    };
    Ok((index("iy", p.y.count)?, index("ix", p.x.count)?))
}

async fn at(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "ix", "iy"], None)?;
    let (iy, ix) = cell_index(&o, &q)?;
    let m = &o.atlas.meta;
    let i = iy * m.plane.x.count + ix;
    let sweeps: serde_json::Map<String, Value> = o
        .atlas
        .maps
        .iter()
        .map(|map| {
            let v = match &map.cells[i] {
                None => json!(null),
                Some(c) => serde_json::to_value(CellRecord::in_atlas(m, c)).unwrap_or(Value::Null),
            };
            (map.sweep.name().to_string(), v)
        })
        .collect();
    let parameters: serde_json::Map<String, Value> =
        m.plane.params(iy, ix).into_iter().map(|(k, v)| (k, json!(v))).collect();
    Ok(Json(json!({"ix": ix, "iy": iy, "parameters": parameters, "sweeps": sweeps})))
}

/// The stored cell of the request: `sweep` and a value of each axis (the
/// plane's own parameter names), as `cell --from FILE --sweep S --at …`.
fn stored_cell(o: &Opened, q: &HashMap<String, String>) -> Result<(Sim, Start), Refusal> {
    let sweep = sweep(o, q)?;
    let p = &o.atlas.meta.plane;
    let mut at = Vec::new();
    for a in [&p.x, &p.y] {
        let Some(t) = q.get(&a.name) else {
            return Err(bad(format!(
                "{}: missing (give the cell by the plane's parameters {} and {})",
                a.name, p.x.name, p.y.name
            )));
        };
        let v = t
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("{}: '{t}' is not a number", a.name)))?;
        at.push((a.name.clone(), v));
    }
    let sim = Sim::new(SceneSource::Stored(o.path.clone()));
    Ok((sim, Start::Cell { file: o.path.clone(), at, sweep: Some(sweep) }))
}

fn run_cell(o: &Opened, q: &HashMap<String, String>) -> Result<engine::Cell, Refusal> {
    run_stored(o, q).map(|(c, _)| c)
}

/// [`run_cell`], with the start it ran from.
fn run_stored(o: &Opened, q: &HashMap<String, String>) -> Result<(engine::Cell, Start), Refusal> {
    unchanged(o)?;
    let (sim, start) = stored_cell(o, q)?;
    Ok((engine::cell(&sim, &start).map_err(failed)?, start))
}

/// The cell clicked, as `cell --from FILE --sweep S --at … --json`; it is
/// the page's selected cell from then on ([`crate::Server::selected`]).
async fn cell(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep"], Some(&o))?;
    let shared = state.clone();
    let c = blocking(&state, move || {
        let (c, start) = run_stored(&o, &q)?;
        if let Start::Cell { file, at, sweep: Some(sweep) } = start {
            shared.select(crate::Selected { file, sweep: sweep.name().to_string(), at });
        }
        Ok(c)
    })
    .await?;
    Ok(Json(c.to_json()))
}

/// The cell's periodic orbit solved by Newton's method with its Floquet
/// multipliers: the object of `orbit --from FILE --sweep S --at … --json`.
async fn orbit(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep", "n"], Some(&o))?;
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, start) = stored_cell(&o, &q)?;
        let mut r = engine::OrbitRequest::new(sim);
        r.start = start;
        // The period to solve for (the engine checks its range).
        r.n = q
            .get("n")
            .map(|t| t.parse::<usize>().map_err(|_| bad(format!("n: expected a whole number, got '{}'", short(t)))))
            .transpose()?;
        engine::orbit(&r, &engine::Quiet).map_err(failed)
    })
    .await?;
    Ok(Json(found.to_json()))
}

/// A picture drawn in memory in `format`, as bytes.
fn drawn(
    format: render::Format,
    draw: impl FnOnce(render::Out<'_>) -> Result<(), render::RenderError>,
) -> Result<Vec<u8>, Refusal> {
    let mut bytes = Vec::new();
    draw(render::Out::Bytes(format, &mut bytes))
        .map_err(|e| Refusal(StatusCode::UNPROCESSABLE_ENTITY, format!("{e:#}")))?;
    Ok(bytes)
}

fn png(bytes: Vec<u8>) -> Response {
    ([(header::CONTENT_TYPE, "image/png")], bytes).into_response()
}

async fn portrait(Shared(state): Shared<St>, Params(q): Params) -> Result<Response, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep"], Some(&o))?;
    let bytes = blocking(&state, move || {
        let c = run_cell(&o, &q)?;
        let p = engine::portrait(&c);
        drawn(render::Format::Png, |out| render::portrait(&p, &render::Page::screen(), out))
    })
    .await?;
    Ok(png(bytes))
}

async fn sections(Shared(state): Shared<St>, Params(q): Params) -> Result<Response, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep", "periods"], Some(&o))?;
    let periods = count(&q, "periods", 1000, 1, MAX_PERIODS)?;
    let bytes = blocking(&state, move || {
        let c = run_cell(&o, &q)?;
        let (panels, title) = engine::section_panels(&c, periods).map_err(failed)?;
        drawn(render::Format::Png, |out| render::sections(&panels, &title, &render::Page::screen(), out))
    })
    .await?;
    Ok(png(bytes))
}

async fn attractors(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep", "samples"], Some(&o))?;
    let samples = count(&q, "samples", 64, 1, MAX_SAMPLES)?;
    let threads = state.threads;
    let (work, _guard) = Request::new(state.clone());
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, point) = stored_cell(&o, &q)?;
        let sampling = grid::attractors::Sampling { samples, ..Default::default() };
        let r = engine::AttractorsRequest { sim, point, sampling, threads };
        let res = engine::attractors(&r, &work).map_err(failed)?;
        let picture = drawn(render::Format::Png, |out| engine::draw_basins(&res, &render::Page::screen(), out))?;
        let mut out = res.to_json();
        let colours: Vec<Value> = res.found.iter().map(|a| json!(grid::palette::colour(a.cell.labels[0]))).collect();
        out["colours"] = Value::from(colours);
        out["basins_png"] = Value::from(BASE64_STANDARD.encode(&picture));
        Ok(out)
    })
    .await?;
    Ok(Json(found))
}

/// The time from a run's start to its end, as its observer hears them
/// (the computation alone, not the loading of its scene and file).
#[derive(Default)]
struct Stopwatch(std::sync::Mutex<(Option<std::time::Instant>, f64)>);

impl engine::Observer for Stopwatch {
    fn begin(&self, _work: &engine::Begin<'_>) {
        if let Ok(mut t) = self.0.lock() {
            t.0 = Some(std::time::Instant::now());
        }
    }
    fn finish(&self) {
        if let Ok(mut t) = self.0.lock() {
            t.1 = t.0.map_or(0.0, |t0| t0.elapsed().as_secs_f64());
        }
    }
}

/// Starts per side of the sample a basin map's estimate is timed on.
const PROBE_SIDE: usize = 8;

/// A basin map to propose for the cell: its two axes (`engine::proposed_axes`,
/// 100 × 100 starts) and the estimate of its time on the server's threads,
/// from the cost per start of an 8 × 8 grid over the same axes on one thread.
async fn basins_plan(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep"], Some(&o))?;
    let threads = state.threads;
    let plan = blocking(&state, move || {
        let c = run_cell(&o, &q)?;
        let (x, y) = engine::proposed_axes(&c, BASIN_SIDE);
        let (sim, start) = stored_cell(&o, &q)?;
        let probe = |a: &Axis| Axis::new(a.name.clone(), a.start, a.stop, PROBE_SIDE);
        let r = engine::BasinsRequest {
            sim,
            start,
            x: probe(&x),
            y: probe(&y),
            phase: None,
            threads: 1,
            early: false,
            output: None,
            command: String::new(),
        };
        let watch = Stopwatch::default();
        engine::basins(&r, &watch).map_err(failed)?;
        let per_start = watch.0.lock().map_or(0.0, |t| t.1) / (PROBE_SIDE * PROBE_SIDE) as f64;
        let starts = x.count * y.count;
        let text = |a: &Axis| format!("{}={}:{}:{}", a.name, a.start, a.stop, a.count);
        Ok(json!({
            "x": text(&x),
            "y": text(&y),
            "components": engine::components(&c.system),
            "starts": starts,
            "max_starts": MAX_BASIN_STARTS,
            "threads": threads,
            "seconds_per_start": per_start,
            "seconds": per_start * starts as f64 / threads.max(1) as f64,
        }))
    })
    .await?;
    Ok(Json(plan))
}

/// The basins of the cell's point over the grid `basin_x`, `basin_y`
/// (`COMPONENT=START:STOP:COUNT`), the rest of the state the stored cell's
/// final state, at the forcing phase `phase` (default the scene's τ): the
/// object of `basins --from FILE --at … --json`, with `colours`, `png`
/// (base64) and `seconds`; it stops when its client goes away.
async fn basins(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "sweep", "basin_x", "basin_y", "phase"], Some(&o))?;
    let axis = |name: &str| -> Result<Axis, Refusal> {
        let t = q.get(name).ok_or_else(|| bad(format!("{name}: missing (COMPONENT=START:STOP:COUNT)")))?;
        Axis::parse(t, name).map_err(|e| bad(short(&e.to_string())))
    };
    let (x, y) = (axis("basin_x")?, axis("basin_y")?);
    if x.count.saturating_mul(y.count) > MAX_BASIN_STARTS {
        return Err(bad(format!(
            "basin_y: {} x {} starts, the page computes at most {MAX_BASIN_STARTS}",
            x.count, y.count
        )));
    }
    let phase = match q.get("phase") {
        None => None,
        Some(t) => Some(
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("phase: '{}' is not a number", short(t))))?,
        ),
    };
    let threads = state.threads;
    let (work, _guard) = Request::new(state.clone());
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, start) = stored_cell(&o, &q)?;
        let r = engine::BasinsRequest {
            sim,
            start,
            x,
            y,
            phase,
            threads,
            early: false,
            output: None,
            command: String::new(),
        };
        let t0 = std::time::Instant::now();
        let (map, _) = engine::basins(&r, &work).map_err(failed)?;
        let seconds = t0.elapsed().as_secs_f64();
        let picture = drawn(render::Format::Png, |out| render::basin_map(&map, &render::Page::screen(), out))?;
        let mut out = engine::basins_report(&map).to_json();
        out["colours"] = json!(map.colours());
        out["png"] = Value::from(BASE64_STANDARD.encode(&picture));
        out["seconds"] = json!(seconds);
        Ok(out)
    })
    .await?;
    Ok(Json(found))
}

/// The parameters a zoom sets beside its box (`set`: `NAME=VALUE,NAME=VALUE`;
/// none when absent or blank; an empty item is refused, as the CLI refuses it).
fn set_of(text: Option<&str>) -> Result<Vec<(String, f64)>, Refusal> {
    let parts = text.filter(|t| !t.trim().is_empty()).into_iter().flat_map(|t| t.split(','));
    parts.map(|t| engine::parse_assignment(t, "set").map_err(|e| bad(short(&e)))).collect()
}

/// Cells per side of the box a zoom's estimate is timed on.
const ZOOM_PROBE_SIDE: usize = 3;

/// The estimate of a zoom of the box `x`, `y` (`NAME=START:STOP:COUNT`) of
/// atlas `atlas` with its sweeps (`sweep`, default the parent's), from a zoom
/// of 3 × 3 cells over the same box on one thread: its cost per cell (the
/// computation alone) times the box's cells over the server's threads, plus
/// what the probe spent besides computing (reading the parent, the file).
async fn zoom_plan(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas", "x", "y", "sweep", "set"], None)?;
    let axis = |name: &str| -> Result<Axis, Refusal> {
        let t = q.get(name).ok_or_else(|| bad(format!("{name}: missing (NAME=START:STOP:COUNT)")))?;
        Axis::parse(t, name).map_err(|e| bad(short(&e.to_string())))
    };
    let (x, y) = (axis("x")?, axis("y")?);
    engine::check_zoom_size(&x, &y).map_err(|e| bad(message(&e)))?;
    let sweeps = match q.get("sweep") {
        None => None,
        Some(t) => Some(SweepKind::parse_set(t, "sweep").map_err(|e| bad(e.to_string()))?),
    };
    let set = set_of(q.get("set").map(String::as_str))?;
    let threads = state.threads;
    let plan = blocking(&state, move || {
        unchanged(&o)?;
        let probe = |a: &Axis| Axis::new(a.name.clone(), a.start, a.stop, ZOOM_PROBE_SIDE);
        let mut r = engine::ZoomRequest::new(&o.path, probe(&x), probe(&y));
        r.sweeps = sweeps.clone();
        r.set = set;
        r.threads = 1;
        let watch = Stopwatch::default();
        let t0 = std::time::Instant::now();
        engine::zoom(&r, &watch).map_err(failed)?;
        let (all, computing) = (t0.elapsed().as_secs_f64(), watch.0.lock().map_or(0.0, |t| t.1));
        let sweeps = sweeps.map_or(o.atlas.meta.sweeps.len(), |s| s.len());
        let probed = (ZOOM_PROBE_SIDE * ZOOM_PROBE_SIDE * sweeps) as f64;
        let per_cell = computing / probed;
        let cells = x.count * y.count;
        let overhead = (all - computing).max(0.0);
        Ok(json!({
            "cells": cells,
            "sweeps": sweeps,
            "threads": threads,
            "seconds_per_cell": per_cell,
            "overhead_seconds": overhead,
            "seconds": overhead + per_cell * (cells * sweeps) as f64 / threads.max(1) as f64,
        }))
    })
    .await?;
    Ok(Json(plan))
}

async fn zoom(Shared(state): Shared<St>, body: axum::body::Bytes) -> Result<Json<Value>, Refusal> {
    let body: Value = serde_json::from_slice(&body).map_err(|e| bad(format!("the body is not JSON ({e})")))?;
    let Some(fields) = body.as_object() else {
        return Err(bad(r#"the body: expected an object {"atlas": ID, "x": "NAME=A:B:N", "y": "NAME=C:D:M"}"#));
    };
    if let Some(k) = fields.keys().find(|k| !["atlas", "x", "y", "sweep", "set"].contains(&k.as_str())) {
        return Err(bad(format!("{}: not a field of a zoom (atlas, x, y, sweep, set)", short(k))));
    }
    let id = match fields.get("atlas") {
        None => 0,
        Some(v) => {
            v.as_u64().ok_or_else(|| bad(format!("atlas: expected an atlas id, got {}", short(&v.to_string()))))?
                as usize
        }
    };
    let o = state.atlas(id).ok_or_else(|| not_found(format!("atlas: no atlas {id}")))?;
    unchanged(&o)?;
    let text = |k: &str| match fields.get(k) {
        None => Err(bad(format!("{k}: missing (NAME=START:STOP:COUNT)"))),
        Some(v) => v
            .as_str()
            .ok_or_else(|| bad(format!("{k}: expected a text NAME=START:STOP:COUNT, got {}", short(&v.to_string())))),
    };
    let axis = |k: &str| -> Result<Axis, Refusal> { Axis::parse(text(k)?, k).map_err(|e| bad(short(&e.to_string()))) };
    let (x, y) = (axis("x")?, axis("y")?);
    engine::check_zoom_size(&x, &y).map_err(|e| bad(message(&e)))?;
    let sweeps = match fields.get("sweep") {
        None => None,
        Some(v) => {
            let t = v.as_str().ok_or_else(|| bad("sweep: expected fresh, up, down or both"))?;
            Some(SweepKind::parse_set(t, "sweep").map_err(|e| bad(e.to_string()))?)
        }
    };
    let set = match fields.get("set") {
        None => Vec::new(),
        Some(v) => set_of(Some(v.as_str().ok_or_else(|| bad("set: expected a text NAME=VALUE,NAME=VALUE"))?))?,
    };
    std::fs::create_dir_all(&state.dir).map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?;
    let (job_id, job) = state.start_job();
    let mut r = engine::ZoomRequest::new(&o.path, x, y);
    r.sweeps = sweeps;
    r.set = set;
    r.threads = state.threads;
    r.output = Some(state.dir.join(format!("zoom-{job_id}.h5")));
    r.command = format!("vibroatlas explore: zoom {} --x {} --y {}", o.path.display(), r.x, r.y);
    for (name, value) in &r.set {
        r.command.push_str(&format!(" --set {name}={value}"));
    }
    r.parent_labels = Some(o.labels_crc32);
    let region = r.region();
    let worker = state.clone();
    let queued = job.clone();
    let task = Box::new(move || run_zoom(&worker, &queued, &r, (id, &o), region));
    match state.zooms.submit(task) {
        Ok(()) => Ok(Json(json!({"job": job_id}))),
        Err(why) => {
            let (status, text) = match why {
                NotQueued::Full => (
                    StatusCode::SERVICE_UNAVAILABLE,
                    format!("{ZOOM_QUEUE} zooms are waiting already; ask again once one is done, or cancel one"),
                ),
                NotQueued::Stopped => (StatusCode::SERVICE_UNAVAILABLE, "the explorer is stopping".to_string()),
            };
            job.end(Phase::Failed(text.clone()));
            Err(Refusal(status, text))
        }
    }
}

/// Runs a zoom for job `job` on the zooms' thread; its child, once done, is
/// an atlas of the state. A zoom that panics ends `failed`, naming the panic.
fn run_zoom(state: &State, job: &Job, r: &engine::ZoomRequest, parent: (usize, &Opened), region: String) {
    // Cancelled while it waited its turn, it never starts.
    if engine::Observer::cancelled(job) {
        job.end(Phase::Cancelled);
        return;
    }
    job.start_clock();
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| engine::zoom(r, job)));
    match ran {
        Ok(Ok(done)) => {
            let path = r.output.clone().unwrap_or_default();
            let child = state.add(Opened::new(path, done.atlas, Some((parent.0, parent.1, region))));
            job.end(Phase::Done(child));
        }
        Ok(Err(_)) if engine::Observer::cancelled(job) => job.end(Phase::Cancelled),
        Ok(Err(e)) => job.end(Phase::Failed(message(&e))),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            job.end(Phase::Failed(format!("the zoom failed: {what}")));
        }
    }
}

fn job_id(state: &State, id: &str) -> Result<Arc<Job>, Refusal> {
    id.parse::<usize>().ok().and_then(|i| state.job(i)).ok_or_else(|| not_found(format!("no job {}", short(id))))
}

async fn job(Shared(state): Shared<St>, Path(id): Path<String>) -> Result<Json<Value>, Refusal> {
    let job = job_id(&state, &id)?;
    let phase = phase(&job);
    let (child, error) = match &phase {
        Phase::Done(c) => (Some(*c), None),
        Phase::Failed(e) => (None, Some(e.clone())),
        _ => (None, None),
    };
    Ok(Json(json!({
        "state": phase.name(),
        "progress": share(&job),
        "seconds": job.seconds(),
        "child": child,
        "url": child.map(|c| format!("/?atlas={c}")),
        "error": error,
    })))
}

async fn cancel(Shared(state): Shared<St>, Path(id): Path<String>) -> Result<Json<Value>, Refusal> {
    let job = job_id(&state, &id)?;
    let was_running = stop(&job);
    Ok(Json(json!({"cancelled": was_running, "state": phase(&job).name()})))
}

async fn figure(Shared(state): Shared<St>, Params(q): Params) -> Result<Response, Refusal> {
    let (id, o) = opened(&state, &q)?;
    only(&q, &["atlas", "view", "mass", "format", "size", "curves"], None)?;
    let (show, mass) = (show(&o, &q)?, mass(&o, &q)?);
    let format = q.get("format").map_or("png", String::as_str);
    let format =
        render::Format::parse(format).ok_or_else(|| bad(format!("format: {}", render::Format::expected(format))))?;
    let size = q.get("size").filter(|s| *s != "screen").cloned();
    let page = render::Page::of(size.as_deref(), None, None).map_err(|e| bad(format!("size: screen, or {e}")))?;
    let curves = if switch(&q, "curves")? { overlays(&state, &o) } else { Vec::new() };
    let name = format!("atlas{id}-{}.{}", q.get("view").map_or("map", String::as_str).replace(':', "-"), format.name());
    let bytes = blocking(&state, move || {
        drawn(format, |out| match show {
            Show::Map(view) => render::map(&o.atlas, view, mass, &curves, &page, out),
            Show::Scalar(sweep, quantity) => render::scalar_map(&o.atlas, sweep, quantity, 0, &page, out),
            Show::Difference(quantity) => render::difference_map(&o.atlas, quantity, 0, &page, out),
        })
    })
    .await?;
    Ok((
        [(header::CONTENT_TYPE, format.media_type().to_string()), (header::CONTENT_DISPOSITION, attachment(&name))],
        bytes,
    )
        .into_response())
}

/// The bifurcation curves stored in the explored file, over atlas `o`'s plane.
fn overlays(state: &State, o: &Opened) -> Vec<render::Overlay> {
    state
        .curves()
        .iter()
        .filter_map(|c| {
            let marks = c.codim2.iter().map(|m| (m.1, m.2));
            render::Overlay::on(&o.atlas.meta.plane, &c.kind, &c.free, &c.points, marks)
        })
        .collect()
}

async fn curves(Shared(state): Shared<St>, Params(q): Params) -> Result<Json<Value>, Refusal> {
    let (_, o) = opened(&state, &q)?;
    only(&q, &["atlas"], None)?;
    // The curves are the explored file's: it must still be the file read.
    unchanged(&state.atlas(0).unwrap_or_else(|| o.clone()))?;
    let list: Vec<Value> = blocking(&state.clone(), move || Ok(overlays(&state, &o)))
        .await?
        .into_iter()
        .map(|c| {
            let (colour, width, dash) = render::curve_style(&c.kind);
            json!({"kind": c.kind, "colour": colour, "width_pt": width, "dash_pt": [dash.0, dash.1], "points": c.points, "marks": c.marks})
        })
        .collect();
    Ok(Json(json!({"curves": list})))
}

async fn file(Shared(state): Shared<St>, Path(id): Path<String>) -> Result<Response, Refusal> {
    let o = id
        .parse::<usize>()
        .ok()
        .and_then(|i| state.atlas(i))
        .ok_or_else(|| not_found(format!("no atlas {}", short(&id))))?;
    unchanged(&o)?;
    let name = match &o.parent {
        Some((_, region)) => format!("zoom {region}.h5").replace([' ', '='], "_").replace(':', "-"),
        None => o.path.file_name().map_or("atlas.h5".into(), |n| n.to_string_lossy().to_string()),
    };
    let bytes = blocking(&state, move || {
        let bytes = std::fs::read(&o.path).map_err(|e| not_found(format!("{}: {e}", o.path.display())))?;
        // A file edited in place keeps its identity: its bytes tell.
        if o.bytes_crc32 != Some(crc32fast::hash(&bytes)) {
            return Err(changed(&o));
        }
        Ok(bytes)
    })
    .await?;
    Ok((
        [(header::CONTENT_TYPE, "application/x-hdf5".to_string()), (header::CONTENT_DISPOSITION, attachment(&name))],
        bytes,
    )
        .into_response())
}

/// The `Content-Disposition` of a download named `name` (a file's name, any
/// characters): the name in plain ASCII (every other character `_`), and
/// whole in RFC 6266's `filename*`, percent-encoded UTF-8.
fn attachment(name: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "._-+".contains(c);
    let plain: String = name.chars().map(|c| if safe(c) { c } else { '_' }).collect();
    let encoded: String = name
        .bytes()
        .map(|b| if safe(char::from(b)) { char::from(b).to_string() } else { format!("%{b:02X}") })
        .collect();
    format!("attachment; filename=\"{plain}\"; filename*=UTF-8''{encoded}")
}
