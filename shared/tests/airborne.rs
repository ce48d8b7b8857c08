//! Balls in flight: jump shots over a ball and over a rail, energy across every event, the
//! `airborne` switch, and elevation in scenes.

mod common;

use breakshot_shared::physics::{
    simulate, BallState, EventKind, MotionState, Outcome, Shot, Strike, TableKind,
};
use breakshot_shared::scene::Scene;
use common::*;
use glam::{DVec2, DVec3};

/// A shot on a 9 ft table: the cue ball at `cue` struck along +y at `speed` with the cue
/// elevated by `elevation` degrees, and object balls at `others` (scene coordinates).
fn jump_shot(cue: [f64; 2], others: &[[f64; 2]], speed: f64, elevation: f64) -> Shot {
    let mut balls = vec![ball(cue, [0.0; 2], [0.0; 3])];
    balls.extend(others.iter().map(|&p| ball(p, [0.0; 2], [0.0; 3])));
    let shot = Shot::new(TableKind::NineFoot, balls);
    shot.struck(
        0,
        Strike::at_angle(speed, 90.0, DVec2::ZERO).elevated(elevation),
    )
}

/// `b` in the air: its centre `lift` above its height at rest, rising at `vz` (m/s).
fn airborne(mut b: BallState, lift: f64, vz: f64) -> BallState {
    (b.lift, b.vz, b.motion) = (lift, vz, MotionState::Airborne);
    b
}

/// `shot`'s outcome, with the invariants checked at every event.
fn run_checked(shot: &Shot) -> Outcome {
    let out = run(shot);
    invariant_figures(shot, &out);
    out
}

fn hits(out: &Outcome, a: u16, b: u16) -> bool {
    out.events
        .iter()
        .any(|e| e.kind == EventKind::BallBall { a, b })
}

fn flies(out: &Outcome, i: usize) -> bool {
    out.history[i]
        .iter()
        .any(|p| p.start.motion == MotionState::Airborne)
}

/// The index of the piece of ball `i`'s motion that begins at `t`, an event's time.
fn piece_at(out: &Outcome, i: usize, t: f64) -> usize {
    out.history[i]
        .iter()
        .position(|p| p.t0 == t)
        .unwrap_or_else(|| panic!("ball {i} starts no new piece of motion at {t} s"))
}

/// Where the cue ball's first hop is highest, relative to where it started, and how high.
fn first_apex(shot: &Shot) -> (f64, f64, f64) {
    let out = run(shot);
    let hop = out.history[0][0];
    assert_eq!(
        hop.start.motion,
        MotionState::Airborne,
        "the strike lifts the ball"
    );
    let t = hop.t0 + hop.start.vz / G;
    (
        hop.pos_at(t).y - hop.start.pos.y,
        hop.height_at(t).0,
        hop.t_end,
    )
}

#[test]
fn a_jump_shot_clears_a_ball_a_lower_one_hits_it() {
    let cue = [0.635, 0.4];
    let (speed, elevation) = (4.0, 45.0);
    let (ahead, height, landing) = first_apex(&jump_shot(cue, &[], speed, elevation));
    assert!(ahead > 0.6, "the hop's top is {ahead} m ahead");
    assert!(height > 2.0 * R, "the hop rises {height} m");
    // A blocker right under the top of the hop, about half the table's length away.
    let blocker = [cue[0], cue[1] + ahead];
    let mut over = jump_shot(cue, &[blocker], speed, elevation);
    over.horizon = Some(landing);
    let out = run(&over);
    assert!(!hits(&out, 0, 1), "cleared: {:?}", out.events);
    assert!(
        out.finals[0].pos.y > blocker[1] + 2.0 * R,
        "passed the blocker"
    );
    assert_eq!(out.finals[1].motion, MotionState::Stationary);
    // The same blocker is hit by a lower elevation and by a slower stroke.
    for (speed, elevation) in [(speed, 10.0), (1.5, elevation)] {
        let out = run(&jump_shot(cue, &[blocker], speed, elevation));
        assert!(
            hits(&out, 0, 1),
            "{speed} m/s at {elevation}°: {:?}",
            out.events
        );
    }
}

