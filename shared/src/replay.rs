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
//! Versions: 1 had level strikes only; 2 adds the cue elevation to every strike; 3 adds the
//! players' names, the physics the game was played with (the build's physics fingerprint,
//! [`crate::protocol::reference_hash`]) and a chain of hashes over the entries. Records of
//! versions 1 and 2 still decode (see `replay/v1.rs`, `replay/v2.rs`), as current records
//! with no names and no physics named. They replay and verify as long as this build's
//! physics plays their shots as the build that wrote them did; once a physics change moves
//! one, replaying says so ([`ReplayError::UnnamedPhysics`]), and nothing more can be checked
//! (they keep no chain of hashes of their own).
//!
//! A record played with other physics than this build's (an older build, before a change
//! that moved a bit) cannot be re-simulated to its hashes. [`GameRecord::verify`] then says
//! so ("recorded with physics N; this build plays M") and checks instead that the record is
//! whole as stored: each entry's `chain` is the hash of the previous one's (or of the header,
//! for the first) and of the entry itself, so a changed, dropped or reordered entry, header
//! or name is found without the physics.

mod v1;
mod v2;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::hash::{chain_hash, hash_hex};
use crate::protocol::reference_hash;
use crate::rules::{Command, Game, RuleError, Seat, Settings, Variant};

/// Version of the record format this build writes.
pub const RECORD_VERSION: u32 = 3;
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
    /// The chain of hashes up to this entry: [`chain_hash`] of the previous entry's chain
    /// (the header's digest for the first) and of this entry's seat, command and hash.
    /// Written by [`GameRecord::push`]; checked by [`GameRecord::check_chain`].
    pub chain: u64,
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
    /// The players' names, seats A and B, as they gave them; `None` for a seat nobody took
    /// (and in records of formats before 3, which kept no names).
    pub players: [Option<String>; 2],
    /// The physics the game was played with: the recording build's physics fingerprint
    /// ([`reference_hash`]); `None` in records of formats before 3.
    pub physics: Option<u64>,
    /// Every applied command, in order.
    pub entries: Vec<RecordEntry>,
}

/// What [`GameRecord::verify`] found.
#[derive(Clone, Debug, PartialEq)]
pub enum Verified {
    /// Every command replayed to its recorded hash; the game as it ends.
    Replayed(Box<Game>),
    /// Recorded with other physics than this build's, and not reproduced by it: the record
    /// was checked whole as stored (its chain of hashes), not re-simulated.
    OtherPhysics {
        /// The physics fingerprint the record names.
        recorded: u64,
        /// This build's.
        this_build: u64,
        /// The first entry this build's physics replays differently.
        differs_at: usize,
    },
}

impl Verified {
    /// A line for a person: what was checked.
    pub fn describe(&self) -> String {
        match self {
            Verified::Replayed(_) => "every shot replayed to its recorded hash".into(),
            Verified::OtherPhysics {
                recorded,
                this_build,
                differs_at,
            } => format!(
                "recorded with physics {}; this build plays {}: from entry {differs_at} its \
                 shots play differently here, so the record's chain of hashes was checked as \
                 stored instead of re-simulated",
                hash_hex(*recorded),
                hash_hex(*this_build)
            ),
        }
    }
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
    /// An entry's chain of hashes is not what its header and entries give: the record was
    /// changed, cut or reordered after it was written.
    #[error("entry {entry}: the chain of hashes is broken (the record was changed after it was written)")]
    ChainBroken {
        /// The first entry whose chain differs, from 0.
        entry: usize,
    },
    /// The record names other physics than this build's, and a shot replays differently:
    /// the game cannot be played again here (see [`GameRecord::verify`]).
    #[error("recorded with physics {}; this build plays {}: entry {entry} replays differently",
        hash_hex(*.recorded), hash_hex(*.this_build))]
    OtherPhysics {
        /// The first entry that replays differently, from 0.
        entry: usize,
        /// The physics fingerprint the record names.
        recorded: u64,
        /// This build's.
        this_build: u64,
    },
    /// A record of an older format, which does not name the physics it was played with, has
    /// a shot this build plays differently: played with older physics, most likely, so it
    /// cannot be checked further here (those formats keep no chain of hashes either).
    #[error("entry {entry} replays differently, and the record (of a format before records named their physics) does not say which physics played it; this build plays {}",
        hash_hex(*.this_build))]
    UnnamedPhysics {
        /// The first entry that replays differently, from 0.
        entry: usize,
        /// This build's physics fingerprint.
        this_build: u64,
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
            ReplayError::Rejected { entry, .. }
            | ReplayError::HashMismatch { entry, .. }
            | ReplayError::ChainBroken { entry }
            | ReplayError::OtherPhysics { entry, .. }
            | ReplayError::UnnamedPhysics { entry, .. } => Some(*entry),
        }
    }
}

fn show(hash: Option<u64>) -> String {
    hash.map_or_else(|| "none".into(), hash_hex)
}

/// The bytes of an entry the chain covers: its seat, command and hash.
fn entry_body(seat: Seat, command: &Command, hash: Option<u64>) -> Vec<u8> {
    encode_any(&(seat, command, hash))
}

