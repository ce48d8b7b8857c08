//! One room as a pure state machine: two seats, spectators, the game, its record, the shot
//! clock and the reconnect windows. It never touches a socket or a clock: the caller passes
//! `now` and carries out the [`RoomOutput`]s it returns, in order.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::limits::MIN_CLOCK_ON_RETURN;
use breakshot_shared::protocol::{
    command_of, AimAid, ClientMessage, ErrorCode, Role, RoomCode, Ruling, SeatToken, SeatView,
    ServerMessage, Snapshot,
};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command, Game, Phase, RuleError, Seat, Settings, Variant};

use crate::output::{ConnId, RoomMeta, RoomOutput, StoreOp, StoredSeat};
use crate::secret::TokenDigest;

const SEATS: [Seat; 2] = [Seat::A, Seat::B];

/// Who sent a message to the room.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Who {
    /// The sender's connection.
    pub conn: ConnId,
    /// What the hub's index says it is in this room: a seat's player or a spectator.
    pub role: Role,
}

#[derive(Clone, Debug)]
struct SeatState {
    name: String,
    digest: TokenDigest,
    conn: Option<ConnId>,
    /// While the player is away: when the seat is forfeited.
    deadline: Option<Instant>,
}

/// The shot clock of the turn being played. It stops at the moment a seated player drops
/// (for a silent drop, when they were last heard from) and runs again with what was left,
/// never less than [`MIN_CLOCK_ON_RETURN`], once everyone seated is back.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Clock {
    Off,
    Running { deadline: Instant },
    Paused { left: Duration },
}

/// The shot clock as the store keeps it, so a restarted server gives the player to move
/// what they had left rather than a full clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockLeft {
    /// The turn the time belongs to; a clock of another turn is not used.
    pub turn: u32,
    /// The time left on it.
    pub left: Duration,
}

/// A room's fixed choices.
#[derive(Clone, Copy, Debug)]
pub struct RoomRules {
    /// The game played: a pool variant, or three-cushion with its race.
    pub variant: Variant,
    /// The rules' settings: calls, shot clock, table.
    pub settings: Settings,
    /// The aim-aid policy the players agreed to (honest clients enforce it).
    pub aim_aid: AimAid,
    /// How long a dropped player's seat is held.
    pub reconnect_window: Duration,
    /// Most commands one game may hold (its record stays bounded): the command that leaves
    /// one place is followed by a concession of the player to move, which ends the game
    /// (and a practice session) in the last place.
    pub max_commands: usize,
}

/// One room: its seats, spectators, game and record. Owned by the hub, or by one worker while
/// it runs a message.
pub struct Room {
    code: RoomCode,
    rules: RoomRules,
    seats: [Option<SeatState>; 2],
    spectators: BTreeSet<ConnId>,
    game: Game,
    record: GameRecord,
    game_number: u32,
    called: Option<u8>,
    clock: Clock,
    rematch: [bool; 2],
    /// Set when the room has nothing left to do and may be dropped from memory.
    closed: bool,
}

type Refusal = (ErrorCode, String);

fn refuse(code: ErrorCode, message: impl Into<String>) -> Refusal {
    (code, message.into())
}

fn error_to(conn: ConnId, (code, message): Refusal) -> Vec<RoomOutput> {
    vec![RoomOutput::Send {
        to: conn,
        msg: ServerMessage::Error { code, message },
    }]
}

/// What an entry point ([`Room::join`], [`Room::rejoin`], [`Room::spectate`]) did, so the
/// hub updates its index from facts rather than from the messages going out.
#[derive(Debug)]
pub struct Entered {
    /// The role the connection now has in the room; `None`: it was refused.
    pub role: Option<Role>,
    /// The older connection that held the seat and is closed by `out`.
    pub replaced: Option<ConnId>,
    /// What to send and store.
    pub out: Vec<RoomOutput>,
}

impl Entered {
    fn refused(conn: ConnId, refusal: Refusal) -> Entered {
        Entered {
            role: None,
            replaced: None,
            out: error_to(conn, refusal),
        }
    }
}

