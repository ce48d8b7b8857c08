//! Three-cushion candidates. A carom has no ghost ball to aim at: the cue ball must meet both
//! other balls with three cushions before the second, and which paths do that is a question
//! for the engine, not for geometry. So the shooter's ball is struck in a fan of directions at
//! a few speeds and spins, each stroke judged once by the rules, and the strokes that score
//! are the candidates (the search then plays them under noise). The engine's speed is what
//! makes a fan of hundreds of strokes cheap.

use glam::DVec2;

use super::candidates::{Breadth, Candidate, Kind};
use super::geometry::rotate;
use crate::physics::Strike;
use crate::rules::{Command, Game};

/// Cue speeds of the fan (m/s): three cushions and two balls take a firm stroke.
const SPEEDS: [f64; 3] = [3.5, 5.0, 2.5];
/// Turns of a scoring stroke tried to judge how steady it is (degrees).
const NUDGES_DEG: [f64; 4] = [-0.3, -0.15, 0.15, 0.3];
/// Most scoring strokes kept as candidates.
const KEEP: usize = 24;

/// The fan's directions for a breadth: more for stronger players.
fn directions(breadth: &Breadth) -> usize {
    (15 * breadth.pots).clamp(36, 240)
}

/// Strokes of the shooter's ball that score a point from `game` as it lies, the steadiest
/// first (those whose neighbours in the fan score too: a small error in the stroke still
/// scores), at most [`KEEP`]; if none scores, a spread of the fan's strokes, so the search
/// still has a choice. Also returns the simulations spent.
pub(super) fn caroms(game: &Game, breadth: &Breadth) -> (Vec<Candidate>, usize) {
    let shooter = game.to_move();
    let n = directions(breadth);
    let tips: &[DVec2] = if breadth.side {
        &[DVec2::ZERO, DVec2::new(0.3, 0.2), DVec2::new(-0.3, 0.2)]
    } else {
        &[DVec2::ZERO]
    };
    let mut candidates = Vec::new();
    let mut spread = Vec::new();
    let mut runs = 0;
    for &speed in SPEEDS.iter().take(breadth.speeds.clamp(1, SPEEDS.len())) {
        for &tip in tips {
            // One fan: which of its strokes score.
            let fan: Vec<(Strike, bool)> = (0..n)
                .map(|k| {
                    let angle = core::f64::consts::TAU * k as f64 / n as f64;
                    let strike = Strike {
                        speed,
                        dir: rotate(DVec2::X, angle),
                        tip,
                        elevation_deg: 0.0,
                    };
                    let mut g = game.clone();
                    runs += 1;
                    let scores = g
                        .apply(shooter, &Command::Shot { strike, call: None })
                        .is_ok_and(|v| !v.foul && v.next == shooter);
                    (strike, scores)
                })
                .collect();
            for (k, &(strike, scores)) in fan.iter().enumerate() {
                let candidate = |prior| Candidate {
                    strike,
                    call: None,
                    kind: Kind::Carom,
                    prior,
                };
                if scores {
                    // Steadiness at the scale of a player's error: the same stroke turned a
                    // little either way.
                    let steady = NUDGES_DEG
                        .iter()
                        .filter(|&&deg| {
                            let nudged = Strike {
                                dir: rotate(strike.dir, deg * (core::f64::consts::PI / 180.0)),
                                ..strike
                            };
                            let mut g = game.clone();
                            runs += 1;
                            g.apply(
                                shooter,
                                &Command::Shot {
                                    strike: nudged,
                                    call: None,
                                },
                            )
                            .is_ok_and(|v| !v.foul && v.next == shooter)
                        })
                        .count();
                    candidates.push(candidate(steady as f64 / NUDGES_DEG.len() as f64));
                } else if k % 8 == 0 {
                    spread.push(candidate(0.0));
                }
            }
        }
    }
    if candidates.is_empty() {
        return (spread, runs);
    }
    candidates.sort_by(|a, b| b.prior.total_cmp(&a.prior));
    candidates.truncate(KEEP);
    (candidates, runs)
}
