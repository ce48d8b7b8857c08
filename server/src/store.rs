//! The game store, with one durability contract and two backends: SQLite in the data
//! directory (the embedded default, no setup) and PostgreSQL (`--store postgres://...`), for
//! a store that lives outside the server's machine.
//!
//! One row per room (its settings and seat token digests), one per game (its header: rules,
//! settings, seed; and, once it is over, its result) and one per accepted command. A command
//! is one appended row, so a write costs the same at the thousandth command as at the first;
//! a game's record is assembled on read. [`Store::apply`] commits a batch in one transaction
//! and returns only once it is durable: the server shows nothing before that.
//!
//! Everything here blocks; the server calls it from its own writer thread, never from an
//! async worker.

use std::path::Path;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::ratings::PlayerRating;
use bincode::config;
use breakshot_shared::protocol::limits::MAX_RECORD;
use breakshot_shared::protocol::PlayerKey;
use breakshot_shared::protocol::RoomCode;
use breakshot_shared::replay::{self, GameRecord, RecordEntry, RecordError, RECORD_VERSION};
use breakshot_shared::rules::Seat;
use thiserror::Error;

use crate::output::{RoomMeta, StoreOp};
use crate::room::ClockLeft;
use crate::secret::TokenDigest;

mod postgres;
mod sqlite;

pub use sqlite::DB_FILE;

/// Why the store failed. On a write the server stops without sending the unstored results.
#[derive(Debug, Error)]
pub enum StoreError {
    /// SQLite failed (for `verify --data`, also: the directory holds no store).
    #[error("database: {0}")]
    Sql(#[from] rusqlite::Error),
    /// PostgreSQL failed, or the connection to it was lost.
    #[error("PostgreSQL: {0}")]
    Postgres(#[from] ::postgres::Error),
    /// A room's stored settings do not decode (or cannot be encoded).
    #[error("room {room}: stored settings are unreadable: {why}")]
    Meta {
        /// The room's code.
        room: String,
        /// The decoder's (or encoder's) message.
        why: String,
    },
    /// A game's header or command rows do not make a record.
    #[error("room {room} game {number}: {why}")]
    Record {
        /// The room's code.
        room: String,
        /// The game's number in the room.
        number: u32,
        /// What is wrong with the record.
        why: RecordError,
    },
    /// The store was made or upgraded by a newer server: run that build (or a newer one).
    #[error("the store's schema version {found} is newer than this build's ({known})")]
    Schema {
        /// The store's schema version.
        found: i64,
        /// The newest version this build knows.
        known: i64,
    },
    /// A `--store` argument that is not a PostgreSQL URL.
    #[error("{0}")]
    Location(String),
    /// A write for a room whose lock another instance holds (two drew one code, say): refused, so
    /// two instances never both store a command of one room.
    #[error("room {0} is owned by another server instance")]
    OwnedElsewhere(String),
}

/// What the store made of a seat token no room on this server knows.
#[derive(Debug)]
pub enum Claim {
    /// The token's room was left unfinished by an instance that is gone: it is this
    /// instance's now, with its latest game to restore.
    Taken(Box<StoredGame>),
    /// The token's room is closed and its last game over.
    Ended(Box<EndedGame>),
    /// Another live instance owns the room.
    Elsewhere,
    /// No unfinished room of another instance has this seat.
    NotFound,
}

/// Where the games are kept.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// SQLite in this directory.
    Sqlite(std::path::PathBuf),
    /// A PostgreSQL database, by its connection URL (`postgres://user@host/db`).
    Postgres(String),
}

impl Location {
    /// A `--store` argument: a `postgres://` or `postgresql://` URL.
    pub fn parse(url: &str) -> Result<Location, StoreError> {
        if url.starts_with("postgres://") || url.starts_with("postgresql://") {
            Ok(Location::Postgres(url.to_string()))
        } else {
            Err(StoreError::Location(format!(
                "{url:?} is not a postgres:// URL (without --store the games are kept in SQLite in the data directory)"
            )))
        }
    }
}

/// One stored game with its room.
#[derive(Debug)]
pub struct StoredGame {
    /// The room as last stored.
    pub meta: RoomMeta,
    /// The game's number in its room, from 1.
    pub number: u32,
    /// The record assembled from the header and the command rows (or why it cannot be).
    pub record: Result<GameRecord, RecordError>,
    /// Whether the game's end is stored (a result, or abandoned).
    pub finished: bool,
    /// The record format its rows are stored in (0 if unreadable): a game of an older
    /// format is written again in the current one before play goes on ([`Store::upgrade`]).
    pub format: u32,
    /// The shot clock of its current turn as last stored, if it has one.
    pub clock: Option<StoredClock>,
    /// A quick-match room's players (seat A's key first): its first game is rated.
    pub rated: Option<[PlayerKey; 2]>,
    /// A room published in the lobby, with its players' keys as far as they are known.
    pub listed: Option<[Option<PlayerKey>; 2]>,
}

/// A game's shot clock as the store last wrote it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoredClock {
    /// The turn it belongs to.
    pub turn: u32,
    /// Milliseconds left when it was written.
    pub left_ms: u64,
    /// Whether it was running then.
    pub running: bool,
    /// When it was written (Unix milliseconds, the store's clock).
    pub at_ms: u64,
}

