//! The PostgreSQL backend: the same tables as SQLite, in a database that may live on another
//! machine and be shared by several servers' tools (`verify`, replays). Every session asks for
//! `synchronous_commit = on`, so a commit that returned is on the database server's disk
//! whatever its default is. The schema is made and upgraded by the numbered migrations in
//! `server/migrations/postgres/`, one instance at a time (an advisory lock).
//!
//! Several server instances may share one database. Each room is owned by one instance at a
//! time through a session-level advisory lock on the room's code, held on the connection
//! that writes the room's games: nothing is written for a room whose lock this connection
//! does not hold, so two instances never both store (and so never both show) a command of
//! one room. When an instance dies its connection ends and PostgreSQL lets go of its locks;
//! another instance then takes the room over when a player comes back to it. A lock needs no
//! renewing and cannot outlive the connection it fences, which a lease in a table would have
//! to be checked for on every write.

use std::cell::RefCell;
use std::collections::BTreeSet;

use crate::ratings::PlayerRating;
use breakshot_shared::protocol::PlayerKey;
use breakshot_shared::protocol::RoomCode;
use postgres::{Client, NoTls, Statement};

use super::{
    assemble, decode_meta, encode_meta, listed_players, rated_players, seat_number, seat_of,
    stored_format, unix_millis, unix_now, Claim, EndedGame, StoreError, StoredClock, StoredGame,
};
use crate::output::StoreOp;
use crate::secret::TokenDigest;

/// The migrations, in order: version n is the n-th.
const MIGRATIONS: &[&str] = &[
    include_str!("../../migrations/postgres/0001_games.sql"),
    include_str!("../../migrations/postgres/0002_seats.sql"),
    include_str!("../../migrations/postgres/0003_clocks.sql"),
    include_str!("../../migrations/postgres/0004_ratings.sql"),
    include_str!("../../migrations/postgres/0005_rated_rooms.sql"),
    include_str!("../../migrations/postgres/0006_listed_rooms.sql"),
];

/// The advisory lock key under which the schema is migrated ("BRKSHOT" in ASCII).
const MIGRATION_LOCK: i64 = 0x0042_524b_5348_4f54;

/// The statements a write uses, prepared once per connection.
struct Writes {
    room: Statement,
    game: Statement,
    clear: Statement,
    command: Statement,
    ended: Statement,
    seat: Statement,
    clock: Statement,
    rating: Statement,
    rated_room: Statement,
    listed_room: Statement,
}

pub(super) struct PgStore {
    // The reads take `&self` like SQLite's; one connection serves them one at a time.
    db: RefCell<Client>,
    writes: Writes,
    /// The rooms whose advisory lock this connection holds.
    owned: RefCell<BTreeSet<String>>,
}

/// A room's advisory lock key: its code's bytes (8 letters or digits) as one number, so no
/// two rooms share a lock. The migration lock's key starts with a zero byte, which no
/// code does.
fn room_key(code: &str) -> i64 {
    let mut bytes = [0u8; 8];
    for (b, c) in bytes.iter_mut().rev().zip(code.bytes().rev()) {
        *b = c;
    }
    i64::from_be_bytes(bytes)
}

fn int(n: u32) -> i64 {
    i64::from(n)
}

fn millis_int(ms: u64) -> i64 {
    i64::try_from(ms).unwrap_or(i64::MAX)
}

