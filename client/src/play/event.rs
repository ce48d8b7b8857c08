//! What a game screen hears ([`GameEvent`]), whoever decides the game, and the one
//! translation of a server's messages into those events ([`game_events`]), used by the
//! network link, the replica, the bot and the tests.

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{AimAid, SeatView, ServerMessage};
use breakshot_shared::rules::{Command, Game, Seat, TurnId};

use super::chat::ChatLine;
use crate::view::hud::Connection;

/// What a game screen hears. A server announces an accepted shot at once, so every client
/// starts showing it, and its judgement when it has simulated it.
#[derive(Clone, Debug, PartialEq)]
pub enum GameEvent {
    /// A new game starts from this state (first game, rematch or resynchronisation).
    Started(Box<Game>),
    /// `seat`'s command on `turn` was accepted by the side that decides; its judgement
    /// follows.
    Accepted {
        /// The turn the command was accepted on.
        turn: TurnId,
        /// Who sent it.
        seat: Seat,
        /// The command.
        command: Command,
    },
    /// `seat`'s command on `turn` passed the rules' check here: the copy of the game here
    /// decides it, and its verdict is the judgement.
    Decided {
        /// The turn the command was checked on.
        turn: TurnId,
        /// Who sent it.
        seat: Seat,
        /// The command.
        command: Command,
    },
    /// The deciding side has judged the last accepted command; for a shot, this is its
    /// state hash. What the rules said is the verdict of the copy of the game here (the same
    /// rules), checked against this hash.
    Judged {
        /// The deciding side's state hash of the table at rest, for a shot.
        hash: Option<u64>,
        /// The deciding side's game after the shot, which a copy that disagrees goes on
        /// from.
        game: Option<Box<Game>>,
    },
    /// Our command was refused; nothing changed.
    Refused(String),
    /// The connection changed.
    Connection(Connection),
    /// The shot clock restarted with this many seconds, or stopped (None).
    ShotClock(Option<f64>),
    /// The aiming aids the room allows (a local game allows them all).
    AimAid(AimAid),
    /// The game this player asked back ended while they were away: how it came out for them.
    EndedAway(AwayResult),
    /// `name` plays in `seat`.
    Seated {
        /// The seat.
        seat: Seat,
        /// The player's name.
        name: String,
    },
    /// A line said in the room (`from` is empty for the server's notices).
    Chat(ChatLine),
    /// A rated game ended: `seat`'s rating went from `before` to `after` (Glicko-2, rounded).
    Rated {
        /// The seat rated.
        seat: Seat,
        /// The rating before the game.
        before: i32,
        /// The rating after it.
        after: i32,
    },
    /// The seats' ratings in a rated room (seat A's, then B's), shown beside the names.
    Ratings([i32; 2]),
    /// Where `seat`, to shoot on `turn`, is aiming now.
    Aim {
        /// The turn being aimed.
        turn: TurnId,
        /// The shooter.
        seat: Seat,
        /// The strike as it is set up.
        strike: Strike,
    },
}

/// How a game that ended while this player was away came out for their seat.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AwayResult {
    /// Whether this seat won; None when the game ended with no winner.
    pub won: Option<bool>,
    /// How the game ended, in the rules' words.
    pub reason: String,
}

impl AwayResult {
    /// The result for `seat` of a game that `winner` won (or nobody).
    pub fn for_seat(seat: Seat, winner: Option<Seat>, reason: &str) -> AwayResult {
        AwayResult {
            won: winner.map(|w| w == seat),
            reason: reason.to_owned(),
        }
    }

    /// The headline and the line under it, as the result screen shows them.
    pub fn lines(&self) -> [String; 2] {
        let headline = match self.won {
            Some(true) => "You won",
            Some(false) => "You lost",
            None => "The game is over",
        };
        [
            headline.to_owned(),
            format!("The game ended while you were away: {}", self.reason),
        ]
    }
}

