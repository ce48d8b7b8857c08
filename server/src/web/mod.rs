//! The web listener (`--web DIR`): on TCP at the same address and port number as the QUIC
//! socket, HTTP/1.1 for the web client's files and `GET /ws` for the game over a
//! Noise-encrypted WebSocket (docs/web.md). Every TCP connection passes the same
//! [`crate::admission::Gate`] as a QUIC one, and a WebSocket past its Noise handshake is
//! served by [`crate::conn::serve`] like any other connection.

pub mod files;
pub mod http;
pub mod key;
pub mod ws;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

use breakshot_shared::protocol::web::{CERTIFICATE_HASH_PATH, WS_PATH};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::watch;
use tokio_tungstenite::tungstenite::handshake::derive_accept_key;

use crate::admission::Ticket;
use crate::limits::Limits;
use crate::stats::Stats;
use crate::webcert::WebCerts;
use crate::writer::Attach;
use http::{answer, HeadError};
use key::NoiseKey;

/// How long one file may take to reach a page (a bundle of a few megabytes on a slow link).
const FILE_TIMEOUT: Duration = Duration::from_secs(120);

/// How long an error answer gets to leave before the socket is closed.
const ANSWER_TIMEOUT: Duration = Duration::from_secs(2);

/// What the web listener serves.
pub struct Web {
    /// The web client's directory, canonical.
    pub root: PathBuf,
    /// The Noise key of the WebSocket.
    pub key: NoiseKey,
    /// The `h3` certificates, whose hashes [`CERTIFICATE_HASH_PATH`] answers.
    pub certs: WebCerts,
}

/// What one TCP connection needs from the server.
pub(crate) struct Visit {
    pub(crate) web: Arc<Web>,
    pub(crate) limits: Limits,
    pub(crate) stats: Arc<Stats>,
    pub(crate) stop: watch::Receiver<bool>,
    pub(crate) attach: Attach,
}

/// Serves one TCP connection to its end: one request, or a WebSocket game connection.
pub(crate) async fn serve(
    mut stream: TcpStream,
    peer: SocketAddr,
    mut ticket: Ticket,
    visit: Visit,
) {
    let _ = stream.set_nodelay(true);
    let deadline = tokio::time::Instant::now() + visit.limits.handshake_timeout;
    let head = match tokio::time::timeout_at(deadline, http::read_head(&mut stream)).await {
        Ok(Ok(head)) => head,
        Ok(Err(HeadError::Closed)) => return,
        Err(_) => {
            tracing::debug!(%peer, "HTTP request head too slow");
            return;
        }
        Ok(Err(HeadError::Malformed)) => {
            return refuse(stream, "400 Bad Request", "bad request", true).await;
        }
        Ok(Err(HeadError::TooLarge)) => {
            let status = "431 Request Header Fields Too Large";
            return refuse(stream, status, "request head too large", true).await;
        }
    };
    visit.stats.web_requests.fetch_add(1, Ordering::Relaxed);
    let with_body = head.method != "HEAD";
    if head.method != "GET" && head.method != "HEAD" {
        return refuse_with(
            stream,
            "405 Method Not Allowed",
            "GET or HEAD only",
            true,
            &[("Allow", "GET, HEAD")],
        )
        .await;
    }
    if head.has_body() {
        return refuse(
            stream,
            "413 Content Too Large",
            "no body expected",
            with_body,
        )
        .await;
    }
    let path = head.target.split(['?', '#']).next().unwrap_or("");
    if path == WS_PATH {
        if head.method != "GET" {
            return refuse(stream, "400 Bad Request", "a WebSocket needs GET", false).await;
        }
        return websocket(stream, peer, head, deadline, ticket, visit).await;
    }
    ticket.handshake_over();
    if path == CERTIFICATE_HASH_PATH {
        return certificate_hashes(stream, &visit.web.certs, with_body).await;
    }
    let file = match files::resolve(&visit.web.root, &head.target) {
        Ok(file) => file,
        Err(files::Refused::Bad) => {
            return refuse(stream, "400 Bad Request", "bad path", with_body).await
        }
        Err(files::Refused::Missing) => {
            return refuse(stream, "404 Not Found", "not found", with_body).await
        }
    };
    let sent = tokio::time::timeout(FILE_TIMEOUT, send_file(&mut stream, &file, with_body)).await;
    if !matches!(sent, Ok(Ok(()))) {
        tracing::debug!(%peer, file = %file.display(), "file not sent in full");
        return;
    }
    linger(stream).await;
}

