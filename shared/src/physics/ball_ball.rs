//! Ball–ball contact: when two balls meet, and what the collision does to them.

use glam::{DVec2, DVec3};

use super::motion::Piece;
use super::params::{BallBallModel, Params};
use super::roots::{first_contact, pair_bound, stays_apart, Poly, Touch};

/// The squared-distance polynomial of two pieces from absolute time `now`:
/// `f(τ) = |d(τ)|² − (2R)²` with `d = r_b − r_a`.
pub fn contact_poly(a: &Piece, b: &Piece, now: f64, radius: f64) -> Poly {
    let dr = b.pos_at(now) - a.pos_at(now);
    let dv = b.vel_at(now) - a.vel_at(now);
    let da = b.acc - a.acc;
    let diameter = 2.0 * radius;
    [
        // |Δr|² − (2R)², factored to keep precision when the balls touch.
        (dr.length() - diameter) * (dr.length() + diameter),
        2.0 * dr.dot(dv),
        dv.dot(dv) + dr.dot(da),
        dv.dot(da),
        0.25 * da.dot(da),
    ]
}

/// The first time after `now` and no later than `until` at which the balls of pieces `a`
/// and `b` touch while approaching. The callers have ruled out most pairs that cannot meet
/// (their boxes, [`earliest_contact`]); the solver itself is cheap enough that no further
/// test pays for itself.
pub fn collision_time(a: &Piece, b: &Piece, now: f64, until: f64, radius: f64) -> Option<f64> {
    let poly = contact_poly(a, b, now, radius);
    first_contact(&poly, until - now, Touch::squared(2.0 * radius)).map(|dt| now + dt)
}

/// A lower bound on [`collision_time`] (with the same arguments), or `None` when that is
/// certainly `None` ([`pair_bound`] on the same relative motion). Cheap: no root
/// isolation.
#[inline]
pub fn earliest_contact(a: &Piece, b: &Piece, now: f64, until: f64, radius: f64) -> Option<f64> {
    if !a.start.motion.is_translating() && !b.start.motion.is_translating() {
        return None;
    }
    let dr = b.pos_at(now) - a.pos_at(now);
    let dv = b.vel_at(now) - a.vel_at(now);
    let t_max = until - now;
    let da = b.acc - a.acc;
    let tau = pair_bound(dr, dv, da, 2.0 * radius, t_max)?;
    // A contact found by the solver lies within [0, until − now]. Nor is there one when the
    // paths, less the most they bend, stay apart: most pairs passing at an angle, for which
    // the bound along the line of centres is far too low, are dismissed here.
    if tau > t_max || stays_apart(dr, dv, da, t_max, 2.0 * radius) {
        return None;
    }
    Some(now + tau)
}

/// Velocity and spin of one ball going into or out of a collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Horizontal velocity of the centre (m/s).
    pub vel: DVec2,
    /// Angular velocity (rad/s) in the table frame.
    pub spin: DVec3,
}

/// Resolves a collision between balls at `pa` and `pb` (touching), returning their new
/// velocities and spins. Equal masses. Does nothing to a pair that is not approaching.
pub fn collide(
    pa: DVec2,
    pb: DVec2,
    a: Kinematics,
    b: Kinematics,
    model: BallBallModel,
    friction: bool,
    params: &Params,
) -> (Kinematics, Kinematics) {
    let n = (pb - pa).normalize_or_zero();
    if n == DVec2::ZERO {
        return (a, b);
    }
    let van = a.vel.dot(n);
    let vbn = b.vel.dot(n);
    let approach = van - vbn;
    if approach <= 0.0 {
        return (a, b);
    }
    let (van_new, vbn_new) = match model {
        BallBallModel::Ideal => (vbn, van),
        BallBallModel::Frictional => {
            let e = params.e_ball;
            (
                0.5 * ((1.0 - e) * van + (1.0 + e) * vbn),
                0.5 * ((1.0 + e) * van + (1.0 - e) * vbn),
            )
        }
    };
    let mut a_out = a;
    let mut b_out = b;
    a_out.vel = a.vel + (van_new - van) * n;
    b_out.vel = b.vel + (vbn_new - vbn) * n;
    if model == BallBallModel::Frictional && friction {
        apply_friction(&mut a_out, &mut b_out, n, (vbn_new - van_new).abs(), params);
    }
    (a_out, b_out)
}

