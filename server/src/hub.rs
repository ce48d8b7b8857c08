//! All connections and rooms of one server, as a pure state machine. It checks the
//! handshake, validates every message, rate-limits, routes messages to rooms and keeps the
//! index from seat-token digests to seats. The driver feeds it events with `now` and
//! carries out the outputs.
//!
//! A message for a room is lent out with the room ([`Output::Run`]), so the driver can run
//! rooms in parallel; until the room is [`Hub::returned`], the hub holds that room's later
//! events in arrival order, and answers every other room and connection at once.

use std::collections::{BTreeMap, VecDeque};
use std::net::IpAddr;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::identity::NONCE_LEN;
use breakshot_shared::protocol::limits::{
    CHAT_BURST, CHAT_REFILL, LOBBY_BURST, LOBBY_REFILL, MAX_ROOMS, MAX_SPECTATORS, QUEUE_BURST,
    QUEUE_REFILL, QUEUE_TIMEOUT, ROOM_CODE_LEN,
};
use breakshot_shared::protocol::{
    validate, ClientMessage, ErrorCode, PlayerKey, Role, RoomCode, SeatToken, ServerMessage,
    PROTOCOL_VERSION,
};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Game, Phase, Seat, Settings, Variant};

use crate::endings::{Ending, Endings};
use crate::limits::Limits;
use crate::lobby::{Listed, Listing, Lobby};
use crate::matchmaking::Queues;
use crate::output::{ConnId, RoomMeta, RoomOutput, StoreOp};
use crate::ratelimit::Bucket;
use crate::ratings::{PlayerRating, Ratings};
use crate::room::{ClockLeft, Entered, Room, RoomRules, Who};
use crate::rooms::Rooms;
use crate::secret::{new_seed, new_token, Entropy, TokenDigest};
use crate::source::source_key;
use crate::work::{Returned, RoomWork};

/// What a hub is started with; fixed for its life.
#[derive(Clone, Debug)]
pub struct HubConfig {
    /// The message, room, entry and retention limits it enforces (the connection counts are
    /// [`crate::admission`]'s).
    pub limits: Limits,
    /// The reference-shot hash of this build's physics; clients must match it.
    pub physics: u64,
    /// Other server instances share the store: a seat token no room here knows may belong
    /// to a room one of them left, which the store is asked for ([`Output::Claim`]).
    pub shared_store: bool,
}

/// The store's answer to an [`Output::Claim`].
#[derive(Debug)]
pub enum Claimed {
    /// The room is this server's now: its latest game, replayed with every hash checked.
    Taken(Box<Restored>),
    /// The seat's room is closed, its last game over `age` ago.
    Ended {
        /// The room as last stored: the seats whose tokens are told the result.
        meta: Box<RoomMeta>,
        /// How its last game ended.
        ending: Ending,
        /// How long ago it ended, in whole seconds of the store's clock.
        age: Duration,
    },
    /// Another live instance owns the room (or the store could not say).
    Elsewhere,
    /// No room elsewhere has the seat (or its room is here already).
    NotFound,
}

/// A game brought back from the store, replayed and checked.
#[derive(Debug)]
pub struct Restored {
    /// The room's settings and seats as last stored.
    pub meta: RoomMeta,
    /// The game's number in its room, from 1.
    pub number: u32,
    /// The game's record as stored, every hash checked.
    pub record: GameRecord,
    /// The game as the replay left it: where play resumes.
    pub game: Game,
    /// The shot clock of the current turn as last stored, if the room has one.
    pub clock: Option<ClockLeft>,
    /// A quick-match room's players (seat A's key first): its first game is rated.
    pub rated: Option<[PlayerKey; 2]>,
    /// A room published in the lobby, with its players' keys as far as they are known.
    pub listed: Option<[Option<PlayerKey>; 2]>,
}

/// Where a connection is in its handshake.
enum Greeting {
    /// Nothing yet: the first message must be `Hello`.
    Unknown,
    /// `Hello` was accepted and its key challenged; the next message must prove it. The
    /// challenge is this connection's alone and is dropped once answered, right or wrong.
    Challenged {
        key: PlayerKey,
        nonce: [u8; NONCE_LEN],
    },
    /// Welcomed: the connection is this player's.
    Welcomed(PlayerKey),
}

struct Conn {
    addr: IpAddr,
    greeting: Greeting,
    room: Option<(RoomCode, Role)>,
    /// Its entry into a room is held until the room comes back.
    entering: bool,
    chat: Bucket,
    messages: Bucket,
    /// Lobby and leaderboard pages.
    lobby: Bucket,
    /// Quick-match joins and leaves.
    queue: Bucket,
}

/// A quick-match room's first game, rated when it ends.
struct RatedGame {
    keys: [PlayerKey; 2],
    names: [String; 2],
    settled: bool,
}

/// What the hub remembers about one source address: its room-entry budget and how many
/// open rooms it created.
struct Source {
    entries: Bucket,
    last_entry: Instant,
    conns: usize,
    rooms: usize,
}

/// An event for a room that is out running a message, kept until it comes back.
enum Held {
    Message(Who, ClientMessage, Instant),
    /// A create, join, rejoin or spectate, routed again once the room is back.
    Enter(ConnId, ClientMessage),
    Disconnect(ConnId, Instant),
}

