//! The engine against closed-form results from the literature (docs/physics.md lists the
//! sources). Where the result is exact, the tolerance is 1e-9 relative; where the reference
//! prints rounded figures, the tolerance is half a unit of the last printed digit.

mod common;

use breakshot_shared::physics::{BallFriction, EventKind, MotionState, Params, Strike};
use common::*;
use glam::DVec2;

/// Case 1 and 2: a centre hit slides, then rolls, then stops.
fn centre_hit(v0: f64) -> (f64, f64, f64) {
    let out = run(&open_shot(vec![ball([0.0, 0.0], [0.0, v0], [0.0; 3])]));
    let slide_end = out
        .events
        .iter()
        .find(|e| {
            matches!(
                e.kind,
                EventKind::Transition {
                    to: MotionState::Rolling,
                    ..
                }
            )
        })
        .expect("slide ends")
        .t;
    let roll_speed = piece(&out, 0, 1).start.vel.y;
    (slide_end, roll_speed, out.finals[0].pos.y)
}

#[test]
fn centre_hit_slides_then_rolls_then_stops() {
    let v0 = 2.0;
    let (slide_end, roll_speed, total) = centre_hit(v0);
    // Exact closed forms.
    let tau = 2.0 * v0 / (7.0 * MU_S * G);
    let slide_dist = v0 * tau - 0.5 * MU_S * G * tau * tau;
    let v_roll = 5.0 / 7.0 * v0;
    let roll_dist = v_roll * v_roll / (2.0 * MU_R * G);
    assert!(rel(slide_end, tau) < 1e-9);
    assert!(rel(roll_speed, v_roll) < 1e-9);
    assert!(rel(total, slide_dist + roll_dist) < 1e-9);
    // The reference's printed figures.
    assert!((slide_end - 0.29125).abs() < 5e-6);
    assert!((roll_speed - 1.42857).abs() < 5e-6);
    assert!((slide_dist - 0.49928).abs() < 5e-6);
    assert!((roll_dist - 10.4017).abs() < 5e-5);
    assert!((v_roll / (MU_R * G) - 14.5624).abs() < 5e-5);
    assert!((total - 10.9010).abs() < 5e-5);
}

#[test]
fn centre_hit_distance_scales_with_speed_squared() {
    assert!((centre_hit(1.0).2 - 2.7252).abs() < 5e-5);
    assert!((centre_hit(3.0).2 - 24.5272).abs() < 5e-5);
}

#[test]
fn sliding_ball_ends_rolling_at_the_closed_form_velocity() {
    let v0 = DVec2::new(1.0, 0.5);
    let w = [3.0, -7.0, 2.0];
    let out = run(&open_shot(vec![ball([0.0; 2], v0.to_array(), w)]));
    let rolling = piece(&out, 0, 1);
    assert_eq!(rolling.start.motion, MotionState::Rolling);
    // v = (5·v0 + 2R·(ω × ẑ))/7, with ω × ẑ = (ω_y, −ω_x).
    let expected = (5.0 * v0 + 2.0 * R * DVec2::new(w[1], -w[0])) / 7.0;
    let err = (rolling.start.vel - expected).length();
    assert!(
        err < 1e-12 * expected.length(),
        "{} vs {expected}",
        rolling.start.vel
    );
}

#[test]
fn draw_of_two_and_a_half_times_speed_stops_dead() {
    let v0 = 1.5;
    let out = run(&open_shot(vec![ball(
        [0.0, 0.0],
        [0.0, v0],
        [2.5 * v0 / R, 0.0, 0.0],
    )]));
    assert_eq!(out.events.len(), 1);
    assert!(matches!(
        out.events[0].kind,
        EventKind::Transition {
            from: MotionState::Sliding,
            to: MotionState::Stationary,
            ..
        }
    ));
    // It stops when the slip ends: after v0/(μs·g), having slid v0²/(2μs·g).
    assert!(rel(out.events[0].t, v0 / (MU_S * G)) < 1e-9);
    assert!(rel(out.finals[0].pos.y, v0 * v0 / (2.0 * MU_S * G)) < 1e-9);
}

