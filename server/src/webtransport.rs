//! WebTransport, the browser's way onto the QUIC endpoint. A connection that negotiated `h3`
//! goes through HTTP/3's SETTINGS and one CONNECT request (to [`WEBTRANSPORT_PATH`] only), then
//! hands the one bidirectional stream the page opens to [`crate::conn::serve`], which treats
//! it exactly as a native client's stream: same frames, limits and hub. Datagrams and any
//! other stream are never read (unread streams are bounded by the connection's receive window,
//! datagrams by quinn's datagram buffer).

use std::net::IpAddr;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::web::WEBTRANSPORT_PATH;
use breakshot_shared::protocol::WEB_ALPN;
use thiserror::Error;
use web_transport_quinn::http::StatusCode;
use web_transport_quinn::{RecvStream, Request, SendStream, Session};

use crate::conn::{self, Transport, Wiring, CLOSE_PROTOCOL};
use crate::limits::Limits;
use crate::quic;
use crate::stats::Stats;

/// How long a refused page gets to read its refusal before the connection is closed.
const REFUSAL_GRACE: Duration = Duration::from_secs(2);

/// A WebTransport session ready to play: the session (which closes with the connection) and
/// the stream the page opened.
pub struct WebStream {
    /// The session; closing it tells the page why.
    pub session: Session,
    /// Bytes for the page.
    pub send: SendStream,
    /// The page's bytes.
    pub recv: RecvStream,
}

/// Why an `h3` connection did not become a game stream.
#[derive(Debug, Error)]
pub enum Refused {
    /// The HTTP/3 exchange before the CONNECT failed or was malformed.
    #[error("WebTransport handshake: {0}")]
    Handshake(String),
    /// The CONNECT asked for another path (answered 404).
    #[error("no WebTransport endpoint at {0:?}")]
    Path(String),
    /// The session opened no bidirectional stream.
    #[error("no stream opened")]
    NoStream,
    /// The CONNECT and the stream did not both come within the open timeout.
    #[error("no stream opened in time")]
    TimedOut,
}

/// Takes a connection that negotiated `h3` as far as the page's stream, within
/// `open_timeout` (the time a native client has to open its stream). A refused connection
/// is closed before this returns.
pub async fn accept(conn: quinn::Connection, open_timeout: Duration) -> Result<WebStream, Refused> {
    let deadline = tokio::time::Instant::now() + open_timeout;
    let connect = async {
        let request = Request::accept(conn.clone())
            .await
            .map_err(|e| Refused::Handshake(e.to_string()))?;
        let path = request.url.path();
        if path != WEBTRANSPORT_PATH {
            // Shown in the log and the close reason: a hostile path is cut short.
            let path = path.chars().take(64).collect();
            if request.reject(StatusCode::NOT_FOUND).await.is_ok() {
                // The answer is on its way; closing now would drop it. The page closes
                // when it has read it.
                let _ = tokio::time::timeout(REFUSAL_GRACE, conn.closed()).await;
            }
            return Err(Refused::Path(path));
        }
        request
            .ok()
            .await
            .map_err(|e| Refused::Handshake(e.to_string()))
    };
    let session = match tokio::time::timeout_at(deadline, connect).await {
        Ok(Ok(session)) => session,
        Ok(Err(refused)) => return Err(close(&conn, refused)),
        Err(_) => return Err(close(&conn, Refused::TimedOut)),
    };
    // From here on the page has a session: it is told why it ends in the session's close.
    let refused = match tokio::time::timeout_at(deadline, session.accept_bi()).await {
        Ok(Ok((send, recv))) => {
            return Ok(WebStream {
                session,
                send,
                recv,
            })
        }
        Ok(Err(_)) => Refused::NoStream,
        Err(_) => Refused::TimedOut,
    };
    session.close(CLOSE_PROTOCOL, refused.to_string().as_bytes());
    Err(refused)
}

fn close(conn: &quinn::Connection, refused: Refused) -> Refused {
    conn.close(CLOSE_PROTOCOL.into(), refused.to_string().as_bytes());
    refused
}

/// Whether a connection's handshake settled on WebTransport's ALPN.
pub fn is_web(conn: &quinn::Connection) -> bool {
    conn.handshake_data()
        .and_then(|data| data.downcast::<quinn::crypto::rustls::HandshakeData>().ok())
        .and_then(|data| data.protocol)
        .is_some_and(|alpn| alpn == WEB_ALPN)
}

/// A WebTransport session as a [`Transport`].
pub struct SessionLink {
    session: Session,
    conn: quinn::Connection,
}

impl Transport for SessionLink {
    type Send = SendStream;

    fn remote_ip(&self) -> IpAddr {
        self.conn.remote_address().ip()
    }

    /// Closes the session (the page's `WebTransport.closed` gets the code and reason), then
    /// the connection; only the first close counts.
    fn close(&self, code: u32, reason: &str) {
        self.session.close(code, reason.as_bytes());
    }

    /// As for a native connection: the session lives on its QUIC connection.
    fn last_heard(&self, now: Instant) -> Instant {
        quic::last_heard(&self.conn, now)
    }

    /// Finishes the stream and waits for the page to acknowledge all of it (or stop it).
    async fn finish(&self, send: &mut SendStream) {
        let _ = send.finish();
        let _ = send.stopped().await;
    }
}

/// Runs one `h3` connection to its end: the WebTransport session and the page's stream
/// ([`accept`]), then the same [`conn::serve`] as a native connection.
pub async fn serve(wiring: Wiring, connection: quinn::Connection, limits: &Limits, stats: &Stats) {
    let stream = match accept(connection.clone(), limits.open_timeout).await {
        Ok(stream) => stream,
        Err(why) => {
            stats.webtransport_refused.fetch_add(1, Ordering::Relaxed);
            tracing::debug!(conn = wiring.id, %why, "WebTransport refused");
            return;
        }
    };
    stats.webtransport_sessions.fetch_add(1, Ordering::Relaxed);
    let link = SessionLink {
        session: stream.session,
        conn: connection,
    };
    conn::serve(wiring, &link, stream.recv, stream.send, limits).await;
}
