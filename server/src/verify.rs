//! Offline verification: re-simulate every stored game and check every recorded hash.

use std::path::Path;

use breakshot_shared::protocol::RoomCode;
use breakshot_shared::replay::Verified;

use crate::store::{Location, Store, StoreError, DB_FILE};

/// The verdict on one stored game.
#[derive(Debug)]
pub struct GameCheck {
    /// The room's code.
    pub room: RoomCode,
    /// The game's number in its room, from 1.
    pub number: u32,
    /// Commands in its record (0 if the record is unreadable).
    pub commands: usize,
    /// Whether the game's end is stored.
    pub finished: bool,
    /// `Err` names the first command whose replay differs (or why the record is unreadable).
    pub result: Result<(), String>,
    /// What was checked, when it was not a replay of every shot: for a game recorded with
    /// other physics, "recorded with physics N; this build plays M" and that its chain of
    /// hashes was checked as stored.
    pub note: Option<String>,
    /// The players' names as the record keeps them (seats A and B).
    pub players: [Option<String>; 2],
}

/// Checks every game stored in `dir`.
pub fn verify_dir(dir: &Path) -> Result<Vec<GameCheck>, StoreError> {
    if !dir.join(DB_FILE).exists() {
        return Err(StoreError::Sql(rusqlite::Error::InvalidPath(
            dir.join(DB_FILE),
        )));
    }
    verify_store(&Location::Sqlite(dir.to_path_buf()))
}

/// Checks every game in a store (SQLite or PostgreSQL).
pub fn verify_store(location: &Location) -> Result<Vec<GameCheck>, StoreError> {
    let store = Store::at(location)?;
    Ok(store
        .all()?
        .into_iter()
        .map(|g| {
            let (commands, players, verified) = match g.record {
                Ok(record) => (
                    record.entries.len(),
                    record.players.clone(),
                    record.verify().map_err(|e| e.to_string()),
                ),
                Err(e) => (0, [None, None], Err(format!("unreadable record: {e}"))),
            };
            let note = match &verified {
                Ok(v @ Verified::OtherPhysics { .. }) => Some(v.describe()),
                _ => None,
            };
            GameCheck {
                room: g.meta.code,
                number: g.number,
                commands,
                finished: g.finished,
                result: verified.map(|_| ()),
                note,
                players,
            }
        })
        .collect())
}
