//! The messages, client to server and server to client. One bidirectional QUIC stream per
//! client carries them as frames (see [`super::framing`]); the client speaks first with
//! [`ClientMessage::Hello`], the server answers [`ServerMessage::Challenge`], the client
//! proves its key with [`ClientMessage::Prove`] and the server says [`ServerMessage::Welcome`].

use serde::{Deserialize, Serialize};

use super::ids::{RoomCode, SeatToken};
use super::lobby::{GameInPlay, RatedPlayer, WaitingRoom};
use crate::physics::Strike;
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
    /// Full paths, and the computer's advice on the table for any player who asks (I / J).
    /// Last, so the rooms stored with the others keep their encoding.
    Advice,
}

/// Client to server.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ClientMessage {
    /// The first message of every connection.
    Hello {
        /// The client's [`super::PROTOCOL_VERSION`]; the server refuses any other.
        protocol: u32,
        /// [`super::reference::reference_hash`] as the client computes it.
        physics: u64,
        /// The player's Ed25519 public key, [`super::identity::PUBLIC_KEY_LEN`] bytes: who
        /// the player is on this server ([`super::identity`]).
        key: Vec<u8>,
    },
    /// The answer to [`ServerMessage::Challenge`]: the key's signature over
    /// [`super::identity::signed_message`], [`super::identity::SIGNATURE_LEN`] bytes.
    Prove {
        /// The Ed25519 signature.
        signature: Vec<u8>,
    },
    /// Opens a room and takes seat A in it. `mode` holds the room's settings (calling every
    /// shot, shot clock).
    CreateRoom {
        /// The game the room plays (8-ball, 9-ball, practice, three-cushion).
        variant: Variant,
        /// The rules' settings; the table must suit the variant.
        mode: Settings,
        /// The aim-aid policy agreed for the room, shown to everyone.
        aim_aid: AimAid,
        /// The creator's name as others see it: 1 to 24 printable characters.
        name: String,
    },
    /// Takes the free seat of a room.
    Join {
        /// The room's code, as the invite gives it.
        room: RoomCode,
        /// The joining player's name: 1 to 24 printable characters.
        name: String,
    },
    /// Takes back a seat after a dropped connection or a server restart.
    Rejoin {
        /// The secret the server gave with [`ServerMessage::Joined`] for this seat.
        token: SeatToken,
    },
    /// Watches a room without a seat.
    Spectate {
        /// The room to watch.
        room: RoomCode,
    },
    /// Strikes the cue ball. `turn` is the turn the shooter saw; a stale turn is refused.
    Shot {
        /// The [`TurnId`] the shooter saw; any other is refused as `StaleTurn`.
        turn: TurnId,
        /// The cue's strike; checked and its aim normalised before the server simulates it.
        strike: Strike,
        /// The pocket called for this shot; if `None`, the last [`ClientMessage::CallPocket`]
        /// of this turn stands.
        call: Option<u8>,
    },
    /// Places the cue ball when in hand (scene coordinates).
    PlaceCueBall {
        /// The turn the player saw.
        turn: TurnId,
        /// Where the cue ball's centre goes (m, scene coordinates: origin at a corner).
        pos: [f64; 2],
    },
    /// Announces the pocket for the coming shot, so the opponent sees it before the strike.
    CallPocket {
        /// The turn the shooter saw.
        turn: TurnId,
        /// Index into the table's pockets, 0..6.
        pocket: u8,
    },
    /// Answers a choice the rules offer (after an illegal break, a push-out, ...).
    Decide {
        /// The turn the player saw.
        turn: TurnId,
        /// One of the options the current phase offers.
        choice: Choice,
    },
    /// Gives up the game.
    Concede,
    /// Asks for another game in the same room (the other player must ask too).
    Rematch,
    /// A line of chat for the room.
    Chat {
        /// The line: 1 to 200 printable characters.
        text: String,
    },
    /// Asks for the record of one of the room's games, finished or not, to watch it again.
    /// Needs no seat and may be sent at any time after `Welcome`: like spectating, a record
    /// is open to whoever knows the room code. Answered by [`ServerMessage::Record`].
    FetchRecord {
        /// The room whose game is wanted.
        room: RoomCode,
        /// The game's number in the room, from 1; `None` for the latest.
        game: Option<u32>,
    },
    /// Where the shooter is aiming now, shown live to the others in the room. Sent at most
    /// a few times a second; the server relays it and keeps nothing.
    Aim {
        /// The turn being aimed; an aim out of turn is dropped.
        turn: TurnId,
        /// The strike as it stands now, checked like a shot's.
        strike: Strike,
    },
    /// Lists the room this player created, while it waits for its second player, in the
    /// lobby (it is private, reached by its invite alone, until then). Answered by
    /// [`ServerMessage::Published`].
    Publish,
    /// Asks for a page (from 0) of the lobby: public rooms waiting for a player and listed
    /// games in play. Rate-limited. Answered by [`ServerMessage::Games`].
    ListGames {
        /// The page, from 0.
        page: u32,
    },
    /// Waits in the quick-match queue of this variant and settings to be paired with a
    /// player of a near rating; answered by [`ServerMessage::Queued`], then `Joined` when
    /// a match is found (a rated game), or [`ServerMessage::Unqueued`].
    QuickMatch {
        /// The game wanted.
        variant: Variant,
        /// Its settings; players are paired only with the same.
        mode: Settings,
        /// The player's display name: 1 to 24 printable characters.
        name: String,
    },
    /// Leaves the quick-match queue.
    LeaveQueue,
    /// Asks for a page (from 0) of the leaderboard. Rate-limited like `ListGames`.
    Leaderboard {
        /// The page, from 0.
        page: u32,
    },
    /// The client's own simulation of a shot ended on another hash than the server's: counted
    /// for the operator (`breakshot_desyncs_reported_total`), never answered.
    ReportDesync {
        /// The turn of the shot.
        turn: TurnId,
        /// The server's hash for it, which the client's own simulation did not reach.
        hash: u64,
    },
}