/// A stun (no spin) cue ball at `v` along +y hitting an object ball at cut angle `phi_deg`;
/// returns the two velocities right after the collision.
fn stun_cut(
    shot_params: Params,
    ideal_model: bool,
    friction: bool,
    v: f64,
    phi_deg: f64,
) -> (DVec2, DVec2) {
    let phi = phi_deg * std::f64::consts::PI / 180.0;
    let contact = 2.0 * R * DVec2::new(libm::sin(phi), libm::cos(phi));
    let mut shot = open_shot(vec![
        ball([0.0, 0.0], [0.0, v], [0.0; 3]),
        ball(contact.to_array(), [0.0; 2], [0.0; 3]),
    ]);
    shot.params = shot_params;
    shot.effects.ball_friction = friction;
    if ideal_model {
        shot = ideal(shot);
    }
    let out = run(&shot);
    assert!(matches!(out.events[0].kind, EventKind::BallBall { .. }));
    // The contact point is placed within rounding of touching.
    assert!(out.events[0].t < 1e-15);
    (piece(&out, 0, 1).start.vel, piece(&out, 1, 1).start.vel)
}

#[test]
fn ideal_full_stun_hit_stops_the_cue_ball() {
    let (cue, obj) = stun_cut(Params::default(), true, true, 2.0, 0.0);
    assert_eq!(cue, DVec2::ZERO);
    assert_eq!(obj, DVec2::new(0.0, 2.0));
}

#[test]
fn inelastic_full_stun_hit_leaves_a_fortieth() {
    let (cue, obj) = stun_cut(Params::default(), false, false, 2.0, 0.0);
    assert!(rel(cue.y, 0.025 * 2.0) < 1e-9);
    assert!(rel(obj.y, 0.975 * 2.0) < 1e-9);
    assert!(cue.x.abs() < 1e-15 && obj.x.abs() < 1e-15);
}

#[test]
fn stun_cut_separates_at_ninety_degrees_when_elastic() {
    for phi in [10.0, 30.0, 60.0] {
        let (cue, obj) = stun_cut(Params::default(), true, true, 2.0, phi);
        assert!((angle_between(cue, obj) - 90.0).abs() < 1e-9, "{phi}");
        let p = phi * std::f64::consts::PI / 180.0;
        assert!(rel(cue.length(), 2.0 * libm::sin(p)) < 1e-9);
        assert!(rel(obj.length(), 2.0 * libm::cos(p)) < 1e-9);
    }
}

#[test]
fn stun_cut_separation_angle_with_restitution() {
    for (phi, expected) in [(15.0, 84.67), (30.0, 87.52), (45.0, 88.57)] {
        let (cue, obj) = stun_cut(Params::default(), false, false, 2.0, phi);
        assert!(
            (angle_between(cue, obj) - expected).abs() < 0.005,
            "{phi}: {}",
            angle_between(cue, obj)
        );
    }
}

#[test]
fn rolling_cue_ball_deflection_follows_the_thirty_degree_rule() {
    let v = 1.0;
    for (phi_deg, expected) in [
        (14.48, 27.63),
        (28.125, 33.749),
        (30.0, 33.67),
        (48.59, 27.27),
    ] {
        let phi = phi_deg * std::f64::consts::PI / 180.0;
        let contact = 2.0 * R * DVec2::new(libm::sin(phi), libm::cos(phi));
        let shot = ideal(open_shot(vec![
            ball([0.0, 0.0], [0.0, v], [-v / R, 0.0, 0.0]),
            ball(contact.to_array(), [0.0; 2], [0.0; 3]),
        ]));
        let out = run(&shot);
        // The cue ball's first rolling piece after the collision.
        let rolling = out.history[0]
            .iter()
            .skip(1)
            .find(|p| p.start.motion == MotionState::Rolling)
            .expect("cue ball rolls again");
        let deflection = angle_between(rolling.start.vel, DVec2::Y);
        let s = libm::sin(phi);
        let c = libm::cos(phi);
        let closed = deg(libm::atan(s * c / (s * s + 0.4)));
        assert!(
            (deflection - closed).abs() < 1e-9,
            "{phi_deg}: {deflection} vs {closed}"
        );
        assert!(
            (deflection - expected).abs() < 0.005,
            "{phi_deg}: {deflection}"
        );
        if phi_deg == 30.0 {
            assert!((rolling.start.vel.length() / v - 0.5579).abs() < 5e-5);
        }
    }
}

