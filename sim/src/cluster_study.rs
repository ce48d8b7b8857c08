//! `breakshot-sim cluster-study`: plays random games (8-ball and 9-ball racks on the three
//! pocket tables, a break and then strikes at random object balls, as a player would) and
//! reports the distribution of events per shot. Every position after the break is one the
//! engine itself left, so frozen clusters, balls frozen to rails and balls resting against
//! each other turn up as they do in play (docs/stability.md).

use breakshot_shared::physics::engine::MAX_EVENTS;
use breakshot_shared::physics::{
    BallState, EventKind, MotionState, Shot, ShotError, Simulator, Strike, TableKind,
};
use breakshot_shared::rules::rack::{self, SplitMix64};

/// What the study measured.
#[derive(Debug, serde::Serialize)]
pub struct Summary {
    pub games: usize,
    pub shots: usize,
    pub median_events: usize,
    pub p99_events: usize,
    pub max_events: usize,
    pub max_ball_ball_events: usize,
    /// Shots that reached the `MAX_EVENTS` safety net.
    pub event_limit: usize,
    /// Shots the engine refused for another reason (none expected).
    pub other_errors: usize,
}

/// Plays `games` games of at most `shots_per_game` strikes each, from `seed`.
pub fn run(games: usize, shots_per_game: usize, seed: u64) -> Summary {
    let mut rng = SplitMix64::new(seed);
    let mut sim = Simulator::new();
    let mut events = Vec::new();
    let mut max_ball_ball = 0;
    let (mut event_limit, mut other_errors) = (0, 0);
    let tables = [
        TableKind::SevenFoot,
        TableKind::EightFoot,
        TableKind::NineFoot,
    ];
    for game in 0..games {
        let kind = tables[game % tables.len()];
        let rack_seed = rng.next_u64();
        let mut balls = if game % 2 == 0 {
            rack::eight_ball(kind, rack_seed)
        } else {
            rack::nine_ball(kind, rack_seed)
        };
        for shot_no in 0..shots_per_game {
            place_cue_ball(&mut balls, kind);
            let Some(strike) = random_strike(&balls, shot_no == 0, &mut rng) else {
                break;
            };
            let shot = Shot::new(kind, balls.clone()).struck(0, strike);
            match sim.run(&shot) {
                Ok(out) => {
                    events.push(out.events.len());
                    let hits = out
                        .events
                        .iter()
                        .filter(|e| matches!(e.kind, EventKind::BallBall { .. }))
                        .count();
                    max_ball_ball = max_ball_ball.max(hits);
                    balls = out.finals.clone();
                }
                Err(ShotError::EventLimit) => {
                    event_limit += 1;
                    events.push(MAX_EVENTS);
                    break;
                }
                Err(_) => {
                    other_errors += 1;
                    break;
                }
            }
        }
    }
    events.sort_unstable();
    let pick = |q: f64| {
        events
            .get(((events.len().max(1) - 1) as f64 * q).round() as usize)
            .copied()
            .unwrap_or(0)
    };
    Summary {
        games,
        shots: events.len(),
        median_events: pick(0.5),
        p99_events: pick(0.99),
        max_events: events.last().copied().unwrap_or(0),
        max_ball_ball_events: max_ball_ball,
        event_limit,
        other_errors,
    }
}

/// Ball in hand after a scratch: the cue ball (index 0) goes back to the break spot, or as
/// near the foot spot as the rules' spotting allows (which always finds a place).
fn place_cue_ball(balls: &mut [BallState], kind: TableKind) {
    let cue = &balls[0];
    if cue.motion != MotionState::Pocketed {
        return;
    }
    let spot = rack::break_spot(kind);
    if rack::is_free(balls, 0, spot, kind) {
        balls[0] = BallState::at_rest(spot);
        return;
    }
    balls[0] = BallState::at_rest(spot);
    balls[0].motion = MotionState::Pocketed;
    let _ = rack::spot(balls, 0, kind);
}

/// The break (hard, at the rack) or a strike at a random object ball still on the table,
/// a few degrees off, at a random speed and tip within the miscue limit.
fn random_strike(balls: &[BallState], brk: bool, rng: &mut SplitMix64) -> Option<Strike> {
    let on_table: Vec<usize> = (1..balls.len())
        .filter(|&i| balls[i].motion != MotionState::Pocketed)
        .collect();
    if on_table.is_empty() {
        return None;
    }
    let target = on_table[rng.below(on_table.len() as u64) as usize];
    // Up to about six degrees either side of the centre of the target ball.
    let aim = (balls[target].pos - balls[0].pos).normalize_or_zero();
    let dir = aim + aim.perp() * ((rng.unit() - 0.5) * 0.2);
    let speed = if brk {
        6.0 + 4.0 * rng.unit()
    } else {
        0.3 + 7.7 * rng.unit()
    };
    let tip = rng.offset(0.45);
    Strike {
        speed,
        dir,
        tip,
        elevation_deg: 0.0,
    }
    .validated()
    .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_study_plays_every_shot_within_the_safety_net() {
        let summary = run(6, 4, 7);
        assert!(summary.shots >= 6, "{summary:?}");
        assert_eq!(summary.event_limit, 0, "{summary:?}");
        assert_eq!(summary.other_errors, 0, "{summary:?}");
        assert!(summary.median_events <= summary.max_events);
    }
}
