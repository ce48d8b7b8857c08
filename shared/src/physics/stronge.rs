//! Stronge's compliant frictional impact (W. J. Stronge, *Impact Mechanics*, 2000, ch. 5;
//! for spheres, Stronge's tangential-compliance analysis), applied to a cushion as pooltool
//! 0.6.0's default cushion does (its `stronge_compliant` resolver, `omega_ratio = 1.8`): the
//! contact's normal and tangential compliances are springs, the normal one stiffer in
//! restitution so that it returns `e_cushion` of the approach speed, and Coulomb friction
//! `f_cushion` bounds the tangential spring force.
//!
//! The geometry is pooltool's: the ball meets a rail when its centre is `R` from the nose
//! line (seen from above), and the contact normal runs from the nose, at `cushion_height`,
//! to the ball's centre, so it points down at φ with `tan φ = (h − R)/R` (15.6° for a pool
//! ball). The impact is solved along that normal and in the plane square to it, in 3-D; the
//! cloth then takes the vertical part of the impulse. Only the tangential impulse turns the
//! ball: the normal one passes through its centre.
//!
//! In time scaled so that the normal frequency is 1, compression lasts π/2 and the contact
//! `(1 + e)·π/2`. The tangential spring vibrates at `ω_t = 1.8` (which fixes the stiffness
//! ratio `η² = β_t/ω_t²`). With `β_n = 1` and `β_t = 7/2` (the inverse effective masses of a
//! sphere on a flat, normal and tangential) and the initial ratio `x = v_t0/v_n0 ≥ 0` of
//! tangential to normal contact speed, three cases:
//! - gross slip, `x > μ((1 + e)β_t − η²/e)`: sliding throughout, the rigid Coulomb result
//!   `v_t = v_t0 − μ·β_t·(1 + e)·v_n0`;
//! - initial stick, `x < μη²`: the contact sticks (the tangential spring oscillates) until
//!   the spring force reaches μ times the normal force in restitution, then slides;
//! - slip–stick–slip in between.
//!
//! The switch times are closed forms (`acos`) or the root of a smooth function found by
//! bracketing on a fixed grid and a fixed number of bisection steps, so the result is
//! deterministic.

use std::f64::consts::FRAC_PI_2;

use glam::DVec3;

use super::params::Params;

/// Ratio of the tangential to the normal contact frequency: pooltool 0.6.0's default
/// resolver sets 1.8 (its class alone defaults to 1.7).
pub const FREQUENCY_RATIO: f64 = 1.8;
/// Inverse effective masses (in units of 1/m) of a sphere against a flat: normal, tangential.
const BETA_N: f64 = 1.0;
const BETA_T: f64 = 3.5;
/// Bisection steps for a switch time: 2^-60 of the contact time.
const BISECTIONS: u32 = 50;
/// Grid on which a switch time is first bracketed.
const GRID: u32 = 64;

/// Unit normal of the contact, from the cushion nose to the ball's centre, for a ball whose
/// centre is `R` from the nose line (pooltool's contact distance) and the nose at
/// `cushion_height`: `n` tilted down by φ with `tan φ = (h − R)/R`.
pub fn contact_normal(n: DVec3, params: &Params) -> DVec3 {
    let r = params.ball_radius;
    let drop = r - params.cushion_height;
    let reach = (r * r + drop * drop).sqrt();
    n * (r / reach) + DVec3::Z * (drop / reach)
}

/// Bounce of a ball with velocity `vel` and spin `spin` off a cushion whose horizontal unit
/// normal `n` points out of the cushion (`vel·n < 0`). Returns velocity (horizontal) and spin.
pub fn bounce(vel: DVec3, spin: DVec3, n: DVec3, params: &Params) -> (DVec3, DVec3) {
    let r = params.ball_radius;
    let n = contact_normal(n, params);
    // Velocity of the ball's surface at the contact point −R·n.
    // Its normal part is the centre's, `vel·n`: negative for a ball on the cloth moving into
    // the cushion, whatever its spin.
    let contact = vel + spin.cross(-n * r);
    let v_n0 = contact.dot(n);
    let tangential = contact - n * v_n0;
    let slip = tangential.length();
    let t_dir = if slip > 0.0 {
        -tangential / slip
    } else {
        DVec3::ZERO
    };
    let v_t0 = -slip;
    let (v_tf, v_nf) = resolve(v_t0, v_n0, params.f_cushion, params.e_cushion);
    let dv_n = (v_nf - v_n0) / BETA_N;
    let dv_t = (v_tf - v_t0) / BETA_T;
    let mut v = vel + n * dv_n + t_dir * dv_t;
    // The cloth takes the vertical part of the impulse.
    v.z = 0.0;
    let w = spin + (-n).cross(t_dir * dv_t) * (2.5 / r);
    (v, w)
}

