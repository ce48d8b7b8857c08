//! The cue ball's trail: the way it went in the last shot, drawn on the cloth and fading with
//! age, so the player sees where it went after the balls have stopped. Computed from the
//! shot's exact motion (`Outcome::state_at`), for drawing only.

use breakshot_shared::physics::Outcome;
use glam::DVec2;

use super::aids::{sample_times, stop_time};
use super::playback::Playback;

/// How quickly a stretch of the trail fades (s of shot time).
pub(crate) const FADE_TIME: f64 = 1.5;
/// How faint the oldest stretch gets.
pub(crate) const FAINTEST: f32 = 0.15;

/// One point of the trail and how strongly it is drawn (0 to 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrailPoint {
    /// The ball's centre on the table (scene coordinates).
    pub pos: DVec2,
    /// How strongly it is drawn: 1 where the ball is now, fading to `FAINTEST`.
    pub strength: f32,
}

/// The last shot's trail, kept after the shot until the next one.
#[derive(Clone, Debug, Default)]
pub struct Trail {
    /// The whole way of the ball (time, position) in the shot followed.
    way: Vec<(f64, DVec2)>,
    /// The shot followed: its duration's bits and its number of events.
    shot: Option<(u64, usize)>,
    /// The shot time shown.
    now: f64,
}

impl Trail {
    /// No trail yet.
    pub fn new() -> Trail {
        Trail::default()
    }

    /// Follows the shot shown, if any, for ball `ball`; with none, keeps the last one.
    pub fn follow(&mut self, playback: Option<&Playback>, ball: usize) {
        let Some(p) = playback else { return };
        let o = p.outcome();
        let mark = (o.duration.to_bits(), o.events.len());
        if self.shot != Some(mark) {
            self.shot = Some(mark);
            self.way = way(o, ball);
        }
        self.now = p.time();
    }

    /// The trail up to the time shown, oldest first.
    pub fn points(&self) -> Vec<TrailPoint> {
        let now = self.now;
        self.way
            .iter()
            .take_while(|(t, _)| *t <= now)
            .map(|&(t, pos)| TrailPoint {
                pos,
                strength: FAINTEST + (1.0 - FAINTEST) * libm::exp(-(now - t) / FADE_TIME) as f32,
            })
            .collect()
    }
}

/// Ball `ball`'s centre through the shot, sampled evenly in time until it stops or falls.
fn way(o: &Outcome, ball: usize) -> Vec<(f64, DVec2)> {
    if ball >= o.history.len() {
        return Vec::new();
    }
    let end = stop_time(o, ball);
    sample_times(end)
        .map(|t| (t, o.state_at(ball, t).pos))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{simulate, BallState, Shot, Strike, TableKind};

    fn playback() -> Playback {
        let balls = vec![BallState::at_rest(DVec2::new(0.6, 0.5))];
        let shot = Shot::new(TableKind::NineFoot, balls)
            .struck(0, Strike::at_angle(1.5, 90.0, DVec2::ZERO));
        Playback::new(simulate(&shot).expect("valid shot"), 0)
    }

    #[test]
    fn the_trail_follows_the_ball_and_fades_behind_it() {
        let mut p = playback();
        let mut trail = Trail::new();
        trail.follow(Some(&p), 0);
        assert_eq!(trail.points().len(), 1, "at the strike, one point");
        p.advance(1.0, 1.0);
        trail.follow(Some(&p), 0);
        let pts = trail.points();
        let last = pts.last().expect("points");
        assert!(
            (last.pos - p.balls()[0].pos).length() < 0.03,
            "ends at the ball"
        );
        assert!(last.strength > 0.95);
        assert!(pts[0].strength < 0.6 && pts[0].strength >= FAINTEST);
        assert!(pts.windows(2).all(|w| w[0].strength <= w[1].strength));
        // Kept when the shot is over and gone from the screen.
        p.finish();
        trail.follow(Some(&p), 0);
        let n = trail.points().len();
        trail.follow(None, 0);
        assert_eq!(trail.points().len(), n);
        assert!((trail.points()[n - 1].pos - p.balls()[0].pos).length() < 1e-9);
    }

    #[test]
    fn a_ball_the_shot_does_not_have_has_no_trail() {
        let p = playback();
        let mut trail = Trail::new();
        trail.follow(Some(&p), 7);
        assert!(trail.points().is_empty());
    }
}
