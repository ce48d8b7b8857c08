//! Undo, redo and "again" at one computer: the games the replica held before each of the
//! player's shots, kept whole, so going back restores the table to the bit (every state
//! is the replica's own `Game`, not a re-simulation).

use breakshot_shared::physics::Strike;
use breakshot_shared::rules::Game;

/// A position to go back to: the game as it stood, and the strike played from it (for
/// "again", which sets the cue as it was).
#[derive(Clone, Debug, PartialEq)]
pub struct Position {
    /// The game as the replica held it.
    pub game: Game,
    /// The strike played from it, if a shot was.
    pub strike: Option<Strike>,
}

/// The positions behind and ahead of the table shown.
#[derive(Clone, Debug, Default)]
pub struct History {
    back: Vec<Position>,
    forward: Vec<Position>,
}

/// How many positions are kept behind the table: old enough ones are forgotten, so a long
/// practice does not grow without bound (a game is a few kilobytes).
pub(crate) const KEPT: usize = 1000;

impl History {
    /// An empty history.
    pub fn new() -> History {
        History::default()
    }

    /// `before` is about to be played from with `strike`: it becomes the position an undo
    /// goes back to, and the positions ahead (undone ones) are dropped.
    pub fn shot(&mut self, before: Game, strike: Strike) {
        self.push(Position {
            game: before,
            strike: Some(strike),
        });
    }

    /// `before` is about to be changed by hand (a ball moved, taken off or put back): an
    /// undo goes back to it as to the table before a shot.
    pub fn changed(&mut self, before: Game) {
        self.push(Position {
            game: before,
            strike: None,
        });
    }

    fn push(&mut self, before: Position) {
        self.forward.clear();
        self.back.push(before);
        if self.back.len() > KEPT {
            self.back.remove(0);
        }
    }

    /// Goes back one shot from `current`: the position before it, which `current` can be
    /// redone to.
    pub fn undo(&mut self, current: Game) -> Option<Position> {
        step(&mut self.back, &mut self.forward, current)
    }

    /// Goes forward again to the position an undo left.
    pub fn redo(&mut self, current: Game) -> Option<Position> {
        step(&mut self.forward, &mut self.back, current)
    }

    /// "Again": the position before the last shot with its strike, to play it once more.
    /// It is an undo (the attempt stays redoable until the next shot replaces it).
    pub fn again(&mut self, current: Game) -> Option<Position> {
        self.undo(current)
    }

    /// Forgets everything (a new rack, another table).
    pub fn clear(&mut self) {
        self.back.clear();
        self.forward.clear();
    }

    /// How many shots can be undone.
    pub fn behind(&self) -> usize {
        self.back.len()
    }

    /// How many undone shots can be redone.
    pub fn ahead(&self) -> usize {
        self.forward.len()
    }
}

/// One step through the history: the position on top of `from`, with `current` (and that
/// position's strike, which leads from one to the other) pushed on `to`.
fn step(from: &mut Vec<Position>, to: &mut Vec<Position>, current: Game) -> Option<Position> {
    let there = from.pop()?;
    to.push(Position {
        game: current,
        strike: there.strike,
    });
    Some(there)
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::hash::state_hash;
    use breakshot_shared::rules::{Command, EightBallRules, Seat, Variant};
    use glam::DVec2;

    fn strike(angle: f64, speed: f64) -> Strike {
        Strike {
            speed,
            dir: DVec2::new(libm::cos(angle), libm::sin(angle)),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        }
    }

    fn play(game: &mut Game, s: Strike) {
        game.apply(
            Seat::A,
            &Command::Shot {
                strike: s,
                call: None,
            },
        )
        .expect("a practice shot is legal");
    }

    /// A practice rack and three shots played on it with a history kept: the games seen.
    fn three_shots() -> (History, Vec<Game>) {
        let mut game =
            Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 7).expect("a rack");
        let mut history = History::new();
        let mut seen = vec![game.clone()];
        for (i, s) in [strike(1.5, 6.0), strike(0.3, 2.0), strike(-2.0, 3.0)]
            .into_iter()
            .enumerate()
        {
            history.shot(game.clone(), s);
            play(&mut game, s);
            assert_ne!(
                state_hash(game.balls()),
                state_hash(seen[i].balls()),
                "shot {i} moved the balls"
            );
            seen.push(game.clone());
        }
        (history, seen)
    }

    #[test]
    fn three_undos_give_back_the_table_before_three_shots_to_the_bit() {
        let (mut history, seen) = three_shots();
        let mut current = seen[3].clone();
        for back in (0..3).rev() {
            current = history.undo(current).expect("a shot to undo").game;
            assert_eq!(current, seen[back]);
            assert_eq!(state_hash(current.balls()), state_hash(seen[back].balls()));
        }
        assert!(history.undo(current.clone()).is_none(), "nothing before");
        assert_eq!(history.ahead(), 3);
        for after in &seen[1..] {
            current = history.redo(current).expect("a shot to redo").game;
            assert_eq!(current, *after);
        }
        assert!(history.redo(current).is_none(), "nothing after");
        assert_eq!(history.behind(), 3);
    }

    #[test]
    fn a_new_shot_after_an_undo_drops_what_was_ahead() {
        let (mut history, seen) = three_shots();
        let back = history.undo(seen[3].clone()).expect("undo").game;
        history.shot(back, strike(0.0, 1.0));
        assert_eq!(history.ahead(), 0);
        assert_eq!(history.behind(), 3);
    }

    #[test]
    fn again_gives_the_position_and_the_strike_of_the_last_shot() {
        let (mut history, seen) = three_shots();
        let again = history
            .again(seen[3].clone())
            .expect("a shot to play again");
        assert_eq!(again.game, seen[2]);
        assert_eq!(again.strike, Some(strike(-2.0, 3.0)));
        // Playing the same strike from it gives the same table as the first time.
        let mut replayed = again.game.clone();
        play(&mut replayed, again.strike.expect("a strike"));
        assert_eq!(replayed, seen[3]);
    }

    #[test]
    fn the_history_is_bounded() {
        let game = Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 1).expect("rack");
        let mut history = History::new();
        for _ in 0..KEPT + 5 {
            history.shot(game.clone(), strike(0.0, 1.0));
        }
        assert_eq!(history.behind(), KEPT);
        history.clear();
        assert_eq!((history.behind(), history.ahead()), (0, 0));
    }
}
