//! The golden shots and their results, in the form of `hashes.txt`: the one list of them.
//!
//! Two builds use this file: the native golden test (`tests/golden.rs`) and the WebAssembly
//! module that runs the same shots in a browser's engine (`web/golden`), so a shot added here is
//! checked in both. It therefore depends only on `breakshot_shared`, `glam` and `libm`, reads no
//! files (the scenes are compiled in) and never panics: a shot that does not simulate is an
//! error line, which can never equal a stored hash.

use std::collections::BTreeMap;

use breakshot_shared::hash::hash_hex;
use breakshot_shared::physics::{simulate, BallState, MotionState, Shot, Strike, TableKind};
use breakshot_shared::protocol::{reference_hash, reference_shots};
use breakshot_shared::rules::rack::SplitMix64;
use breakshot_shared::scene::Scene;
use glam::{DVec2, DVec3};

/// The ball radius of the hand-built shots (the standard pool ball).
const R: f64 = 0.028575;

/// The scene files of the golden set, by name (they sit next to this file).
const SCENES: [(&str, &str); 5] = [
    ("center_hit_open", include_str!("center_hit_open.json")),
    ("stun_shot_open", include_str!("stun_shot_open.json")),
    (
        "half_ball_rolling_open",
        include_str!("half_ball_rolling_open.json"),
    ),
    ("break_8ball_7ft", include_str!("break_8ball_7ft.json")),
    ("snooker_break", include_str!("snooker_break.json")),
];

/// One golden result: the number of events and the state hash, or why the shot failed.
pub type Entry = Result<(usize, String), String>;

/// Every golden shot, by name, or why one could not be built.
pub fn shots() -> Result<Vec<(String, Shot)>, String> {
    let mut shots = Vec::new();
    for (name, text) in SCENES {
        let shot = Scene::from_json(text)
            .and_then(|scene| scene.to_shot())
            .map_err(|e| format!("scene {name}: {e}"))?;
        shots.push((name.to_string(), shot));
    }
    // A frozen five-ball cradle.
    let mut cradle = vec![ball([0.0, 0.0], [0.0, 2.0])];
    for k in 1..=5 {
        cradle.push(ball([0.0, k as f64 * 2.0 * R], [0.0; 2]));
    }
    shots.push(("cradle_5_frozen".into(), open_shot(cradle)));
    // Breaks with a real cue strike: frozen and gapped racks, 9 ft, with side and draw.
    for (name, jitter, speed, tip) in [
        ("break_9ft_frozen", 0.0, 8.0, (0.0, 0.0)),
        ("break_9ft_gapped", 1e-4, 11.0, (0.1, -0.2)),
    ] {
        let mut rng = SplitMix64::new(42);
        let mut shot = break_shot(TableKind::NineFoot, jitter, &mut rng)?;
        shot.strike = Some((0, Strike::at_angle(speed, 90.3, DVec2::new(tip.0, tip.1))));
        shots.push((name.into(), shot));
    }
    // A cushion shot with english on an 8 ft table.
    let mut rail = open_shot(vec![ball([0.3, 0.4], [0.0; 2])]);
    rail.table = TableKind::EightFoot;
    rail.strike = Some((0, Strike::at_angle(3.0, 63.0, DVec2::new(-0.3, 0.2))));
    shots.push(("cushions_english_8ft".into(), rail));
    // A massé around a blocker and a jump over one, on a 9 ft table (cue elevation).
    let blocker = |y: f64| ball([0.635, y], [0.0; 2]);
    let mut masse = open_shot(vec![ball([0.6, 0.5], [0.0; 2]), blocker(0.9)]);
    masse.table = TableKind::NineFoot;
    let strike = Strike::at_angle(2.5, 88.0, DVec2::new(0.35, 0.1)).elevated(70.0);
    shots.push(("masse_9ft".into(), masse.struck(0, strike)));
    let mut jump = open_shot(vec![ball([0.635, 0.4], [0.0; 2]), blocker(1.09)]);
    jump.table = TableKind::NineFoot;
    let strike = Strike::at_angle(4.0, 90.0, DVec2::new(0.0, -0.1)).elevated(45.0);
    shots.push(("jump_9ft".into(), jump.struck(0, strike)));
    // The handshake's reference shots, one per mechanism (see protocol::reference): the
    // physics fingerprint is made of exactly these.
    for reference in reference_shots() {
        shots.push((format!("reference_{}", reference.name), reference.shot));
    }
    Ok(shots)
}

/// Simulates every golden shot and adds the physics fingerprint (no events of its own), so a
/// change of it is reviewed too. Sorted by name, as `hashes.txt` is.
pub fn results() -> BTreeMap<String, Entry> {
    let mut results = BTreeMap::new();
    match shots() {
        Ok(shots) => {
            for (name, shot) in shots {
                let result = simulate(&shot)
                    .map(|out| (out.events.len(), hash_hex(out.hash())))
                    .map_err(|e| e.to_string());
                results.insert(name, result);
            }
        }
        Err(e) => {
            results.insert("shots".into(), Err(e));
        }
    }
    let fingerprint = reference_hash()
        .map(|h| (0, hash_hex(h)))
        .map_err(|e| e.to_string());
    results.insert("physics_fingerprint".into(), fingerprint);
    results
}

/// The results as `hashes.txt` holds them: `name events hash`, one line each; a failed shot
/// is `name error: why`.
pub fn to_text(results: &BTreeMap<String, Entry>) -> String {
    let mut text = String::new();
    for (name, result) in results {
        match result {
            Ok((events, hash)) => text.push_str(&format!("{name} {events} {hash}\n")),
            Err(why) => text.push_str(&format!("{name} error: {why}\n")),
        }
    }
    text
}

fn ball(pos: [f64; 2], vel: [f64; 2]) -> BallState {
    BallState {
        pos: DVec2::from_array(pos),
        vel: DVec2::from_array(vel),
        spin: DVec3::ZERO,
        motion: MotionState::Stationary,
        pocket: None,
        lift: 0.0,
        vz: 0.0,
    }
}

fn open_shot(balls: Vec<BallState>) -> Shot {
    Shot::new(TableKind::Open, balls)
}

/// A 15-ball triangle, apex on the foot spot, rows towards the far end, behind a resting cue
/// ball on the head spot. Each object ball is moved by up to `jitter` metres from its frozen
/// position, on a grid spaced `2R + 2·jitter`, so neighbours never overlap.
fn break_shot(table: TableKind, jitter: f64, rng: &mut SplitMix64) -> Result<Shot, String> {
    let (w, l) = table.size().ok_or("a break needs a pocket table")?;
    let mut balls = vec![ball([w / 2.0, 0.25 * l], [0.0; 2])];
    let spacing = 2.0 * R + 2.0 * jitter;
    let row_step = spacing * 3f64.sqrt() / 2.0;
    let (cx, fy) = (w / 2.0, 0.75 * l);
    for row in 0..5 {
        for k in 0..=row {
            let x = cx + (k as f64 - row as f64 / 2.0) * spacing;
            let y = fy + row as f64 * row_step;
            let (dx, dy) = if jitter > 0.0 {
                // An angle in [0, 2π): the bits of `lo + (hi - lo) * u` with lo = 0.
                let a = 2.0 * std::f64::consts::PI * rng.unit();
                let r = jitter * rng.unit().sqrt();
                (r * libm::cos(a), r * libm::sin(a))
            } else {
                (0.0, 0.0)
            };
            balls.push(ball([x + dx, y + dy], [0.0; 2]));
        }
    }
    Ok(Shot {
        table,
        ..open_shot(balls)
    })
}
