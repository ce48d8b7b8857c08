//! The native client's way in: a QUIC connection and the one bidirectional stream it opens,
//! run by [`conn::serve`] like any other transport.

use std::net::IpAddr;
use std::time::Instant;

use crate::conn::{self, Transport, Wiring, CLOSE_PROTOCOL};
use crate::limits::Limits;
use crate::tls::IDLE_TIMEOUT;

/// A QUIC connection as a [`Transport`].
pub struct QuicLink(pub quinn::Connection);

impl Transport for QuicLink {
    type Send = quinn::SendStream;

    fn remote_ip(&self) -> IpAddr {
        self.0.remote_address().ip()
    }

    fn close(&self, code: u32, reason: &str) {
        self.0.close(code.into(), reason.as_bytes());
    }

    fn last_heard(&self, now: Instant) -> Instant {
        last_heard(&self.0, now)
    }

    /// Finishes the stream and waits for the peer to acknowledge all of it (or stop it).
    async fn finish(&self, send: &mut quinn::SendStream) {
        let _ = send.finish();
        let _ = send.stopped().await;
    }
}

/// When `connection` last heard its peer, as far as `now` knows: one that timed out had heard
/// nothing for the idle timeout (its peer's keep-alives stopped then); any other end is seen
/// as it happens.
pub fn last_heard(connection: &quinn::Connection, now: Instant) -> Instant {
    match connection.close_reason() {
        Some(quinn::ConnectionError::TimedOut) => now.checked_sub(IDLE_TIMEOUT).unwrap_or(now),
        _ => now,
    }
}

/// Runs one QUIC connection to its end: waits up to `open_timeout` for the client's stream
/// (closing the connection without one), then serves it.
pub async fn serve(wiring: Wiring, connection: quinn::Connection, limits: &Limits) {
    let Ok(Ok((send, recv))) =
        tokio::time::timeout(limits.open_timeout, connection.accept_bi()).await
    else {
        connection.close(CLOSE_PROTOCOL.into(), b"no stream opened");
        return;
    };
    let link = QuicLink(connection);
    conn::serve(wiring, &link, recv, send, limits).await;
}
