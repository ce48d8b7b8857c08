//! Mathavan, Jackson and Parkin (2010), "A theoretical analysis of billiard ball dynamics
//! under cushion impacts", Proc. IMechE Part C 224(9): the cushion bounce as an integration
//! over the normal impulse `P` at the cushion nose.
//!
//! The ball touches the nose at `I`, at angle θ above its equator, and the cloth at `C`
//! below its centre. Each step adds `ΔP` along the nose's normal, Coulomb friction
//! `f_cushion·ΔP` against the slip at `I`, and at `C` the cloth's normal reaction that keeps
//! the centre on the cloth with sliding friction `mu_slide` times that reaction against the
//! slip at `C` (the paper's eqs. 12–17, written here as vectors). Compression ends when the
//! centre stops approaching the nose; restitution ends when the work of the normal impulse
//! has given back `e_cushion²` of the work absorbed in compression (eq. 16b).
//!
//! The step is fixed by the input, so the result is deterministic: `ΔP` is the impulse of a
//! frictionless bounce of the same approach speed divided by [`STEPS`]. A friction impulse
//! that would reverse a slip within one step stops it instead (the paper's rolling
//! condition, eq. 15), so a contact that rolls stays rolling rather than chattering.

use glam::DVec3;

use super::params::Params;

/// Steps of a frictionless bounce; friction changes the count a little, and the loop stops
/// after 40 times as many whatever happens.
pub const STEPS: u32 = 400;

/// Bounce off a cushion in the cushion's frame: `x` into the cushion, `y` along it, `z` up.
/// `vel.x > 0` (approaching). Returns the velocity (horizontal) and the spin.
pub fn bounce(vel: DVec3, spin: DVec3, sin: f64, cos: f64, params: &Params) -> (DVec3, DVec3) {
    integrate(vel, spin, sin, cos, params, STEPS)
}

fn integrate(
    vel: DVec3,
    spin: DVec3,
    sin: f64,
    cos: f64,
    params: &Params,
    steps: u32,
) -> (DVec3, DVec3) {
    let r = params.ball_radius;
    let m = params.ball_mass;
    let inertia = params.inertia();
    let e = params.e_cushion;
    let mu_w = params.f_cushion;
    let mu_s = params.mu_slide;
    // Contact points from the centre, and the nose normal (from the ball into the nose).
    let n = DVec3::new(cos, 0.0, sin);
    let r_i = n * r;
    let r_c = DVec3::new(0.0, 0.0, -r);
    let dp = (1.0 + e) * m * vel.x / (cos * f64::from(steps));
    // A point contact's tangential slip changes at 7/(2m) per unit impulse.
    let stop = m / 3.5;
    let mut v = DVec3::new(vel.x, vel.y, 0.0);
    let mut w = spin;
    let mut work = 0.0;
    let mut compressed: Option<f64> = None;
    for _ in 0..40 * steps {
        let mut slip_i = v + w.cross(r_i);
        slip_i -= n * slip_i.dot(n);
        let slip_c = v + w.cross(r_c);
        let j_i = -n * dp + friction(slip_i, mu_w * dp, stop);
        // The cloth holds the centre at height R: its reaction cancels the vertical impulse.
        let reaction = -j_i.z;
        let j_c = DVec3::new(0.0, 0.0, reaction) + friction(slip_c, mu_s * reaction, stop);
        let approach = v.dot(n);
        v += (j_i + j_c) / m;
        v.z = 0.0;
        w += (r_i.cross(j_i) + r_c.cross(j_c)) / inertia;
        work += dp * 0.5 * (approach + v.dot(n));
        match compressed {
            None if v.dot(n) <= 0.0 => compressed = Some(work),
            Some(w_c) if work <= (1.0 - e * e) * w_c => break,
            _ => {}
        }
    }
    (v, w)
}

/// Coulomb friction impulse against `slip`, at most `limit`, and no more than stops it.
fn friction(slip: DVec3, limit: f64, stop: f64) -> DVec3 {
    let s = slip.length();
    if s == 0.0 {
        return DVec3::ZERO;
    }
    -slip * (limit.min(s * stop) / s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(e: f64, mu_w: f64, mu_s: f64) -> Params {
        Params {
            e_cushion: e,
            f_cushion: mu_w,
            mu_slide: mu_s,
            ..Params::default()
        }
    }

    #[test]
    fn frictionless_head_on_bounce_returns_e_times_the_speed() {
        // Without friction the centre's motion along x is a linear function of P, so the
        // work balance of eq. 16 gives exactly v' = −e·v (up to one step's overshoot).
        let p = params(0.8, 0.0, 0.0);
        let (sin, cos) = (0.2, (1.0f64 - 0.04).sqrt());
        let (v, w) = bounce(DVec3::new(2.0, 0.0, 0.0), DVec3::ZERO, sin, cos, &p);
        let step = (1.0 + 0.8) * 2.0 / f64::from(STEPS);
        assert!((v.x + 1.6).abs() <= 1.01 * step, "{v}");
        assert!(v.y == 0.0 && w.length() < 1e-9, "{v} {w}");
    }

    #[test]
    fn the_fixed_step_count_is_converged() {
        // A slipping, spinning ball at 35° to the cushion: ten times more steps move the
        // result by under 1 % of the speed.
        let p = params(0.85, 0.2, 0.2);
        let (sin, cos) = (0.2, (1.0f64 - 0.04).sqrt());
        let (v0, w0) = (DVec3::new(1.0, 0.7, 0.0), DVec3::new(-10.0, 20.0, 30.0));
        let (v, w) = integrate(v0, w0, sin, cos, &p, STEPS);
        let (v10, w10) = integrate(v0, w0, sin, cos, &p, 10 * STEPS);
        assert!(v.x < 0.0, "{v}");
        assert!((v - v10).length() < 0.01 * v0.length(), "{v} vs {v10}");
        assert!(
            (w - w10).length() * p.ball_radius < 0.01 * v0.length(),
            "{w} vs {w10}"
        );
    }

    #[test]
    fn friction_never_adds_energy() {
        let p = params(1.0, 0.3, 0.3);
        let (sin, cos) = (0.2, (1.0f64 - 0.04).sqrt());
        let ke = |v: DVec3, w: DVec3| {
            0.5 * p.ball_mass * v.length_squared() + 0.5 * p.inertia() * w.length_squared()
        };
        for (v0, w0) in [
            (DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 40.0, 0.0)),
            (DVec3::new(0.5, -1.0, 0.0), DVec3::new(30.0, 0.0, -50.0)),
        ] {
            let (v, w) = bounce(v0, w0, sin, cos, &p);
            assert!(ke(v, w) <= ke(v0, w0) * 1.001, "{v} {w}");
        }
    }
}
