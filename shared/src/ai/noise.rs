//! Execution noise: the gap between the shot a player means and the shot the cue delivers.
//!
//! The model of the computational pool tournaments: independent Gaussian errors on the aim
//! angle, the cue speed, both tip offsets and, for an elevated cue, its elevation, scaled by
//! one factor per level. Draws come from the rules' [`SplitMix64`] so a seed gives
//! the same errors on every machine.

use glam::DVec2;

use crate::physics::cue::{MAX_CUE_SPEED, MAX_ELEVATION_DEG, MISCUE_LIMIT};
use crate::physics::{Params, Strike};
use crate::rules::rack::SplitMix64;

/// Standard deviation of the aim angle at factor 1 (degrees).
pub const AIM_SIGMA_DEG: f64 = 0.125;
/// Standard deviation of the cue elevation at factor 1 (degrees). Drawn only for a strike
/// with the cue raised: a level cue stays level (the cushion rail keeps it down).
pub const ELEVATION_SIGMA_DEG: f64 = 0.1;
/// Standard deviation of the cue speed at factor 1 (m/s).
pub const SPEED_SIGMA: f64 = 0.075;
/// Standard deviation of each tip offset at factor 1 (m).
pub const TIP_SIGMA_M: f64 = 0.0005;

/// A seeded source of uniform and Gaussian numbers.
#[derive(Clone, Copy, Debug)]
pub struct Rng(SplitMix64);

impl Rng {
    /// A source that starts from `seed`; equal seeds give equal sequences.
    pub fn new(seed: u64) -> Rng {
        Rng(SplitMix64::new(seed))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.unit()
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// A standard normal number (Box–Muller; one of the pair is dropped to keep the state a
    /// single word).
    pub fn gaussian(&mut self) -> f64 {
        // 1 - unit() is in (0, 1], so the logarithm is finite.
        let u = 1.0 - self.unit();
        let v = self.unit();
        libm::sqrt(-2.0 * libm::log(u)) * libm::cos(2.0 * std::f64::consts::PI * v)
    }
}

/// Mixes a seed with a salt into an independent stream (one SplitMix64 step of both).
pub(super) fn mix(seed: u64, salt: u64) -> u64 {
    SplitMix64::new(seed ^ salt.wrapping_mul(0x9E37_79B9_7F4A_7C15)).next_u64()
}

/// The execution noise of one player.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Multiplies every standard deviation (0 = a perfect cue).
    pub factor: f64,
}

impl Noise {
    /// The aim angle's standard deviation (radians).
    pub fn aim_sigma(&self) -> f64 {
        self.factor * AIM_SIGMA_DEG * (std::f64::consts::PI / 180.0)
    }

    /// `strike` as this player delivers it, with errors drawn from `rng`. The result is
    /// always a valid strike: speed and tip are clamped into what the cue accepts.
    pub fn perturb(&self, strike: &Strike, rng: &mut Rng) -> Strike {
        if self.factor == 0.0 {
            return *strike;
        }
        let f = self.factor;
        let angle = f * AIM_SIGMA_DEG * (std::f64::consts::PI / 180.0) * rng.gaussian();
        let speed = strike.speed + f * SPEED_SIGMA * rng.gaussian();
        let tip_sigma = f * TIP_SIGMA_M / Params::default().ball_radius;
        let mut tip = strike.tip + DVec2::new(rng.gaussian(), rng.gaussian()) * tip_sigma;
        // Keep clear of the miscue limit by a hair so the clamped tip is always accepted.
        let limit = MISCUE_LIMIT * 0.999;
        if tip.length() > limit {
            tip *= limit / tip.length();
        }
        // Drawn last and only for a raised cue, so a level strike's errors (and every
        // decision among level strikes) do not depend on it.
        let elevation_deg = if strike.elevation_deg > 0.0 {
            (strike.elevation_deg + f * ELEVATION_SIGMA_DEG * rng.gaussian())
                .clamp(0.0, MAX_ELEVATION_DEG)
        } else {
            strike.elevation_deg
        };
        let (s, c) = (libm::sin(angle), libm::cos(angle));
        let d = strike.dir;
        Strike {
            speed: speed.clamp(0.05, MAX_CUE_SPEED),
            dir: DVec2::new(d.x * c - d.y * s, d.x * s + d.y * c),
            tip,
            elevation_deg,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_has_unit_spread() {
        let mut rng = Rng::new(5);
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| rng.gaussian()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "mean {mean}");
        assert!((var - 1.0).abs() < 0.05, "variance {var}");
    }

    #[test]
    fn only_a_raised_cue_gets_an_elevation_error_of_the_model_s_spread() {
        let noise = Noise { factor: 2.0 };
        let strike = |elevation_deg| Strike {
            speed: 3.0,
            dir: DVec2::Y,
            tip: DVec2::ZERO,
            elevation_deg,
        };
        // A level cue stays level, and its other errors are those drawn before.
        let (mut a, mut b) = (Rng::new(3), Rng::new(3));
        let level = noise.perturb(&strike(0.0), &mut a);
        assert_eq!(level.elevation_deg, 0.0);
        let raised = noise.perturb(&strike(30.0), &mut b);
        assert_eq!(
            (level.speed, level.dir, level.tip),
            (raised.speed, raised.dir, raised.tip)
        );
        // A raised cue's elevation spreads by factor × 0.1°.
        let mut rng = Rng::new(8);
        let n = 4000;
        let errors: Vec<f64> = (0..n)
            .map(|_| noise.perturb(&strike(30.0), &mut rng).elevation_deg - 30.0)
            .collect();
        let sd = (errors.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
        let want = 2.0 * ELEVATION_SIGMA_DEG;
        assert!((sd - want).abs() < 0.05 * want, "sd {sd}, want {want}");
        // Clamped into what the cue accepts, straight down included.
        let mut rng = Rng::new(9);
        for _ in 0..200 {
            let s = Noise { factor: 50.0 }.perturb(&strike(MAX_ELEVATION_DEG), &mut rng);
            assert!(s.validated().is_ok() && s.elevation_deg <= MAX_ELEVATION_DEG);
        }
    }

    #[test]
    fn perturbed_strikes_stay_valid() {
        let mut rng = Rng::new(1);
        let noise = Noise { factor: 50.0 };
        let strike = Strike {
            speed: 0.1,
            dir: DVec2::Y,
            tip: DVec2::new(0.0, 0.49),
            elevation_deg: 0.0,
        };
        for _ in 0..1000 {
            assert!(noise.perturb(&strike, &mut rng).validated().is_ok());
        }
    }
}
