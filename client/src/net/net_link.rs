//! A game screen's [`GameLink`] over the network: commands go to the server, and what the
//! server announces comes back as the same [`GameEvent`]s a local game produces.

use std::collections::VecDeque;

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{ClientMessage, Invite, Role, RoomCode, SeatToken, ServerMessage};
use breakshot_shared::rules::{Command, Game, Seat, TurnId};

use super::player::Entry;
use super::port::{Port, SessionEvent};
use super::seats::SeatStore;
#[cfg(not(target_arch = "wasm32"))]
use super::session::Session;
use crate::play::{game_events, GameEvent, GameLink};
use crate::view::hud::Connection;

/// A [`GameLink`] over a [`Port`]: natively a `Session`, the client on a thread of its own;
/// in the browser a [`PolledSession`](super::PolledSession).
pub struct NetLink<P: Port> {
    session: P,
    events: VecDeque<GameEvent>,
    /// Where the seat taken is remembered, and the invite it is remembered under.
    memory: Option<(SeatStore, Invite)>,
}

/// An invite that cannot be joined.
#[derive(Debug, thiserror::Error)]
#[error("{0} names a server but no room: ask the host for the game's invite")]
pub struct NoRoom(pub String);

#[cfg(not(target_arch = "wasm32"))]
impl NetLink<Session> {
    /// Connects to the server an invite names and joins its room (see [`NetLink::joining`]).
    pub fn join(
        invite: Invite,
        name: &str,
        seats: Option<SeatStore>,
    ) -> Result<NetLink<Session>, NoRoom> {
        NetLink::joining(Session::connect(invite.clone()), invite, name, seats)
    }

    /// The next event, waiting at most `timeout` for one: for a caller with nothing to do
    /// until the server answers (opening a hosted room), not for frame loops.
    pub fn wait(&mut self, timeout: std::time::Duration) -> Option<GameEvent> {
        if self.events.is_empty() {
            if let Some(event) = self.session.recv_timeout(timeout) {
                self.translate(event);
            }
        }
        self.poll()
    }
}

impl<P: Port> NetLink<P> {
    /// Asks, through `session` (connecting to the server of `invite`), for the free seat of
    /// the invite's room (watching it when both seats are taken), or, when `seats` remembers
    /// a seat in that room, takes that seat back, falling back to the free seat when the
    /// server no longer knows it. The seat taken is remembered in `seats`.
    pub fn joining(
        mut session: P,
        invite: Invite,
        name: &str,
        seats: Option<SeatStore>,
    ) -> Result<NetLink<P>, NoRoom> {
        let Some(room) = invite.room.clone() else {
            return Err(NoRoom(invite.to_string()));
        };
        let join = Entry::Join {
            room,
            name: name.into(),
            watch_if_full: true,
        };
        let entry = match seats.as_ref().and_then(|s| s.load(&invite)) {
            Some(token) => Entry::Rejoin {
                token,
                otherwise: Some(Box::new(join)),
            },
            None => join,
        };
        session.enter(entry);
        let mut link = NetLink::new(session);
        link.memory = seats.map(|s| (s, invite));
        Ok(link)
    }

    /// A link over a session that has joined (or will join) a room.
    pub fn new(session: P) -> NetLink<P> {
        NetLink {
            session,
            events: VecDeque::new(),
            memory: None,
        }
    }

    /// Remembers the seat this link takes (or has taken back with `Rejoin`) in `seats`,
    /// under `invite` (with the room joined).
    pub fn remember(&mut self, seats: SeatStore, invite: Invite) {
        self.memory = Some((seats, invite));
    }

    /// The session under the link.
    pub fn session(&self) -> &P {
        &self.session
    }

    /// The session under the link, to enter a room through it.
    pub fn session_mut(&mut self) -> &mut P {
        &mut self.session
    }

    fn translate(&mut self, event: SessionEvent) {
        let connection = match event {
            SessionEvent::Connected => Connection::Connected,
            SessionEvent::Closed(why) => Connection::Closed(why),
            SessionEvent::Reconnecting => Connection::Reconnecting,
            SessionEvent::SeatGone => {
                if let Some((store, invite)) = &self.memory {
                    store.forget(invite);
                }
                return;
            }
            SessionEvent::Message(msg) => {
                if let ServerMessage::Joined {
                    role: Role::Player(_),
                    token: Some(token),
                    snapshot,
                } = &msg
                {
                    self.save_seat(snapshot.room.clone(), *token);
                }
                self.events
                    .extend(game_events(&msg, self.session.seating().seat()));
                return;
            }
        };
        self.events.push_back(GameEvent::Connection(connection));
    }

    /// Remembers the seat the server gave in `room`.
    fn save_seat(&self, room: RoomCode, token: SeatToken) {
        if let Some((store, invite)) = &self.memory {
            // A host remembers its server's invite before the room is opened.
            let invite = invite.with_room(room);
            if let Err(e) = store.save(&invite, token) {
                tracing::warn!(error = %e, "cannot remember the seat");
            }
        }
    }
}

impl<P: Port> GameLink for NetLink<P> {
    fn seat(&self) -> Option<Seat> {
        self.session.seating().seat()
    }

    fn watching(&self) -> bool {
        self.session.seating().role == Some(Role::Spectator)
    }

    fn send(&mut self, game: &Game, _seat: Seat, command: Command) {
        let Some(msg) = ClientMessage::for_command(game.turn(), command) else {
            self.events
                .push_back(GameEvent::Refused("not available in an online game".into()));
            return;
        };
        if !self.session.send(msg) {
            self.events
                .push_back(GameEvent::Connection(Connection::Closed(
                    "connection lost".into(),
                )));
        }
    }

    fn poll(&mut self) -> Option<GameEvent> {
        while let Some(event) = self.session.try_recv() {
            self.translate(event);
        }
        self.events.pop_front()
    }

    fn rematch(&mut self) {
        self.session.send(ClientMessage::Rematch);
    }

    fn report_desync(&mut self, turn: TurnId, hash: u64) {
        // Counted by the operator (`breakshot_desyncs_reported_total`), never answered.
        self.session
            .send(ClientMessage::ReportDesync { turn, hash });
    }

    fn chats(&self) -> bool {
        true
    }

    fn chat(&mut self, text: String) {
        self.session.send(ClientMessage::Chat { text });
    }

    fn aim(&mut self, turn: TurnId, strike: Strike) {
        self.session.send(ClientMessage::Aim { turn, strike });
    }
}
