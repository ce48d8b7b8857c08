//! The shot being set up: direction, power, tip offset and cue elevation, turned into a cue
//! [`Strike`].

use breakshot_shared::physics::cue::{MAX_ELEVATION_DEG, MISCUE_LIMIT};
use breakshot_shared::physics::Strike;
use glam::DVec2;

/// Cue speed at full power (m/s): a hard break. The engine accepts up to 15.
pub(crate) const MAX_SHOT_SPEED: f64 = 12.0;
/// Cue speed of a fresh set-up (m/s): a soft shot.
pub(crate) const DEFAULT_SHOT_SPEED: f64 = 1.5;

/// The shot being set up: direction, power, the tip's offset on the cue ball and the cue's
/// elevation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aim {
    /// Direction in the scene plane, radians from +x.
    pub angle: f64,
    /// 0 to 1: the cue speed, as a share of `MAX_SHOT_SPEED` (the bar, the keys and the
    /// pull-back all move it in proportion).
    pub power: f64,
    /// Tip offset [side, height] in units of R, within the miscue limit.
    pub tip: DVec2,
    /// Cue elevation in degrees: 0 level, up to 90 straight down (massé, jump shots).
    pub elevation_deg: f64,
}

impl Default for Aim {
    fn default() -> Self {
        Aim {
            angle: std::f64::consts::FRAC_PI_2,
            power: DEFAULT_SHOT_SPEED / MAX_SHOT_SPEED,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        }
    }
}

impl Aim {
    /// The unit direction of the shot.
    pub fn dir(&self) -> DVec2 {
        DVec2::new(libm::cos(self.angle), libm::sin(self.angle))
    }

    /// Cue stick speed for the current power (m/s).
    pub fn speed(&self) -> f64 {
        MAX_SHOT_SPEED * self.power
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

    /// Sets the cue elevation, clamped to 0..=90 degrees.
    pub fn set_elevation(&mut self, degrees: f64) {
        if degrees.is_finite() {
            self.elevation_deg = degrees.clamp(0.0, MAX_ELEVATION_DEG);
        }
    }

    /// Points the cue along `dir` (ignored if it has no direction).
    pub fn point_along(&mut self, dir: DVec2) {
        if dir.is_finite() && dir.length_squared() > 1e-18 {
            self.angle = libm::atan2(dir.y, dir.x);
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
            elevation_deg: self.elevation_deg,
        }
    }

    /// Adopts a strike (from a scene file) as the set-up.
    pub fn from_strike(s: &Strike) -> Aim {
        let mut aim = Aim::default();
        aim.point_along(s.dir);
        aim.set_power(s.speed.max(0.0) / MAX_SHOT_SPEED);
        aim.set_tip(s.tip);
        aim.set_elevation(s.elevation_deg);
        aim
    }
}

/// Seconds between two showings of a player's aim to the others, at the most.
pub(crate) const AIM_SHARE_INTERVAL: f64 = 0.1;

/// Decides when the aim being set up is shown to the others in an online room: when it has
/// changed, and no more often than every `AIM_SHARE_INTERVAL`.
#[derive(Clone, Debug, Default)]
pub struct AimShare {
    last: Option<Strike>,
    wait: f64,
}

impl AimShare {
    /// After `dt` seconds, the strike to send now, if any.
    pub fn offer(&mut self, strike: Strike, dt: f64) -> Option<Strike> {
        let dt = if dt.is_finite() { dt.max(0.0) } else { 0.0 };
        self.wait = (self.wait - dt).max(0.0);
        if self.last == Some(strike) || self.wait > 0.0 {
            return None;
        }
        self.last = Some(strike);
        self.wait = AIM_SHARE_INTERVAL;
        Some(strike)
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
            a.set_elevation(100.0 * p);
            assert!(a.strike().validated().is_ok(), "{a:?}");
        }
        a.set_power(1.0);
        assert_eq!(a.strike().speed, MAX_SHOT_SPEED);
    }

    #[test]
    fn a_strike_survives_the_round_trip() {
        let s = Strike::at_angle(3.0, 30.0, DVec2::new(0.2, -0.1)).elevated(35.0);
        let back = Aim::from_strike(&s).strike();
        assert!((back.speed - 3.0).abs() < 1e-9 && (back.dir - s.dir).length() < 1e-12);
        assert_eq!(back.tip, s.tip);
        assert_eq!(back.elevation_deg, 35.0);
    }

    #[test]
    fn elevation_is_held_between_level_and_straight_down() {
        let mut a = Aim::default();
        assert_eq!(a.strike().elevation_deg, 0.0);
        a.set_elevation(30.0);
        assert_eq!(a.strike().elevation_deg, 30.0);
        a.set_elevation(-5.0);
        assert_eq!(a.elevation_deg, 0.0);
        a.set_elevation(120.0);
        assert_eq!(a.elevation_deg, MAX_ELEVATION_DEG);
        a.set_elevation(f64::NAN);
        assert_eq!(a.elevation_deg, MAX_ELEVATION_DEG);
    }

    #[test]
    fn the_aim_is_shared_when_it_changes_at_most_ten_times_a_second() {
        let mut share = AimShare::default();
        let mut a = Aim::default();
        assert!(
            share.offer(a.strike(), 0.0).is_some(),
            "the first aim goes at once"
        );
        assert!(
            share.offer(a.strike(), 1.0).is_none(),
            "an unchanged aim is not resent"
        );
        let mut sent = 0;
        for _ in 0..60 {
            a.rotate(0.01);
            sent += share.offer(a.strike(), 1.0 / 60.0).is_some() as u32;
        }
        assert!((9..=11).contains(&sent), "{sent} aims sent in one second");
        // The aim where it came to rest is sent once the interval has passed.
        let rest = a.strike();
        let late = (0..10).find_map(|_| share.offer(rest, 1.0 / 60.0));
        assert_eq!(late, Some(rest));
    }
}