/// bincode's standard encoding of `value` (these types always encode).
fn encode_any<T: Serialize>(value: &T) -> Vec<u8> {
    bincode::serde::encode_to_vec(value, bincode::config::standard()).unwrap_or_default()
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
    /// An entry of an older format, its chain still to be written ([`GameRecord::rechain`]).
    fn unchained(seat: Seat, command: Command, hash: Option<u64>) -> RecordEntry {
        RecordEntry {
            seat,
            command,
            hash,
            chain: 0,
        }
    }

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
            v2::VERSION => decode_whole::<v2::EntryV2>(bytes).map(RecordEntry::from),
            v1::VERSION => decode_whole::<v1::EntryV1>(bytes).map(RecordEntry::from),
            other => Err(RecordError::Version(other)),
        }
    }
}

impl GameRecord {
    /// An empty record of a game about to start with this build's physics, its players not
    /// named yet ([`GameRecord::name_player`]).
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> GameRecord {
        GameRecord {
            version: RECORD_VERSION,
            variant,
            settings,
            seed,
            players: [None, None],
            physics: reference_hash().ok(),
            entries: Vec::new(),
        }
    }

    /// Names the player of `seat`. The names are part of the header the chain of hashes
    /// starts from, so a record with entries has its chain written again.
    pub fn name_player(&mut self, seat: Seat, name: &str) {
        self.players[seat.index()] = Some(name.to_string());
        self.rechain();
    }

    /// The header's digest, where the chain of hashes starts: every field but the entries.
    fn header_digest(&self) -> u64 {
        let header = (
            self.version,
            self.variant,
            self.settings,
            self.seed,
            &self.players,
            self.physics,
        );
        chain_hash(0, &encode_any(&header))
    }

    /// A record of an older format in today's, its chain written: the older formats kept
    /// neither the players' names nor the physics (the table's defaults played them).
    fn upgraded(
        variant: Variant,
        settings: Settings,
        seed: u64,
        entries: impl IntoIterator<Item = RecordEntry>,
    ) -> GameRecord {
        let mut record = GameRecord {
            version: RECORD_VERSION,
            variant,
            settings,
            seed,
            players: [None, None],
            physics: None,
            entries: entries.into_iter().collect(),
        };
        record.rechain();
        record
    }

    /// Writes every entry's chain from the header on (after a change to the header, or for a
    /// record converted from an older format).
    pub fn rechain(&mut self) {
        let mut prev = self.header_digest();
        for e in &mut self.entries {
            e.chain = chain_hash(prev, &entry_body(e.seat, &e.command, e.hash));
            prev = e.chain;
        }
    }

    /// Checks the chain of hashes: every entry's chain follows from the header and the
    /// entries before it. Needs no physics.
    pub fn check_chain(&self) -> Result<(), ReplayError> {
        let mut prev = self.header_digest();
        for (entry, e) in self.entries.iter().enumerate() {
            let chain = chain_hash(prev, &entry_body(e.seat, &e.command, e.hash));
            if chain != e.chain {
                return Err(ReplayError::ChainBroken { entry });
            }
            prev = chain;
        }
        Ok(())
    }

    /// Checks the record as far as this build can: replays it with every hash checked; if it
    /// was recorded with other physics and a shot plays differently here, checks its chain of
    /// hashes instead and says so ([`Verified::OtherPhysics`]).
    pub fn verify(&self) -> Result<Verified, ReplayError> {
        match self.replay() {
            Ok(game) => Ok(Verified::Replayed(Box::new(game))),
            Err(ReplayError::OtherPhysics {
                entry,
                recorded,
                this_build,
            }) => {
                self.check_chain()?;
                Ok(Verified::OtherPhysics {
                    recorded,
                    this_build,
                    differs_at: entry,
                })
            }
            Err(e) => Err(e),
        }
    }

    /// The record of `game`'s start (its variant, settings and seed).
    pub fn of(game: &Game) -> GameRecord {
        GameRecord::new(game.variant(), game.settings(), game.seed())
    }

    /// Appends an applied command and the hash of the shot it played, chained to the entry
    /// before it.
    pub fn push(&mut self, seat: Seat, command: Command, hash: Option<u64>) {
        let prev = self
            .entries
            .last()
            .map_or_else(|| self.header_digest(), |e| e.chain);
        let chain = chain_hash(prev, &entry_body(seat, &command, hash));
        self.entries.push(RecordEntry {
            seat,
            command,
            hash,
            chain,
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
            v2::VERSION => decode_whole::<v2::RecordV2>(bytes).map(GameRecord::from),
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
                if let Ok(this_build) = reference_hash() {
                    match self.physics {
                        Some(recorded) if recorded != this_build => {
                            return Err(ReplayError::OtherPhysics {
                                entry: i,
                                recorded,
                                this_build,
                            });
                        }
                        None => {
                            return Err(ReplayError::UnnamedPhysics {
                                entry: i,
                                this_build,
                            })
                        }
                        Some(_) => {}
                    }
                }
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
