//! The player's side of the protocol as a state machine with no I/O and no clock, after
//! quinn-proto: it is told what the transport did (a connection opened, bytes arrived, the
//! connection failed) and what time it is, and it answers with what to do (open a
//! connection to an address, close it), the frames to send and the events to show.
//!
//! It owns every decision a player's connection makes: the handshake (`Hello`, the protocol
//! version, the physics and the player's key, proved by signing the server's challenge), the invite's addresses tried in order with growing pauses,
//! entering a room ([`Entry`]: join, take a remembered seat back and fall back when the
//! server no longer knows it, watch a full room), taking the seat back after a drop,
//! asking the next instance when one says the game is played on another, and the one
//! record of the seat held ([`Seating`]). The drivers only move bytes: [`Client`] (quinn on
//! tokio: the window's network thread, the bot, the tests) and [`Polled`] (any
//! [`Transport`], polled once a frame, for a front end without threads).
//!
//! [`Client`]: super::Client
//! [`Polled`]: super::Polled
//! [`Transport`]: super::Transport

mod entry;
mod opening;
#[cfg(test)]
mod tests;

use std::collections::VecDeque;
use std::time::Duration;

use breakshot_shared::protocol::limits::RECONNECT_WINDOW;
use breakshot_shared::protocol::{
    encode_frame, reference_hash, split_frame, ClientMessage, ErrorCode, Fingerprint, Identity,
    Invite, ServerAddress, ServerMessage, PROTOCOL_VERSION,
};

pub use entry::{Entry, Seating};
use opening::{Opening, Purpose, Then};

use super::error::NetError;

/// How long one address of several is given to answer (the transport's handshake and ours)
/// before the next is tried: an instance that is down never answers.
pub const ATTEMPT_LIMIT: Duration = Duration::from_secs(3);

/// When and for how long a player connects again.
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
}

/// What the core asks its driver to do with the transport.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Open a connection to `server` (the invite's address at `at`), trusting only the
    /// certificate with `fingerprint`; answer with [`PlayerCore::opened`] or
    /// [`PlayerCore::failed`].
    Open {
        /// The address's index in the invite.
        at: usize,
        /// The address.
        server: ServerAddress,
        /// The certificate to trust.
        fingerprint: Fingerprint,
    },
    /// Close the connection (or give up the attempt in progress).
    Close,
}

/// What the core tells its user.
#[derive(Clone, Debug, PartialEq)]
pub enum PlayerEvent {
    /// The first handshake succeeded: messages may be sent.
    Connected,
    /// A message from the server (every one after `Welcome` that the core did not answer
    /// itself).
    Message(ServerMessage),
    /// The seat taken or given back; the seat's token is in it, to remember.
    Seated(Seating),
    /// The seat remembered is gone (the server no longer knows its token, or its game ended
    /// while the player was away): forget it.
    SeatGone,
    /// The connection of a seated player dropped (with the reason); the core is connecting
    /// again to take the seat back.
    Reconnecting(String),
    /// Connected again; `Rejoin` is sent and the server's `Joined` follows.
    Reconnected,
    /// The connection ended for good (or never started), with the reason.
    Closed(NetError),
}

/// Where the connection stands.
enum Link {
    /// Trying the invite's addresses.
    Opening(Opening),
    /// The handshake is done: messages flow.
    Ready,
    /// Ended for good.
    Closed,
}

/// A player's connection to one server, without I/O: see the module documentation.
pub struct PlayerCore {
    invite: Invite,
    policy: Reconnect,
    /// The `Hello` this core says.
    hello: ClientMessage,
    /// Who the player is: the key `Hello` names and `Prove` signs with.
    identity: Identity,
    /// The index in the invite of the address connected to (or last connected to).
    at: usize,
    link: Link,
    seating: Seating,
    /// The entry waiting for the connection, or waiting for the server's answer.
    entry: Option<Entry>,
    /// Whether `entry` has been sent.
    entry_sent: bool,
    /// The seat a `Rejoin` sent asks back, until the server answers it.
    asked: Option<breakshot_shared::protocol::SeatToken>,
    /// Taking a seat back, from the first loss until a `Rejoin` is answered other than
    /// "played elsewhere": when it began and the pause before asking again.
    retry: Option<(Duration, Duration)>,
    /// Bytes received that do not make a whole frame yet.
    inbox: Vec<u8>,
    transmits: VecDeque<Vec<u8>>,
    actions: VecDeque<Action>,
    events: VecDeque<PlayerEvent>,
}