impl StoredClock {
    /// What is left at `now_ms` (Unix milliseconds): a stopped clock keeps its time; a
    /// running one has lost the time since it was written. A server that was stopped in an
    /// orderly way stopped every clock first (its players' connections closed); one that
    /// crashed cannot say when it stopped, so the time it was down counts as played, and the
    /// returning player still finds at least the room's minimum.
    pub fn left_at(&self, now_ms: u64) -> ClockLeft {
        let ran = if self.running {
            now_ms.saturating_sub(self.at_ms)
        } else {
            0
        };
        ClockLeft {
            turn: self.turn,
            left: Duration::from_millis(self.left_ms.saturating_sub(ran)),
        }
    }
}

/// A stored game that is over, with its room.
#[derive(Clone, Debug)]
pub struct EndedGame {
    /// The room as last stored: whose seats are told the result.
    pub meta: RoomMeta,
    /// The game's number in its room, from 1.
    pub number: u32,
    /// `None` if nobody won (also for a game abandoned before anyone could win).
    pub winner: Option<Seat>,
    /// The readable reason, as `GameOver` gave it.
    pub reason: String,
    /// When the store recorded the end (seconds since the Unix epoch).
    pub at: u64,
}

/// Seconds since the Unix epoch, the store's clock for when games ended.
pub fn unix_now() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

/// Milliseconds since the Unix epoch, the store's clock for shot clocks.
pub fn unix_millis() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
}

/// The game store on one of its backends. Every call blocks: the server uses it from its
/// writer thread (and at start, from a thread of its own).
pub struct Store(Backend);

enum Backend {
    Sqlite(sqlite::SqliteStore),
    // Boxed: a client with its prepared statements is several times a SQLite connection.
    Postgres(Box<postgres::PgStore>),
}

impl Store {
    /// Opens (or creates) the SQLite store in `dir`, migrating an older schema.
    pub fn open(dir: &Path) -> Result<Store, StoreError> {
        Ok(Store(Backend::Sqlite(sqlite::SqliteStore::open(dir)?)))
    }

    /// Connects to a PostgreSQL store, creating or migrating its tables. Blocks; call it
    /// outside an async runtime (the server does, on a thread of its own).
    pub fn connect(url: &str) -> Result<Store, StoreError> {
        Ok(Store(Backend::Postgres(Box::new(
            postgres::PgStore::connect(url)?,
        ))))
    }

    /// Opens the store `location` names, as [`Store::open`] or [`Store::connect`] does.
    pub fn at(location: &Location) -> Result<Store, StoreError> {
        match location {
            Location::Sqlite(dir) => Store::open(dir),
            Location::Postgres(url) => Store::connect(url),
        }
    }

