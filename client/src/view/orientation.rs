//! How each ball is turned, for drawing only. The engine gives every ball's exact angular
//! velocity at any instant (`Outcome::state_at(..).spin`); here it is integrated from frame to
//! frame into an orientation, so numbers and stripes roll across the balls, turn with side spin
//! and stand still on a sliding stun ball. Nothing here feeds back into the physics.
//!
//! Axes are the scene's: x and y on the cloth, z up. A ball's own frame has its number spots on
//! ±z (see `sphere`), so a ball that never moved shows its number on top.

use breakshot_shared::physics::{MotionState, Outcome};
use glam::{DQuat, DVec3};

use super::playback::Playback;

/// Longest step of the integration (s): the spin changes linearly within a piece, and the
/// midpoint rule over steps this short is exact to far below a pixel.
const MAX_STEP: f64 = 1.0 / 240.0;

/// Something that tells one shot from another without keeping it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ShotMark {
    duration: u64,
    events: usize,
    balls: usize,
}

impl ShotMark {
    fn of(outcome: &Outcome) -> ShotMark {
        ShotMark {
            duration: outcome.duration.to_bits(),
            events: outcome.events.len(),
            balls: outcome.history.len(),
        }
    }
}

/// Every ball's orientation, carried from shot to shot.
#[derive(Clone, Debug, Default)]
pub struct Orientations {
    turns: Vec<DQuat>,
    /// The shot being followed and the shot time reached in it.
    shot: Option<(ShotMark, f64)>,
}

impl Orientations {
    /// Every ball unturned.
    pub fn new() -> Orientations {
        Orientations::default()
    }

    /// Ball `i`'s orientation: the rotation from its own frame to the scene's.
    pub fn get(&self, i: usize) -> DQuat {
        self.turns.get(i).copied().unwrap_or(DQuat::IDENTITY)
    }

    /// Catches up with the shot being shown, if any: from where the last call left off (or the
    /// shot's start, for a new shot) to the time shown now.
    pub fn follow(&mut self, playback: Option<&Playback>) {
        let Some(p) = playback else {
            self.shot = None;
            return;
        };
        let mark = ShotMark::of(p.outcome());
        let from = match self.shot {
            Some((m, t)) if m == mark && t <= p.time() => t,
            _ => 0.0,
        };
        self.turn(p.outcome(), from, p.time());
        self.shot = Some((mark, p.time()));
    }

    /// Turns every ball by its spin over shot times `t0..t1`.
    pub fn turn(&mut self, outcome: &Outcome, t0: f64, t1: f64) {
        let n = outcome.history.len();
        if self.turns.len() != n {
            self.turns.resize(n, DQuat::IDENTITY);
        }
        if !t0.is_finite() || !t1.is_finite() || t1 <= t0 {
            return;
        }
        let steps = ((t1 - t0) / MAX_STEP).ceil().max(1.0);
        let h = (t1 - t0) / steps;
        for (i, q) in self.turns.iter_mut().enumerate() {
            if outcome.history[i].is_empty() {
                continue;
            }
            for k in 0..steps as usize {
                let mid = t0 + (k as f64 + 0.5) * h;
                let s = outcome.state_at(i, mid);
                if matches!(s.motion, MotionState::Stationary | MotionState::Pocketed) {
                    continue;
                }
                *q = (rotation(s.spin * h) * *q).normalize();
            }
        }
    }
}