impl PlayerCore {
    /// A core that starts connecting to the server `invite` names at `now`, retrying as
    /// `policy` says.
    pub fn new(invite: Invite, policy: Reconnect, identity: Identity, now: Duration) -> PlayerCore {
        Self::claiming(invite, policy, identity, PROTOCOL_VERSION, now)
    }

    /// [`PlayerCore::new`] saying `Hello` with another protocol version than ours (to test
    /// refusals).
    pub fn claiming(
        invite: Invite,
        policy: Reconnect,
        identity: Identity,
        protocol: u32,
        now: Duration,
    ) -> Self {
        let mut core = PlayerCore {
            invite,
            policy,
            hello: ClientMessage::Hello {
                protocol,
                physics: 0,
                key: Vec::new(),
            },
            identity,
            at: 0,
            link: Link::Closed,
            seating: Seating::default(),
            entry: None,
            entry_sent: false,
            asked: None,
            retry: None,
            inbox: Vec::new(),
            transmits: VecDeque::new(),
            actions: VecDeque::new(),
            events: VecDeque::new(),
        };
        match hello(protocol, &core.identity) {
            Ok(msg) => {
                core.hello = msg;
                let opening = Opening::new(Purpose::First, 0, now, policy.first_for, policy);
                core.begin(opening, now);
            }
            Err(e) => core.close(e),
        }
        core
    }

    /// The invite this core connects by.
    pub fn invite(&self) -> &Invite {
        &self.invite
    }

    /// The seat held, as the server last said.
    pub fn seating(&self) -> &Seating {
        &self.seating
    }

    /// The index in the invite of the address connected to (or last connected to).
    pub fn address_index(&self) -> usize {
        self.at
    }

    /// True once the handshake is done and until the connection drops.
    pub fn is_ready(&self) -> bool {
        matches!(self.link, Link::Ready)
    }

    /// True once the connection has ended for good.
    pub fn is_closed(&self) -> bool {
        matches!(self.link, Link::Closed)
    }

    /// Enters a room as `entry` says: at once when connected, else once the handshake is
    /// done. The core carries out its fallbacks itself.
    pub fn enter(&mut self, entry: Entry) {
        self.entry = Some(entry);
        self.entry_sent = false;
        if self.is_ready() {
            self.send_entry();
        }
    }

