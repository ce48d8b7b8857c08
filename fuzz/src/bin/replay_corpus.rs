//! Runs every fuzz target over its seed corpus (`fuzz/corpus/<target>/`) and over a fixed
//! number of deterministic mutations of each seed, with plain stable cargo. It is what CI
//! runs to keep the targets compiling and the seeds passing; real fuzzing uses
//! `cargo fuzz run <target>` (see fuzz/README.md).
//!
//! `replay-corpus [MUTATIONS_PER_SEED]` (default 200); `replay-corpus --write-seeds`
//! (re)writes the generated seeds of the frame, shot and record targets.

use std::path::Path;

type Target = fn(&[u8]);

const TARGETS: [(&str, Target); 4] = [
    ("frame", breakshot_fuzz::frame),
    ("scene", breakshot_fuzz::scene),
    ("shot", breakshot_fuzz::shot),
    ("record", breakshot_fuzz::record),
];

fn main() -> Result<(), String> {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    if std::env::args().nth(1).as_deref() == Some("--write-seeds") {
        return write_seeds(&corpus);
    }
    let mutations: u64 = match std::env::args().nth(1) {
        Some(n) => n.parse().map_err(|_| format!("not a count: {n}"))?,
        None => 200,
    };
    for (name, target) in TARGETS {
        let dir = corpus.join(name);
        let mut seeds = Vec::new();
        for entry in std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))? {
            let path = entry.map_err(|e| e.to_string())?.path();
            seeds.push(std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?);
        }
        let mut runs = 0u64;
        let mut rng = 0x2545_f491_4f6c_dd1du64;
        for seed in &seeds {
            target(seed);
            runs += 1;
            for _ in 0..mutations {
                target(&mutate(seed, &mut rng));
                runs += 1;
            }
        }
        println!("{name}: {} seeds, {runs} inputs, no failure", seeds.len());
    }
    Ok(())
}

/// A copy of `seed` with a few bytes flipped, inserted or cut (xorshift-driven).
fn mutate(seed: &[u8], rng: &mut u64) -> Vec<u8> {
    let mut next = || {
        *rng ^= *rng << 13;
        *rng ^= *rng >> 7;
        *rng ^= *rng << 17;
        *rng
    };
    let mut out = seed.to_vec();
    for _ in 0..1 + next() % 4 {
        let at = (next() as usize) % (out.len() + 1);
        match next() % 4 {
            0 if at < out.len() => out[at] ^= 1 << (next() % 8),
            1 if at < out.len() => out[at] = next() as u8,
            2 => out.insert(at, next() as u8),
            _ if at < out.len() => {
                out.truncate(at);
            }
            _ => out.push(next() as u8),
        }
    }
    out
}

/// Seeds made from real messages, a real game and a real shot, so fuzzing starts from
/// inputs that reach deep into each parser.
fn write_seeds(corpus: &Path) -> Result<(), String> {
    use breakshot_shared::physics::Strike;
    use breakshot_shared::protocol::{
        encode_frame, reference_hash, AimAid, ClientMessage, RoomCode, PROTOCOL_VERSION,
    };
    use breakshot_shared::replay::GameRecord;
    use breakshot_shared::rules::{Command, EightBallRules, Game, Settings, Variant};
    use glam::DVec2;

    let write = |target: &str, name: &str, bytes: &[u8]| -> Result<(), String> {
        let dir = corpus.join(target);
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        std::fs::write(dir.join(name), bytes).map_err(|e| e.to_string())
    };
    let variant = Variant::EightBall(EightBallRules::Wpa);
    let strike = Strike {
        speed: 9.0,
        dir: DVec2::new(0.01, 1.0).normalize(),
        tip: DVec2::new(0.1, -0.2),
        elevation_deg: 0.0,
    };
    let room = RoomCode::parse("K7QX2M4B").map_err(|e| e.to_string())?;
    let messages = [
        (
            "hello",
            ClientMessage::Hello {
                protocol: PROTOCOL_VERSION,
                physics: reference_hash().map_err(|e| e.to_string())?,
                key: vec![7; 32],
            },
        ),
        (
            "prove",
            ClientMessage::Prove {
                signature: vec![9; 64],
            },
        ),
        (
            "create",
            ClientMessage::CreateRoom {
                variant,
                mode: Settings::online(),
                aim_aid: AimAid::Full,
                name: "ann".into(),
            },
        ),
        (
            "join",
            ClientMessage::Join {
                room,
                name: "ben".into(),
            },
        ),
        (
            "shot",
            ClientMessage::Shot {
                turn: 0,
                strike,
                call: Some(3),
            },
        ),
        (
            "masse",
            ClientMessage::Shot {
                turn: 0,
                strike: strike.elevated(60.0),
                call: None,
            },
        ),
        (
            "place",
            ClientMessage::PlaceCueBall {
                turn: 4,
                pos: [0.5, 0.6],
            },
        ),
        (
            "chat",
            ClientMessage::Chat {
                text: "nice shot".into(),
            },
        ),
    ];
    for (name, msg) in &messages {
        let frame = encode_frame(msg).map_err(|e| e.to_string())?;
        write("frame", name, &frame)?;
    }
    // Shot seeds: table, ball count, positions, then the strike's numbers and elevation (a
    // fraction of 90 degrees in two bytes), the game's seed, then a command.
    let mut shot = vec![3u8, 5];
    for (x, y) in [
        (0.5, 0.25),
        (0.5, 0.75),
        (0.48, 0.78),
        (0.52, 0.78),
        (0.2, 0.9),
    ] {
        shot.extend_from_slice(&((x * 65535.0) as u16).to_le_bytes());
        shot.extend_from_slice(&((y * 65535.0) as u16).to_le_bytes());
    }
    for v in [6.0f64, 0.0, 1.0, 0.0, 0.2] {
        shot.extend_from_slice(&v.to_le_bytes());
    }
    let payload = &encode_frame(&messages[3].1).map_err(|e| e.to_string())?[4..];
    for (name, elevation) in [("straight", 0u16), ("jump", u16::MAX / 3)] {
        let numbers = [&elevation.to_le_bytes()[..], &7u64.to_le_bytes()].concat();
        write("shot", name, &[&shot[..], &numbers, payload].concat())?;
    }
    write("shot", "empty", &[])?;
    // A short real game.
    let mut game = Game::new(variant, Settings::offline(), 42);
    let mut record = GameRecord::of(&game);
    for (speed, elevation_deg) in [(9.0, 0.0), (4.0, 30.0), (2.0, 70.0)] {
        let seat = game.to_move();
        let cue = game.balls()[0].pos;
        let target = game.balls()[1].pos;
        let command = Command::Shot {
            strike: Strike {
                speed,
                dir: (target - cue).normalize(),
                tip: DVec2::new(0.2, 0.0),
                elevation_deg,
            },
            call: None,
        };
        match game.apply(seat, &command) {
            Ok(verdict) => record.push(seat, command, verdict.shot.map(|s| s.hash)),
            Err(_) => break,
        }
    }
    write("record", "short-game", &record.encode())?;
    write(
        "record",
        "new-game",
        &GameRecord::of(&Game::new(Variant::NineBall, Settings::online(), 7)).encode(),
    )?;
    Ok(())
}
