//! Records of format version 1, written before strikes carried a cue elevation: every strike
//! was level. They are read with this copy of that layout and turned into current records
//! whose strikes have θ = 0, which play exactly as they did (a level strike is the same
//! physics in both versions), so their hashes still verify.
//!
//! bincode writes an enum's variant by its index and a struct's fields in order, so these
//! types mirror version 1 variant for variant and field for field. They are frozen: a later
//! change to [`Command`] is a new format version, not an edit here.

use glam::DVec2;
use serde::Deserialize;

use super::{GameRecord, RecordEntry};
use crate::physics::Strike;
use crate::rules::{Choice, Command, Seat, Settings, Variant};

/// The version this module reads.
pub(super) const VERSION: u32 = 1;

#[derive(Deserialize)]
struct LevelStrike {
    speed: f64,
    dir: DVec2,
    tip: DVec2,
}

#[derive(Deserialize)]
enum CommandV1 {
    Shot {
        strike: LevelStrike,
        call: Option<u8>,
    },
    PlaceCueBall {
        pos: [f64; 2],
    },
    Decide(Choice),
    TimeExpired,
    Concede,
    ProposeStalemate,
    PlaceBall {
        ball: u8,
        pos: Option<[f64; 2]>,
    },
    LoadLayout {
        balls: Vec<Option<[f64; 2]>>,
    },
    Forfeit,
}

#[derive(Deserialize)]
pub(super) struct EntryV1 {
    seat: Seat,
    command: CommandV1,
    hash: Option<u64>,
}

#[derive(Deserialize)]
pub(super) struct RecordV1 {
    // Read by `GameRecord::decode` before the rest; kept for the layout.
    _version: u32,
    variant: Variant,
    settings: Settings,
    seed: u64,
    entries: Vec<EntryV1>,
}

impl From<CommandV1> for Command {
    fn from(c: CommandV1) -> Command {
        match c {
            CommandV1::Shot { strike, call } => Command::Shot {
                strike: Strike {
                    speed: strike.speed,
                    dir: strike.dir,
                    tip: strike.tip,
                    elevation_deg: 0.0,
                },
                call,
            },
            CommandV1::PlaceCueBall { pos } => Command::PlaceCueBall { pos },
            CommandV1::Decide(choice) => Command::Decide(choice),
            CommandV1::TimeExpired => Command::TimeExpired,
            CommandV1::Concede => Command::Concede,
            CommandV1::ProposeStalemate => Command::ProposeStalemate,
            CommandV1::PlaceBall { ball, pos } => Command::PlaceBall { ball, pos },
            CommandV1::LoadLayout { balls } => Command::LoadLayout { balls },
            CommandV1::Forfeit => Command::Forfeit,
        }
    }
}

impl From<EntryV1> for RecordEntry {
    fn from(e: EntryV1) -> RecordEntry {
        RecordEntry::unchained(e.seat, e.command.into(), e.hash)
    }
}

impl From<RecordV1> for GameRecord {
    fn from(r: RecordV1) -> GameRecord {
        let entries = r.entries.into_iter().map(RecordEntry::from);
        GameRecord::upgraded(r.variant, r.settings, r.seed, entries)
    }
}
