//! Ghost-ball pots ranked by geometry alone: the baseline player of the load bot and of the
//! computer player's study.

use glam::DVec2;

use crate::physics::Table;
use crate::rules::{is_off_table, Game};

/// What the ghost-ball player looks at in a game: the cue ball, the balls it may aim at
/// (those the rules let it hit first, still on the table) and the pockets' centres.
pub struct GhostView {
    /// The cue ball's centre.
    pub cue: DVec2,
    /// The balls that may be aimed at, with their centres.
    pub targets: Vec<(u8, DVec2)>,
    /// The pockets' centres.
    pub pockets: Vec<DVec2>,
}

impl GhostView {
    /// The view of `game` as it stands.
    pub fn of(game: &Game) -> GhostView {
        let balls = game.balls();
        let table = Table::new(game.table());
        let legal = game.legal_first_balls();
        GhostView {
            cue: balls[game.cue_ball()].pos,
            targets: balls
                .iter()
                .enumerate()
                .filter(|&(i, b)| i != game.cue_ball() && !is_off_table(b))
                .filter(|&(i, _)| legal.is_empty() || legal.contains(&(i as u8)))
                .map(|(i, b)| (i as u8, b.pos))
                .collect(),
            pockets: table
                .pockets
                .iter()
                .map(|p| table.to_scene(p.center))
                .collect(),
        }
    }
}

/// Every pot of a target into a pocket that the ghost-ball aim makes at all likely (the cue
/// ball's aim within about 73° of the object ball's path), best first: `(score, aim,
/// pocket)`, scored by straightness less a tenth of the distance the balls travel.
pub fn ranked_pots(
    cue: DVec2,
    targets: &[(u8, DVec2)],
    pockets: &[DVec2],
    radius: f64,
) -> Vec<(f64, DVec2, u8)> {
    let mut options = Vec::new();
    for (_, t) in targets {
        for (k, p) in pockets.iter().enumerate() {
            let to_pocket = (*p - *t).normalize_or_zero();
            let ghost = *t - to_pocket * (2.0 * radius);
            let aim = (ghost - cue).normalize_or_zero();
            let straightness = aim.dot(to_pocket);
            if straightness > 0.3 {
                let dist = ghost.distance(cue) + p.distance(*t);
                options.push((straightness - 0.1 * dist, aim, k as u8));
            }
        }
    }
    options.sort_by(|a, b| b.0.total_cmp(&a.0));
    options
}
