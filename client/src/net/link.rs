//! A game screen's [`GameLink`] over the network: commands go to the server, and what the
//! server announces comes back as the same [`GameEvent`]s a local game produces.

use std::collections::VecDeque;

use breakshot_shared::protocol::{ClientMessage, Invite, Role, SeatView, ServerMessage};
use breakshot_shared::rules::{Command, Seat};

use super::session::{Session, SessionEvent};
use crate::play::link::{GameEvent, GameLink, Judgement};
use crate::view::hud::Connection;

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

    pub fn session(&self) -> &Session {
        &self.session
    }

    fn translate(&mut self, event: SessionEvent) {
        let my_seat = self.seat();
        let out = &mut self.events;
        match event {
            SessionEvent::Connected => out.push_back(GameEvent::Connection(Connection::Connected)),
            SessionEvent::Closed(why) => {
                out.push_back(GameEvent::Connection(Connection::Closed(why)))
            }
            SessionEvent::Reconnecting => {
                out.push_back(GameEvent::Connection(Connection::Reconnecting))
            }
            SessionEvent::Check(_) => {}
            SessionEvent::Message(msg) => match msg {
                ServerMessage::Joined { snapshot, .. }
                | ServerMessage::GameStarted { snapshot } => {
                    out.push_back(GameEvent::AimAid(snapshot.aim_aid));
                    out.push_back(GameEvent::Connection(opponent_state(
                        &snapshot.seats,
                        my_seat,
                    )));
                    out.push_back(GameEvent::Started(Box::new(snapshot.game)));
                    let seconds = snapshot.shot_clock_ms.map(|ms| ms as f64 / 1000.0);
                    out.push_back(GameEvent::ShotClock(seconds));
                }
                ServerMessage::PlayerJoined { seat, .. } if Some(seat) != my_seat => {
                    out.push_back(GameEvent::Connection(Connection::Connected));
                }
                ServerMessage::ShotAccepted { seat, command, .. } => {
                    out.push_back(GameEvent::Accepted { seat, command });
                }
                ServerMessage::ShotResolved { hash, ruling, .. } => {
                    out.push_back(GameEvent::Judged(Judgement {
                        reasons: ruling.reasons,
                        foul: ruling.foul,
                        hash: Some(hash),
                    }));
                }
                ServerMessage::Applied {
                    seat,
                    command,
                    ruling,
                    ..
                } => {
                    out.push_back(GameEvent::Accepted { seat, command });
                    out.push_back(GameEvent::Judged(Judgement {
                        reasons: ruling.reasons,
                        foul: ruling.foul,
                        hash: None,
                    }));
                }
                ServerMessage::TurnChanged { shot_clock_ms, .. } => {
                    out.push_back(GameEvent::ShotClock(
                        shot_clock_ms.map(|ms| ms as f64 / 1000.0),
                    ));
                }
                ServerMessage::PlayerLeft { seat, reconnect_ms } if Some(seat) != my_seat => {
                    out.push_back(GameEvent::Connection(Connection::OpponentLeft {
                        seconds_left: reconnect_ms as f64 / 1000.0,
                    }));
                }
                ServerMessage::PlayerBack { .. } => {
                    out.push_back(GameEvent::Connection(Connection::Connected));
                }
                ServerMessage::Error { message, .. } => out.push_back(GameEvent::Refused(message)),
                ServerMessage::Reject { reason } => {
                    out.push_back(GameEvent::Connection(Connection::Closed(reason)));
                }
                _ => {}
            },
        }
    }
}

/// The connection state a room's seats show to the player in `me`: the other seat empty,
/// its player away (with the time left to come back), or both there.
fn opponent_state(seats: &[Option<SeatView>; 2], me: Option<Seat>) -> Connection {
    let Some(me) = me else {
        return Connection::Connected;
    };
    let other = match me {
        Seat::A => &seats[1],
        Seat::B => &seats[0],
    };
    match other {
        None => Connection::WaitingForOpponent,
        Some(v) if !v.connected => Connection::OpponentLeft {
            seconds_left: v.reconnect_ms.unwrap_or(0) as f64 / 1000.0,
        },
        Some(_) => Connection::Connected,
    }
}

impl GameLink for NetLink {
    fn seat(&self) -> Option<Seat> {
        match self.session.mirror().role() {
            Some(Role::Player(seat)) => Some(seat),
            _ => None,
        }
    }

    fn send(&mut self, _seat: Seat, command: Command) {
        let Some(turn) = self.session.mirror().game().map(|g| g.turn()) else {
            self.events
                .push_back(GameEvent::Refused("not in a game yet".into()));
            return;
        };
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

#[cfg(test)]
mod tests {
    use super::*;

    fn here(connected: bool, reconnect_ms: Option<u64>) -> Option<SeatView> {
        Some(SeatView {
            name: "p".into(),
            connected,
            reconnect_ms,
        })
    }

    #[test]
    fn the_other_seat_gives_the_connection_state() {
        let me = Some(Seat::A);
        assert_eq!(
            opponent_state(&[here(true, None), None], me),
            Connection::WaitingForOpponent
        );
        assert_eq!(
            opponent_state(&[here(true, None), here(true, None)], me),
            Connection::Connected
        );
        assert_eq!(
            opponent_state(&[here(true, None), here(false, Some(90_500))], me),
            Connection::OpponentLeft { seconds_left: 90.5 }
        );
        // Seat B looks at seat A; a spectator sees the game as connected.
        assert_eq!(
            opponent_state(&[None, here(true, None)], Some(Seat::B)),
            Connection::WaitingForOpponent
        );
        assert_eq!(opponent_state(&[None, None], None), Connection::Connected);
    }
}
