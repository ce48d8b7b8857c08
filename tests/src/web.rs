//! A browser's way in, from Rust: a WebSocket to `/ws` with the page's side of the Noise
//! handshake (docs/web.md), and raw HTTP requests for the web listener's tests.

use std::future::Future;
use std::net::SocketAddr;
use std::time::Duration;

use anyhow::{anyhow, bail, Context, Result};
use breakshot_shared::protocol::web::{
    MAX_NOISE_MESSAGE, MAX_NOISE_PAYLOAD, NOISE_PATTERN, NOISE_PROLOGUE, WS_PATH,
};
use breakshot_shared::protocol::{
    decode_payload, encode_frame, split_frame, ClientMessage, ServerMessage,
};
use futures_util::{SinkExt, StreamExt};
use snow::{HandshakeState, TransportState};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::WebSocketStream;

use crate::{Reads, PATIENCE};

/// A WebSocket to a server's `/ws`, upgraded but with no Noise message sent yet.
pub type Socket = WebSocketStream<TcpStream>;

/// Opens a WebSocket to `addr`'s `/ws`.
pub async fn open(addr: SocketAddr) -> Result<Socket> {
    let tcp = TcpStream::connect(addr).await?;
    let url = format!("ws://{addr}{WS_PATH}");
    let (ws, _) = tokio::time::timeout(PATIENCE, tokio_tungstenite::client_async(url, tcp))
        .await
        .map_err(|_| anyhow!("no WebSocket upgrade"))??;
    Ok(ws)
}

/// The page's side of the handshake, ready to write message 1, for the server key `key`.
pub fn initiator(key: &[u8; 32]) -> Result<HandshakeState> {
    Ok(snow::Builder::new(NOISE_PATTERN.parse()?)
        .remote_public_key(key)?
        .prologue(NOISE_PROLOGUE)?
        .build_initiator()?)
}

/// The next message the server sends, or `None` once it closed the socket (a close frame,
/// the end of the stream or an error); an error only if nothing comes within [`PATIENCE`].
pub async fn next(ws: &mut Socket) -> Result<Option<Message>> {
    loop {
        let got = tokio::time::timeout(PATIENCE, ws.next())
            .await
            .map_err(|_| anyhow!("the server neither sent nor closed"))?;
        match got {
            Some(Ok(Message::Ping(_) | Message::Pong(_))) => continue,
            Some(Ok(Message::Close(_))) | None | Some(Err(_)) => return Ok(None),
            Some(Ok(m)) => return Ok(Some(m)),
        }
    }
}

/// A game connection over a WebSocket, past its Noise handshake.
pub struct WebPlayer {
    /// The socket.
    pub ws: Socket,
    noise: TransportState,
    buf: Vec<u8>,
}

impl WebPlayer {
    /// Connects and runs the Noise handshake with server key `key`.
    pub async fn connect(addr: SocketAddr, key: &[u8; 32]) -> Result<WebPlayer> {
        let mut ws = open(addr).await?;
        let mut hs = initiator(key)?;
        let mut out = vec![0u8; MAX_NOISE_MESSAGE];
        let len = hs.write_message(&[], &mut out)?;
        ws.send(Message::binary(out[..len].to_vec())).await?;
        let Some(Message::Binary(reply)) = next(&mut ws).await? else {
            bail!("no Noise message 2");
        };
        let mut payload = vec![0u8; MAX_NOISE_MESSAGE];
        let n = hs.read_message(&reply, &mut payload)?;
        if n != 0 {
            bail!("Noise message 2 carries {n} bytes");
        }
        Ok(WebPlayer {
            ws,
            noise: hs.into_transport_mode()?,
            buf: Vec::new(),
        })
    }

    /// Connects and says hello; the server's `Welcome` has been read.
    pub async fn hello(addr: SocketAddr, key: &[u8; 32]) -> Result<WebPlayer> {
        let mut p = WebPlayer::connect(addr, key).await?;
        let me = breakshot_client::net::fresh_identity();
        p.send(&crate::hello_of(&me)?).await?;
        let challenge = p.recv().await?;
        p.send(&crate::prove_of(&me, &challenge)?).await?;
        match p.recv().await? {
            ServerMessage::Welcome { .. } => Ok(p),
            other => bail!("expected Welcome, got {other:?}"),
        }
    }