/// Every connection, room and seat token of one server; run on one thread, which passes `now`
/// with each event and carries out the outputs in order.
pub struct Hub {
    config: HubConfig,
    /// The rooms here; a room lent out with its work is in `away` instead.
    rooms: Rooms,
    away: BTreeMap<RoomCode, VecDeque<Held>>,
    /// Who created each open room, for the rooms-per-address limit.
    creators: BTreeMap<RoomCode, IpAddr>,
    sources: BTreeMap<IpAddr, Source>,
    conns: BTreeMap<ConnId, Conn>,
    tokens: BTreeMap<TokenDigest, (RoomCode, Seat)>,
    /// Seats of games that ended, for players who come back after their room is gone.
    endings: Endings,
    rng: Box<dyn Entropy>,
    /// Draining: no new room is opened; the games in play go on to their end.
    draining: bool,
    /// Rooms refused because of the drain.
    drain_refusals: usize,
    /// The public rooms listed.
    lobby: Lobby,
    /// Players waiting for a quick match.
    queues: Queues,
    /// Every player's rating.
    ratings: Ratings,
    /// Quick-match rooms whose first game is rated.
    rated: BTreeMap<RoomCode, RatedGame>,
    /// Desyncs clients reported (`ReportDesync`).
    desyncs: usize,
}

/// How many rooms are in each state, for the operator's metrics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Census {
    /// Rooms waiting for their second player.
    pub waiting: usize,
    /// Rooms with both players and a game in play (a room out running a command counts here).
    pub playing: usize,
    /// Rooms whose game is over, kept for a rematch.
    pub over: usize,
}

/// What the hub asks its driver to do, in order: what its rooms ask, and what only the hub
/// does (lend a room out, read the store for a seat or a record).
#[derive(Debug)]
pub enum Output {
    /// A send, close or store, as a room asks them (the hub's own sends and closes too).
    Room(RoomOutput),
    /// Send `to` the stored record of one of `room`'s games (or an error). The writer reads
    /// it after committing every earlier store operation, so it holds every result already
    /// sent.
    SendRecord {
        /// The connection that sent `FetchRecord`.
        to: ConnId,
        /// The room whose game is sent, finished or not.
        room: RoomCode,
        /// The game's number in the room; `None` for the latest.
        game: Option<u32>,
    },
    /// Ask the store for the room of an unknown seat token, in a store shared with other
    /// server instances: the room may have been left by an instance that stopped. The answer
    /// goes back to [`Hub::claimed`]. Everything before it in the list comes first.
    Claim {
        /// The connection rejoining; its entry waits for the answer.
        conn: ConnId,
        /// The seat token it sent; the store is asked only for its digest.
        token: SeatToken,
    },
    /// Run a message through its room away from the hub (see [`crate::work`]): carry out
    /// the outputs the work returns, then give the room back with [`Hub::returned`].
    /// Everything before it in the list comes first.
    Run(RoomWork),
}

impl From<RoomOutput> for Output {
    fn from(o: RoomOutput) -> Output {
        Output::Room(o)
    }
}

/// A room's outputs as the hub's.
fn lift(out: Vec<RoomOutput>) -> Vec<Output> {
    out.into_iter().map(Output::Room).collect()
}

fn send(to: ConnId, msg: ServerMessage) -> Output {
    Output::Room(RoomOutput::Send { to, msg })
}

fn error(to: ConnId, code: ErrorCode, message: impl Into<String>) -> Vec<Output> {
    vec![send(
        to,
        ServerMessage::Error {
            code,
            message: message.into(),
        },
    )]
}

impl Hub {
    /// A hub with no connections or rooms; `rng` draws room codes, seat tokens and game seeds.
    pub fn new(config: HubConfig, rng: Box<dyn Entropy>) -> Hub {
        Hub {
            queues: Queues::new(QUEUE_TIMEOUT, config.limits.match_one_address),
            config,
            rooms: Rooms::default(),
            away: BTreeMap::new(),
            creators: BTreeMap::new(),
            sources: BTreeMap::new(),
            conns: BTreeMap::new(),
            tokens: BTreeMap::new(),
            endings: Endings::default(),
            rng,
            draining: false,
            drain_refusals: 0,
            lobby: Lobby::default(),
            ratings: Ratings::default(),
            rated: BTreeMap::new(),
            desyncs: 0,
        }
    }

    /// Takes the ratings the store kept (at start).
    pub fn load_ratings(&mut self, stored: impl IntoIterator<Item = (PlayerKey, PlayerRating)>) {
        self.ratings = Ratings::from_stored(stored);
    }

    /// Every rating, for the leaderboard and tests.
    pub fn ratings(&self) -> &Ratings {
        &self.ratings
    }

    /// Players waiting in each quick-match queue, for the metrics.
    pub fn queue_lengths(&self) -> Vec<(Variant, Settings, usize)> {
        self.queues.lengths()
    }

    /// Desyncs clients have reported.
    pub fn desyncs(&self) -> usize {
        self.desyncs
    }

    /// Rooms listed in the lobby.
    pub fn listed(&self) -> usize {
        self.lobby.len()
    }

