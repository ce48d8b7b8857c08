//! The animation of a simulated shot. Every frame shows the exact state at the frame's time,
//! `outcome.state_at(ball, t)`; nothing is stepped, so a slow frame never changes where a ball
//! ends up.

use breakshot_shared::physics::{BallState, EventKind, Outcome, Table};
use glam::{DVec2, DVec3};

/// How long a pocketed ball is shown falling into its pocket (s).
pub(crate) const DROP_TIME: f64 = 0.25;
/// How long it takes to slide from where it was caught to the middle of the pocket (s).
const DROP_CENTRING: f64 = 0.08;
/// Gravity for the fall (m/s²).
const GRAVITY: f64 = 9.81;

/// How long the cue is shown going through at the start of a shot (s).
pub(crate) const STROKE_TIME: f64 = 0.15;

/// The cue's stroke at the start of a shot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// Where the struck ball was.
    pub at: DVec2,
    /// The way the cue went (unit, on the table): the way the ball left.
    pub dir: DVec2,
    /// How far through the stroke the shot is: 0 at the strike, 1 at its end.
    pub done: f64,
}

/// A ball seen falling into a pocket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PocketDrop {
    /// The ball.
    pub ball: usize,
    /// Its centre (scene coordinates, z up from the cloth).
    pub centre: DVec3,
}

/// The slowest playback speed.
pub(crate) const MIN_SPEED: f64 = 0.125;
/// The fastest playback speed.
pub(crate) const MAX_SPEED: f64 = 8.0;

/// A shot being shown.
#[derive(Clone, Debug)]
pub struct Playback {
    outcome: Outcome,
    /// The ball the cue struck.
    cue: usize,
    /// Shot time shown now (s).
    time: f64,
}

impl Playback {
    /// Shows `outcome`, a shot struck on ball `cue`, from its start.
    pub fn new(outcome: Outcome, cue: usize) -> Playback {
        Playback {
            outcome,
            cue,
            time: 0.0,
        }
    }

    /// The ball the cue struck (in three-cushion the shooter's own: the white or the
    /// yellow).
    pub fn cue(&self) -> usize {
        self.cue
    }

    /// The shot shown.
    pub fn outcome(&self) -> &Outcome {
        &self.outcome
    }

    /// Shot time shown now (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Moves the shot clock on by `wall_dt` seconds of real time at `speed` times real speed.
    pub fn advance(&mut self, wall_dt: f64, speed: f64) {
        let dt = if wall_dt.is_finite() {
            wall_dt.max(0.0)
        } else {
            0.0
        };
        let speed = speed.clamp(MIN_SPEED, MAX_SPEED);
        self.time = (self.time + dt * speed).min(self.outcome.duration);
    }

    /// Jumps to the end of the shot.
    pub fn finish(&mut self) {
        self.time = self.outcome.duration;
    }

    /// The whole shot has been shown.
    pub fn finished(&self) -> bool {
        self.time >= self.outcome.duration
    }

    /// Every ball's state at the time shown.
    pub fn balls(&self) -> Vec<BallState> {
        (0..self.outcome.history.len())
            .map(|i| self.outcome.state_at(i, self.time))
            .collect()
    }

    /// Balls pocketed so far, in the order they fell.
    pub fn pocketed_so_far(&self) -> Vec<usize> {
        self.outcome
            .events
            .iter()
            .take_while(|e| e.t <= self.time)
            .filter_map(|e| match e.kind {
                EventKind::BallPocket { ball, .. } => Some(ball as usize),
                _ => None,
            })
            .collect()
    }

    /// The cue going through ball `ball` in the first `STROKE_TIME` of the shot; None after
    /// it, or when the ball left without moving across the table.
    pub fn stroke(&self, ball: usize) -> Option<Stroke> {
        if self.time >= STROKE_TIME || ball >= self.outcome.history.len() {
            return None;
        }
        let start = self.outcome.state_at(ball, 0.0);
        let dir = start.vel.try_normalize()?;
        Some(Stroke {
            at: start.pos,
            dir,
            done: self.time / STROKE_TIME,
        })
    }

    /// The balls falling into pockets at the time shown, pocketed less than `DROP_TIME`
    /// ago. The physics ends a ball at the pocket's edge; this is for the eye only: the ball
    /// slides to the middle of the pocket as it falls under gravity. `table` is the shot's
    /// table, for its pockets; balls of `radius`.
    pub fn dropping(&self, table: &Table, radius: f64) -> Vec<PocketDrop> {
        self.outcome
            .events
            .iter()
            .take_while(|e| e.t <= self.time)
            .filter_map(|e| match e.kind {
                EventKind::BallPocket { ball, pocket } => Some((ball as usize, pocket, e.t)),
                _ => None,
            })
            .filter(|&(_, _, t)| self.time - t < DROP_TIME)
            .filter_map(|(ball, pocket, t)| {
                let hole = table.to_scene(table.pockets.get(pocket as usize)?.center);
                let caught = self.outcome.state_at(ball, t).pos;
                let centre = drop_centre(caught, hole, self.time - t, radius);
                Some(PocketDrop { ball, centre })
            })
            .collect()
    }
}

