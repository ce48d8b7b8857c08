//! The async driver of the [`PlayerCore`]: quinn on tokio, for the window's network thread
//! ([`Session`](super::Session)), the bot and the integration tests. It opens the
//! connections the core asks for, moves bytes both ways and tells the core the time; every
//! decision (the handshake, the addresses in order, retries, taking the seat back) is the
//! core's.

use std::future::Future;
use std::pin::Pin;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::{
    ClientMessage, Identity, Invite, Role, RoomCode, SeatToken, ServerMessage,
};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;

use super::channel::{endpoint, open_stream, Stream};
use super::error::NetError;
use super::player::{Action, Entry, PlayerCore, PlayerEvent, Reconnect, Seating};

/// What [`Client::recv`] gives.
#[derive(Clone, Debug, PartialEq)]
pub enum ClientEvent {
    /// A message from the server.
    Message(ServerMessage),
    /// The seat remembered is gone: forget it.
    SeatGone,
    /// The connection of a seated player dropped (with the reason); the client is
    /// connecting again to take the seat back.
    Reconnecting(String),
    /// Connected again; `Rejoin` is sent and the server's `Joined` follows.
    Reconnected,
}

/// One live connection: its sending half, and its receiving half in a task of its own
/// (reading is not cancel-safe; receiving from the channel is, so callers may `select!`).
struct Live {
    quic: quinn::Connection,
    send: quinn::SendStream,
    /// The bytes read, each with when its read returned: the stream's chunks as quinn
    /// received them, not copied (a load run's thousands of connections would each keep a
    /// buffer and copy every read into a new one).
    incoming: mpsc::Receiver<Result<(Instant, quinn::Chunk), NetError>>,
    reader: JoinHandle<()>,
}

impl Live {
    fn new(stream: Stream) -> Live {
        let Stream {
            conn,
            send,
            mut recv,
        } = stream;
        let (tx, incoming) = mpsc::channel(64);
        let quic = conn.clone();
        let reader = tokio::spawn(async move {
            loop {
                let read = match recv.read_chunk(usize::MAX, true).await {
                    Ok(Some(chunk)) => Ok((Instant::now(), chunk)),
                    Ok(None) => Err(NetError::Lost("the connection ended".into())),
                    Err(e) => Err(NetError::Lost(
                        conn.close_reason().map_or(e.to_string(), |r| r.to_string()),
                    )),
                };
                let lost = read.is_err();
                if tx.send(read).await.is_err() || lost {
                    return;
                }
            }
        });
        Live {
            quic,
            send,
            incoming,
            reader,
        }
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        self.reader.abort();
        self.quic.close(0u32.into(), b"bye");
    }
}

type Opening = Pin<Box<dyn Future<Output = Result<Stream, NetError>> + Send>>;

/// A client of one server: the core with quinn under it.
pub struct Client {
    endpoint: quinn::Endpoint,
    /// The endpoint may carry other clients' connections ([`Client::connect_on`]).
    shared: bool,
    core: PlayerCore,
    /// When this client started: the core's clock counts from here.
    origin: Instant,
    live: Option<Live>,
    /// The connection being opened, when the core asked for one.
    opening: Option<Opening>,
    /// When the last bytes handed to the core were read off the connection.
    read_at: Option<Instant>,
}

impl Client {
    /// Connects to the server `invite` names (retrying as `policy` says) and completes the
    /// handshake. Must be called inside a tokio runtime.
    pub async fn connect(invite: Invite, policy: Reconnect) -> Result<Client, NetError> {
        Self::connect_on(None, invite, policy).await
    }

    /// [`Client::connect`] as the player `identity`.
    pub async fn connect_as(
        invite: Invite,
        policy: Reconnect,
        identity: Identity,
    ) -> Result<Client, NetError> {
        Self::connect_through(endpoint()?, false, invite, policy, identity).await
    }

    /// [`Client::connect`] through `endpoint` when one is given, which other connections may
    /// share (a load run's bots: a few UDP sockets for thousands of connections, rather than
    /// one each); without, through an endpoint of its own. Closing a client on a shared
    /// endpoint does not wait for the endpoint to go idle, since its other connections keep it
    /// busy; the endpoint's driver sends the close.
    pub async fn connect_on(
        endpoint: Option<quinn::Endpoint>,
        invite: Invite,
        policy: Reconnect,
    ) -> Result<Client, NetError> {
        let identity = super::keys::for_connection();
        match endpoint {
            Some(shared) => Self::connect_through(shared, true, invite, policy, identity).await,
            None => Self::connect_as(invite, policy, identity).await,
        }
    }

    /// Connects through `endpoint`, which other connections share when `shared` says so.
    async fn connect_through(
        endpoint: quinn::Endpoint,
        shared: bool,
        invite: Invite,
        policy: Reconnect,
        identity: Identity,
    ) -> Result<Client, NetError> {
        let origin = Instant::now();
        let core = PlayerCore::new(invite, policy, identity, Duration::ZERO);
        let mut client = Client {
            endpoint,
            shared,
            core,
            origin,
            live: None,
            opening: None,
            read_at: None,
        };
        loop {
            match client.core.poll_event() {
                Some(PlayerEvent::Connected) => return Ok(client),
                Some(PlayerEvent::Closed(e)) => return Err(e),
                Some(_) => {}
                None => client.step().await,
            }
        }
    }

    /// Enters a room as `entry` says; the core carries out its fallbacks.
    pub async fn enter(&mut self, entry: Entry) {
        self.core.enter(entry);
        self.flush().await;
    }

