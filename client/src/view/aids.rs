//! Aiming aids: the aim line, the ghost ball and the predicted paths of the cue ball and of
//! the first ball it hits. They come from simulating the shot with the same engine the server
//! uses, so what the aids show is what the shot will do: the curve of a massé, the flight of
//! a jump (each point of a path has its height) and where a jumping ball lands.

use breakshot_shared::physics::{EventKind, MotionState, Outcome, Shot, ShotError, Simulator};
use breakshot_shared::protocol::AimAid;
use breakshot_shared::rules::{Seat, Verdict};
use glam::DVec2;

/// Points per second of shot time along a ball's way (a predicted path, the trail).
const SAMPLES_PER_SECOND: f64 = 60.0;
/// Most points in one way sampled.
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
            AimAid::Full | AimAid::Advice => (true, true, true),
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

/// One point of a predicted path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// The ball's centre on the table (scene coordinates).
    pub pos: DVec2,
    /// Its height above the cloth's resting height (m): zero on the cloth.
    pub lift: f64,
}

/// The pieces of a path that are drawn, in order: every piece on the cloth, and every other
/// piece of a stretch in the air, so that a jump's flight is dotted in both views.
pub fn drawn_pieces(pts: &[PathPoint]) -> impl Iterator<Item = (&PathPoint, &PathPoint)> {
    let mut flying = 0usize;
    pts.windows(2).filter_map(move |w| {
        if w[0].lift > 0.0 || w[1].lift > 0.0 {
            flying += 1;
            if flying % 2 == 0 {
                return None;
            }
        }
        Some((&w[0], &w[1]))
    })
}

/// What a shot is predicted to do (scene coordinates).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prediction {
    /// Where the cue ball is when it first touches a ball, a cushion or the cloth (landing
    /// from a jump), or falls or leaves the table: the end of the aim line.
    pub aim_end: Option<DVec2>,
    /// The cue ball's way to `aim_end`: the aim line, curved for a massé.
    pub aim_path: Vec<PathPoint>,
    /// The cue ball's centre when it first touches another ball.
    pub ghost: Option<DVec2>,
    /// The first ball the cue ball hits.
    pub first_hit: Option<usize>,
    /// Where the cue ball goes.
    pub cue_path: Vec<PathPoint>,
    /// Where the first ball hit goes.
    pub object_path: Vec<PathPoint>,
}

/// The warning to show on the aim line for a shot the rules, previewing it
/// ([`Game::preview`](breakshot_shared::rules::Game::preview)), would judge a foul or the
/// loss of the game: their first reason, as they would give it. None for a fair shot.
pub fn preview_warning(verdict: &Verdict, shooter: Seat) -> Option<String> {
    let lost = verdict
        .over
        .as_ref()
        .is_some_and(|(winner, _)| *winner != Some(shooter));
    if !verdict.foul && !lost {
        return None;
    }
    let why = verdict
        .reasons
        .iter()
        .find(|r| r.starts_with("Foul") || lost)
        .or(verdict.reasons.first())?;
    Some(format!("If played: {why}"))
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
    let mut aim_time = None;
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
            EventKind::BallCushion { ball, .. }
            | EventKind::BallPocket { ball, .. }
            | EventKind::BallTable { ball }
            | EventKind::BallOffTable { ball } => ball == cue16,
            // A jumping ball coming down to settle on the cloth.
            EventKind::Transition {
                ball,
                from: MotionState::Airborne,
                ..
            } => ball == cue16,
            _ => false,
        };
        if touches && aim_end.is_none() {
            aim_end = Some(outcome.state_at(cue, e.t).pos);
            aim_time = Some(e.t);
        }
        if ghost.is_some() {
            break;
        }
    }
    Prediction {
        aim_end,
        aim_path: aim_time
            .map(|t| path_until(outcome, cue, t))
            .unwrap_or_default(),
        ghost,
        first_hit,
        cue_path: path(outcome, cue),
        object_path: first_hit.map(|b| path(outcome, b)).unwrap_or_default(),
    }
}

