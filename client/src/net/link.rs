//! A game screen's [`GameLink`] over the network: commands go to the server, and what the
//! server announces comes back as the same [`GameEvent`]s a local game produces.

use std::collections::VecDeque;

use breakshot_shared::protocol::{ClientMessage, Invite};
use breakshot_shared::rules::{Command, Game, Seat};

use super::session::{Session, SessionEvent};
use crate::play::link::{game_events, GameEvent, GameLink};
use crate::view::hud::Connection;

/// A [`GameLink`] over a [`Session`].
pub struct NetLink {
    session: Session,
    events: VecDeque<GameEvent>,
}

/// An invite that cannot be joined.
#[derive(Debug, thiserror::Error)]
#[error("{0} names a server but no room: ask the host for the game's invite")]
pub struct NoRoom(pub String);

impl NetLink {
    /// Connects to the server an invite names and asks for the free seat of its room.
    pub fn join(invite: Invite, name: &str) -> Result<NetLink, NoRoom> {
        let Some(room) = invite.room.clone() else {
            return Err(NoRoom(invite.to_string()));
        };
        let session = Session::connect(invite);
        session.send(ClientMessage::Join {
            room,
            name: name.into(),
        });
        Ok(NetLink::new(session))
    }

    /// A link over a session that has joined (or will join) a room.
    pub fn new(session: Session) -> NetLink {
        NetLink {
            session,
            events: VecDeque::new(),
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
                self.events.extend(game_events(&msg, self.session.seat()));
                return;
            }
        };
        self.events.push_back(GameEvent::Connection(connection));
    }
}

impl GameLink for NetLink {
    fn seat(&self) -> Option<Seat> {
        self.session.seat()
    }

    fn send(&mut self, game: &Game, _seat: Seat, command: Command) {
        let turn = game.turn();
        let msg = match command {
            Command::Shot { strike, call } => ClientMessage::Shot { turn, strike, call },
            Command::PlaceCueBall { pos } => ClientMessage::PlaceCueBall { turn, pos },
            Command::Decide(choice) => ClientMessage::Decide { turn, choice },
            Command::Concede => ClientMessage::Concede,
            _ => {
                self.events
                    .push_back(GameEvent::Refused("not available in an online game".into()));
                return;
            }
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
}
