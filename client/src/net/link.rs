//! A game screen's [`GameLink`] over the network: commands go to the server, and what the
//! server announces comes back as the same [`GameEvent`]s a local game produces.

use std::collections::VecDeque;

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, Invite, Role, RoomCode, ServerMessage};
use breakshot_shared::rules::{Command, Game, Seat, TurnId};

use super::seats::SeatStore;
use super::session::{Session, SessionEvent};
use crate::play::{game_events, AwayResult, GameEvent, GameLink};
use crate::view::hud::Connection;

/// A [`GameLink`] over a [`Session`].
pub struct NetLink {
    session: Session,
    events: VecDeque<GameEvent>,
    /// Where the seat taken is remembered, and the invite it is remembered under.
    memory: Option<(SeatStore, Invite)>,
    /// While a remembered seat is being taken back: the player's name, to ask for the free
    /// seat instead if the server no longer knows the token.
    rejoining: Option<String>,
    /// While the free seat of this room is being asked for: a room whose seats are both
    /// taken is watched instead.
    joining: Option<RoomCode>,
}

/// An invite that cannot be joined.
#[derive(Debug, thiserror::Error)]
#[error("{0} names a server but no room: ask the host for the game's invite")]
pub struct NoRoom(pub String);

impl NetLink {
    /// Connects to the server an invite names and asks for the free seat of its room, or,
    /// when `seats` remembers a seat in that room, takes that seat back. The seat taken is
    /// remembered in `seats`.
    pub fn join(invite: Invite, name: &str, seats: Option<SeatStore>) -> Result<NetLink, NoRoom> {
        let Some(room) = invite.room.clone() else {
            return Err(NoRoom(invite.to_string()));
        };
        let token = seats.as_ref().and_then(|s| s.load(&invite));
        let session = Session::connect(invite.clone());
        let mut link = NetLink::new(session);
        match token {
            Some(token) => {
                link.session.send(ClientMessage::Rejoin { token });
                link.rejoining = Some(name.into());
            }
            None => link.ask_seat(room, name.into()),
        }
        link.memory = seats.map(|s| (s, invite));
        Ok(link)
    }

    /// A link over a session that has joined (or will join) a room.
    pub fn new(session: Session) -> NetLink {
        NetLink {
            session,
            events: VecDeque::new(),
            memory: None,
            rejoining: None,
            joining: None,
        }
    }

    /// Asks for the free seat of `room`.
    fn ask_seat(&mut self, room: RoomCode, name: String) {
        self.joining = Some(room.clone());
        self.session.send(ClientMessage::Join { room, name });
    }

    /// Remembers the seat this link takes (or has taken back with `Rejoin`) in `seats`,
    /// under `invite` (with the room joined).
    pub fn remember(&mut self, seats: SeatStore, invite: Invite) {
        self.memory = Some((seats, invite));
    }

    /// True while a remembered seat is being asked back and the server has not answered.
    pub fn rejoining(&self) -> bool {
        self.rejoining.is_some()
    }

    /// Saves a seat the server gave; when a remembered token is refused, forgets it and asks
    /// for the free seat instead. Returns true when the message was handled here and is no
    /// concern of the game screen.
    fn remember_seat(&mut self, msg: &ServerMessage) -> bool {
        match msg {
            ServerMessage::Joined {
                role: Role::Player(_),
                token: Some(token),
                snapshot,
            } => {
                self.rejoining = None;
                self.joining = None;
                if let Some((store, invite)) = &self.memory {
                    // A host remembers its server's invite before the room is opened.
                    let invite = invite.with_room(snapshot.room.clone());
                    if let Err(e) = store.save(&invite, *token) {
                        tracing::warn!(error = %e, "cannot remember the seat");
                    }
                }
                false
            }
            ServerMessage::GameFinished {
                seat,
                winner,
                reason,
                ..
            } => {
                // The game ended while this player was away: show how, and keep no seat.
                self.rejoining = None;
                if let Some((store, invite)) = &self.memory {
                    store.forget(invite);
                }
                self.events
                    .push_back(GameEvent::EndedAway(AwayResult::for_seat(
                        *seat, *winner, reason,
                    )));
                true
            }
            ServerMessage::Error {
                code: ErrorCode::BadToken | ErrorCode::NoSuchRoom,
                ..
            } if self.rejoining.is_some() => {
                let name = self.rejoining.take().unwrap_or_default();
                let Some((store, invite)) = &self.memory else {
                    return false;
                };
                store.forget(invite);
                let Some(room) = invite.room.clone() else {
                    return false;
                };
                self.ask_seat(room, name);
                true
            }
            ServerMessage::Error {
                code: ErrorCode::RoomFull,
                ..
            } if self.joining.is_some() => {
                // Both seats are taken (two players, or a host and the computer): the
                // invite still lets its holder watch.
                if let Some(room) = self.joining.take() {
                    self.session.send(ClientMessage::Spectate { room });
                }
                true
            }
            _ => false,
        }
    }

    /// The session under the link.
    pub fn session(&self) -> &Session {
        &self.session
    }

    fn translate(&mut self, event: SessionEvent) {
        let connection = match event {
            SessionEvent::Connected => Connection::Connected,
            SessionEvent::Closed(why) => Connection::Closed(why),
            SessionEvent::Reconnecting => Connection::Reconnecting,
            SessionEvent::Message(msg) => {
                if self.remember_seat(&msg) {
                    return;
                }
                self.events.extend(game_events(&msg, self.session.seat()));
                return;
            }
        };
        self.events.push_back(GameEvent::Connection(connection));
    }
}

/// The message a player sends for `command` on `turn`; None for a command only the rules
/// themselves make (the shot clock, a forfeit) or only practice allows.
pub(crate) fn command_message(turn: TurnId, command: Command) -> Option<ClientMessage> {
    Some(match command {
        Command::Shot { strike, call } => ClientMessage::Shot { turn, strike, call },
        Command::PlaceCueBall { pos } => ClientMessage::PlaceCueBall { turn, pos },
        Command::Decide(choice) => ClientMessage::Decide { turn, choice },
        Command::Concede => ClientMessage::Concede,
        _ => return None,
    })
}

impl GameLink for NetLink {
    fn seat(&self) -> Option<Seat> {
        self.session.seat()
    }

    fn watching(&self) -> bool {
        self.session.role() == Some(Role::Spectator)
    }

    fn send(&mut self, game: &Game, _seat: Seat, command: Command) {
        let Some(msg) = command_message(game.turn(), command) else {
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
