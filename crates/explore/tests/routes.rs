//! The explorer's HTTP API in process, without a browser: a served atlas
//! whose mass and stop are named in markup, asked over a plain TCP socket as
//! any client (a page of another site, a rebound host name, a script) would.
//! Each answer's status, its JSON error and its security headers are checked.

use engine::{AtlasRequest, SceneSource, Sim};
use grid::{Axis, SweepKind};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// A mass and a stop named in markup that would run script if a page put it
/// into `innerHTML`.
const MARKUP_MASS: &str = "<img src=x onerror=document.title=this.alt alt=XSS>";
const MARKUP_STOP: &str = "<b id=injected>A";

/// The scene of tests/data/markup-names.toml, whose names are those above.
fn scene() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/markup-names.toml");
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(MARKUP_MASS) && text.contains(MARKUP_STOP));
    text
}

/// A 6 × 4 up-sweep atlas of the markup scene, written once.
fn atlas_file() -> &'static PathBuf {
    static FILE: OnceLock<PathBuf> = OnceLock::new();
    FILE.get_or_init(|| {
        // Under the target folder (cargo's scratch for integration tests), not
        // /tmp; emptied first, so that runs leave one copy.
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("explore-routes");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("markup.h5");
        let sim = Sim::new(SceneSource::Text(scene()));
        let x = Axis::parse("omega=1.5:3:6", "--x").unwrap();
        let y = Axis::parse("sigma=-0.5:0:4", "--y").unwrap();
        let mut r = AtlasRequest::new(sim, x, y, vec![SweepKind::Up]);
        r.threads = 1;
        r.output = Some(path.clone());
        engine::atlas(&r, &engine::Quiet).unwrap();
        path
    })
}

fn serve() -> explore::Server {
    let r = explore::ExploreRequest { file: atlas_file().clone(), port: 0, threads: 1 };
    explore::serve(&r).unwrap()
}

fn port(server: &explore::Server) -> u16 {
    server.url().trim_end_matches('/').rsplit(':').next().unwrap().parse().unwrap()
}

/// An answer: status, headers (names in lower case), body.
struct Answer {
    status: u16,
    headers: Vec<(String, String)>,
    body: Vec<u8>,
}

impl Answer {
    fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// The `error` of a JSON error answer (the test fails on any other body).
    fn error(&self) -> String {
        assert_eq!(self.header("content-type"), Some("application/json"), "status {}", self.status);
        let v: serde_json::Value = serde_json::from_slice(&self.body).unwrap();
        v["error"].as_str().unwrap_or_else(|| panic!("no error in {v}")).to_string()
    }

    fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap()
    }
}

/// Sends one HTTP/1.1 request (`Connection: close`) with the `headers` given
/// (a `Host` among them or none) and reads the whole answer.
fn send(port: u16, method: &str, target: &str, headers: &[(&str, &str)], body: &[u8]) -> Answer {
    let mut head = format!("{method} {target} HTTP/1.1\r\nConnection: close\r\nContent-Length: {}\r\n", body.len());
    for (k, v) in headers {
        head.push_str(&format!("{k}: {v}\r\n"));
    }
    head.push_str("\r\n");
    send_bytes(port, &[head.as_bytes(), body].concat())
}

/// Sends `bytes` as they are and reads the whole answer.
fn send_bytes(port: u16, bytes: &[u8]) -> Answer {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    s.write_all(bytes).unwrap();
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).unwrap();
    let split = raw.windows(4).position(|w| w == b"\r\n\r\n").expect("an HTTP answer");
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let mut lines = head.lines();
    let status = lines.next().unwrap().split(' ').nth(1).unwrap().parse().unwrap();
    let headers = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_string()))
        .collect::<Vec<_>>();
    let mut body = raw[split + 4..].to_vec();
    if headers.iter().any(|(k, v)| k == "transfer-encoding" && v == "chunked") {
        body = unchunk(&body);
    }
    Answer { status, headers, body }
}

