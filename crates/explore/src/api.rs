//! The explorer's HTTP API (docs/explore.md): its routes, each reading its
//! query as a type of `wire.rs` (`asked`), checking what depends on the
//! atlas, calling the libraries (engine, render, store) and answering a type
//! of `wire.rs` as JSON or, for a view's colours and the pictures, bytes. A
//! bad request is a 4xx with `{"error": "…"}` naming what is wrong, never a
//! crash of the server.

use crate::guard::{self, brief, short};
use crate::state::{phase, share, stop, Job, NotQueued, Opened, Phase, Request, State, BUSY_LIMIT, ZOOM_QUEUE};
use crate::wire::*;
use axum::extract::{Path, State as Shared};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use base64::prelude::{Engine as _, BASE64_STANDARD};
use engine::{CellRecord, SceneSource, Sim, Start};
use grid::{Axis, SweepKind};
use render::{Show, View};
use scene::Named;
use serde_json::Value;
use std::sync::Arc;

type St = Arc<State>;

/// Most starts of a basin map the page computes (500 × 500).
const MAX_BASIN_STARTS: usize = 250_000;
/// Starts per side the page proposes for a basin map.
const BASIN_SIDE: usize = 100;

/// An engine error as one line (each cause of its chain, a refusal in the
/// API's words: the request's fields).
fn message(e: &engine::Error) -> String {
    engine::in_words(e, &engine::Fields)
}

fn failed(e: engine::Error) -> Refusal {
    Refusal(StatusCode::UNPROCESSABLE_ENTITY, message(&e))
}

/// The basins' words: their grid's axes are the query's `basin_x` and
/// `basin_y` (the request's `x` and `y`).
struct BasinWords;