impl PgStore {
    pub(super) fn connect(url: &str) -> Result<PgStore, StoreError> {
        let mut db = Client::connect(url, NoTls)?;
        db.batch_execute("SET synchronous_commit = on")?;
        // The rooms' locks last as long as this session: when this server's machine or its
        // network dies, the database ends the session (and frees the rooms) once the
        // connection has been silent for about 25 s, instead of the system's default of hours.
        // Unix-socket sessions ignore these, and a process that dies closes its socket at once.
        db.batch_execute(
            "SET tcp_keepalives_idle = 10; SET tcp_keepalives_interval = 5;
             SET tcp_keepalives_count = 3; SET tcp_user_timeout = 25000",
        )?;
        migrate(&mut db)?;
        let writes = Writes {
            room: db.prepare(
                "INSERT INTO rooms (code, meta) VALUES ($1, $2)
                 ON CONFLICT (code) DO UPDATE SET meta = excluded.meta",
            )?,
            game: db.prepare(
                "INSERT INTO games (room, number, header, finished) VALUES ($1, $2, $3, FALSE)
                 ON CONFLICT (room, number) DO UPDATE
                 SET header = excluded.header, finished = FALSE, winner = NULL,
                     reason = NULL, finished_at = NULL",
            )?,
            clear: db.prepare("DELETE FROM commands WHERE room = $1 AND number = $2")?,
            command: db.prepare(
                "INSERT INTO commands (room, number, idx, entry) VALUES ($1, $2, $3, $4)",
            )?,
            ended: db.prepare(
                "UPDATE games SET finished = TRUE, winner = $3, reason = $4, finished_at = $5
                 WHERE room = $1 AND number = $2",
            )?,
            seat: db.prepare(
                "INSERT INTO seats (digest, room) VALUES ($1, $2) ON CONFLICT (digest) DO NOTHING",
            )?,
            clock: db.prepare(
                "INSERT INTO clocks (room, number, turn, left_ms, running, at_ms)
                 VALUES ($1, $2, $3, $4, $5, $6)
                 ON CONFLICT (room, number) DO UPDATE
                 SET turn = excluded.turn, left_ms = excluded.left_ms,
                     running = excluded.running, at_ms = excluded.at_ms",
            )?,
            rating: db.prepare(
                "INSERT INTO ratings (player, name, rating, deviation, volatility, games)
                 VALUES ($1, $2, $3, $4, $5, $6)
                 ON CONFLICT (player) DO UPDATE
                 SET name = excluded.name, rating = excluded.rating,
                     deviation = excluded.deviation, volatility = excluded.volatility,
                     games = excluded.games",
            )?,
            rated_room: db.prepare(
                "INSERT INTO rated_rooms (code, player_a, player_b) VALUES ($1, $2, $3)
                 ON CONFLICT (code) DO NOTHING",
            )?,
            listed_room: db.prepare(
                "INSERT INTO listed_rooms (code, player_a, player_b) VALUES ($1, $2, $3)
                 ON CONFLICT (code) DO UPDATE
                 SET player_a = excluded.player_a, player_b = excluded.player_b",
            )?,
        };
        Ok(PgStore {
            db: RefCell::new(db),
            writes,
            owned: RefCell::new(BTreeSet::new()),
        })
    }

    /// Takes the room's lock unless this connection holds it already; `false` if another
    /// instance holds it.
    fn own(&self, room: &str) -> Result<bool, StoreError> {
        if self.owned.borrow().contains(room) {
            return Ok(true);
        }
        let got: bool = self
            .db
            .borrow_mut()
            .query_one("SELECT pg_try_advisory_lock($1)", &[&room_key(room)])?
            .get(0);
        if got {
            self.owned.borrow_mut().insert(room.to_string());
        }
        Ok(got)
    }

    fn release(&self, room: &str) -> Result<(), StoreError> {
        if self.owned.borrow_mut().remove(room) {
            self.db
                .borrow_mut()
                .execute("SELECT pg_advisory_unlock($1)", &[&room_key(room)])?;
        }
        Ok(())
    }