#[test]
fn draw_and_follow_after_a_full_hit() {
    let v = 2.0;
    for k in [1.0, -1.0] {
        let shot = ideal(open_shot(vec![
            ball([0.0, 0.0], [0.0, v], [-k * v / R, 0.0, 0.0]),
            ball([0.0, 2.0 * R], [0.0; 2], [0.0; 3]),
        ]));
        let out = run(&shot);
        let rolling = out.history[0]
            .iter()
            .find(|p| p.t0 > 0.0 && p.start.motion == MotionState::Rolling)
            .expect("cue ball rolls");
        assert!(rel(rolling.start.vel.y, k * 2.0 * v / 7.0) < 1e-9);
        assert!((rolling.start.vel.y - k * 0.5714).abs() < 5e-5);
        assert!((rolling.t0 - 0.2912).abs() < 5e-5);
        assert!((rolling.start.pos.y.abs() - 0.0832).abs() < 5e-5);
    }
}

#[test]
fn spin_about_the_vertical_decays_at_the_spin_friction_rate() {
    let p = Params::default();
    let rate = 5.0 * p.mu_spin * p.gravity / (2.0 * p.ball_radius);
    assert!((rate - 10.9).abs() < 0.05);
    let out = run(&open_shot(vec![ball(
        [0.0, 0.0],
        [0.0; 2],
        [0.0, 0.0, 25.0],
    )]));
    assert_eq!(out.events.len(), 1);
    assert!(rel(out.events[0].t, 25.0 / rate) < 1e-12);
    assert_eq!(out.finals[0].motion, MotionState::Stationary);
}

#[test]
fn cut_induced_throw_matches_alciatore() {
    let params = Params {
        e_ball: 1.0,
        ball_friction: BallFriction::SpeedDependent {
            a: 0.009951,
            b: 0.108,
            c: 1.088,
        },
        ..Params::default()
    };
    let (_, obj) = stun_cut(params, false, true, 1.341, 30.0);
    let phi = 30.0_f64;
    let line = DVec2::new(
        libm::sin(phi.to_radians_exact()),
        libm::cos(phi.to_radians_exact()),
    );
    assert!((angle_between(obj, line) - 3.549).abs() < 5e-4);
    // At 15° friction saturates (the surfaces stop slipping): atan(tan 15° / 7).
    for v in [0.5, 1.341, 3.0] {
        let (_, obj) = stun_cut(params, false, true, v, 15.0);
        let line = DVec2::new(
            libm::sin(15f64.to_radians_exact()),
            libm::cos(15f64.to_radians_exact()),
        );
        let expected = deg(libm::atan(libm::tan(15f64.to_radians_exact()) / 7.0));
        assert!((angle_between(obj, line) - expected).abs() < 1e-9, "{v}");
        assert!((expected - 2.192).abs() < 5e-4);
    }
}

trait ExactRadians {
    fn to_radians_exact(self) -> f64;
}
impl ExactRadians for f64 {
    fn to_radians_exact(self) -> f64 {
        self * std::f64::consts::PI / 180.0
    }
}

#[test]
fn cue_strike_speed_and_natural_roll() {
    let p = Params::default();
    let centre = Strike {
        speed: 1.0,
        dir: DVec2::Y,
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    };
    let (v, w) = centre.ball_motion(&p).expect("valid");
    let expected = 2.0 / (1.0 + p.ball_mass / 0.567);
    assert!(rel(v.length(), expected) < 1e-12);
    assert!((v.length() - 1.5385).abs() < 5e-5);
    assert_eq!(w.length(), 0.0);
    // Two fifths of R above centre: rolling from the start.
    let roll = Strike {
        speed: 1.0,
        dir: DVec2::Y,
        tip: DVec2::new(0.0, 0.4),
        elevation_deg: 0.0,
    };
    let (v, w) = roll.ball_motion(&p).expect("valid");
    assert!((v.y + R * w.x).abs() < 1e-12 * v.y, "no slip");
    let mut shot = open_shot(vec![ball([0.0, 0.0], [0.0; 2], [0.0; 3])]);
    shot.strike = Some((0, roll));
    let out = run(&shot);
    assert_eq!(out.history[0][0].start.motion, MotionState::Rolling);
}