impl engine::Words for BasinWords {
    fn option(&self, o: engine::Opt) -> String {
        match o {
            engine::Opt::X => "basin_x".into(),
            engine::Opt::Y => "basin_y".into(),
            o => o.name().into(),
        }
    }
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

/// A route's request: its atlas, its query read as a `T`, and, where the
/// route takes a cell of the plane, the plane's two parameters as given.
struct Asked<T> {
    id: usize,
    o: Arc<Opened>,
    q: T,
    at: Vec<(String, String)>,
}

/// Reads a request: the atlas of its `atlas` parameter (0, the file given,
/// by default; a 409 where its file was replaced or changed since it was
/// read), then the rest as a `T`; with `cell`, the atlas's two
/// parameters are keys of the query as well (a cell's `omega=…&delta=…`).
fn asked<T: for<'de> serde::Deserialize<'de>>(state: &State, p: &Params, cell: bool) -> Result<Asked<T>, Refusal> {
    let id = match p.get("atlas") {
        None => 0,
        Some(t) => t.parse::<usize>().map_err(|_| bad(format!("atlas: expected an atlas id, got '{}'", short(t))))?,
    };
    let o = state.atlas(id).ok_or_else(|| not_found(format!("atlas: no atlas {id}")))?;
    // Every route answers for the file as read, while it is that file.
    unchanged(&o)?;
    let plane = &o.atlas.meta.plane;
    let axes = if cell { vec![plane.x.name.as_str(), plane.y.name.as_str()] } else { Vec::new() };
    let (q, at) = p.read::<T>(&axes)?;
    Ok(Asked { id, o, q, at })
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

/// The labelled mass named `name` (the first by default).
fn mass(o: &Opened, name: Option<&str>) -> Result<usize, Refusal> {
    let masses = &o.atlas.meta.masses;
    match name {
        None => Ok(0),
        Some(m) => masses
            .iter()
            .position(|n| n == m)
            .ok_or_else(|| bad(format!("mass: no labelled mass {}; the atlas labels {}", short(m), masses.join(", ")))),
    }
}

/// The sweep named `name` (the file's first by default).
fn sweep(o: &Opened, name: Option<&str>) -> Result<SweepKind, Refusal> {
    let sweeps = &o.atlas.meta.sweeps;
    match name {
        None => Ok(sweeps[0]),
        Some(s) => SweepKind::parse(s).filter(|k| sweeps.contains(k)).ok_or_else(|| {
            let have: Vec<&str> = sweeps.iter().map(|k| k.name()).collect();
            bad(format!("sweep: '{}' is not a sweep of the atlas ({})", short(s), have.join(", ")))
        }),
    }
}

/// The views of an atlas, by name ([`Show::all`]).
fn views(o: &Opened) -> Vec<String> {
    let m = &o.atlas.meta;
    Show::all(m).into_iter().map(|v| v.name(m)).collect()
}

/// The view named `name` ([`Show::named`]: a sweep, `hysteresis`,
/// `NAME:SWEEP` of a number per cell, `NAME:hysteresis` of a quantity's up
/// less down), the file's first sweep by default.
fn show(o: &Opened, name: Option<&str>) -> Result<Show, Refusal> {
    let m = &o.atlas.meta;
    let Some(name) = name else { return Ok(Show::Map(View::Sweep(m.sweeps[0]))) };
    if let Some(show) = Show::named(m, name) {
        return Ok(show);
    }
    // Why a number's view is none, where the view's parts say (as render says it).
    let why = match name.rsplit_once(':').map(|(what, sweep)| Show::of(m, what, View::parse(sweep))) {
        Some(Err(render::NoSuchView::Difference(number))) => {
            format!(": {} has no up less down (the quantities of the motion have one)", number.name(m))
        }
        Some(Err(render::NoSuchView::Sweep(kind))) => format!(": the atlas has no {} sweep", kind.name()),
        Some(Err(render::NoSuchView::Hysteresis)) => ": hysteresis needs up and down sweeps".to_string(),
        _ => String::new(),
    };
    Err(bad(format!("view: '{}' is not a view of the atlas{why} ({})", short(name), views(o).join(", "))))
}

fn axis_answer<'a>(a: &'a Axis, o: &'a Opened) -> AxisAnswer<'a> {
    let m = &o.atlas.meta;
    let symbol = m.symbol(&a.name);
    AxisAnswer {
        name: &a.name,
        symbol_runs: render::subscript_runs(&symbol).into_iter().map(|(t, sub)| (t.to_string(), sub)).collect(),
        symbol,
        long_name: m.long_name(&a.name),
        start: a.start,
        stop: a.stop,
        count: a.count,
        values: a.values(),
    }
}

async fn atlas(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { id, o, q: Nothing {}, .. } = asked(&state, &p, false)?;
    let m = &o.atlas.meta;
    let labels = m
        .sweeps
        .iter()
        .map(|&s| {
            let per_mass = m.masses.iter().enumerate().map(|(mi, name)| {
                let rows = o.atlas.legend(s, mi).into_iter();
                let rows =
                    rows.map(|(l, n)| LabelRow { label: l.to_string(), count: n, colour: grid::palette::colour(l) });
                (name.as_str(), rows.collect())
            });
            (s.name(), per_mass.collect())
        })
        .collect();
    answer(&AtlasAnswer {
        id,
        file: o.path.display().to_string(),
        parent: o.parent.as_ref().map(|(id, region)| Parent { id: *id, region }),
        boxes: &o.boxes,
        scene: &m.scene_name,
        preset: m.preset.name(),
        x: axis_answer(&m.plane.x, &o),
        y: axis_answer(&m.plane.y, &o),
        along: m.plane.along.name(),
        sweeps: m.sweeps.iter().map(|s| s.name()).collect(),
        masses: &m.masses,
        views: views(&o),
        labels,
        settings: m.overrides.iter().map(|(k, v)| Setting { name: k, symbol: m.symbol(k), value: *v }).collect(),
    })
}

async fn map(Shared(state): Shared<St>, p: Params) -> Result<Response, Refusal> {
    let Asked { o, q, .. } = asked::<ViewQuery>(&state, &p, false)?;
    let (show, mass) = (show(&o, q.view.as_deref())?, mass(&o, q.mass.as_deref())?);
    let layer =
        blocking(&state, move || render::layer(&o.atlas, show, mass, &[]).map_err(|e| bad(e.to_string()))).await?;
    let mut bytes = layer.above;
    bytes.extend(layer.below);
    Ok(([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response())
}

async fn legend(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, .. } = asked::<LegendQuery>(&state, &p, false)?;
    let (show, mass) = (show(&o, q.view.as_deref())?, mass(&o, q.mass.as_deref())?);
    let curves = if q.curves.0 { overlays(&state, &o) } else { Vec::new() };
    let layer =
        blocking(&state, move || render::layer(&o.atlas, show, mass, &curves).map_err(|e| bad(e.to_string()))).await?;
    let legend =
        layer.legend.into_iter().map(|k| KeyRow { swatch: k.swatch, colours: k.colours, text: k.text }).collect();
    let scale = layer.scale.map(|(title, lo, hi, colours)| ScaleAnswer { title, lo, hi, colours });
    answer(&LegendAnswer { legend, scale })
}

/// The cell `(iy, ix)` of the `ix`, `iy` parameters.
fn cell_index(o: &Opened, q: &AtQuery) -> Result<(usize, usize), Refusal> {
    let p = &o.atlas.meta.plane;
    let index = |name: &str, t: Option<&str>, count: usize| -> Result<usize, Refusal> {
        let t = t.ok_or_else(|| bad(format!("{name}: missing")))?;
        t.parse::<usize>()
            .ok()
            .filter(|&i| i < count)
            .ok_or_else(|| bad(format!("{name}: expected 0 to {}, got '{}'", count - 1, short(t))))
    };
    Ok((index("iy", q.iy.as_deref(), p.y.count)?, index("ix", q.ix.as_deref(), p.x.count)?))
}

async fn at(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, .. } = asked::<AtQuery>(&state, &p, false)?;
    let (iy, ix) = cell_index(&o, &q)?;
    let m = &o.atlas.meta;
    let i = iy * m.plane.x.count + ix;
    let sweeps =
        o.atlas.maps.iter().map(|map| (map.sweep.name(), map.cells[i].as_ref().map(|c| CellRecord::in_atlas(m, c))));
    answer(&AtAnswer { ix, iy, parameters: m.plane.params(iy, ix).into_iter().collect(), sweeps: sweeps.collect() })
}

/// The stored cell of the request: its sweep and a value of each axis (the
/// plane's own parameter names), as `cell --from FILE --sweep S --at …`.
fn stored_cell(o: &Opened, sweep_name: Option<&str>, given: &[(String, String)]) -> Result<(Sim, Start), Refusal> {
    let sweep = sweep(o, sweep_name)?;
    let p = &o.atlas.meta.plane;
    let mut at = Vec::new();
    for a in [&p.x, &p.y] {
        let Some((_, t)) = given.iter().find(|(k, _)| *k == a.name) else {
            return Err(bad(format!(
                "{}: missing (give the cell by the plane's parameters {} and {})",
                a.name, p.x.name, p.y.name
            )));
        };
        let v = t
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("{}: '{}' is not a number", a.name, short(t))))?;
        a.nearest(v).map_err(|e| bad(format!("{}: {e}", a.name)))?;
        at.push((a.name.clone(), v));
    }
    let sim = Sim::new(SceneSource::Stored(o.path.clone()));
    Ok((sim, Start::Cell { file: o.path.clone(), at, sweep: Some(sweep) }))
}