    pub(super) fn apply(&mut self, ops: &[&StoreOp]) -> Result<(), StoreError> {
        // Every room written must be this instance's: the locks are taken before the
        // transaction (a session lock outlives it either way).
        for op in ops {
            let room = match op {
                StoreOp::Room(meta) => &meta.code,
                StoreOp::GameStarted { room, .. }
                | StoreOp::Command { room, .. }
                | StoreOp::GameEnded { room, .. }
                | StoreOp::Clock { room, .. }
                | StoreOp::RatedRoom { room, .. }
                | StoreOp::Listed { room, .. } => room,
                StoreOp::Released(_) | StoreOp::Rating { .. } => continue,
            };
            if !self.own(room.as_str())? {
                return Err(StoreError::OwnedElsewhere(room.to_string()));
            }
        }
        let w = &self.writes;
        let mut tx = self.db.get_mut().transaction()?;
        for op in ops {
            match op {
                StoreOp::Room(meta) => {
                    tx.execute(&w.room, &[&meta.code.as_str(), &encode_meta(meta)?])?;
                    for seat in meta.seats.iter().flatten() {
                        tx.execute(&w.seat, &[&seat.digest.0.as_slice(), &meta.code.as_str()])?;
                    }
                }
                StoreOp::GameStarted {
                    room,
                    number,
                    header,
                } => {
                    tx.execute(&w.game, &[&room.as_str(), &int(*number), header])?;
                    tx.execute(&w.clear, &[&room.as_str(), &int(*number)])?;
                }
                StoreOp::Command {
                    room,
                    number,
                    index,
                    entry,
                } => {
                    tx.execute(
                        &w.command,
                        &[&room.as_str(), &int(*number), &int(*index), entry],
                    )?;
                }
                StoreOp::GameEnded {
                    room,
                    number,
                    winner,
                    reason,
                } => {
                    let at = i64::try_from(unix_now()).unwrap_or(i64::MAX);
                    tx.execute(
                        &w.ended,
                        &[
                            &room.as_str(),
                            &int(*number),
                            &winner.map(seat_number),
                            reason,
                            &at,
                        ],
                    )?;
                }
                StoreOp::Clock {
                    room,
                    number,
                    turn,
                    left_ms,
                    running,
                } => {
                    tx.execute(
                        &w.clock,
                        &[
                            &room.as_str(),
                            &int(*number),
                            &int(*turn),
                            &millis_int(*left_ms),
                            running,
                            &millis_int(unix_millis()),
                        ],
                    )?;
                }
                StoreOp::Released(_) => {}
                StoreOp::RatedRoom { room, players } => {
                    let [a, b] = players.map(|k| k.0.to_vec());
                    tx.execute(&w.rated_room, &[&room.as_str(), &a, &b])?;
                }
                StoreOp::Listed { room, players } => {
                    let [a, b] = players.map(|k| k.map(|k| k.0.to_vec()));
                    tx.execute(&w.listed_room, &[&room.as_str(), &a, &b])?;
                }
                StoreOp::Rating { key, rating } => {
                    tx.execute(
                        &w.rating,
                        &[
                            &key.0.as_slice(),
                            &rating.name,
                            &rating.rating,
                            &rating.deviation,
                            &rating.volatility,
                            &int(rating.games),
                        ],
                    )?;
                }
            }
        }
        tx.commit()?;
        // Let go only once what the room's last batch says is committed, so whoever takes
        // the room next reads all of it.
        for op in ops {
            if let StoreOp::Released(room) = op {
                self.release(room.as_str())?;
            }
        }
        Ok(())
    }

    /// Every player's rating.
    pub(super) fn ratings(&self) -> Result<Vec<(PlayerKey, PlayerRating)>, StoreError> {
        let rows = self.db.borrow_mut().query(
            "SELECT player, name, rating, deviation, volatility, games FROM ratings",
            &[],
        )?;
        let mut out = Vec::new();
        for row in rows {
            let key: Vec<u8> = row.get(0);
            let games: i64 = row.get(5);
            // A row that is no key is skipped rather than trusted.
            if let Ok(key) = <[u8; 32]>::try_from(key.as_slice()) {
                out.push((
                    PlayerKey(key),
                    PlayerRating {
                        name: row.get(1),
                        rating: row.get(2),
                        deviation: row.get(3),
                        volatility: row.get(4),
                        games: u32::try_from(games).unwrap_or(0),
                    },
                ));
            }
        }
        Ok(out)
    }

    /// The unfinished games of rooms no other instance owns, taking them.
    pub(super) fn unfinished(&self) -> Result<Vec<StoredGame>, StoreError> {
        let mut out = Vec::new();
        for game in self.games(false, None)? {
            if self.own(game.meta.code.as_str())? {
                out.push(game);
            }
        }
        Ok(out)
    }