    /// How many rooms the drain has refused so far.
    pub fn drain_refusals(&self) -> usize {
        self.drain_refusals
    }

    /// Rooms by state; linear in the rooms, so the driver takes it now and then, not per event.
    pub fn census(&self) -> Census {
        let mut census = Census {
            playing: self.away.len(),
            ..Census::default()
        };
        for room in self.rooms.values() {
            if room.is_waiting() {
                census.waiting += 1;
            } else if matches!(room.game().phase(), Phase::Over { .. }) {
                census.over += 1;
            } else {
                census.playing += 1;
            }
        }
        census
    }

    /// The configuration it was made with (the driver reads `finished_retention` at start).
    pub fn config(&self) -> &HubConfig {
        &self.config
    }

    /// Room `code` if it is here; `None` also while it is out running a message.
    pub fn room(&self, code: &RoomCode) -> Option<&Room> {
        self.rooms.get(code)
    }

    /// The rooms here (not those out running a message).
    pub fn rooms(&self) -> impl Iterator<Item = &Room> {
        self.rooms.values()
    }

    /// Every open room, here or out.
    pub fn room_count(&self) -> usize {
        self.rooms.len() + self.away.len()
    }

    /// Rooms out running a message.
    pub fn rooms_away(&self) -> usize {
        self.away.len()
    }

    /// A room back from its work: it takes the events held for it, in order, until one of
    /// them sends it out again.
    pub fn returned(&mut self, now: Instant, back: Returned) -> Vec<Output> {
        let room = *back.0;
        let code = room.code().clone();
        let mut held = self.away.remove(&code).unwrap_or_default();
        self.rooms.insert(room);
        let mut out = Vec::new();
        while let Some(event) = held.pop_front() {
            match event {
                Held::Message(who, msg, read) => {
                    out.extend(self.lend(&code, who, msg, read));
                    if let Some(waiting) = self.away.get_mut(&code) {
                        waiting.extend(held);
                        break;
                    }
                }
                Held::Enter(conn, msg) => {
                    let Some(c) = self.conns.get_mut(&conn) else {
                        continue;
                    };
                    c.entering = false;
                    out.extend(self.route(now, now, conn, msg, None));
                    if self.conns.get(&conn).is_some_and(|c| c.room.is_some()) {
                        self.refund_entry(conn);
                    }
                }
                Held::Disconnect(conn, last_heard) => {
                    if let Some(mut room) = self.rooms.get_mut(&code) {
                        out.extend(lift(room.disconnect(now, last_heard, conn)));
                    }
                }
            }
        }
        out.extend(self.settle_rating(&code));
        out
    }

    /// A room whose work failed (a bug: handling a message panicked). Its state cannot be
    /// trusted, so it is dropped rather than taken back: its players are told and are out
    /// of it, entries held for it are answered, and its game stays in the store as last
    /// committed (every result shown was), restored when the server starts again.
    pub fn failed(&mut self, code: &RoomCode) -> Vec<Output> {
        const WHY: &str = "this room stopped after an internal error; its game is stored up to \
                           the last result shown";
        let mut out = Vec::new();
        for event in self.away.remove(code).unwrap_or_default() {
            if let Held::Enter(conn, _) = event {
                if let Some(c) = self.conns.get_mut(&conn) {
                    c.entering = false;
                    out.extend(error(conn, ErrorCode::ServerBusy, WHY));
                }
            }
        }
        for (&id, c) in &mut self.conns {
            if c.room.as_ref().is_some_and(|(r, _)| r == code) {
                c.room = None;
                out.extend(error(id, ErrorCode::ServerBusy, WHY));
            }
        }
        self.tokens.retain(|_, (c, _)| c != code);
        self.lobby.remove(code);
        self.rated.remove(code);
        if let Some(addr) = self.creators.remove(code) {
            if let Some(source) = self.sources.get_mut(&addr) {
                source.rooms = source.rooms.saturating_sub(1);
            }
        }
        if self.config.shared_store {
            out.push(Output::Room(RoomOutput::Store(StoreOp::Released(
                code.clone(),
            ))));
        }
        out
    }

    /// Sends `msg` out with its room, or holds it if the room is already out.
    fn lend(
        &mut self,
        code: &RoomCode,
        who: Who,
        msg: ClientMessage,
        read: Instant,
    ) -> Vec<Output> {
        if let Some(held) = self.away.get_mut(code) {
            held.push_back(Held::Message(who, msg, read));
            return Vec::new();
        }
        match self.rooms.remove(code) {
            Some(room) => {
                self.away.insert(code.clone(), VecDeque::new());
                vec![Output::Run(RoomWork::new(Box::new(room), who, msg, read))]
            }
            None => error(who.conn, ErrorCode::NoSuchRoom, "the room is closed"),
        }
    }

    /// The room an entry names, if that room is out: the entry waits for it.
    fn entry_away(&self, msg: &ClientMessage) -> Option<RoomCode> {
        let code = match msg {
            ClientMessage::Join { room, .. } | ClientMessage::Spectate { room } => room.clone(),
            ClientMessage::Rejoin { token } => self.tokens.get(&TokenDigest::of(token))?.0.clone(),
            _ => return None,
        };
        self.away.contains_key(&code).then_some(code)
    }

