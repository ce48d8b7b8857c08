//! The messages, client to server and server to client. One bidirectional QUIC stream per
//! client carries them as frames (see [`super::framing`]); the client speaks first with
//! [`ClientMessage::Hello`].

use serde::{Deserialize, Serialize};

use super::ids::{RoomCode, SeatToken};
use crate::physics::{BallState, Strike};
use crate::rules::{Choice, Command, Game, Seat, Settings, TurnId, Variant};

/// Which drawing aids the room's players are allowed. The server cannot see a player's
/// screen: this is an agreement that honest clients enforce, shown to everyone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum AimAid {
    /// No aim line at all.
    Off,
    /// The cue ball's path to its first contact.
    FirstContact,
    /// Full predicted paths of the cue ball and the first object ball.
    Full,
}

/// Client to server.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ClientMessage {
    /// The first message of every connection.
    Hello {
        protocol: u32,
        /// [`super::reference::reference_hash`] as the client computes it.
        physics: u64,
    },
    /// Opens a room and takes seat A in it. `mode` holds the room's settings (calling every
    /// shot, shot clock).
    CreateRoom {
        variant: Variant,
        mode: Settings,
        aim_aid: AimAid,
        name: String,
    },
    /// Takes the free seat of a room.
    Join { room: RoomCode, name: String },
    /// Takes back a seat after a dropped connection or a server restart.
    Rejoin { token: SeatToken },
    /// Watches a room without a seat.
    Spectate { room: RoomCode },
    /// Strikes the cue ball. `turn` is the turn the shooter saw; a stale turn is refused.
    Shot {
        turn: TurnId,
        strike: Strike,
        /// The pocket called for this shot; if `None`, the last [`ClientMessage::CallPocket`]
        /// of this turn stands.
        call: Option<u8>,
    },
    /// Places the cue ball when in hand (scene coordinates).
    PlaceCueBall { turn: TurnId, pos: [f64; 2] },
    /// Announces the pocket for the coming shot, so the opponent sees it before the strike.
    CallPocket { turn: TurnId, pocket: u8 },
    /// Answers a choice the rules offer (after an illegal break, a push-out, ...).
    Decide { turn: TurnId, choice: Choice },
    /// Gives up the game.
    Concede,
    /// Asks for another game in the same room (the other player must ask too).
    Rematch,
    /// A line of chat for the room.
    Chat { text: String },
    /// Asks for the record of the room's latest game, finished or not, to watch it again.
    /// Needs no seat and may be sent at any time after `Welcome`: like spectating, a record
    /// is open to whoever knows the room code. Answered by [`ServerMessage::Record`].
    FetchRecord { room: RoomCode },
    /// Where the shooter is aiming now, shown live to the others in the room. Sent at most
    /// a few times a second; the server relays it and keeps nothing.
    Aim { turn: TurnId, strike: Strike },
}

/// What a connection is in a room.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Role {
    Player(Seat),
    Spectator,
}

/// One seat as others see it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeatView {
    pub name: String,
    pub connected: bool,
    /// While disconnected: milliseconds left before the game is forfeited.
    pub reconnect_ms: Option<u64>,
}

/// Everything a client needs to show a room from scratch (on join, rejoin and rematch).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    pub room: RoomCode,
    /// Games played in this room so far, this one included.
    pub game_number: u32,
    pub game: Game,
    pub seats: [Option<SeatView>; 2],
    pub aim_aid: AimAid,
    /// The pocket called for the current turn, if any.
    pub called: Option<u8>,
    /// Milliseconds left on the shot clock, if the room has one and it is running.
    pub shot_clock_ms: Option<u64>,
}

/// The rules' judgement of an accepted command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ruling {
    pub foul: bool,
    /// Readable reasons, in the order the rules found them.
    pub reasons: Vec<String>,
    /// Balls pocketed by a shot: (ball number, pocket index).
    pub pocketed: Vec<(u8, u8)>,
    /// Who plays next.
    pub next: Seat,
}

