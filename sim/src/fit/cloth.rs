//! Fitting the parameters every shot shares (cloth, ball and cushion constants):
//! Nelder–Mead on a loss of the shots' RMSEs ([`Loss`]), each parameter kept inside a
//! physically sensible range. Every trial of the parameters refits each shot's strike
//! briefly from its last fit, since a strike tuned to one cloth is not the best on another.

use breakshot_shared::physics::{BallFriction, Models, Params};

use super::recording::Recording;
use super::strike::{self, nelder_mead, StrikeFit};

/// The fitted parameters and the range each may take.
pub const RANGES: [(&str, f64, f64); 7] = [
    // Ball–cloth sliding friction: 0.1–0.4 covers pool and carom cloths.
    ("mu_slide", 0.1, 0.4),
    // Rolling resistance: heated carom cloth is fast, 0.003–0.02.
    ("mu_roll", 0.003, 0.02),
    // Spin friction length (m).
    ("mu_spin", 0.002, 0.03),
    // Ball–ball restitution of phenolic balls.
    ("e_ball", 0.85, 0.99),
    // Cushion restitution and friction.
    ("e_cushion", 0.6, 0.98),
    ("f_cushion", 0.05, 0.4),
    // Ball–ball friction at zero slip (the throw and spin transfer of a collision); a
    // speed-dependent law keeps its shape, scaled to this value.
    ("mu_ball", 0.02, 0.3),
];

/// Nelder–Mead iterations of the strike refit inside each trial of the parameters.
const REFIT_ITERS: u64 = 15;

/// The scale of the robust loss (m): where a shot's error starts to count less than in
/// proportion.
pub const ROBUST_SCALE: f64 = 0.1;

/// What the shared fit minimises over the shots' RMSEs (`--loss`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Loss {
    /// Cauchy's loss `c² ln(1 + (r/c)²)` with `c` = [`ROBUST_SCALE`], averaged: like the
    /// squared error for a shot that fits, growing only as the logarithm for one that does
    /// not, so the few shots holding what the engine does not model (a double hit, a
    /// push) do not pull the constants every other shot shares.
    #[default]
    Robust,
    /// The mean RMSE: every metre off counts the same, in any shot.
    Mean,
}

impl Loss {
    /// The loss of one shot's RMSE `r` (m).
    pub fn of(self, r: f64) -> f64 {
        match self {
            Loss::Robust => {
                let x = r / ROBUST_SCALE;
                ROBUST_SCALE * ROBUST_SCALE * libm::log1p(x * x)
            }
            Loss::Mean => r,
        }
    }

    /// How the report names it.
    pub fn describe(self) -> String {
        match self {
            Loss::Robust => format!(
                "the robust (Cauchy) loss of the shots' RMSEs, scale {} cm",
                ROBUST_SCALE * 100.0
            ),
            Loss::Mean => "the mean of the shots' RMSEs".into(),
        }
    }
}

/// The parameters' values, in the order of [`RANGES`].
pub fn values(p: &Params) -> [f64; 7] {
    [
        p.mu_slide,
        p.mu_roll,
        p.mu_spin,
        p.e_ball,
        p.e_cushion,
        p.f_cushion,
        p.ball_friction.at(0.0),
    ]
}

/// `friction` scaled so that it is `mu` at zero slip, keeping how it falls with speed (a
/// law that is nothing at zero slip has no shape to keep: it becomes `mu` at every speed).
fn ball_friction_at_rest(friction: BallFriction, mu: f64) -> BallFriction {
    match friction {
        BallFriction::SpeedDependent { a, b, c } if a + b > 0.0 => {
            let scale = mu / (a + b);
            BallFriction::SpeedDependent {
                a: a * scale,
                b: b * scale,
                c,
            }
        }
        _ => BallFriction::Constant(mu),
    }
}

