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
//!
//! An elevated cue (TP A-30 with the cue tilted down by θ, as in pooltool's 3-D strike) keeps
//! the same model in the cue's own frame: the tip offset `(a, b)` is measured across the cue
//! (b along the cue's tilted "up"), so the impulse magnitude is the same, and the impulse
//! points along the tilted cue, `d = cos θ·f − sin θ·ẑ`. It gives the ball a horizontal
//! velocity `J·cos θ/m` (turned by the squirt as above), a velocity `J·sin θ/m` into the slate,
//! and spin `r × J/I` whose axis now has a component along the travel: the sliding ball
//! curves (massé). What becomes of the velocity into the slate is the engine's business
//! (a bounce with `e_table`, or absorbed by the slate with the `airborne` effect off).

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
/// Largest cue elevation (degrees): straight down.
pub const MAX_ELEVATION_DEG: f64 = 90.0;

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
    /// Cue elevation θ in degrees: 0 level, 90 straight down. The tip offset is measured
    /// across the cue, so with an elevated cue "height" runs along the cue's tilted up.
    /// Carried by the wire protocol since version 2 and by records since format 2.
    pub elevation_deg: f64,
}

/// What the cue gives the ball: the horizontal and vertical velocity and the spin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Launch {
    /// Horizontal velocity (m/s): along the aim, turned by the squirt.
    pub vel: DVec2,
    /// Vertical velocity (m/s), negative: into the slate (zero for a level cue).
    pub vz: f64,
    /// Angular velocity (rad/s) in the table frame.
    pub spin: DVec3,
}

/// Why a strike is refused.
#[derive(Clone, Copy, Debug, Error, PartialEq)]
pub enum StrikeError {
    /// The speed is not finite or not within 0 to [`MAX_CUE_SPEED`].
    #[error("strike.speed must be a finite number between 0 and {MAX_CUE_SPEED} m/s")]
    Speed,
    /// The aim direction is zero or not finite.
    #[error("strike.dir must be a finite, non-zero direction")]
    Direction,
    /// The tip lies beyond [`MISCUE_LIMIT`] from the centre, or is not finite.
    #[error("strike.tip must be finite and within {MISCUE_LIMIT} R of the centre (miscue)")]
    Miscue,
    /// The elevation is not within 0 to [`MAX_ELEVATION_DEG`] degrees.
    #[error("strike.elevation_deg must be a finite number from 0 to {MAX_ELEVATION_DEG}")]
    Elevation,
}

impl Strike {
    /// A strike aimed at `angle_deg` degrees from +x (90 = +y).
    pub fn at_angle(speed: f64, angle_deg: f64, tip: DVec2) -> Strike {
        let rad = angle_deg * (std::f64::consts::PI / 180.0);
        Strike {
            speed,
            dir: DVec2::new(libm::cos(rad), libm::sin(rad)),
            tip,
            elevation_deg: 0.0,
        }
    }

