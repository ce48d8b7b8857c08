//! The one network client: connects by invite (the invite's addresses in order, retrying a
//! server that is not up yet), says `Hello`, remembers the seat token the server hands out,
//! and when a seated player's connection drops, connects again and takes the seat back with
//! `Rejoin` (going on to the next address when an instance says the game is played on
//! another). The window's
//! [`Session`](super::Session), the bot and the integration tests all drive this client;
//! none has a reconnect loop of its own.

use std::time::{Duration, Instant};

use breakshot_shared::protocol::limits::RECONNECT_WINDOW;
use breakshot_shared::protocol::{
    ClientMessage, ErrorCode, Invite, Role, RoomCode, SeatToken, ServerMessage,
};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;

use super::channel::{endpoint, Channel, NetError, Writer};

/// When and for how long the client connects again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reconnect {
    /// How long the first connection is retried (a server still starting, or restarting).
    pub first_for: Duration,
    /// How long a seated player whose connection dropped keeps trying to take the seat back.
    pub rejoin_for: Duration,
    /// The first pause between attempts; each failure doubles it, up to `max_pause`.
    pub pause: Duration,
    /// The longest pause between attempts.
    pub max_pause: Duration,
}

impl Default for Reconnect {
    /// What the game ships: a few seconds for the first connection, and a dropped seat
    /// retried for as long as the server holds it.
    fn default() -> Reconnect {
        Reconnect {
            first_for: Duration::from_secs(5),
            rejoin_for: RECONNECT_WINDOW,
            pause: Duration::from_millis(100),
            max_pause: Duration::from_secs(2),
        }
    }
}

impl Reconnect {
    /// One attempt, no retries: for tests that script every connection themselves.
    pub fn never() -> Reconnect {
        Reconnect {
            first_for: Duration::ZERO,
            rejoin_for: Duration::ZERO,
            ..Reconnect::default()
        }
    }

    /// Opens a connection, trying the invite's addresses in order from the one at `start`,
    /// again and again for `patience` with growing pauses. Returns it with the index of the
    /// address that answered. A server that answers and refuses us is final.
    async fn open(
        &self,
        ep: &quinn::Endpoint,
        invite: &Invite,
        start: usize,
        patience: Duration,
    ) -> Result<(Channel, usize), NetError> {
        let since = Instant::now();
        let mut pause = self.pause;
        loop {
            match Channel::open_from(ep, invite, start).await {
                Ok(c) => return Ok(c),
                // Refusals are final: retrying cannot change the answer.
                Err(e) if e.is_refusal() => return Err(e),
                Err(e) if since.elapsed() + pause > patience => return Err(e),
                Err(_) => {
                    tokio::time::sleep(pause).await;
                    pause = (pause * 2).min(self.max_pause);
                }
            }
        }
    }
}

/// What [`Client::recv`] gives.
#[derive(Clone, Debug, PartialEq)]
pub enum ClientEvent {
    /// A message from the server.
    Message(ServerMessage),
    /// The connection of a seated player dropped (with the reason); the client is
    /// connecting again to take the seat back.
    Reconnecting(String),
    /// Connected again; `Rejoin` is sent and the server's `Joined` follows.
    Reconnected,
}

/// One live connection: its writer, and its reader in a task of its own (reading a frame
/// is not cancel-safe; receiving from the channel is, so callers may `select!` on it).
struct Live {
    quic: quinn::Connection,
    writer: Writer,
    incoming: mpsc::Receiver<Result<ServerMessage, NetError>>,
    reader: JoinHandle<()>,
}

