//! The head of every request, read and checked before the HTTP layer sees
//! it, so that a request the HTTP layer would refuse on its own (a head that
//! does not parse, a bare carriage return, a `Content-Length` that is not one
//! number, a head over [`MAX_HEAD`], one that never ends) is answered like
//! every other error: JSON, `{"error": "…"}`, with the page's security
//! headers. Each connection carries one request (every answer says
//! `Connection: close`, [`crate::guard`]), so every head passes here.

use crate::guard::CONTENT_SECURITY_POLICY;
use std::io;
use std::net::SocketAddr;
use std::pin::Pin;
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::mpsc;

/// The longest request head (request line and headers) read.
pub(crate) const MAX_HEAD: usize = 64 * 1024;

/// The most headers a request may have.
const MAX_HEADERS: usize = 64;

/// How long a client may take to send its request's head.
const HEAD_WAIT: Duration = Duration::from_secs(10);

/// Connections whose head was read and passed, waiting for the server.
const WAITING: usize = 64;

/// A listener handing the server only connections whose head passed
/// [`screen`]; the others were answered and closed.
pub(crate) struct Screened {
    passed: mpsc::Receiver<(Prefixed, SocketAddr)>,
    addr: SocketAddr,
}

/// Accepts connections on `listener`, reading and checking each one's head
/// on a task of its own (a slow client holds up no other).
pub(crate) fn screened(listener: TcpListener) -> io::Result<Screened> {
    let addr = listener.local_addr()?;
    let (tx, passed) = mpsc::channel(WAITING);
    tokio::spawn(async move {
        while !tx.is_closed() {
            let Ok((stream, peer)) = listener.accept().await else {
                // Out of descriptors, for instance: wait, and accept again.
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            };
            let tx = tx.clone();
            tokio::spawn(async move {
                if let Some(io) = screen(stream).await {
                    let _ = tx.send((io, peer)).await;
                }
            });
        }
    });
    Ok(Screened { passed, addr })
}

impl axum::serve::Listener for Screened {
    type Io = Prefixed;
    type Addr = SocketAddr;

    async fn accept(&mut self) -> (Prefixed, SocketAddr) {
        match self.passed.recv().await {
            Some(passed) => passed,
            // The accepting task ended (it ends only once this listener is
            // gone): nothing more will come.
            None => std::future::pending().await,
        }
    }

    fn local_addr(&self) -> io::Result<SocketAddr> {
        Ok(self.addr)
    }
}

/// Reads the head of `stream`'s request: the connection with what was read
/// put back in front, or `None` where it was answered with an error (or
/// closed before its head ended).
async fn screen(mut stream: TcpStream) -> Option<Prefixed> {
    let mut read = Vec::with_capacity(1024);
    let mut chunk = [0u8; 4096];
    let ended = tokio::time::timeout(HEAD_WAIT, async {
        loop {
            if ends(&read) {
                return Ok(true);
            }
            if read.len() > MAX_HEAD {
                return Ok(false);
            }
            match stream.read(&mut chunk).await {
                Ok(0) => return Err(()),
                Ok(n) => read.extend_from_slice(&chunk[..n]),
                Err(_) => return Err(()),
            }
        }
    })
    .await;
    let refusal = match ended {
        Err(_) => Some((408, format!("the request's head did not arrive within {} s", HEAD_WAIT.as_secs()))),
        Ok(Err(())) => return None,
        Ok(Ok(false)) => Some((431, format!("the request's head is over {} KiB", MAX_HEAD / 1024))),
        Ok(Ok(true)) => refuse(&read),
    };
    match refusal {
        None => Some(Prefixed { read, at: 0, stream }),
        Some((status, message)) => {
            let _ = stream.write_all(&answer(status, &message)).await;
            let _ = stream.shutdown().await;
            // What the client still sends is read and dropped for a moment:
            // closed with it unread, the connection would be reset, and
            // the client might lose the answer.
            let mut rest = [0u8; 4096];
            let _ = tokio::time::timeout(Duration::from_secs(1), async {
                while matches!(stream.read(&mut rest).await, Ok(n) if n > 0) {}
            })
            .await;
            None
        }
    }
}

/// Whether `read` holds a whole head (its blank line).
fn ends(read: &[u8]) -> bool {
    read.windows(4).any(|w| w == b"\r\n\r\n")
}