/// The stored cell run, as `cell --from FILE --sweep S --at …`, with the
/// start it ran from.
fn run_stored(o: &Opened, sweep: Option<&str>, at: &[(String, String)]) -> Result<(engine::Cell, Start), Refusal> {
    unchanged(o)?;
    let (sim, start) = stored_cell(o, sweep, at)?;
    Ok((engine::cell(&sim, &start).map_err(failed)?, start))
}

/// The cell clicked, as `cell --from FILE --sweep S --at … --json`; it is
/// the page's selected cell from then on ([`crate::Server::selected`]).
async fn cell(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, at, .. } = asked::<CellQuery>(&state, &p, true)?;
    let shared = state.clone();
    let c = blocking(&state, move || {
        let (c, start) = run_stored(&o, q.sweep.as_deref(), &at)?;
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
async fn orbit(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, at, .. } = asked::<OrbitQuery>(&state, &p, true)?;
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, start) = stored_cell(&o, q.sweep.as_deref(), &at)?;
        let mut r = engine::OrbitRequest::new(sim);
        r.start = start;
        // The period to solve for (the engine checks its range).
        r.n = q.n.map(|n| n.0);
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

async fn portrait(Shared(state): Shared<St>, p: Params) -> Result<Response, Refusal> {
    let Asked { o, q, at, .. } = asked::<CellQuery>(&state, &p, true)?;
    let bytes = blocking(&state, move || {
        let (c, _) = run_stored(&o, q.sweep.as_deref(), &at)?;
        let p = engine::portrait(&c);
        drawn(render::Format::Png, |out| render::portrait(&p, &render::Page::screen(), out))
    })
    .await?;
    Ok(png(bytes))
}

async fn sections(Shared(state): Shared<St>, p: Params) -> Result<Response, Refusal> {
    let Asked { o, q, at, .. } = asked::<SectionsQuery>(&state, &p, true)?;
    let periods = q.periods.map_or(1000, |n| n.0);
    let bytes = blocking(&state, move || {
        let (c, _) = run_stored(&o, q.sweep.as_deref(), &at)?;
        let (panels, title) = engine::section_panels(&c, periods).map_err(failed)?;
        drawn(render::Format::Png, |out| render::sections(&panels, &title, &render::Page::screen(), out))
    })
    .await?;
    Ok(png(bytes))
}

async fn attractors(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, at, .. } = asked::<AttractorsQuery>(&state, &p, true)?;
    let samples = q.samples.map_or(64, |n| n.0);
    let threads = state.threads;
    let (work, _guard) = Request::new(state.clone());
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, point) = stored_cell(&o, q.sweep.as_deref(), &at)?;
        let sampling = grid::attractors::Sampling { samples, ..Default::default() };
        let r = engine::AttractorsRequest { sim, point, sampling, threads };
        let res = engine::attractors(&r, &work).map_err(failed)?;
        let picture = drawn(render::Format::Png, |out| engine::draw_basins(&res, &render::Page::screen(), out))?;
        Ok(AttractorsAnswer {
            found: res.to_json(),
            colours: res.found.iter().map(|a| grid::palette::colour(a.cell.labels[0])).collect(),
            basins_png: BASE64_STANDARD.encode(&picture),
        })
    })
    .await?;
    answer(&found)
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
async fn basins_plan(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, at, .. } = asked::<CellQuery>(&state, &p, true)?;
    let threads = state.threads;
    let plan = blocking(&state, move || {
        let (c, start) = run_stored(&o, q.sweep.as_deref(), &at)?;
        let (x, y) = engine::proposed_axes(&c, BASIN_SIDE);
        let sim = Sim::new(SceneSource::Stored(o.path.clone()));
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
        Ok(BasinsPlan {
            x: text(&x),
            y: text(&y),
            components: engine::components(&c.system),
            starts,
            max_starts: MAX_BASIN_STARTS,
            threads,
            seconds_per_start: per_start,
            seconds: per_start * starts as f64 / threads.max(1) as f64,
        })
    })
    .await?;
    answer(&plan)
}

