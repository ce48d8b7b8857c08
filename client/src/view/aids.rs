//! Aiming aids: the aim line, the ghost ball and the predicted paths of the cue ball and of
//! the first ball it hits. They come from simulating the shot with the same engine the server
//! uses, so what the aids show is what the shot will do.

use breakshot_shared::physics::{EventKind, Outcome, Shot, ShotError, Simulator};
use breakshot_shared::protocol::AimAid;
use glam::DVec2;

/// Points per second of shot time along a predicted path.
const SAMPLES_PER_SECOND: f64 = 60.0;
/// Most points in one predicted path.
const MAX_POINTS: usize = 1200;

/// Which aids are shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AidToggles {
    /// Show the aim line.
    pub aim_line: bool,
    /// Show the ghost ball.
    pub ghost_ball: bool,
    /// Show the predicted paths.
    pub paths: bool,
}

impl Default for AidToggles {
    fn default() -> Self {
        AidToggles {
            aim_line: true,
            ghost_ball: true,
            paths: true,
        }
    }
}

/// One aid, for toggling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aid {
    /// The aim line.
    AimLine,
    /// The ghost ball.
    GhostBall,
    /// The predicted paths.
    Paths,
}

impl AidToggles {
    /// The aids shown: those toggled on that the room's policy allows. `FirstContact`
    /// allows the aim line and the ghost ball (the cue ball's way to its first contact),
    /// not the paths after it.
    pub fn allowed_by(self, policy: AimAid) -> AidToggles {
        let (line, ghost, paths) = match policy {
            AimAid::Off => (false, false, false),
            AimAid::FirstContact => (true, true, false),
            AimAid::Full => (true, true, true),
        };
        AidToggles {
            aim_line: self.aim_line && line,
            ghost_ball: self.ghost_ball && ghost,
            paths: self.paths && paths,
        }
    }

    /// Whether any aid is shown.
    pub fn any(self) -> bool {
        self.aim_line || self.ghost_ball || self.paths
    }

    /// Switches `aid` on or off.
    pub fn toggle(&mut self, aid: Aid) {
        let flag = match aid {
            Aid::AimLine => &mut self.aim_line,
            Aid::GhostBall => &mut self.ghost_ball,
            Aid::Paths => &mut self.paths,
        };
        *flag = !*flag;
    }
}

/// What a shot is predicted to do (scene coordinates).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prediction {
    /// Where the cue ball is when it first touches a ball or a cushion, or falls: the end of
    /// the aim line.
    pub aim_end: Option<DVec2>,
    /// The cue ball's centre when it first touches another ball.
    pub ghost: Option<DVec2>,
    /// The first ball the cue ball hits.
    pub first_hit: Option<usize>,
    /// Where the cue ball goes.
    pub cue_path: Vec<DVec2>,
    /// Where the first ball hit goes.
    pub object_path: Vec<DVec2>,
}

/// Simulates `shot` (whose strike is on ball `cue`) and extracts the aids.
pub fn predict(sim: &mut Simulator, shot: &Shot, cue: usize) -> Result<Prediction, ShotError> {
    let outcome = sim.run(shot)?;
    Ok(prediction_of(outcome, cue))
}

/// The aids for a simulated shot.
pub fn prediction_of(outcome: &Outcome, cue: usize) -> Prediction {
    let cue16 = cue as u16;
    let mut aim_end = None;
    let mut ghost = None;
    let mut first_hit = None;
    for e in &outcome.events {
        let touches = match e.kind {
            EventKind::BallBall { a, b } if a == cue16 || b == cue16 => {
                let other = if a == cue16 { b } else { a };
                if ghost.is_none() {
                    ghost = Some(outcome.state_at(cue, e.t).pos);
                    first_hit = Some(other as usize);
                }
                true
            }
            EventKind::BallCushion { ball, .. } | EventKind::BallPocket { ball, .. } => {
                ball == cue16
            }
            _ => false,
        };
        if touches && aim_end.is_none() {
            aim_end = Some(outcome.state_at(cue, e.t).pos);
        }
        if ghost.is_some() {
            break;
        }
    }
    Prediction {
        aim_end,
        ghost,
        first_hit,
        cue_path: path(outcome, cue),
        object_path: first_hit.map(|b| path(outcome, b)).unwrap_or_default(),
    }
}

