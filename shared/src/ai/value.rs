//! What a table is worth to a player, without simulating: the chance the shooter has a
//! makeable pot, and how far each player is through the rack.

use super::geometry::Layout;
use crate::rules::{Game, Group, InHand, Phase, Seat, Variant};

/// Shot quality assumed for a ball in hand anywhere: a good player nearly always has a pot.
const IN_HAND_QUALITY: f64 = 0.9;
/// … and for a ball in hand behind the head string.
const KITCHEN_QUALITY: f64 = 0.6;

/// How good the best pot is for whoever shoots next on `game`: 0 (nothing) to 1 (sure).
pub(super) fn shot_quality(game: &Game, aim_sigma: f64) -> f64 {
    let in_hand = match game.phase() {
        Phase::Shooting { in_hand, .. } => *in_hand,
        _ => return 0.0,
    };
    match in_hand {
        Some(InHand::Anywhere) => return IN_HAND_QUALITY,
        Some(InHand::Kitchen | InHand::D) => return KITCHEN_QUALITY,
        None => {}
    }
    let layout = Layout::new(game.table(), game.balls());
    let Some(cue) = layout.cue() else {
        return IN_HAND_QUALITY;
    };
    let targets = pottable(game);
    layout.best_pot(cue, &targets, aim_sigma)
}

/// Balls the player to move may pot on a direct shot and keep the table.
pub(super) fn pottable(game: &Game) -> Vec<u8> {
    match game.variant() {
        Variant::Practice => (1..game.balls().len() as u8).collect(),
        Variant::Snooker { .. } => super::snooker::targets(game),
        _ => game.legal_first_balls(),
    }
}

/// How far `seat` is through the rack, 0 to 1 (8-ball: its group and the 8).
fn progress(game: &Game, seat: Seat) -> f64 {
    let Variant::EightBall(_) = game.variant() else {
        return 0.0;
    };
    let Some(group) = game.group_of(seat) else {
        return 0.0;
    };
    let on_table = |b: u8| {
        game.balls()
            .get(usize::from(b))
            .is_some_and(|s| s.motion != crate::physics::MotionState::Pocketed)
    };
    let left = Group::balls(group).filter(|&b| on_table(b)).count();
    (7 - left) as f64 / 8.0
}

/// The worth of `game` to `me`, 0 (lost) to 1 (won): a rough chance of winning.
pub(super) fn value(game: &Game, me: Seat, aim_sigma: f64) -> f64 {
    value_at(game, me, aim_sigma, 1)
}

fn value_at(game: &Game, me: Seat, aim_sigma: f64, depth: u32) -> f64 {
    let shooter = game.to_move();
    let for_shooter = match game.phase() {
        Phase::Over { winner, .. } => {
            return match winner {
                Some(w) if *w == me => 1.0,
                Some(_) => 0.0,
                None => 0.5,
            }
        }
        Phase::Deciding { options } => {
            // The chooser takes the option best for it.
            let best = options
                .iter()
                .filter_map(|&c| {
                    let mut g = game.clone();
                    g.apply(shooter, &crate::rules::Command::Decide(c)).ok()?;
                    (depth > 0).then(|| value_at(&g, shooter, aim_sigma, depth - 1))
                })
                .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))));
            best.unwrap_or(0.5)
        }
        Phase::Shooting { .. } if game.is_break() => 0.52,
        Phase::Shooting { .. } => {
            let q = shot_quality(game, aim_sigma);
            // Snooker is won on points: its own worth of the scores and the balls left.
            match super::snooker::value_for_shooter(game, q) {
                Some(v) => v,
                None => {
                    let lead = progress(game, shooter) - progress(game, shooter.other());
                    (0.5 + 0.4 * q + 0.1 * lead).clamp(0.0, 1.0)
                }
            }
        }
    };
    if shooter == me {
        for_shooter
    } else {
        1.0 - for_shooter
    }
}
