//! Where a game is decided, as a game screen sees it: it sends [`Command`]s and hears
//! [`GameEvent`]s. The same screen plays over the network (the server decides) or on one
//! computer with two players taking turns ([`LocalLink`], the rules run here).

use std::collections::VecDeque;

use breakshot_shared::protocol::{AimAid, Invite};
use breakshot_shared::rules::{Command, Game, Seat, Settings, Variant, Verdict};

use crate::view::hud::Connection;

/// What a game screen hears. A server announces an accepted shot at once, so every client
/// starts showing it, and its judgement when it has simulated it; the same two steps are
/// used when the rules run here.
#[derive(Clone, Debug, PartialEq)]
pub enum GameEvent {
    /// A new game starts from this state (first game, rematch or resynchronisation).
    Started(Box<Game>),
    /// `seat`'s command was accepted and is to be applied.
    Accepted {
        seat: Seat,
        command: Command,
    },
    /// The judgement of the last accepted command: readable reasons, whether it was a foul,
    /// and for a shot the deciding side's state hash.
    Judged(Judgement),
    /// Our command was refused; nothing changed.
    Refused(String),
    Connection(Connection),
    /// The shot clock restarted with this many seconds, or stopped (None).
    ShotClock(Option<f64>),
    /// The aiming aids the room allows (a local game allows them all).
    AimAid(AimAid),
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Judgement {
    pub reasons: Vec<String>,
    pub foul: bool,
    pub hash: Option<u64>,
}

impl Judgement {
    /// The judgement in a rules verdict.
    pub fn of(verdict: &Verdict) -> Judgement {
        Judgement {
            reasons: crate::view::hud::verdict_lines(verdict),
            foul: verdict.foul,
            hash: verdict.shot.as_ref().map(|s| s.hash),
        }
    }
}

/// A source of game events and a sink for commands.
pub trait GameLink {
    /// The seat played here, or None when both seats are (players take turns at one
    /// computer).
    fn seat(&self) -> Option<Seat>;
    fn send(&mut self, seat: Seat, command: Command);
    fn poll(&mut self) -> Option<GameEvent>;
    /// Starts a new game with the same settings.
    fn rematch(&mut self);
    /// The invite to show while the opponent's seat is empty, when this computer hosts.
    fn invite(&self) -> Option<&Invite> {
        None
    }
}

/// Two players at one computer: the rules are applied here.
pub struct LocalLink {
    game: Game,
    seed: u64,
    events: VecDeque<GameEvent>,
}

impl LocalLink {
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> LocalLink {
        let game = Game::new(variant, settings, seed);
        LocalLink {
            events: VecDeque::from([GameEvent::Started(Box::new(game.clone()))]),
            game,
            seed,
        }
    }
}

impl GameLink for LocalLink {
    fn seat(&self) -> Option<Seat> {
        None
    }

    fn send(&mut self, seat: Seat, command: Command) {
        match self.game.apply(seat, &command) {
            Ok(verdict) => {
                self.events.push_back(GameEvent::Accepted { seat, command });
                self.events
                    .push_back(GameEvent::Judged(Judgement::of(&verdict)));
            }
            Err(e) => self.events.push_back(GameEvent::Refused(e.to_string())),
        }
    }

    fn poll(&mut self) -> Option<GameEvent> {
        self.events.pop_front()
    }

    fn rematch(&mut self) {
        self.seed = self.seed.wrapping_add(1);
        self.game = Game::new(self.game.variant(), self.game.settings(), self.seed);
        self.events
            .push_back(GameEvent::Started(Box::new(self.game.clone())));
    }
}
