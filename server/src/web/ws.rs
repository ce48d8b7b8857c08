//! The browser's fallback way in: a WebSocket (`GET /ws`) whose binary messages are Noise
//! messages (`Noise_NK_25519_ChaChaPoly_BLAKE2s`, docs/web.md). After the handshake a pump
//! task decrypts what the page sends into one end of an in-memory pipe and encrypts what
//! comes out of it; the other end is the byte stream [`conn::serve`] runs, so the hub treats
//! the page exactly like a native connection.

use std::net::IpAddr;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use breakshot_shared::protocol::web::{
    MAX_NOISE_MESSAGE, MAX_NOISE_PAYLOAD, NOISE_PATTERN, NOISE_PROLOGUE,
};
use futures_util::{SinkExt, StreamExt};
use snow::TransportState;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, DuplexStream, WriteHalf};
use tokio::sync::{watch, Notify};
use tokio_tungstenite::tungstenite::protocol::frame::coding::CloseCode;
use tokio_tungstenite::tungstenite::protocol::{CloseFrame, Role, WebSocketConfig};
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::WebSocketStream;

use super::key::NoiseKey;
use crate::conn::{Transport, CLOSE_NORMAL};
use crate::tls::IDLE_TIMEOUT;

/// How often the server pings a quiet page (browsers answer pings by themselves), so a page
/// that vanished is noticed after [`IDLE_TIMEOUT`] as a QUIC peer would be.
const PING_EVERY: Duration = breakshot_shared::protocol::limits::KEEP_ALIVE;

/// How long a close frame may take to go out before the socket is dropped anyway.
const CLOSE_TIMEOUT: Duration = Duration::from_secs(1);

/// The pipe between the pump and the connection: a little more than one Noise message.
const PIPE: usize = 2 * MAX_NOISE_MESSAGE;

/// WebSocket limits: no message or frame over one Noise message.
pub fn config() -> WebSocketConfig {
    WebSocketConfig::default()
        .max_message_size(Some(MAX_NOISE_MESSAGE))
        .max_frame_size(Some(MAX_NOISE_MESSAGE))
}

/// Wraps an upgraded stream (with any bytes read past the request head) as a server-side
/// WebSocket.
pub async fn websocket<S>(stream: S, early: Vec<u8>) -> WebSocketStream<S>
where
    S: AsyncRead + AsyncWrite + Unpin,
{
    WebSocketStream::from_partially_read(stream, early, Role::Server, Some(config())).await
}

/// Runs the responder's side of the Noise handshake (the caller bounds its time): message 1
/// `-> e, es` with an empty payload, message 2 `<- e, ee` with an empty payload.
pub async fn handshake<S>(
    ws: &mut WebSocketStream<S>,
    key: &NoiseKey,
) -> Result<TransportState, String>
where
    S: AsyncRead + AsyncWrite + Unpin,
{
    let params = NOISE_PATTERN
        .parse()
        .map_err(|e| format!("Noise pattern: {e}"))?;
    let mut noise = snow::Builder::new(params)
        .local_private_key(&key.private)
        .and_then(|b| b.prologue(NOISE_PROLOGUE))
        .and_then(|b| b.build_responder())
        .map_err(|e| format!("Noise setup: {e}"))?;
    let first = loop {
        match ws.next().await {
            Some(Ok(Message::Binary(b))) => break b,
            Some(Ok(Message::Ping(_) | Message::Pong(_))) => continue,
            Some(Ok(Message::Text(_))) => return Err("a text message".into()),
            Some(Ok(_)) | None => return Err("closed in the handshake".into()),
            Some(Err(e)) => return Err(format!("WebSocket: {e}")),
        }
    };
    let mut payload = vec![0u8; MAX_NOISE_MESSAGE];
    let n = noise
        .read_message(&first, &mut payload)
        .map_err(|e| format!("Noise message 1: {e}"))?;
    if n != 0 {
        return Err("Noise message 1 carries a payload".into());
    }
    let mut out = vec![0u8; MAX_NOISE_MESSAGE];
    let len = noise
        .write_message(&[], &mut out)
        .map_err(|e| format!("Noise message 2: {e}"))?;
    out.truncate(len);
    ws.send(Message::binary(out))
        .await
        .map_err(|e| format!("WebSocket: {e}"))?;
    noise
        .into_transport_mode()
        .map_err(|e| format!("Noise: {e}"))
}

/// What the pump and the connection share.
#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    /// The connection asked to close (the reason is in `state`).
    close: Notify,
    /// The pump has sent everything the connection wrote before finishing.
    flushed: Notify,
}

#[derive(Default)]
struct State {
    close: Option<(u32, String)>,
    last_heard: Option<Instant>,
    timed_out: bool,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // Plain values, valid even if a holder panicked.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn heard(&self) {
        self.lock().last_heard = Some(Instant::now());
    }
}

/// A Noise-encrypted WebSocket as a [`Transport`]; made by [`start`].
pub struct WsLink {
    ip: IpAddr,
    shared: Arc<Shared>,
}

impl Transport for WsLink {
    type Send = WriteHalf<DuplexStream>;

    fn remote_ip(&self) -> IpAddr {
        self.ip
    }

    fn close(&self, code: u32, reason: &str) {
        let mut state = self.shared.lock();
        if state.close.is_none() {
            state.close = Some((code, reason.to_string()));
            self.shared.close.notify_one();
        }
    }