impl ClientMessage {
    /// The message a player sends for `command` on `turn`; None for a command only the rules
    /// themselves make (the shot clock, a forfeit) or only practice allows. Whoever chooses a
    /// move (a person, the computer) speaks in rules' commands; this is where they become
    /// the wire's.
    pub fn for_command(turn: TurnId, command: Command) -> Option<ClientMessage> {
        Some(match command {
            Command::Shot { strike, call } => ClientMessage::Shot { turn, strike, call },
            Command::PlaceCueBall { pos } => ClientMessage::PlaceCueBall { turn, pos },
            Command::Decide(choice) => ClientMessage::Decide { turn, choice },
            Command::Concede => ClientMessage::Concede,
            _ => return None,
        })
    }
}

/// What a connection is in a room.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Role {
    /// Holds this seat and may send its commands.
    Player(Seat),
    /// Watches: receives everything the players do, but cannot act on the game.
    Spectator,
}

/// One seat as others see it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeatView {
    /// The name the player chose.
    pub name: String,
    /// Whether the player's connection is up now.
    pub connected: bool,
    /// While disconnected: milliseconds left before the game is forfeited.
    pub reconnect_ms: Option<u64>,
}

/// Everything a client needs to show a room from scratch (on join, rejoin and rematch).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// The room's code.
    pub room: RoomCode,
    /// Games played in this room so far, this one included.
    pub game_number: u32,
    /// The whole game: rules, settings, balls, phase and the player to move.
    pub game: Game,
    /// Seats A and B, in that order; `None` while a seat has not been taken.
    pub seats: [Option<SeatView>; 2],
    /// The room's aim-aid policy.
    pub aim_aid: AimAid,
    /// The pocket called for the current turn, if any.
    pub called: Option<u8>,
    /// Milliseconds left on the shot clock, if the room has one and it is running.
    pub shot_clock_ms: Option<u64>,
}

/// The rules' judgement of an accepted command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ruling {
    /// Whether the rules called a foul.
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
    /// No open room has this code (for `FetchRecord`: no stored game in it).
    NoSuchRoom,
    /// Both seats are taken, or the room has its most spectators.
    RoomFull,
    /// The server knows no seat with this token.
    BadToken,
    /// The command belongs to the other seat.
    NotYourTurn,
    /// The command answers a turn that is over.
    StaleTurn,
    /// The rules refuse the command.
    Illegal,
    /// A spectator sent a command only players may send.
    Spectator,
    /// Chat faster than the room allows.
    RateLimited,
    /// The game is over: a command for it comes too late.
    GameOver,
    /// The server cannot serve this now: it is full, its store failed, or the game is
    /// played on another instance. Try again later, or the invite's next address.
    ServerBusy,
    /// The answer would not fit in one frame (a stored record beyond
    /// [`super::limits::MAX_SENT_RECORD`]).
    TooLarge,
    /// The room has no game of the number asked for (`FetchRecord`); the message says how
    /// many it has.
    NoSuchGame,
}