#[test]
fn squirt_angle_matches_alciatore() {
    let p = Params::default();
    for (a, expected) in [(0.1, 0.426), (0.25, 1.040), (0.5, 1.886)] {
        let s = Strike {
            speed: 2.0,
            dir: DVec2::Y,
            tip: DVec2::new(a, 0.0),
            elevation_deg: 0.0,
        };
        let (v, _) = s.ball_motion(&p).expect("valid");
        let squirt = angle_between(v, DVec2::Y);
        assert!((squirt - expected).abs() < 5e-4, "{a}: {squirt}");
        // Right-hand english sends the ball left of the aim.
        assert!(v.x < 0.0);
    }
}

#[test]
fn heathcote_rolling_law_maps_to_mu_roll_and_back() {
    let p = Params::default();
    let k = p.heathcote_k();
    assert!(rel(p.mu_roll_from_heathcote(k), p.mu_roll) < 1e-12);
    // F = k·W^(5/3)/R^(4/3) is the rolling resistance mu_roll·W.
    let w = p.ball_mass * p.gravity;
    let force = k * libm::pow(w, 5.0 / 3.0) / libm::pow(p.ball_radius, 4.0 / 3.0);
    assert!(rel(force, p.mu_roll * w) < 1e-12);
}

#[test]
fn heathcote_k_in_a_scene_rolls_like_the_mu_roll_it_maps_to() {
    let v = 1.5;
    let mut shot = open_shot(vec![ball([0.0, 0.0], [0.0, v], [-v / R, 0.0, 0.0])]);
    let by_mu = run(&shot);
    shot.params.heathcote_k = Some(shot.params.heathcote_k());
    shot.params.mu_roll = 0.5; // ignored when heathcote_k is given
    let by_k = run(&shot);
    assert!(rel(by_k.finals[0].pos.y, by_mu.finals[0].pos.y) < 1e-12);
    assert!(rel(by_k.duration, by_mu.duration) < 1e-12);
}

/// The ball's velocity when it first rolls without slip (the end of the last slide).
fn first_rolling_velocity(out: &breakshot_shared::physics::Outcome) -> DVec2 {
    out.history[0]
        .iter()
        .find(|p| p.start.motion == MotionState::Rolling)
        .expect("the ball ends up rolling")
        .start
        .vel
}

/// Coriolis' massé rule (Alciatore TP A.19): the cue's impulse J along the cue line, acting
/// at the tip, and the slate's (vertical, and frictional in a bounce) at the contact point,
/// leave the angular momentum about the contact point unchanged, so the ball ends up rolling
/// from where it was struck towards the point A where the cue's line meets the cloth, at
/// (5/7)·|J_z|·|CA|/(m·R). Squirt adds a sideways impulse through the centre, which adds
/// 5/7 of its velocity; with no side offset there is none. Through every bounce of a ball
/// that flies (the `airborne` effect on) and with the slate taking the vertical impulse at
/// once (off) alike.
#[test]
fn masse_follows_coriolis_rule() {
    let p = Params::default();
    let m = p.ball_mass;
    let mut squirt_seen: f64 = 0.0;
    for elevation in [15.0, 40.0, 65.0, 85.0] {
        for tip in [
            [0.0, 0.3],
            [0.3, 0.0],
            [-0.25, 0.2],
            [0.4, -0.2],
            [0.1, -0.45],
        ] {
            for airborne in [true, false] {
                let strike =
                    Strike::at_angle(3.0, 70.0, DVec2::from_array(tip)).elevated(elevation);
                let (impulse, contact) = strike.impulse(&p).expect("valid");
                let launch = strike.launch(&p).expect("valid");
                // Where the cue's line meets the cloth (height −R from the centre).
                let s = (-R - contact.z) / impulse.z;
                let ca = DVec2::new(contact.x + s * impulse.x, contact.y + s * impulse.y);
                let squirt = launch.vel * m - DVec2::new(impulse.x, impulse.y);
                squirt_seen = squirt_seen.max(squirt.length() / (m * launch.vel.length()));
                let expected =
                    ca * (5.0 / 7.0 * impulse.z.abs() / (m * R)) + squirt * (5.0 / 7.0 / m);
                let mut shot = open_shot(vec![ball([0.0, 0.0], [0.0; 2], [0.0; 3])]);
                shot.effects.airborne = airborne;
                let out = run(&shot.struck(0, strike));
                let v = first_rolling_velocity(&out);
                let label = format!("θ {elevation}, tip {tip:?}, airborne {airborne}");
                assert!(
                    angle_between(v, expected) < 0.01,
                    "{label}: {v} vs {expected}"
                );
                assert!(
                    rel(v.length(), expected.length()) < 1e-9,
                    "{label}: {v} vs {expected}"
                );
                if tip[0] == 0.0 {
                    // The plain rule, with no squirt at all.
                    let plain = ca * (5.0 / 7.0 * impulse.z.abs() / (m * R));
                    assert!(angle_between(v, plain) < 0.01, "{label}");
                    assert!(rel(v.length(), plain.length()) < 1e-9, "{label}");
                }
            }
        }
    }
    // The squirt correction is a few percent of the speed, not nothing.
    assert!(squirt_seen > 0.01, "{squirt_seen}");
}