/// The ball's centre and height from the strike until it stops or falls.
pub fn path(outcome: &Outcome, ball: usize) -> Vec<PathPoint> {
    path_until(outcome, ball, stop_time(outcome, ball))
}

/// Evenly spaced times from 0 to `end` (both included) to sample a ball's way at.
pub(crate) fn sample_times(end: f64) -> impl Iterator<Item = f64> {
    let n = ((end * SAMPLES_PER_SECOND).ceil() as usize).clamp(1, MAX_POINTS);
    (0..=n).map(move |k| end * k as f64 / n as f64)
}

/// When ball `ball` comes to rest or falls in `outcome`; the shot's end if it never does.
pub(crate) fn stop_time(outcome: &Outcome, ball: usize) -> f64 {
    outcome
        .rest_time
        .get(ball)
        .copied()
        .flatten()
        .unwrap_or(outcome.duration)
}

/// The ball's centre and height from the strike to time `end`, sampled evenly in time and
/// at each of its events, so corners of the path and the bounces of a jump are exact.
fn path_until(outcome: &Outcome, ball: usize, end: f64) -> Vec<PathPoint> {
    let mut times: Vec<f64> = sample_times(end).collect();
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
        .map(|t| {
            let s = outcome.state_at(ball, t);
            PathPoint {
                pos: s.pos,
                lift: s.lift,
            }
        })
        .collect()
}

