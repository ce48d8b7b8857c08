//! Three-cushion candidates. A carom has no ghost ball to aim at: the cue ball must meet both
//! other balls with three cushions before the second, and which paths do that is a question
//! for the engine, not for geometry. So the shooter's ball is struck in a fan of directions at
//! a few speeds and spins, each stroke judged once by the rules, and the strokes that score
//! are the candidates (the search then plays them under noise). The engine's speed is what
//! makes a fan of hundreds of strokes cheap.

use glam::DVec2;

use super::candidates::{Breadth, Candidate, Kind};
use super::geometry::rotate;
use super::thinking::Meter;
use crate::physics::Strike;
use crate::rules::{Command, Game};

/// Cue speeds of the fan (m/s): three cushions and two balls take a firm stroke.
const SPEEDS: [f64; 3] = [3.5, 5.0, 2.5];
/// Turns of a scoring stroke tried to judge how steady it is (degrees).
pub(super) const NUDGES_DEG: [f64; 4] = [-0.3, -0.15, 0.15, 0.3];
/// Most scoring strokes kept as candidates.
pub(super) const KEEP: usize = 24;

/// The fan's directions for a breadth: more for stronger players.
pub(super) fn directions(breadth: &Breadth) -> usize {
    (15 * breadth.pots).clamp(36, 240)
}

/// The fan's speeds for a breadth.
fn speeds(breadth: &Breadth) -> &'static [f64] {
    &SPEEDS[..breadth.speeds.clamp(1, SPEEDS.len())]
}

/// The fan's tips for a breadth: side spin both ways for those who use it.
fn tips(breadth: &Breadth) -> &'static [DVec2] {
    const PLAIN: [DVec2; 1] = [DVec2::ZERO];
    const SIDE: [DVec2; 3] = [DVec2::ZERO, DVec2::new(0.3, 0.2), DVec2::new(-0.3, 0.2)];
    if breadth.side {
        &SIDE
    } else {
        &PLAIN
    }
}

/// How many fans a breadth strikes: one per speed and tip.
pub(super) fn fans(breadth: &Breadth) -> usize {
    speeds(breadth).len() * tips(breadth).len()
}

/// Strokes of the shooter's ball that score a point from `game` as it lies, the steadiest
/// first (those whose neighbours in the fan score too: a small error in the stroke still
/// scores), at most [`KEEP`]; if none scores, a spread of the fan's strokes, so the search
/// still has a choice.
pub(super) async fn caroms(game: &Game, breadth: &Breadth, meter: &Meter) -> Vec<Candidate> {
    let shooter = game.to_move();
    // Does `strike` score from the table as it lies?
    let scores = async |strike: Strike| {
        meter.simulation().await;
        let mut g = game.clone();
        g.apply(shooter, &Command::Shot { strike, call: None })
            .is_ok_and(|v| !v.foul && v.next == shooter)
    };
    let n = directions(breadth);
    let tips = tips(breadth);
    let mut candidates = Vec::new();
    let mut spread = Vec::new();
    for &speed in speeds(breadth) {
        for &tip in tips {
            // One fan: which of its strokes score.
            let mut fan: Vec<(Strike, bool)> = Vec::with_capacity(n);
            for k in 0..n {
                let angle = core::f64::consts::TAU * k as f64 / n as f64;
                let strike = Strike {
                    speed,
                    dir: rotate(DVec2::X, angle),
                    tip,
                    elevation_deg: 0.0,
                };
                fan.push((strike, scores(strike).await));
            }
            for (k, &(strike, scoring)) in fan.iter().enumerate() {
                let candidate = |prior| Candidate {
                    strike,
                    call: None,
                    kind: Kind::Carom,
                    prior,
                };
                if scoring {
                    // Steadiness at the scale of a player's error: the same stroke turned a
                    // little either way.
                    let mut steady = 0;
                    for deg in NUDGES_DEG {
                        let nudged = Strike {
                            dir: rotate(strike.dir, deg * (core::f64::consts::PI / 180.0)),
                            ..strike
                        };
                        steady += usize::from(scores(nudged).await);
                    }
                    candidates.push(candidate(steady as f64 / NUDGES_DEG.len() as f64));
                } else if k % 8 == 0 {
                    spread.push(candidate(0.0));
                }
            }
        }
    }
    if candidates.is_empty() {
        return spread;
    }
    candidates.sort_by(|a, b| b.prior.total_cmp(&a.prior));
    candidates.truncate(KEEP);
    candidates
}
