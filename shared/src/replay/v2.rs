//! Records of format version 2: the current commands (strikes with their cue elevation), but
//! no players' names, no physics named and no chain of hashes. They are read with this copy
//! of that layout and turned into current records that name no players and no physics (so
//! they replay and verify as they did), their chain written on conversion.
//!
//! bincode writes a struct's fields in order, so these types mirror version 2 field for
//! field. They are frozen: a later change to [`Command`] is a new format version, and this
//! module then needs its own copy of version 2's `Command`, as `v1.rs` has of version 1's.

use serde::Deserialize;

use super::{GameRecord, RecordEntry};
use crate::rules::{Command, Seat, Settings, Variant};

/// The version this module reads.
pub(super) const VERSION: u32 = 2;

#[derive(Deserialize)]
pub(super) struct EntryV2 {
    seat: Seat,
    command: Command,
    hash: Option<u64>,
}

#[derive(Deserialize)]
pub(super) struct RecordV2 {
    // Read by `GameRecord::decode` before the rest; kept for the layout.
    _version: u32,
    variant: Variant,
    settings: Settings,
    seed: u64,
    entries: Vec<EntryV2>,
}

impl From<EntryV2> for RecordEntry {
    fn from(e: EntryV2) -> RecordEntry {
        RecordEntry::unchained(e.seat, e.command, e.hash)
    }
}

impl From<RecordV2> for GameRecord {
    fn from(r: RecordV2) -> GameRecord {
        let entries = r.entries.into_iter().map(RecordEntry::from);
        GameRecord::upgraded(r.variant, r.settings, r.seed, entries)
    }
}