impl Room {
    /// A new room with its creator in seat A. Returns the room and what to do: store it,
    /// then welcome the creator (with `token`, which only the caller ever sees whole).
    pub fn create(
        now: Instant,
        code: RoomCode,
        rules: RoomRules,
        seed: u64,
        creator: ConnId,
        name: String,
        token: SeatToken,
    ) -> (Room, Vec<RoomOutput>) {
        let seat = SeatState {
            name,
            digest: TokenDigest::of(&token),
            conn: Some(creator),
            deadline: None,
        };
        let mut room = Room {
            code,
            rules,
            seats: [Some(seat), None],
            spectators: BTreeSet::new(),
            game: Game::new(rules.variant, rules.settings, seed),
            record: GameRecord::new(rules.variant, rules.settings, seed),
            game_number: 1,
            called: None,
            clock: Clock::Off,
            rematch: [false; 2],
            closed: false,
        };
        room.record = room.start_record(seed);
        room.restart_clock(now, Duration::ZERO);
        let out = vec![
            RoomOutput::Store(StoreOp::Room(room.meta())),
            room.store_start(),
            RoomOutput::Send {
                to: creator,
                msg: ServerMessage::Joined {
                    role: Role::Player(Seat::A),
                    token: Some(token),
                    snapshot: Box::new(room.snapshot(now)),
                },
            },
        ];
        (room, out)
    }

    /// A room brought back from the store after a restart: every seat is away, with a fresh
    /// reconnect window from `now`, and the shot clock paused with the time `clock` says was
    /// left on the current turn (a full clock if the store has none for it).
    pub fn restore(
        now: Instant,
        meta: RoomMeta,
        rules: RoomRules,
        game_number: u32,
        record: GameRecord,
        game: Game,
        clock: Option<ClockLeft>,
    ) -> Room {
        let seats = meta.seats.map(|s| {
            s.map(|s| SeatState {
                name: s.name,
                digest: s.digest,
                conn: None,
                deadline: Some(now + rules.reconnect_window),
            })
        });
        let mut room = Room {
            code: meta.code,
            rules,
            seats,
            spectators: BTreeSet::new(),
            game,
            record,
            game_number,
            called: None,
            clock: Clock::Off,
            rematch: [false; 2],
            closed: false,
        };
        room.restart_clock(now, Duration::ZERO);
        if let (Clock::Paused { .. }, Some(stored)) = (room.clock, clock) {
            if stored.turn == room.game.turn() {
                room.clock = Clock::Paused { left: stored.left };
            }
        }
        room
    }

    /// The room's code: its key in the hub and in the store.
    pub fn code(&self) -> &RoomCode {
        &self.code
    }

    /// The current game, as every accepted command has left it.
    pub fn game(&self) -> &Game {
        &self.game
    }

    /// The current game's number in this room, from 1.
    pub fn game_number(&self) -> u32 {
        self.game_number
    }

    /// The current game's record: its header and every command accepted so far (the store's copy
    /// catches up once the writer commits).
    pub fn record(&self) -> &GameRecord {
        &self.record
    }

    /// Whether the room still waits for its second player.
    pub fn is_waiting(&self) -> bool {
        self.seats.iter().any(Option::is_none)
    }