/// Coulomb friction at the contact (Alciatore TP A-14, extended to both balls and full 3D
/// spin as pooltool's `frictional_inelastic` does). The vertical part of the impulse is taken
/// by the cloth: velocities stay horizontal, spins change in all three axes.
fn apply_friction(
    a: &mut Kinematics,
    b: &mut Kinematics,
    n: DVec2,
    separation: f64,
    params: &Params,
) {
    let va = DVec3::new(a.vel.x, a.vel.y, 0.0);
    let vb = DVec3::new(b.vel.x, b.vel.y, 0.0);
    let n3 = DVec3::new(n.x, n.y, 0.0);
    if let Some((dva, dw)) = friction_impulse(va, a.spin, vb, b.spin, n3, separation, params) {
        a.vel += DVec2::new(dva.x, dva.y);
        b.vel -= DVec2::new(dva.x, dva.y);
        a.spin += dw;
        b.spin += dw;
    }
}

/// The friction of two touching balls, equal masses, whose line of centres (from `a` to
/// `b`) is the unit `n3`, in 3-D: the surfaces slip past each other with tangential velocity
/// `s`; each ball's velocity changes by `μ(|s|)·Δv_n` against `s`, but never more than the
/// `|s|/7` that stops the slip (then the surfaces roll on each other). `Δv_n` is the normal
/// separation speed after the impact. Returns the change of `a`'s velocity (`b`'s is its
/// opposite) and the change of each ball's spin (the same for both), or `None` without slip.
pub(super) fn friction_impulse(
    va: DVec3,
    wa: DVec3,
    vb: DVec3,
    wb: DVec3,
    n3: DVec3,
    separation: f64,
    params: &Params,
) -> Option<(DVec3, DVec3)> {
    let r = params.ball_radius;
    // Surface velocity of each ball at the contact point, tangential part only (the normal
    // parts of the centre velocities are handled by restitution).
    let ca = va + wa.cross(n3 * r);
    let cb = vb + wb.cross(-n3 * r);
    let rel = ca - cb;
    let slip = rel - n3 * rel.dot(n3);
    let slip_speed = slip.length();
    if slip_speed <= 0.0 {
        return None;
    }
    let mu = params.ball_friction.at(slip_speed);
    let dv = (mu * separation).min(slip_speed / 7.0);
    let dva = slip * (-dv / slip_speed);
    let dw = n3.cross(dva) * (2.5 / r);
    Some((dva, dw))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still() -> Kinematics {
        Kinematics {
            vel: DVec2::ZERO,
            spin: DVec3::ZERO,
        }
    }

    #[test]
    fn ideal_exchanges_normal_components() {
        let p = Params::default();
        let a = Kinematics {
            vel: DVec2::new(0.3, 2.0),
            spin: DVec3::ZERO,
        };
        let (a2, b2) = collide(
            DVec2::ZERO,
            DVec2::new(0.0, 2.0 * p.ball_radius),
            a,
            still(),
            BallBallModel::Ideal,
            true,
            &p,
        );
        assert_eq!(a2.vel, DVec2::new(0.3, 0.0));
        assert_eq!(b2.vel, DVec2::new(0.0, 2.0));
    }

    #[test]
    fn separating_pair_is_untouched() {
        let p = Params::default();
        let a = Kinematics {
            vel: DVec2::new(0.0, -1.0),
            spin: DVec3::ZERO,
        };
        let out = collide(
            DVec2::ZERO,
            DVec2::new(0.0, 2.0 * p.ball_radius),
            a,
            still(),
            BallBallModel::Frictional,
            true,
            &p,
        );
        assert_eq!(out, (a, still()));
    }
}