/// The basins of the cell's point over the grid `basin_x`, `basin_y`
/// (`COMPONENT=START:STOP:COUNT`), the rest of the state the stored cell's
/// final state, at the forcing phase `phase` (default the scene's τ): the
/// object of `basins --from FILE --at … --json`, with `colours`, `png`
/// (base64) and `seconds`; it stops when its client goes away.
async fn basins(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, at, .. } = asked::<BasinsQuery>(&state, &p, true)?;
    let axis = |name: &str, t: Option<&str>| -> Result<Axis, Refusal> {
        let t = t.ok_or_else(|| bad(format!("{name}: missing (COMPONENT=START:STOP:COUNT)")))?;
        Axis::parse(t, name).map_err(|e| bad(brief(&e.to_string())))
    };
    let (x, y) = (axis("basin_x", q.basin_x.as_deref())?, axis("basin_y", q.basin_y.as_deref())?);
    if x.count.saturating_mul(y.count) > MAX_BASIN_STARTS {
        return Err(bad(format!(
            "basin_y: {} x {} starts, the page computes at most {MAX_BASIN_STARTS}",
            x.count, y.count
        )));
    }
    let phase = q.phase.map(|p| p.0);
    let threads = state.threads;
    let (work, _guard) = Request::new(state.clone());
    let found = blocking(&state, move || {
        unchanged(&o)?;
        let (sim, start) = stored_cell(&o, q.sweep.as_deref(), &at)?;
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
        let words = |e| Refusal(StatusCode::UNPROCESSABLE_ENTITY, engine::in_words(&e, &BasinWords));
        let (map, _) = engine::basins(&r, &work).map_err(words)?;
        let seconds = t0.elapsed().as_secs_f64();
        let picture = drawn(render::Format::Png, |out| render::basin_map(&map, &render::Page::screen(), out))?;
        Ok(BasinsAnswer {
            found: engine::basins_report(&map).to_json(),
            colours: map.colours(),
            png: BASE64_STANDARD.encode(&picture),
            seconds,
        })
    })
    .await?;
    answer(&found)
}