/// The rotation by the rotation vector `w` (axis times angle).
fn rotation(w: DVec3) -> DQuat {
    let angle = w.length();
    if angle < 1e-12 {
        return DQuat::IDENTITY;
    }
    DQuat::from_axis_angle(w / angle, angle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::params::Params;
    use breakshot_shared::physics::{simulate, BallState, Shot, Strike, TableKind};
    use glam::DVec2;

    fn shot(tip: DVec2, speed: f64) -> Outcome {
        let balls = vec![BallState::at_rest(DVec2::new(0.5, 0.5))];
        let shot =
            Shot::new(TableKind::NineFoot, balls).struck(0, Strike::at_angle(speed, 90.0, tip));
        simulate(&shot).expect("valid shot")
    }

    /// When ball 0 first rolls.
    fn rolling_from(o: &Outcome) -> f64 {
        o.history[0]
            .iter()
            .find(|p| p.start.motion == MotionState::Rolling)
            .map(|p| p.t0)
            .expect("the ball rolls")
    }

    /// The angle turned about `axis` by `q` (assuming it turns about that axis).
    fn angle_about(q: DQuat, axis: DVec3) -> f64 {
        let (a, angle) = q.to_axis_angle();
        angle * a.dot(axis)
    }

    #[test]
    fn a_rolling_ball_turns_by_distance_over_radius_about_the_axis_across_its_path() {
        // Follow through: the tip above centre makes the ball roll almost at once.
        let o = shot(DVec2::new(0.0, 0.4), 1.0);
        let r = Params::default().ball_radius;
        // A short stretch, so the turn stays under half a revolution and reads back unambiguously.
        let (t0, t1) = (rolling_from(&o) + 0.01, rolling_from(&o) + 0.06);
        assert!(t1 < o.duration, "still rolling at the end of the window");
        let mut turns = Orientations::new();
        turns.turn(&o, t0, t1);
        let d = o.state_at(0, t1).pos - o.state_at(0, t0).pos;
        // Moving along +y, a rolling ball turns about −x (ω = ẑ × v / R).
        assert!(d.y > 0.02 && d.x.abs() < 1e-9);
        let want = d.length() / r;
        let got = angle_about(turns.get(0), DVec3::NEG_X);
        assert!(
            (got - want).abs() < 1e-6,
            "turned {got} rad, rolled {want} rad"
        );
    }

    #[test]
    fn a_sliding_stun_ball_does_not_turn_until_friction_makes_it_roll() {
        // A centre hit: the ball leaves without spin and slides.
        let o = shot(DVec2::ZERO, 2.0);
        let roll = rolling_from(&o);
        assert!(roll > 0.1, "slides for a while");
        let r = Params::default().ball_radius;
        let mut turns = Orientations::new();
        let early = 0.02;
        turns.turn(&o, 0.0, early);
        let slid = (o.state_at(0, early).pos - o.state_at(0, 0.0).pos).length();
        let turned = angle_about(turns.get(0), DVec3::NEG_X);
        // Sliding, the spin grows from zero: far less turning than rolling that far would give.
        assert!(turned < 0.1 * slid / r, "turned {turned} over {slid} m");
        // Once rolling, it turns with the distance.
        let mut rolled = Orientations::new();
        rolled.turn(&o, roll, roll + 0.03);
        let d = (o.state_at(0, roll + 0.03).pos - o.state_at(0, roll).pos).length();
        let got = angle_about(rolled.get(0), DVec3::NEG_X);
        assert!((got - d / r).abs() < 1e-3 * (d / r));
    }

    #[test]
    fn side_spin_turns_the_ball_about_the_vertical() {
        let left = shot(DVec2::new(-0.4, 0.0), 1.0);
        let right = shot(DVec2::new(0.4, 0.0), 1.0);
        let spin = |o: &Outcome| o.state_at(0, 0.0).spin.z;
        assert!(
            spin(&left) * spin(&right) < 0.0,
            "opposite sides, opposite spins"
        );
        for o in [&left, &right] {
            let wz = spin(o);
            let sign = wz.signum();
            assert!(wz.abs() > 1.0, "the tip off centre gives side spin ({wz})");
            // Only the vertical part of the spin: the ball turned about z as much as ∫ωz dt.
            let mut turns = Orientations::new();
            let t = 0.05;
            turns.turn(o, 0.0, t);
            let up = turns.get(0) * DVec3::X;
            let about_z = libm::atan2(up.y, up.x);
            let mut want = 0.0;
            let n = 1000;
            for k in 0..n {
                want += o.state_at(0, (k as f64 + 0.5) * t / n as f64).spin.z * t / n as f64;
            }
            assert!(want * sign > 0.01);
            // The roll about x tilts the x axis little over this time; its heading follows ωz.
            assert!(
                (about_z - want).abs() < 0.02 * want.abs() + 1e-3,
                "{about_z} vs {want}"
            );
        }
    }

    #[test]
    fn following_a_playback_frame_by_frame_equals_one_jump() {
        let o = shot(DVec2::new(0.2, 0.3), 2.0);
        let mut smooth = Orientations::new();
        let mut p = Playback::new(o.clone(), 0);
        for _ in 0..40 {
            p.advance(1.0 / 60.0, 1.0);
            smooth.follow(Some(&p));
        }
        let mut jump = Orientations::new();
        jump.turn(&o, 0.0, p.time());
        // Steps fall differently, so the two agree to the integration's accuracy, not the bit.
        let apart = smooth.get(0).angle_between(jump.get(0));
        assert!(apart < 2e-3, "{apart} rad apart");
        // A new shot starts from the orientation the balls were left in.
        let kept = smooth.get(0);
        smooth.follow(None);
        assert_eq!(smooth.get(0), kept);
    }
}
