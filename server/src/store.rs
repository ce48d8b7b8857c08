//! The game store: SQLite in the data directory, WAL with `synchronous=FULL`, so a commit
//! that returned survives a crash or a power cut. One row per room (its settings and seat
//! token digests), one row per game (its whole record, replaced on every command).
//!
//! Everything here blocks; the server calls it from its own writer thread, never from an
//! async worker.

use std::path::Path;

use bincode::config;
use breakshot_shared::protocol::limits::MAX_RECORD;
use breakshot_shared::protocol::RoomCode;
use rusqlite::{params, Connection, OptionalExtension};
use thiserror::Error;

use crate::output::{RoomMeta, StoreOp};

pub const DB_FILE: &str = "games.sqlite3";

#[derive(Debug, Error)]
pub enum StoreError {
    #[error("database: {0}")]
    Sql(#[from] rusqlite::Error),
    #[error("room {room}: stored settings are unreadable: {why}")]
    Meta { room: String, why: String },
}

/// One stored game with its room.
#[derive(Debug)]
pub struct StoredGame {
    pub meta: RoomMeta,
    pub number: u32,
    pub record: Vec<u8>,
    pub finished: bool,
}

pub struct Store {
    db: Connection,
}

impl Store {
    /// Opens (or creates) the store in `dir`.
    pub fn open(dir: &Path) -> Result<Store, StoreError> {
        let db = Connection::open(dir.join(DB_FILE))?;
        db.pragma_update(None, "journal_mode", "WAL")?;
        db.pragma_update(None, "synchronous", "FULL")?;
        db.execute_batch(
            "CREATE TABLE IF NOT EXISTS rooms (
                 code TEXT PRIMARY KEY,
                 meta BLOB NOT NULL
             );
             CREATE TABLE IF NOT EXISTS games (
                 room TEXT NOT NULL REFERENCES rooms(code),
                 number INTEGER NOT NULL,
                 record BLOB NOT NULL,
                 finished INTEGER NOT NULL,
                 PRIMARY KEY (room, number)
             );",
        )?;
        Ok(Store { db })
    }

    /// Applies `ops` in one transaction: all of them are durable when this returns `Ok`.
    pub fn apply(&mut self, ops: &[&StoreOp]) -> Result<(), StoreError> {
        let tx = self.db.transaction()?;
        for op in ops {
            match op {
                StoreOp::Room(meta) => {
                    let blob =
                        bincode::serde::encode_to_vec(meta, config::standard()).map_err(|e| {
                            StoreError::Meta {
                                room: meta.code.to_string(),
                                why: e.to_string(),
                            }
                        })?;
                    tx.execute(
                        "INSERT INTO rooms (code, meta) VALUES (?1, ?2)
                         ON CONFLICT(code) DO UPDATE SET meta = excluded.meta",
                        params![meta.code.as_str(), blob],
                    )?;
                }
                StoreOp::Game {
                    room,
                    number,
                    record,
                    finished,
                } => {
                    tx.execute(
                        "INSERT INTO games (room, number, record, finished) VALUES (?1, ?2, ?3, ?4)
                         ON CONFLICT(room, number) DO UPDATE
                         SET record = excluded.record, finished = excluded.finished",
                        params![room.as_str(), number, record, finished],
                    )?;
                }
            }
        }
        tx.commit()?;
        Ok(())
    }

    /// Games still being played, for a restart.
    pub fn unfinished(&self) -> Result<Vec<StoredGame>, StoreError> {
        self.games("WHERE g.finished = 0")
    }

    /// Every stored game, in room and game order.
    pub fn all(&self) -> Result<Vec<StoredGame>, StoreError> {
        self.games("")
    }

    /// Overwrites one game's record (for tests of tamper detection).
    pub fn overwrite_record(
        &self,
        room: &RoomCode,
        number: u32,
        record: &[u8],
    ) -> Result<bool, StoreError> {
        let n = self.db.execute(
            "UPDATE games SET record = ?3 WHERE room = ?1 AND number = ?2",
            params![room.as_str(), number, record],
        )?;
        Ok(n == 1)
    }

    /// One game's record.
    pub fn record(&self, room: &RoomCode, number: u32) -> Result<Option<Vec<u8>>, StoreError> {
        Ok(self
            .db
            .query_row(
                "SELECT record FROM games WHERE room = ?1 AND number = ?2",
                params![room.as_str(), number],
                |r| r.get(0),
            )
            .optional()?)
    }

    /// The latest game of a room: (number, record, finished).
    pub fn latest(&self, room: &RoomCode) -> Result<Option<(u32, Vec<u8>, bool)>, StoreError> {
        Ok(self
            .db
            .query_row(
                "SELECT number, record, finished FROM games WHERE room = ?1
                 ORDER BY number DESC LIMIT 1",
                params![room.as_str()],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )
            .optional()?)
    }

    fn games(&self, filter: &str) -> Result<Vec<StoredGame>, StoreError> {
        let sql = format!(
            "SELECT r.code, r.meta, g.number, g.record, g.finished
             FROM games g JOIN rooms r ON r.code = g.room {filter}
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
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (code, meta, number, record, finished) = row?;
            let meta = decode_meta(&meta).map_err(|why| StoreError::Meta { room: code, why })?;
            out.push(StoredGame {
                meta,
                number,
                record,
                finished,
            });
        }
        Ok(out)
    }
}

fn decode_meta(bytes: &[u8]) -> Result<RoomMeta, String> {
    let cfg = config::standard().with_limit::<MAX_RECORD>();
    bincode::serde::decode_from_slice(bytes, cfg)
        .map(|(m, _)| m)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use breakshot_shared::protocol::AimAid;
    use breakshot_shared::rules::{EightBallRules, Settings, Variant};

    use super::*;
    use crate::output::StoredSeat;
    use crate::secret::TokenDigest;

    #[test]
    fn games_survive_reopening_and_finished_ones_are_not_reloaded() {
        let dir = std::env::temp_dir().join(format!("breakshot-store-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let meta = |code: &str| RoomMeta {
            code: RoomCode::parse(code).unwrap(),
            variant: Variant::EightBall(EightBallRules::Wpa),
            settings: Settings::offline(),
            aim_aid: AimAid::Off,
            seats: [
                Some(StoredSeat {
                    name: "ann".into(),
                    digest: TokenDigest([1; 32]),
                }),
                None,
            ],
        };
        let game = |code: &str, finished| StoreOp::Game {
            room: RoomCode::parse(code).unwrap(),
            number: 1,
            record: vec![1, 2, 3],
            finished,
        };
        {
            let mut store = Store::open(&dir).unwrap();
            let ops = [
                StoreOp::Room(meta("AAAAAAAA")),
                game("AAAAAAAA", false),
                StoreOp::Room(meta("BBBBBBBB")),
                game("BBBBBBBB", false),
            ];
            store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
            store.apply(&[&game("BBBBBBBB", true)]).unwrap();
        }
        let store = Store::open(&dir).unwrap();
        let open = store.unfinished().unwrap();
        assert_eq!(open.len(), 1);
        assert_eq!(open[0].meta.code.as_str(), "AAAAAAAA");
        assert_eq!(open[0].record, vec![1, 2, 3]);
        assert_eq!(
            open[0].meta.seats[0].as_ref().unwrap().digest,
            TokenDigest([1; 32])
        );
        assert_eq!(store.all().unwrap().len(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