fn unchunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let end = b.windows(2).position(|w| w == b"\r\n").unwrap();
        let n = usize::from_str_radix(std::str::from_utf8(&b[..end]).unwrap().trim(), 16).unwrap();
        if n == 0 {
            return out;
        }
        out.extend_from_slice(&b[end + 2..end + 2 + n]);
        b = &b[end + 4 + n..];
    }
}

fn get(port: u16, target: &str) -> Answer {
    let host = format!("127.0.0.1:{port}");
    send(port, "GET", target, &[("Host", &host)], b"")
}

fn post_zoom(port: u16, extra: &[(&str, &str)]) -> Answer {
    let host = format!("127.0.0.1:{port}");
    let mut headers = vec![("Host", host.as_str())];
    headers.extend_from_slice(extra);
    send(port, "POST", "/api/zoom", &headers, br#"{"atlas": 0, "x": "omega=1.5:3:11", "y": "sigma=-0.5:0:7"}"#)
}

#[test]
fn every_answer_carries_a_strict_policy() {
    let server = serve();
    let p = port(&server);
    for target in ["/", "/explore.js", "/api/atlas", "/api/no-such-route"] {
        let a = get(p, target);
        let csp = a.header("content-security-policy").unwrap_or_default();
        assert!(csp.contains("script-src 'self'") && csp.contains("default-src 'none'"), "{target}: {csp}");
        assert!(!csp.contains("unsafe-inline") && !csp.contains("unsafe-eval"), "{target}: {csp}");
        assert_eq!(a.header("x-content-type-options"), Some("nosniff"), "{target}");
    }
    // The page itself has no inline script for the policy to block.
    let page = String::from_utf8(get(p, "/").body).unwrap();
    assert!(!page.contains("<script>") && !page.contains("onclick=") && !page.contains("style="), "{page}");
}

#[test]
fn names_in_markup_come_back_as_json_strings() {
    let server = serve();
    let a = get(port(&server), "/api/atlas");
    assert_eq!(a.status, 200);
    let v = a.json();
    assert_eq!(v["masses"][0], MARKUP_MASS);
    let at = get(port(&server), "/api/at?ix=2&iy=1").json();
    assert!(at["sweeps"]["up"]["labels"][MARKUP_MASS].is_string(), "{at}");
    // The page puts every text from the server into the document as text:
    // no assignment of markup is left in its script.
    let script = String::from_utf8(get(port(&server), "/explore.js").body).unwrap();
    for sink in ["innerHTML", "outerHTML", "insertAdjacentHTML", "document.write", "eval("] {
        assert!(!script.contains(sink), "explore.js uses {sink}");
    }
}

/// The page's cell is one record: every key `/api/at` gives of a stored
/// cell (class, labels, stability, reason, final state, section points,
/// quantities) is the value the cell run again from its stored start gives
/// in `/api/cell`, the JSON of `cell --json`.
#[test]
fn a_stored_cell_is_the_record_its_run_gives() {
    let server = serve();
    let p = port(&server);
    for (ix, iy) in [(0, 0), (2, 1), (5, 3)] {
        let at = get(p, &format!("/api/at?ix={ix}&iy={iy}")).json();
        let (omega, sigma) = (&at["parameters"]["omega"], &at["parameters"]["sigma"]);
        let cell = get(p, &format!("/api/cell?sweep=up&omega={omega}&sigma={sigma}")).json();
        let stored = at["sweeps"]["up"].as_object().unwrap();
        for key in ["class", "labels", "symmetry", "lyapunov", "max_multiplier", "reason", "final_state", "quantities"]
        {
            assert!(stored.contains_key(key), "{key} missing from {at}");
        }
        for (key, value) in stored {
            assert_eq!(&cell[key], value, "{key} of ({ix}, {iy})");
        }
    }
}

/// Requests the HTTP layer would refuse on its own, with an empty body, are
/// answered as every error is: JSON naming the fault, with the policy.
#[test]
fn malformed_requests_get_json_errors() {
    let server = serve();
    let p = port(&server);
    let host = format!("Host: 127.0.0.1:{p}\r\n");
    let long = format!("GET /api/atlas?pad={} HTTP/1.1\r\n{host}\r\n", "a".repeat(70_000));
    let many: String = (0..100).map(|i| format!("X-{i}: 1\r\n")).collect();
    let cases: Vec<(String, u16, &str)> = vec![
        (format!("GET /api/atlas HTTP/1.1\r\n{host}X-A: b\rc\r\n\r\n"), 400, "not HTTP/1.1"),
        (
            format!("POST /api/zoom HTTP/1.1\r\n{host}Content-Length: 123456789012345678901234\r\n\r\n"),
            400,
            "Content-Length",
        ),
        (format!("POST /api/zoom HTTP/1.1\r\n{host}Content-Length: +5\r\n\r\nabcde"), 400, "Content-Length"),
        (format!("GET /api/atlas HTTP/1.1\r\n{host}Transfer-Encoding: identity\r\n\r\n"), 400, "Transfer-Encoding"),
        (format!("POST /api/zoom HTTP/1.1\r\n{host}Content-Length: 18446744073709551615\r\n\r\n"), 413, "at most"),
        (format!("GET /api/atlas HTTP/1.1\r\n{host}{many}\r\n"), 431, "headers"),
        (long, 431, "KiB"),
        ("NOT HTTP AT ALL\r\n\r\n".to_string(), 400, "not HTTP/1.1"),
    ];
    for (request, status, said) in cases {
        let a = send_bytes(p, request.as_bytes());
        assert_eq!(a.status, status, "{}", &request[..40.min(request.len())]);
        assert!(a.error().contains(said), "{}", a.error());
        assert!(a.header("content-security-policy").is_some_and(|c| c.contains("default-src 'none'")));
    }
    // The server still answers, and closes each connection after one answer.
    let a = get(p, "/api/atlas");
    assert_eq!((a.status, a.header("connection")), (200, Some("close")));
    // A client that half-closes once its request is sent (`nc -N`) gets its
    // answer, each of ten times; so does one ending its lines with a bare LF.
    for _ in 0..10 {
        let mut s = TcpStream::connect(("127.0.0.1", p)).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        s.write_all(format!("GET /api/atlas HTTP/1.1\r\n{host}\r\n").as_bytes()).unwrap();
        s.shutdown(std::net::Shutdown::Write).unwrap();
        let mut raw = Vec::new();
        s.read_to_end(&mut raw).unwrap();
        assert!(raw.starts_with(b"HTTP/1.1 200"), "{}", String::from_utf8_lossy(&raw));
    }
    let lf = send_bytes(p, format!("GET /api/atlas HTTP/1.1\nHost: 127.0.0.1:{p}\n\n").as_bytes());
    assert_eq!(lf.status, 200);
}

#[test]
fn another_host_name_is_refused() {
    let server = serve();
    let p = port(&server);
    for host in ["evil.example", "evil.example:80", &format!("127.0.0.1:{}", p + 1), "127.0.0.1"] {
        for target in ["/api/files/0", "/api/atlas", "/"] {
            let a = send(p, "GET", target, &[("Host", host)], b"");
            assert_eq!(a.status, 403, "{host} {target}");
            assert!(a.error().starts_with("Host: the explorer answers to"), "{}", a.error());
        }
    }
    let none = send(p, "GET", "/api/atlas", &[], b"");
    assert_eq!(none.status, 403);
    assert_eq!(get(p, "/api/files/0").status, 200);
    let local = format!("localhost:{p}");
    assert_eq!(send(p, "GET", "/api/atlas", &[("Host", &local)], b"").status, 200);
}

#[test]
fn a_zoom_from_another_site_or_not_json_is_refused() {
    let server = serve();
    let p = port(&server);
    let plain = post_zoom(p, &[("Content-Type", "text/plain")]);
    assert_eq!(plain.status, 415);
    assert!(plain.error().starts_with("Content-Type:"), "{}", plain.error());
    assert_eq!(post_zoom(p, &[]).status, 415);
    let json = ("Content-Type", "application/json");
    let foreign = post_zoom(p, &[json, ("Origin", "http://evil.example")]);
    assert_eq!(foreign.status, 403);
    assert!(foreign.error().starts_with("Origin:"), "{}", foreign.error());
    let cross = post_zoom(p, &[json, ("Sec-Fetch-Site", "cross-site")]);
    assert_eq!(cross.status, 403);
    let host = format!("127.0.0.1:{p}");
    let delete = send(p, "DELETE", "/api/jobs/0", &[("Host", &host), ("Origin", "http://evil.example")], b"");
    assert_eq!(delete.status, 403);
    // The page's own origin (and a script, which names none) may.
    let origin = format!("http://127.0.0.1:{p}");
    let own = post_zoom(p, &[json, ("Origin", &origin), ("Sec-Fetch-Site", "same-origin")]);
    assert_eq!(own.status, 200, "{}", String::from_utf8_lossy(&own.body));
    let job = own.json()["job"].as_u64().unwrap();
    let cancel = send(p, "DELETE", &format!("/api/jobs/{job}"), &[("Host", &host), ("Origin", &origin)], b"");
    assert_eq!(cancel.status, 200);
    // Another site's image or fetch may not start work; a link to the page may.
    let read = |site: &str, mode: &str| {
        send(
            p,
            "GET",
            "/api/figure?view=up",
            &[("Host", &host), ("Sec-Fetch-Site", site), ("Sec-Fetch-Mode", mode)],
            b"",
        )
    };
    for site in ["cross-site", "same-site"] {
        let a = read(site, "no-cors");
        assert_eq!(a.status, 403, "{site}");
        assert!(a.error().starts_with("Sec-Fetch-Site: only the explorer's own page"), "{}", a.error());
    }
    assert_eq!(read("cross-site", "navigate").status, 200);
    assert_eq!(read("same-origin", "no-cors").status, 200);
}

#[test]
fn every_error_is_json() {
    let server = serve();
    let p = port(&server);
    let host = format!("127.0.0.1:{p}");
    let long = format!("/api/atlas?pad={}", "a".repeat(20_000));
    let a = send(p, "GET", &long, &[("Host", &host)], b"");
    assert_eq!(a.status, 414);
    assert!(a.error().contains("at most 8192"), "{}", a.error());
    let big = vec![b' '; 200_000];
    let a = send(p, "POST", "/api/zoom", &[("Host", &host), ("Content-Type", "application/json")], &big);
    assert_eq!(a.status, 413);
    assert!(!a.error().is_empty());
    for (method, target, status) in [
        ("GET", "/api/nothing", 404),
        ("PUT", "/api/atlas", 405),
        ("GET", "/api/jobs/x", 404),
        ("GET", "/api/at?ix=-1&iy=0", 400),
        ("GET", "/api/files/99", 404),
    ] {
        let a = send(p, method, target, &[("Host", &host)], b"");
        assert_eq!(a.status, status, "{method} {target}");
        assert!(!a.error().is_empty(), "{method} {target}");
    }
}

/// The threads of this process now.
fn threads() -> usize {
    std::fs::read_dir("/proc/self/task").map(|d| d.count()).unwrap_or(0)
}

#[test]
fn queued_zooms_are_bounded_and_a_stop_is_quick() {
    let before = threads();
    let server = serve();
    let p = port(&server);
    let json = ("Content-Type", "application/json");
    let mut refused = 0;
    for _ in 0..40 {
        let a = post_zoom(p, &[json]);
        match a.status {
            200 => {}
            503 => {
                assert!(a.error().contains("zooms are waiting already"), "{}", a.error());
                refused += 1;
            }
            s => panic!("status {s}: {}", String::from_utf8_lossy(&a.body)),
        }
    }
    assert!(refused >= 40 - 1 - 8 - 1, "{refused} of 40 refused");
    let during = threads();
    assert!(during <= before + 24, "{before} threads before, {during} with 40 zooms asked for");
    let t = Instant::now();
    server.stop();
    assert!(t.elapsed() < Duration::from_secs(2), "stopped in {:?}", t.elapsed());
}

/// Issue 66: the cell's basins through the API: a proposed grid over the
/// components named in markup (JSON strings, as every name), the map over a
/// small grid of them, and bad grids refused with a JSON reason.
#[test]
fn basins_of_a_cell_over_components_named_in_markup() {
    let server = serve();
    let p = port(&server);
    let cell = "sweep=up&omega=2.1&sigma=-0.5";
    let plan = get(p, &format!("/api/basins/plan?{cell}"));
    assert_eq!(plan.status, 200, "{}", plan.error());
    let plan = plan.json();
    let x = format!("x_{MARKUP_MASS}");
    assert_eq!(plan["components"][0], x);
    assert!(plan["x"].as_str().unwrap().starts_with(&format!("{x}=-")), "{plan}");
    assert!(plan["seconds"].as_f64().unwrap() >= 0.0 && plan["starts"] == 10_000, "{plan}");
    let encode = |t: &str| t.bytes().map(|b| format!("%{b:02X}")).collect::<String>();
    let grid =
        format!("basin_x={}&basin_y={}", encode(&format!("{x}=-1:1:6")), encode(&format!("v_{MARKUP_MASS}=-1:1:5")));
    let b = get(p, &format!("/api/basins?{cell}&{grid}"));
    assert_eq!(b.status, 200, "{}", b.error());
    let b = b.json();
    assert_eq!((b["starts"].as_u64(), b["x"]["name"].as_str()), (Some(30), Some(x.as_str())));
    let shares: f64 = b["attractors"].as_array().unwrap().iter().map(|a| a["fraction"].as_f64().unwrap()).sum();
    assert!((shares - 1.0).abs() < 1e-12 && b["png"].as_str().is_some_and(|s| s.len() > 100), "{b}");
    for (query, says) in [
        (format!("{cell}&basin_y=v=0:1:4"), "basin_x: missing"),
        (format!("{cell}&basin_x={}&basin_y=v=0:1:4", encode("x_Q=0:1:4")), "basin_x: no state component 'x_Q'"),
        (
            format!("{cell}&basin_x={}&basin_y={}", encode(&format!("{x}=-1:1:3")), encode(&format!("{x}=-1:1:3"))),
            "basin_y: the same component as basin_x",
        ),
        (format!("{cell}&basin_x={}&basin_y={}", encode("a=0:1:1000"), encode("b=0:1:1000")), "at most 250000"),
        (format!("{cell}&{grid}&phase=nan"), "phase"),
    ] {
        let a = get(p, &format!("/api/basins?{query}"));
        assert!(a.status == 400 || a.status == 422, "{query}: {}", a.status);
        assert!(a.error().contains(says), "{query}: {}", a.error());
    }
}

/// A zoom's `set` (a slice at another parameter value, issue 65) refuses an
/// empty item and a name given twice, as `zoom --set` does, in one JSON reason.
#[test]
fn a_zooms_set_is_refused_as_the_cli_refuses_it() {
    let server = serve();
    let p = port(&server);
    let plan = |set: &str| get(p, &format!("/api/zoom/plan?atlas=0&x=omega=1.5:3:3&y=sigma=-0.5:0:3&set={set}"));
    let a = plan(",,");
    assert_eq!(a.status, 400);
    assert!(a.json()["error"].as_str().unwrap().starts_with("set : expected NAME=VALUE"), "{}", a.json());
    let a = plan("zeta=0.01,zeta=0.02");
    assert!(a.status >= 400, "{}", a.status);
    assert!(a.json()["error"].as_str().unwrap().contains("zeta: given twice"), "{}", a.json());
    // This scene has omega and sigma only: an unknown name is named.
    let a = plan("zeta=0.02");
    assert!(a.json()["error"].as_str().unwrap().contains("unknown parameter 'zeta'"), "{}", a.json());
    // A box one value wide is planned as it is zoomed (its probe was 3 values
    // wide, refused as "a count of 1 is one value…", a count never given).
    let line = get(p, "/api/zoom/plan?atlas=0&x=omega=2:2:1&y=sigma=-0.5:0:3");
    assert_eq!(line.status, 200, "{}", String::from_utf8_lossy(&line.body));
    assert_eq!(line.json()["cells"], 3);
}

/// A box outside the parent's plane, or a sweep the parent lacks, is refused
/// when the zoom is asked, as `/api/zoom/plan` and `zoom` refuse it, with no
/// job started (a check of the issues' contracts found `{"job": 0}` answered
/// first and the job failing after).
#[test]
fn a_zoom_outside_the_plane_is_refused_when_asked() {
    let server = serve();
    let p = port(&server);
    let host = format!("127.0.0.1:{p}");
    let json = [("Host", host.as_str()), ("Content-Type", "application/json")];
    let outside = br#"{"atlas": 0, "x": "omega=2.5:4:3", "y": "sigma=-0.5:0:3"}"#;
    let a = send(p, "POST", "/api/zoom", &json, outside);
    assert_eq!(a.status, 400);
    assert_eq!(a.error(), "x: omega=2.5:4 is not within the parent's 1.5 to 3");
    let down = br#"{"atlas": 0, "x": "omega=1.5:3:3", "y": "sigma=-0.5:0:3", "sweep": "down"}"#;
    let a = send(p, "POST", "/api/zoom", &json, down);
    assert_eq!(a.status, 400);
    assert!(a.error().starts_with("sweep: ") && a.error().ends_with("has up, not down"), "{}", a.error());
    assert_eq!(get(p, "/api/jobs/0").status, 404, "no job started");
}

/// Issue 61: a file replaced since the explorer read it gets a 409 from
/// every route that answers for it (a check of the issues' contracts found
/// `/api/at` and `/api/figure` still answering from what was read).
#[test]
fn every_route_refuses_a_file_replaced_since_it_was_read() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("explore-replaced");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("a.h5");
    std::fs::copy(atlas_file(), &file).unwrap();
    let server = explore::serve(&explore::ExploreRequest { file: file.clone(), port: 0, threads: 1 }).unwrap();
    let p = port(&server);
    let routes = ["/api/atlas", "/api/map", "/api/legend", "/api/at?ix=0&iy=0", "/api/figure", "/api/curves"];
    for route in routes {
        assert_eq!(get(p, route).status, 200, "{route}");
    }
    let copy = dir.join("copy.h5");
    std::fs::copy(&file, &copy).unwrap();
    std::fs::rename(&copy, &file).unwrap();
    for route in routes {
        let a = get(p, route);
        assert_eq!(a.status, 409, "{route}");
        assert!(a.error().contains("the file changed or was removed since the explorer read it"), "{route}");
    }
}