#[test]
fn a_ball_jumped_over_the_rail_leaves_the_table() {
    let (_, length) = TableKind::NineFoot.size().expect("pocket table");
    let shot = jump_shot([0.635, length - 0.3], &[], 4.0, 45.0);
    let out = run(&shot);
    let left = out
        .events
        .iter()
        .find(|e| e.kind == EventKind::BallOffTable { ball: 0 })
        .expect("the ball leaves the table");
    assert_eq!(out.finals[0].motion, MotionState::OffTable);
    assert_eq!(out.rest_time[0], Some(left.t));
    assert!(
        (out.finals[0].pos.y - length).abs() < 1e-9,
        "left over the far rail"
    );
    // A low hop towards the rail meets the cushion nose instead and stays on the table.
    let low = run(&jump_shot([0.635, length - 0.2], &[], 2.0, 20.0));
    assert!(low
        .events
        .iter()
        .any(|e| matches!(e.kind, EventKind::BallCushion { ball: 0, .. })));
    assert!(!low.finals[0].motion.is_gone());
}

#[test]
fn energy_never_rises_across_any_event() {
    let mut shots = Vec::new();
    // Jumps and massé shots among a few balls, on every pocket table.
    let mut rng = Rng::new(7);
    for table in [
        TableKind::SevenFoot,
        TableKind::EightFoot,
        TableKind::NineFoot,
    ] {
        let (w, l) = table.size().expect("pocket table");
        for k in 0..12 {
            let mut balls = vec![ball([0.5 * w, 0.25 * l], [0.0; 2], [0.0; 3])];
            for m in 0..4 {
                let x = 0.2 * w + 0.15 * w * m as f64;
                balls.push(ball([x, 0.4 * l + 0.05 * k as f64], [0.0; 2], [0.0; 3]));
            }
            let tip = DVec2::new(rng.range(-0.35, 0.35), rng.range(-0.35, 0.35));
            let strike = Strike::at_angle(rng.range(1.0, 8.0), rng.range(60.0, 120.0), tip)
                .elevated(rng.range(5.0, 85.0));
            shots.push(Shot::new(table, balls).struck(0, strike));
        }
    }
    // A jumped break into a full rack.
    let mut rng = Rng::new(3);
    let mut jump_break = break_shot(TableKind::NineFoot, 1e-4, 0.0, 0.0, &mut rng);
    jump_break.strike = Some((0, Strike::at_angle(9.0, 90.0, DVec2::ZERO).elevated(25.0)));
    shots.push(jump_break);
    let mut flew = 0;
    for shot in &shots {
        let out = run(shot);
        let (overlap, _) = invariant_figures(shot, &out);
        assert!(overlap < 1e-9, "balls overlap by {overlap} m");
        flew += usize::from(flies(&out, 0));
    }
    assert!(flew > shots.len() / 2, "only {flew} shots left the cloth");
}

#[test]
fn with_the_switch_off_nothing_flies_and_no_flight_is_predicted() {
    let mut shot = jump_shot([0.635, 0.4], &[[0.635, 1.0]], 4.0, 45.0);
    shot.effects.airborne = false;
    let out = run(&shot);
    assert!(out
        .history
        .iter()
        .flatten()
        .all(|p| p.start.motion != MotionState::Airborne));
    assert_eq!(out.work.flight_checks, 0);
    // A level shot predicts no flight even with the switch on, and costs the same.
    let mut level = jump_shot([0.635, 0.4], &[[0.635, 1.0]], 4.0, 0.0);
    let on = run(&level);
    level.effects.airborne = false;
    let off = run(&level);
    assert_eq!(on.work.flight_checks, 0);
    assert_eq!((on.events, on.work), (off.events, off.work));
}

