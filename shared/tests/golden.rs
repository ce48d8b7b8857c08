//! Golden hashes: a fixed set of shots whose event count and state hash are committed in
//! `tests/golden/hashes.txt`. Any change of a single bit in any result fails this test, in
//! debug and in release builds alike.
//!
//! The handshake's reference shots (one per mechanism) and the physics fingerprint made of
//! them are among the entries, so a physics change that moves the fingerprint shows here.
//!
//! After a deliberate change to the physics, regenerate the file and review what changed:
//!
//! ```sh
//! BREAKSHOT_BLESS=1 cargo test -p breakshot-shared --test golden
//! ```

mod common;

use std::collections::BTreeMap;
use std::path::PathBuf;

use breakshot_shared::hash::hash_hex;
use breakshot_shared::physics::{simulate, Shot, Strike, TableKind};
use breakshot_shared::protocol::{reference_hash, reference_shots};
use breakshot_shared::scene::Scene;
use common::*;
use glam::DVec2;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Every golden shot, by name.
fn shots() -> Vec<(String, Shot)> {
    let mut shots = Vec::new();
    for name in [
        "center_hit_open",
        "stun_shot_open",
        "half_ball_rolling_open",
        "break_8ball_7ft",
        "snooker_break",
    ] {
        let text = std::fs::read_to_string(dir().join(format!("{name}.json"))).expect("scene file");
        let scene = Scene::from_json(&text).expect("valid scene");
        shots.push((name.to_string(), scene.to_shot().expect("valid")));
    }
    // A frozen five-ball cradle.
    let mut cradle = vec![ball([0.0, 0.0], [0.0, 2.0], [0.0; 3])];
    for k in 1..=5 {
        cradle.push(ball([0.0, k as f64 * 2.0 * R], [0.0; 2], [0.0; 3]));
    }
    shots.push(("cradle_5_frozen".into(), open_shot(cradle)));
    // Breaks with a real cue strike: frozen and gapped racks, 9 ft, with side and draw.
    for (name, jitter, speed, tip) in [
        ("break_9ft_frozen", 0.0, 8.0, (0.0, 0.0)),
        ("break_9ft_gapped", 1e-4, 11.0, (0.1, -0.2)),
    ] {
        let mut rng = Rng::new(42);
        let mut shot = break_shot(TableKind::NineFoot, jitter, 0.0, 0.0, &mut rng);
        shot.balls[0].vel = DVec2::ZERO;
        shot.strike = Some((0, Strike::at_angle(speed, 90.3, DVec2::new(tip.0, tip.1))));
        shots.push((name.into(), shot));
    }
    // A cushion shot with english on an 8 ft table.
    let mut rail = open_shot(vec![ball([0.3, 0.4], [0.0; 2], [0.0; 3])]);
    rail.table = TableKind::EightFoot;
    rail.strike = Some((0, Strike::at_angle(3.0, 63.0, DVec2::new(-0.3, 0.2))));
    shots.push(("cushions_english_8ft".into(), rail));
    // A massé around a blocker and a jump over one, on a 9 ft table (cue elevation).
    let blocker = |y: f64| ball([0.635, y], [0.0; 2], [0.0; 3]);
    let mut masse = open_shot(vec![ball([0.6, 0.5], [0.0; 2], [0.0; 3]), blocker(0.9)]);
    masse.table = TableKind::NineFoot;
    let strike = Strike::at_angle(2.5, 88.0, DVec2::new(0.35, 0.1)).elevated(70.0);
    shots.push(("masse_9ft".into(), masse.struck(0, strike)));
    let mut jump = open_shot(vec![ball([0.635, 0.4], [0.0; 2], [0.0; 3]), blocker(1.09)]);
    jump.table = TableKind::NineFoot;
    let strike = Strike::at_angle(4.0, 90.0, DVec2::new(0.0, -0.1)).elevated(45.0);
    shots.push(("jump_9ft".into(), jump.struck(0, strike)));
    // The handshake's reference shots, one per mechanism (see protocol::reference): the
    // physics fingerprint is made of exactly these.
    for reference in reference_shots() {
        shots.push((format!("reference_{}", reference.name), reference.shot));
    }
    shots
}

fn read_expected() -> BTreeMap<String, (usize, String)> {
    let text = std::fs::read_to_string(dir().join("hashes.txt")).unwrap_or_default();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let parts: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(parts.len(), 3, "bad line in hashes.txt: {l}");
            (
                parts[0].to_string(),
                (parts[1].parse().expect("event count"), parts[2].to_string()),
            )
        })
        .collect()
}

#[test]
fn golden_hashes_hold() {
    let mut actual: BTreeMap<String, (usize, String)> = shots()
        .into_iter()
        .map(|(name, shot)| {
            let out = simulate(&shot).expect("simulates");
            (name, (out.events.len(), hash_hex(out.hash())))
        })
        .collect();
    // The fingerprint itself (no events of its own), so a change of it is reviewed here too.
    let fingerprint = reference_hash().expect("the reference shots simulate");
    actual.insert("physics_fingerprint".into(), (0, hash_hex(fingerprint)));
    let expected = read_expected();
    let mut changes = Vec::new();
    for (name, got) in &actual {
        match expected.get(name) {
            Some(want) if want == got => {}
            Some(want) => changes.push(format!(
                "{name}: {} events {} -> {} events {}",
                want.0, want.1, got.0, got.1
            )),
            None => changes.push(format!("{name}: new, {} events {}", got.0, got.1)),
        }
    }
    for name in expected.keys().filter(|n| !actual.contains_key(*n)) {
        changes.push(format!("{name}: removed"));
    }
    if std::env::var_os("BREAKSHOT_BLESS").is_some() {
        let mut text = String::from(
            "# name events hash — regenerate with BREAKSHOT_BLESS=1 (see golden.rs)\n",
        );
        for (name, (events, hash)) in &actual {
            text.push_str(&format!("{name} {events} {hash}\n"));
        }
        std::fs::write(dir().join("hashes.txt"), text).expect("write hashes.txt");
        for c in &changes {
            println!("changed: {c}");
        }
        return;
    }
    assert!(
        changes.is_empty(),
        "golden hashes changed:\n{}",
        changes.join("\n")
    );
}