    /// The room of a seat token, taken from an instance that let go of it (or stopped).
    pub(super) fn claim(&self, seat: &TokenDigest) -> Result<Claim, StoreError> {
        let room = self.db.borrow_mut().query_opt(
            "SELECT room FROM seats WHERE digest = $1",
            &[&seat.0.as_slice()],
        )?;
        let Some(room) = room.map(|r| r.get::<_, String>(0)) else {
            return Ok(Claim::NotFound);
        };
        if self.owned.borrow().contains(&room) {
            // Already here: the room was brought back by an earlier claim.
            return Ok(Claim::NotFound);
        }
        if !self.own(&room)? {
            return Ok(Claim::Elsewhere);
        }
        if let Some(game) = self.games(false, Some(&room))?.pop() {
            return Ok(Claim::Taken(Box::new(game)));
        }
        // The game is over: nothing to own, but its player may learn how it ended.
        self.release(&room)?;
        Ok(match self.ended_since(0, Some(&room))?.pop() {
            Some(ended) => Claim::Ended(Box::new(ended)),
            None => Claim::NotFound,
        })
    }

    /// Every game (`all`) or the unfinished ones, of one room or of all, in room and game
    /// order.
    pub(super) fn games(
        &self,
        all: bool,
        room: Option<&str>,
    ) -> Result<Vec<StoredGame>, StoreError> {
        let rows = self.db.borrow_mut().query(
            "SELECT r.code, r.meta, g.number, g.header, g.finished,
                    c.turn, c.left_ms, c.running, c.at_ms, q.player_a, q.player_b,
                    l.code, l.player_a, l.player_b
             FROM games g JOIN rooms r ON r.code = g.room
             LEFT JOIN clocks c ON c.room = g.room AND c.number = g.number
             LEFT JOIN rated_rooms q ON q.code = g.room
             LEFT JOIN listed_rooms l ON l.code = g.room
             WHERE ($1 OR NOT g.finished) AND ($2::TEXT IS NULL OR g.room = $2)
             ORDER BY g.room COLLATE \"C\", g.number",
            &[&all, &room],
        )?;
        let mut out = Vec::new();
        for row in rows {
            let code: String = row.get(0);
            let number = game_number(row.get(2));
            let header: Vec<u8> = row.get(3);
            let record = assemble(&header, self.entries(&code, number)?);
            let meta =
                decode_meta(row.get(1)).map_err(|why| StoreError::Meta { room: code, why })?;
            let clock = match (
                row.get::<_, Option<i64>>(5),
                row.get::<_, Option<i64>>(6),
                row.get::<_, Option<bool>>(7),
                row.get::<_, Option<i64>>(8),
            ) {
                (Some(turn), Some(left_ms), Some(running), Some(at_ms)) => Some(StoredClock {
                    turn: u32::try_from(turn).unwrap_or(u32::MAX),
                    left_ms: u64::try_from(left_ms).unwrap_or(0),
                    running,
                    at_ms: u64::try_from(at_ms).unwrap_or(0),
                }),
                _ => None,
            };
            out.push(StoredGame {
                meta,
                number,
                record,
                finished: row.get(4),
                format: stored_format(&header),
                clock,
                rated: rated_players(row.get(9), row.get(10)),
                listed: listed_players(row.get(11), row.get(12), row.get(13)),
            });
        }
        Ok(out)
    }

