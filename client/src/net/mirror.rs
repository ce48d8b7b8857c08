//! The client's copy of the game. Every command the server accepts is applied here too,
//! with the same physics and rules, so a shot can be animated before the server's result
//! arrives; the server's hash then confirms the prediction bit for bit, or counts a desync.

use std::collections::BTreeMap;

use breakshot_shared::protocol::{Role, RoomCode, SeatToken, ServerMessage};
use breakshot_shared::rules::{Game, Phase, Seat, TurnId};

/// What the mirror learned from a message.
#[derive(Clone, Debug, PartialEq)]
pub enum Check {
    /// A shot was simulated locally; its hash is `hash`.
    Predicted { turn: TurnId, hash: u64 },
    /// The server's hash equals the local one.
    Confirmed { turn: TurnId },
    /// The server's result differs from the local one (or the local rules refused a
    /// command the server accepted).
    Desync {
        turn: TurnId,
        local: Option<u64>,
        server: u64,
    },
}

#[derive(Default)]
pub struct Mirror {
    game: Option<Game>,
    role: Option<Role>,
    room: Option<RoomCode>,
    token: Option<SeatToken>,
    predicted: BTreeMap<TurnId, Option<u64>>,
    confirmed: u32,
    desyncs: u32,
}

impl Mirror {
    pub fn game(&self) -> Option<&Game> {
        self.game.as_ref()
    }

    pub fn role(&self) -> Option<Role> {
        self.role
    }

    pub fn seat(&self) -> Option<Seat> {
        match self.role {
            Some(Role::Player(s)) => Some(s),
            _ => None,
        }
    }

    pub fn room(&self) -> Option<&RoomCode> {
        self.room.as_ref()
    }

    /// The seat token to rejoin with.
    pub fn token(&self) -> Option<SeatToken> {
        self.token
    }

    pub fn confirmed(&self) -> u32 {
        self.confirmed
    }

    pub fn desyncs(&self) -> u32 {
        self.desyncs
    }

    /// Whether the game waits for this client's seat.
    pub fn my_move(&self) -> bool {
        match (&self.game, self.seat()) {
            (Some(g), Some(seat)) => {
                g.to_move() == seat && !matches!(g.phase(), Phase::Over { .. })
            }
            _ => false,
        }
    }

    pub fn observe(&mut self, msg: &ServerMessage) -> Option<Check> {
        match msg {
            ServerMessage::Joined {
                role,
                token,
                snapshot,
            } => {
                self.role = Some(*role);
                if token.is_some() {
                    self.token = *token;
                }
                self.room = Some(snapshot.room.clone());
                self.reset(snapshot.game.clone());
                None
            }
            ServerMessage::GameStarted { snapshot } => {
                self.reset(snapshot.game.clone());
                None
            }
            ServerMessage::ShotAccepted {
                turn,
                seat,
                command,
            } => {
                let game = self.game.as_mut()?;
                if game.turn() != *turn {
                    return None;
                }
                let hash = game
                    .apply(*seat, command)
                    .ok()
                    .and_then(|v| v.shot.map(|s| s.hash));
                self.predicted.insert(*turn, hash);
                hash.map(|hash| Check::Predicted { turn: *turn, hash })
            }
            ServerMessage::ShotResolved { turn, hash, .. } => {
                let local = self.predicted.remove(turn)?;
                if local == Some(*hash) {
                    self.confirmed += 1;
                    Some(Check::Confirmed { turn: *turn })
                } else {
                    self.desyncs += 1;
                    Some(Check::Desync {
                        turn: *turn,
                        local,
                        server: *hash,
                    })
                }
            }
            ServerMessage::Applied {
                turn,
                seat,
                command,
                ..
            } => {
                let game = self.game.as_mut()?;
                if game.turn() == *turn && game.apply(*seat, command).is_err() {
                    self.desyncs += 1;
                    return Some(Check::Desync {
                        turn: *turn,
                        local: None,
                        server: 0,
                    });
                }
                None
            }
            _ => None,
        }
    }

    fn reset(&mut self, game: Game) {
        self.game = Some(game);
        self.predicted.clear();
    }
}