    /// The same strike with the cue elevated by `degrees`.
    pub fn elevated(self, degrees: f64) -> Strike {
        Strike {
            elevation_deg: degrees,
            ..self
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
        if !(0.0..=MAX_ELEVATION_DEG).contains(&self.elevation_deg) {
            return Err(StrikeError::Elevation);
        }
        Ok(Strike {
            dir: self.dir / len,
            ..*self
        })
    }

    /// The ball's velocity and spin just after the strike, with the vertical part of the
    /// impulse taken by the slate (as with the `airborne` effect off).
    pub fn ball_motion(&self, params: &Params) -> Result<(DVec2, DVec3), StrikeError> {
        let l = self.launch(params)?;
        Ok((l.vel, l.spin))
    }

    /// The impulse on the ball and the point it acts at (relative to the centre): its line
    /// is the cue's. Squirt is not in it (see [`Strike::launch`]).
    pub fn impulse(&self, params: &Params) -> Result<(DVec3, DVec3), StrikeError> {
        let g = self.geometry(params)?;
        Ok((g.along * (params.ball_mass * g.speed), g.contact))
    }

    /// The ball's motion just after the strike: velocity along the cue (its horizontal part
    /// turned by the squirt, its vertical part into the slate) and spin `r × J / I`.
    pub fn launch(&self, params: &Params) -> Result<Launch, StrikeError> {
        let g = self.geometry(params)?;
        let impulse = g.along * (params.ball_mass * g.speed);
        let spin = g.contact.cross(impulse) / params.inertia();
        // Squirt turns the ball's path away from the side struck.
        let a = g.strike.tip.x;
        let one_minus = 1.0 - a * a;
        let squirt =
            libm::atan(2.5 * a * one_minus.sqrt() / (1.0 + 1.0 / END_MASS_RATIO + 2.5 * one_minus));
        let (sn, cs) = (libm::sin(squirt), libm::cos(squirt));
        let heading = g.forward * cs - g.side * sn;
        Ok(Launch {
            vel: heading * (g.speed * g.cos_e),
            vz: g.along.z * g.speed,
            spin,
        })
    }

    fn geometry(&self, params: &Params) -> Result<Geometry, StrikeError> {
        let s = self.validated()?;
        let m = params.ball_mass;
        let r = params.ball_radius;
        let (a, b) = (s.tip.x, s.tip.y);
        // Ball speed J/m; the offset across the cue is (a, b) whatever the elevation.
        let speed = 2.0 * s.speed / (1.0 + m / CUE_MASS + 2.5 * (a * a + b * b));
        // Frame of the shot: forward f, right-hand side `side` (f rotated clockwise), up z.
        let f = s.dir;
        let side = DVec2::new(f.y, -f.x);
        // Contact point relative to the centre: behind the ball along the cue, offset a·R
        // sideways and b·R along the cue's up.
        let depth = (1.0 - a * a - b * b).sqrt();
        let (cos_e, along, contact) = if s.elevation_deg == 0.0 {
            (
                1.0,
                DVec3::new(f.x, f.y, 0.0),
                DVec3::new(
                    r * (a * side.x - depth * f.x),
                    r * (a * side.y - depth * f.y),
                    r * b,
                ),
            )
        } else {
            let rad = s.elevation_deg * (std::f64::consts::PI / 180.0);
            let (sin_e, cos_e) = (libm::sin(rad), libm::cos(rad));
            // The cue points down along `along`; its "up" is `up`.
            let along = DVec3::new(cos_e * f.x, cos_e * f.y, -sin_e);
            let up = DVec3::new(sin_e * f.x, sin_e * f.y, cos_e);
            let side3 = DVec3::new(side.x, side.y, 0.0);
            (cos_e, along, (side3 * a + up * b - along * depth) * r)
        };
        Ok(Geometry {
            strike: s,
            speed,
            forward: f,
            side,
            cos_e,
            along,
            contact,
        })
    }
}

/// The strike's frame and impulse line.
struct Geometry {
    strike: Strike,
    /// J/m (m/s).
    speed: f64,
    forward: DVec2,
    side: DVec2,
    /// Horizontal part of the cue's unit direction (cos θ).
    cos_e: f64,
    /// Unit direction of the impulse (along the cue).
    along: DVec3,
    /// Tip contact point relative to the centre (m).
    contact: DVec3,
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
                elevation_deg: 0.0,
            },
            Strike {
                speed: 1.0,
                dir: DVec2::ZERO,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
            Strike {
                speed: 1.0,
                dir: DVec2::Y,
                tip: DVec2::new(0.4, 0.4),
                elevation_deg: 0.0,
            },
            Strike {
                speed: 99.0,
                dir: DVec2::Y,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
        ];
        let level = Strike::at_angle(1.0, 90.0, DVec2::ZERO);
        let elevated = [-1.0, 90.5, f64::NAN].map(|e| level.elevated(e));
        for s in bad.into_iter().chain(elevated) {
            assert!(s.ball_motion(&p).is_err(), "{s:?}");
        }
    }

    #[test]
    fn an_elevated_strike_drives_the_ball_into_the_slate_and_tilts_its_spin() {
        let p = Params::default();
        let level = Strike::at_angle(2.0, 90.0, DVec2::new(0.3, 0.0));
        let flat = level.launch(&p).expect("valid");
        assert_eq!(flat.vz, 0.0);
        assert_eq!(
            flat.spin.y, 0.0,
            "a level side hit spins about the vertical only"
        );
        let steep = level.elevated(60.0).launch(&p).expect("valid");
        // Same impulse magnitude, split between the cloth and the slate.
        let (h, v) = (steep.vel.length(), -steep.vz);
        assert!((h * h + v * v).sqrt() - flat.vel.length() < 1e-12);
        assert!((v / h - 3f64.sqrt()).abs() < 0.05, "{h} {v}");
        // The spin axis gains a component along the travel: a massé.
        assert!(steep.spin.y.abs() > 0.1 * steep.spin.length());
        // Straight down through the centre: no horizontal motion, no spin.
        let down = Strike::at_angle(2.0, 90.0, DVec2::ZERO).elevated(90.0);
        let l = down.launch(&p).expect("valid");
        assert!(l.vel.length() < 1e-12 && l.spin.length() < 1e-9 && l.vz < 0.0);
    }
}
