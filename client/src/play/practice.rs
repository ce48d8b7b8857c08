//! The window's practice table: a rules [`Game`] of [`Variant::Practice`] laid out from a
//! scene (a scene file, or a game's opening rack), played through the local link and the
//! replica like any other game; the rules re-spot a pocketed cue ball and check every
//! placement.

use breakshot_shared::physics::{Effects, Models};
use breakshot_shared::rules::{EightBallRules, Game, RuleError, Settings, Variant};
use breakshot_shared::scene::{Scene, SceneBall};

use crate::view::palette;

/// The practice table the menu opens: an 8-ball rack on the 9 ft table (shuffled by
/// `seed`), the cue ball behind the head string.
pub fn practice_rack(seed: u64) -> Result<Game, RuleError> {
    Game::practice(&rack_scene(Variant::EightBall(EightBallRules::Wpa), seed))
}

/// The opening position of `variant`'s game (its rack shuffled by `seed`: the three-cushion
/// start on the carom table, a 9-ball diamond, ...) as a scene, the balls named as the game
/// names them ([`palette::ball_ids`]).
pub fn rack_scene(variant: Variant, seed: u64) -> Scene {
    let game = Game::new(variant, Settings::offline(), seed);
    let balls = palette::ball_ids(&game)
        .into_iter()
        .zip(game.balls())
        .map(|(id, b)| SceneBall {
            id,
            pos: b.pos.to_array(),
            vel: [0.0; 2],
            spin: [0.0; 3],
        })
        .collect();
    Scene {
        table: game.table(),
        physics: game.params(),
        models: Models::default(),
        effects: Effects::default(),
        horizon: None,
        balls,
        strike: None,
    }
}