/// A ball dropped from height h lands after √(2h/g) and bounces back up to e²·h, again and
/// again, until a bounce would rise less than the cut-off.
#[test]
fn dropped_ball_bounces_to_e_squared_h() {
    let p = Params::default();
    let h = 0.3;
    let mut dropped = ball([0.0, 0.0], [0.0; 2], [0.0; 3]);
    dropped.lift = h;
    dropped.motion = MotionState::Airborne;
    let out = run(&open_shot(vec![dropped]));
    let landing = out.events[0];
    assert_eq!(landing.kind, EventKind::BallTable { ball: 0 });
    assert!(rel(landing.t, (2.0 * h / G).sqrt()) < 1e-12);
    let mut height = h;
    let mut bounces = 0;
    for piece in out.history[0].iter().skip(1) {
        if piece.start.motion != MotionState::Airborne {
            break;
        }
        let apex = piece.start.vz * piece.start.vz / (2.0 * G);
        height *= p.e_table * p.e_table;
        assert!(
            rel(apex, height) < 1e-9,
            "bounce {bounces}: {apex} vs {height}"
        );
        bounces += 1;
    }
    // 0.3 m, then 75 mm, 19 mm; the third bounce would rise 4.7 mm, under the cut-off.
    assert_eq!(bounces, 2);
    let settle = out.events[bounces];
    assert!(matches!(
        settle.kind,
        EventKind::Transition {
            from: MotionState::Airborne,
            to: MotionState::Stationary,
            ..
        }
    ));
    assert_eq!(out.finals[0].motion, MotionState::Stationary);
    assert_eq!(out.finals[0].pos, DVec2::ZERO);
}

/// A ball leaving the cloth at vertical speed w lands 2w/g later, vt·2w/g further on.
#[test]
fn launched_ball_lands_at_the_ballistic_time() {
    for (w, v) in [(0.5, [0.0, 1.0]), (1.7, [0.8, -0.6]), (3.0, [0.0, 0.0])] {
        let mut b = ball([0.0, 0.0], v, [0.0; 3]);
        // Rolling spin, so the bounce's friction has no slip to act on.
        b.spin = glam::DVec3::new(-v[1] / R, v[0] / R, 0.0);
        b.vz = w;
        let out = run(&open_shot(vec![b]));
        assert_eq!(out.history[0][0].start.motion, MotionState::Airborne);
        let landing = out.events[0];
        let t = 2.0 * w / G;
        assert!(rel(landing.t, t) < 1e-12, "{w}: {} vs {t}", landing.t);
        let at = out.state_at(0, landing.t).pos;
        assert!(
            (at - DVec2::from_array(v) * t).length() < 1e-12,
            "{w}: {at}"
        );
    }
}
