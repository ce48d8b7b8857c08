//! Property tests over random racks and shots: the invariants of every simulation.

mod common;

use breakshot_shared::physics::motion::SLIP_EPS;
use breakshot_shared::physics::{simulate, EventKind, Strike, TableKind};
use breakshot_shared::scene::{Scene, SceneBall, SceneStrike};
use common::*;
use glam::DVec2;
use proptest::prelude::*;

fn tables() -> impl Strategy<Value = TableKind> {
    prop_oneof![
        Just(TableKind::SevenFoot),
        Just(TableKind::EightFoot),
        Just(TableKind::NineFoot)
    ]
}

/// A random break with a real cue strike (speed, aim, tip) on a random rack.
fn random_break(
    table: TableKind,
    seed: u64,
    jitter: f64,
    speed: f64,
    aim_deg: f64,
    tip: (f64, f64),
) -> breakshot_shared::physics::Shot {
    let mut rng = common::Rng::new(seed);
    let mut shot = break_shot(table, jitter, 0.0, 0.0, &mut rng);
    shot.balls[0].vel = DVec2::ZERO;
    shot.strike = Some((
        0,
        Strike::at_angle(speed, 90.0 + aim_deg, DVec2::new(tip.0, tip.1)),
    ));
    shot
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn random_breaks_keep_every_invariant(
        table in tables(),
        seed in any::<u64>(),
        jitter in 0.0..1.25e-4f64,
        speed in 0.5..10.0f64,
        aim in -4.0..4.0f64,
        side in -0.3..0.3f64,
        height in -0.3..0.3f64,
    ) {
        let shot = random_break(table, seed, jitter, speed, aim, (side, height));
        let out = simulate(&shot).expect("simulates");
        prop_assert!(out.events.len() < 1000);
        let overlap = check_invariants(&shot, &out);
        prop_assert!(overlap < 1e-9, "overlap {overlap}");
        // Linear momentum is unchanged by every ball–ball contact: to rounding, and to the
        // cloth's impulse when a ball left with a slip under `SLIP_EPS` is set rolling at the
        // same instant (at most 2/7·SLIP_EPS per ball involved).
        for e in &out.events {
            if !matches!(e.kind, EventKind::BallBall { .. }) {
                continue;
            }
            if out.events.iter().any(|o| o.t == e.t && !matches!(o.kind, EventKind::BallBall { .. })) {
                continue;
            }
            let momentum = |t: f64, before: bool| {
                out.history.iter().map(|pieces| {
                    let k = if before {
                        pieces.partition_point(|q| q.t0 < t)
                    } else {
                        pieces.partition_point(|q| q.t0 <= t)
                    };
                    let q = &pieces[k.max(1) - 1];
                    q.vel_at(t.min(q.t_end))
                }).fold(DVec2::ZERO, |a, b| a + b)
            };
            let (p0, p1) = (momentum(e.t, true), momentum(e.t, false));
            let tolerance = 1e-12 * p0.length() + out.history.len() as f64 * 2.0 / 7.0 * SLIP_EPS;
            prop_assert!((p0 - p1).length() <= tolerance, "{p0} -> {p1} at {}", e.t);
        }
        // The table the shot leaves is one the next shot may start from: every ball at rest
        // is on the playing surface (against a rail, in a pocket's mouth, against a jaw).
        let mut next = shot.clone();
        next.balls = out.finals.clone();
        next.strike = None;
        prop_assert!(simulate(&next).is_ok(), "{:?}", simulate(&next).err());
        // The same shot twice gives the same bits.
        let again = simulate(&shot).expect("simulates");
        prop_assert_eq!(out.hash(), again.hash());
        prop_assert_eq!(&out.events, &again.events);
    }

    #[test]
    fn scene_json_round_trip_keeps_the_hash(
        table in tables(),
        seed in any::<u64>(),
        jitter in 0.0..1.25e-4f64,
        speed in 0.5..10.0f64,
        aim in -4.0..4.0f64,
    ) {
        let shot = random_break(table, seed, jitter, speed, aim, (0.0, 0.1));
        let scene = Scene {
            table,
            physics: shot.params,
            models: shot.models,
            effects: shot.effects,
            horizon: None,
            balls: shot.balls.iter().enumerate().map(|(i, b)| SceneBall {
                id: i.to_string(),
                pos: b.pos.to_array(),
                vel: b.vel.to_array(),
                spin: b.spin.to_array(),
            }).collect(),
            strike: shot.strike.map(|(_, s)| SceneStrike {
                ball: "0".into(),
                speed: s.speed,
                dir: Some(s.dir.to_array()),
                angle_deg: None,
                tip: s.tip.to_array(),
                elevation_deg: s.elevation_deg,
            }),
        };
        let text = scene.to_json();
        let parsed = Scene::from_json(&text).expect("parses");
        prop_assert_eq!(&parsed, &scene);
        let direct = simulate(&shot).expect("simulates").hash();
        let via_json = simulate(&parsed.to_shot().expect("valid")).expect("simulates").hash();
        prop_assert_eq!(direct, via_json);
    }
}