/// The sixth audit: two Host (or Origin) headers, the explorer's first, and
/// an address naming another host were served; each is refused now, with a
/// JSON reason.
#[test]
fn doubled_headers_and_foreign_addresses_are_refused() {
    let server = serve();
    let p = port(&server);
    let host = format!("127.0.0.1:{p}");
    let a = send(p, "GET", "/api/atlas", &[("Host", &host), ("Host", "evil.example")], b"");
    assert_eq!(a.status, 400);
    assert!(a.json()["error"].as_str().unwrap().starts_with("host: given 2 times"), "{}", a.json());
    let origin = format!("http://{host}");
    let a =
        post_zoom(p, &[("Content-Type", "application/json"), ("Origin", &origin), ("Origin", "http://evil.example")]);
    assert_eq!(a.status, 400);
    let a = send(p, "GET", "http://evil.example/api/atlas", &[("Host", &host)], b"");
    assert_eq!(a.status, 403);
    assert!(a.json()["error"].as_str().unwrap().contains("names the host 'evil.example'"), "{}", a.json());
    let own = format!("http://{host}/api/atlas");
    assert_eq!(send(p, "GET", &own, &[("Host", &host)], b"").status, 200);
}

/// The sixth audit's leftovers: a query key given twice was read as one of
/// its values, `/api/orbit` ignored `n`, and a download's name went into its
/// `Content-Disposition` as it was (a file named with a newline gave an
/// empty 200). Now: one JSON refusal; the period asked for, as `orbit --n`;
/// the name in ASCII and whole in `filename*`, and the file's bytes.
#[test]
fn a_repeated_key_n_and_an_odd_file_name() {
    let server = serve();
    let p = port(&server);
    for target in ["/api/atlas?atlas=0&atlas=0", "/api/map?view=up&view=up", "/api/orbit?omega=2&omega=2&sigma=0"] {
        let a = get(p, target);
        assert_eq!(a.status, 400, "{target}");
        assert!(a.error().ends_with(": given twice"), "{target}: {}", a.error());
    }
    let a = get(p, "/api/map?view=%ZZ");
    assert_eq!(a.status, 400);
    // A parameter the request does not take (misspelt) is refused, naming
    // it and what the request takes.
    for (target, says) in [
        ("/api/map?veiw=up", "veiw: not a parameter of this request (it takes atlas, view, mass)"),
        (
            "/api/orbit?omega=2&sigma=0&delta=1",
            "delta: not a parameter of this request (it takes atlas, sweep, n, omega, sigma)",
        ),
        ("/api/at?ix=0&iy=0&x=1", "x: not a parameter of this request (it takes atlas, ix, iy)"),
    ] {
        let a = get(p, target);
        assert_eq!(a.status, 400, "{target}");
        assert_eq!(a.error(), says, "{target}");
    }
    // A periodic cell of the plane.
    let (at, own) = ["1.5", "1.8", "2.1", "2.4", "2.7", "3"]
        .iter()
        .flat_map(|w| ["-0.5", "0"].map(|s| format!("omega={w}&sigma={s}&sweep=up")))
        .map(|at| {
            let a = get(p, &format!("/api/orbit?{at}"));
            (at, a)
        })
        .find(|(_, a)| a.status == 200)
        .expect("a periodic cell");
    let n = own.json()["n"].as_u64().unwrap();
    let doubled = get(p, &format!("/api/orbit?{at}&n={}", 2 * n));
    assert_eq!(doubled.status, 200);
    assert_eq!(doubled.json()["n"].as_u64(), Some(2 * n), "{}", doubled.json());
    for (bad, status) in [("n=x", 400), ("n=0", 422), ("n=1001", 422)] {
        let a = get(p, &format!("/api/orbit?{at}&{bad}"));
        assert_eq!(a.status, status, "{bad}: {}", a.error());
        assert!(a.error().starts_with("n: "), "{bad}: {}", a.error());
    }
    drop(server);

    let odd = atlas_file().with_file_name("a \"b\";c\u{e9}\n.h5");
    std::fs::copy(atlas_file(), &odd).unwrap();
    let r = explore::ExploreRequest { file: odd.clone(), port: 0, threads: 1 };
    let server = explore::serve(&r).unwrap();
    let a = get(port(&server), "/api/files/0");
    assert_eq!(a.status, 200);
    assert_eq!(a.body, std::fs::read(&odd).unwrap());
    assert_eq!(
        a.header("content-disposition"),
        Some("attachment; filename=\"a__b__c__.h5\"; filename*=UTF-8''a%20%22b%22%3Bc%C3%A9%0A.h5")
    );
    std::fs::remove_file(&odd).unwrap();
}

