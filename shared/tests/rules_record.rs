//! Game records: encoding round trip, re-simulation, and tamper detection.

mod player;

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::reference_hash;
use breakshot_shared::replay::{
    GameRecord, RecordError, ReplayError, MAX_RECORD_BYTES, RECORD_VERSION,
};
use breakshot_shared::rules::{
    Choice, Command, EightBallRules, Game, RuleError, Seat, Settings, Variant,
};
use glam::DVec2;
use player::{play, Dice};

/// A game of random legal play and its record.
fn recorded_game(variant: Variant, seed: u64) -> (Game, GameRecord) {
    let mut game = Game::new(variant, Settings::online(), seed);
    let mut record = GameRecord::of(&game);
    let played = play(&mut game, &mut Dice::new(seed), 60);
    for (seat, cmd, verdict) in played.log {
        record.push(seat, cmd, verdict.shot.map(|s| s.hash));
    }
    assert!(record.entries.len() > 5, "too short a game to test");
    (game, record)
}

fn games() -> Vec<(Game, GameRecord)> {
    vec![
        recorded_game(Variant::EightBall(EightBallRules::Wpa), 2),
        recorded_game(Variant::NineBall, 2),
    ]
}

#[test]
fn record_round_trips_through_its_encoding() {
    for (_, record) in games() {
        let bytes = record.encode();
        assert_eq!(GameRecord::decode(&bytes), Ok(record));
    }
}

#[test]
fn replaying_a_record_reproduces_every_hash_and_the_game() {
    for (game, record) in games() {
        let decoded = GameRecord::decode(&record.encode()).unwrap();
        let replayed = decoded.replay().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(replayed, game);
    }
}

fn first_shot(record: &GameRecord, from: usize) -> usize {
    (from..record.entries.len())
        .find(|&i| matches!(record.entries[i].command, Command::Shot { .. }))
        .expect("a shot")
}

#[test]
fn a_changed_shot_fails_replay_at_that_entry() {
    let (_, mut record) = recorded_game(Variant::NineBall, 2);
    let k = first_shot(&record, 3);
    if let Command::Shot { strike, .. } = &mut record.entries[k].command {
        strike.speed *= 1.0 + 1e-12;
    }
    let err = record.replay().unwrap_err();
    assert_eq!(err.entry(), Some(k), "{err}");
    assert!(matches!(err, ReplayError::HashMismatch { .. }), "{err}");
    assert!(err
        .to_string()
        .starts_with(&format!("entry {k}: the state hash differs")));
}

#[test]
fn a_changed_hash_fails_replay_at_that_entry() {
    let (_, mut record) = recorded_game(Variant::EightBall(EightBallRules::Wpa), 2);
    let k = first_shot(&record, 2);
    let real = record.entries[k].hash;
    record.entries[k].hash = real.map(|h| h ^ 1);
    assert_eq!(
        record.replay(),
        Err(ReplayError::HashMismatch {
            entry: k,
            recorded: real.map(|h| h ^ 1),
            replayed: real,
        })
    );
}

#[test]
fn a_command_the_rules_refuse_fails_replay_at_that_entry() {
    let (_, mut record) = recorded_game(Variant::NineBall, 2);
    let k = first_shot(&record, 1);
    let seat = record.entries[k].seat.other();
    record.entries[k].seat = seat;
    assert_eq!(
        record.replay(),
        Err(ReplayError::Rejected {
            entry: k,
            seat,
            error: RuleError::NotYourTurn
        })
    );
}

fn small_record() -> GameRecord {
    let mut r = GameRecord::new(Variant::NineBall, Settings::online(), 7);
    // Pinned here, not this build's fingerprint, so the encoding below stays put when the
    // physics moves.
    r.physics = Some(0x0000_5eed_0000_0001);
    r.name_player(Seat::A, "ann");
    r.push(
        Seat::A,
        Command::Shot {
            strike: Strike {
                speed: 1.5,
                dir: DVec2::new(0.0, 1.0),
                tip: DVec2::new(0.0, 0.25),
                elevation_deg: 0.0,
            },
            call: Some(2),
        },
        Some(0x0123_4567_89ab_cdef),
    );
    r.push(Seat::B, Command::Decide(Choice::HandBack), None);
    r.push(Seat::B, Command::PlaceCueBall { pos: [0.5, 0.25] }, None);
    r
}

#[test]
fn record_encoding_is_pinned() {
    // The encoding is the stored format: a change here breaks every stored game, so it must
    // come with a new RECORD_VERSION.
    let hex: String = small_record()
        .encode()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    assert_eq!(hex, GOLDEN);
}

/// [`small_record`] as a record of format 1 or 2 reads back: no names, no physics, its chain
/// written on reading.
fn as_old_format(mut r: GameRecord) -> GameRecord {
    r.players = [None, None];
    r.physics = None;
    r.rechain();
    r
}

/// Version 3, NineBall, online settings (no calls, 60 s clock, 9ft), seed 7, the players
/// (ann in seat A, nobody in seat B), the physics, then three entries each with its link of
/// the chain, all in bincode's standard configuration.
const GOLDEN: &str = "030100013c03070103616e6e0001fd01000000ed5e0000030000000000000000f83f0000000000000000000000000000f03f0000000000000000000000000000d03f0000000000000000010201fdefcdab8967452301fdd8a58d99d39d3ffd01020500fd22cfc5b318f5e54f0101000000000000e03f000000000000d03f00fd95c2ee7d2d9c4d6d";