    /// Sends a message. While the seat is being taken back there is no connection and the
    /// message is lost, as it would be on a dropped connection.
    pub async fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        self.core.send(msg)?;
        self.flush().await;
        Ok(())
    }

    /// Sends raw bytes (to test how the server treats malformed frames).
    pub async fn send_raw(&mut self, bytes: &[u8]) -> Result<(), NetError> {
        self.core.send_raw(bytes)?;
        self.flush().await;
        Ok(())
    }

    /// The next event. A lost connection is an error, unless this client holds a seat and
    /// its policy lets it take the seat back: then [`ClientEvent::Reconnecting`] and, once
    /// connected again, [`ClientEvent::Reconnected`] come first. Cancel-safe.
    pub async fn recv(&mut self) -> Result<ClientEvent, NetError> {
        loop {
            match self.core.poll_event() {
                Some(PlayerEvent::Message(msg)) => return Ok(ClientEvent::Message(msg)),
                Some(PlayerEvent::SeatGone) => return Ok(ClientEvent::SeatGone),
                Some(PlayerEvent::Reconnecting(why)) => return Ok(ClientEvent::Reconnecting(why)),
                Some(PlayerEvent::Reconnected) => return Ok(ClientEvent::Reconnected),
                Some(PlayerEvent::Closed(e)) => return Err(e),
                Some(PlayerEvent::Connected | PlayerEvent::Seated(_)) => {}
                None if self.core.is_closed() => {
                    return Err(NetError::Lost("the connection is closed".into()))
                }
                None => self.step().await,
            }
        }
    }

    /// Carries out what the core asks, then waits for the next thing to tell it: the
    /// connection opened or failed, bytes, or the time it named.
    async fn step(&mut self) {
        self.flush().await;
        if self.core.has_events() || self.core.is_closed() {
            return;
        }
        let deadline = self.core.timeout().map(|t| self.origin + t);
        let sleep = async {
            match deadline {
                Some(at) => tokio::time::sleep_until(at.into()).await,
                None => std::future::pending().await,
            }
        };
        let (opening_slot, live_slot) = (&mut self.opening, &mut self.live);
        let opening = async {
            match opening_slot {
                Some(o) => o.await,
                None => std::future::pending().await,
            }
        };
        let incoming = async {
            match live_slot {
                Some(live) => live.incoming.recv().await,
                None => std::future::pending().await,
            }
        };
        enum Woke {
            Opened(Result<Stream, NetError>),
            Read(Option<Result<(Instant, quinn::Chunk), NetError>>),
            Time,
        }
        let woke = tokio::select! {
            r = opening => Woke::Opened(r),
            r = incoming => Woke::Read(r),
            _ = sleep => Woke::Time,
        };
        let now = self.origin.elapsed();
        match woke {
            Woke::Opened(result) => {
                self.opening = None;
                match result {
                    Ok(stream) => {
                        self.live = Some(Live::new(stream));
                        self.core.opened(now);
                    }
                    Err(e) => self.core.failed(e, now),
                }
            }
            Woke::Read(Some(Ok((at, chunk)))) => {
                self.read_at = Some(at);
                self.core.received(&chunk.bytes, now);
            }
            Woke::Read(Some(Err(e))) => {
                self.live = None;
                self.core.failed(e, now);
            }
            Woke::Read(None) => {
                self.live = None;
                self.core
                    .failed(NetError::Lost("the connection ended".into()), now);
            }
            Woke::Time => self.core.handle_timeout(now),
        }
        self.flush().await;
    }

    /// Does what the core asked of the transport and writes its frames.
    async fn flush(&mut self) {
        while let Some(action) = self.core.poll_action() {
            match action {
                Action::Open {
                    server,
                    fingerprint,
                    ..
                } => {
                    let endpoint = self.endpoint.clone();
                    self.live = None;
                    self.opening = Some(Box::pin(async move {
                        open_stream(&endpoint, &server, fingerprint).await
                    }));
                }
                Action::Close => {
                    self.live = None;
                    self.opening = None;
                }
            }
        }
        while let Some(frame) = self.core.poll_transmit() {
            let Some(live) = &mut self.live else {
                continue;
            };
            if let Err(e) = live.send.write_all(&frame).await {
                // The reader hears of the loss too; what was queued behind it is lost
                // with the connection.
                tracing::debug!(error = %e, "writing to the server failed");
                break;
            }
        }
    }

    /// When the bytes that ended the last message received were read off the connection:
    /// the time since is what this process made the message wait (its runtime busy with
    /// other work, a load run's other connections).
    pub fn read_at(&self) -> Option<Instant> {
        self.read_at
    }

    /// The seat held, as the server last said.
    pub fn seating(&self) -> &Seating {
        self.core.seating()
    }

    /// The index in the invite of the address this client is (or was last) connected to.
    pub fn address_index(&self) -> usize {
        self.core.address_index()
    }

    /// The seat token to take the seat back with, once seated.
    pub fn token(&self) -> Option<SeatToken> {
        self.core.seating().token
    }

    /// Our role in the room joined last.
    pub fn role(&self) -> Option<Role> {
        self.core.seating().role
    }

    /// The room joined last.
    pub fn room(&self) -> Option<&RoomCode> {
        self.core.seating().room.as_ref()
    }

    /// The current QUIC connection, to close it or read why it closed (None while
    /// reconnecting).
    pub fn quic(&self) -> Option<&quinn::Connection> {
        self.live.as_ref().map(|l| &l.quic)
    }

    /// Closes the connection and waits at most `grace` for the close to reach the server,
    /// so the opponent hears at once that we left rather than after the idle timeout. On a
    /// shared endpoint ([`Client::connect_on`]) it does not wait: the endpoint's driver,
    /// kept running by its other connections, sends the close.
    pub async fn close(mut self, grace: Duration) {
        self.core.leave();
        self.live = None;
        if !self.shared {
            let _ = tokio::time::timeout(grace, self.endpoint.wait_idle()).await;
        }
    }
}