/// Where a path comes down on the cloth: its points on the cloth right after points in the
/// air (the bounces and the landing of a jump).
pub fn landings(path: &[PathPoint]) -> Vec<DVec2> {
    path.windows(2)
        .filter(|w| w[0].lift > 0.0 && w[1].lift <= 0.0)
        .map(|w| w[1].pos)
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
        let last = p.object_path.last().expect("path").pos;
        assert!(last.y > 1.4 + 0.1 && (last.x - 0.635).abs() < 1e-6);
        assert_eq!(p.cue_path[0].pos, DVec2::new(0.635, 0.6));
        // The aim line runs straight from the cue ball to the ghost ball, on the cloth.
        assert_eq!(
            p.aim_path.first().map(|q| q.pos),
            Some(DVec2::new(0.635, 0.6))
        );
        assert_eq!(p.aim_path.last().map(|q| q.pos), p.ghost);
        assert!(p
            .aim_path
            .iter()
            .all(|q| q.lift == 0.0 && (q.pos.x - 0.635).abs() < 1e-9));
        assert!(landings(&p.cue_path).is_empty());
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
    fn a_masse_shot_s_aim_line_curves() {
        // examples/masse_9ft.json: a cue elevated 70 degrees, struck right of centre.
        let balls = vec![BallState::at_rest(DVec2::new(0.6, 0.5))];
        let strike = Strike::at_angle(2.5, 88.0, DVec2::new(0.35, 0.1)).elevated(70.0);
        let s = Shot::new(TableKind::NineFoot, balls).struck(0, strike);
        let p = predict(&mut Simulator::new(), &s, 0).expect("valid");
        let start = p.cue_path[0].pos;
        let end = p.cue_path.last().expect("path").pos;
        // How far the path strays from the straight line between its ends.
        let chord = (end - start).normalize();
        let bow = p
            .cue_path
            .iter()
            .map(|q| (q.pos - start).perp_dot(chord).abs())
            .fold(0.0, f64::max);
        assert!(bow > 0.02, "the path bows {bow} m off its chord");
        // A level shot along the same line does not.
        let level = Shot::new(s.table, s.balls.clone())
            .struck(0, Strike::at_angle(2.5, 88.0, DVec2::new(0.0, 0.1)));
        let q = predict(&mut Simulator::new(), &level, 0).expect("valid");
        let (a, b) = (q.cue_path[0].pos, q.aim_end.expect("reaches a cushion"));
        let straight = (b - a).normalize();
        assert!(q
            .aim_path
            .iter()
            .all(|pt| (pt.pos - a).perp_dot(straight).abs() < 1e-6));
    }

    #[test]
    fn a_jump_shot_s_paths_carry_its_height_and_its_landings() {
        // examples/jump_9ft.json: a cue elevated 45 degrees, a little below centre.
        let balls = vec![
            BallState::at_rest(DVec2::new(0.635, 0.4)),
            BallState::at_rest(DVec2::new(0.635, 1.09)),
        ];
        let strike = Strike::at_angle(4.0, 90.0, DVec2::new(0.0, -0.1)).elevated(45.0);
        let s = Shot::new(TableKind::NineFoot, balls).struck(0, strike);
        let p = predict(&mut Simulator::new(), &s, 0).expect("valid");
        let highest = p.cue_path.iter().map(|q| q.lift).fold(0.0, f64::max);
        assert!(highest > 0.005, "the cue ball rises {highest} m");
        let down = landings(&p.cue_path);
        assert!(!down.is_empty(), "the cue ball never comes down");
        // The aim line ends where the cue ball first comes down or touches something.
        let end = p.aim_end.expect("an aim line");
        assert_eq!(p.aim_path.last().map(|q| q.pos), Some(end));
        assert!(p.aim_path.iter().any(|q| q.lift > 0.0));
        assert!(end.y > 0.4 && end.y <= down[0].y + 1e-9, "{end} {down:?}");
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
        assert_eq!(p.cue_path.last().map(|q| q.pos), Some(played.finals[0].pos));
        let (w, l, r) = (1.42, 2.84, game.params().ball_radius);
        let near = |f: &dyn Fn(DVec2) -> bool| p.cue_path.iter().any(|q| f(q.pos));
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

    fn verdict(foul: bool, reasons: &[&str], over: Option<Option<Seat>>) -> Verdict {
        Verdict {
            reasons: reasons.iter().map(|r| r.to_string()).collect(),
            foul,
            shot: None,
            next: Seat::A,
            over: over.map(|winner| (winner, "over".into())),
            outcome: None,
        }
    }

    #[test]
    fn the_rules_preview_is_warned_of_in_their_words_only_for_a_foul_or_a_loss() {
        let fair = verdict(false, &["Player A pocketed a ball and continues"], None);
        assert_eq!(preview_warning(&fair, Seat::A), None);
        let foul = verdict(
            true,
            &[
                "Player B to shoot",
                "Foul: wrong ball first - hit the 5 before the 3",
            ],
            None,
        );
        assert_eq!(
            preview_warning(&foul, Seat::A).as_deref(),
            Some("If played: Foul: wrong ball first - hit the 5 before the 3")
        );
        let lost = verdict(
            false,
            &["Player A loses: pocketed the 8 early"],
            Some(Some(Seat::B)),
        );
        assert_eq!(
            preview_warning(&lost, Seat::A).as_deref(),
            Some("If played: Player A loses: pocketed the 8 early")
        );
        let won = verdict(false, &["Player A wins"], Some(Some(Seat::A)));
        assert_eq!(preview_warning(&won, Seat::A), None);
    }

    #[test]
    fn a_flight_is_dotted_and_the_cloth_drawn_whole() {
        let at = |x: f64, lift: f64| PathPoint {
            pos: DVec2::new(x, 0.0),
            lift,
        };
        let pts = [
            at(0.0, 0.0),
            at(1.0, 0.0),
            at(2.0, 0.1),
            at(3.0, 0.2),
            at(4.0, 0.1),
            at(5.0, 0.0),
            at(6.0, 0.0),
        ];
        let starts: Vec<f64> = drawn_pieces(&pts).map(|(a, _)| a.pos.x).collect();
        // On the cloth 0-1 and 5-6; in the air 1-2, 2-3, 3-4, 4-5, of which every other.
        assert_eq!(starts, [0.0, 1.0, 3.0, 5.0]);
    }
}
