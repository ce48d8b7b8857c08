//! Game records: the rules variant, settings and rack seed of a game, and every command
//! applied to it with the state hash its shot produced. Because the physics and the rules are
//! deterministic, a record is the whole game: [`GameRecord::replay`] plays it again and checks
//! every hash, which is how replays are verified and how a stored game is restored.
//!
//! Encoding: bincode 2 (standard configuration: little-endian, variable-length integers) of
//! the record, whose first field is the format version. Decoding reads the version first, so
//! a record from another version is refused by name rather than misread, and is limited to
//! [`MAX_RECORD_BYTES`] so a hostile length prefix cannot make it allocate without bound.
//!
//! Versions: 1 had level strikes only; 2 adds the cue elevation to every strike. Records of
//! version 1 still decode (see `replay/v1.rs`), as current records with θ = 0, and replay and verify
//! as they did.

mod v1;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::hash::hash_hex;
use crate::rules::{Command, Game, RuleError, Seat, Settings, Variant};

/// Version of the record format this build writes.
pub const RECORD_VERSION: u32 = 2;
/// The oldest version this build still reads.
pub const OLDEST_RECORD_VERSION: u32 = v1::VERSION;
/// Largest encoded record accepted (4 MiB). A command takes well under 100 bytes, so this
/// holds tens of thousands of commands, far beyond any real game.
pub const MAX_RECORD_BYTES: usize = 1 << 22;

/// One applied command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RecordEntry {
    /// The seat the command was applied for.
    pub seat: Seat,
    /// The command as applied (a shot's aim normalised).
    pub command: Command,
    /// The state hash of the shot the command played (`ShotReport::hash`), `None` for
    /// commands that play no shot.
    pub hash: Option<u64>,
}

/// A whole game.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GameRecord {
    /// The format version, first in the encoding; [`RECORD_VERSION`] once decoded.
    pub version: u32,
    /// The game played.
    pub variant: Variant,
    /// The game's settings, as [`Game::settings`] gives them.
    pub settings: Settings,
    /// The rack seed the game started from ([`Game::seed`]).
    pub seed: u64,
    /// Every applied command, in order.
    pub entries: Vec<RecordEntry>,
}

/// Why bytes are not a record.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum RecordError {
    /// More than [`MAX_RECORD_BYTES`] bytes.
    #[error("record is larger than {MAX_RECORD_BYTES} bytes")]
    TooLarge,
    /// A format version this build does not read (outside
    /// [`OLDEST_RECORD_VERSION`]..=[`RECORD_VERSION`]).
    #[error("record format version {0} is not supported (this build reads {OLDEST_RECORD_VERSION} to {RECORD_VERSION})")]
    Version(u32),
    /// bincode could not decode the bytes; holds its error.
    #[error("record is malformed: {0}")]
    Malformed(String),
    /// This many bytes follow the end of the record.
    #[error("record has {0} unexpected bytes after its end")]
    TrailingBytes(usize),
}

/// Why a record does not replay.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum ReplayError {
    /// The record is not in the current format (decode it with [`GameRecord::decode`]).
    #[error("record format version {0} is not supported (this build reads {RECORD_VERSION})")]
    Version(u32),
    /// The rules refused a recorded command.
    #[error("entry {entry} ({seat:?}): the rules refuse the command: {error}")]
    Rejected {
        /// The entry's index, from 0.
        entry: usize,
        /// The seat it was recorded for.
        seat: Seat,
        /// Why the rules refused it.
        error: RuleError,
    },
    /// A command replayed to a different shot hash than recorded (or played a shot where
    /// none was recorded, or none where one was): the physics or the rules differ.
    #[error("entry {entry}: the state hash differs (recorded {}, replayed {})",
        show(*.recorded), show(*.replayed))]
    HashMismatch {
        /// The entry's index, from 0.
        entry: usize,
        /// The hash in the record; `None` for a command that played no shot.
        recorded: Option<u64>,
        /// The hash the replay gave; `None` if it played no shot.
        replayed: Option<u64>,
    },
}

impl ReplayError {
    /// The index of the entry that failed (None for a record that cannot be replayed at all).
    pub fn entry(&self) -> Option<usize> {
        match self {
            ReplayError::Version(_) => None,
            ReplayError::Rejected { entry, .. } | ReplayError::HashMismatch { entry, .. } => {
                Some(*entry)
            }
        }
    }
}

fn show(hash: Option<u64>) -> String {
    hash.map_or_else(|| "none".into(), hash_hex)
}