#[test]
fn scenes_take_an_elevation_and_report_heights_in_flight() {
    let text = r#"{
        "table": "9ft",
        "balls": [{ "id": "cue", "pos": [0.635, 0.4] }],
        "strike": { "ball": "cue", "speed": 4.0, "angle_deg": 90, "elevation_deg": 45 }
    }"#;
    let scene = Scene::from_json(text).expect("valid scene");
    let result = scene.run(Some(0.05)).expect("runs");
    assert!(result.events.iter().any(|e| e.kind == "ball_table"));
    let samples = result.samples.expect("samples");
    let flying: Vec<_> = samples
        .iter()
        .flat_map(|s| &s.balls)
        .filter(|b| b.state == "airborne")
        .collect();
    assert!(!flying.is_empty());
    assert!(flying.iter().all(|b| b.z.is_some_and(|z| z >= R)));
    assert!(samples
        .iter()
        .flat_map(|s| &s.balls)
        .filter(|b| b.state != "airborne")
        .all(|b| b.z.is_none()));
    for bad in ["-1", "91", "1e300"] {
        let text = text.replace(
            "\"elevation_deg\": 45",
            &format!("\"elevation_deg\": {bad}"),
        );
        let err = Scene::from_json(&text).expect_err("refused");
        assert!(err.to_string().contains("elevation_deg"), "{err}");
    }
    // The simulated shot is the one the scene describes.
    assert_eq!(
        result.hash,
        breakshot_shared::hash::hash_hex(
            simulate(&scene.to_shot().expect("valid"))
                .expect("runs")
                .hash()
        )
    );
}

#[test]
fn a_bounce_at_the_cut_off_ends_either_way() {
    use breakshot_shared::physics::airborne::SETTLE_HEIGHT;
    let e = breakshot_shared::physics::Params::default().e_table;
    // Drops whose first rebound rises the cut-off height, to rounding, and a hair either side.
    let exact = SETTLE_HEIGHT / (e * e);
    for h in [exact * (1.0 - 1e-12), exact, exact * (1.0 + 1e-12)] {
        let b = airborne(ball([0.0, 0.0], [0.3, 0.0], [0.0, 0.3 / R, 0.0]), h, 0.0);
        let out = run_checked(&Shot::new(TableKind::Open, vec![b]));
        assert!(out.events.len() <= 4, "{h}: {:?}", out.events);
        assert_eq!(out.finals[0].motion, MotionState::Stationary);
    }
}

/// A ball dropped onto a cushion nose edge, from well inside it to exactly above it: it
/// bounces off the edge into the bed (or, centred right above the edge, off the table), and
/// every case ends in a handful of events.
#[test]
fn landing_on_a_cushion_nose() {
    let (w, l) = TableKind::NineFoot.size().expect("pocket table");
    let ulp = l - f64::from_bits(l.to_bits() - 1);
    for d in [0.9 * R, 0.5 * R, 1e-3 * R, 1e-9 * R, ulp, 0.0] {
        let b = airborne(ball([0.5 * w, l - d], [0.0; 2], [0.0; 3]), 0.1, 0.0);
        let out = run_checked(&Shot::new(TableKind::NineFoot, vec![b]));
        assert!(
            matches!(out.events[0].kind, EventKind::BallCushion { ball: 0, .. })
                || out.events[0].kind == EventKind::BallOffTable { ball: 0 },
            "{d}: {:?}",
            out.events[0]
        );
        assert!(out.events.len() < 100, "{d}: {} events", out.events.len());
        let last = out.finals[0];
        assert!(matches!(
            last.motion,
            MotionState::Stationary | MotionState::OffTable
        ));
        if last.motion == MotionState::Stationary {
            assert!(last.pos.y < l, "{d}: {:?}", last.pos);
        }
        println!(
            "drop {d:e} m from the nose line: {} events, {:?}",
            out.events.len(),
            last.motion
        );
    }
}