/// A zoom's box and its options, as `zoom` takes them: its axes `x`, `y`
/// (`NAME=START:STOP:COUNT`, at most [`engine::check_zoom_size`]'s cells),
/// its sweeps (`sweep`, default the parent's) and the parameters it sets
/// beside the box (`set`: `NAME=VALUE,NAME=VALUE`; none when absent or blank;
/// an empty item is refused, as the CLI refuses it).
type ZoomBox = (Axis, Axis, Option<Vec<SweepKind>>, Vec<(String, f64)>);

fn parsed_box(
    x: &Option<String>,
    y: &Option<String>,
    sweep: &Option<String>,
    set: &Option<String>,
) -> Result<ZoomBox, Refusal> {
    let axis = |name: &str, t: &Option<String>| -> Result<Axis, Refusal> {
        let t = t.as_deref().ok_or_else(|| bad(format!("{name}: missing (NAME=START:STOP:COUNT)")))?;
        Axis::parse(t, name).map_err(|e| bad(brief(&e.to_string())))
    };
    let (x, y) = (axis("x", x)?, axis("y", y)?);
    engine::check_zoom_size(&x, &y).map_err(|e| bad(message(&e)))?;
    let sweeps =
        sweep.as_deref().map(|t| SweepKind::parse_set(t, "sweep").map_err(|e| bad(e.to_string()))).transpose()?;
    let parts = set.as_deref().filter(|t| !t.trim().is_empty()).into_iter().flat_map(|t| t.split(','));
    let set =
        parts.map(|t| engine::parse_assignment(t, "set").map_err(|e| bad(brief(&e)))).collect::<Result<_, _>>()?;
    Ok((x, y, sweeps, set))
}

/// Cells per side of the box a zoom's estimate is timed on.
const ZOOM_PROBE_SIDE: usize = 3;

/// The estimate of a zoom of the box `x`, `y` (`NAME=START:STOP:COUNT`) of
/// atlas `atlas` with its sweeps (`sweep`, default the parent's), from a zoom
/// of 3 × 3 cells over the same box on one thread: its cost per cell (the
/// computation alone) times the box's cells over the server's threads, plus
/// what the probe spent besides computing (reading the parent, the file).
async fn zoom_plan(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q, .. } = asked::<ZoomPlanQuery>(&state, &p, false)?;
    let (x, y, sweeps, set) = parsed_box(&q.x, &q.y, &q.sweep, &q.set)?;
    let threads = state.threads;
    let plan = blocking(&state, move || {
        unchanged(&o)?;
        // A side of one value stays one (a line of the plane).
        let probe = |a: &Axis| Axis::new(a.name.clone(), a.start, a.stop, ZOOM_PROBE_SIDE.min(a.count));
        let (px, py) = (probe(&x), probe(&y));
        let probed = (px.count * py.count) as f64;
        let mut r = engine::ZoomRequest::new(&o.path, px, py);
        r.sweeps = sweeps.clone();
        r.set = set;
        r.threads = 1;
        let watch = Stopwatch::default();
        let t0 = std::time::Instant::now();
        engine::zoom(&r, &watch).map_err(failed)?;
        let (all, computing) = (t0.elapsed().as_secs_f64(), watch.0.lock().map_or(0.0, |t| t.1));
        let sweeps = sweeps.map_or(o.atlas.meta.sweeps.len(), |s| s.len());
        let per_cell = computing / (probed * sweeps as f64);
        let cells = x.count * y.count;
        let overhead = (all - computing).max(0.0);
        Ok(ZoomPlan {
            cells,
            sweeps,
            threads,
            seconds_per_cell: per_cell,
            overhead_seconds: overhead,
            seconds: overhead + per_cell * (cells * sweeps) as f64 / threads.max(1) as f64,
        })
    })
    .await?;
    answer(&plan)
}

