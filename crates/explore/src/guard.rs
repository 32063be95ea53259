//! Who may talk to the explorer, and how every answer is sealed.
//!
//! The server listens on 127.0.0.1 only, but a page of any web site the user
//! has open can still send requests there, and a site whose name resolves to
//! 127.0.0.1 (DNS rebinding) can read the answers. So every request passes
//! [`screen`]:
//!
//! - its `Host` must be `127.0.0.1:PORT` or `localhost:PORT` (else 403): a
//!   rebound name arrives with its own host name; an address that names its
//!   own host must name one of these, and `Host`, `Origin` and
//!   `Sec-Fetch-Site` come once each (else 400);
//! - a `GET` that the browser says another site's page made (`Sec-Fetch-Site:
//!   cross-site` or `same-site`), other than a navigation to it, is refused
//!   (403): a page elsewhere could otherwise start the explorer's work;
//! - a request that changes something (`POST`, `DELETE`) must come from the
//!   page's own origin when the browser names one (`Origin`, `Sec-Fetch-Site`),
//!   and a `POST` must carry `Content-Type: application/json`, which a
//!   cross-site form or `text/plain` fetch cannot send without a preflight
//!   that this server never grants (else 403, or 415 for the type);
//! - every answer carries a strict Content-Security-Policy (the page's own
//!   script and style only, no inline script, no frames), `nosniff` and
//!   `no-referrer`;
//! - every error is JSON, `{"error": "…"}`, whoever made it (a route, an
//!   extractor's rejection, the body limit; a head the HTTP layer would
//!   refuse is answered before it, [`crate::head`]);
//! - every answer closes its connection, so that each request's head is
//!   checked.

use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, Method, StatusCode, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::sync::Arc;

/// The policy of every answer: the page's own script, style, images and API
/// (images also as `data:` URLs, the basin pictures), nothing inline, no
/// plug-ins, no frames, no base or form elsewhere.
pub(crate) const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'self'; style-src 'self'; \
     img-src 'self' data:; connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// The largest body a request may carry (a zoom's is about a hundred bytes).
pub(crate) const MAX_BODY: usize = 64 * 1024;

/// The longest request target (path and query) served; a longer one is 414.
pub(crate) const MAX_URI: usize = 8 * 1024;

/// The names the server answers to: `127.0.0.1:PORT` and `localhost:PORT`.
pub(crate) struct Allowed {
    hosts: [String; 2],
    origins: [String; 2],
}

impl Allowed {
    /// The names of a server on `port`.
    pub fn on(port: u16) -> Arc<Allowed> {
        let hosts = [format!("127.0.0.1:{port}"), format!("localhost:{port}")];
        let origins = hosts.clone().map(|h| format!("http://{h}"));
        Arc::new(Allowed { hosts, origins })
    }