/// Every route of the API refuses a bad parameter with a JSON reason that
/// names it (issue 63): an unknown key, a view, a sweep, an index, a count or a
/// format the route does not take, each with status 400 (or 422 for a value
/// the request's own checks refuse), and the server answers on afterwards.
#[test]
fn every_route_names_the_parameter_it_refuses() {
    let server = serve();
    let p = port(&server);
    let cell = "sweep=up&omega=2.1&sigma=-0.5";
    let cases: Vec<(String, &str)> = vec![
        ("/api/atlas?bogus=1".into(), "bogus: not a parameter"),
        ("/api/map?view=sideways".into(), "view:"),
        ("/api/legend?view=sideways".into(), "view:"),
        ("/api/at?ix=x&iy=0".into(), "ix"),
        ("/api/cell?sweep=sideways&omega=2.1&sigma=-0.5".into(), "sweep"),
        ("/api/cell?sweep=up&omega=2.1".into(), "sigma"),
        (format!("/api/orbit?{cell}&n=0"), "n"),
        ("/api/cell/portrait.png?sweep=down&omega=2.1&sigma=-0.5".into(), "sweep"),
        (format!("/api/cell/sections.png?{cell}&periods=x"), "periods"),
        (format!("/api/attractors?{cell}&samples=0"), "samples"),
        ("/api/basins/plan?sweep=fresh&omega=2.1&sigma=-0.5".into(), "sweep"),
        ("/api/zoom/plan?x=omega&y=sigma=-0.5:0:4".into(), "x"),
        ("/api/figure?format=bmp".into(), "format"),
        ("/api/curves?bogus=1".into(), "bogus: not a parameter"),
    ];
    for (target, says) in cases {
        let a = get(p, &target);
        assert!(a.status == 400 || a.status == 422, "{target}: {} {}", a.status, a.error());
        assert!(a.error().contains(says), "{target}: '{}' does not name {says}", a.error());
    }
    assert_eq!(get(p, "/api/atlas").status, 200);
}