/// Version 2: the same record with no names, no physics and no chain. The strike is speed,
/// aim, tip and, new in version 2, the elevation (0.0: eight zero bytes after the tip).
const GOLDEN_V2: &str = "020100013c0307030000000000000000f83f0000000000000000000000000000f03f0000000000000000000000000000d03f0000000000000000010201fdefcdab8967452301010205000101000000000000e03f000000000000d03f00";

/// The same record as version 1 wrote it: level strikes, no elevation field.
const GOLDEN_V1: &str = "010100013c0307030000000000000000f83f0000000000000000000000000000f03f0000000000000000000000000000d03f010201fdefcdab8967452301010205000101000000000000e03f000000000000d03f00";

fn unhex(hex: &str) -> Vec<u8> {
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
        .collect()
}

#[test]
fn a_record_of_version_1_decodes_with_level_strikes() {
    assert_eq!(
        GameRecord::decode(&unhex(GOLDEN_V1)),
        Ok(as_old_format(small_record()))
    );
}

#[test]
fn a_record_of_version_2_decodes_with_no_names_and_no_physics() {
    let old = GameRecord::decode(&unhex(GOLDEN_V2)).unwrap();
    assert_eq!(old, as_old_format(small_record()));
    assert_eq!(old.check_chain(), Ok(()));
}

/// A 9-ball game of random legal play (40 commands: shots, fouls, ball in hand), encoded by
/// the build before version 2 (commit 76a5cae), so in version 1.
const OLD_GAME: &[u8] = include_bytes!("fixtures/record_v1_nine_ball.bin");

#[test]
fn a_game_recorded_in_version_1_decodes_and_says_its_physics_is_not_named() {
    assert_eq!(OLD_GAME[0], 1, "the fixture is of version 1");
    let record = GameRecord::decode(OLD_GAME).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(record.version, RECORD_VERSION);
    assert_eq!(record.physics, None);
    let shots: Vec<&Strike> = record
        .entries
        .iter()
        .filter_map(|e| match &e.command {
            Command::Shot { strike, .. } => Some(strike),
            _ => None,
        })
        .collect();
    assert!(shots.len() > 10, "too few shots: {}", shots.len());
    assert!(shots.iter().all(|s| s.elevation_deg == 0.0));
    // Its shots were played by an older physics than this build's (the root solver's
    // change moved the last bits of every break): replaying and verifying say so, naming
    // the first shot, rather than claiming a check that the format cannot give.
    let this_build = reference_hash().unwrap();
    let unnamed = ReplayError::UnnamedPhysics {
        entry: 0,
        this_build,
    };
    assert_eq!(record.replay(), Err(unnamed.clone()));
    assert_eq!(record.verify(), Err(unnamed.clone()));
    assert!(unnamed
        .to_string()
        .contains("does not say which physics played it"));
    // Written again in the current version it reads back the same.
    let again = GameRecord::decode(&record.encode()).unwrap();
    assert_eq!(again, record);
}

#[test]
fn an_elevated_strike_round_trips_through_a_record() {
    let mut r = small_record();
    if let Command::Shot { strike, .. } = &mut r.entries[0].command {
        strike.elevation_deg = 37.5;
    }
    assert_eq!(GameRecord::decode(&r.encode()), Ok(r));
}

#[test]
fn bad_bytes_are_refused_with_a_reason() {
    let bytes = small_record().encode();
    // Truncated.
    assert!(matches!(
        GameRecord::decode(&bytes[..bytes.len() - 3]),
        Err(RecordError::Malformed(_))
    ));
    // Trailing garbage.
    let mut long = bytes.clone();
    long.extend_from_slice(&[0, 0]);
    assert_eq!(
        GameRecord::decode(&long),
        Err(RecordError::TrailingBytes(2))
    );
    // Another version (the version is the first varint: 1 byte below 251).
    let mut other = bytes.clone();
    other[0] = (RECORD_VERSION + 1) as u8;
    assert_eq!(
        GameRecord::decode(&other),
        Err(RecordError::Version(RECORD_VERSION + 1))
    );
    // Too large.
    assert_eq!(
        GameRecord::decode(&vec![0; MAX_RECORD_BYTES + 1]),
        Err(RecordError::TooLarge)
    );
    // A hostile length: version, variant, settings and seed, then a claim of 2^60 entries.
    let header = GameRecord::new(Variant::NineBall, Settings::online(), 7).encode();
    let mut hostile = header[..header.len() - 1].to_vec();
    hostile.push(253); // bincode's marker for a u64 varint
    hostile.extend_from_slice(&(1u64 << 60).to_le_bytes());
    // Refused when the bytes run out, without reserving room for the claimed entries.
    assert!(matches!(
        GameRecord::decode(&hostile),
        Err(RecordError::Malformed(_))
    ));
    assert!(matches!(
        GameRecord::decode(&[]),
        Err(RecordError::Malformed(_))
    ));
}

#[test]
fn a_record_of_another_version_does_not_replay() {
    let mut r = small_record();
    r.version = RECORD_VERSION + 1;
    assert_eq!(
        r.replay().unwrap_err(),
        ReplayError::Version(RECORD_VERSION + 1)
    );
}

#[test]
fn a_game_in_progress_round_trips_through_serde() {
    let (game, _) = recorded_game(Variant::NineBall, 2);
    let config = bincode::config::standard();
    let bytes = bincode::serde::encode_to_vec(&game, config).unwrap();
    let (back, _): (Game, usize) = bincode::serde::decode_from_slice(&bytes, config).unwrap();
    assert_eq!(back, game);
}