/// A ball in flight grazing a ball on the cloth: the 3-D distance's double root, told apart
/// a nanometre either way.
#[test]
fn grazing_a_ball_in_flight() {
    // A ball in flight passes a resting one at the top of its hop, where the centres'
    // closest 3-D distance is 2R·(1 ∓ 1e-9).
    let w = 0.6;
    let v = 2.0;
    let t_top = w / G;
    let top = w * w / (2.0 * G);
    for (sign, expect_hit) in [(-1.0, true), (1.0, false)] {
        let miss = 2.0 * R * (1.0 + sign * 1e-9);
        // Horizontal offset at the top so that the 3-D distance there is `miss`.
        let dx = (miss * miss - top * top).sqrt();
        let mut flying = ball([0.0, -v * t_top], [0.0, v], [0.0; 3]);
        flying.vz = w;
        let resting = ball([dx, 0.0], [0.0; 2], [0.0; 3]);
        let out = run(&Shot::new(TableKind::Open, vec![flying, resting]));
        let hit = out
            .events
            .iter()
            .find(|e| e.kind == EventKind::BallBall { a: 0, b: 1 });
        assert_eq!(hit.is_some(), expect_hit, "{miss}: {:?}", out.events);
        if let Some(hit) = hit {
            assert!((hit.t - t_top).abs() < 1e-3, "{}", hit.t);
        }
    }
}

/// A ball coming down inside a pocket's capture circle falls in as it lands; one coming down
/// just outside the circle, on the table side, bounces on the cloth first.
#[test]
fn a_ball_landing_in_a_pocket_falls_in() {
    let table = breakshot_shared::physics::Table::new(TableKind::NineFoot);
    // Thrown level from 5 cm up at 1.5 m/s towards the pocket, it lands after τ = √(2h/g).
    let (h, v) = (0.05, 1.5);
    let travel = v * (2.0 * h / G).sqrt();
    for (k, pocket) in table.pockets.iter().enumerate() {
        let centre = table.to_scene(pocket.center);
        // Along the pocket's own axis, between its jaws (seen by balls in flight too).
        let c = pocket.center;
        let inward = if c.y.abs() < 1e-9 {
            DVec2::new(-c.x.signum(), 0.0)
        } else {
            DVec2::new(-c.x.signum(), -c.y.signum()).normalize()
        };
        for (reach, falls) in [(0.0, true), (0.9, true), (1.05, false)] {
            let landing = centre + inward * (reach * pocket.radius);
            let start = landing + inward * travel;
            let vel = -inward * v;
            let b = airborne(ball([start.x, start.y], [vel.x, vel.y], [0.0; 3]), h, 0.0);
            let out = run(&Shot::new(TableKind::NineFoot, vec![b]));
            let pocketed = EventKind::BallPocket {
                ball: 0,
                pocket: k as u8,
            };
            let first = out.events[0];
            assert_eq!(
                first.kind == pocketed,
                falls,
                "{} pocket, landing {reach} of its radius in: {:?}",
                pocket.name,
                out.events
            );
            if !falls {
                assert_eq!(first.kind, EventKind::BallTable { ball: 0 });
            } else {
                // At the landing: the flight's time, where the ball comes down.
                assert!((first.t - (2.0 * h / G).sqrt()).abs() < 1e-9, "{}", first.t);
                assert_eq!(out.finals[0].motion, MotionState::Pocketed);
                assert_eq!(out.finals[0].pocket, Some(k as u8));
            }
        }
    }
}

/// The distance from a point (engine coordinates, as in pieces, height `z` above the cloth) to
/// the nose of jaw `k`, the horizontal circle of the jaw's radius at the cushion height.
fn to_jaw_nose(table: &breakshot_shared::physics::Table, k: usize, p: DVec2, z: f64) -> f64 {
    let h = breakshot_shared::physics::Params::default().cushion_height;
    let jaw = table.jaws[k];
    let across = (p - jaw.center).length() - jaw.radius;
    (across * across + (z - h) * (z - h)).sqrt()
}