impl Live {
    fn new(conn: Channel) -> Live {
        let (quic, writer, mut reader) = conn.split();
        let (tx, incoming) = mpsc::channel(64);
        let reader = tokio::spawn(async move {
            loop {
                let msg = reader.recv().await;
                let lost = msg.is_err();
                if tx.send(msg).await.is_err() || lost {
                    return;
                }
            }
        });
        Live {
            quic,
            writer,
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

/// No connection, while the seat is being taken back.
struct Lost {
    /// Why the last connection ended.
    why: String,
    /// The last instance asked plays the game elsewhere: pause before asking the next, so
    /// instances that disagree for a moment (one still holds a dead one's room) are not
    /// hammered.
    pause_first: bool,
}

/// Taking a seat back, from the first loss until a `Rejoin` is answered other than "played
/// elsewhere".
struct Retry {
    since: Instant,
    /// The pause before asking again after a "played elsewhere"; doubles each time.
    pause: Duration,
}

/// A client of one server: see the module documentation.
pub struct Client {
    endpoint: quinn::Endpoint,
    invite: Invite,
    /// The index in the invite of the address connected to (or last connected to).
    at: usize,
    policy: Reconnect,
    live: Option<Live>,
    /// Set while there is no connection and the seat is being taken back.
    lost: Option<Lost>,
    /// Set while the seat is being taken back, connected or not.
    retry: Option<Retry>,
    /// The seat a `Rejoin` sent asks back, until the server answers it.
    asked: Option<SeatToken>,
    token: Option<SeatToken>,
    role: Option<Role>,
    room: Option<RoomCode>,
}

impl Client {
    /// Connects to the server `invite` names (retrying as `policy` says) and completes the
    /// handshake. Must be called inside a tokio runtime.
    pub async fn connect(invite: Invite, policy: Reconnect) -> Result<Client, NetError> {
        let endpoint = endpoint()?;
        let (conn, at) = policy.open(&endpoint, &invite, 0, policy.first_for).await?;
        Ok(Client {
            endpoint,
            invite,
            at,
            policy,
            live: Some(Live::new(conn)),
            lost: None,
            retry: None,
            asked: None,
            token: None,
            role: None,
            room: None,
        })
    }

    /// Sends a message. While the seat is being taken back there is no connection and the
    /// message is lost, as it would be on a dropped connection.
    pub async fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        if let ClientMessage::Rejoin { token } = msg {
            self.asked = Some(*token);
        }
        match &mut self.live {
            Some(live) => live.writer.send(msg).await,
            None => Err(NetError::Lost("reconnecting".into())),
        }
    }

    /// Sends raw bytes (to test how the server treats malformed frames).
    pub async fn send_raw(&mut self, bytes: &[u8]) -> Result<(), NetError> {
        match &mut self.live {
            Some(live) => live.writer.send_raw(bytes).await,
            None => Err(NetError::Lost("reconnecting".into())),
        }
    }

    /// The next event. A lost connection is an error, unless this client holds a seat and
    /// its policy lets it take the seat back: then [`ClientEvent::Reconnecting`] and, once
    /// connected again, [`ClientEvent::Reconnected`] come first. An instance that answers a
    /// `Rejoin` with [`ErrorCode::ServerBusy`] (the game is played on another instance of a
    /// server that has several) is treated the same way: the next address is asked.
    /// Cancel-safe.
    pub async fn recv(&mut self) -> Result<ClientEvent, NetError> {
        if let Some(lost) = &self.lost {
            let retry = self.retry.get_or_insert(Retry {
                since: Instant::now(),
                pause: self.policy.pause,
            });
            if lost.pause_first {
                tokio::time::sleep(retry.pause).await;
                retry.pause = (retry.pause * 2).min(self.policy.max_pause);
            }
            let left = self.policy.rejoin_for.saturating_sub(retry.since.elapsed());
            let why = lost.why.clone();
            let (conn, at) = self
                .policy
                .open(&self.endpoint, &self.invite, self.at, left)
                .await
                .map_err(|e| NetError::Lost(format!("{why}; reconnecting failed: {e}")))?;
            self.at = at;
            let mut live = Live::new(conn);
            if let Some(token) = self.token {
                live.writer.send(&ClientMessage::Rejoin { token }).await?;
                self.asked = Some(token);
            }
            self.live = Some(live);
            self.lost = None;
            return Ok(ClientEvent::Reconnected);
        }
        let Some(live) = &mut self.live else {
            return Err(NetError::Lost("the connection is closed".into()));
        };
        let end = match live.incoming.recv().await {
            Some(Ok(msg)) => {
                if let Some(token) = self.asked.take() {
                    if played_elsewhere(&msg) && self.may_retry() {
                        return Ok(self.ask_next_instance(token, &msg));
                    }
                    self.retry = None;
                }
                self.note(&msg);
                return Ok(ClientEvent::Message(msg));
            }
            Some(Err(e)) => e,
            None => NetError::Lost("the connection ended".into()),
        };
        self.live = None;
        match self.token {
            Some(_) if self.may_retry() => {
                let why = end.to_string();
                self.lost = Some(Lost {
                    why: why.clone(),
                    pause_first: false,
                });
                Ok(ClientEvent::Reconnecting(why))
            }
            _ => Err(end),
        }
    }

    /// Whether the policy lets this client connect again by itself.
    fn may_retry(&self) -> bool {
        !self.policy.rejoin_for.is_zero()
    }

    /// The instance connected to says another one plays the game of the seat `token` asked
    /// back: leaves it and starts asking the invite's next address.
    fn ask_next_instance(&mut self, token: SeatToken, answer: &ServerMessage) -> ClientEvent {
        self.live = None;
        self.token = Some(token);
        self.at = (self.at + 1) % self.invite.servers.len();
        let why = match answer {
            ServerMessage::Error { message, .. } => message.clone(),
            _ => "the game is played on another server instance".into(),
        };
        self.lost = Some(Lost {
            why: why.clone(),
            pause_first: true,
        });
        ClientEvent::Reconnecting(why)
    }

    /// Remembers the seat a `Joined` gave, to take it back after a drop.
    fn note(&mut self, msg: &ServerMessage) {
        if let ServerMessage::Joined {
            role,
            token,
            snapshot,
        } = msg
        {
            self.role = Some(*role);
            if token.is_some() {
                self.token = *token;
            }
            self.room = Some(snapshot.room.clone());
        }
    }

    /// The index in the invite of the address this client is (or was last) connected to.
    pub fn address_index(&self) -> usize {
        self.at
    }

    /// The seat token to take the seat back with, once seated.
    pub fn token(&self) -> Option<SeatToken> {
        self.token
    }

    /// Our role in the room joined last.
    pub fn role(&self) -> Option<Role> {
        self.role
    }

    /// The room joined last.
    pub fn room(&self) -> Option<&RoomCode> {
        self.room.as_ref()
    }

    /// The current QUIC connection, to close it or read why it closed (None while
    /// reconnecting).
    pub fn quic(&self) -> Option<&quinn::Connection> {
        self.live.as_ref().map(|l| &l.quic)
    }

    /// Closes the connection and waits at most `grace` for the close to reach the server,
    /// so the opponent hears at once that we left rather than after the idle timeout.
    pub async fn close(mut self, grace: Duration) {
        self.live = None;
        let _ = tokio::time::timeout(grace, self.endpoint.wait_idle()).await;
    }
}

/// The answer an instance gives to a `Rejoin` for a game another instance plays.
fn played_elsewhere(msg: &ServerMessage) -> bool {
    matches!(
        msg,
        ServerMessage::Error {
            code: ErrorCode::ServerBusy,
            ..
        }
    )
}