/// What a server message means for a game screen of the player in seat `me` (None: a
/// spectator, or not seated yet).
pub(crate) fn game_events(msg: &ServerMessage, me: Option<Seat>) -> Vec<GameEvent> {
    let secs = |ms: u64| ms as f64 / 1000.0;
    match msg {
        ServerMessage::Joined { snapshot, .. } | ServerMessage::GameStarted { snapshot } => {
            let seated = [Seat::A, Seat::B]
                .into_iter()
                .zip(&snapshot.seats)
                .filter_map(|(seat, view)| {
                    let name = view.as_ref()?.name.clone();
                    Some(GameEvent::Seated { seat, name })
                });
            [
                GameEvent::AimAid(snapshot.aim_aid),
                GameEvent::Connection(opponent_state(&snapshot.seats, me)),
                GameEvent::Started(Box::new(snapshot.game.clone())),
                GameEvent::ShotClock(snapshot.shot_clock_ms.map(secs)),
            ]
            .into_iter()
            .chain(seated)
            .collect()
        }
        ServerMessage::PlayerJoined { seat, name } => {
            let mut events = vec![GameEvent::Seated {
                seat: *seat,
                name: name.clone(),
            }];
            if Some(*seat) != me {
                events.push(GameEvent::Connection(Connection::Connected));
            }
            events
        }
        ServerMessage::Aim { turn, seat, strike } => vec![GameEvent::Aim {
            turn: *turn,
            seat: *seat,
            strike: *strike,
        }],
        ServerMessage::Chat { from, text } => vec![GameEvent::Chat(ChatLine {
            from: from.clone(),
            text: text.clone(),
        })],
        ServerMessage::ShotAccepted {
            turn,
            seat,
            command,
        } => vec![GameEvent::Accepted {
            turn: *turn,
            seat: *seat,
            command: command.clone(),
        }],
        ServerMessage::ShotResolved { hash, game, .. } => vec![GameEvent::Judged {
            hash: Some(*hash),
            game: Some(game.clone()),
        }],
        ServerMessage::Applied {
            turn,
            seat,
            command,
            ..
        } => vec![
            GameEvent::Accepted {
                turn: *turn,
                seat: *seat,
                command: command.clone(),
            },
            GameEvent::Judged {
                hash: None,
                game: None,
            },
        ],
        ServerMessage::TurnChanged { shot_clock_ms, .. } => {
            vec![GameEvent::ShotClock(shot_clock_ms.map(secs))]
        }
        ServerMessage::PlayerLeft { seat, reconnect_ms } if Some(*seat) != me => {
            vec![GameEvent::Connection(Connection::OpponentLeft {
                seconds_left: secs(*reconnect_ms),
            })]
        }
        ServerMessage::PlayerBack { .. } => vec![GameEvent::Connection(Connection::Connected)],
        ServerMessage::GameOver { .. } => vec![GameEvent::ShotClock(None)],
        ServerMessage::GameFinished {
            seat,
            winner,
            reason,
            ..
        } => vec![GameEvent::EndedAway(AwayResult::for_seat(
            *seat, *winner, reason,
        ))],
        ServerMessage::Error { message, .. } => vec![GameEvent::Refused(message.clone())],
        ServerMessage::Reject { reason } => {
            vec![GameEvent::Connection(Connection::Closed(reason.clone()))]
        }
        ServerMessage::Rated {
            seat,
            before,
            after,
        } => vec![GameEvent::Rated {
            seat: *seat,
            before: *before,
            after: *after,
        }],
        ServerMessage::Ratings { ratings } => vec![GameEvent::Ratings(*ratings)],
        // The server's own notice, said in the room like its other notices.
        ServerMessage::Draining { message } => vec![GameEvent::Chat(ChatLine {
            from: String::new(),
            text: format!("Server: {message}"),
        })],
        _ => Vec::new(),
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

    #[test]
    fn a_rating_and_a_drain_reach_the_game_screen() {
        let rated = ServerMessage::Rated {
            seat: Seat::B,
            before: 1500,
            after: 1338,
        };
        assert_eq!(
            game_events(&rated, Some(Seat::A)),
            [GameEvent::Rated {
                seat: Seat::B,
                before: 1500,
                after: 1338
            }]
        );
        let ratings = ServerMessage::Ratings {
            ratings: [1620, 1480],
        };
        assert_eq!(
            game_events(&ratings, None),
            [GameEvent::Ratings([1620, 1480])]
        );
        let drain = ServerMessage::Draining {
            message: "your game goes on to its end".into(),
        };
        match &game_events(&drain, Some(Seat::A))[..] {
            [GameEvent::Chat(line)] => {
                assert!(line.from.is_empty(), "a notice, not a player's line");
                assert!(line.text.contains("your game goes on"), "{}", line.text);
            }
            other => panic!("a drain should be said in the room, got {other:?}"),
        }
    }
}