async fn send_file(
    stream: &mut TcpStream,
    file: &std::path::Path,
    with_body: bool,
) -> std::io::Result<()> {
    let mut f = tokio::fs::File::open(file).await?;
    let len = f.metadata().await?.len();
    http::write_head(
        stream,
        "200 OK",
        files::content_type(file),
        len,
        &[("Cache-Control", "no-cache")],
    )
    .await?;
    if with_body {
        let copied = tokio::io::copy(&mut (&mut f).take(len), stream).await?;
        if copied != len {
            return Err(std::io::Error::other("the file shrank while being sent"));
        }
    }
    stream.flush().await
}

/// `GET /certificate.sha256`: the hashes a page passes as `serverCertificateHashes`, hex, one
/// per line, newest first; never cached, since they change with every rotation.
async fn certificate_hashes(mut stream: TcpStream, certs: &WebCerts, with_body: bool) {
    let hashes: Vec<String> = certs.hashes().iter().map(|h| h.to_string()).collect();
    let _ = tokio::time::timeout(
        ANSWER_TIMEOUT,
        answer(
            &mut stream,
            "200 OK",
            &hashes.join("\n"),
            with_body,
            &[("Cache-Control", "no-store")],
        ),
    )
    .await;
    linger(stream).await;
}

/// Answers a short error and closes.
async fn refuse(stream: TcpStream, status: &str, body: &str, with_body: bool) {
    refuse_with(stream, status, body, with_body, &[]).await;
}

/// Answers a short error with the `extra` header lines that say what would be accepted,
/// and closes.
async fn refuse_with(
    mut stream: TcpStream,
    status: &str,
    body: &str,
    with_body: bool,
    extra: &[(&str, &str)],
) {
    let _ = tokio::time::timeout(
        ANSWER_TIMEOUT,
        answer(&mut stream, status, body, with_body, extra),
    )
    .await;
    linger(stream).await;
}

/// Ends the connection after an answer: the sending side first, then what the peer still
/// sends is read away for a moment, so closing does not reset the connection before the
/// peer has read the answer.
async fn linger(mut stream: TcpStream) {
    let _ = stream.shutdown().await;
    let _ = tokio::time::timeout(ANSWER_TIMEOUT, async {
        let mut sink = [0u8; 4096];
        let mut left = 64 * 1024usize;
        while left > 0 {
            match stream.read(&mut sink).await {
                Ok(0) | Err(_) => break,
                Ok(n) => left = left.saturating_sub(n),
            }
        }
    })
    .await;
}

/// `GET /ws`: the upgrade, the Noise handshake (both by `deadline`), then the game.
async fn websocket(
    mut stream: TcpStream,
    peer: SocketAddr,
    head: http::Head,
    deadline: tokio::time::Instant,
    mut ticket: Ticket,
    visit: Visit,
) {
    let key = head.header("sec-websocket-key").map(str::trim);
    let upgrade = head.has_token("upgrade", "websocket") && head.has_token("connection", "upgrade");
    let (Some(key), true) = (key, upgrade) else {
        return refuse(
            stream,
            "400 Bad Request",
            "a WebSocket upgrade is expected",
            true,
        )
        .await;
    };
    if head.header("sec-websocket-version").map(str::trim) != Some("13") {
        return refuse_with(
            stream,
            "426 Upgrade Required",
            "WebSocket version 13 only",
            true,
            &[("Sec-WebSocket-Version", "13")],
        )
        .await;
    }
    let accept = derive_accept_key(key.as_bytes());
    let response = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Accept: {accept}\r\n\r\n"
    );
    let handshake = async {
        stream
            .write_all(response.as_bytes())
            .await
            .map_err(|e| e.to_string())?;
        let mut ws = ws::websocket(stream, head.rest).await;
        let noise = ws::handshake(&mut ws, &visit.web.key).await?;
        Ok::<_, String>((ws, noise))
    };
    let shaken = tokio::time::timeout_at(deadline, handshake).await;
    ticket.handshake_over();
    let (ws, noise) = match shaken {
        Ok(Ok(done)) => done,
        Ok(Err(why)) => {
            visit
                .stats
                .web_sockets_failed
                .fetch_add(1, Ordering::Relaxed);
            tracing::debug!(%peer, %why, "WebSocket handshake failed");
            return;
        }
        Err(_) => {
            visit
                .stats
                .web_sockets_failed
                .fetch_add(1, Ordering::Relaxed);
            tracing::debug!(%peer, "WebSocket handshake took too long");
            return;
        }
    };
    visit.stats.web_sockets.fetch_add(1, Ordering::Relaxed);
    let (link, pipe) = ws::start(ws, noise, peer.ip(), visit.stop.clone());
    let (recv, send) = tokio::io::split(pipe);
    tracing::debug!(%peer, "WebSocket connected");
    visit.attach.serve(&link, recv, send).await;
    drop(ticket);
}
