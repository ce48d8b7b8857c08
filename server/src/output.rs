//! What a room asks its driver to do, in order, and what the store keeps: the lowest layer
//! of the server's outputs (the hub's own, [`crate::hub::Output`], wrap these).

use crate::ratings::PlayerRating;
use breakshot_shared::protocol::PlayerKey;
use breakshot_shared::protocol::{AimAid, RoomCode, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Seat, Settings, Variant};
use serde::{Deserialize, Serialize};

use crate::secret::TokenDigest;

/// A connection, numbered by the driver.
pub type ConnId = u64;

/// One thing a room asks its driver to do. A room returns them in lists, carried out in
/// order; the hub adds what only it asks for ([`crate::hub::Output`]).
#[derive(Debug)]
pub enum RoomOutput {
    /// Send one message on one connection.
    Send {
        /// The connection; one that is gone already is skipped.
        to: ConnId,
        /// The message, written as one frame.
        msg: ServerMessage,
    },
    /// Close a connection after what was queued for it is sent.
    Close {
        /// The connection to close (with code [`crate::conn::CLOSE_NORMAL`]).
        conn: ConnId,
        /// Sent to the peer as the close reason.
        reason: String,
    },
    /// Store durably. Every `Send` after a `Store` in the same list must wait until the
    /// store is done: that is how nothing is shown before it is safe on disk.
    Store(StoreOp),
}

/// One durable write. The writer commits every operation of a batch in one transaction before
/// it sends any message of that batch.
#[derive(Debug)]
pub enum StoreOp {
    /// A room's lasting facts: settings and who holds the seats (as token digests).
    Room(RoomMeta),
    /// A game begins: its header, an encoded [`breakshot_shared::replay::GameRecord`] with
    /// no entries yet (rules, settings, seed).
    GameStarted {
        /// The room it is played in.
        room: RoomCode,
        /// Its number in the room, from 1; each rematch is the next.
        number: u32,
        /// `GameRecord::encode` of the record with no entries.
        header: Vec<u8>,
    },
    /// One more command of a game: an encoded [`breakshot_shared::replay::RecordEntry`],
    /// `index` counting from 0. Appended; nothing already stored is rewritten.
    Command {
        /// The game's room, as in its `GameStarted`.
        room: RoomCode,
        /// The game's number in the room.
        number: u32,
        /// The command's place in the game's record; rows are appended in this order.
        index: u32,
        /// `RecordEntry::encode`: the command with its shot's hash.
        entry: Vec<u8>,
    },
    /// The game ended (`winner: None` for no winner, or a game abandoned before anyone
    /// could win).
    GameEnded {
        /// The game's room.
        room: RoomCode,
        /// The game's number in the room.
        number: u32,
        /// Who won, if anyone.
        winner: Option<Seat>,
        /// The readable reason, as `GameOver` gave it ("abandoned" when nobody could win).
        reason: String,
    },
    /// The shot clock of a game's current turn: what it has left and whether it runs. The
    /// store keeps the latest only, stamped with its own clock, so a restarted server can
    /// give the player to move what they had left (a running clock less the time since).
    Clock {
        /// The game's room.
        room: RoomCode,
        /// The game's number in the room.
        number: u32,
        /// The turn the clock belongs to.
        turn: u32,
        /// Milliseconds left when this was written.
        left_ms: u64,
        /// Whether the clock was running (both players here) or stopped (one away).
        running: bool,
    },
    /// The room closed on this server: a store shared with other instances lets go of it.
    Released(RoomCode),
    /// A quick-match room: its first game is rated between these players, so a server that
    /// restarts or takes the room over rates it as the one that opened it would have.
    RatedRoom {
        /// The room.
        room: RoomCode,
        /// The players' keys, seat A's first.
        players: [PlayerKey; 2],
    },
    /// A room listed in the lobby (its creator published it), with its players' keys as far
    /// as they are known (seat A's first; seat B's once it is taken), so that a server that
    /// restarts or takes the room over lists it again with their ratings.
    Listed {
        /// The room.
        room: RoomCode,
        /// The players' keys by seat.
        players: [Option<PlayerKey>; 2],
    },
    /// A player's rating after a rated game (kept by key, the latest only).
    Rating {
        /// Who.
        key: PlayerKey,
        /// Their rating now, with the name they played under.
        rating: PlayerRating,
    },
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

/// A taken seat as the store keeps it: its token only as a digest.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StoredSeat {
    /// The player's name as given when taking the seat (1 to 24 characters).
    pub name: String,
    /// SHA-256 of the seat token; a rejoin is checked against it.
    pub digest: TokenDigest,
}

/// A room's lasting facts, stored when it is created and again when seat B is taken.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoomMeta {
    /// The room's code: its key in every table.
    pub code: RoomCode,
    /// The game played: a pool variant, or three-cushion with its race.
    pub variant: Variant,
    /// The rules' settings: calls, shot clock, table.
    pub settings: Settings,
    /// The aim-aid policy the players agreed to (honest clients enforce it).
    pub aim_aid: AimAid,
    /// Seats A and B, in that order; `None` for a seat nobody has taken.
    pub seats: [Option<StoredSeat>; 2],
}
