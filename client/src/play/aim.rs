//! The shot being set up: direction, power and tip offset, turned into a cue [`Strike`].

use breakshot_shared::physics::cue::MISCUE_LIMIT;
use breakshot_shared::physics::Strike;
use glam::DVec2;

/// Cue speed at full power (m/s): a hard break. The engine accepts up to 15.
pub const MAX_SHOT_SPEED: f64 = 12.0;

#[derive(Clone, Copy, Debug, PartialEq)]
/// The shot being set up: direction, power and the tip's offset on the cue ball.
pub struct Aim {
    /// Direction in the scene plane, radians from +x.
    pub angle: f64,
    /// 0 to 1; the cue speed grows with its square so soft shots are easy to judge.
    pub power: f64,
    /// Tip offset [side, height] in units of R, within the miscue limit.
    pub tip: DVec2,
}

impl Default for Aim {
    fn default() -> Self {
        Aim {
            angle: std::f64::consts::FRAC_PI_2,
            power: 0.35,
            tip: DVec2::ZERO,
        }
    }
}

impl Aim {
    /// The unit direction of the shot.
    pub fn dir(&self) -> DVec2 {
        DVec2::new(self.angle.cos(), self.angle.sin())
    }

    /// Cue stick speed for the current power (m/s).
    pub fn speed(&self) -> f64 {
        MAX_SHOT_SPEED * self.power * self.power
    }

    /// Sets the power, clamped to 0..=1.
    pub fn set_power(&mut self, power: f64) {
        if power.is_finite() {
            self.power = power.clamp(0.0, 1.0);
        }
    }

    /// Sets the tip offset, pulled back onto the miscue limit if it is beyond it.
    pub fn set_tip(&mut self, tip: DVec2) {
        if !tip.is_finite() {
            return;
        }
        let len = tip.length();
        self.tip = if len > MISCUE_LIMIT {
            tip * (MISCUE_LIMIT / len)
        } else {
            tip
        };
    }

    /// Points the cue along `dir` (ignored if it has no direction).
    pub fn point_along(&mut self, dir: DVec2) {
        if dir.is_finite() && dir.length_squared() > 1e-18 {
            self.angle = dir.y.atan2(dir.x);
        }
    }

    /// Turns the aim by `radians`.
    pub fn rotate(&mut self, radians: f64) {
        if radians.is_finite() {
            self.angle = (self.angle + radians).rem_euclid(std::f64::consts::TAU);
        }
    }

    /// The cue strike; the set-up is always valid, so this is too.
    pub fn strike(&self) -> Strike {
        Strike {
            speed: self.speed(),
            dir: self.dir(),
            tip: self.tip,
        }
    }

    /// Adopts a strike (from a scene file) as the set-up.
    pub fn from_strike(s: &Strike) -> Aim {
        let mut aim = Aim::default();
        aim.point_along(s.dir);
        aim.set_power((s.speed.max(0.0) / MAX_SHOT_SPEED).sqrt());
        aim.set_tip(s.tip);
        aim
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tip_is_held_at_the_miscue_limit() {
        let mut a = Aim::default();
        a.set_tip(DVec2::new(0.9, 0.9));
        assert!((a.tip.length() - MISCUE_LIMIT).abs() < 1e-12);
        assert!((a.tip.x - a.tip.y).abs() < 1e-12);
        a.set_tip(DVec2::new(0.1, -0.2));
        assert_eq!(a.tip, DVec2::new(0.1, -0.2));
        a.set_tip(DVec2::new(f64::NAN, 0.0));
        assert_eq!(a.tip, DVec2::new(0.1, -0.2));
    }

    #[test]
    fn every_setting_gives_a_valid_strike() {
        let mut a = Aim::default();
        for p in [-1.0, 0.0, 0.5, 1.0, 7.0] {
            a.set_power(p);
            a.rotate(1.3);
            a.set_tip(DVec2::new(p, -p));
            assert!(a.strike().validated().is_ok(), "{a:?}");
        }
        a.set_power(1.0);
        assert_eq!(a.strike().speed, MAX_SHOT_SPEED);
    }

    #[test]
    fn a_strike_survives_the_round_trip() {
        let s = Strike::at_angle(3.0, 30.0, DVec2::new(0.2, -0.1));
        let back = Aim::from_strike(&s).strike();
        assert!((back.speed - 3.0).abs() < 1e-9 && (back.dir - s.dir).length() < 1e-12);
        assert_eq!(back.tip, s.tip);
    }
}