/// Final tangential and normal contact speeds of Stronge's compliant impact with
/// `v_t0 ≤ 0`, `v_n0 < 0`, friction `mu` and restitution `e`.
pub fn resolve(v_t0: f64, v_n0: f64, mu: f64, e: f64) -> (f64, f64) {
    let v_nf = -e * v_n0;
    if mu == 0.0 || v_t0 == 0.0 || e == 0.0 {
        // No tangential force can act (or, with e = 0, the contact ends at full compression
        // and the sticking spring has nothing to give back): friction as a rigid impulse.
        let dv = (-v_t0).min(-mu * BETA_T * (1.0 + e) * v_n0);
        return (v_t0 + dv, v_nf);
    }
    let w_t = FREQUENCY_RATIO;
    let r = BETA_T / BETA_N;
    let eta2 = r / (w_t * w_t);
    let t_c = FRAC_PI_2;
    let t_f = (1.0 + e) * t_c;
    let x = v_t0 / v_n0;
    // Phase of the normal oscillation in restitution (π/2 at t_c, π at t_f).
    let phase = |t: f64| t / e + FRAC_PI_2 * (1.0 - 1.0 / e);
    let v_t = if x > mu * ((1.0 + e) * r - eta2 / e) {
        v_t0 - mu * v_n0 * r * (1.0 + e)
    } else if x < mu * eta2 {
        // Stuck from the start: the tangential spring holds while its force stays under
        // μ times the normal force, which falls to zero at t_f.
        let excess =
            |t: f64| (x * libm::sin(w_t * t)).abs() - mu * eta2 * w_t * libm::sin(phase(t));
        let t_slip = root(excess, t_c, t_f);
        v_t0 * libm::cos(w_t * t_slip) + mu * v_n0 * r * e * (1.0 + libm::cos(phase(t_slip)))
    } else {
        // Slides first, sticks when the slip stops, slides again in restitution.
        let tau = if x <= mu * r {
            let c = (x / mu - r) / (eta2 - r);
            libm::acos(c.clamp(-1.0, 1.0)) / FRAC_PI_2
        } else {
            let c = (x / mu - r) / (eta2 / e - e * r);
            (libm::acos(c.clamp(-1.0, 1.0)) - FRAC_PI_2 * (1.0 - 1.0 / e)) / FRAC_PI_2 * e
        };
        let t_stick = t_c * tau;
        let (u_s, v_s) = if t_stick <= t_c {
            (
                -mu * v_n0 * eta2 * libm::sin(t_stick),
                v_t0 - mu * r * v_n0 * (1.0 - libm::cos(t_stick)),
            )
        } else {
            (
                -mu * v_n0 * eta2 * libm::sin(phase(t_stick)),
                v_t0 - mu * r * v_n0 * (1.0 - e * libm::cos(phase(t_stick))),
            )
        };
        let spring = |t: f64| {
            u_s * libm::cos(w_t * (t - t_stick)) - v_s / w_t * libm::sin(w_t * (t - t_stick))
        };
        let excess = |t: f64| (spring(t) / (mu * v_n0)).abs() - eta2 * libm::sin(phase(t));
        // The excess touches zero at t_stick itself (the slip has just stopped with the
        // spring force at μN): look for the crossing after it.
        let t_slip = root(excess, t_stick.max(t_c), t_f);
        let dt = t_slip - t_stick;
        let v_stick = w_t * u_s * libm::sin(w_t * dt) + v_s * libm::cos(w_t * dt);
        v_stick + r * mu * v_n0 * e * (1.0 + libm::cos(phase(t_slip)))
    };
    (v_t, v_nf)
}