/// Where a ball caught by a pocket at `caught` is `since` seconds later: moving to the
/// pocket's middle `hole` and falling from its resting height `radius`.
pub(crate) fn drop_centre(caught: DVec2, hole: DVec2, since: f64, radius: f64) -> DVec3 {
    let since = since.max(0.0);
    let along = (since / DROP_CENTRING).min(1.0);
    caught
        .lerp(hole, along)
        .extend(radius - 0.5 * GRAVITY * since * since)
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{simulate, Shot, Strike, TableKind};
    use glam::DVec2;

    fn straight_in() -> Outcome {
        // The cue ball drives ball 1 into the bottom-left corner pocket.
        let balls = vec![
            BallState::at_rest(DVec2::new(0.3, 0.3)),
            BallState::at_rest(DVec2::new(0.15, 0.15)),
        ];
        let shot = Shot::new(TableKind::NineFoot, balls)
            .struck(0, Strike::at_angle(3.0, 225.0, DVec2::ZERO));
        simulate(&shot).expect("valid shot")
    }

    #[test]
    fn frames_show_the_exact_state_whatever_the_frame_rate() {
        let outcome = straight_in();
        let mut smooth = Playback::new(outcome.clone(), 0);
        let mut jerky = Playback::new(outcome.clone(), 0);
        for _ in 0..30 {
            smooth.advance(1.0 / 60.0, 1.0);
        }
        jerky.advance(0.3, 1.0);
        jerky.advance(0.2, 1.0);
        let t = smooth.time();
        assert!((t - 0.5).abs() < 1e-9 && (jerky.time() - 0.5).abs() < 1e-9);
        assert_eq!(smooth.balls()[0].pos, outcome.state_at(0, t).pos);
        assert!((smooth.balls()[0].pos - jerky.balls()[0].pos).length() < 1e-9);
    }

    #[test]
    fn ends_on_the_final_table_and_reports_pocketed_balls_in_order() {
        let outcome = straight_in();
        let mut p = Playback::new(outcome.clone(), 0);
        assert!(p.pocketed_so_far().is_empty());
        p.advance(1e9, 2.0);
        assert!(p.finished());
        assert_eq!(p.balls(), outcome.finals);
        assert_eq!(p.pocketed_so_far(), vec![1]);
    }

    #[test]
    fn a_pocketed_ball_is_seen_falling_into_its_pocket_for_a_moment() {
        let outcome = straight_in();
        let table = Table::new(TableKind::NineFoot);
        let r = 0.028575;
        let (fell, pocket) = outcome
            .events
            .iter()
            .find_map(|e| match e.kind {
                EventKind::BallPocket { ball: 1, pocket } => Some((e.t, pocket as usize)),
                _ => None,
            })
            .expect("ball 1 falls");
        let mut p = Playback::new(outcome.clone(), 0);
        p.advance(fell - 0.01, 1.0);
        assert!(p.dropping(&table, r).is_empty());
        p.advance(0.01 + 0.5 * DROP_TIME, 1.0);
        let [d] = p.dropping(&table, r)[..] else {
            panic!("{:?}", p.dropping(&table, r))
        };
        assert_eq!(d.ball, 1);
        // Below the cloth, in the middle of its pocket.
        let hole = table.to_scene(table.pockets[pocket].center);
        assert!(d.centre.z < r - 0.05, "{}", d.centre);
        assert!(
            (d.centre.truncate() - hole).length() < 1e-9,
            "{} vs {hole}",
            d.centre
        );
        p.advance(DROP_TIME, 1.0);
        assert!(p.dropping(&table, r).is_empty(), "gone once it has fallen");
        // It starts where it was caught.
        let caught = outcome.state_at(1, fell).pos;
        assert_eq!(drop_centre(caught, hole, 0.0, r), caught.extend(r));
    }

    #[test]
    fn the_cue_is_seen_going_through_the_ball_at_the_start_only() {
        let outcome = straight_in();
        let mut p = Playback::new(outcome.clone(), 0);
        let s = p.stroke(0).expect("at the strike");
        assert_eq!(s.at, outcome.state_at(0, 0.0).pos);
        let want = DVec2::new(-1.0, -1.0).normalize();
        assert!((s.dir - want).length() < 1e-9, "{}", s.dir);
        assert_eq!(s.done, 0.0);
        p.advance(0.5 * STROKE_TIME, 1.0);
        assert!((p.stroke(0).expect("still").done - 0.5).abs() < 1e-9);
        // The ball at rest was not struck.
        assert_eq!(p.stroke(1), None);
        p.advance(STROKE_TIME, 1.0);
        assert_eq!(p.stroke(0), None);
    }

    #[test]
    fn bad_frame_times_do_not_move_the_clock() {
        let mut p = Playback::new(straight_in(), 0);
        p.advance(f64::NAN, 1.0);
        p.advance(-1.0, 1.0);
        assert_eq!(p.time(), 0.0);
    }
}