    /// Brings back a room from the store (after its record was replayed and checked).
    pub fn restore(&mut self, now: Instant, restored: Restored) {
        let Restored {
            meta,
            number,
            record,
            game,
            clock,
            rated,
            listed,
        } = restored;
        let rules = RoomRules {
            variant: meta.variant,
            settings: meta.settings,
            aim_aid: meta.aim_aid,
            reconnect_window: self.config.limits.reconnect_window,
            max_commands: self.config.limits.max_commands(meta.variant),
        };
        if let Some(keys) = rated {
            // Rated as the instance that opened the room would have (only game 1 is: a room
            // brought back at a later game was rated where its first ended).
            let names = meta
                .seats
                .clone()
                .map(|s| s.map(|s| s.name).unwrap_or_default());
            self.rated.insert(
                meta.code.clone(),
                RatedGame {
                    keys,
                    names,
                    settled: false,
                },
            );
        }
        // Listed in the lobby again as it was: a quick match's room as a rated game in play,
        // a published one waiting for its second player or in play once it came.
        if let Some(keys) = rated.map(|keys| keys.map(Some)).or(listed) {
            let seat = |k: usize| {
                meta.seats[k].as_ref().map(|s| Listed {
                    name: s.name.clone(),
                    key: keys[k],
                })
            };
            let listing = Listing {
                variant: meta.variant,
                mode: meta.settings,
                host: seat(0).unwrap_or(Listed {
                    name: String::new(),
                    key: keys[0],
                }),
                guest: seat(1),
                since: now,
                rated: rated.is_some(),
            };
            self.lobby.list(meta.code.clone(), listing);
        }
        let room = Room::restore(now, meta, rules, number, record, game, clock);
        self.index_tokens(&room);
        self.rooms.insert(room);
    }

    /// The store answered a claim for `conn`'s seat `token`: a room taken over is restored
    /// here, then the rejoin is answered as any other.
    pub fn claimed(
        &mut self,
        now: Instant,
        conn: ConnId,
        token: SeatToken,
        claimed: Claimed,
    ) -> Vec<Output> {
        let elsewhere = matches!(claimed, Claimed::Elsewhere);
        if let Claimed::Taken(r) = claimed {
            self.restore(now, *r);
        } else if let Claimed::Ended { meta, ending, age } = claimed {
            self.restore_ending(now, &meta, ending, age);
        }
        let Some(c) = self.conns.get_mut(&conn) else {
            return Vec::new();
        };
        c.entering = false;
        if elsewhere {
            // The token is a real seat's, not a guess: asking again costs nothing.
            self.refund_entry(conn);
            return error(
                conn,
                ErrorCode::ServerBusy,
                "this game is played on another server instance; try again shortly",
            );
        }
        let msg = ClientMessage::Rejoin { token };
        if self.entry_away(&msg).is_some() {
            // The room is out running a message: the rejoin waits for it.
            return self.route(now, now, conn, msg, None);
        }
        let out = self.rejoin(now, conn, token, false);
        if self.conns.get(&conn).is_some_and(|c| c.room.is_some()) || told_result(&out, conn) {
            self.refund_entry(conn);
        }
        out
    }

    /// Remembers a game found over in the store at start, `age` after it ended.
    pub fn restore_ending(&mut self, now: Instant, meta: &RoomMeta, ending: Ending, age: Duration) {
        let Some(left) = self.config.limits.finished_retention.checked_sub(age) else {
            return;
        };
        let seats = [Seat::A, Seat::B]
            .into_iter()
            .zip(&meta.seats)
            .filter_map(|(seat, s)| s.as_ref().map(|s| (seat, s.digest)));
        self.endings.keep(&ending, seats, now + left);
    }

    /// A connection from `addr` opened its stream.
    pub fn connected(&mut self, now: Instant, conn: ConnId, addr: IpAddr) {
        // Every per-address limit counts under the source's key (an IPv6 /64).
        let addr = source_key(addr);
        self.forget_idle_sources(now);
        let limits = &self.config.limits;
        let per_second = limits.messages_per_second.max(1);
        self.conns.insert(
            conn,
            Conn {
                addr,
                greeting: Greeting::Unknown,
                room: None,
                entering: false,
                chat: Bucket::new(CHAT_BURST, CHAT_REFILL, now),
                messages: Bucket::new(per_second, Duration::from_secs(1) / per_second, now),
                lobby: Bucket::new(LOBBY_BURST, LOBBY_REFILL, now),
                queue: Bucket::new(QUEUE_BURST, QUEUE_REFILL, now),
            },
        );
        let source = self.sources.entry(addr).or_insert_with(|| Source {
            entries: Bucket::new(limits.entry_burst, limits.entry_refill, now),
            last_entry: now,
            conns: 0,
            rooms: 0,
        });
        source.conns += 1;
    }

