//! `breakshot-sim cluster-study`: plays random games by the rules (8-ball and 9-ball on the
//! three pocket tables, both seats played by the ghost-ball player: the break, then pots it
//! aims at a legal ball with a little noise, ball in hand placed anywhere legal) and reports
//! the distribution of events per shot. Every position is one the rules and the engine left,
//! so frozen clusters, balls frozen to rails and balls resting against each other turn up as
//! they do in play (docs/stability.md).

use breakshot_shared::ai::{ghost_move, Rng};
use breakshot_shared::physics::{EventKind, ShotError, TableKind};
use breakshot_shared::rules::{Command, EightBallRules, Game, RuleError, Seat, Settings, Variant};

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
    /// Commands the rules refused for another reason: the ghost-ball player shoots a cue
    /// ball in hand from where it lies, which the rules refuse when that spot is no legal
    /// placement (a few in ten thousand games). The game ends there.
    pub other_errors: usize,
}

/// Plays `games` games of at most `shots_per_game` shots each (the break included), from
/// `seed`.
pub fn run(games: usize, shots_per_game: usize, seed: u64) -> Summary {
    let variants = [Variant::EightBall(EightBallRules::Wpa), Variant::NineBall];
    let tables = [
        TableKind::SevenFoot,
        TableKind::EightFoot,
        TableKind::NineFoot,
    ];
    let mut events = Vec::new();
    let mut max_ball_ball = 0;
    let (mut event_limit, mut other_errors) = (0, 0);
    let limit_message = RuleError::InvalidShot(ShotError::EventLimit.to_string());
    for g in 0..games {
        let game_seed = seed.wrapping_mul(1_000_003).wrapping_add(g as u64);
        let settings = Settings {
            table: tables[g % tables.len()],
            ..Settings::offline()
        };
        let mut game = Game::new(variants[g % variants.len()], settings, game_seed);
        let mut players = [Rng::new(game_seed ^ 0xA), Rng::new(game_seed ^ 0xB)];
        let mut shots = 0;
        // Each shot takes at most a few commands (a decision, a placement, the shot).
        for _ in 0..4 * shots_per_game {
            if shots == shots_per_game {
                break;
            }
            let seat = game.to_move();
            let rng = &mut players[usize::from(seat == Seat::B)];
            let Some(command) = ghost_move(&game, rng) else {
                break;
            };
            let is_shot = matches!(command, Command::Shot { .. });
            match game.apply(seat, &command) {
                Ok(verdict) => {
                    if let Some(out) = verdict.outcome.as_ref().filter(|_| is_shot) {
                        shots += 1;
                        events.push(out.events.len());
                        let hits = out
                            .events
                            .iter()
                            .filter(|e| matches!(e.kind, EventKind::BallBall { .. }))
                            .count();
                        max_ball_ball = max_ball_ball.max(hits);
                    }
                    if verdict.over.is_some() {
                        break;
                    }
                }
                Err(e) if e == limit_message => {
                    event_limit += 1;
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
        shots: events.len() + event_limit,
        median_events: pick(0.5),
        p99_events: pick(0.99),
        max_events: events.last().copied().unwrap_or(0),
        max_ball_ball_events: max_ball_ball,
        event_limit,
        other_errors,
    }
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
        assert!(summary.max_events > 0, "{summary:?}");
    }
}
