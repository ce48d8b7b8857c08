//! Who chooses a seat's moves when no person does: the ghost-ball player (aim at a pocket,
//! with some randomness) or the computer player at a level. A seat controller: it only
//! picks commands; how they travel is the link's concern.

use breakshot_shared::ai::{self, Level, Rng};
use breakshot_shared::protocol::ClientMessage;
use breakshot_shared::rules::Game;

/// Picks a move for whoever is to move: a decision, a cue-ball placement or a shot.
#[derive(Clone, Debug)]
pub struct Chooser {
    rng: Rng,
    /// None: ghost-ball aim; else the computer player at this level.
    level: Option<Level>,
}

impl Chooser {
    /// A chooser aiming ghost-ball pots, whose randomness starts from `seed`.
    pub fn new(seed: u64) -> Chooser {
        Chooser {
            rng: Rng::new(seed),
            level: None,
        }
    }

    /// A chooser that plays as the computer player at `level` (`shared::ai`), with
    /// decisions seeded from `seed`.
    pub fn computer(level: Level, seed: u64) -> Chooser {
        Chooser {
            rng: Rng::new(seed),
            level: Some(level),
        }
    }

    /// The computer player's level, None for ghost-ball aim.
    pub fn level(&self) -> Option<Level> {
        self.level
    }

    /// The move for the seat to move, `None` if the game is over. The computer player may
    /// think for up to a second.
    pub fn choose(&mut self, game: &Game) -> Option<ClientMessage> {
        let command = match self.level {
            Some(level) => ai::decide(game, level, self.rng.next_u64())?,
            None => ai::ghost_move(game, &mut self.rng)?,
        };
        ClientMessage::for_command(game.turn(), command)
    }
}