fn config() -> impl bincode::config::Config {
    bincode::config::standard().with_limit::<MAX_RECORD_BYTES>()
}

/// Decodes all of `bytes` as one `T`, within the size limit.
fn decode_whole<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, RecordError> {
    if bytes.len() > MAX_RECORD_BYTES {
        return Err(RecordError::TooLarge);
    }
    let (value, used): (T, usize) = bincode::serde::decode_from_slice(bytes, config())
        .map_err(|e| RecordError::Malformed(e.to_string()))?;
    if used != bytes.len() {
        return Err(RecordError::TrailingBytes(bytes.len() - used));
    }
    Ok(value)
}

/// The format version an encoded record was written in (its first field), if this build
/// reads it.
pub fn format_version(bytes: &[u8]) -> Result<u32, RecordError> {
    if bytes.len() > MAX_RECORD_BYTES {
        return Err(RecordError::TooLarge);
    }
    let (version, _): (u32, usize) = bincode::decode_from_slice(bytes, config())
        .map_err(|e| RecordError::Malformed(e.to_string()))?;
    if !(OLDEST_RECORD_VERSION..=RECORD_VERSION).contains(&version) {
        return Err(RecordError::Version(version));
    }
    Ok(version)
}

impl RecordEntry {
    /// One entry on its own (a store keeps a game as its header, the record with no entries,
    /// followed by one row per entry), in the record's encoding.
    pub fn encode(&self) -> Vec<u8> {
        // As for a whole record: these types always encode.
        bincode::serde::encode_to_vec(self, bincode::config::standard()).unwrap_or_default()
    }

    /// An entry written in the current format.
    pub fn decode(bytes: &[u8]) -> Result<RecordEntry, RecordError> {
        RecordEntry::decode_version(bytes, RECORD_VERSION)
    }

    /// An entry written in format `version` (an entry carries no version of its own: it is
    /// its game's header's, [`format_version`]).
    pub fn decode_version(bytes: &[u8], version: u32) -> Result<RecordEntry, RecordError> {
        match version {
            RECORD_VERSION => decode_whole(bytes),
            v1::VERSION => decode_whole::<v1::EntryV1>(bytes).map(RecordEntry::from),
            other => Err(RecordError::Version(other)),
        }
    }
}

impl GameRecord {
    /// An empty record of a game about to start.
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> GameRecord {
        GameRecord {
            version: RECORD_VERSION,
            variant,
            settings,
            seed,
            entries: Vec::new(),
        }
    }

    /// The record of `game`'s start (its variant, settings and seed).
    pub fn of(game: &Game) -> GameRecord {
        GameRecord::new(game.variant(), game.settings(), game.seed())
    }

    /// Appends an applied command and the hash of the shot it played.
    pub fn push(&mut self, seat: Seat, command: Command, hash: Option<u64>) {
        self.entries.push(RecordEntry {
            seat,
            command,
            hash,
        });
    }

    /// The record in its encoding, its version first ([`GameRecord::decode`] reads it back).
    pub fn encode(&self) -> Vec<u8> {
        // Encoding into a Vec only fails for types serde cannot express in bincode, which
        // these are not; an empty result would then be refused by `decode`.
        bincode::serde::encode_to_vec(self, bincode::config::standard()).unwrap_or_default()
    }

    /// A record of any version this build reads, in the current format: a record of an
    /// older version comes back as its current equivalent (version [`RECORD_VERSION`]).
    pub fn decode(bytes: &[u8]) -> Result<GameRecord, RecordError> {
        match format_version(bytes)? {
            v1::VERSION => decode_whole::<v1::RecordV1>(bytes).map(GameRecord::from),
            _ => decode_whole(bytes),
        }
    }

    /// Plays the record again from its seed, checking that every command is accepted and
    /// every shot ends with the recorded hash. Returns the game at the end, or names the
    /// first entry that differs.
    pub fn replay(&self) -> Result<Game, ReplayError> {
        if self.version != RECORD_VERSION {
            return Err(ReplayError::Version(self.version));
        }
        let mut game = Game::new(self.variant, self.settings, self.seed);
        for (i, e) in self.entries.iter().enumerate() {
            let verdict =
                game.apply(e.seat, &e.command)
                    .map_err(|error| ReplayError::Rejected {
                        entry: i,
                        seat: e.seat,
                        error,
                    })?;
            let replayed = verdict.shot.map(|s| s.hash);
            if replayed != e.hash {
                return Err(ReplayError::HashMismatch {
                    entry: i,
                    recorded: e.hash,
                    replayed,
                });
            }
        }
        Ok(game)
    }
}