    /// The latest game of each room (or of one) if it ended at `since` or later.
    pub(super) fn ended_since(
        &self,
        since: u64,
        room: Option<&str>,
    ) -> Result<Vec<EndedGame>, StoreError> {
        let since = i64::try_from(since).unwrap_or(i64::MAX);
        let rows = self.db.borrow_mut().query(
            "SELECT r.code, r.meta, g.number, g.winner, g.reason, g.finished_at
             FROM games g JOIN rooms r ON r.code = g.room
             WHERE g.finished AND g.finished_at >= $1
               AND ($2::TEXT IS NULL OR g.room = $2)
               AND g.number = (SELECT MAX(number) FROM games WHERE room = g.room)
             ORDER BY g.finished_at",
            &[&since, &room],
        )?;
        rows.into_iter()
            .map(|row| {
                let code: String = row.get(0);
                let meta =
                    decode_meta(row.get(1)).map_err(|why| StoreError::Meta { room: code, why })?;
                Ok(EndedGame {
                    meta,
                    number: game_number(row.get(2)),
                    winner: row.get::<_, Option<i64>>(3).and_then(seat_of),
                    reason: row.get::<_, Option<String>>(4).unwrap_or_default(),
                    at: u64::try_from(row.get::<_, i64>(5)).unwrap_or(0),
                })
            })
            .collect()
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
    fn game_column<T: for<'a> postgres::types::FromSql<'a>>(
        &self,
        column: &'static str,
        room: &str,
        number: u32,
    ) -> Result<Option<T>, StoreError> {
        let row = self.db.borrow_mut().query_opt(
            &format!("SELECT {column} FROM games WHERE room = $1 AND number = $2"),
            &[&room, &int(number)],
        )?;
        Ok(row.map(|r| r.get(0)))
    }

    /// The latest game of `room`: (number, finished).
    pub(super) fn latest_game(&self, room: &str) -> Result<Option<(u32, bool)>, StoreError> {
        let latest = self.db.borrow_mut().query_opt(
            "SELECT number, finished FROM games WHERE room = $1 ORDER BY number DESC LIMIT 1",
            &[&room],
        )?;
        Ok(latest.map(|row| (game_number(row.get(0)), row.get(1))))
    }

    pub(super) fn overwrite_record(
        &self,
        room: &RoomCode,
        number: u32,
        record: &[u8],
    ) -> Result<bool, StoreError> {
        let mut db = self.db.borrow_mut();
        let mut tx = db.transaction()?;
        let n = tx.execute(
            "UPDATE games SET header = $3 WHERE room = $1 AND number = $2",
            &[&room.as_str(), &int(number), &record],
        )?;
        tx.execute(
            "DELETE FROM commands WHERE room = $1 AND number = $2",
            &[&room.as_str(), &int(number)],
        )?;
        tx.commit()?;
        Ok(n == 1)
    }

    /// A game's command rows, in order.
    pub(super) fn entries(&self, room: &str, number: u32) -> Result<Vec<Vec<u8>>, StoreError> {
        let rows = self.db.borrow_mut().query(
            "SELECT entry FROM commands WHERE room = $1 AND number = $2 ORDER BY idx",
            &[&room, &int(number)],
        )?;
        Ok(rows.into_iter().map(|r| r.get(0)).collect())
    }
}

/// A stored game number (written from a `u32`).
fn game_number(n: i64) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// Brings the schema up to this build's, in one transaction under an advisory lock: of
/// several instances starting at once, one migrates and the others then find nothing to do.
fn migrate(db: &mut Client) -> Result<(), StoreError> {
    let known = i64::try_from(MIGRATIONS.len()).unwrap_or(i64::MAX);
    let mut tx = db.transaction()?;
    tx.execute("SELECT pg_advisory_xact_lock($1)", &[&MIGRATION_LOCK])?;
    tx.batch_execute("CREATE TABLE IF NOT EXISTS breakshot_schema (version BIGINT NOT NULL)")?;
    let found: i64 = tx
        .query_one(
            "SELECT COALESCE(MAX(version), 0) FROM breakshot_schema",
            &[],
        )?
        .get(0);
    if found > known {
        return Err(StoreError::Schema { found, known });
    }
    for (version, sql) in (1..).zip(MIGRATIONS) {
        if version > found {
            tx.batch_execute(sql)?;
            tx.execute(
                "INSERT INTO breakshot_schema (version) VALUES ($1)",
                &[&version],
            )?;
        }
    }
    tx.commit()?;
    Ok(())
}
