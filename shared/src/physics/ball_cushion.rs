//! Ball–cushion contact: when a ball reaches a rail or a jaw, and the bounce.
//!
//! The cushion nose touches the ball above its equator, at height `h` above the cloth, at an
//! angle θ with `sin θ = (h − R)/R`. Seen from above the ball then touches the nose when its
//! centre is `R·cos θ` from the nose line (rails) or `R·cos θ + ρ` from a jaw's axis
//! (`R` and `R + ρ` with the `stronge` model, which follows pooltool's geometry).

use glam::{DVec2, DVec3};

use super::mathavan;
use super::motion::Piece;
use super::params::{CushionModel, Params};
use super::roots::{first_contact, Poly, Touch};
use super::stronge;
use super::table::{Jaw, Rail};

/// sin θ and cos θ of the contact angle at the cushion nose.
pub fn nose_angle(params: &Params) -> (f64, f64) {
    let sin = (params.cushion_height - params.ball_radius) / params.ball_radius;
    (sin, (1.0 - sin * sin).sqrt())
}

/// Horizontal distance from a ball's centre to a cushion nose when they touch.
pub fn contact_distance(params: &Params) -> f64 {
    params.ball_radius * nose_angle(params).1
}

/// Horizontal distance from a ball's centre to a cushion nose at which `model` meets it. The
/// `stronge` model takes pooltool's geometry, in which a ball meets the nose line when its
/// centre is `R` from it (see [`stronge::contact_normal`]); the others touch the nose itself,
/// [`contact_distance`].
pub fn model_contact_distance(params: &Params, model: CushionModel) -> f64 {
    match model {
        CushionModel::Stronge => params.ball_radius,
        _ => contact_distance(params),
    }
}

/// The signed distance from the ball of `piece` to the line where it touches `rail` (its
/// nose line moved out by `contact`), as `c₀ + c₁·τ + c₂·τ²` in the time `τ` after `now`.
pub fn rail_line(piece: &Piece, rail: &Rail, now: f64, contact: f64) -> [f64; 3] {
    let n = rail.normal;
    [
        n.dot(piece.pos_at(now) - rail.a) - contact,
        n.dot(piece.vel_at(now)),
        0.5 * n.dot(piece.acc),
    ]
}

/// First time in (now, until] that the ball of `piece` reaches `rail` moving into it, from
/// its [`rail_line`] at `now`.
pub fn rail_time(piece: &Piece, rail: &Rail, now: f64, until: f64, line: [f64; 3]) -> Option<f64> {
    let poly: Poly = [line[0], line[1], line[2], 0.0, 0.0];
    let t = now + first_contact(&poly, until - now, Touch::linear())?;
    // Only the stretch between the rail's ends is straight cushion; past them the ball meets
    // a jaw or goes into the pocket.
    let along = rail.b - rail.a;
    let s = along.dot(piece.pos_at(t) - rail.a);
    (s >= 0.0 && s <= along.dot(along)).then_some(t)
}

/// First time in (now, until] that the ball of `piece` touches `jaw` while approaching it.
pub fn jaw_time(piece: &Piece, jaw: &Jaw, now: f64, until: f64, contact: f64) -> Option<f64> {
    circle_time(piece, jaw.center, jaw.radius + contact, now, until)
}

/// First time in (now, until] that the centre of the ball of `piece` comes within `radius` of
/// the fixed point `center` while approaching it. The caller rules out first the paths that
/// stay far from it (the engine by the path's box and a bound on the time of contact).
pub fn circle_time(piece: &Piece, center: DVec2, radius: f64, now: f64, until: f64) -> Option<f64> {
    let d = piece.pos_at(now) - center;
    let v = piece.vel_at(now);
    let a = piece.acc;
    let dist = d.length();
    let poly: Poly = [
        (dist - radius) * (dist + radius),
        2.0 * d.dot(v),
        v.dot(v) + d.dot(a),
        v.dot(a),
        0.25 * a.dot(a),
    ];
    first_contact(&poly, until - now, Touch::squared(radius)).map(|dt| now + dt)
}

