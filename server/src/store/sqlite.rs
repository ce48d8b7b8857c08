//! The embedded backend: SQLite in the data directory, WAL with `synchronous=FULL`, so a
//! commit that returned survives a crash or a power cut.

use std::path::Path;

use crate::ratings::PlayerRating;
use breakshot_shared::protocol::PlayerKey;
use breakshot_shared::protocol::RoomCode;
use breakshot_shared::replay::{self, GameRecord, RecordEntry, RECORD_VERSION};
use rusqlite::{params, Connection, OptionalExtension};

use super::{
    assemble, decode_meta, encode_meta, listed_players, rated_players, seat_number, seat_of,
    stored_format, unix_millis, unix_now, EndedGame, StoreError, StoredClock, StoredGame,
};
use crate::output::StoreOp;

/// The SQLite store's file in the data directory (with its `-wal` and `-shm` files while open).
pub const DB_FILE: &str = "games.sqlite3";

/// The schema this build writes (`PRAGMA user_version`). Version 1 (no version set) kept
/// each game's whole record in `games.record`; it is migrated in place on open: the record
/// becomes the game's header, with no command rows after it. Version 2 may hold records of
/// format 1 (level strikes, before the cue elevation); on open they are rewritten in the
/// current format, so a game goes on with rows of one format only. Version 4 adds the table of
/// rated (quick-match) rooms, version 5 that of the rooms listed in the lobby.
const SCHEMA: i64 = 5;

pub(super) struct SqliteStore {
    pub(super) db: Connection,
}

