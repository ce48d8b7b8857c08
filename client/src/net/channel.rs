//! One connection to one server address: QUIC with a pinned certificate and one
//! bidirectional stream ([`open_stream`], what the [`Client`](super::Client) asks for), and
//! [`Channel`], such a stream with the handshake done, for tools and tests that speak the
//! protocol message by message.

use std::net::SocketAddr;

use breakshot_shared::protocol::{
    decode_payload, encode_frame, payload_len, ClientMessage, Fingerprint, Invite, ServerAddress,
    ServerMessage, HEADER_LEN, PROTOCOL_VERSION,
};

use super::error::NetError;
use super::pinned::client_config;
use super::player::{answer_to_hello, hello, prove};

/// A client endpoint for any number of connections.
pub fn endpoint() -> Result<quinn::Endpoint, NetError> {
    let any: SocketAddr = ([0, 0, 0, 0], 0).into();
    quinn::Endpoint::client(any).map_err(|e| NetError::Connect(e.to_string()))
}

/// Socket buffers a shared endpoint asks for (the kernel may cap them, e.g. at
/// `net.core.rmem_max`), as the server's.
const SHARED_SOCKET_BUFFER: usize = 4 * 1024 * 1024;

/// A client endpoint meant to carry many connections at once (a load run's bots): one UDP
/// socket and one driver for all of them, its socket's buffers enlarged as the server's are,
/// so that a burst over many connections does not overflow them. Must be called inside a
/// tokio runtime.
pub fn shared_endpoint() -> Result<quinn::Endpoint, NetError> {
    let connect = |e: std::io::Error| NetError::Connect(e.to_string());
    let socket = std::net::UdpSocket::bind(SocketAddr::from(([0, 0, 0, 0], 0))).map_err(connect)?;
    let state = quinn::udp::UdpSocketState::new((&socket).into()).map_err(connect)?;
    for (what, result) in [
        (
            "receive",
            state.set_recv_buffer_size((&socket).into(), SHARED_SOCKET_BUFFER),
        ),
        (
            "send",
            state.set_send_buffer_size((&socket).into(), SHARED_SOCKET_BUFFER),
        ),
    ] {
        if let Err(e) = result {
            tracing::warn!(error = %e, "cannot enlarge a shared endpoint's UDP {what} buffer");
        }
    }
    quinn::Endpoint::new(
        quinn::EndpointConfig::default(),
        None,
        socket,
        std::sync::Arc::new(quinn::TokioRuntime),
    )
    .map_err(connect)
}

/// An open QUIC connection to a server and its one stream, before the handshake.
pub(crate) struct Stream {
    pub(crate) conn: quinn::Connection,
    pub(crate) send: quinn::SendStream,
    pub(crate) recv: quinn::RecvStream,
}

/// Connects to `server`, trusting only the certificate with `fingerprint`, and opens the
/// stream. The server sees the stream only once something is written: the caller's `Hello`.
pub(crate) async fn open_stream(
    endpoint: &quinn::Endpoint,
    server: &ServerAddress,
    fingerprint: Fingerprint,
) -> Result<Stream, NetError> {
    let addr = tokio::net::lookup_host(server.authority())
        .await
        .map_err(|_| NetError::Resolve(server.authority()))?
        .find(SocketAddr::is_ipv4)
        .ok_or_else(|| NetError::Resolve(server.authority()))?;
    let config = client_config(fingerprint).map_err(NetError::Connect)?;
    let conn = endpoint
        .connect_with(config, addr, "breakshot")
        .map_err(|e| NetError::Connect(e.to_string()))?
        .await
        .map_err(|e| {
            let why = e.to_string();
            // Our own verifier refused the certificate: the pinned fingerprint differs.
            if why.contains("invalid peer certificate") {
                NetError::WrongFingerprint
            } else {
                NetError::Connect(why)
            }
        })?;
    let (send, recv) = conn
        .open_bi()
        .await
        .map_err(|e| NetError::Lost(e.to_string()))?;
    Ok(Stream { conn, send, recv })
}

/// One handshaken connection to a server, read and written message by message.
pub struct Channel {
    conn: quinn::Connection,
    send: quinn::SendStream,
    recv: quinn::RecvStream,
}

impl Channel {
    /// Connects to the first address the invite names, trusting only its fingerprint, and
    /// completes the handshake (protocol version and physics reference hash).
    pub async fn open(endpoint: &quinn::Endpoint, invite: &Invite) -> Result<Channel, NetError> {
        Self::open_at(
            endpoint,
            invite.first(),
            invite.fingerprint,
            PROTOCOL_VERSION,
        )
        .await
    }

    /// Connects to one address, trusting only `fingerprint`, and says `Hello` claiming
    /// `protocol` (another version than ours, to test refusals).
    pub async fn open_at(
        endpoint: &quinn::Endpoint,
        server: &ServerAddress,
        fingerprint: Fingerprint,
        protocol: u32,
    ) -> Result<Channel, NetError> {
        let Stream { conn, send, recv } = open_stream(endpoint, server, fingerprint).await?;
        let mut c = Channel { conn, send, recv };
        let identity = super::keys::for_connection();
        let hello = hello(protocol, &identity)?;
        c.send(&hello).await?;
        match c.recv().await? {
            ServerMessage::Challenge { nonce } => c.send(&prove(&hello, &identity, &nonce)).await?,
            other => {
                answer_to_hello(other)?;
                return Err(NetError::Handshake("welcomed without a challenge".into()));
            }
        }
        answer_to_hello(c.recv().await?)?;
        Ok(c)
    }

    /// Sends one message.
    pub async fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        let frame = encode_frame(msg)?;
        self.send_raw(&frame).await
    }

    /// Sends raw bytes (to test how the server treats malformed frames).
    pub async fn send_raw(&mut self, bytes: &[u8]) -> Result<(), NetError> {
        self.send
            .write_all(bytes)
            .await
            .map_err(|e| NetError::Lost(e.to_string()))
    }

    /// Receives one message; not cancel-safe.
    pub async fn recv(&mut self) -> Result<ServerMessage, NetError> {
        let mut header = [0u8; HEADER_LEN];
        self.recv
            .read_exact(&mut header)
            .await
            .map_err(|e| NetError::Lost(self.reason(e.to_string())))?;
        let len = payload_len(header)?;
        let mut payload = vec![0u8; len];
        self.recv
            .read_exact(&mut payload)
            .await
            .map_err(|e| NetError::Lost(self.reason(e.to_string())))?;
        Ok(decode_payload(&payload)?)
    }

    /// The QUIC connection, to close it or read why it closed.
    pub fn quic(&self) -> &quinn::Connection {
        &self.conn
    }

    fn reason(&self, fallback: String) -> String {
        self.conn.close_reason().map_or(fallback, |r| r.to_string())
    }
}
