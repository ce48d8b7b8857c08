//! What the sans-IO core asks its driver to do, in order.

use breakshot_shared::protocol::{AimAid, RoomCode, ServerMessage};
use breakshot_shared::rules::{Settings, Variant};
use serde::{Deserialize, Serialize};

use crate::secret::TokenDigest;

/// A connection, numbered by the driver.
pub type ConnId = u64;

#[derive(Debug)]
pub enum Output {
    /// Send one message on one connection.
    Send { to: ConnId, msg: ServerMessage },
    /// Close a connection after what was queued for it is sent.
    Close { conn: ConnId, reason: String },
    /// Store durably. Every `Send` after a `Store` in the same list must wait until the
    /// store is done: that is how nothing is shown before it is safe on disk.
    Store(StoreOp),
    /// Send `to` the stored record of `room`'s latest game (or an error). The writer reads
    /// it after committing every earlier store operation, so it holds every result already
    /// sent.
    SendRecord { to: ConnId, room: RoomCode },
}

#[derive(Debug)]
pub enum StoreOp {
    /// A room's lasting facts: settings and who holds the seats (as token digests).
    Room(RoomMeta),
    /// One game's record (encoded [`breakshot_shared::replay::GameRecord`]), replaced whole.
    Game {
        room: RoomCode,
        number: u32,
        record: Vec<u8>,
        finished: bool,
    },
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StoredSeat {
    pub name: String,
    pub digest: TokenDigest,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoomMeta {
    pub code: RoomCode,
    pub variant: Variant,
    pub settings: Settings,
    pub aim_aid: AimAid,
    pub seats: [Option<StoredSeat>; 2],
}