/// Balls thrown in flight at every jaw of a 9 ft table, from several heights: those that
/// meet a jaw's nose touch it exactly (the centre one radius from the nose circle, checked
/// by the closed form of the distance, not by the solver's polynomial), bounce back into the
/// bed, and keep the energy from rising; those high enough pass over the jaw and leave.
#[test]
fn balls_in_flight_meet_the_jaws() {
    let table = breakshot_shared::physics::Table::new(TableKind::NineFoot);
    let mut touched = 0;
    let mut over = 0;
    for k in 0..table.jaws.len() {
        let jaw = table.jaws[k];
        // The rail end the jaw rounds off, and the direction along the rail from there.
        let (normal, along) = table
            .rails
            .iter()
            .find_map(|rail| {
                let touch = jaw.center + rail.normal * jaw.radius;
                [(rail.a, rail.b), (rail.b, rail.a)]
                    .into_iter()
                    .find(|(end, _)| (touch - *end).length() < 1e-9)
                    .map(|(end, other)| (rail.normal, (other - end).normalize()))
            })
            .expect("every jaw ends a rail");
        // Thrown from the bed at the jaw's rounded nose, past the rail's end.
        let inward = (normal - along).normalize();
        let axis = table.to_scene(jaw.center);
        for (lift, vz) in [
            (0.0, 0.4),
            (0.01, 0.3),
            (0.03, 0.0),
            (0.05, 0.5),
            (0.2, 0.0),
        ] {
            let start = axis + inward * (table.jaws[k].radius + 2.5 * R);
            let vel = -inward * 2.0;
            let b = airborne(ball([start.x, start.y], [vel.x, vel.y], [0.0; 3]), lift, vz);
            let out = run_checked(&Shot::new(TableKind::NineFoot, vec![b]));
            let first = out.events[0];
            let hop = out.history[0][0];
            let s = hop.state_at(first.t, R);
            let z = R + s.lift;
            match first.kind {
                EventKind::BallCushion {
                    cushion: breakshot_shared::physics::Cushion::Jaw(j),
                    ..
                } => {
                    let gap = to_jaw_nose(&table, j as usize, s.pos, z) - R;
                    assert!(gap.abs() < 1e-9, "jaw {j}, lift {lift}: gap {gap:e}");
                    // Approaching until then: a moment earlier the ball was farther away.
                    let before = out.state_at(0, first.t - 1e-4);
                    let earlier = to_jaw_nose(&table, j as usize, before.pos, R + before.lift);
                    assert!(earlier > R, "jaw {j}: {earlier}");
                    // It comes away from the jaw, towards the bed.
                    let after = out.history[0][1].start;
                    assert!(after.vel.dot(inward) > 0.0, "jaw {j}: {:?}", after.vel);
                    touched += 1;
                }
                EventKind::BallOffTable { ball: 0 } => {
                    assert!(z - table_cushion_height() > R, "left below the nose: {z}");
                    over += 1;
                }
                other => println!("jaw {k}, lift {lift}: first {other:?}"),
            }
        }
    }
    assert!(touched >= table.jaws.len(), "{touched} jaw contacts");
    assert!(over >= table.jaws.len() / 2, "{over} balls over a jaw");
    println!("{touched} jaw contacts in flight, {over} balls over a jaw");
}

fn table_cushion_height() -> f64 {
    breakshot_shared::physics::Params::default().cushion_height
}

/// A ball coming down on another at a cut, with side spin: the contact's friction throws the
/// object ball off the 3-D line of centres and spins it, as on the cloth; with the
/// `ball_friction` effect off (or the ideal model) the collision is frictionless.
#[test]
fn ball_friction_acts_in_flight() {
    let collide = |friction: bool| {
        // Falling onto the object ball from 6 cm up, at a half-ball cut, with side spin.
        let falling = airborne(ball([R, -0.2], [0.0, 2.0], [0.0, 0.0, 40.0]), 0.045, 0.0);
        let target = ball([0.0, 0.0], [0.0; 2], [0.0; 3]);
        let mut shot = Shot::new(TableKind::Open, vec![falling, target]);
        shot.effects.ball_friction = friction;
        let out = run_checked(&shot);
        let hit = out
            .events
            .iter()
            .find(|e| e.kind == EventKind::BallBall { a: 0, b: 1 })
            .expect("the balls meet in flight");
        let a = out.state_at(0, hit.t);
        let line = (out.state_at(1, hit.t).pos - a.pos).normalize();
        let b = out.history[1][piece_at(&out, 1, hit.t)].start;
        let a = out.history[0][piece_at(&out, 0, hit.t)].start;
        (angle_between(b.vel, line), a.spin)
    };
    let before = DVec3::new(0.0, 0.0, 40.0);
    let (throw, spin) = collide(true);
    let (straight, kept) = collide(false);
    println!("in flight: throw {throw:.3}°, striker's spin {spin}; frictionless {straight:e}°");
    assert!(throw > 0.1, "throw {throw}°");
    assert!((spin - before).length() > 1.0, "the striker's spin {spin}");
    assert!(straight < 1e-6 && kept == before, "{straight} {kept}");
}

