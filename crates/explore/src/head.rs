//! Every request, read whole and checked before the HTTP layer sees it, so
//! that one the HTTP layer would refuse on its own (a head that does not
//! parse, a bare carriage return, a `Content-Length` that is not one number,
//! a `Transfer-Encoding`, a head over [`MAX_HEAD`], a body over
//! [`MAX_BODY`], one that never ends) is answered like every other error:
//! JSON, `{"error": "…"}`, with the page's security headers. Each
//! connection carries one request (every answer says `Connection: close`,
//! [`crate::guard`]): the server is handed that request, and nothing the
//! client sends after it, not even its end of the stream (a client that
//! half-closes still gets its answer).

use crate::guard::{CONTENT_SECURITY_POLICY, MAX_BODY};
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

/// How long a client may take to send its request, head and body.
const REQUEST_WAIT: Duration = Duration::from_secs(10);

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

/// Reads `stream`'s request: the connection with the request put back in
/// front, or `None` where it was answered with an error (or closed before
/// its request ended).
async fn screen(mut stream: TcpStream) -> Option<Prefixed> {
    let mut read = Vec::with_capacity(1024);
    let read_all = tokio::time::timeout(REQUEST_WAIT, async {
        let mut chunk = [0u8; 4096];
        let mut whole = None;
        loop {
            if whole.is_none() {
                whole = match head(&read) {
                    Head::Partial => None,
                    Head::Refused(status, message) => return Ok(Err((status, message))),
                    Head::Whole(n) => Some(n),
                };
            }
            if let Some(n) = whole.filter(|&n| read.len() >= n) {
                return Ok(Ok(n));
            }
            match stream.read(&mut chunk).await {
                Ok(0) | Err(_) => return Err(()),
                Ok(n) => read.extend_from_slice(&chunk[..n]),
            }
        }
    })
    .await;
    let refusal = match read_all {
        Err(_) => (408, format!("the request did not arrive whole within {} s", REQUEST_WAIT.as_secs())),
        Ok(Err(())) => return None,
        Ok(Ok(Err(refused))) => refused,
        Ok(Ok(Ok(n))) => {
            // What follows the request (a second one) is not read.
            read.truncate(n);
            return Some(Prefixed { read, at: 0, stream });
        }
    };
    let (status, message) = refusal;
    let _ = stream.write_all(&answer(status, &message)).await;
    let _ = stream.shutdown().await;
    // What the client still sends is read and dropped for a moment: closed
    // with it unread, the connection would be reset, and the client might
    // lose the answer.
    let mut rest = [0u8; 4096];
    let _ = tokio::time::timeout(Duration::from_secs(1), async {
        while matches!(stream.read(&mut rest).await, Ok(n) if n > 0) {}
    })
    .await;
    None
}

/// What the bytes read so far hold.
#[derive(Debug, PartialEq)]
enum Head {
    /// Not yet a whole head.
    Partial,
    /// A refused request: its status and why.
    Refused(u16, String),
    /// A sound head: the request's length in bytes, head and body.
    Whole(usize),
}

/// What the start of `read` is: a head not yet whole, a refused one, or a
/// sound one and the length of its request.
fn head(read: &[u8]) -> Head {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut request = httparse::Request::new(&mut headers);
    let too_long = || Head::Refused(431, format!("the request's head is over {} KiB", MAX_HEAD / 1024));
    let n = match request.parse(read) {
        Err(httparse::Error::TooManyHeaders) => {
            return Head::Refused(431, format!("the request has more than {MAX_HEADERS} headers"));
        }
        Err(e) => return Head::Refused(400, format!("the request's head is not HTTP/1.1 ({e})")),
        Ok(httparse::Status::Partial) if read.len() > MAX_HEAD => return too_long(),
        Ok(httparse::Status::Partial) => return Head::Partial,
        Ok(httparse::Status::Complete(n)) if n > MAX_HEAD => return too_long(),
        Ok(httparse::Status::Complete(n)) => n,
    };
    let named = |name: &'static str| request.headers.iter().filter(move |h| h.name.eq_ignore_ascii_case(name));
    if named("transfer-encoding").next().is_some() {
        return Head::Refused(400, "Transfer-Encoding: not taken; send the body with its Content-Length".into());
    }
    let mut length = None;
    for h in named("content-length") {
        let text = String::from_utf8_lossy(h.value);
        let digits = text.trim();
        let number = (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())).then(|| digits.parse::<u64>());
        let Some(Ok(bytes)) = number else {
            return Head::Refused(400, format!("Content-Length: '{}' is not a number of bytes", short(&text)));
        };
        if length.is_some_and(|m| m != bytes) {
            return Head::Refused(400, "Content-Length: given twice, with two values".into());
        }
        length = Some(bytes);
    }
    match length.unwrap_or(0) {
        bytes if bytes > MAX_BODY as u64 => {
            Head::Refused(413, format!("Content-Length: {bytes} bytes; a body is at most {} KiB", MAX_BODY / 1024))
        }
        bytes => Head::Whole(n + bytes as usize),
    }
}

