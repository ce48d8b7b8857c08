//! The cue strike: stick speed, aim and tip offset to the ball's velocity and spin.
//!
//! Alciatore's instantaneous point-impact model (TP A-30, A-31), as pooltool uses it: a level
//! cue of mass `M` at speed `V0` strikes the ball at a point offset `a·R` to the side and
//! `b·R` above the centre. The impact is elastic and frictionless at the tip (no miscue), so
//! the impulse lies along the cue and
//!
//! ```text
//! J = 2·m·V0 / (1 + m/M + 5/2·(a² + b²))        (a, b in units of R)
//! v = J/m along the cue,    ω = (r × J)/I       with r the tip contact point
//! ```
//!
//! which gives `v = 1.5385·V0` for a centre hit and natural roll from the start at `b = 0.4`.
//! A side offset also makes the ball squirt: it leaves at an angle away from the side struck,
//! `atan(5/2·a·√(1−a²) / (1 + m/m_e + 5/2·(1−a²)))` with the cue's end mass `m_e` (TP A-31).
//! Offsets beyond the miscue limit are refused.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::params::Params;

/// Cue stick mass M (kg).
pub const CUE_MASS: f64 = 0.567;
/// Effective end mass of the cue shaft, as a fraction of the ball's mass (squirt).
pub const END_MASS_RATIO: f64 = 1.0 / 30.0;
/// Largest tip offset from the centre (in units of R) that does not miscue.
pub const MISCUE_LIMIT: f64 = 0.5;
/// Fastest cue stick speed accepted (m/s): beyond any human break.
pub const MAX_CUE_SPEED: f64 = 15.0;

/// A cue strike on one ball.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Strike {
    /// Cue stick speed V0 (m/s).
    pub speed: f64,
    /// Unit aim direction in the table plane.
    pub dir: DVec2,
    /// Tip offset [side, height] in units of R: side > 0 is right of centre as the shooter
    /// sees it, height > 0 above the centre.
    pub tip: DVec2,
}

#[derive(Clone, Copy, Debug, Error, PartialEq)]
pub enum StrikeError {
    #[error("strike.speed must be a finite number between 0 and {MAX_CUE_SPEED} m/s")]
    Speed,
    #[error("strike.dir must be a finite, non-zero direction")]
    Direction,
    #[error("strike.tip must be finite and within {MISCUE_LIMIT} R of the centre (miscue)")]
    Miscue,
}

impl Strike {
    /// A strike aimed at `angle_deg` degrees from +x (90 = +y).
    pub fn at_angle(speed: f64, angle_deg: f64, tip: DVec2) -> Strike {
        let rad = angle_deg * (std::f64::consts::PI / 180.0);
        Strike {
            speed,
            dir: DVec2::new(libm::cos(rad), libm::sin(rad)),
            tip,
        }
    }

    /// Checks the strike and returns it with its direction normalised.
    pub fn validated(&self) -> Result<Strike, StrikeError> {
        if !self.speed.is_finite() || self.speed < 0.0 || self.speed > MAX_CUE_SPEED {
            return Err(StrikeError::Speed);
        }
        let len = self.dir.length();
        if !len.is_finite() || len == 0.0 {
            return Err(StrikeError::Direction);
        }
        if !self.tip.is_finite() || self.tip.length() > MISCUE_LIMIT {
            return Err(StrikeError::Miscue);
        }
        Ok(Strike {
            dir: self.dir / len,
            ..*self
        })
    }

    /// The ball's velocity and spin just after the strike.
    pub fn ball_motion(&self, params: &Params) -> Result<(DVec2, DVec3), StrikeError> {
        let s = self.validated()?;
        let m = params.ball_mass;
        let r = params.ball_radius;
        let (a, b) = (s.tip.x, s.tip.y);
        let speed = 2.0 * s.speed / (1.0 + m / CUE_MASS + 2.5 * (a * a + b * b));
        // Frame of the shot: forward f, right-hand side `side` (f rotated clockwise), up z.
        let f = s.dir;
        let side = DVec2::new(f.y, -f.x);
        // Contact point relative to the centre: behind the ball, offset a·R sideways, b·R up.
        let depth = (1.0 - a * a - b * b).sqrt();
        let contact = DVec3::new(
            r * (a * side.x - depth * f.x),
            r * (a * side.y - depth * f.y),
            r * b,
        );
        let impulse = DVec3::new(f.x, f.y, 0.0) * (m * speed);
        let spin = contact.cross(impulse) / params.inertia();
        // Squirt turns the ball's path away from the side struck.
        let one_minus = 1.0 - a * a;
        let squirt =
            libm::atan(2.5 * a * one_minus.sqrt() / (1.0 + 1.0 / END_MASS_RATIO + 2.5 * one_minus));
        let (sn, cs) = (libm::sin(squirt), libm::cos(squirt));
        let heading = f * cs - side * sn;
        Ok((heading * speed, spin))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn miscue_and_bad_numbers_are_refused() {
        let p = Params::default();
        let bad = [
            Strike {
                speed: f64::NAN,
                dir: DVec2::Y,
                tip: DVec2::ZERO,
            },
            Strike {
                speed: 1.0,
                dir: DVec2::ZERO,
                tip: DVec2::ZERO,
            },
            Strike {
                speed: 1.0,
                dir: DVec2::Y,
                tip: DVec2::new(0.4, 0.4),
            },
            Strike {
                speed: 99.0,
                dir: DVec2::Y,
                tip: DVec2::ZERO,
            },
        ];
        for s in bad {
            assert!(s.ball_motion(&p).is_err(), "{s:?}");
        }
    }
}