/// The first hop of a centre-ball jump shot against the closed form of the same strike and
/// bounce: the ball leaves the tip at `v = 2V/(1 + m/M)` along the cue (the instantaneous
/// point strike, Alciatore TP A.30, as pooltool's 3-D mode on its main branch applies it), is
/// driven into the slate at `v·sin θ`, comes off at `e_t·v·sin θ` with its horizontal speed
/// lowered by the slate's friction `μ·(1 + e_t)·v·sin θ` (at most the 2/7 that ends the
/// slip), and flies a parabola: apex `(e_t·v·sin θ)²/2g`, first landing `v_h·2e_t·v·sin θ/g`
/// from the strike.
#[test]
fn jump_heights_and_distances_match_the_closed_form() {
    let p = breakshot_shared::physics::Params::default();
    let m_over_cue = p.ball_mass / breakshot_shared::physics::cue::CUE_MASS;
    let e = p.e_table;
    for speed in [2.0, 4.0, 6.0] {
        for elevation in [30.0, 45.0, 60.0, 75.0] {
            let shot = jump_shot([0.635, 0.4], &[], speed, elevation);
            let (_, apex, landing) = first_apex(&shot);
            let v = 2.0 * speed / (1.0 + m_over_cue);
            let rad = elevation * (std::f64::consts::PI / 180.0);
            let down = v * libm::sin(rad);
            let level = v * libm::cos(rad);
            let up = e * down;
            let vh = level - (p.mu_slide * (1.0 + e) * down).min(2.0 / 7.0 * level);
            let want_apex = up * up / (2.0 * G);
            let want_distance = vh * 2.0 * up / G;
            let out = run(&shot);
            let hop = out.history[0][0];
            let distance = hop.pos_at(landing).y - hop.start.pos.y;
            println!(
                "{speed} m/s at {elevation}°: apex {:.1} mm (closed form {:.1}), first landing \
                 {:.3} m ({:.3})",
                apex * 1e3,
                want_apex * 1e3,
                distance,
                want_distance
            );
            assert!((apex - want_apex).abs() < 1e-12, "{apex} {want_apex}");
            assert!(
                (distance - want_distance).abs() < 1e-12,
                "{distance} {want_distance}"
            );
        }
    }
}

/// A ball in flight meeting a rail's nose while running along the rail: the nose's friction
/// takes some of its speed along the rail and spins it, under every cushion model but the
/// mirror one, which leaves both as they were.
#[test]
fn the_nose_has_friction_in_flight() {
    use breakshot_shared::physics::CushionModel;
    let (w, l) = TableKind::NineFoot.size().expect("pocket table");
    let along = |model: CushionModel| {
        let b = airborne(ball([0.3 * w, l - 0.1], [1.0, 1.5], [0.0; 3]), 0.01, 0.3);
        let mut shot = Shot::new(TableKind::NineFoot, vec![b]);
        shot.models.cushion = model;
        let out = run_checked(&shot);
        let nose = out
            .events
            .iter()
            .find(|e| matches!(e.kind, EventKind::BallCushion { ball: 0, .. }))
            .expect("meets the nose");
        let k = piece_at(&out, 0, nose.t);
        assert_eq!(out.history[0][k - 1].start.motion, MotionState::Airborne);
        out.history[0][k].start
    };
    let mirror = along(CushionModel::Simple);
    assert_eq!((mirror.vel.x, mirror.spin), (1.0, DVec3::ZERO));
    for model in [
        CushionModel::Han2005,
        CushionModel::Mathavan2010,
        CushionModel::Stronge,
    ] {
        let s = along(model);
        assert!(s.vel.x < 0.99 && s.spin.length() > 1.0, "{model:?}: {s:?}");
    }
}