    /// Whether nobody is in the room and no seat awaits a reconnect; the hub then drops it.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The digests of the seats' tokens, for the caller's token index.
    pub fn seat_digests(&self) -> impl Iterator<Item = (Seat, TokenDigest)> + '_ {
        SEATS
            .into_iter()
            .filter_map(|s| self.seats[s.index()].as_ref().map(|st| (s, st.digest)))
    }

    /// The room's lasting facts as the store keeps them: settings, and seats by token digest.
    pub fn meta(&self) -> RoomMeta {
        RoomMeta {
            code: self.code.clone(),
            variant: self.rules.variant,
            settings: self.rules.settings,
            aim_aid: self.rules.aim_aid,
            seats: self.seats.clone().map(|s| {
                s.map(|s| StoredSeat {
                    name: s.name,
                    digest: s.digest,
                })
            }),
        }
    }

    /// Everything a client needs to draw the room from scratch.
    pub fn snapshot(&self, now: Instant) -> Snapshot {
        Snapshot {
            room: self.code.clone(),
            game_number: self.game_number,
            game: self.game.clone(),
            seats: self.seats.clone().map(|s| {
                s.map(|s| SeatView {
                    name: s.name,
                    connected: s.conn.is_some(),
                    reconnect_ms: s.deadline.map(|d| millis(d.saturating_duration_since(now))),
                })
            }),
            aim_aid: self.rules.aim_aid,
            called: self.called,
            shot_clock_ms: match self.clock {
                Clock::Running { deadline } => {
                    Some(millis(deadline.saturating_duration_since(now)))
                }
                _ => None,
            },
        }
    }

    /// Takes the free seat B.
    pub fn join(&mut self, now: Instant, conn: ConnId, name: String, token: SeatToken) -> Entered {
        if self.seats[1].is_some() {
            return Entered::refused(conn, refuse(ErrorCode::RoomFull, "both seats are taken"));
        }
        self.seats[1] = Some(SeatState {
            name: name.clone(),
            digest: TokenDigest::of(&token),
            conn: Some(conn),
            deadline: None,
        });
        self.restart_clock(now, Duration::ZERO);
        let mut out = vec![RoomOutput::Store(StoreOp::Room(self.meta()))];
        // The record names both players. Only a practice room can have played before its
        // second seat is taken; its record keeps the one name it started with.
        if self.record.entries.is_empty() {
            self.record.name_player(Seat::B, &name);
            out.push(self.store_start());
        }
        out.extend(self.store_clock(now));
        out.extend(self.broadcast_except(
            conn,
            ServerMessage::PlayerJoined {
                seat: Seat::B,
                name,
            },
        ));
        // The game starts now: the others learn that its clock runs (the joiner reads it in
        // the snapshot).
        out.extend(self.clock_to_others(now, conn));
        out.push(RoomOutput::Send {
            to: conn,
            msg: ServerMessage::Joined {
                role: Role::Player(Seat::B),
                token: Some(token),
                snapshot: Box::new(self.snapshot(now)),
            },
        });
        Entered {
            role: Some(Role::Player(Seat::B)),
            replaced: None,
            out,
        }
    }

    /// Gives `seat` back to a player who proved it with its token. An older connection still
    /// holding the seat is closed.
    pub fn rejoin(&mut self, now: Instant, conn: ConnId, seat: Seat, token: SeatToken) -> Entered {
        let mut out = Vec::new();
        let Some(state) = self.seats[seat.index()].as_mut() else {
            return Entered::refused(conn, refuse(ErrorCode::BadToken, "no such seat"));
        };
        if !state.digest.matches(&TokenDigest::of(&token)) {
            return Entered::refused(conn, refuse(ErrorCode::BadToken, "unknown seat token"));
        }
        let replaced = state.conn.replace(conn);
        if let Some(old) = replaced {
            out.push(RoomOutput::Close {
                conn: old,
                reason: "replaced by a newer connection".into(),
            });
        }
        let was_away = state.deadline.take().is_some();
        if was_away {
            self.resume_clock(now);
            out.extend(self.store_clock(now));
        }
        out.extend(self.broadcast_except(conn, ServerMessage::PlayerBack { seat }));
        if was_away {
            out.extend(self.clock_to_others(now, conn));
        }
        out.push(RoomOutput::Send {
            to: conn,
            msg: ServerMessage::Joined {
                role: Role::Player(seat),
                token: Some(token),
                snapshot: Box::new(self.snapshot(now)),
            },
        });
        Entered {
            role: Some(Role::Player(seat)),
            replaced,
            out,
        }
    }

    /// Lets `conn` watch, unless `max` spectators already do.
    pub fn spectate(&mut self, now: Instant, conn: ConnId, max: usize) -> Entered {
        if self.spectators.len() >= max {
            return Entered::refused(conn, refuse(ErrorCode::RoomFull, "too many spectators"));
        }
        self.spectators.insert(conn);
        Entered {
            role: Some(Role::Spectator),
            replaced: None,
            out: vec![RoomOutput::Send {
                to: conn,
                msg: ServerMessage::Joined {
                    role: Role::Spectator,
                    token: None,
                    snapshot: Box::new(self.snapshot(now)),
                },
            }],
        }
    }

    /// A message from someone in the room. Chat is rate-limited by the caller.
    pub fn handle(&mut self, now: Instant, who: Who, msg: ClientMessage) -> Vec<RoomOutput> {
        let seat = match who.role {
            Role::Player(seat) => seat,
            Role::Spectator => {
                if let ClientMessage::Chat { text } = msg {
                    return self.broadcast(ServerMessage::Chat {
                        from: "spectator".into(),
                        text,
                    });
                }
                return error_to(
                    who.conn,
                    refuse(ErrorCode::Spectator, "spectators cannot act on the game"),
                );
            }
        };
        let result = match msg {
            ClientMessage::Chat { text } => Ok(self.chat(seat, text)),
            ClientMessage::Rematch => self.rematch(now, seat),
            ClientMessage::CallPocket { turn, pocket } => self.call_pocket(seat, turn, pocket),
            ClientMessage::Aim { turn, strike } => Ok(self.relay_aim(who.conn, seat, turn, strike)),
            other => match command_of(&other, self.called) {
                Some((turn, command)) => self.play(now, seat, turn, command),
                None => Err(refuse(ErrorCode::Unexpected, "not a message for a room")),
            },
        };
        result.unwrap_or_else(|r| error_to(who.conn, r))
    }

    /// A connection went away; its peer was last heard from at `last_heard` (at most `now`),
    /// which is when a seated player's shot clock stops.
    pub fn disconnect(
        &mut self,
        now: Instant,
        last_heard: Instant,
        conn: ConnId,
    ) -> Vec<RoomOutput> {
        self.spectators.remove(&conn);
        let Some(seat) = SEATS.into_iter().find(|s| {
            self.seats[s.index()]
                .as_ref()
                .is_some_and(|st| st.conn == Some(conn))
        }) else {
            return Vec::new();
        };
        let window = self.rules.reconnect_window;
        if let Some(state) = self.seats[seat.index()].as_mut() {
            state.conn = None;
            state.deadline = Some(now + window);
        }
        self.pause_clock(last_heard.min(now));
        let mut out: Vec<RoomOutput> = self.store_clock(now).into_iter().collect();
        out.extend(self.broadcast(ServerMessage::PlayerLeft {
            seat,
            reconnect_ms: millis(window),
        }));
        out
    }

    /// The earliest instant at which [`Room::tick`] has something to do.
    pub fn next_deadline(&self) -> Option<Instant> {
        let seats = self.seats.iter().flatten().filter_map(|s| s.deadline);
        let clock = match self.clock {
            Clock::Running { deadline } => Some(deadline),
            _ => None,
        };
        seats.chain(clock).min()
    }

    /// Forfeits seats whose window ran out and runs out the shot clock.
    pub fn tick(&mut self, now: Instant) -> Vec<RoomOutput> {
        let mut out = Vec::new();
        for seat in SEATS {
            let expired = self.seats[seat.index()]
                .as_ref()
                .and_then(|s| s.deadline)
                .is_some_and(|d| d <= now);
            if !expired {
                continue;
            }
            if let Some(s) = self.seats[seat.index()].as_mut() {
                s.deadline = None;
            }
            let opponent_present = self.seats[seat.other().index()].is_some();
            if !self.is_over() && opponent_present {
                out.extend(
                    self.play(now, seat, None, Command::Forfeit)
                        .unwrap_or_default(),
                );
            }
        }
        if let Clock::Running { deadline } = self.clock {
            if deadline <= now && !self.is_over() {
                let seat = self.game.to_move();
                self.clock = Clock::Off;
                out.extend(
                    self.play(now, seat, None, Command::TimeExpired)
                        .unwrap_or_default(),
                );
            }
        }
        let nobody_here = self.connections().next().is_none();
        let nobody_coming = self.seats.iter().flatten().all(|s| s.deadline.is_none());
        if nobody_here && nobody_coming && !self.closed {
            self.closed = true;
            if !self.is_over() {
                // Abandoned before anyone could forfeit (no opponent ever came).
                out.push(RoomOutput::Store(StoreOp::GameEnded {
                    room: self.code.clone(),
                    number: self.game_number,
                    winner: None,
                    reason: "abandoned".into(),
                }));
            }
        }
        out
    }

    fn is_over(&self) -> bool {
        matches!(self.game.phase(), Phase::Over { .. })
    }

    fn both_seated(&self) -> bool {
        self.seats.iter().all(Option::is_some) || matches!(self.rules.variant, Variant::Practice)
    }

    /// Checks, applies, records, and tells everyone, in that order.
    fn play(
        &mut self,
        now: Instant,
        seat: Seat,
        turn: Option<u32>,
        command: Command,
    ) -> Result<Vec<RoomOutput>, Refusal> {
        if self.is_over() {
            return Err(refuse(ErrorCode::GameOver, "the game is over"));
        }
        if !self.both_seated() {
            return Err(refuse(ErrorCode::Unexpected, "waiting for an opponent"));
        }
        let answered = self.game.turn();
        if let Some(t) = turn {
            if t != answered {
                return Err(refuse(
                    ErrorCode::StaleTurn,
                    format!("turn {t} is over; the table is at turn {answered}"),
                ));
            }
        }
        // Work on a copy: a refusal leaves the game exactly as it was.
        let mut next = self.game.clone();
        let verdict = next.apply(seat, &command).map_err(rule_refusal)?;
        let hash = verdict.shot.as_ref().map(|s| s.hash);
        let duration = verdict
            .shot
            .as_ref()
            .and_then(|s| s.events.last())
            .map_or(0.0, |e| e.t);
        self.record.push(seat, command.clone(), hash);
        let stored = self.store_command();
        self.game = next;
        if self.game.turn() != answered {
            self.called = None;
        }
        let ruling = Ruling {
            foul: verdict.foul,
            reasons: verdict.reasons.clone(),
            pocketed: verdict
                .shot
                .as_ref()
                .map(|s| s.pocketed.clone())
                .unwrap_or_default(),
            next: verdict.next,
        };
        let mut out = vec![stored];
        if let Phase::Over { winner, reason } = self.game.phase() {
            out.push(RoomOutput::Store(StoreOp::GameEnded {
                room: self.code.clone(),
                number: self.game_number,
                winner: *winner,
                reason: reason.clone(),
            }));
        }
        match hash {
            Some(hash) => {
                out.extend(self.broadcast(ServerMessage::ShotAccepted {
                    turn: answered,
                    seat,
                    command,
                }));
                out.extend(self.broadcast(ServerMessage::ShotResolved {
                    turn: answered,
                    hash,
                    game: Box::new(self.game.clone()),
                    ruling,
                }));
            }
            None => out.extend(self.broadcast(ServerMessage::Applied {
                turn: answered,
                seat,
                command,
                ruling,
            })),
        }
        if let Phase::Over { winner, reason } = self.game.phase() {
            let msg = ServerMessage::GameOver {
                winner: *winner,
                reason: reason.clone(),
            };
            self.clock = Clock::Off;
            out.extend(self.broadcast(msg));
        } else {
            let animation = Duration::try_from_secs_f64(duration).unwrap_or(Duration::ZERO);
            self.restart_clock(now, animation);
            // Stored with the command, before anyone hears of the new turn.
            out.splice(1..1, self.store_clock(now));
            let msg = ServerMessage::TurnChanged {
                turn: self.game.turn(),
                to_move: self.game.to_move(),
                shot_clock_ms: self.clock_ms(now),
            };
            out.extend(self.broadcast(msg));
            if self.record.entries.len() + 1 >= self.rules.max_commands {
                out.extend(self.end_at_length_limit(now));
            }
        }
        Ok(out)
    }

    /// Ends a game that has one place left in its record: the player to move concedes
    /// (in practice, the session ends), so the record never grows past the limit.
    fn end_at_length_limit(&mut self, now: Instant) -> Vec<RoomOutput> {
        let mut out = self.broadcast(ServerMessage::Chat {
            from: String::new(),
            text: format!(
                "this game reached its length limit of {} commands and ends now",
                self.rules.max_commands
            ),
        });
        let seat = self.game.to_move();
        out.extend(
            self.play(now, seat, None, Command::Concede)
                .unwrap_or_default(),
        );
        out
    }

    /// Shows the shooter's aim to everyone else in the room. An aim out of turn is dropped
    /// without an answer: it is a picture of a moment, and a late one is simply old.
    fn relay_aim(&self, from: ConnId, seat: Seat, turn: u32, strike: Strike) -> Vec<RoomOutput> {
        if self.is_over() || turn != self.game.turn() || seat != self.game.to_move() {
            return Vec::new();
        }
        self.broadcast_except(from, ServerMessage::Aim { turn, seat, strike })
    }

    fn call_pocket(
        &mut self,
        seat: Seat,
        turn: u32,
        pocket: u8,
    ) -> Result<Vec<RoomOutput>, Refusal> {
        if self.is_over() {
            return Err(refuse(ErrorCode::GameOver, "the game is over"));
        }
        if turn != self.game.turn() {
            return Err(refuse(ErrorCode::StaleTurn, "that turn is over"));
        }
        if seat != self.game.to_move() {
            return Err(refuse(ErrorCode::NotYourTurn, "only the shooter calls"));
        }
        self.called = Some(pocket);
        Ok(self.broadcast(ServerMessage::PocketCalled { turn, seat, pocket }))
    }

    fn rematch(&mut self, now: Instant, seat: Seat) -> Result<Vec<RoomOutput>, Refusal> {
        if !self.is_over() {
            return Err(refuse(ErrorCode::Unexpected, "the game is still on"));
        }
        self.rematch[seat.index()] = true;
        if !self.rematch.iter().all(|r| *r) {
            return Ok(self.broadcast(ServerMessage::RematchOffered { seat }));
        }
        // The new game's seed comes from the old one so the room needs no randomness here;
        // it is recorded, so replays do not depend on how it was chosen.
        let seed = self
            .record
            .seed
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .wrapping_add(u64::from(self.game_number));
        self.game = Game::new(self.rules.variant, self.rules.settings, seed);
        self.record = self.start_record(seed);
        self.game_number += 1;
        self.rematch = [false; 2];
        self.called = None;
        self.restart_clock(now, Duration::ZERO);
        let mut out = vec![self.store_start()];
        out.extend(self.store_clock(now));
        out.extend(self.broadcast(ServerMessage::GameStarted {
            snapshot: Box::new(self.snapshot(now)),
        }));
        Ok(out)
    }

    fn chat(&self, seat: Seat, text: String) -> Vec<RoomOutput> {
        let from = self.seats[seat.index()]
            .as_ref()
            .map_or_else(String::new, |s| s.name.clone());
        self.broadcast(ServerMessage::Chat { from, text })
    }

    /// The record of a new game of this room from `seed`, naming the players seated.
    fn start_record(&self, seed: u64) -> GameRecord {
        let mut record = GameRecord::new(self.rules.variant, self.rules.settings, seed);
        for seat in SEATS {
            if let Some(s) = &self.seats[seat.index()] {
                record.name_player(seat, &s.name);
            }
        }
        record
    }

    /// Stores the start of the current game (its record's header).
    fn store_start(&self) -> RoomOutput {
        RoomOutput::Store(StoreOp::GameStarted {
            room: self.code.clone(),
            number: self.game_number,
            header: self.record.encode(),
        })
    }

    /// Stores the record's last entry.
    fn store_command(&self) -> RoomOutput {
        let index = self.record.entries.len().saturating_sub(1);
        RoomOutput::Store(StoreOp::Command {
            room: self.code.clone(),
            number: self.game_number,
            index: u32::try_from(index).unwrap_or(u32::MAX),
            entry: self
                .record
                .entries
                .last()
                .map(|e| e.encode())
                .unwrap_or_default(),
        })
    }

    fn connections(&self) -> impl Iterator<Item = ConnId> + '_ {
        self.seats
            .iter()
            .flatten()
            .filter_map(|s| s.conn)
            .chain(self.spectators.iter().copied())
    }

    fn broadcast(&self, msg: ServerMessage) -> Vec<RoomOutput> {
        self.connections()
            .map(|to| RoomOutput::Send {
                to,
                msg: msg.clone(),
            })
            .collect()
    }

    fn broadcast_except(&self, except: ConnId, msg: ServerMessage) -> Vec<RoomOutput> {
        self.connections()
            .filter(|c| *c != except)
            .map(|to| RoomOutput::Send {
                to,
                msg: msg.clone(),
            })
            .collect()
    }

    fn everyone_seated_is_here(&self) -> bool {
        self.seats.iter().flatten().all(|s| s.conn.is_some())
    }

    /// Starts the shot clock for a new turn (if the room has one), paused if a player is
    /// away. `animation` is how long the last shot takes to play out on screen.
    fn restart_clock(&mut self, now: Instant, animation: Duration) {
        self.clock = match self.rules.settings.shot_clock {
            Some(secs) if !self.is_over() && self.seats.iter().all(Option::is_some) => {
                let left = Duration::from_secs(u64::from(secs)) + animation;
                if self.everyone_seated_is_here() {
                    Clock::Running {
                        deadline: now + left,
                    }
                } else {
                    Clock::Paused { left }
                }
            }
            _ => Clock::Off,
        };
    }

    /// Stops the clock with the time it had left at `at`.
    fn pause_clock(&mut self, at: Instant) {
        if let Clock::Running { deadline } = self.clock {
            self.clock = Clock::Paused {
                left: deadline.saturating_duration_since(at),
            };
        }
    }

    /// Runs a paused clock again once everyone seated is here, with what it had left but
    /// never less than [`MIN_CLOCK_ON_RETURN`].
    fn resume_clock(&mut self, now: Instant) {
        if let Clock::Paused { left } = self.clock {
            if self.everyone_seated_is_here() {
                self.clock = Clock::Running {
                    deadline: now + left.max(MIN_CLOCK_ON_RETURN),
                };
            }
        }
    }

    /// The shot clock as it stands, to store (nothing when the room has none running or
    /// paused).
    fn store_clock(&self, now: Instant) -> Option<RoomOutput> {
        let (left, running) = match self.clock {
            Clock::Off => return None,
            Clock::Running { deadline } => (deadline.saturating_duration_since(now), true),
            Clock::Paused { left } => (left, false),
        };
        Some(RoomOutput::Store(StoreOp::Clock {
            room: self.code.clone(),
            number: self.game_number,
            turn: self.game.turn(),
            left_ms: millis(left),
            running,
        }))
    }

    /// Tells everyone but `conn` how the shot clock stands, when the room has one running:
    /// after a join or a return it starts or runs again, and every screen shows the same.
    fn clock_to_others(&self, now: Instant, conn: ConnId) -> Vec<RoomOutput> {
        if !matches!(self.clock, Clock::Running { .. }) {
            return Vec::new();
        }
        self.broadcast_except(
            conn,
            ServerMessage::TurnChanged {
                turn: self.game.turn(),
                to_move: self.game.to_move(),
                shot_clock_ms: self.clock_ms(now),
            },
        )
    }

    fn clock_ms(&self, now: Instant) -> Option<u64> {
        match self.clock {
            Clock::Running { deadline } => Some(millis(deadline.saturating_duration_since(now))),
            Clock::Paused { left } => Some(millis(left)),
            Clock::Off => None,
        }
    }
}

fn rule_refusal(e: RuleError) -> Refusal {
    let code = match e {
        RuleError::NotYourTurn => ErrorCode::NotYourTurn,
        _ => ErrorCode::Illegal,
    };
    (code, e.to_string())
}

fn millis(d: Duration) -> u64 {
    u64::try_from(d.as_millis()).unwrap_or(u64::MAX)
}
