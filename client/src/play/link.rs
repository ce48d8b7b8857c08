//! Where a game is decided, as a game screen sees it: it sends [`Command`]s and hears
//! [`GameEvent`]s. The same screen plays over the network (the server decides) or on one
//! computer with two players taking turns ([`LocalLink`]: the rules here decide).

use std::collections::VecDeque;

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::Invite;
use breakshot_shared::rules::{Command, Game, Seat, Settings, TurnId, Variant};

use super::event::GameEvent;

/// The game as a screen shows it, as a link that plays a seat itself needs to see it.
pub trait Shown {
    /// The game shown, if any.
    fn shown_game(&self) -> Option<&Game>;
    /// True when the game shown waits for `seat` to shoot or decide (no shot playing).
    fn waits_for(&self, seat: Seat) -> bool;
}

/// A source of game events and a sink for commands.
pub trait GameLink {
    /// The seat played here, or None when both seats are (players take turns at one
    /// computer) or when none is ([`GameLink::watching`]).
    fn seat(&self) -> Option<Seat>;
    /// Sends `seat`'s command on the game as it stands here.
    fn send(&mut self, game: &Game, seat: Seat, command: Command);
    /// The next event, if one is waiting. Never blocks.
    fn poll(&mut self) -> Option<GameEvent>;
    /// Starts a new game with the same settings.
    fn rematch(&mut self);
    /// Whether players can chat here (an online room).
    fn chats(&self) -> bool {
        false
    }
    /// Says `text` in the room.
    fn chat(&mut self, _text: String) {}
    /// Shows the others where this player aims on `turn` (online rooms; throttled by the
    /// caller).
    fn aim(&mut self, _turn: TurnId, _strike: Strike) {}
    /// Tells the deciding side that its judgement of the shot on `turn` (its state hash
    /// `hash`) was not reached here; a local game has nobody to tell.
    fn report_desync(&mut self, _turn: TurnId, _hash: u64) {}
    /// The link a friend opens in a browser to join, when the web client is served here.
    fn web_link(&self) -> Option<String> {
        None
    }
    /// The invite to show while the opponent's seat is empty, when this computer hosts.
    fn invite(&self) -> Option<&Invite> {
        None
    }
    /// True when this computer only watches the game (a spectator): no seat is played here.
    fn watching(&self) -> bool {
        false
    }
    /// Called once a frame with the game as the screen shows it, `dt` seconds after the last
    /// call: a link that plays a seat itself (the computer) answers here when the game waits
    /// for that seat.
    fn update(&mut self, _shown: &dyn Shown, _dt: f64) {}
    /// True while the seat this link plays itself is thinking about its move.
    fn thinking(&self) -> bool {
        false
    }
    /// True when the player here may take shots back (against the computer: the rules here
    /// decide and nobody else sees the game).
    fn takes_back(&self) -> bool {
        false
    }
}

/// Two players at one computer: the rules here check each command, and the screen's copy of
/// the game applies it.
pub struct LocalLink {
    variant: Variant,
    settings: Settings,
    seed: u64,
    /// The game a rematch starts again from, when it is not a new rack (a practice table).
    again: Option<Game>,
    events: VecDeque<GameEvent>,
}

impl LocalLink {
    /// A new local game.
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> LocalLink {
        let game = Game::new(variant, settings, seed);
        LocalLink {
            variant,
            settings,
            seed,
            again: None,
            events: VecDeque::from([GameEvent::Started(Box::new(game))]),
        }
    }

    /// A local game starting from `game` (a practice table laid out from a scene); a
    /// rematch starts from it again.
    pub fn from_game(game: Game) -> LocalLink {
        LocalLink {
            variant: game.variant(),
            settings: game.settings(),
            seed: game.seed(),
            again: Some(game.clone()),
            events: VecDeque::from([GameEvent::Started(Box::new(game))]),
        }
    }
}

impl GameLink for LocalLink {
    fn seat(&self) -> Option<Seat> {
        None
    }

    fn send(&mut self, game: &Game, seat: Seat, command: Command) {
        let event = match game.check(seat, &command) {
            Ok(()) => GameEvent::Decided {
                turn: game.turn(),
                seat,
                command,
            },
            Err(e) => GameEvent::Refused(e.to_string()),
        };
        self.events.push_back(event);
    }

    fn poll(&mut self) -> Option<GameEvent> {
        self.events.pop_front()
    }

    fn rematch(&mut self) {
        let game = match &self.again {
            Some(game) => game.clone(),
            None => {
                self.seed = self.seed.wrapping_add(1);
                Game::new(self.variant, self.settings, self.seed)
            }
        };
        self.events.push_back(GameEvent::Started(Box::new(game)));
    }
}