    /// Sends a message. Without a connection (while the seat is being taken back) the
    /// message is lost, as it would be on a dropped connection.
    pub fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        if !self.is_ready() {
            return Err(NetError::Lost("reconnecting".into()));
        }
        if let ClientMessage::Rejoin { token } = msg {
            self.asked = Some(*token);
        }
        self.transmits.push_back(encode_frame(msg)?);
        Ok(())
    }

    /// Sends raw bytes (to test how the server treats malformed frames).
    pub fn send_raw(&mut self, bytes: &[u8]) -> Result<(), NetError> {
        if !self.is_ready() {
            return Err(NetError::Lost("reconnecting".into()));
        }
        self.transmits.push_back(bytes.to_vec());
        Ok(())
    }

    /// The transport opened the connection asked for: say `Hello`.
    pub fn opened(&mut self, _now: Duration) {
        if let Link::Opening(opening) = &mut self.link {
            if opening.open() {
                self.inbox.clear();
                if let Ok(frame) = encode_frame(&self.hello) {
                    self.transmits.push_back(frame);
                }
            }
        }
    }

    /// The transport failed to open the connection asked for, or the open connection ended.
    pub fn failed(&mut self, error: NetError, now: Duration) {
        match &self.link {
            Link::Opening(_) => self.attempt_failed(error, now),
            Link::Ready => self.lost(error, now),
            Link::Closed => {}
        }
    }

    /// Bytes arrived on the open connection (any split: frames are put back together here).
    pub fn received(&mut self, bytes: &[u8], now: Duration) {
        self.inbox.extend_from_slice(bytes);
        loop {
            let (msg, used) = match split_frame(&self.inbox) {
                Ok(Some((payload, used))) => (
                    breakshot_shared::protocol::decode_payload::<ServerMessage>(payload),
                    used,
                ),
                Ok(None) => return,
                Err(e) => return self.failed(e.into(), now),
            };
            self.inbox.drain(..used);
            match msg {
                Ok(msg) => self.message(msg, now),
                Err(e) => return self.failed(e.into(), now),
            }
            if self.is_closed() || matches!(&self.link, Link::Opening(o) if !o.is_open()) {
                // The connection was given up: what followed on it is no concern.
                self.inbox.clear();
                return;
            }
        }
    }

    /// When [`PlayerCore::handle_timeout`] must be called next, if at all.
    pub fn timeout(&self) -> Option<Duration> {
        match &self.link {
            Link::Opening(opening) => opening.timeout(),
            _ => None,
        }
    }

    /// The time [`PlayerCore::timeout`] named has come (or passed).
    pub fn handle_timeout(&mut self, now: Duration) {
        let Link::Opening(opening) = &mut self.link else {
            return;
        };
        if opening.attempt_overdue(now) {
            let at = opening.attempt_at(self.invite.servers.len());
            let server = self.invite.servers[at].clone();
            self.actions.push_back(Action::Close);
            self.attempt_failed(NetError::Connect(format!("{server} did not answer")), now);
        } else if opening.pause_over(now) {
            self.next_attempt(now);
        }
    }

    /// What the driver must do next with the transport.
    pub fn poll_action(&mut self) -> Option<Action> {
        self.actions.pop_front()
    }

    /// The next frame to write on the open connection.
    pub fn poll_transmit(&mut self) -> Option<Vec<u8>> {
        self.transmits.pop_front()
    }

    /// True when an event waits for [`PlayerCore::poll_event`].
    pub fn has_events(&self) -> bool {
        !self.events.is_empty()
    }

    /// The next event for the user.
    pub fn poll_event(&mut self) -> Option<PlayerEvent> {
        self.events.pop_front()
    }

    /// Leaves: closes the connection and ends the core.
    pub fn leave(&mut self) {
        if !self.is_closed() {
            self.actions.push_back(Action::Close);
            self.link = Link::Closed;
        }
    }

    /// Starts `opening`: the first attempt now, or after its pause.
    fn begin(&mut self, opening: Opening, now: Duration) {
        let pause_first = opening.pauses_first();
        self.link = Link::Opening(opening);
        if !pause_first {
            self.next_attempt(now);
        }
    }

    /// Asks the transport for the next address of the pass in progress.
    fn next_attempt(&mut self, now: Duration) {
        let n = self.invite.servers.len();
        let Link::Opening(opening) = &mut self.link else {
            return;
        };
        if n == 0 {
            return self.close(NetError::Connect("the invite names no server".into()));
        }
        let at = opening.start_attempt(now, n);
        self.actions.push_back(Action::Open {
            at,
            server: self.invite.servers[at].clone(),
            fingerprint: self.invite.fingerprint,
        });
    }

    /// The attempt in progress failed: the next address, the next pass after a pause, or
    /// the end.
    fn attempt_failed(&mut self, error: NetError, now: Duration) {
        let n = self.invite.servers.len();
        let Link::Opening(opening) = &mut self.link else {
            return;
        };
        match opening.failed(error, now, n) {
            Then::Nothing => {}
            Then::Wait if opening.timeout().is_some_and(|t| t > now) => {}
            Then::Next | Then::Wait => self.next_attempt(now),
            Then::GiveUp(failure) => {
                let failure = match opening.purpose() {
                    Purpose::First => match failure {
                        NetError::Connect(why) | NetError::Resolve(why) => NetError::Unreachable {
                            tried: addresses(&self.invite),
                            why,
                        },
                        other => other,
                    },
                    Purpose::Rejoin(why) => {
                        NetError::Lost(format!("{why}; reconnecting failed: {failure}"))
                    }
                };
                self.close(failure);
            }
        }
    }

    /// Ends for good with `error`.
    fn close(&mut self, error: NetError) {
        self.link = Link::Closed;
        self.events.push_back(PlayerEvent::Closed(error));
    }

    /// The open connection dropped: take the seat back, if there is one to take back.
    fn lost(&mut self, error: NetError, now: Duration) {
        self.actions.push_back(Action::Close);
        if self.seating.token.is_some() && self.may_retry() {
            let why = error.to_string();
            self.reconnect(why, false, now);
        } else {
            self.close(error);
        }
    }

    /// Connects again to take the seat back, from the address `self.at`; `pause_first`:
    /// after the pause the retry has reached (an instance said "played elsewhere").
    fn reconnect(&mut self, why: String, pause_first: bool, now: Duration) {
        let (since, pause) = *self.retry.get_or_insert((now, self.policy.pause));
        let patience = self
            .policy
            .rejoin_for
            .saturating_sub(now.saturating_sub(since));
        let mut opening = Opening::new(
            Purpose::Rejoin(why.clone()),
            self.at,
            now,
            patience,
            self.policy,
        );
        if pause_first {
            opening.pause_for(pause, now);
            if let Some(retry) = &mut self.retry {
                retry.1 = (pause * 2).min(self.policy.max_pause);
            }
        }
        self.events.push_back(PlayerEvent::Reconnecting(why));
        self.begin(opening, now);
    }

    /// Whether the policy lets this core connect again by itself.
    fn may_retry(&self) -> bool {
        !self.policy.rejoin_for.is_zero()
    }

    /// A whole message from the server.
    fn message(&mut self, msg: ServerMessage, now: Duration) {
        if let Link::Opening(opening) = &self.link {
            if opening.is_open() {
                self.greeted(msg, now);
            }
            return;
        }
        if let Some(token) = self.asked.take() {
            if played_elsewhere(&msg) && self.may_retry() {
                return self.ask_next_instance(token, &msg, now);
            }
            self.retry = None;
            if matches!(msg, ServerMessage::Joined { .. }) {
                self.seating.token = Some(token);
            }
        }
        if self.entry_answered(&msg) {
            return;
        }
        if matches!(msg, ServerMessage::GameFinished { .. }) {
            // The game of the seat asked back ended while the player was away: there is
            // no seat to keep.
            self.seating = Seating::default();
            self.events.push_back(PlayerEvent::SeatGone);
        }
        if let Some(seating) = self.seating.observe(&msg) {
            self.events.push_back(PlayerEvent::Seated(seating));
        }
        self.events.push_back(PlayerEvent::Message(msg));
    }

    /// The key this core proves: who the player is on the server.
    pub fn identity(&self) -> &Identity {
        &self.identity
    }

    /// The answer to `Hello` (a challenge, answered here), then the answer to `Prove`.
    fn greeted(&mut self, msg: ServerMessage, now: Duration) {
        if let ServerMessage::Challenge { nonce } = msg {
            if let Ok(frame) = encode_frame(&prove(&self.hello, &self.identity, &nonce)) {
                self.transmits.push_back(frame);
            }
            return;
        }
        match answer_to_hello(msg) {
            Ok(()) => {
                let Link::Opening(opening) = &self.link else {
                    return;
                };
                let n = self.invite.servers.len().max(1);
                self.at = opening.attempt_at(n);
                let first = matches!(opening.purpose(), Purpose::First);
                self.link = Link::Ready;
                if first {
                    self.events.push_back(PlayerEvent::Connected);
                    if self.entry.is_some() && !self.entry_sent {
                        self.send_entry();
                    }
                } else {
                    if let Some(token) = self.seating.token {
                        let _ = self.send(&ClientMessage::Rejoin { token });
                    }
                    self.events.push_back(PlayerEvent::Reconnected);
                }
            }
            Err(e) => {
                self.actions.push_back(Action::Close);
                self.attempt_failed(e, now);
            }
        }
    }

    /// The instance connected to says another one plays the game of the seat `token` asked
    /// back: leaves it and starts asking the invite's next address.
    fn ask_next_instance(
        &mut self,
        token: breakshot_shared::protocol::SeatToken,
        answer: &ServerMessage,
        now: Duration,
    ) {
        self.actions.push_back(Action::Close);
        self.seating.token = Some(token);
        self.at = (self.at + 1) % self.invite.servers.len().max(1);
        let why = match answer {
            ServerMessage::Error { message, .. } => message.clone(),
            _ => "the game is played on another server instance".into(),
        };
        self.reconnect(why, true, now);
    }

    /// Sends the entry waiting.
    fn send_entry(&mut self) {
        if let Some(msg) = self.entry.as_ref().map(Entry::message) {
            self.entry_sent = self.send(&msg).is_ok();
        }
    }

    /// Carries out the entry's fallback when `msg` refuses it; true when `msg` was answered
    /// here and is no concern of the user.
    fn entry_answered(&mut self, msg: &ServerMessage) -> bool {
        let Some(entry) = self.entry.take().filter(|_| self.entry_sent) else {
            return false;
        };
        let code = match msg {
            ServerMessage::Joined { .. } => return false,
            ServerMessage::GameFinished { .. } => return false,
            // Out of the queue without a match: the entry is over.
            ServerMessage::Unqueued { .. } => return false,
            ServerMessage::Error { code, .. } => *code,
            _ => {
                self.entry = Some(entry);
                return false;
            }
        };
        let rejoin = matches!(entry, Entry::Rejoin { .. });
        match entry.fallback(code) {
            Some((next, gone)) => {
                if gone {
                    self.seating = Seating::default();
                    self.events.push_back(PlayerEvent::SeatGone);
                }
                self.enter(next);
                true
            }
            None => {
                if rejoin && code == ErrorCode::BadToken {
                    self.events.push_back(PlayerEvent::SeatGone);
                }
                false
            }
        }
    }
}