    /// A connection ended, its peer last heard from at `last_heard`: a seated player's seat is
    /// held for the reconnect window and the shot clock stops as it stood then (after the
    /// room's held events, if it is out).
    pub fn disconnected(&mut self, now: Instant, last_heard: Instant, conn: ConnId) -> Vec<Output> {
        let Some(state) = self.conns.remove(&conn) else {
            return Vec::new();
        };
        // A player who drops while queued is out of the queue: nobody is matched with them.
        self.queues.leave(conn);
        if let Some(source) = self.sources.get_mut(&state.addr) {
            source.conns = source.conns.saturating_sub(1);
        }
        let Some((code, _)) = state.room else {
            return Vec::new();
        };
        if let Some(held) = self.away.get_mut(&code) {
            held.push_back(Held::Disconnect(conn, last_heard));
            return Vec::new();
        }
        match self.rooms.get_mut(&code) {
            Some(mut room) => lift(room.disconnect(now, last_heard, conn)),
            None => Vec::new(),
        }
    }

    /// A message read just now.
    pub fn handle(&mut self, now: Instant, conn: ConnId, msg: ClientMessage) -> Vec<Output> {
        self.handle_read(now, now, conn, msg)
    }

    /// A message read at `read` (carried with a room's work for the server's time per
    /// command).
    pub fn handle_read(
        &mut self,
        now: Instant,
        read: Instant,
        conn: ConnId,
        msg: ClientMessage,
    ) -> Vec<Output> {
        let Some(state) = self.conns.get_mut(&conn) else {
            return Vec::new();
        };
        if !state.messages.take(now) {
            return vec![Output::Room(RoomOutput::Close {
                conn,
                reason: "too many messages".into(),
            })];
        }
        if !matches!(state.greeting, Greeting::Welcomed(_)) {
            return self.hello(conn, msg);
        }
        if state.entering {
            return error(
                conn,
                ErrorCode::Unexpected,
                "the answer to your entry into a room is on its way",
            );
        }
        let msg = match validate(msg) {
            Ok(msg) => msg,
            Err(e) => return error(conn, e.code(), e.to_string()),
        };
        // The connection's own budgets: chat, lobby pages, the quick-match queue.
        let budget = match msg {
            ClientMessage::Chat { .. } => {
                Some((&mut state.chat, "chat is limited to a few lines at a time"))
            }
            ClientMessage::ListGames { .. } | ClientMessage::Leaderboard { .. } => Some((
                &mut state.lobby,
                "the lobby is limited to a few pages a second",
            )),
            ClientMessage::QuickMatch { .. } | ClientMessage::LeaveQueue => Some((
                &mut state.queue,
                "joining and leaving the queue is limited; wait a little",
            )),
            _ => None,
        };
        if let Some((bucket, why)) = budget {
            if !bucket.take(now) {
                return error(conn, ErrorCode::RateLimited, why);
            }
        }
        let in_room = state.room.clone();
        let entering = matches!(
            msg,
            ClientMessage::CreateRoom { .. }
                | ClientMessage::Join { .. }
                | ClientMessage::Rejoin { .. }
                | ClientMessage::Spectate { .. }
        );
        if entering && self.queues.is_queued(conn) {
            return error(
                conn,
                ErrorCode::Unexpected,
                "waiting for a quick match: leave the queue first",
            );
        }
        // Anything that names a room or a seat by a secret the sender may be guessing uses
        // the address's entry budget. A stored record can be fetched from inside a room too.
        let entry = match msg {
            ClientMessage::CreateRoom { .. }
            | ClientMessage::Join { .. }
            | ClientMessage::Rejoin { .. }
            | ClientMessage::Spectate { .. } => in_room.is_none(),
            ClientMessage::FetchRecord { .. } => true,
            _ => false,
        };
        if entry && !self.take_entry(now, conn) {
            return error(
                conn,
                ErrorCode::RateLimited,
                "too many attempts to enter rooms from this address; wait a little",
            );
        }
        let out = self.route(now, read, conn, msg, in_room.clone());
        // Only failed entries are charged: guessing codes or tokens is what the budget is
        // for, and players behind one address (or rejoining after a restart) must not be
        // locked out by their own successes.
        let entered = in_room.is_none() && self.conns.get(&conn).is_some_and(|c| c.room.is_some());
        if entry && (entered || told_result(&out, conn)) {
            self.refund_entry(conn);
        }
        out
    }