async fn zoom(Shared(state): Shared<St>, p: Params, body: axum::body::Bytes) -> Result<Json<Value>, Refusal> {
    p.none()?;
    let body = ZoomBody::read(&body)?;
    let id = body.atlas.map_or(0, |id| id as usize);
    let o = state.atlas(id).ok_or_else(|| not_found(format!("atlas: no atlas {id}")))?;
    unchanged(&o)?;
    let (x, y, sweeps, set) = parsed_box(&body.x, &body.y, &body.sweep, &body.set)?;
    // A box outside the parent's plane, a sweep it lacks and a parameter set
    // beside the box are refused now, not by the job later.
    engine::zoom_box(&o.atlas.meta, &o.path, (&x, &y), sweeps.as_deref()).map_err(|e| bad(message(&e)))?;
    engine::zoom_setup(&o.atlas.meta, &o.path, &set).map_err(|e| bad(message(&e)))?;
    let dir = state.zoom_dir().map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?;
    let (job_id, job) = state.start_job();
    let mut r = engine::ZoomRequest::new(&o.path, x, y);
    r.sweeps = sweeps;
    r.set = set;
    r.threads = state.threads;
    r.output = Some(dir.join(format!("zoom-{job_id}.h5")));
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
        Ok(()) => answer(&Started { job: job_id }),
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

async fn job(Shared(state): Shared<St>, Path(id): Path<String>, p: Params) -> Result<Json<Value>, Refusal> {
    p.none()?;
    let job = job_id(&state, &id)?;
    let phase = phase(&job);
    let (child, error) = match &phase {
        Phase::Done(c) => (Some(*c), None),
        Phase::Failed(e) => (None, Some(e.clone())),
        _ => (None, None),
    };
    answer(&JobAnswer {
        state: phase.name(),
        progress: share(&job),
        seconds: job.seconds(),
        child,
        url: child.map(|c| format!("/?atlas={c}")),
        error,
    })
}

async fn cancel(Shared(state): Shared<St>, Path(id): Path<String>, p: Params) -> Result<Json<Value>, Refusal> {
    p.none()?;
    let job = job_id(&state, &id)?;
    let was_running = stop(&job);
    answer(&Cancelled { cancelled: was_running, state: phase(&job).name() })
}

async fn figure(Shared(state): Shared<St>, p: Params) -> Result<Response, Refusal> {
    let Asked { id, o, q, .. } = asked::<FigureQuery>(&state, &p, false)?;
    let (show, mass) = (show(&o, q.view.as_deref())?, mass(&o, q.mass.as_deref())?);
    let format = q.format.map_or(render::Format::Png, |f| f.0);
    let size = q.size.as_deref().filter(|s| *s != "screen");
    let page = render::Page::of(size, None, None).map_err(|e| bad(format!("size: {e} (or screen)")))?;
    let curves = if q.curves.0 { overlays(&state, &o) } else { Vec::new() };
    let name = format!("atlas{id}-{}.{}", q.view.as_deref().unwrap_or("map").replace(':', "-"), format.name());
    let bytes =
        blocking(&state, move || drawn(format, |out| render::draw(&o.atlas, show, mass, &curves, 0, &page, out)))
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

async fn curves(Shared(state): Shared<St>, p: Params) -> Result<Json<Value>, Refusal> {
    let Asked { o, q: Nothing {}, .. } = asked(&state, &p, false)?;
    // The curves are the explored file's: it must still be the file read.
    unchanged(&state.atlas(0).unwrap_or_else(|| o.clone()))?;
    let overlays = blocking(&state.clone(), move || Ok(overlays(&state, &o))).await?;
    let curves = overlays
        .into_iter()
        .map(|c| {
            let (colour, width_pt, dash) = render::curve_style(&c.kind);
            CurveAnswer { colour, width_pt, dash_pt: [dash.0, dash.1], kind: c.kind, points: c.points, marks: c.marks }
        })
        .collect();
    answer(&CurvesAnswer { curves })
}

async fn file(Shared(state): Shared<St>, Path(id): Path<String>, p: Params) -> Result<Response, Refusal> {
    p.none()?;
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