/// The ball's centre from the strike until it stops or falls, sampled evenly in time and at
/// each of its events, so corners of the path are exact.
pub fn path(outcome: &Outcome, ball: usize) -> Vec<DVec2> {
    let end = outcome
        .rest_time
        .get(ball)
        .copied()
        .flatten()
        .unwrap_or(outcome.duration);
    let n = ((end * SAMPLES_PER_SECOND).ceil() as usize).clamp(1, MAX_POINTS);
    let mut times: Vec<f64> = (0..=n).map(|k| end * k as f64 / n as f64).collect();
    let b16 = ball as u16;
    times.extend(
        outcome
            .events
            .iter()
            .filter(|e| e.t <= end && e.kind.balls().0[..e.kind.balls().1].contains(&b16))
            .map(|e| e.t),
    );
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
        .into_iter()
        .map(|t| outcome.state_at(ball, t).pos)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{BallState, Strike, TableKind};

    fn shot(balls: Vec<DVec2>, angle: f64) -> Shot {
        let balls = balls.into_iter().map(BallState::at_rest).collect();
        Shot::new(TableKind::NineFoot, balls).struck(0, Strike::at_angle(2.0, angle, DVec2::ZERO))
    }

    #[test]
    fn ghost_ball_touches_the_object_ball_on_the_aim_line() {
        let r = 0.028575;
        let s = shot(vec![DVec2::new(0.635, 0.6), DVec2::new(0.635, 1.4)], 90.0);
        let p = predict(&mut Simulator::new(), &s, 0).expect("valid");
        assert_eq!(p.first_hit, Some(1));
        let g = p.ghost.expect("ball hit");
        assert!(
            (g - DVec2::new(0.635, 1.4 - 2.0 * r)).length() < 1e-6,
            "{g}"
        );
        assert_eq!(p.aim_end, p.ghost);
        // The object ball goes on up the table from where it was.
        let last = *p.object_path.last().expect("path");
        assert!(last.y > 1.4 + 0.1 && (last.x - 0.635).abs() < 1e-6);
        assert_eq!(p.cue_path[0], DVec2::new(0.635, 0.6));
    }

    #[test]
    fn a_miss_has_no_ghost_and_the_aim_line_ends_at_the_cushion() {
        let s = shot(vec![DVec2::new(0.635, 0.6), DVec2::new(0.3, 1.4)], 90.0);
        let p = predict(&mut Simulator::new(), &s, 0).expect("valid");
        assert!(p.ghost.is_none() && p.first_hit.is_none() && p.object_path.is_empty());
        let end = p.aim_end.expect("reaches the cushion");
        assert!(end.y > 2.4 && (end.x - 0.635).abs() < 1e-6, "{end}");
    }

    #[test]
    fn a_three_cushion_prediction_is_the_shot_the_rules_play() {
        use breakshot_shared::rules::{Command, Game, Seat, Settings, Variant};
        let mut game = Game::new(Variant::three_cushion(), Settings::offline(), 1);
        let strike = Strike::at_angle(4.0, 60.0, DVec2::new(0.2, 0.0));
        let p = predict(
            &mut Simulator::new(),
            &game.shot_for(&strike),
            game.cue_ball(),
        )
        .expect("valid");
        let played = game
            .apply(Seat::A, &Command::Shot { strike, call: None })
            .expect("a legal shot")
            .outcome
            .expect("the trajectory");
        // The path is the white's as the rules simulate it (carom table and balls), and it
        // comes off the cushions: its points reach near at least three of the four.
        assert_eq!(p.cue_path.last(), Some(&played.finals[0].pos));
        let (w, l, r) = (1.42, 2.84, game.params().ball_radius);
        let near = |f: &dyn Fn(DVec2) -> bool| p.cue_path.iter().any(|&q| f(q));
        let cushions = [
            near(&|q| q.x < r + 1e-3),
            near(&|q| q.x > w - r - 1e-3),
            near(&|q| q.y < r + 1e-3),
            near(&|q| q.y > l - r - 1e-3),
        ];
        assert!(cushions.iter().filter(|&&c| c).count() >= 3, "{cushions:?}");
    }

    #[test]
    fn a_room_s_policy_limits_the_aids_shown() {
        let all = AidToggles::default();
        assert!(!all.allowed_by(AimAid::Off).any());
        let first = all.allowed_by(AimAid::FirstContact);
        assert!(first.aim_line && first.ghost_ball && !first.paths);
        assert_eq!(all.allowed_by(AimAid::Full), all);
        // The policy never turns on an aid the player turned off.
        let mut some = all;
        some.toggle(Aid::AimLine);
        assert!(!some.allowed_by(AimAid::Full).aim_line);
    }

    #[test]
    fn toggles_flip_one_aid_each() {
        let mut t = AidToggles::default();
        t.toggle(Aid::GhostBall);
        assert!(t.aim_line && !t.ghost_ball && t.paths);
    }
}
