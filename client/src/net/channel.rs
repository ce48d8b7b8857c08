//! One channel to a server (the framing under [`Client`](super::Client)): QUIC with a pinned certificate, one bidirectional stream,
//! `Hello` first, then framed messages both ways.

use std::net::SocketAddr;
use std::time::Duration;

use breakshot_shared::protocol::{
    decode_payload, encode_frame, payload_len, reference_hash, ClientMessage, Fingerprint,
    FrameError, Invite, ServerAddress, ServerMessage, HEADER_LEN, PROTOCOL_VERSION,
};
use thiserror::Error;

use super::pinned::client_config;

#[derive(Debug, Error)]
/// Why a connection failed or ended.
pub enum NetError {
    #[error("cannot resolve {0}")]
    /// The server's name did not resolve.
    Resolve(String),
    #[error("cannot connect: {0}")]
    /// No QUIC connection could be made.
    Connect(String),
    #[error(
        "this invite's fingerprint does not match the server: ask the host for a fresh invite"
    )]
    /// The server's certificate is not the one the invite names.
    WrongFingerprint,
    #[error("connection lost: {0}")]
    /// The connection dropped.
    Lost(String),
    #[error("the server refused us: {0}")]
    /// The server answered and refused us.
    Rejected(String),
    #[error("bad frame from the server: {0}")]
    /// A frame from the server could not be read.
    Frame(#[from] FrameError),
    #[error("the server sent {0} before Welcome")]
    /// The server's first answer was not `Welcome`.
    Handshake(String),
}

impl NetError {
    /// The server answered and will not have us (or is not the server the invite names):
    /// asking again cannot change the answer.
    pub fn is_refusal(&self) -> bool {
        matches!(self, NetError::Rejected(_) | NetError::WrongFingerprint)
    }
}

/// How long one address of several is given to answer before the next is tried (a handshake
/// takes a few round trips; an instance that is down never answers).
pub const ATTEMPT_LIMIT: Duration = Duration::from_secs(3);

/// A client endpoint for any number of connections.
pub fn endpoint() -> Result<quinn::Endpoint, NetError> {
    let any: SocketAddr = ([0, 0, 0, 0], 0).into();
    quinn::Endpoint::client(any).map_err(|e| NetError::Connect(e.to_string()))
}

/// One handshaken connection to a server.
pub struct Channel {
    conn: quinn::Connection,
    writer: Writer,
    reader: Reader,
}

/// The sending half of a connection.
pub struct Writer {
    send: quinn::SendStream,
}

/// The receiving half of a connection.
pub struct Reader {
    conn: quinn::Connection,
    recv: quinn::RecvStream,
}

impl Channel {
    /// Connects to the server the invite names, trusting only its fingerprint, and
    /// completes the handshake (protocol version and physics reference hash). The invite's
    /// addresses are tried in order.
    pub async fn open(endpoint: &quinn::Endpoint, invite: &Invite) -> Result<Channel, NetError> {
        Ok(Self::open_from(endpoint, invite, 0).await?.0)
    }

    /// [`Channel::open`] trying the invite's addresses in order from the one at `start`
    /// (wrapping round), giving each [`ATTEMPT_LIMIT`] while others remain. Returns the
    /// channel and the index of the address that answered. When none does, a refusal is
    /// reported before a failure to connect: it says more.
    pub async fn open_from(
        endpoint: &quinn::Endpoint,
        invite: &Invite,
        start: usize,
    ) -> Result<(Channel, usize), NetError> {
        let n = invite.servers.len();
        let mut failure = NetError::Connect("the invite names no server".into());
        for k in 0..n {
            let at = (start + k) % n;
            let attempt = Self::open_at(
                endpoint,
                &invite.servers[at],
                invite.fingerprint,
                PROTOCOL_VERSION,
            );
            let result = if k + 1 < n {
                tokio::time::timeout(ATTEMPT_LIMIT, attempt)
                    .await
                    .unwrap_or_else(|_| {
                        Err(NetError::Connect(format!(
                            "{} did not answer",
                            invite.servers[at]
                        )))
                    })
            } else {
                attempt.await
            };
            match result {
                Ok(c) => return Ok((c, at)),
                Err(e) if failure.is_refusal() && !e.is_refusal() => {}
                Err(e) => failure = e,
            }
        }
        Err(failure)
    }

    /// Connects to one address, trusting only `fingerprint`, and says `Hello` claiming
    /// `protocol` (another version than ours, to test refusals).
    pub async fn open_at(
        endpoint: &quinn::Endpoint,
        server: &ServerAddress,
        fingerprint: Fingerprint,
        protocol: u32,
    ) -> Result<Channel, NetError> {
        let physics = reference_hash().map_err(|e| NetError::Connect(e.to_string()))?;
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
        let mut c = Channel {
            writer: Writer { send },
            reader: Reader {
                conn: conn.clone(),
                recv,
            },
            conn,
        };
        // The server sees the stream only once something is written: say Hello at once.
        c.send(&ClientMessage::Hello { protocol, physics }).await?;
        match c.recv().await? {
            ServerMessage::Welcome { .. } => Ok(c),
            ServerMessage::Reject { reason } => Err(NetError::Rejected(reason)),
            other => Err(NetError::Handshake(format!("{other:?}"))),
        }
    }

    /// Sends one message.
    pub async fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        self.writer.send(msg).await
    }

    /// Receives one message (not cancel-safe: see [`Channel::split`]).
    pub async fn recv(&mut self) -> Result<ServerMessage, NetError> {
        self.reader.recv().await
    }

    /// Sends raw bytes (to test how the server treats malformed frames).
    pub async fn send_raw(&mut self, bytes: &[u8]) -> Result<(), NetError> {
        self.writer.send_raw(bytes).await
    }

    /// The QUIC connection, to close it or read why it closed.
    pub fn quic(&self) -> &quinn::Connection {
        &self.conn
    }

    /// Splits into halves that can be used from different tasks (reading is not
    /// cancel-safe, so a reader belongs in a task of its own rather than a `select!`).
    pub fn split(self) -> (quinn::Connection, Writer, Reader) {
        (self.conn, self.writer, self.reader)
    }
}

impl Writer {
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
}

impl Reader {
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

    fn reason(&self, fallback: String) -> String {
        self.conn.close_reason().map_or(fallback, |r| r.to_string())
    }
}