    /// A page that answered no ping for the idle timeout was last heard when it last sent
    /// anything; any other end is seen as it happens.
    fn last_heard(&self, now: Instant) -> Instant {
        let state = self.shared.lock();
        match (state.timed_out, state.last_heard) {
            (true, Some(at)) => at.min(now),
            (true, None) => now.checked_sub(IDLE_TIMEOUT).unwrap_or(now),
            _ => now,
        }
    }

    /// Ends the pipe, then waits for the pump to have sent what was in it.
    async fn finish(&self, send: &mut WriteHalf<DuplexStream>) {
        let _ = send.shutdown().await;
        self.shared.flushed.notified().await;
    }
}

/// Starts the pump for a WebSocket past its handshake; returns the link and the byte stream
/// for [`crate::conn::serve`]. The pump ends when the page goes, the connection closes, or
/// `stop` turns true (the server shutting down).
pub fn start<S>(
    ws: WebSocketStream<S>,
    noise: TransportState,
    ip: IpAddr,
    stop: watch::Receiver<bool>,
) -> (WsLink, DuplexStream)
where
    S: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let (ours, theirs) = tokio::io::duplex(PIPE);
    let shared = Arc::new(Shared::default());
    shared.heard();
    tokio::spawn(pump(ws, noise, theirs, shared.clone(), stop));
    (WsLink { ip, shared }, ours)
}

/// How the pump ends: quietly (the page went) or with a close frame.
enum End {
    Gone,
    Close(CloseCode, String),
}

async fn pump<S>(
    mut ws: WebSocketStream<S>,
    mut noise: TransportState,
    mut pipe: DuplexStream,
    shared: Arc<Shared>,
    mut stop: watch::Receiver<bool>,
) where
    S: AsyncRead + AsyncWrite + Unpin,
{
    let mut plain = vec![0u8; MAX_NOISE_MESSAGE];
    let mut cipher = vec![0u8; MAX_NOISE_MESSAGE];
    let mut outgoing = vec![0u8; MAX_NOISE_PAYLOAD];
    let mut finished = false;
    let mut ping = tokio::time::interval_at(tokio::time::Instant::now() + PING_EVERY, PING_EVERY);
    let end = loop {
        tokio::select! {
            msg = ws.next() => match msg {
                Some(Ok(Message::Binary(b))) => {
                    shared.heard();
                    let Ok(n) = noise.read_message(&b, &mut plain) else {
                        break End::Close(CloseCode::Policy, "bad Noise message".into());
                    };
                    if pipe.write_all(&plain[..n]).await.is_err() {
                        break End::Gone;
                    }
                }
                Some(Ok(Message::Ping(_) | Message::Pong(_))) => shared.heard(),
                Some(Ok(Message::Text(_))) => {
                    break End::Close(CloseCode::Unsupported, "binary messages only".into());
                }
                Some(Ok(Message::Frame(_))) => {}
                Some(Ok(Message::Close(_))) | None => break End::Gone,
                Some(Err(e)) => {
                    tracing::debug!(error = %e, "WebSocket ended");
                    break End::Gone;
                }
            },
            read = pipe.read(&mut outgoing), if !finished => match read {
                Ok(0) | Err(_) => {
                    finished = true;
                    let _ = ws.flush().await;
                    shared.flushed.notify_one();
                }
                Ok(n) => {
                    let Ok(len) = noise.write_message(&outgoing[..n], &mut cipher) else {
                        break End::Close(CloseCode::Error, "cannot encrypt".into());
                    };
                    let msg = Message::binary(cipher[..len].to_vec());
                    // A page that stops reading must not hold the pump past a close.
                    tokio::select! {
                        sent = ws.send(msg) => if sent.is_err() { break End::Gone },
                        _ = shared.close.notified() => break closing(&shared),
                        _ = stop.changed() => break shutting_down(),
                    }
                }
            },
            _ = shared.close.notified() => break closing(&shared),
            _ = stop.changed() => break shutting_down(),
            _ = ping.tick() => {
                let quiet = shared.lock().last_heard.is_none_or(|t| t.elapsed() >= IDLE_TIMEOUT);
                if quiet {
                    shared.lock().timed_out = true;
                    break End::Gone;
                }
                let _ = tokio::time::timeout(CLOSE_TIMEOUT, ws.send(Message::Ping(Default::default()))).await;
            }
        }
    };
    if let End::Close(code, reason) = end {
        let frame = CloseFrame {
            code,
            reason: short(&reason).into(),
        };
        let _ = tokio::time::timeout(CLOSE_TIMEOUT, ws.close(Some(frame))).await;
    }
    // Dropping the pipe ends the connection's reading, so it ends too.
}

/// The close the connection asked for, as a WebSocket close.
fn closing(shared: &Shared) -> End {
    let (code, reason) = shared
        .lock()
        .close
        .clone()
        .unwrap_or((CLOSE_NORMAL, String::new()));
    let code = if code == CLOSE_NORMAL {
        CloseCode::Normal
    } else {
        CloseCode::Policy
    };
    End::Close(code, reason)
}

fn shutting_down() -> End {
    End::Close(CloseCode::Away, "server shutting down".into())
}

/// A close reason cut to the 123 bytes a close frame holds, on a character boundary.
fn short(reason: &str) -> String {
    let mut end = reason.len().min(123);
    while !reason.is_char_boundary(end) {
        end -= 1;
    }
    reason[..end].to_string()
}