/// Server to client.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ServerMessage {
    /// The answer to a `Hello` the server accepts: sign this, once, to prove the key.
    Challenge {
        /// Fresh random bytes, drawn for this connection alone.
        nonce: [u8; super::identity::NONCE_LEN],
    },
    /// The handshake succeeded.
    Welcome {
        /// The server's [`super::PROTOCOL_VERSION`], equal to the client's.
        protocol: u32,
    },
    /// The handshake failed; the server closes the connection after this.
    Reject {
        /// Why, readable by a person (e.g. the two protocol versions, or the physics hashes).
        reason: String,
    },
    /// The connection is now in a room. `token` is sent once, to the player who took the
    /// seat (and again on rejoin).
    Joined {
        /// A seat, or a spectator.
        role: Role,
        /// The seat's secret for a later `Rejoin`; `None` for a spectator.
        token: Option<SeatToken>,
        /// The room as it is now.
        snapshot: Box<Snapshot>,
    },
    /// A new game started in the room (a rematch).
    GameStarted {
        /// The room with its new game.
        snapshot: Box<Snapshot>,
    },
    /// The other seat was taken.
    PlayerJoined {
        /// The seat taken.
        seat: Seat,
        /// Its player's name.
        name: String,
    },
    /// The shooter called a pocket for this turn.
    PocketCalled {
        /// The turn the call belongs to.
        turn: TurnId,
        /// The shooter's seat.
        seat: Seat,
        /// Index into the table's pockets, 0..6.
        pocket: u8,
    },
    /// A shot was accepted: sent to everyone at once so each starts simulating it.
    ShotAccepted {
        /// The turn the shot was taken on (before it is applied).
        turn: TurnId,
        /// The shooter's seat.
        seat: Seat,
        /// Exactly what the server simulates, aim normalised and call filled in.
        command: Command,
    },
    /// The server's own simulation of the accepted shot.
    ShotResolved {
        /// The turn of the matching `ShotAccepted`.
        turn: TurnId,
        /// The physics state hash of the shot's final table; a client's own differs only
        /// when its physics do (a desync).
        hash: u64,
        /// The game after the shot and the rules: the table (balls spotted and so on,
        /// indexed by ball number), the phase and the player to move. A client that did not
        /// simulate the shot itself (a load bot checking only some shots) goes on from it.
        game: Box<Game>,
        /// What the rules made of the shot.
        ruling: Ruling,
    },
    /// A command other than a shot (placing the cue ball, a decision, a concession, the
    /// shot clock running out) was applied.
    Applied {
        /// The turn the command answered (before it is applied).
        turn: TurnId,
        /// The seat the command was applied for (for `TimeExpired`, the one out of time).
        seat: Seat,
        /// The command as applied.
        command: Command,
        /// What the rules made of it.
        ruling: Ruling,
    },
    /// The table is ready for the next command.
    TurnChanged {
        /// The new current turn, which the next command must name.
        turn: TurnId,
        /// The seat the table waits for.
        to_move: Seat,
        /// Milliseconds left on the shot clock, counting the last shot's time on screen;
        /// `None` if the room has no clock.
        shot_clock_ms: Option<u64>,
    },
    /// A player dropped; their seat is held for `reconnect_ms` milliseconds.
    PlayerLeft {
        /// The seat left empty.
        seat: Seat,
        /// How long the seat is held before the game is forfeited (ms).
        reconnect_ms: u64,
    },
    /// A dropped player came back.
    PlayerBack {
        /// The seat taken back.
        seat: Seat,
    },
    /// The game ended.
    GameOver {
        /// The winning seat; `None` if nobody won.
        winner: Option<Seat>,
        /// Why, readable by a person.
        reason: String,
    },
    /// The other player wants another game; a new one starts when both have asked.
    RematchOffered {
        /// The seat that asked.
        seat: Seat,
    },
    /// A chat line, relayed to everyone in the room.
    Chat {
        /// The player's name, or `spectator`.
        from: String,
        /// The line as sent.
        text: String,
    },
    /// A command was refused; nothing changed.
    Error {
        /// What kind of refusal, for the client to act on.
        code: ErrorCode,
        /// Why, readable by a person (the rules' reason for `Illegal`).
        message: String,
    },
    /// The answer to [`ClientMessage::FetchRecord`]: the game asked for (numbered from 1; the
    /// latest if no number was given) as it is stored, an encoded [`crate::replay::GameRecord`] holding every command
    /// applied so far.
    Record {
        /// The room asked about.
        room: RoomCode,
        /// The game's number in its room, from 1.
        game: u32,
        /// Whether the game is over; if not, the record ends at its latest command.
        finished: bool,
        /// The record, as [`crate::replay::GameRecord::encode`] writes it.
        record: Vec<u8>,
    },
    /// The answer to a [`ClientMessage::Rejoin`] whose game ended while the player was away
    /// (their room may be closed, or the server restarted since): the game's result, for the
    /// seat the token held. The connection is left out of any room; the game is over for
    /// this player.
    GameFinished {
        /// The room the game was played in.
        room: RoomCode,
        /// The game's number in its room, from 1.
        game: u32,
        /// The seat the token held.
        seat: Seat,
        /// The winning seat; `None` if nobody won.
        winner: Option<Seat>,
        /// Why the game ended, readable by a person.
        reason: String,
    },
    /// The shooter's aim on `turn`, relayed from its [`ClientMessage::Aim`].
    Aim {
        /// The turn being aimed.
        turn: TurnId,
        /// The shooter's seat.
        seat: Seat,
        /// The strike as it stands now (checked, aim normalised).
        strike: Strike,
    },
    /// The room is listed in the lobby now, until its second player comes.
    Published {
        /// The room listed.
        room: RoomCode,
    },
    /// A page of the lobby.
    Games {
        /// The page, from 0.
        page: u32,
        /// Pages in all (at least 1), of whichever list is longer.
        pages: u32,
        /// Public rooms waiting for a player, the longest waiting first.
        waiting: Vec<WaitingRoom>,
        /// Listed games in play, to watch.
        playing: Vec<GameInPlay>,
    },
    /// The player waits in the quick-match queue.
    Queued {
        /// Players waiting in this queue now, this one included.
        waiting: u32,
        /// Seconds this player may wait before the queue gives up.
        timeout_s: u32,
    },
    /// The player is out of the queue without a match (they left, or waited too long).
    Unqueued {
        /// Why, readable by a person.
        reason: String,
    },
    /// A page of the leaderboard.
    Leaders {
        /// The page, from 0.
        page: u32,
        /// Pages in all (at least 1).
        pages: u32,
        /// The players of this page, best first.
        players: Vec<RatedPlayer>,
    },
    /// A rated game ended: this seat's rating before and after (Glicko-2, rounded).
    Rated {
        /// The seat whose rating changed.
        seat: Seat,
        /// The rating before the game.
        before: i32,
        /// The rating after it.
        after: i32,
    },
    /// The server is shutting down: no new games; games in play go on to their end.
    Draining {
        /// What it means for the player, readable by a person.
        message: String,
    },
    /// The seats' ratings in a rated (quick-match) room, rounded, sent after `Joined` to
    /// whoever enters it (its players when it opens and when they come back, watchers), so
    /// the names carry them from the first shot. A player's first rated game starts at 1500.
    Ratings {
        /// Seat A's rating, then seat B's.
        ratings: [i32; 2],
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn a_player_s_command_goes_out_as_a_message_the_server_reads_back_as_that_command() {
        let strike = Strike::at_angle(2.0, 30.0, DVec2::new(0.1, -0.2));
        let commands = [
            Command::Shot {
                strike,
                call: Some(3),
            },
            Command::PlaceCueBall { pos: [0.5, 0.25] },
            Command::Decide(Choice::PushOut),
            Command::Concede,
        ];
        for command in commands {
            let msg = ClientMessage::for_command(7, command.clone()).expect("a player's command");
            let (turn, back) = command_of(&msg, None).expect("read back");
            assert_eq!(back, command);
            let expected_turn = (command != Command::Concede).then_some(7);
            assert_eq!(turn, expected_turn, "{command:?}");
        }
    }

    #[test]
    fn commands_only_the_rules_make_have_no_message() {
        for command in [Command::TimeExpired, Command::Forfeit] {
            assert_eq!(ClientMessage::for_command(1, command), None);
        }
    }
}