/// The server's answer to `Hello`: `Welcome`, else why not.
pub(crate) fn answer_to_hello(msg: ServerMessage) -> Result<(), NetError> {
    match msg {
        ServerMessage::Welcome { .. } => Ok(()),
        ServerMessage::Reject { reason } => Err(NetError::Rejected(reason)),
        other => Err(NetError::Handshake(format!("{other:?}"))),
    }
}

/// The `Hello` this build says for `identity`, claiming `protocol`.
pub(crate) fn hello(protocol: u32, identity: &Identity) -> Result<ClientMessage, NetError> {
    let physics = reference_hash().map_err(|e| NetError::Connect(e.to_string()))?;
    Ok(ClientMessage::Hello {
        protocol,
        physics,
        key: identity.public().0.to_vec(),
    })
}

/// The `Prove` that answers the server's challenge `nonce` to `hello`: the signature covers
/// the challenge and what `hello` claimed.
pub(crate) fn prove(
    hello: &ClientMessage,
    identity: &Identity,
    nonce: &[u8; breakshot_shared::protocol::identity::NONCE_LEN],
) -> ClientMessage {
    let (protocol, physics) = match hello {
        ClientMessage::Hello {
            protocol, physics, ..
        } => (*protocol, *physics),
        _ => (PROTOCOL_VERSION, 0),
    };
    ClientMessage::Prove {
        signature: identity.sign(nonce, protocol, physics),
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

/// The invite's addresses as a person reads them: `HOST:PORT`, joined by "then".
fn addresses(invite: &Invite) -> String {
    let all: Vec<String> = invite.servers.iter().map(|s| s.to_string()).collect();
    all.join(", then ")
}