    /// Applies `ops` in one transaction: all of them are durable when this returns `Ok`.
    pub fn apply(&mut self, ops: &[&StoreOp]) -> Result<(), StoreError> {
        match &mut self.0 {
            Backend::Sqlite(s) => s.apply(ops),
            Backend::Postgres(s) => s.apply(ops),
        }
    }

    /// Every player's rating, for the hub at start and the leaderboard.
    pub fn ratings(&self) -> Result<Vec<(PlayerKey, PlayerRating)>, StoreError> {
        match &self.0 {
            Backend::Sqlite(s) => s.ratings(),
            Backend::Postgres(s) => s.ratings(),
        }
    }

    /// Games still being played, for a restart. In a shared store, only those of rooms no
    /// other instance owns, which become this one's.
    pub fn unfinished(&self) -> Result<Vec<StoredGame>, StoreError> {
        match &self.0 {
            Backend::Sqlite(s) => s.unfinished(),
            Backend::Postgres(s) => s.unfinished(),
        }
    }

    /// Looks for the room of a seat no room on this server has: in a store shared by
    /// several instances, the room of one that stopped is taken over. SQLite belongs to one
    /// server, which restored every room at start.
    pub fn claim(&self, seat: &TokenDigest) -> Result<Claim, StoreError> {
        match &self.0 {
            Backend::Sqlite(_) => Ok(Claim::NotFound),
            Backend::Postgres(s) => s.claim(seat),
        }
    }

    /// Whether other server instances may share this store (and so own some of its rooms).
    pub fn shared(&self) -> bool {
        matches!(self.0, Backend::Postgres(_))
    }

    /// Every stored game, in room and game order.
    pub fn all(&self) -> Result<Vec<StoredGame>, StoreError> {
        match &self.0 {
            Backend::Sqlite(s) => s.all(),
            Backend::Postgres(s) => s.games(true, None),
        }
    }

    /// The latest game of each room if it ended at `since` (Unix seconds) or later: the
    /// games whose players may still come back to learn the result.
    pub fn ended_since(&self, since: u64) -> Result<Vec<EndedGame>, StoreError> {
        match &self.0 {
            Backend::Sqlite(s) => s.ended_since(since),
            Backend::Postgres(s) => s.ended_since(since, None),
        }
    }

    /// One game's record, encoded: its header and its command rows, assembled.
    pub fn record(&self, room: &RoomCode, number: u32) -> Result<Option<Vec<u8>>, StoreError> {
        let code = room.as_str();
        let header = match &self.0 {
            Backend::Sqlite(s) => s.header(code, number)?,
            Backend::Postgres(s) => s.header(code, number)?,
        };
        let Some(header) = header else {
            return Ok(None);
        };
        let entries = match &self.0 {
            Backend::Sqlite(s) => s.entries(code, number)?,
            Backend::Postgres(s) => s.entries(code, number)?,
        };
        encoded_record(room, number, &header, entries).map(Some)
    }

    /// The latest game of a room: (number, encoded record, finished).
    pub fn latest(&self, room: &RoomCode) -> Result<Option<(u32, Vec<u8>, bool)>, StoreError> {
        let latest = match &self.0 {
            Backend::Sqlite(s) => s.latest_game(room.as_str())?,
            Backend::Postgres(s) => s.latest_game(room.as_str())?,
        };
        let Some((number, finished)) = latest else {
            return Ok(None);
        };
        Ok(self
            .record(room, number)?
            .map(|record| (number, record, finished)))
    }

    /// Game `number` of a room: (number, encoded record, finished), if the room has it.
    pub fn game(
        &self,
        room: &RoomCode,
        number: u32,
    ) -> Result<Option<(u32, Vec<u8>, bool)>, StoreError> {
        let finished = match &self.0 {
            Backend::Sqlite(s) => s.finished(room.as_str(), number)?,
            Backend::Postgres(s) => s.finished(room.as_str(), number)?,
        };
        let Some(finished) = finished else {
            return Ok(None);
        };
        Ok(self
            .record(room, number)?
            .map(|record| (number, record, finished)))
    }

