//! Effects on demand: each switch turns its effect off, and an effect that is off costs
//! nothing (no event time is ever predicted for it).

mod common;

use breakshot_shared::physics::{Effects, EventKind, MotionState, Shot, TableKind};
use common::*;
use glam::DVec2;

fn on_table(table: TableKind, balls: Vec<breakshot_shared::physics::BallState>) -> Shot {
    Shot {
        table,
        ..open_shot(balls)
    }
}

#[test]
fn cushions_and_pockets_off_predict_nothing_for_them() {
    let (w, l) = TableKind::NineFoot.size().expect("size");
    let mut shot = on_table(
        TableKind::NineFoot,
        vec![
            ball([w / 2.0, l / 4.0], [0.2, 1.5], [0.0; 3]),
            ball([w / 2.0 + 0.05, l / 2.0], [0.0; 2], [0.0; 3]),
        ],
    );
    let full = run(&shot);
    assert!(full.work.cushion_checks > 0 && full.work.pocket_checks > 0);
    shot.effects.cushions = false;
    shot.effects.pockets = false;
    let bare = run(&shot);
    assert_eq!(bare.work.cushion_checks, 0);
    assert_eq!(bare.work.pocket_checks, 0);
    assert!(!bare.events.iter().any(|e| matches!(
        e.kind,
        EventKind::BallCushion { .. } | EventKind::BallPocket { .. }
    )));
    // The same shot on the open cloth does exactly the same work and gets the same result
    // (to rounding: the engine works in coordinates centred on the table).
    shot.table = TableKind::Open;
    let open = run(&shot);
    assert_eq!(open.work, bare.work);
    assert_eq!(open.events.len(), bare.events.len());
    for (a, b) in open.events.iter().zip(&bare.events) {
        assert_eq!(a.kind, b.kind);
        assert!((a.t - b.t).abs() < 1e-12);
    }
}

#[test]
fn pockets_off_closes_the_rails() {
    // Straight into the corner: with pockets it drops, without it bounces back.
    let shot = |pockets: bool| {
        let mut s = on_table(
            TableKind::NineFoot,
            vec![ball([0.4, 0.4], [-1.5, -1.5], [0.0; 3])],
        );
        s.effects.pockets = pockets;
        s
    };
    let with = run(&shot(true));
    assert!(with
        .events
        .iter()
        .any(|e| matches!(e.kind, EventKind::BallPocket { .. })));
    let without = run(&shot(false));
    assert!(!without
        .events
        .iter()
        .any(|e| matches!(e.kind, EventKind::BallPocket { .. })));
    assert!(
        without
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::BallCushion { .. }))
            .count()
            >= 2
    );
    assert_ne!(without.finals[0].motion, MotionState::Pocketed);
}

#[test]
fn frictions_off_keep_velocity_and_spin() {
    let spin = [3.0, -2.0, 7.0];
    let mut shot = open_shot(vec![ball([0.0, 0.0], [0.4, 1.0], spin)]);
    shot.effects = Effects {
        slide_friction: false,
        ..Effects::default()
    };
    shot.effects.spin_friction = false;
    shot.horizon = Some(5.0);
    let out = run(&shot);
    assert!(out.events.is_empty(), "{:?}", out.events);
    let s = out.finals[0];
    assert_eq!(s.motion, MotionState::Sliding);
    assert_eq!(s.vel, DVec2::new(0.4, 1.0));
    assert_eq!(s.spin.to_array(), spin);
    assert_eq!(s.pos, DVec2::new(2.0, 5.0));
    assert_eq!(out.duration, 5.0);
    assert_eq!(out.rest_time[0], None);
}

#[test]
fn rolling_without_roll_friction_never_slows() {
    let v = 1.2;
    let mut shot = open_shot(vec![ball([0.0, 0.0], [0.0, v], [-v / R, 0.0, 0.0])]);
    shot.effects.roll_friction = false;
    shot.horizon = Some(10.0);
    let out = run(&shot);
    assert!(out.events.is_empty());
    assert_eq!(out.finals[0].vel.y, v);
    assert_eq!(out.finals[0].motion, MotionState::Rolling);
}

#[test]
fn spin_without_spin_friction_never_decays() {
    let mut shot = open_shot(vec![ball([0.0, 0.0], [0.0; 2], [0.0, 0.0, 9.0])]);
    shot.effects.spin_friction = false;
    shot.horizon = Some(3.0);
    let out = run(&shot);
    assert!(out.events.is_empty());
    assert_eq!(out.finals[0].spin.z, 9.0);
    assert_eq!(out.finals[0].motion, MotionState::Spinning);
}

#[test]
fn ball_friction_off_means_no_throw() {
    let phi = 30f64 * std::f64::consts::PI / 180.0;
    let contact = 2.0 * R * DVec2::new(libm::sin(phi), libm::cos(phi));
    let shot = |friction: bool| {
        let mut s = open_shot(vec![
            ball([0.0, 0.0], [0.0, 1.0], [0.0; 3]),
            ball(contact.to_array(), [0.0; 2], [0.0; 3]),
        ]);
        s.effects.ball_friction = friction;
        s
    };
    let without = run(&shot(false));
    let obj = without.history[1][1].start.vel;
    let off = angle_between(obj, contact);
    assert!(
        off < 1e-6,
        "object ball leaves {off}° off the line of centres"
    );
    let with = run(&shot(true));
    assert!(
        angle_between(with.history[1][1].start.vel, contact) > 1.0,
        "throw"
    );
}

#[test]
fn balls_at_rest_are_not_re_solved() {
    // One ball rolls across a table of fifteen that it never reaches.
    let (w, l) = TableKind::NineFoot.size().expect("size");
    let mut rng = Rng::new(1);
    let mut balls = vec![ball([0.1, 0.2], [0.0, 0.3], [-0.3 / R, 0.0, 0.0])];
    balls.extend(rack15(TableKind::NineFoot, 1e-4, &mut rng));
    let out = run(&on_table(TableKind::NineFoot, balls));
    assert_eq!(out.events.len(), 1, "{:?}", out.events);
    // Only pairs with the moving ball are predicted, once each at the start; when it stops,
    // every ball is at rest and nothing is predicted at all.
    assert_eq!(out.work.pair_checks, 15);
    let _ = (w, l);
}