/// `base` with the values `x` (clamped into their ranges), and how far outside they were.
pub fn with_values(base: &Params, x: &[f64]) -> (Params, f64) {
    let mut v = [0.0; 7];
    let mut excess = 0.0;
    for (k, (_, lo, hi)) in RANGES.iter().enumerate() {
        v[k] = x[k].clamp(*lo, *hi);
        excess += (x[k] - v[k]).abs() / (hi - lo);
    }
    let p = Params {
        mu_slide: v[0],
        mu_roll: v[1],
        mu_spin: v[2],
        e_ball: v[3],
        e_cushion: v[4],
        f_cushion: v[5],
        ball_friction: ball_friction_at_rest(base.ball_friction, v[6]),
        ..*base
    };
    (p, excess)
}

/// The mean `loss` of the RMSEs (m) over the recordings under `params`, each strike
/// refitted from `fits` with `iters` Nelder–Mead iterations.
pub fn mean_loss(
    recs: &[Recording],
    fits: &[StrikeFit],
    params: &Params,
    models: Models,
    iters: u64,
    loss: Loss,
) -> f64 {
    let mut sum = 0.0;
    for (rec, fit) in recs.iter().zip(fits) {
        sum += loss.of(match strike::fit(rec, params, models, Some(fit), iters) {
            Ok(f) => f.rmse,
            Err(_) => 10.0,
        });
    }
    sum / recs.len().max(1) as f64
}

/// Fits the shared parameters from `start` by `loss`, the strikes held at `fits`.
pub fn fit(
    recs: &[Recording],
    fits: &[StrikeFit],
    start: &Params,
    models: Models,
    iters: u64,
    loss: Loss,
) -> Params {
    let cost = |x: &[f64]| {
        let (p, excess) = with_values(start, x);
        mean_loss(recs, fits, &p, models, REFIT_ITERS, loss) + excess
    };
    let x0 = values(start);
    let step: Vec<f64> = RANGES.iter().map(|(_, lo, hi)| 0.15 * (hi - lo)).collect();
    let (best, _) = nelder_mead(&cost, &x0, &step, iters);
    with_values(start, &best).0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_robust_loss_is_the_squared_error_for_a_close_shot_and_a_logarithm_for_a_far_one() {
        let robust = Loss::Robust;
        // Close: about r² (the first term of ln(1 + x) is x).
        let close = 0.001;
        assert!((robust.of(close) / (close * close) - 1.0).abs() < 1e-3);
        // Far: ten times farther costs far less than a hundred times more, and the order
        // of the errors is kept.
        let (at_scale, ten_times) = (robust.of(ROBUST_SCALE), robust.of(10.0 * ROBUST_SCALE));
        assert!(ten_times / at_scale < 7.0, "{}", ten_times / at_scale);
        assert!(robust.of(0.05) < at_scale && at_scale < ten_times);
        assert_eq!(robust.of(0.0), 0.0);
        assert_eq!(Loss::Mean.of(0.25), 0.25);
    }

    #[test]
    fn the_ball_friction_fitted_is_its_value_at_zero_slip_and_its_law_keeps_its_shape() {
        let pool = Params::default();
        // The start's own value gives the start back, bit for bit.
        assert_eq!(with_values(&pool, &values(&pool)).0, pool);
        let mut x = values(&pool);
        x[6] = 0.2;
        let (p, excess) = with_values(&pool, &x);
        assert_eq!(excess, 0.0);
        assert!((values(&p)[6] - 0.2).abs() < 1e-15);
        // Twice the friction at zero slip: about twice at every slip speed.
        let ratio = |v: f64| p.ball_friction.at(v) / pool.ball_friction.at(v);
        assert!((ratio(2.0) - ratio(0.0)).abs() < 1e-12, "{}", ratio(2.0));
        // A law that is nothing at zero slip becomes the value at every speed, not a NaN.
        let none = BallFriction::SpeedDependent {
            a: 0.0,
            b: 0.0,
            c: 1.0,
        };
        let flat = ball_friction_at_rest(none, 0.1);
        assert_eq!(flat, BallFriction::Constant(0.1));
    }
}