    /// How many games a room has played (the number of its latest), if it has any.
    pub fn games_played(&self, room: &RoomCode) -> Result<Option<u32>, StoreError> {
        let latest = match &self.0 {
            Backend::Sqlite(s) => s.latest_game(room.as_str())?,
            Backend::Postgres(s) => s.latest_game(room.as_str())?,
        };
        Ok(latest.map(|(number, _)| number))
    }

    /// Writes a game stored in an older record format again, whole, in the current one, so
    /// the commands appended to it from now on are in the format of its header. Does
    /// nothing for a game already in the current format (or one that does not read).
    pub fn upgrade(&mut self, game: &StoredGame) -> Result<(), StoreError> {
        let Ok(record) = &game.record else {
            return Ok(());
        };
        if game.format == RECORD_VERSION {
            return Ok(());
        }
        let ops = StoreOp::whole_game(&game.meta.code, game.number, record);
        self.apply(&ops.iter().collect::<Vec<_>>())
    }

    /// Replaces one game's record whole (for tests of tamper detection).
    pub fn overwrite_record(
        &self,
        room: &RoomCode,
        number: u32,
        record: &[u8],
    ) -> Result<bool, StoreError> {
        match &self.0 {
            Backend::Sqlite(s) => s.overwrite_record(room, number, record),
            Backend::Postgres(s) => s.overwrite_record(room, number, record),
        }
    }
}

/// A game's record: its header followed by its command rows, in order, each row read in
/// its header's format; a game stored in an older format comes back in the current one.
fn assemble(header: &[u8], entries: Vec<Vec<u8>>) -> Result<GameRecord, RecordError> {
    let version = replay::format_version(header)?;
    let mut record = GameRecord::decode(header)?;
    for bytes in entries {
        record
            .entries
            .push(RecordEntry::decode_version(&bytes, version)?);
    }
    if version != RECORD_VERSION {
        record.rechain();
    }
    Ok(record)
}

/// The format a stored game's header is written in (0 if it is unreadable).
fn stored_format(header: &[u8]) -> u32 {
    replay::format_version(header).unwrap_or(0)
}

/// Room `room`'s game `number`, assembled and encoded whole, as `record` answers: a record
/// that does not assemble is an error naming the game.
fn encoded_record(
    room: &RoomCode,
    number: u32,
    header: &[u8],
    entries: Vec<Vec<u8>>,
) -> Result<Vec<u8>, StoreError> {
    let record = assemble(header, entries).map_err(|why| StoreError::Record {
        room: room.to_string(),
        number,
        why,
    })?;
    Ok(record.encode())
}

fn seat_number(seat: Seat) -> i64 {
    match seat {
        Seat::A => 0,
        Seat::B => 1,
    }
}

fn seat_of(number: i64) -> Option<Seat> {
    match number {
        0 => Some(Seat::A),
        1 => Some(Seat::B),
        _ => None,
    }
}

/// The players of a rated room's row, if the room has one and both keys are keys.
fn player_key(k: Option<Vec<u8>>) -> Option<PlayerKey> {
    <[u8; 32]>::try_from(k?.as_slice()).ok().map(PlayerKey)
}

fn rated_players(a: Option<Vec<u8>>, b: Option<Vec<u8>>) -> Option<[PlayerKey; 2]> {
    Some([player_key(a)?, player_key(b)?])
}

/// A listed room's players, when its row (`code`) was found.
fn listed_players(
    code: Option<String>,
    a: Option<Vec<u8>>,
    b: Option<Vec<u8>>,
) -> Option<[Option<PlayerKey>; 2]> {
    code.map(|_| [player_key(a), player_key(b)])
}

fn encode_meta(meta: &RoomMeta) -> Result<Vec<u8>, StoreError> {
    bincode::serde::encode_to_vec(meta, config::standard()).map_err(|e| StoreError::Meta {
        room: meta.code.to_string(),
        why: e.to_string(),
    })
}

fn decode_meta(bytes: &[u8]) -> Result<RoomMeta, String> {
    let cfg = config::standard().with_limit::<MAX_RECORD>();
    bincode::serde::decode_from_slice(bytes, cfg)
        .map(|(m, _)| m)
        .map_err(|e| e.to_string())
}