/// The bounce off a cushion whose nose normal (pointing from the nose to the ball, in the
/// plane) is `normal`. Returns the new velocity and spin; a ball not moving into the cushion
/// is returned unchanged.
pub fn bounce(
    vel: DVec2,
    spin: DVec3,
    normal: DVec2,
    model: CushionModel,
    params: &Params,
) -> (DVec2, DVec3) {
    if vel.dot(normal) >= 0.0 {
        return (vel, spin);
    }
    match model {
        CushionModel::Simple => {
            let vn = vel.dot(normal);
            (vel - (1.0 + params.e_cushion) * vn * normal, spin)
        }
        CushionModel::Han2005 => han2005(vel, spin, normal, params),
        CushionModel::Mathavan2010 => {
            let (sin, cos) = nose_angle(params);
            // Into the cushion frame (x into the nose, y along it) and back.
            let ex = -normal;
            let ey = DVec2::new(normal.y, -normal.x);
            let to = |a: DVec2, z: f64| DVec3::new(a.dot(ex), a.dot(ey), z);
            let back = |a: DVec3| (ex * a.x + ey * a.y, a.z);
            let (v, w) =
                mathavan::bounce(to(vel, 0.0), to(spin.truncate(), spin.z), sin, cos, params);
            let (w_xy, w_z) = back(w);
            (back(v).0, w_xy.extend(w_z))
        }
        CushionModel::Stronge => {
            let (v, w) = stronge::bounce(vel.extend(0.0), spin, normal.extend(0.0), params);
            (v.truncate(), w)
        }
    }
}