    fn route(
        &mut self,
        now: Instant,
        read: Instant,
        conn: ConnId,
        msg: ClientMessage,
        in_room: Option<(RoomCode, Role)>,
    ) -> Vec<Output> {
        if in_room.is_none() {
            if let Some(code) = self.entry_away(&msg) {
                if let Some(c) = self.conns.get_mut(&conn) {
                    c.entering = true;
                }
                if let Some(held) = self.away.get_mut(&code) {
                    held.push_back(Held::Enter(conn, msg));
                }
                return Vec::new();
            }
        }
        match (msg, in_room) {
            (ClientMessage::Hello { .. } | ClientMessage::Prove { .. }, _) => {
                error(conn, ErrorCode::Unexpected, "already greeted")
            }
            // Only the store knows every game (a room that ended is no longer here).
            (ClientMessage::FetchRecord { room, game }, _) => {
                vec![Output::SendRecord {
                    to: conn,
                    room,
                    game,
                }]
            }
            (
                ClientMessage::CreateRoom { .. }
                | ClientMessage::Join { .. }
                | ClientMessage::Rejoin { .. }
                | ClientMessage::Spectate { .. },
                Some(_),
            ) => error(conn, ErrorCode::Unexpected, "already in a room"),
            (
                ClientMessage::CreateRoom {
                    variant,
                    mode,
                    aim_aid,
                    name,
                },
                None,
            ) => {
                let rules = RoomRules {
                    variant,
                    settings: mode,
                    aim_aid,
                    reconnect_window: self.config.limits.reconnect_window,
                    max_commands: self.config.limits.max_commands(variant),
                };
                self.create(now, conn, rules, name)
            }
            (ClientMessage::ListGames { page }, _) => {
                let ratings = &self.ratings;
                vec![send(
                    conn,
                    self.lobby
                        .page(now, page, |k| ratings.get(k).map(PlayerRating::shown)),
                )]
            }
            (ClientMessage::Leaderboard { page }, _) => {
                let (pages, players) = self.ratings.leaderboard(page);
                vec![send(
                    conn,
                    ServerMessage::Leaders {
                        page,
                        pages,
                        players,
                    },
                )]
            }
            (ClientMessage::ReportDesync { .. }, _) => {
                self.desyncs += 1;
                Vec::new()
            }
            (ClientMessage::Publish, in_room) => self.publish(now, conn, in_room),
            (ClientMessage::QuickMatch { .. } | ClientMessage::LeaveQueue, Some(_)) => {
                error(conn, ErrorCode::Unexpected, "already in a room")
            }
            (
                ClientMessage::QuickMatch {
                    variant,
                    mode,
                    name,
                },
                None,
            ) => self.queue(now, conn, variant, mode, name),
            (ClientMessage::LeaveQueue, None) => {
                if self.queues.leave(conn) {
                    vec![send(
                        conn,
                        ServerMessage::Unqueued {
                            reason: "you left the queue".into(),
                        },
                    )]
                } else {
                    error(conn, ErrorCode::Unexpected, "not waiting for a quick match")
                }
            }
            (ClientMessage::Join { room, name }, None) => self.join(now, conn, room, name),
            (ClientMessage::Rejoin { token }, None) => self.rejoin(now, conn, token, true),
            (ClientMessage::Spectate { room }, None) => {
                let entry = self
                    .rooms
                    .get_mut(&room)
                    .map(|mut r| r.spectate(now, conn, MAX_SPECTATORS));
                match entry {
                    Some(entry) => self.entered(conn, room, entry),
                    None => error(conn, ErrorCode::NoSuchRoom, format!("no room {room}")),
                }
            }
            (other, Some((code, role))) => self.lend(&code, Who { conn, role }, other, read),
            (_, None) => error(conn, ErrorCode::Unexpected, "join or create a room first"),
        }
    }

    /// The earliest instant at which [`Hub::tick`] has something to do.
    pub fn next_deadline(&self) -> Option<Instant> {
        let rooms = self.rooms.next_deadline();
        rooms.into_iter().chain(self.queues.next_deadline()).min()
    }

    /// Runs what is due by `now` (shot clocks, forfeits at the end of a reconnect window) and drops
    /// closed rooms, keeping their seats' results; the driver calls it at [`Hub::next_deadline`].
    pub fn tick(&mut self, now: Instant) -> Vec<Output> {
        let mut out = Vec::new();
        // The rooms due and the rooms closed, in the order of their codes.
        let mut ticked = self.rooms.due(now);
        ticked.extend(self.rooms.closed());
        ticked.sort();
        ticked.dedup();
        for code in &ticked {
            if let Some(mut room) = self.rooms.get_mut(code) {
                out.extend(lift(room.tick(now)));
            }
        }
        // A forfeit at the end of a reconnect window ends a rated game too.
        for code in ticked {
            out.extend(self.settle_rating(&code));
        }
        out.extend(self.match_queued(now));
        let closed = self.rooms.closed();
        self.endings.expire(now);
        for code in closed {
            if self.config.shared_store {
                out.push(Output::Room(RoomOutput::Store(StoreOp::Released(
                    code.clone(),
                ))));
            }
            self.tokens.retain(|_, (c, _)| *c != code);
            self.lobby.remove(&code);
            self.rated.remove(&code);
            if let Some(room) = self.rooms.remove(&code) {
                self.keep_ending(now, &room);
            }
            if let Some(addr) = self.creators.remove(&code) {
                if let Some(source) = self.sources.get_mut(&addr) {
                    source.rooms = source.rooms.saturating_sub(1);
                }
            }
        }
        out
    }

    /// Source addresses the hub remembers (for tests and statistics).
    pub fn sources(&self) -> usize {
        self.sources.len()
    }

    /// Rooms created from `addr` whose game is not over. A finished room stays in memory
    /// until its players leave, but no longer counts against its creator's limit.
    fn rooms_in_play(&self, addr: IpAddr) -> usize {
        // A room out running a message counts as in play.
        self.creators
            .iter()
            .filter(|(code, creator)| {
                **creator == addr
                    && (self.away.contains_key(*code)
                        || self
                            .rooms
                            .get(code)
                            .is_some_and(|r| !matches!(r.game().phase(), Phase::Over { .. })))
            })
            .count()
    }

