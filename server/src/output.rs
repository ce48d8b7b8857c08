//! What the sans-IO core asks its driver to do, in order.

use breakshot_shared::protocol::{AimAid, RoomCode, SeatToken, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Seat, Settings, Variant};
use serde::{Deserialize, Serialize};

use crate::secret::TokenDigest;
use crate::work::RoomWork;

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
    /// Ask the store for the room of an unknown seat token, in a store shared with other
    /// server instances: the room may have been left by an instance that stopped. The answer
    /// goes back to [`crate::hub::Hub::claimed`]. Everything before it in the list comes first.
    Claim { conn: ConnId, token: SeatToken },
    /// Run a message through its room away from the hub (see [`crate::work`]): carry out
    /// the outputs the work returns, then give the room back with
    /// [`crate::hub::Hub::returned`]. Everything before it in the list comes first.
    Run(RoomWork),
}

#[derive(Debug)]
pub enum StoreOp {
    /// A room's lasting facts: settings and who holds the seats (as token digests).
    Room(RoomMeta),
    /// A game begins: its header, an encoded [`breakshot_shared::replay::GameRecord`] with
    /// no entries yet (rules, settings, seed).
    GameStarted {
        room: RoomCode,
        number: u32,
        header: Vec<u8>,
    },
    /// One more command of a game: an encoded [`breakshot_shared::replay::RecordEntry`],
    /// `index` counting from 0. Appended; nothing already stored is rewritten.
    Command {
        room: RoomCode,
        number: u32,
        index: u32,
        entry: Vec<u8>,
    },
    /// The game ended (`winner: None` for no winner, or a game abandoned before anyone
    /// could win).
    GameEnded {
        room: RoomCode,
        number: u32,
        winner: Option<Seat>,
        reason: String,
    },
    /// The room closed on this server: a store shared with other instances lets go of it.
    Released(RoomCode),
}

impl StoreOp {
    /// The operations that store `record` as game `number` of `room` from scratch.
    pub fn whole_game(room: &RoomCode, number: u32, record: &GameRecord) -> Vec<StoreOp> {
        let header = GameRecord {
            entries: Vec::new(),
            ..record.clone()
        };
        let mut ops = vec![StoreOp::GameStarted {
            room: room.clone(),
            number,
            header: header.encode(),
        }];
        ops.extend(
            record
                .entries
                .iter()
                .zip(0..)
                .map(|(e, index)| StoreOp::Command {
                    room: room.clone(),
                    number,
                    index,
                    entry: e.encode(),
                }),
        );
        ops
    }
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
