//! The reference shot: a fixed, built-in break whose state hash both sides compute at
//! start. A client whose physics differs from the server's by a single bit gets a different
//! hash and is refused in the handshake, before it could desynchronise a game.

use glam::DVec2;

use crate::physics::{simulate, BallState, Params, Shot, ShotError, Strike, TableKind};

/// A six-ball triangle on a 9-foot table, broken hard with a little side and follow, so the
/// shot exercises ball–ball and cushion collisions, pockets and every motion state.
pub fn reference_shot() -> Shot {
    let table = TableKind::NineFoot;
    let (width, length) = table.size().unwrap_or((1.27, 2.54));
    let r = Params::default().ball_radius;
    let row = 2.0 * r * 0.866_025_403_784_438_6 + 1e-4;
    let apex = DVec2::new(width / 2.0, length * 0.75);
    let mut balls = vec![BallState::at_rest(DVec2::new(
        width / 2.0 + 0.05,
        length * 0.25,
    ))];
    for i in 0..3u32 {
        for j in 0..=i {
            let x = apex.x + (f64::from(j) - f64::from(i) / 2.0) * (2.0 * r + 1e-4);
            balls.push(BallState::at_rest(DVec2::new(
                x,
                apex.y + f64::from(i) * row,
            )));
        }
    }
    let aim = apex - balls[0].pos;
    let strike = Strike {
        speed: 8.0,
        dir: aim / aim.length(),
        tip: DVec2::new(0.1, 0.2),
        elevation_deg: 0.0,
    };
    Shot::new(table, balls).struck(0, strike)
}

/// The state hash of [`reference_shot`] as this build computes it.
pub fn reference_hash() -> Result<u64, ShotError> {
    simulate(&reference_shot()).map(|o| o.hash())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_shot_is_valid_busy_and_repeatable() {
        let outcome = simulate(&reference_shot()).unwrap();
        assert!(outcome.events.len() > 10, "{} events", outcome.events.len());
        assert_eq!(reference_hash().unwrap(), outcome.hash());
    }
}