    /// Takes one room entry from the budget of `conn`'s address.
    fn take_entry(&mut self, now: Instant, conn: ConnId) -> bool {
        let Some(addr) = self.conns.get(&conn).map(|c| c.addr) else {
            return false;
        };
        match self.sources.get_mut(&addr) {
            Some(source) => {
                source.last_entry = now;
                source.entries.take(now)
            }
            None => false,
        }
    }

    fn refund_entry(&mut self, conn: ConnId) {
        let addr = self.conns.get(&conn).map(|c| c.addr);
        if let Some(source) = addr.and_then(|a| self.sources.get_mut(&a)) {
            source.entries.refund();
        }
    }

    /// Drops what is remembered about addresses with no connection and no room once their
    /// entry budget has had time to refill, so the map stays as small as the live set.
    fn forget_idle_sources(&mut self, now: Instant) {
        let limits = &self.config.limits;
        let refill = limits
            .entry_refill
            .saturating_mul(limits.entry_burst.min(1_000_000));
        self.sources.retain(|_, s| {
            s.conns > 0 || s.rooms > 0 || now.saturating_duration_since(s.last_entry) < refill
        });
    }

    /// The handshake: `Hello` (version, physics, key) is answered by a fresh challenge, and
    /// its `Prove` by `Welcome`; anything else, or a wrong answer, closes the connection.
    fn hello(&mut self, conn: ConnId, msg: ClientMessage) -> Vec<Output> {
        let Some(state) = self.conns.get_mut(&conn) else {
            return Vec::new();
        };
        let greeting = std::mem::replace(&mut state.greeting, Greeting::Unknown);
        let physics = self.config.physics;
        let reason = match (greeting, msg) {
            (Greeting::Unknown, ClientMessage::Hello { protocol, .. })
                if protocol != PROTOCOL_VERSION =>
            {
                format!(
                    "protocol version {protocol} is not supported; this server speaks version {PROTOCOL_VERSION}"
                )
            }
            (
                Greeting::Unknown,
                ClientMessage::Hello {
                    physics: theirs, ..
                },
            ) if theirs != physics => {
                format!(
                    "physics differ: reference shot hash {theirs:016x}, the server's is {physics:016x}; update the game"
                )
            }
            (Greeting::Unknown, ClientMessage::Hello { key, .. }) => {
                match PlayerKey::from_wire(&key) {
                    Ok(key) => {
                        let mut nonce = [0u8; NONCE_LEN];
                        self.rng.fill(&mut nonce);
                        if let Some(c) = self.conns.get_mut(&conn) {
                            c.greeting = Greeting::Challenged { key, nonce };
                        }
                        return vec![send(conn, ServerMessage::Challenge { nonce })];
                    }
                    Err(e) => e.to_string(),
                }
            }
            (Greeting::Challenged { key, nonce }, ClientMessage::Prove { signature }) => {
                match key.verify(&nonce, PROTOCOL_VERSION, physics, &signature) {
                    Ok(()) => {
                        if let Some(c) = self.conns.get_mut(&conn) {
                            c.greeting = Greeting::Welcomed(key);
                        }
                        return vec![send(
                            conn,
                            ServerMessage::Welcome {
                                protocol: PROTOCOL_VERSION,
                            },
                        )];
                    }
                    Err(e) => e.to_string(),
                }
            }
            (Greeting::Challenged { .. }, _) => "the answer to a challenge must be Prove".into(),
            _ => "the first message must be Hello".into(),
        };
        vec![
            send(
                conn,
                ServerMessage::Reject {
                    reason: reason.clone(),
                },
            ),
            Output::Room(RoomOutput::Close { conn, reason }),
        ]
    }

    /// The player a welcomed connection is (its key), if it is welcomed.
    pub fn player_of(&self, conn: ConnId) -> Option<PlayerKey> {
        match self.conns.get(&conn)?.greeting {
            Greeting::Welcomed(key) => Some(key),
            _ => None,
        }
    }

    /// Whether the server holds the most rooms it may.
    fn full(&self) -> bool {
        self.room_count() >= self.config.limits.max_rooms.min(MAX_ROOMS)
    }

    /// While the server drains, a new game is refused (and counted as a drain refusal).
    fn refuse_while_draining(&mut self, conn: ConnId) -> Option<Vec<Output>> {
        if !self.draining {
            return None;
        }
        self.drain_refusals += 1;
        Some(error(
            conn,
            ErrorCode::ServerBusy,
            "this server is shutting down and opens no new games; try another",
        ))
    }

    fn create(
        &mut self,
        now: Instant,
        conn: ConnId,
        rules: RoomRules,
        name: String,
    ) -> Vec<Output> {
        if let Some(refused) = self.refuse_while_draining(conn) {
            return refused;
        }
        if self.full() {
            return error(conn, ErrorCode::ServerBusy, "the server is full; try later");
        }
        let addr = self.conns.get(&conn).map(|c| c.addr);
        let owned = addr.map_or(0, |a| self.rooms_in_play(a));
        if owned >= self.config.limits.rooms_per_address {
            return error(
                conn,
                ErrorCode::ServerBusy,
                "too many open rooms from this address; finish one first",
            );
        }
        let code = self.new_code();
        let token = new_token(self.rng.as_mut());
        let seed = new_seed(self.rng.as_mut());
        let (room, out) = Room::create(now, code.clone(), rules, seed, conn, name, token);
        self.tokens
            .insert(TokenDigest::of(&token), (code.clone(), Seat::A));
        self.rooms.insert(room);
        if let Some(addr) = addr {
            self.creators.insert(code.clone(), addr);
            if let Some(source) = self.sources.get_mut(&addr) {
                source.rooms += 1;
            }
        }
        self.set_room(conn, code, Role::Player(Seat::A));
        lift(out)
    }

