//! Records outlive physics changes: a record names the physics it was played with, keeps its
//! players' names, and one recorded with other physics still verifies, by its chain of hashes
//! as stored, with a clear statement of the two physics.
//!
//! The fixtures are real records, written by [`write_fixture`]:
//! - `record_v3_this_physics.bin` by the build that added it: after any later change that
//!   moves one of its shots it is a record of older physics, and the test checks it so;
//! - `record_v3_other_physics.bin` by this build with one deliberate physics change (the
//!   ball–ball restitution `e_ball` at 0.94 instead of 0.95), so its every shot plays
//!   differently here.
//!
//! To write one again: `BREAKSHOT_WRITE_RECORD=FILE cargo test -p breakshot-shared --test
//! record_physics write_fixture`.

mod player;

use breakshot_shared::protocol::reference_hash;
use breakshot_shared::replay::{GameRecord, ReplayError, Verified};
use breakshot_shared::rules::{Game, Seat, Settings, Variant};
use player::{play, Dice};

const THIS_PHYSICS: &[u8] = include_bytes!("fixtures/record_v3_this_physics.bin");
const OTHER_PHYSICS: &[u8] = include_bytes!("fixtures/record_v3_other_physics.bin");

/// A 9-ball game of random legal play between ann and ben, recorded.
fn named_game() -> GameRecord {
    let mut game = Game::new(Variant::NineBall, Settings::online(), 11);
    let mut record = GameRecord::of(&game);
    record.name_player(Seat::A, "ann");
    record.name_player(Seat::B, "ben");
    let played = play(&mut game, &mut Dice::new(11), 30);
    for (seat, cmd, verdict) in played.log {
        record.push(seat, cmd, verdict.shot.map(|s| s.hash));
    }
    record
}

/// Writes [`named_game`] to the file `BREAKSHOT_WRITE_RECORD` names; does nothing otherwise.
#[test]
fn write_fixture() {
    let Some(path) = std::env::var_os("BREAKSHOT_WRITE_RECORD") else {
        return;
    };
    std::fs::write(path, named_game().encode()).expect("writing the fixture");
}

fn names(record: &GameRecord) -> [Option<&str>; 2] {
    [record.players[0].as_deref(), record.players[1].as_deref()]
}

#[test]
fn a_record_names_its_physics_and_its_players_and_round_trips() {
    let record = named_game();
    assert_eq!(record.physics, Some(reference_hash().unwrap()));
    assert_eq!(names(&record), [Some("ann"), Some("ben")]);
    let back = GameRecord::decode(&record.encode()).unwrap();
    assert_eq!(back, record);
    assert!(matches!(back.verify(), Ok(Verified::Replayed(_))));
}

#[test]
fn a_record_of_other_physics_verifies_by_its_chain_and_says_so() {
    let record = GameRecord::decode(OTHER_PHYSICS).unwrap();
    let this_build = reference_hash().unwrap();
    let recorded = record.physics.expect("the fixture names its physics");
    assert_ne!(
        recorded, this_build,
        "the fixture was made with other physics"
    );
    assert_eq!(names(&record), [Some("ann"), Some("ben")]);
    assert!(record.entries.len() > 5);

    // Replaying it here fails on its first shot, naming both physics.
    let failed = record.replay().unwrap_err();
    assert!(
        matches!(failed, ReplayError::OtherPhysics { recorded: r, this_build: b, .. } if r == recorded && b == this_build),
        "{failed:?}"
    );
    // Verification says so and checks the record whole instead.
    let verified = record.verify().unwrap();
    let line = verified.describe();
    assert!(
        matches!(verified, Verified::OtherPhysics { .. }),
        "{verified:?}"
    );
    assert!(
        line.contains(&format!(
            "recorded with physics {recorded:016x}; this build plays {this_build:016x}"
        )),
        "{line}"
    );

    // A record changed after it was written is caught without the physics: a shot's hash,
    // a name, or an entry left out.
    let mut tampered = record.clone();
    let k = tampered
        .entries
        .iter()
        .position(|e| e.hash.is_some())
        .unwrap();
    tampered.entries[k].hash = tampered.entries[k].hash.map(|h| h ^ 1);
    assert_eq!(
        tampered.verify(),
        Err(ReplayError::ChainBroken { entry: k })
    );
    let mut renamed = record.clone();
    renamed.players[1] = Some("eve".into());
    assert_eq!(renamed.verify(), Err(ReplayError::ChainBroken { entry: 0 }));
    let mut cut = record.clone();
    cut.entries.remove(1);
    assert_eq!(cut.verify(), Err(ReplayError::ChainBroken { entry: 1 }));
}

#[test]
fn a_record_of_this_builds_physics_replays_and_one_from_before_a_change_verifies() {
    let record = GameRecord::decode(THIS_PHYSICS).unwrap();
    assert_eq!(names(&record), [Some("ann"), Some("ben")]);
    let recorded = record.physics.expect("the fixture names its physics");
    match record.verify() {
        // Made by this build's physics: every shot replays to its hash.
        Ok(Verified::Replayed(_)) => {}
        // Made before a physics change that moved one of its shots: verified by its chain.
        Ok(Verified::OtherPhysics { this_build, .. }) => {
            assert_ne!(recorded, this_build);
            assert_eq!(this_build, reference_hash().unwrap());
        }
        Err(e) => panic!("{e}"),
    }
    assert_eq!(record.check_chain(), Ok(()));
}
