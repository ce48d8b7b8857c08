//! Games the unit tests start from.

use breakshot_shared::rules::{EightBallRules, Game, Settings, Variant};

/// An 8-ball game under WPA rules, offline, racked from `seed`, at its break.
pub(crate) fn eight_ball(seed: u64) -> Game {
    Game::new(
        Variant::EightBall(EightBallRules::Wpa),
        Settings::offline(),
        seed,
    )
}