/// Machine-readable error codes; each [`ServerMessage::Error`] also carries a readable text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ErrorCode {
    /// The message is not valid here (before Hello, twice, outside a room, ...).
    Unexpected,
    /// A number is not finite, out of range, or a text too long.
    Invalid,
    NoSuchRoom,
    RoomFull,
    BadToken,
    NotYourTurn,
    /// The command answers a turn that is over.
    StaleTurn,
    /// The rules refuse the command.
    Illegal,
    Spectator,
    RateLimited,
    GameOver,
    ServerBusy,
    /// The answer would not fit in one frame (a stored record beyond
    /// [`super::limits::MAX_SENT_RECORD`]).
    TooLarge,
}

/// Server to client.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ServerMessage {
    /// The handshake succeeded.
    Welcome {
        protocol: u32,
    },
    /// The handshake failed; the server closes the connection after this.
    Reject {
        reason: String,
    },
    /// The connection is now in a room. `token` is sent once, to the player who took the
    /// seat (and again on rejoin).
    Joined {
        role: Role,
        token: Option<SeatToken>,
        snapshot: Box<Snapshot>,
    },
    /// A new game started in the room (a rematch).
    GameStarted {
        snapshot: Box<Snapshot>,
    },
    /// The other seat was taken.
    PlayerJoined {
        seat: Seat,
        name: String,
    },
    /// The shooter called a pocket for this turn.
    PocketCalled {
        turn: TurnId,
        seat: Seat,
        pocket: u8,
    },
    /// A shot was accepted: sent to everyone at once so each starts simulating it.
    ShotAccepted {
        turn: TurnId,
        seat: Seat,
        command: Command,
    },
    /// The server's own simulation of the accepted shot.
    ShotResolved {
        turn: TurnId,
        hash: u64,
        balls: Vec<BallState>,
        ruling: Ruling,
    },
    /// A command other than a shot (placing the cue ball, a decision, a concession, the
    /// shot clock running out) was applied.
    Applied {
        turn: TurnId,
        seat: Seat,
        command: Command,
        ruling: Ruling,
    },
    /// The table is ready for the next command.
    TurnChanged {
        turn: TurnId,
        to_move: Seat,
        shot_clock_ms: Option<u64>,
    },
    /// A player dropped; their seat is held for `reconnect_ms` milliseconds.
    PlayerLeft {
        seat: Seat,
        reconnect_ms: u64,
    },
    PlayerBack {
        seat: Seat,
    },
    GameOver {
        winner: Option<Seat>,
        reason: String,
    },
    RematchOffered {
        seat: Seat,
    },
    Chat {
        from: String,
        text: String,
    },
    Error {
        code: ErrorCode,
        message: String,
    },
    /// The answer to [`ClientMessage::FetchRecord`]: the room's latest game (numbered from 1)
    /// as it is stored, an encoded [`crate::replay::GameRecord`] holding every command
    /// applied so far.
    Record {
        room: RoomCode,
        game: u32,
        finished: bool,
        record: Vec<u8>,
    },
    /// The answer to a [`ClientMessage::Rejoin`] whose game ended while the player was away
    /// (their room may be closed, or the server restarted since): the game's result, for the
    /// seat the token held. The connection is left out of any room; the game is over for
    /// this player.
    GameFinished {
        room: RoomCode,
        /// The game's number in its room, from 1.
        game: u32,
        seat: Seat,
        winner: Option<Seat>,
        reason: String,
    },
    /// The shooter's aim on `turn`, relayed from its [`ClientMessage::Aim`].
    Aim {
        turn: TurnId,
        seat: Seat,
        strike: Strike,
    },
}

/// Turns a player's message into the rules command it asks for (with the turn it
/// answers), if it is one.
pub fn command_of(msg: &ClientMessage, called: Option<u8>) -> Option<(Option<TurnId>, Command)> {
    match msg {
        ClientMessage::Shot { turn, strike, call } => Some((
            Some(*turn),
            Command::Shot {
                strike: *strike,
                call: call.or(called),
            },
        )),
        ClientMessage::PlaceCueBall { turn, pos } => {
            Some((Some(*turn), Command::PlaceCueBall { pos: *pos }))
        }
        ClientMessage::Decide { turn, choice } => Some((Some(*turn), Command::Decide(*choice))),
        ClientMessage::Concede => Some((None, Command::Concede)),
        _ => None,
    }
}