    /// Encrypts `bytes` (any piece of the stream, at most one Noise payload) as one message.
    pub async fn send_bytes(&mut self, bytes: &[u8]) -> Result<()> {
        let mut out = vec![0u8; MAX_NOISE_MESSAGE];
        for piece in bytes.chunks(MAX_NOISE_PAYLOAD) {
            let len = self.noise.write_message(piece, &mut out)?;
            self.ws.send(Message::binary(out[..len].to_vec())).await?;
        }
        Ok(())
    }

    /// Sends one message as a frame, split over two Noise messages when it has more than one
    /// byte (the server must not care where the pieces break).
    pub async fn send(&mut self, msg: &ClientMessage) -> Result<()> {
        let frame = encode_frame(msg)?;
        let (a, b) = frame.split_at(frame.len() / 2);
        self.send_bytes(a).await?;
        self.send_bytes(b).await
    }

    /// The next message, within [`PATIENCE`].
    pub async fn recv(&mut self) -> Result<ServerMessage> {
        loop {
            if let Some((payload, used)) = split_frame(&self.buf)? {
                let msg = decode_payload(payload)?;
                self.buf.drain(..used);
                return Ok(msg);
            }
            let Some(msg) = next(&mut self.ws).await? else {
                bail!("the server closed the WebSocket");
            };
            let Message::Binary(cipher) = msg else {
                bail!("a message that is not binary: {msg:?}");
            };
            let mut plain = vec![0u8; MAX_NOISE_MESSAGE];
            let n = self
                .noise
                .read_message(&cipher, &mut plain)
                .context("decrypting")?;
            self.buf.extend_from_slice(&plain[..n]);
        }
    }
}

impl Reads for WebPlayer {
    fn recv(&mut self) -> impl Future<Output = Result<ServerMessage>> + Send {
        WebPlayer::recv(self)
    }
}

/// An HTTP response as read back: the status code, the head's lines, the body.
#[derive(Debug)]
pub struct Response {
    /// The status code.
    pub status: u16,
    /// Header names (lowercase) and values.
    pub headers: Vec<(String, String)>,
    /// Everything after the head.
    pub body: Vec<u8>,
}

impl Response {
    /// The value of header `name` (lowercase).
    pub fn header(&self, name: &str) -> Option<&str> {
        breakshot_server::web::http::header(&self.headers, name)
    }
}

/// Sends `request` as it is and reads the whole response until the server closes.
pub async fn request(addr: SocketAddr, request: &[u8]) -> Result<Response> {
    let mut tcp = TcpStream::connect(addr).await?;
    tcp.write_all(request).await?;
    read_response(&mut tcp).await
}

/// Reads a response until the server closes, within [`PATIENCE`].
pub async fn read_response(tcp: &mut TcpStream) -> Result<Response> {
    let mut all = Vec::new();
    tokio::time::timeout(PATIENCE, tcp.read_to_end(&mut all))
        .await
        .map_err(|_| anyhow!("the server never finished its answer"))??;
    let end = all
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .ok_or_else(|| anyhow!("no response head in {:?}", String::from_utf8_lossy(&all)))?;
    let head = std::str::from_utf8(&all[..end])?;
    let mut lines = head.split("\r\n");
    let status = lines
        .next()
        .and_then(|l| l.split(' ').nth(1))
        .and_then(|c| c.parse().ok())
        .ok_or_else(|| anyhow!("no status in {head:?}"))?;
    let headers = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(n, v)| (n.trim().to_ascii_lowercase(), v.trim().to_string()))
        .collect();
    Ok(Response {
        status,
        headers,
        body: all[end + 4..].to_vec(),
    })
}

/// `GET target` with a Host header.
pub async fn get(addr: SocketAddr, target: &str) -> Result<Response> {
    request(
        addr,
        format!("GET {target} HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes(),
    )
    .await
}

/// Whether the server closed `tcp` (without an answer) within `limit`.
pub async fn closed_within(tcp: &mut TcpStream, limit: Duration) -> bool {
    let mut buf = [0u8; 256];
    matches!(
        tokio::time::timeout(limit, tcp.read(&mut buf)).await,
        Ok(Ok(0) | Err(_))
    )
}