    /// Why a request is refused, or `None`: its host (the `Host` header,
    /// and the address's own host where it names one), origin and type.
    fn refuse(&self, method: &Method, headers: &HeaderMap, uri: &Uri) -> Option<(StatusCode, String)> {
        let text = |name: header::HeaderName| headers.get(name).map(|v| v.to_str().unwrap_or("(not text)"));
        let uri_len = uri.path_and_query().map_or(0, |p| p.as_str().len());
        if uri_len > MAX_URI {
            return Some((
                StatusCode::URI_TOO_LONG,
                format!("the request's address is {uri_len} bytes long; at most {MAX_URI} are served"),
            ));
        }
        // One of each header the checks read: with two, a check could read
        // one and another part of the stack the other.
        for name in [header::HOST, header::ORIGIN, header::HeaderName::from_static("sec-fetch-site")] {
            let n = headers.get_all(&name).iter().count();
            if n > 1 {
                return Some((StatusCode::BAD_REQUEST, format!("{name}: given {n} times; one is expected")));
            }
        }
        if let Some(a) = uri.authority().map(|a| a.as_str()) {
            if !self.hosts.iter().any(|h| h.eq_ignore_ascii_case(a)) {
                let why = format!(
                    "the address names the host '{}'; the explorer answers to {} only",
                    short(a),
                    self.hosts[0]
                );
                return Some((StatusCode::FORBIDDEN, why));
            }
        }
        match text(header::HOST) {
            Some(h) if self.hosts.iter().any(|a| a.eq_ignore_ascii_case(h)) => {}
            h => {
                let got = h.map_or("none".to_string(), |h| format!("'{}'", short(h)));
                return Some((
                    StatusCode::FORBIDDEN,
                    format!("Host: the explorer answers to {} or {} only, got {got}", self.hosts[0], self.hosts[1]),
                ));
            }
        }
        let site = headers.get("sec-fetch-site").and_then(|v| v.to_str().ok());
        if method == Method::GET || method == Method::HEAD {
            // Another site's page may send the user here (a link, an
            // address typed or shared), not fetch from here: its images,
            // scripts and fetches would start work (a figure, a zoom's
            // plan) and record a cell as clicked.
            let navigates = headers.get("sec-fetch-mode").is_some_and(|m| m == "navigate");
            return match site {
                Some(site @ ("cross-site" | "same-site")) if !navigates => Some((
                    StatusCode::FORBIDDEN,
                    format!("Sec-Fetch-Site: only the explorer's own page may ask for this, not a {site} request"),
                )),
                _ => None,
            };
        }
        if let Some(o) = text(header::ORIGIN) {
            if !self.origins.iter().any(|a| a.eq_ignore_ascii_case(o)) {
                return Some((
                    StatusCode::FORBIDDEN,
                    format!("Origin: only the explorer's own page may change things, not '{}'", short(o)),
                ));
            }
        }
        if let Some(site) = site {
            if site != "same-origin" && site != "none" {
                return Some((
                    StatusCode::FORBIDDEN,
                    format!("Sec-Fetch-Site: only the explorer's own page may change things, not a {site} request"),
                ));
            }
        }
        if method == Method::POST {
            let json = text(header::CONTENT_TYPE)
                .and_then(|t| t.split(';').next())
                .is_some_and(|t| t.trim().eq_ignore_ascii_case("application/json"));
            if !json {
                return Some((
                    StatusCode::UNSUPPORTED_MEDIA_TYPE,
                    "Content-Type: a POST's body must be sent as application/json".to_string(),
                ));
            }
        }
        None
    }
}

/// An error answer: `{"error": message}`.
pub(crate) fn error(status: StatusCode, message: &str) -> Response {
    (status, axum::Json(serde_json::json!({ "error": message }))).into_response()
}

/// The middleware of every route: refuses what [`Allowed`] refuses, turns
/// any error answer that is not JSON into `{"error": …}` (its text, or the
/// status's reason), and adds the security headers.
pub(crate) async fn screen(State(allowed): State<Arc<Allowed>>, request: Request, next: Next) -> Response {
    let mut answer = match allowed.refuse(request.method(), request.headers(), request.uri()) {
        Some((status, message)) => error(status, &message),
        None => as_json(next.run(request).await).await,
    };
    let h = answer.headers_mut();
    h.insert(header::CONTENT_SECURITY_POLICY, HeaderValue::from_static(CONTENT_SECURITY_POLICY));
    h.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    // One request per connection: the next one's head is read and checked
    // before the HTTP layer sees it (crate::head).
    h.insert(header::CONNECTION, HeaderValue::from_static("close"));
    h.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    h.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    h.insert("cross-origin-resource-policy", HeaderValue::from_static("same-origin"));
    answer
}

/// An error answer whose body is not JSON, as `{"error": its text}`.
async fn as_json(answer: Response) -> Response {
    let status = answer.status();
    let is_json = answer
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|t| t.to_str().ok())
        .is_some_and(|t| t.starts_with("application/json"));
    if !(status.is_client_error() || status.is_server_error()) || is_json {
        return answer;
    }
    let body = axum::body::to_bytes(answer.into_body(), MAX_BODY).await.unwrap_or_default();
    let text = String::from_utf8_lossy(&body);
    let reason = status.canonical_reason().unwrap_or("error").to_lowercase();
    let message = if text.trim().is_empty() { reason } else { format!("{reason}: {}", text.trim()) };
    error(status, &message)
}

/// A text the user gave as an error message shows it: at most 80 characters.
pub(crate) fn short(t: &str) -> String {
    scene::excerpt(t, 80)
}

/// A library's whole message, which may quote what the user gave: at most
/// 400 characters, so that a reason is kept whole where the input was of a
/// usual length, and a page-long input is not sent back in full.
pub(crate) fn brief(message: &str) -> String {
    scene::excerpt(message, 400)
}
