//! A racked table for practice: fifteen balls in a triangle on the foot spot, the cue ball on
//! the head string.

use breakshot_shared::physics::{BallState, Params, TableKind};
use glam::DVec2;

/// Gap left between racked balls (m), so that rounding never makes two of them overlap.
const RACK_GAP: f64 = 1e-5;

/// Ball numbers row by row from the apex: 1 at the apex, 8 in the middle, a solid and a
/// stripe in the back corners.
const RACK_ORDER: [u8; 15] = [1, 9, 2, 10, 8, 3, 11, 4, 12, 5, 6, 13, 7, 14, 15];

/// Balls 0 (cue) to 15 at rest, indexed by ball number, on `kind` (the nine-foot table's
/// size if `kind` is the open table).
pub fn eight_ball_rack(kind: TableKind, params: &Params) -> Vec<BallState> {
    let (w, l) = kind.size().unwrap_or((1.27, 2.54));
    let r = params.ball_radius + 0.5 * RACK_GAP;
    let foot = DVec2::new(0.5 * w, 0.75 * l);
    let mut balls = vec![BallState::at_rest(DVec2::ZERO); 16];
    balls[0] = BallState::at_rest(DVec2::new(0.5 * w, 0.25 * l));
    let mut k = 0;
    for row in 0..5 {
        for j in 0..=row {
            let x = foot.x + (2.0 * j as f64 - row as f64) * r;
            let y = foot.y + row as f64 * 3f64.sqrt() * r;
            balls[RACK_ORDER[k] as usize] = BallState::at_rest(DVec2::new(x, y));
            k += 1;
        }
    }
    balls
}

/// Ids of the racked balls: "cue", then "1" to "15".
pub fn rack_ids() -> Vec<String> {
    std::iter::once("cue".to_string())
        .chain((1..=15).map(|n| n.to_string()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::engine::check;
    use breakshot_shared::physics::Shot;

    #[test]
    fn rack_is_a_valid_table_with_every_ball() {
        for kind in [
            TableKind::SevenFoot,
            TableKind::EightFoot,
            TableKind::NineFoot,
        ] {
            let params = Params::default();
            let balls = eight_ball_rack(kind, &params);
            assert_eq!(balls.len(), 16);
            let shot = Shot {
                table: kind,
                params,
                models: Default::default(),
                effects: Default::default(),
                horizon: None,
                balls: balls.clone(),
                strike: None,
            };
            assert_eq!(check(&shot), Ok(()));
            // Apex on the foot spot, eight in the middle of the third row.
            let (w, l) = kind.size().expect("pocket table");
            assert_eq!(balls[1].pos, DVec2::new(0.5 * w, 0.75 * l));
            assert!((balls[8].pos.x - 0.5 * w).abs() < 1e-12);
        }
    }
}