/// Where `f` crosses from negative to non-negative in `[lo, hi]`: the first grid point
/// (of [`GRID`]) where `f < 0` starts the search (the slip functions touch zero at the
/// interval's start), the next grid point where `f ≥ 0` closes it, and bisection finds the
/// crossing between them. Without a crossing, `lo`.
fn root(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let at = |k: u32| lo + (hi - lo) * f64::from(k) / f64::from(GRID);
    let Some(first) = (0..=GRID).find(|&k| f(at(k)) < 0.0) else {
        return lo;
    };
    let Some(close) = (first + 1..=GRID).find(|&k| f(at(k)) >= 0.0) else {
        return hi;
    };
    let (mut a, mut b) = (at(close - 1), at(close));
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (a + b);
        if f(mid) < 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_speed_follows_restitution() {
        for x in [0.0, 0.05, 0.3, 2.0] {
            let (_, v_n) = resolve(-x, -1.0, 0.2, 0.85);
            assert!((v_n - 0.85).abs() < 1e-15);
        }
    }

    #[test]
    fn gross_slip_is_the_rigid_coulomb_result() {
        // Closed form: a sliding contact loses μ·β_t·(1 + e)·|v_n0| of tangential speed.
        let (mu, e) = (0.2, 0.85);
        let (v_t, _) = resolve(-3.0, -1.0, mu, e);
        assert!(
            (v_t - (-3.0 + mu * BETA_T * (1.0 + e))).abs() < 1e-12,
            "{v_t}"
        );
    }

    #[test]
    fn the_three_cases_join_continuously() {
        // The final tangential speed is a continuous function of the incidence ratio
        // (Stronge's curve of final against initial ratio): no jumps between the cases.
        let (mu, e) = (0.2, 0.85);
        let mut last = resolve(-1e-6, -1.0, mu, e).0;
        let mut x = 1e-6;
        while x < 3.0 {
            x += 1e-4;
            let v = resolve(-x, -1.0, mu, e).0;
            assert!((v - last).abs() < 1e-2, "jump at x = {x}: {last} -> {v}");
            last = v;
        }
    }

    #[test]
    fn a_contact_that_never_slides_follows_the_tangential_spring() {
        // Closed form: with friction too high to slide until the normal force vanishes at
        // t_f, the contact speed is the undamped spring's, v_t0·cos(ω_t·t_f).
        let e = 0.85;
        let (v_t, _) = resolve(-0.1, -1.0, 1e6, e);
        let expected = -0.1 * libm::cos(FREQUENCY_RATIO * (1.0 + e) * FRAC_PI_2);
        assert!((v_t - expected).abs() < 1e-6, "{v_t} vs {expected}");
    }

    #[test]
    fn the_contact_normal_points_from_the_nose_to_the_centre() {
        // pooltool's geometry: the centre R from the nose line, the nose at h above the
        // cloth, so the normal falls at tan φ = (h − R)/R.
        let p = Params::default();
        let n = contact_normal(DVec3::Y, &p);
        let (r, h) = (p.ball_radius, p.cushion_height);
        assert!((n.length() - 1.0).abs() < 1e-15);
        assert_eq!(n.x, 0.0);
        assert!((-n.z / n.y - (h - r) / r).abs() < 1e-15, "{n}");
    }

    #[test]
    fn a_frictionless_square_hit_returns_e_along_the_tilted_normal() {
        // Closed form: with μ = 0 only the normal impulse acts, (1 + e)·v·cos φ along the
        // tilted normal; the cloth takes its vertical part, so the ball comes back at
        // v·((1 + e)·cos²φ − 1), and it passes through the centre, so no spin.
        let p = Params {
            f_cushion: 0.0,
            ..Params::default()
        };
        let (v, w) = bounce(DVec3::new(0.0, -1.0, 0.0), DVec3::ZERO, DVec3::Y, &p);
        let cos = contact_normal(DVec3::Y, &p).y;
        assert!(
            (v.y - ((1.0 + p.e_cushion) * cos * cos - 1.0)).abs() < 1e-15,
            "{v}"
        );
        assert_eq!((v.x, v.z), (0.0, 0.0));
        assert_eq!(w, DVec3::ZERO);
    }

    #[test]
    fn bounce_keeps_the_ball_on_the_cloth() {
        let p = Params::default();
        let n = DVec3::new(0.0, 1.0, 0.0);
        let (v, w) = bounce(
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::new(20.0, 0.0, 10.0),
            n,
            &p,
        );
        assert_eq!(v.z, 0.0);
        assert!(v.y > 0.0 && w.is_finite());
    }
}