/// At most 40 characters of `text`.
fn short(text: &str) -> String {
    scene::excerpt(text, 40)
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

/// A connection whose request was read to check it: the request is read
/// again, and then nothing: the connection carries one request, and its
/// client's end of the stream (a half-close) must not end the answer.
pub(crate) struct Prefixed {
    read: Vec<u8>,
    at: usize,
    stream: TcpStream,
}

impl AsyncRead for Prefixed {
    fn poll_read(mut self: Pin<&mut Self>, _cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        let this = &mut *self;
        if this.at < this.read.len() {
            let n = buf.remaining().min(this.read.len() - this.at);
            buf.put_slice(&this.read[this.at..this.at + n]);
            this.at += n;
            return Poll::Ready(Ok(()));
        }
        // Never more: the server answers and closes (a read that never
        // ends, as no other request is to come).
        Poll::Pending
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

    /// Requests the HTTP layer would refuse without a JSON body are
    /// refused here with their reason; a sound one is measured whole.
    #[test]
    fn malformed_requests_are_refused_with_their_reason() {
        let ok = b"POST /api/zoom HTTP/1.1\r\nHost: 127.0.0.1:1\r\nContent-Length: 2\r\n\r\n{}";
        assert_eq!(head(ok), Head::Whole(ok.len()));
        assert_eq!(head(&ok[..ok.len() - 5]), Head::Partial);
        let lf = b"GET / HTTP/1.1\nHost: 127.0.0.1:1\n\n";
        assert_eq!(head(lf), Head::Whole(lf.len()));
        let cases: [(&[u8], u16, &str); 9] = [
            (b"GET /\rX HTTP/1.1\r\n\r\n", 400, "not HTTP/1.1"),
            (b"GET / HTTP/1.1\r\nHost: a\rb\r\n\r\n", 400, "not HTTP/1.1"),
            (b"GET /api/atlas\r\n", 400, "not HTTP/1.1"),
            (b"POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n", 400, "Content-Length"),
            (b"POST / HTTP/1.1\r\nContent-Length: +5\r\n\r\n", 400, "not a number"),
            (b"POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n", 400, "given twice"),
            (b"POST / HTTP/1.1\r\nTransfer-Encoding: identity\r\n\r\n", 400, "Transfer-Encoding"),
            (b"POST / HTTP/1.1\r\nContent-Length: 18446744073709551615\r\n\r\n", 413, "at most"),
            (b"POST / HTTP/1.1\r\nContent-Length: 65537\r\n\r\n", 413, "at most"),
        ];
        for (request, status, said) in cases {
            let Head::Refused(s, message) = head(request) else { panic!("{}", String::from_utf8_lossy(request)) };
            assert_eq!(s, status, "{message}");
            assert!(message.contains(said), "{message}");
        }
        let many: String = (0..=MAX_HEADERS).map(|i| format!("X-{i}: 1\r\n")).collect();
        let request = format!("GET / HTTP/1.1\r\n{many}\r\n");
        assert!(matches!(head(request.as_bytes()), Head::Refused(431, _)));
        // A head over the limit is refused however it arrives, whole or not.
        let long = format!("GET / HTTP/1.1\r\nX-A: {}\r\n\r\n", "a".repeat(MAX_HEAD));
        assert!(matches!(head(long.as_bytes()), Head::Refused(431, _)));
        assert!(matches!(head(&long.as_bytes()[..MAX_HEAD + 1]), Head::Refused(431, _)));
    }
}