/// Han (2005), "Dynamics in carom and three cushion billiards", J. Mech. Sci. Tech. 19(4):
/// a single impulse at the nose contact, with restitution `e_cushion` along the contact
/// normal and Coulomb friction `f_cushion` in the contact's tangent plane, capped at the
/// impulse that stops the slip. The impulse's vertical part is taken by the cloth.
///
/// With the two corrections pooltool made to its copy of the paper's equations (its PR
/// #247): the slip stops during the impact when `P_zS ≤ μ·P_zE` (the uncorrected test left
/// out μ), and a sliding impulse points against the slip vector `(sx, sy)/|s|` (the
/// uncorrected code gave it a fixed direction).
fn han2005(vel: DVec2, spin: DVec3, normal: DVec2, params: &Params) -> (DVec2, DVec3) {
    let r = params.ball_radius;
    let m = params.ball_mass;
    let e = params.e_cushion;
    let mu = params.f_cushion;
    let (sin, cos) = nose_angle(params);
    // Cushion frame: x into the cushion, y along it, z up (right-handed).
    let ex = -normal;
    let ey = DVec2::new(normal.y, -normal.x);
    let vx = vel.dot(ex);
    let vy = vel.dot(ey);
    let wx = spin.x * ex.x + spin.y * ex.y;
    let wy = spin.x * ey.x + spin.y * ey.y;
    let wz = spin.z;
    // Slip of the contact point in the tangent plane (Han's eq. 14) and approach speed
    // along the contact normal.
    let sx = vx * sin + r * wy;
    let sy = -vy - r * wz * cos + r * wx * sin;
    let c = vx * cos;
    // Effective inverse masses: tangential 7/(2m), normal 1/m.
    let a_t = 3.5 / m;
    let normal_impulse = (1.0 + e) * c * m;
    let slip = (sx * sx + sy * sy).sqrt();
    let (px, py, pz) = if slip / a_t <= mu * normal_impulse {
        // The slip stops during the impact.
        (
            -sx / a_t * sin - normal_impulse * cos,
            sy / a_t,
            sx / a_t * cos - normal_impulse * sin,
        )
    } else {
        let f = mu * normal_impulse / slip;
        (
            -f * sx * sin - normal_impulse * cos,
            f * sy,
            f * sx * cos - normal_impulse * sin,
        )
    };
    let inertia = params.inertia();
    let vx2 = vx + px / m;
    let vy2 = vy + py / m;
    let wx2 = wx - r / inertia * py * sin;
    let wy2 = wy + r / inertia * (px * sin - pz * cos);
    let wz2 = wz + r / inertia * py * cos;
    let vel2 = ex * vx2 + ey * vy2;
    let w2 = ex * wx2 + ey * wy2;
    (vel2, DVec3::new(w2.x, w2.y, wz2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bounce off a cushion whose normal is `+y`, under the default parameters.
    fn off_the_y_cushion(v: DVec2, w: DVec3, model: CushionModel) -> (DVec2, DVec3) {
        bounce(v, w, DVec2::Y, model, &Params::default())
    }

    /// The ball's kinetic energy, of its travel and its spin, under the default parameters.
    fn energy(v: DVec2, w: DVec3) -> f64 {
        let p = Params::default();
        0.5 * p.ball_mass * v.length_squared() + 0.5 * p.inertia() * w.length_squared()
    }

    #[test]
    fn head_on_bounce_reverses_with_restitution_and_keeps_energy_bounded() {
        let v0 = DVec2::new(0.0, -1.0);
        let (v, w) = off_the_y_cushion(v0, DVec3::ZERO, CushionModel::Han2005);
        assert!(v.y > 0.0 && v.y < 1.0, "{v}");
        assert!(v.x.abs() < 1e-15);
        assert!(energy(v, w) <= energy(v0, DVec3::ZERO));
    }

    /// The Han bounce in the cushion frame: (vx into the cushion, vy along it) and spin.
    fn han_in_frame(vx: f64, vy: f64, w: DVec3, p: &Params) -> (DVec2, DVec3) {
        // normal +y: into the cushion is −y; along it is (normal.y, −normal.x) = +x.
        bounce(DVec2::new(vy, -vx), w, DVec2::Y, CushionModel::Han2005, p)
    }

    #[test]
    fn han_stick_test_carries_mu() {
        // pooltool's first correction: the slip stops when P_zS ≤ μ·P_zE. A ball sliding
        // along the cushion with slip just over μ·P_zE·(7/2m) must slide, and the impulse
        // along the cushion is then exactly μ·P_zE.
        let p = Params::default();
        let (sin, cos) = nose_angle(&p);
        let (vx, m) = (1.0, p.ball_mass);
        let pze = (1.0 + p.e_cushion) * vx * cos * m;
        // Slip along the cushion only: sy = −vy for a ball without spin, and sx = vx·sin.
        let sx = vx * sin;
        let target = 1.01 * p.f_cushion * pze * 3.5 / m;
        let vy = -(target * target - sx * sx).sqrt();
        let (v, _) = han_in_frame(vx, vy, DVec3::ZERO, &p);
        let slip = (sx * sx + vy * vy).sqrt();
        let py = p.f_cushion * pze * (-vy) / slip;
        assert!((v.x - (vy + py / m)).abs() < 1e-12, "{v}");
        // Under the uncorrected test (P_zS ≤ P_zE) this slip would stop: vy' = vy + sy·(2/7).
        let uncorrected = vy + (-vy) / 3.5;
        assert!((v.x - uncorrected).abs() > 1e-3);
    }

    #[test]
    fn han_slide_follows_the_slip_vector() {
        // pooltool's second correction: the sliding impulse points against the slip. With
        // pure side spin the slip at the nose is along the cushion (sx = vx·sin θ is the
        // only other part), so the impulse along the cushion is μ·P_zE·sy/|s|, not zero.
        let p = Params::default();
        let (sin, cos) = nose_angle(&p);
        let (vx, wz, m, r) = (1.0, 200.0, p.ball_mass, p.ball_radius);
        let (v, _) = han_in_frame(vx, 0.0, DVec3::new(0.0, 0.0, wz), &p);
        let (sx, sy) = (vx * sin, -r * wz * cos);
        let pze = (1.0 + p.e_cushion) * vx * cos * m;
        let slip = (sx * sx + sy * sy).sqrt();
        assert!(slip / 3.5 * m > p.f_cushion * pze, "this spin must slide");
        let py = p.f_cushion * pze * sy / slip;
        assert!((v.x - py / m).abs() < 1e-12, "{v}");
    }

    #[test]
    fn every_model_turns_the_ball_back_and_takes_energy() {
        let (v0, w0) = (DVec2::new(0.6, -1.0), DVec3::new(10.0, -5.0, 40.0));
        for model in [
            CushionModel::Han2005,
            CushionModel::Mathavan2010,
            CushionModel::Stronge,
            CushionModel::Simple,
        ] {
            let (v, w) = off_the_y_cushion(v0, w0, model);
            assert!(v.y > 0.0, "{model:?}: {v}");
            assert!(energy(v, w) <= energy(v0, w0) * 1.001, "{model:?}: {v} {w}");
        }
    }

    #[test]
    fn simple_model_mirrors_normal_velocity() {
        let (v, _) = off_the_y_cushion(DVec2::new(0.5, -1.0), DVec3::ZERO, CushionModel::Simple);
        assert!((v.y - Params::default().e_cushion).abs() < 1e-15);
        assert_eq!(v.x, 0.5);
    }
}