impl SqliteStore {
    /// Opens (or creates) the store in `dir`, migrating an older schema.
    pub(super) fn open(dir: &Path) -> Result<SqliteStore, StoreError> {
        let db = Connection::open(dir.join(DB_FILE))?;
        db.pragma_update(None, "journal_mode", "WAL")?;
        db.pragma_update(None, "synchronous", "FULL")?;
        let version: i64 = db.pragma_query_value(None, "user_version", |r| r.get(0))?;
        if version > SCHEMA {
            return Err(StoreError::Schema {
                found: version,
                known: SCHEMA,
            });
        }
        let has_v1_games: bool = db.query_row(
            "SELECT COUNT(*) FROM pragma_table_info('games') WHERE name = 'record'",
            [],
            |r| r.get(0),
        )?;
        let tx = db.unchecked_transaction()?;
        if has_v1_games {
            tx.execute_batch(
                "ALTER TABLE games RENAME COLUMN record TO header;
                 ALTER TABLE games ADD COLUMN winner INTEGER;
                 ALTER TABLE games ADD COLUMN reason TEXT;
                 ALTER TABLE games ADD COLUMN finished_at INTEGER;",
            )?;
        }
        tx.execute_batch(
            "CREATE TABLE IF NOT EXISTS rooms (
                 code TEXT PRIMARY KEY,
                 meta BLOB NOT NULL
             );
             CREATE TABLE IF NOT EXISTS games (
                 room TEXT NOT NULL REFERENCES rooms(code),
                 number INTEGER NOT NULL,
                 header BLOB NOT NULL,
                 finished INTEGER NOT NULL,
                 winner INTEGER,
                 reason TEXT,
                 finished_at INTEGER,
                 PRIMARY KEY (room, number)
             );
             CREATE TABLE IF NOT EXISTS commands (
                 room TEXT NOT NULL,
                 number INTEGER NOT NULL,
                 idx INTEGER NOT NULL,
                 entry BLOB NOT NULL,
                 PRIMARY KEY (room, number, idx)
             ) WITHOUT ROWID;
             CREATE INDEX IF NOT EXISTS games_finished ON games (finished, finished_at);
             CREATE TABLE IF NOT EXISTS clocks (
                 room TEXT NOT NULL,
                 number INTEGER NOT NULL,
                 turn INTEGER NOT NULL,
                 left_ms INTEGER NOT NULL,
                 running INTEGER NOT NULL,
                 at_ms INTEGER NOT NULL,
                 PRIMARY KEY (room, number)
             ) WITHOUT ROWID;
             CREATE TABLE IF NOT EXISTS ratings (
                 player BLOB PRIMARY KEY,
                 name TEXT NOT NULL,
                 rating REAL NOT NULL,
                 deviation REAL NOT NULL,
                 volatility REAL NOT NULL,
                 games INTEGER NOT NULL
             ) WITHOUT ROWID;
             CREATE TABLE IF NOT EXISTS rated_rooms (
                 code TEXT PRIMARY KEY REFERENCES rooms(code),
                 player_a BLOB NOT NULL,
                 player_b BLOB NOT NULL
             ) WITHOUT ROWID;
             CREATE TABLE IF NOT EXISTS listed_rooms (
                 code TEXT PRIMARY KEY REFERENCES rooms(code),
                 player_a BLOB,
                 player_b BLOB
             ) WITHOUT ROWID;",
        )?;
        if version < 3 {
            rewrite_old_records(&tx)?;
        }
        tx.pragma_update(None, "user_version", SCHEMA)?;
        tx.commit()?;
        Ok(SqliteStore { db })
    }

    /// Applies `ops` in one transaction: all of them are durable when this returns `Ok`.
    pub(super) fn apply(&mut self, ops: &[&StoreOp]) -> Result<(), StoreError> {
        let tx = self.db.transaction()?;
        for op in ops {
            match op {
                StoreOp::Room(meta) => {
                    let blob = encode_meta(meta)?;
                    tx.prepare_cached(
                        "INSERT INTO rooms (code, meta) VALUES (?1, ?2)
                         ON CONFLICT(code) DO UPDATE SET meta = excluded.meta",
                    )?
                    .execute(params![meta.code.as_str(), blob])?;
                }
                StoreOp::GameStarted {
                    room,
                    number,
                    header,
                } => {
                    tx.prepare_cached(
                        "INSERT INTO games (room, number, header, finished) VALUES (?1, ?2, ?3, 0)
                         ON CONFLICT(room, number) DO UPDATE
                         SET header = excluded.header, finished = 0, winner = NULL,
                             reason = NULL, finished_at = NULL",
                    )?
                    .execute(params![room.as_str(), number, header])?;
                    tx.prepare_cached("DELETE FROM commands WHERE room = ?1 AND number = ?2")?
                        .execute(params![room.as_str(), number])?;
                }
                StoreOp::Command {
                    room,
                    number,
                    index,
                    entry,
                } => {
                    tx.prepare_cached(
                        "INSERT INTO commands (room, number, idx, entry) VALUES (?1, ?2, ?3, ?4)",
                    )?
                    .execute(params![room.as_str(), number, index, entry])?;
                }
                StoreOp::GameEnded {
                    room,
                    number,
                    winner,
                    reason,
                } => {
                    let at = unix_now();
                    tx.prepare_cached(
                        "UPDATE games SET finished = 1, winner = ?3, reason = ?4, finished_at = ?5
                         WHERE room = ?1 AND number = ?2",
                    )?
                    .execute(params![
                        room.as_str(),
                        number,
                        winner.map(seat_number),
                        reason,
                        i64::try_from(at).unwrap_or(i64::MAX)
                    ])?;
                }
                StoreOp::Clock {
                    room,
                    number,
                    turn,
                    left_ms,
                    running,
                } => {
                    tx.prepare_cached(
                        "INSERT INTO clocks (room, number, turn, left_ms, running, at_ms)
                         VALUES (?1, ?2, ?3, ?4, ?5, ?6)
                         ON CONFLICT(room, number) DO UPDATE
                         SET turn = excluded.turn, left_ms = excluded.left_ms,
                             running = excluded.running, at_ms = excluded.at_ms",
                    )?
                    .execute(params![
                        room.as_str(),
                        number,
                        turn,
                        i64::try_from(*left_ms).unwrap_or(i64::MAX),
                        running,
                        i64::try_from(unix_millis()).unwrap_or(i64::MAX)
                    ])?;
                }
                // One server owns every room of its own SQLite file.
                StoreOp::Released(_) => {}
                StoreOp::RatedRoom { room, players } => {
                    tx.prepare_cached(
                        "INSERT INTO rated_rooms (code, player_a, player_b) VALUES (?1, ?2, ?3)
                         ON CONFLICT(code) DO NOTHING",
                    )?
                    .execute(params![
                        room.as_str(),
                        players[0].0.as_slice(),
                        players[1].0.as_slice()
                    ])?;
                }
                StoreOp::Listed { room, players } => {
                    let [a, b] = players.map(|k| k.map(|k| k.0.to_vec()));
                    tx.prepare_cached(
                        "INSERT INTO listed_rooms (code, player_a, player_b) VALUES (?1, ?2, ?3)
                         ON CONFLICT(code) DO UPDATE
                         SET player_a = excluded.player_a, player_b = excluded.player_b",
                    )?
                    .execute(params![room.as_str(), a, b])?;
                }
                StoreOp::Rating { key, rating } => {
                    tx.prepare_cached(
                        "INSERT INTO ratings (player, name, rating, deviation, volatility, games)
                         VALUES (?1, ?2, ?3, ?4, ?5, ?6)
                         ON CONFLICT(player) DO UPDATE
                         SET name = excluded.name, rating = excluded.rating,
                             deviation = excluded.deviation, volatility = excluded.volatility,
                             games = excluded.games",
                    )?
                    .execute(params![
                        key.0.as_slice(),
                        rating.name,
                        rating.rating,
                        rating.deviation,
                        rating.volatility,
                        rating.games
                    ])?;
                }
            }
        }
        tx.commit()?;
        Ok(())
    }

    /// Every player's rating.
    pub(super) fn ratings(&self) -> Result<Vec<(PlayerKey, PlayerRating)>, StoreError> {
        let mut q = self
            .db
            .prepare("SELECT player, name, rating, deviation, volatility, games FROM ratings")?;
        let rows = q.query_map([], |r| {
            Ok((
                r.get::<_, Vec<u8>>(0)?,
                PlayerRating {
                    name: r.get(1)?,
                    rating: r.get(2)?,
                    deviation: r.get(3)?,
                    volatility: r.get(4)?,
                    games: r.get(5)?,
                },
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (key, rating) = row?;
            // A row that is no key is skipped rather than trusted.
            if let Ok(key) = <[u8; 32]>::try_from(key.as_slice()) {
                out.push((PlayerKey(key), rating));
            }
        }
        Ok(out)
    }

    /// Games still being played, for a restart.
    pub(super) fn unfinished(&self) -> Result<Vec<StoredGame>, StoreError> {
        self.games("WHERE g.finished = 0")
    }

    /// The latest game of each room if it ended at `since` (Unix seconds) or later: the
    /// games whose players may still come back to learn the result.
    pub(super) fn ended_since(&self, since: u64) -> Result<Vec<EndedGame>, StoreError> {
        let mut stmt = self.db.prepare(
            "SELECT r.code, r.meta, g.number, g.winner, g.reason, g.finished_at
             FROM games g JOIN rooms r ON r.code = g.room
             WHERE g.finished = 1 AND g.finished_at >= ?1
               AND g.number = (SELECT MAX(number) FROM games WHERE room = g.room)
             ORDER BY g.finished_at",
        )?;
        let since = i64::try_from(since).unwrap_or(i64::MAX);
        let rows = stmt.query_map(params![since], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, Vec<u8>>(1)?,
                r.get::<_, u32>(2)?,
                r.get::<_, Option<i64>>(3)?,
                r.get::<_, Option<String>>(4)?,
                r.get::<_, i64>(5)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (code, meta, number, winner, reason, at) = row?;
            let meta = decode_meta(&meta).map_err(|why| StoreError::Meta { room: code, why })?;
            out.push(EndedGame {
                meta,
                number,
                winner: winner.and_then(seat_of),
                reason: reason.unwrap_or_default(),
                at: u64::try_from(at).unwrap_or(0),
            });
        }
        Ok(out)
    }

    /// Every stored game, in room and game order.
    pub(super) fn all(&self) -> Result<Vec<StoredGame>, StoreError> {
        self.games("")
    }

    /// Replaces one game's record whole (for tests of tamper detection).
    pub(super) fn overwrite_record(
        &self,
        room: &RoomCode,
        number: u32,
        record: &[u8],
    ) -> Result<bool, StoreError> {
        let tx = self.db.unchecked_transaction()?;
        let n = tx.execute(
            "UPDATE games SET header = ?3 WHERE room = ?1 AND number = ?2",
            params![room.as_str(), number, record],
        )?;
        tx.execute(
            "DELETE FROM commands WHERE room = ?1 AND number = ?2",
            params![room.as_str(), number],
        )?;
        tx.commit()?;
        Ok(n == 1)
    }

    /// Game `number` of `room`: its header row, if it is stored.
    pub(super) fn header(&self, room: &str, number: u32) -> Result<Option<Vec<u8>>, StoreError> {
        self.game_column("header", room, number)
    }

    /// Whether game `number` of `room` is over, if it is stored.
    pub(super) fn finished(&self, room: &str, number: u32) -> Result<Option<bool>, StoreError> {
        self.game_column("finished", room, number)
    }

    /// One column (a fixed name, never input) of game `number` of `room`, if it is stored.
    fn game_column<T: rusqlite::types::FromSql>(
        &self,
        column: &'static str,
        room: &str,
        number: u32,
    ) -> Result<Option<T>, StoreError> {
        let sql = format!("SELECT {column} FROM games WHERE room = ?1 AND number = ?2");
        Ok(self
            .db
            .query_row(&sql, params![room, number], |r| r.get(0))
            .optional()?)
    }

    /// The latest game of `room`: (number, finished).
    pub(super) fn latest_game(&self, room: &str) -> Result<Option<(u32, bool)>, StoreError> {
        Ok(self
            .db
            .query_row(
                "SELECT number, finished FROM games WHERE room = ?1
                 ORDER BY number DESC LIMIT 1",
                params![room],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()?)
    }

    /// A game's command rows, in order.
    pub(super) fn entries(&self, room: &str, number: u32) -> Result<Vec<Vec<u8>>, StoreError> {
        let mut stmt = self.db.prepare_cached(
            "SELECT entry FROM commands WHERE room = ?1 AND number = ?2 ORDER BY idx",
        )?;
        let rows = stmt.query_map(params![room, number], |r| r.get(0))?;
        Ok(rows.collect::<Result<_, _>>()?)
    }

    fn games(&self, filter: &str) -> Result<Vec<StoredGame>, StoreError> {
        let sql = format!(
            "SELECT r.code, r.meta, g.number, g.header, g.finished,
                    c.turn, c.left_ms, c.running, c.at_ms, q.player_a, q.player_b,
                    l.code, l.player_a, l.player_b
             FROM games g JOIN rooms r ON r.code = g.room
             LEFT JOIN clocks c ON c.room = g.room AND c.number = g.number
             LEFT JOIN rated_rooms q ON q.code = g.room
             LEFT JOIN listed_rooms l ON l.code = g.room {filter}
             ORDER BY g.room, g.number"
        );
        let mut stmt = self.db.prepare(&sql)?;
        let rows = stmt.query_map([], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, Vec<u8>>(1)?,
                r.get::<_, u32>(2)?,
                r.get::<_, Vec<u8>>(3)?,
                r.get::<_, bool>(4)?,
                clock_of(
                    r.get::<_, Option<u32>>(5)?,
                    r.get::<_, Option<i64>>(6)?,
                    r.get::<_, Option<bool>>(7)?,
                    r.get::<_, Option<i64>>(8)?,
                ),
                rated_players(r.get(9)?, r.get(10)?),
                listed_players(r.get(11)?, r.get(12)?, r.get(13)?),
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (code, meta, number, header, finished, clock, rated, listed) = row?;
            let record = assemble(&header, self.entries(&code, number)?);
            let meta = decode_meta(&meta).map_err(|why| StoreError::Meta { room: code, why })?;
            out.push(StoredGame {
                meta,
                number,
                record,
                finished,
                format: stored_format(&header),
                clock,
                rated,
                listed,
            });
        }
        Ok(out)
    }
}

/// A stored clock row, if the game has one.
fn clock_of(
    turn: Option<u32>,
    left_ms: Option<i64>,
    running: Option<bool>,
    at_ms: Option<i64>,
) -> Option<StoredClock> {
    Some(StoredClock {
        turn: turn?,
        left_ms: u64::try_from(left_ms?).unwrap_or(0),
        running: running?,
        at_ms: u64::try_from(at_ms?).unwrap_or(0),
    })
}

/// Rewrites every game stored in an older record format, its header and its command rows, in
/// the current one. A game that does not decode is left as it is: reading it reports why.
fn rewrite_old_records(tx: &Connection) -> Result<(), StoreError> {
    let games: Vec<(String, u32, Vec<u8>)> = tx
        .prepare("SELECT room, number, header FROM games")?
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
        .collect::<Result<_, _>>()?;
    for (room, number, header) in games {
        let Ok(version) = replay::format_version(&header) else {
            continue;
        };
        if version == RECORD_VERSION {
            continue;
        }
        let Ok(record) = GameRecord::decode(&header) else {
            continue;
        };
        let rows: Vec<(i64, Vec<u8>)> = tx
            .prepare("SELECT idx, entry FROM commands WHERE room = ?1 AND number = ?2")?
            .query_map(params![room, number], |r| Ok((r.get(0)?, r.get(1)?)))?
            .collect::<Result<_, _>>()?;
        let Ok(entries) = rows
            .iter()
            .map(|(_, bytes)| RecordEntry::decode_version(bytes, version))
            .collect::<Result<Vec<_>, _>>()
        else {
            continue;
        };
        // The whole record, to write its chain of hashes in the current format.
        let mut whole = GameRecord {
            entries,
            ..record.clone()
        };
        whole.rechain();
        tx.execute(
            "UPDATE games SET header = ?3 WHERE room = ?1 AND number = ?2",
            params![room, number, record.encode()],
        )?;
        for ((idx, _), entry) in rows.iter().zip(&whole.entries) {
            tx.execute(
                "UPDATE commands SET entry = ?4 WHERE room = ?1 AND number = ?2 AND idx = ?3",
                params![room, number, idx, entry.encode()],
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use breakshot_shared::protocol::AimAid;
    use breakshot_shared::rules::{Settings, Variant};

    use bincode::config;
    use breakshot_shared::rules::Seat;

    use super::*;
    use crate::output::RoomMeta;

    fn room_meta(code: &RoomCode) -> RoomMeta {
        RoomMeta {
            code: code.clone(),
            variant: Variant::Practice,
            settings: Settings::offline(),
            aim_aid: AimAid::Off,
            seats: [None, None],
        }
    }

    fn place(i: u32) -> RecordEntry {
        RecordEntry {
            seat: Seat::A,
            command: breakshot_shared::rules::Command::PlaceCueBall {
                pos: [0.5, f64::from(i)],
            },
            hash: None,
            chain: 0,
        }
    }

    /// What the tests both backends share (in the tests crate) cannot see: appending a
    /// command adds one row and leaves the game's header row as it was stored first.
    #[test]
    fn a_game_is_appended_one_row_per_command() {
        let tmp = breakshot_testkit::scratch("append");
        let code = RoomCode::parse("CCCCCCCC").unwrap();
        let record = GameRecord::new(Variant::Practice, Settings::offline(), 3);
        let mut store = SqliteStore::open(tmp.path()).unwrap();
        let mut ops = vec![StoreOp::Room(room_meta(&code))];
        ops.extend(StoreOp::whole_game(&code, 1, &record));
        store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
        for i in 0..50 {
            let op = StoreOp::Command {
                room: code.clone(),
                number: 1,
                index: i,
                entry: place(i).encode(),
            };
            store.apply(&[&op]).unwrap();
        }
        let header: Vec<u8> = store
            .db
            .query_row("SELECT header FROM games", [], |r| r.get(0))
            .unwrap();
        assert_eq!(GameRecord::decode(&header).unwrap().entries.len(), 0);
        let rows: u32 = store
            .db
            .query_row("SELECT COUNT(*) FROM commands", [], |r| r.get(0))
            .unwrap();
        assert_eq!(rows, 50);
    }

    #[test]
    fn records_of_the_first_format_are_rewritten_in_the_current_one() {
        let tmp = breakshot_testkit::scratch("format");
        let dir = tmp.path().to_path_buf();
        let code = RoomCode::parse("EEEEEEEE").unwrap();
        // A format-1 header: version, variant, settings, seed and no entries.
        let header = bincode::serde::encode_to_vec(
            (
                1u32,
                Variant::Practice,
                Settings::offline(),
                5u64,
                Vec::<u8>::new(),
            ),
            config::standard(),
        )
        .unwrap();
        // One format-1 command row: seat A, a level shot (speed 1.5 along +y, tip 0.25 high,
        // no elevation field), pocket 2 called, a hash; the bytes of the pinned format-1
        // record in shared/tests/rules_record.rs.
        let old_row: Vec<u8> = (0..OLD_SHOT_ROW.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&OLD_SHOT_ROW[i..i + 2], 16).unwrap())
            .collect();
        {
            let mut store = SqliteStore::open(&dir).unwrap();
            let ops = [
                StoreOp::Room(room_meta(&code)),
                StoreOp::GameStarted {
                    room: code.clone(),
                    number: 1,
                    header,
                },
                StoreOp::Command {
                    room: code.clone(),
                    number: 1,
                    index: 0,
                    entry: old_row,
                },
            ];
            store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
            store.db.pragma_update(None, "user_version", 2).unwrap();
        }
        let mut store = SqliteStore::open(&dir).unwrap();
        let shot = RecordEntry {
            seat: Seat::A,
            command: breakshot_shared::rules::Command::Shot {
                strike: breakshot_shared::physics::Strike {
                    speed: 1.5,
                    dir: glam::DVec2::new(0.0, 1.0),
                    tip: glam::DVec2::new(0.0, 0.25),
                    elevation_deg: 0.0,
                },
                call: Some(2),
            },
            hash: Some(0x0123_4567_89ab_cdef),
            chain: 0,
        };
        // A record of format 1 names no physics; read back, its chain is written.
        let mut record = GameRecord::new(Variant::Practice, Settings::offline(), 5);
        record.physics = None;
        record.entries.push(shot);
        record.rechain();
        assert_eq!(store.unfinished().unwrap()[0].record, Ok(record.clone()));
        // The game goes on with rows of the current format only.
        let op = StoreOp::Command {
            room: code.clone(),
            number: 1,
            index: 1,
            entry: place(1).encode(),
        };
        store.apply(&[&op]).unwrap();
        record.entries.push(place(1));
        drop(store);
        let store = SqliteStore::open(&dir).unwrap();
        assert_eq!(store.all().unwrap()[0].record, Ok(record));
    }

    const OLD_SHOT_ROW: &str = "0000000000000000f83f0000000000000000000000000000f03f0000000000000000000000000000d03f010201fdefcdab8967452301";

    #[test]
    fn a_store_of_the_first_schema_is_migrated_in_place() {
        let tmp = breakshot_testkit::scratch("migrate");
        let dir = tmp.path().to_path_buf();
        let code = RoomCode::parse("DDDDDDDD").unwrap();
        let mut record = GameRecord::new(Variant::Practice, Settings::offline(), 4);
        record.entries.extend((0..3).map(place));
        {
            // The first schema: the whole record in one column.
            let db = Connection::open(dir.join(DB_FILE)).unwrap();
            db.execute_batch(
                "CREATE TABLE rooms (code TEXT PRIMARY KEY, meta BLOB NOT NULL);
                 CREATE TABLE games (room TEXT NOT NULL REFERENCES rooms(code),
                     number INTEGER NOT NULL, record BLOB NOT NULL,
                     finished INTEGER NOT NULL, PRIMARY KEY (room, number));",
            )
            .unwrap();
            let meta = bincode::serde::encode_to_vec(room_meta(&code), config::standard()).unwrap();
            db.execute(
                "INSERT INTO rooms VALUES (?1, ?2)",
                params![code.as_str(), meta],
            )
            .unwrap();
            db.execute(
                "INSERT INTO games VALUES (?1, 1, ?2, 0)",
                params![code.as_str(), record.encode()],
            )
            .unwrap();
        }
        let mut store = SqliteStore::open(&dir).unwrap();
        assert_eq!(store.unfinished().unwrap()[0].record, Ok(record.clone()));
        // The game goes on in the new form.
        let next = place(3);
        let op = StoreOp::Command {
            room: code.clone(),
            number: 1,
            index: 3,
            entry: next.encode(),
        };
        store.apply(&[&op]).unwrap();
        record.entries.push(next);
        drop(store);
        let store = SqliteStore::open(&dir).unwrap();
        assert_eq!(store.all().unwrap()[0].record, Ok(record));
    }
}