/// Why the head at the start of `read` is refused (status and message), or
/// `None`.
fn refuse(read: &[u8]) -> Option<(u16, String)> {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut request = httparse::Request::new(&mut headers);
    match request.parse(read) {
        Err(httparse::Error::TooManyHeaders) => {
            return Some((431, format!("the request has more than {MAX_HEADERS} headers")));
        }
        Err(e) => return Some((400, format!("the request's head is not HTTP/1.1 ({e})"))),
        Ok(httparse::Status::Partial) => return Some((400, "the request's head is not HTTP/1.1".into())),
        Ok(httparse::Status::Complete(_)) => {}
    }
    let named = |name: &'static str| request.headers.iter().filter(move |h| h.name.eq_ignore_ascii_case(name));
    let mut length = None;
    for h in named("content-length") {
        let text = String::from_utf8_lossy(h.value);
        let Ok(n) = text.trim().parse::<u64>() else {
            return Some((400, format!("Content-Length: '{}' is not a number of bytes", short(&text))));
        };
        if length.is_some_and(|m| m != n) {
            return Some((400, "Content-Length: given twice, with two values".into()));
        }
        length = Some(n);
    }
    if length.is_some() && named("transfer-encoding").next().is_some() {
        return Some((400, "Content-Length and Transfer-Encoding: give one of them".into()));
    }
    None
}

/// At most 40 characters of `text`.
fn short(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_string(),
    }
}

/// The whole answer to a refused head: the status, the security headers
/// every answer carries, and `{"error": message}`.
fn answer(status: u16, message: &str) -> Vec<u8> {
    let body = serde_json::json!({ "error": message }).to_string();
    let reason = axum::http::StatusCode::from_u16(status).ok().and_then(|s| s.canonical_reason()).unwrap_or("Error");
    format!(
        "HTTP/1.1 {status} {reason}\r\ncontent-type: application/json\r\ncontent-length: {}\r\nconnection: close\r\n\
         content-security-policy: {CONTENT_SECURITY_POLICY}\r\nx-content-type-options: nosniff\r\n\
         referrer-policy: no-referrer\r\nx-frame-options: DENY\r\ncross-origin-resource-policy: same-origin\r\n\r\n{body}",
        body.len()
    )
    .into_bytes()
}

/// A connection whose first bytes were read to check its head: they are
/// read again first, then the connection itself.
pub(crate) struct Prefixed {
    read: Vec<u8>,
    at: usize,
    stream: TcpStream,
}

impl AsyncRead for Prefixed {
    fn poll_read(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        let this = &mut *self;
        if this.at < this.read.len() {
            let n = buf.remaining().min(this.read.len() - this.at);
            buf.put_slice(&this.read[this.at..this.at + n]);
            this.at += n;
            return Poll::Ready(Ok(()));
        }
        Pin::new(&mut this.stream).poll_read(cx, buf)
    }
}

impl AsyncWrite for Prefixed {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.stream).poll_write(cx, buf)
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heads the HTTP layer would refuse without a JSON body are refused
    /// here with their reason; a sound one passes.
    #[test]
    fn malformed_heads_are_refused_with_their_reason() {
        let ok = b"GET /api/atlas HTTP/1.1\r\nHost: 127.0.0.1:1\r\nContent-Length: 0\r\n\r\n";
        assert_eq!(refuse(ok), None);
        let cases: [(&[u8], u16, &str); 5] = [
            (b"GET /\rX HTTP/1.1\r\n\r\n", 400, "not HTTP/1.1"),
            (b"GET / HTTP/1.1\r\nHost: a\rb\r\n\r\n", 400, "not HTTP/1.1"),
            (b"POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n", 400, "Content-Length"),
            (b"POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n", 400, "given twice"),
            (b"POST / HTTP/1.1\r\nContent-Length: 1\r\nTransfer-Encoding: chunked\r\n\r\n", 400, "give one"),
        ];
        for (head, status, said) in cases {
            let (s, message) = refuse(head).unwrap_or_else(|| panic!("{}", String::from_utf8_lossy(head)));
            assert_eq!(s, status, "{message}");
            assert!(message.contains(said), "{message}");
        }
        let many: String = (0..=MAX_HEADERS).map(|i| format!("X-{i}: 1\r\n")).collect();
        let head = format!("GET / HTTP/1.1\r\n{many}\r\n");
        assert_eq!(refuse(head.as_bytes()).map(|r| r.0), Some(431));
    }
}
