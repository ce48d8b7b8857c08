//! How a ball above the cloth is drawn from above: bigger the higher it is (it is nearer the
//! eye), with its shadow left on the cloth and falling further away from it as it rises.
//! The light is up and to the left of the table, as for every ball's shadow.

/// Growth of the drawn radius per ball radius of height. A real eye a metre above the table
/// would see a jump of a few centimetres make the ball a few percent bigger, too little to
/// read; this makes a typical jump (a ball radius or two) plainly visible.
pub(crate) const GROWTH_PER_RADIUS: f64 = 0.3;
/// The largest drawn size, as a multiple of the radius.
pub(crate) const MAX_SCALE: f64 = 2.0;
/// Where a ball's shadow falls on the cloth, from its centre, in ball radii (screen x, y):
/// at rest.
pub(crate) const SHADOW_AT_REST: [f64; 2] = [0.22, 0.28];
/// How much further the shadow falls per ball radius of height.
pub(crate) const SHADOW_PER_RADIUS: [f64; 2] = [0.3, 0.38];

/// A ball's look at a height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Drawn radius as a multiple of the ball's.
    pub scale: f64,
    /// The shadow's centre from the ball's (screen x, y), in ball radii.
    pub shadow: [f64; 2],
    /// The shadow's darkness as a fraction of a resting ball's: it fades as the ball rises.
    pub shadow_strength: f64,
}

/// The look of a ball whose centre is `lift` metres above its resting height, for balls of
/// `radius` metres. A ball on the cloth (lift 0, or anything not a finite height above it)
/// looks as it always does.
pub fn flight(lift: f64, radius: f64) -> Flight {
    let h = if lift.is_finite() && radius > 0.0 {
        (lift / radius).max(0.0)
    } else {
        0.0
    };
    Flight {
        scale: (1.0 + GROWTH_PER_RADIUS * h).min(MAX_SCALE),
        shadow: [
            SHADOW_AT_REST[0] + SHADOW_PER_RADIUS[0] * h,
            SHADOW_AT_REST[1] + SHADOW_PER_RADIUS[1] * h,
        ],
        shadow_strength: 1.0 / (1.0 + 0.15 * h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: f64 = 0.028575;

    #[test]
    fn a_ball_on_the_cloth_looks_as_always() {
        for lift in [0.0, -1e-9, f64::NAN, f64::INFINITY] {
            let f = flight(lift, R);
            assert_eq!(f.scale, 1.0);
            assert_eq!(f.shadow, SHADOW_AT_REST);
            assert_eq!(f.shadow_strength, 1.0);
        }
    }

    #[test]
    fn a_higher_ball_is_bigger_and_its_shadow_further_and_fainter() {
        let low = flight(0.5 * R, R);
        let high = flight(2.0 * R, R);
        assert!(1.0 < low.scale && low.scale < high.scale);
        assert!((high.scale - (1.0 + 2.0 * GROWTH_PER_RADIUS)).abs() < 1e-12);
        assert!(low.shadow[0] < high.shadow[0] && low.shadow[1] < high.shadow[1]);
        assert!(high.shadow_strength < low.shadow_strength && low.shadow_strength < 1.0);
        // However high, the ball is drawn at most twice its size.
        assert_eq!(flight(100.0 * R, R).scale, MAX_SCALE);
    }
}