    fn join(&mut self, now: Instant, conn: ConnId, code: RoomCode, name: String) -> Vec<Output> {
        let token = new_token(self.rng.as_mut());
        let Some(entry) = self
            .rooms
            .get_mut(&code)
            .map(|mut room| room.join(now, conn, name.clone(), token))
        else {
            return error(conn, ErrorCode::NoSuchRoom, format!("no room {code}"));
        };
        if entry.role.is_some() {
            self.tokens
                .insert(TokenDigest::of(&token), (code.clone(), Seat::B));
            let key = self.player_of(conn);
            if let Some(host) = self.lobby.seated(&code, Listed { name, key }) {
                let listed = StoreOp::Listed {
                    room: code.clone(),
                    players: [host, key],
                };
                let mut out = self.entered(conn, code, entry);
                out.insert(0, Output::Room(RoomOutput::Store(listed)));
                return out;
            }
        }
        self.entered(conn, code, entry)
    }

    /// A seat token's player comes back; with `claim`, a token no room here knows is looked
    /// for in a shared store.
    fn rejoin(&mut self, now: Instant, conn: ConnId, token: SeatToken, claim: bool) -> Vec<Output> {
        let digest = TokenDigest::of(&token);
        let Some((code, seat)) = self.tokens.get(&digest).cloned() else {
            if let Some(result) = self.endings.answer(now, &digest) {
                return vec![send(conn, result)];
            }
            if claim && self.config.shared_store {
                if let Some(c) = self.conns.get_mut(&conn) {
                    c.entering = true;
                }
                return vec![Output::Claim { conn, token }];
            }
            return error(
                conn,
                ErrorCode::BadToken,
                "unknown seat token (the game may be over)",
            );
        };
        let Some(entry) = self
            .rooms
            .get_mut(&code)
            .map(|mut room| room.rejoin(now, conn, seat, token))
        else {
            return error(conn, ErrorCode::NoSuchRoom, "the room is closed");
        };
        self.entered(conn, code, entry)
    }

    /// Indexes what an entry point did: `conn` is in room `code` with its role, and the
    /// connection it replaced is in no room. Returns what the entry sends, with the seats'
    /// ratings after it in a rated room.
    fn entered(&mut self, conn: ConnId, code: RoomCode, entry: Entered) -> Vec<Output> {
        let mut out = lift(entry.out);
        let Some(role) = entry.role else { return out };
        if let Some(c) = entry.replaced.and_then(|old| self.conns.get_mut(&old)) {
            c.room = None;
        }
        out.extend(self.ratings_told(conn, &code));
        self.set_room(conn, code, role);
        out
    }

    /// The seats' ratings for `conn`, if `code` is a rated room.
    pub(super) fn ratings_told(&self, conn: ConnId, code: &RoomCode) -> Option<Output> {
        let game = self.rated.get(code)?;
        let ratings = game.keys.map(|k| self.ratings.shown_or_start(&k));
        Some(send(conn, ServerMessage::Ratings { ratings }))
    }

    /// A room code no open room has.
    fn new_code(&mut self) -> RoomCode {
        loop {
            let mut bytes = [0u8; ROOM_CODE_LEN];
            self.rng.fill(&mut bytes);
            let code = RoomCode::from_random(bytes);
            if !self.rooms.contains_key(&code) && !self.away.contains_key(&code) {
                return code;
            }
        }
    }

    /// Keeps the seats of a closing room's last game, so its players learn how it ended.
    fn keep_ending(&mut self, now: Instant, room: &Room) {
        let (winner, reason) = match room.game().phase() {
            Phase::Over { winner, reason } => (*winner, reason.clone()),
            _ => (None, "abandoned".to_string()),
        };
        let ending = Ending {
            room: room.code().clone(),
            game: room.game_number(),
            winner,
            reason,
        };
        let until = now + self.config.limits.finished_retention;
        self.endings.keep(&ending, room.seat_digests(), until);
    }

    fn set_room(&mut self, conn: ConnId, code: RoomCode, role: Role) {
        if let Some(c) = self.conns.get_mut(&conn) {
            c.room = Some((code, role));
        }
    }

    fn index_tokens(&mut self, room: &Room) {
        for (seat, digest) in room.seat_digests() {
            self.tokens.insert(digest, (room.code().clone(), seat));
        }
    }
}

/// Whether the outputs tell `conn` how its game ended (a valid token of a finished game).
fn told_result(out: &[Output], conn: ConnId) -> bool {
    out.iter().any(
        |o| matches!(o, Output::Room(RoomOutput::Send { to, msg: ServerMessage::GameFinished { .. } }) if *to == conn),
    )
}

mod public;
#[cfg(test)]
mod tests;