/// A refusal names what the user gave (found by an independent check): a
/// cell's parameter out of the plane names that parameter; a key on a route
/// that takes none is refused; a view of a number with no up less down says
/// so; a print size is refused in its own words; a long input does not cut
/// off the reason; a zoom's field given twice is refused.
#[test]
fn refusals_name_what_the_user_gave() {
    let server = serve();
    let p = port(&server);
    let host = format!("127.0.0.1:{p}");
    let cases: Vec<(String, &str)> = vec![
        ("/api/cell?sweep=up&omega=-1&sigma=-0.5".into(), "omega: omega = -1 is outside the file's 1.5 to 3"),
        ("/api/files/0?bogus=1".into(), "bogus: not a parameter of this request (it takes none)"),
        ("/api/jobs/0?x=1".into(), "x: not a parameter of this request (it takes none)"),
        ("/api/figure?view=up&size=10x10".into(), "size: 10 mm is outside 20..1000 mm (or screen)"),
        (
            "/api/zoom/plan?x=omega=1.5:3:1&y=sigma=-0.5:0:4".into(),
            "a count of 1 is one value, but start 1.5 and stop 3 differ",
        ),
    ];
    for (target, says) in cases {
        let a = get(p, &target);
        assert_eq!(a.status, 400, "{target}: {}", a.error());
        assert!(a.error().contains(says), "{target}: '{}' does not say '{says}'", a.error());
    }
    let lyapunov = get(p, "/api/legend?view=lyapunov:hysteresis");
    assert_eq!(lyapunov.status, 400);
    // This atlas is the up sweep alone: no hysteresis of anything.
    let said = lyapunov.error();
    assert!(
        said.starts_with(
            "view: 'lyapunov:hysteresis' is not a view of the atlas: hysteresis needs up and down sweeps ("
        ),
        "{said}"
    );
    let json = [("Host", host.as_str()), ("Content-Type", "application/json")];
    let twice = br#"{"atlas": 0, "x": "omega=1.5:3:3", "x": "omega=1.5:3:3", "y": "sigma=-0.5:0:3"}"#;
    let a = send(p, "POST", "/api/zoom", &json, twice);
    assert_eq!((a.status, a.error()), (400, "x: given twice".to_string()));
    let a = send(p, "POST", "/api/zoom?atlas=0", &json, br#"{"x": "omega=1.5:3:3", "y": "sigma=-0.5:0:3"}"#);
    assert_eq!((a.status, a.error()), (400, "atlas: not a parameter of this request (it takes none)".to_string()));
}
