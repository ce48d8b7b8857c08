//! The hub and its rooms without sockets or a clock: messages in, outputs out.

use std::time::{Duration, Instant};

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::limits::{
    CHAT_BURST, CHAT_REFILL, LOBBY_BURST, MAX_MESSAGES_PER_SECOND, QUEUE_TIMEOUT,
};
use breakshot_shared::protocol::{
    reference_hash, AimAid, ClientMessage, ErrorCode, Identity, PlayerKey, Role, RoomCode,
    SeatToken, ServerMessage, PROTOCOL_VERSION,
};
use breakshot_shared::replay::{GameRecord, RecordEntry};
use breakshot_shared::rules::{Command, EightBallRules, Game, Seat, Settings, Variant};
use glam::DVec2;

use super::Output;
use super::{Claimed, Hub, HubConfig, Restored};
use crate::limits::Limits;
use crate::output::{ConnId, RoomOutput, StoreOp};
use crate::room::ClockLeft;
use crate::secret::TestEntropy;

const WINDOW: Duration = Duration::from_secs(120);
const PEER: std::net::IpAddr = std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST);

struct World {
    hub: Hub,
    now: Instant,
}

/// The player of connection `conn` in these tests: a key of its own.
fn identity(conn: ConnId) -> Identity {
    let mut seed = [0u8; 32];
    seed[..8].copy_from_slice(&conn.to_le_bytes());
    Identity::from_seed(&seed)
}

fn hello_of(id: &Identity) -> ClientMessage {
    ClientMessage::Hello {
        protocol: PROTOCOL_VERSION,
        physics: reference_hash().unwrap(),
        key: id.public().0.to_vec(),
    }
}

fn challenge_in(out: &[Output], conn: ConnId) -> [u8; 32] {
    match sent_to(out, conn)[..] {
        [ServerMessage::Challenge { nonce }] => *nonce,
        ref other => panic!("no challenge: {other:?}"),
    }
}

fn prove(id: &Identity, nonce: &[u8; 32]) -> ClientMessage {
    ClientMessage::Prove {
        signature: id.sign(nonce, PROTOCOL_VERSION, reference_hash().unwrap()),
    }
}

fn sent_to(out: &[Output], conn: ConnId) -> Vec<&ServerMessage> {
    out.iter()
        .filter_map(|o| match o {
            Output::Room(RoomOutput::Send { to, msg }) if *to == conn => Some(msg),
            _ => None,
        })
        .collect()
}

/// Whether `conn` was sent a message `want` accepts.
fn got(out: &[Output], conn: ConnId, want: impl Fn(&ServerMessage) -> bool) -> bool {
    sent_to(out, conn).into_iter().any(want)
}

fn error_code(out: &[Output], conn: ConnId) -> Option<ErrorCode> {
    sent_to(out, conn).into_iter().find_map(|m| match m {
        ServerMessage::Error { code, .. } => Some(*code),
        _ => None,
    })
}

/// Opens a WPA 8-ball room with no aim aid, for a player called `name`.
fn create_room(mode: Settings, name: &str) -> ClientMessage {
    ClientMessage::CreateRoom {
        variant: Variant::EightBall(EightBallRules::Wpa),
        mode,
        aim_aid: AimAid::Off,
        name: name.into(),
    }
}

fn join_room(room: &RoomCode, name: &str) -> ClientMessage {
    ClientMessage::Join {
        room: room.clone(),
        name: name.into(),
    }
}

fn stores(out: &[Output]) -> usize {
    out.iter()
        .filter(|o| matches!(o, Output::Room(RoomOutput::Store(_))))
        .count()
}

impl World {
    fn new() -> World {
        World::with_store(false)
    }

    /// A hub whose store other instances share (or not).
    fn with_store(shared_store: bool) -> World {
        let config = HubConfig {
            limits: Limits {
                reconnect_window: WINDOW,
                max_rooms: 100,
                ..Limits::default()
            },
            physics: reference_hash().unwrap(),
            shared_store,
        };
        World {
            hub: Hub::new(config, Box::new(TestEntropy::new(9))),
            now: Instant::now(),
        }
    }

    /// What the hub and the rooms it lends out answer, as a driver with one worker that
    /// runs every room's work at once would carry it out.
    fn send(&mut self, conn: ConnId, msg: ClientMessage) -> Vec<Output> {
        let out = self.hub.handle(self.now, conn, msg);
        self.settle(out)
    }

    /// Runs every room's work in `out` in place, and gives the rooms back.
    fn settle(&mut self, out: Vec<Output>) -> Vec<Output> {
        let mut done = Vec::new();
        for o in out {
            match o {
                Output::Run(work) => {
                    let (worked, back) = work.run(self.now);
                    done.extend(self.settle(super::lift(worked)));
                    let after = self.hub.returned(self.now, back);
                    done.extend(self.settle(after));
                }
                other => done.push(other),
            }
        }
        done
    }

    fn greet(&mut self, conn: ConnId) {
        self.hub.connected(self.now, conn, PEER);
        self.handshake(conn);
    }

    /// Hello, the challenge, the proof: conn is welcomed as [`identity`]`(conn)`.
    fn handshake(&mut self, conn: ConnId) {
        let id = identity(conn);
        let out = self.send(conn, hello_of(&id));
        let nonce = challenge_in(&out, conn);
        let out = self.send(conn, prove(&id, &nonce));
        assert_eq!(self.hub.player_of(conn), Some(id.public()));
        assert!(matches!(
            sent_to(&out, conn)[..],
            [ServerMessage::Welcome { .. }]
        ));
    }

    /// A new world in which [`World::pair`] has seated two players: it, the room and the
    /// seats' tokens.
    fn paired(settings: Settings) -> (World, RoomCode, SeatToken, SeatToken) {
        let mut w = World::new();
        let (room, token_a, token_b) = w.pair(settings);
        (w, room, token_a, token_b)
    }

    /// Conn 1 creates a room (seat A), conn 2 joins it (seat B).
    fn pair(&mut self, settings: Settings) -> (RoomCode, SeatToken, SeatToken) {
        let (room, token_a, token_b, _) = self.pair_seen(settings);
        (room, token_a, token_b)
    }

    /// [`World::pair`], with what the join sent.
    fn pair_seen(&mut self, settings: Settings) -> (RoomCode, SeatToken, SeatToken, Vec<Output>) {
        self.greet(1);
        self.greet(2);
        let out = self.send(1, create_room(settings, "ann"));
        let (room, token_a) = joined(&out, 1);
        let out = self.send(2, join_room(&room, "ben"));
        let (_, token_b) = joined(&out, 2);
        assert!(got(&out, 1, |m| matches!(
            m,
            ServerMessage::PlayerJoined { seat: Seat::B, .. }
        )));
        (room, token_a, token_b, out)
    }

    fn game(&self, room: &RoomCode) -> Game {
        self.hub.room(room).unwrap().game().clone()
    }

    fn advance(&mut self, d: Duration) -> Vec<Output> {
        self.now += d;
        self.hub.tick(self.now)
    }
}

fn joined(out: &[Output], conn: ConnId) -> (RoomCode, SeatToken) {
    sent_to(out, conn)
        .into_iter()
        .find_map(|m| match m {
            ServerMessage::Joined {
                token: Some(t),
                snapshot,
                ..
            } => Some((snapshot.room.clone(), *t)),
            _ => None,
        })
        .expect("joined with a token")
}

fn break_shot(game: &Game) -> ClientMessage {
    let cue = game.balls()[0].pos;
    let target = game.balls()[1..]
        .iter()
        .map(|b| b.pos)
        .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
        .unwrap();
    ClientMessage::Shot {
        turn: game.turn(),
        strike: Strike {
            speed: 9.0,
            dir: target - cue,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        },
        call: None,
    }
}

#[test]
fn the_handshake_refuses_other_versions_other_physics_and_silence() {
    let mut w = World::new();
    for (conn, msg, why) in [
        (
            1,
            ClientMessage::Hello {
                protocol: PROTOCOL_VERSION + 1,
                physics: reference_hash().unwrap(),
                key: identity(1).public().0.to_vec(),
            },
            "protocol version",
        ),
        (
            4,
            // The version before the cue elevation.
            ClientMessage::Hello {
                protocol: PROTOCOL_VERSION - 1,
                physics: reference_hash().unwrap(),
                key: Vec::new(),
            },
            "protocol version",
        ),
        (
            2,
            ClientMessage::Hello {
                protocol: PROTOCOL_VERSION,
                physics: reference_hash().unwrap() ^ 1,
                key: identity(2).public().0.to_vec(),
            },
            "physics differ",
        ),
        (3, ClientMessage::Concede, "first message must be Hello"),
    ] {
        w.hub.connected(w.now, conn, PEER);
        let out = w.send(conn, msg);
        match sent_to(&out, conn)[..] {
            [ServerMessage::Reject { reason }] => assert!(reason.contains(why), "{reason}"),
            ref other => panic!("{other:?}"),
        }
        assert!(
            matches!(out.last(), Some(Output::Room(RoomOutput::Close { conn: c, .. })) if *c == conn)
        );
    }
}

/// The reject and close a hostile handshake gets, with the reason.
fn refused(out: &[Output], conn: ConnId) -> String {
    assert!(
        matches!(out.last(), Some(Output::Room(RoomOutput::Close { conn: c, .. })) if *c == conn),
        "{out:?}"
    );
    match sent_to(out, conn)[..] {
        [ServerMessage::Reject { reason }] => reason.clone(),
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn a_key_must_be_proved_over_this_connection_s_own_challenge() {
    let mut w = World::new();
    let ann = identity(1);
    // A forged signature: another key signed the challenge.
    w.hub.connected(w.now, 1, PEER);
    let nonce = challenge_in(&w.send(1, hello_of(&ann)), 1);
    let why = refused(&w.send(1, prove(&identity(66), &nonce)), 1);
    assert!(why.contains("does not prove the key"), "{why}");
    assert_eq!(w.hub.player_of(1), None);
    // A replayed challenge: the proof seen on one connection, sent on another.
    w.hub.connected(w.now, 2, PEER);
    let seen = challenge_in(&w.send(2, hello_of(&ann)), 2);
    let proof = prove(&ann, &seen);
    assert!(matches!(
        sent_to(&w.send(2, proof.clone()), 2)[..],
        [ServerMessage::Welcome { .. }]
    ));
    w.hub.connected(w.now, 3, PEER);
    let fresh = challenge_in(&w.send(3, hello_of(&ann)), 3);
    assert_ne!(fresh, seen, "each connection has its own challenge");
    let why = refused(&w.send(3, proof.clone()), 3);
    assert!(why.contains("does not prove the key"), "{why}");
    // Nor does the proof count twice on its own connection.
    assert_eq!(
        error_code(&w.send(2, proof), 2),
        Some(ErrorCode::Unexpected)
    );
    // Keys and signatures of the wrong length.
    for (conn, len) in [(4, 0), (5, 31), (6, 33), (7, 1000)] {
        w.hub.connected(w.now, conn, PEER);
        let hello = ClientMessage::Hello {
            protocol: PROTOCOL_VERSION,
            physics: reference_hash().unwrap(),
            key: vec![5; len],
        };
        let why = refused(&w.send(conn, hello), conn);
        assert!(why.contains(&format!("not {len}")), "{why}");
    }
    w.hub.connected(w.now, 8, PEER);
    let nonce = challenge_in(&w.send(8, hello_of(&identity(8))), 8);
    let mut short = prove(&identity(8), &nonce);
    if let ClientMessage::Prove { signature } = &mut short {
        signature.pop();
    }
    let why = refused(&w.send(8, short), 8);
    assert!(why.contains("signature is 64 bytes"), "{why}");
    // A proof before any Hello, and anything but a proof after one.
    w.hub.connected(w.now, 9, PEER);
    let why = refused(&w.send(9, prove(&identity(9), &[0; 32])), 9);
    assert!(why.contains("first message must be Hello"), "{why}");
    w.hub.connected(w.now, 10, PEER);
    challenge_in(&w.send(10, hello_of(&identity(10))), 10);
    let why = refused(&w.send(10, hello_of(&identity(10))), 10);
    assert!(why.contains("must be Prove"), "{why}");
}

#[test]
fn an_accepted_shot_is_stored_before_anyone_hears_of_it_and_matches_a_replay() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    let before = w.game(&room);
    let shot = break_shot(&before);
    let out = w.send(1, shot.clone());

    // The store comes first; then both players get the same accepted command and result.
    assert!(matches!(
        out[0],
        Output::Room(RoomOutput::Store(StoreOp::Command {
            number: 1,
            index: 0,
            ..
        }))
    ));
    for conn in [1, 2] {
        let msgs = sent_to(&out, conn);
        assert!(matches!(
            msgs[0],
            ServerMessage::ShotAccepted {
                turn: 0,
                seat: Seat::A,
                ..
            }
        ));
        assert!(matches!(
            msgs[1],
            ServerMessage::ShotResolved { turn: 0, .. }
        ));
    }
    let ServerMessage::ShotResolved { hash, game, .. } = sent_to(&out, 2)[1] else {
        unreachable!()
    };
    // The same command applied to a copy of the old game gives the same hash.
    let ClientMessage::Shot { strike, .. } = shot else {
        unreachable!()
    };
    let mut copy = before.clone();
    let verdict = copy
        .apply(
            Seat::A,
            &Command::Shot {
                strike: strike.validated().unwrap(),
                call: None,
            },
        )
        .unwrap();
    assert_eq!(verdict.shot.unwrap().hash, *hash);
    // The game sent is the rules' game after the shot, all of it.
    assert_eq!(&copy, &**game);
    // And the stored header and command replay to the room's game.
    let Output::Room(RoomOutput::Store(StoreOp::Command { entry, .. })) = &out[0] else {
        unreachable!()
    };
    let mut record = GameRecord::of(&before);
    record.entries.push(RecordEntry::decode(entry).unwrap());
    let replayed = record.replay().unwrap();
    assert_eq!(replayed, w.game(&room));
}

#[test]
fn refused_commands_store_nothing_and_change_nothing() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    let before = w.game(&room);
    let good = break_shot(&before);
    let ClientMessage::Shot { strike, call, .. } = good.clone() else {
        unreachable!()
    };
    let stale = ClientMessage::Shot {
        turn: 5,
        strike,
        call,
    };
    let nan = ClientMessage::Shot {
        turn: 0,
        strike: Strike {
            speed: f64::NAN,
            ..strike
        },
        call,
    };
    for (conn, msg, code) in [
        (2, good.clone(), ErrorCode::NotYourTurn),
        (1, stale, ErrorCode::StaleTurn),
        (1, nan, ErrorCode::Invalid),
        (1, ClientMessage::Rematch, ErrorCode::Unexpected),
        (
            1,
            ClientMessage::Join {
                room: room.clone(),
                name: "x".into(),
            },
            ErrorCode::Unexpected,
        ),
    ] {
        let out = w.send(conn, msg);
        assert_eq!(error_code(&out, conn), Some(code));
        assert_eq!(stores(&out), 0);
        assert_eq!(w.game(&room), before);
    }
}

#[test]
fn a_dropped_player_forfeits_only_when_the_window_runs_out() {
    let (mut w, _, _, token_b) = World::paired(Settings::offline());
    let out = w.hub.disconnected(w.now, w.now, 2);
    assert!(matches!(
        sent_to(&out, 1)[..],
        [ServerMessage::PlayerLeft {
            seat: Seat::B,
            reconnect_ms: 120_000
        }]
    ));

    // Back in time: the seat is theirs again, and the old deadline does nothing.
    w.now += WINDOW / 2;
    w.greet(3);
    let out = w.send(3, ClientMessage::Rejoin { token: token_b });
    assert!(matches!(
        sent_to(&out, 1)[..],
        [ServerMessage::PlayerBack { seat: Seat::B }]
    ));
    assert!(matches!(
        sent_to(&out, 3)[..],
        [ServerMessage::Joined {
            role: Role::Player(Seat::B),
            ..
        }]
    ));
    assert!(w.advance(WINDOW).is_empty());

    // Gone for good this time.
    w.hub.disconnected(w.now, w.now, 3);
    assert!(w.advance(WINDOW - Duration::from_millis(1)).is_empty());
    let out = w.advance(Duration::from_millis(1));
    assert!(got(&out, 1, |m| matches!(
        m,
        ServerMessage::GameOver {
            winner: Some(Seat::A),
            reason,
        } if reason.contains("Player B left and forfeited")
    )));
    assert!(out.iter().any(|o| matches!(
        o,
        Output::Room(RoomOutput::Store(StoreOp::GameEnded {
            winner: Some(Seat::A),
            ..
        }))
    )));
}

#[test]
fn a_wrong_token_takes_no_seat() {
    let (mut w, ..) = World::paired(Settings::offline());
    w.greet(3);
    let out = w.send(
        3,
        ClientMessage::Rejoin {
            token: SeatToken([0; 16]),
        },
    );
    assert_eq!(error_code(&out, 3), Some(ErrorCode::BadToken));
}

#[test]
fn the_shot_clock_runs_out_but_pauses_while_a_player_is_away() {
    let (mut w, room, _, token_b) = World::paired(clocked());
    assert!(w.advance(Duration::from_secs(10)).is_empty());

    // B drops with 20 s left on A's clock: the clock stops.
    w.hub.disconnected(w.now, w.now, 2);
    assert!(w.advance(Duration::from_secs(60)).is_empty());
    assert_eq!(w.game(&room).turn(), 0);

    // B is back: the clock goes on from 20 s.
    w.greet(3);
    w.send(3, ClientMessage::Rejoin { token: token_b });
    assert!(w.advance(Duration::from_secs(19)).is_empty());
    let out = w.advance(Duration::from_secs(1));
    assert!(got(&out, 1, |m| matches!(
        m,
        ServerMessage::Applied {
            seat: Seat::A,
            command: Command::TimeExpired,
            ..
        }
    )));
    // The command, and the next turn's clock.
    assert_eq!(stores(&out), 2);
    assert_eq!(w.game(&room).turn(), 1);
}

#[test]
fn every_seat_sees_the_shot_clock_from_the_opening_break_and_after_a_return() {
    let mut w = World::new();
    // The clock starts when B sits down: the host is told so, B reads it in the snapshot.
    let (_, _, token_b, out) = w.pair_seen(clocked());
    assert_eq!(clock_told(&out, 1), Some(30_000));
    let snapshot_clock = sent_to(&out, 2).iter().find_map(|m| match m {
        ServerMessage::Joined { snapshot, .. } => snapshot.shot_clock_ms,
        _ => None,
    });
    assert_eq!(snapshot_clock, Some(30_000));

    // B drops with 20 s left and comes back: the host learns the clock runs again from 20 s.
    w.advance(Duration::from_secs(10));
    w.hub.disconnected(w.now, w.now, 2);
    w.advance(Duration::from_secs(60));
    w.greet(3);
    let out = w.send(3, ClientMessage::Rejoin { token: token_b });
    assert_eq!(clock_told(&out, 1), Some(20_000));
}

/// The clock of a room with a 30 s shot clock, as `out` tells `conn` (a `TurnChanged`).
fn clock_told(out: &[Output], conn: ConnId) -> Option<u64> {
    sent_to(out, conn).iter().find_map(|m| match m {
        ServerMessage::TurnChanged { shot_clock_ms, .. } => *shot_clock_ms,
        _ => None,
    })
}

/// The last shot clock `out` stores: (turn, ms left, running).
fn clock_stored(out: &[Output]) -> Option<(u32, u64, bool)> {
    out.iter().rev().find_map(|o| match o {
        Output::Room(RoomOutput::Store(StoreOp::Clock {
            turn,
            left_ms,
            running,
            ..
        })) => Some((*turn, *left_ms, *running)),
        _ => None,
    })
}

fn clocked() -> Settings {
    Settings {
        shot_clock: Some(30),
        ..Settings::offline()
    }
}

#[test]
fn the_clock_stops_when_a_silent_player_was_last_heard_and_the_opponent_is_told_at_once() {
    let (mut w, room, token_a, _) = World::paired(clocked());
    // A, to move, falls silent after 12 s; the server finds out 5 s later (the idle
    // timeout). The clock stopped at 12 s, with 18 s left, and B hears of it at once.
    w.advance(Duration::from_secs(12));
    let last_heard = w.now;
    w.now += Duration::from_secs(5);
    let out = w.hub.disconnected(w.now, last_heard, 1);
    assert!(matches!(
        sent_to(&out, 2)[..],
        [ServerMessage::PlayerLeft { seat: Seat::A, .. }]
    ));
    assert_eq!(clock_stored(&out), Some((0, 18_000, false)));
    // However long A is away, nothing runs out.
    assert!(w.advance(Duration::from_secs(100)).is_empty());

    // A is back with the 18 s they had.
    w.greet(3);
    let out = w.send(3, ClientMessage::Rejoin { token: token_a });
    let snapshot_clock = sent_to(&out, 3).iter().find_map(|m| match m {
        ServerMessage::Joined { snapshot, .. } => snapshot.shot_clock_ms,
        _ => None,
    });
    assert_eq!(snapshot_clock, Some(18_000));
    assert_eq!(clock_told(&out, 2), Some(18_000));
    assert_eq!(clock_stored(&out), Some((0, 18_000, true)));
    assert!(w
        .advance(Duration::from_millis(17_999))
        .iter()
        .all(|o| !matches!(o, Output::Room(RoomOutput::Send { .. }))));
    let out = w.advance(Duration::from_millis(1));
    assert!(got(&out, 2, |m| matches!(
        m,
        ServerMessage::Applied {
            command: Command::TimeExpired,
            ..
        }
    )));
    assert_eq!(w.game(&room).turn(), 1);
}

#[test]
fn a_player_who_dropped_with_seconds_left_comes_back_to_the_fair_minimum() {
    let (mut w, _, token_a, _) = World::paired(clocked());
    w.advance(Duration::from_secs(27));
    w.hub.disconnected(w.now, w.now, 1);
    w.advance(Duration::from_secs(30));
    w.greet(3);
    let out = w.send(3, ClientMessage::Rejoin { token: token_a });
    let minimum = breakshot_shared::protocol::limits::MIN_CLOCK_ON_RETURN;
    assert_eq!(
        clock_told(&out, 2),
        Some(u64::try_from(minimum.as_millis()).unwrap())
    );
}

#[test]
fn a_restored_room_gives_the_player_to_move_the_time_stored_not_a_full_clock() {
    let mut first = World::new();
    let (room, token_a, token_b) = first.pair(clocked());
    first.advance(Duration::from_secs(8));
    // The server stops: both connections close, and each stop of the clock is stored.
    first.hub.disconnected(first.now, first.now, 2);
    let out = first.hub.disconnected(first.now, first.now, 1);
    assert_eq!(clock_stored(&out), Some((0, 22_000, false)));
    let left = first.hub.room(&room).unwrap();
    // The room as the store gives it back, with 22 s left stored for `turn`.
    let stored = |turn| Restored {
        meta: left.meta(),
        number: left.game_number(),
        record: left.record().clone(),
        game: left.game().clone(),
        clock: Some(ClockLeft {
            turn,
            left: Duration::from_secs(22),
        }),
        rated: None,
        listed: None,
    };
    // A server restores `room` and both players come back: what the second's return sends.
    let back = |room: Restored| {
        let mut w = World::new();
        w.hub.restore(w.now, room);
        w.greet(1);
        w.greet(2);
        w.send(1, ClientMessage::Rejoin { token: token_a });
        w.send(2, ClientMessage::Rejoin { token: token_b })
    };
    assert_eq!(clock_told(&back(stored(0)), 1), Some(22_000));
    // A clock stored for another turn is not used: the turn gets a full clock.
    assert_eq!(clock_told(&back(stored(7)), 1), Some(30_000));
}

#[test]
fn chat_is_rate_limited_and_floods_close_the_connection() {
    let (mut w, ..) = World::paired(Settings::offline());
    let line = || ClientMessage::Chat {
        text: "nice shot".into(),
    };
    for _ in 0..CHAT_BURST {
        let out = w.send(1, line());
        assert!(got(&out, 2, |m| matches!(m, ServerMessage::Chat { .. })));
    }
    assert_eq!(
        error_code(&w.send(1, line()), 1),
        Some(ErrorCode::RateLimited)
    );
    w.now += CHAT_REFILL;
    assert_eq!(error_code(&w.send(1, line()), 1), None);

    w.now += Duration::from_secs(5);
    let mut closed = false;
    for _ in 0..=MAX_MESSAGES_PER_SECOND {
        let out = w.send(2, ClientMessage::Rematch);
        closed |= out
            .iter()
            .any(|o| matches!(o, Output::Room(RoomOutput::Close { conn: 2, .. })));
    }
    assert!(closed);
}

#[test]
fn spectators_watch_but_cannot_act() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    w.greet(3);
    let out = w.send(3, ClientMessage::Spectate { room: room.clone() });
    assert!(matches!(
        sent_to(&out, 3)[..],
        [ServerMessage::Joined {
            role: Role::Spectator,
            token: None,
            ..
        }]
    ));
    let before = w.game(&room);
    let out = w.send(3, break_shot(&before));
    assert_eq!(error_code(&out, 3), Some(ErrorCode::Spectator));
    assert_eq!(w.game(&room), before);
    // They do see the players' shots.
    let out = w.send(1, break_shot(&before));
    assert!(got(&out, 3, |m| matches!(
        m,
        ServerMessage::ShotResolved { .. }
    )));
}

#[test]
fn the_shooters_aim_is_shown_to_the_others_live_and_nothing_else_changes() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    w.greet(3);
    w.send(3, ClientMessage::Spectate { room: room.clone() });
    let before = w.game(&room);
    let strike = Strike::at_angle(2.0, 80.0, DVec2::ZERO)
        .validated()
        .expect("a valid strike");
    let aim = |turn| ClientMessage::Aim { turn, strike };
    let out = w.send(1, aim(before.turn()));
    for conn in [2, 3] {
        assert!(
            sent_to(&out, conn).iter().any(|m| matches!(
                m,
                ServerMessage::Aim { seat: Seat::A, strike: s, .. } if *s == strike
            )),
            "conn {conn} saw no aim"
        );
    }
    assert!(sent_to(&out, 1).is_empty(), "the shooter is not echoed");
    assert_eq!(stores(&out), 0, "an aim is not stored");
    // Out of turn, or from the other seat: dropped without a word.
    assert!(w.send(1, aim(before.turn() + 1)).is_empty());
    assert!(w.send(2, aim(before.turn())).is_empty());
    // A strike that is no strike is refused like a shot's.
    let bad = ClientMessage::Aim {
        turn: before.turn(),
        strike: Strike {
            speed: f64::NAN,
            ..strike
        },
    };
    assert_eq!(error_code(&w.send(1, bad), 1), Some(ErrorCode::Invalid));
    assert_eq!(w.game(&room), before);
}

#[test]
fn a_called_pocket_is_announced_and_carried_by_the_shot() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    let call = |turn| ClientMessage::CallPocket { turn, pocket: 3 };
    assert_eq!(
        error_code(&w.send(2, call(0)), 2),
        Some(ErrorCode::NotYourTurn)
    );
    assert_eq!(
        error_code(&w.send(1, call(7)), 1),
        Some(ErrorCode::StaleTurn)
    );
    let out = w.send(1, call(0));
    for conn in [1, 2] {
        assert!(matches!(
            sent_to(&out, conn)[..],
            [ServerMessage::PocketCalled {
                turn: 0,
                seat: Seat::A,
                pocket: 3
            }]
        ));
    }
    assert_eq!(stores(&out), 0);
    let out = w.send(1, break_shot(&w.game(&room)));
    assert!(got(&out, 2, |m| matches!(
        m,
        ServerMessage::ShotAccepted {
            command: Command::Shot { call: Some(3), .. },
            ..
        }
    )));
}

#[test]
fn a_rematch_starts_when_both_players_ask() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    assert_eq!(
        error_code(&w.send(1, ClientMessage::Rematch), 1),
        Some(ErrorCode::Unexpected)
    );
    let out = w.send(2, ClientMessage::Concede);
    assert!(got(&out, 1, |m| matches!(
        m,
        ServerMessage::GameOver {
            winner: Some(Seat::A),
            ..
        }
    )));

    let out = w.send(1, ClientMessage::Rematch);
    assert!(matches!(
        sent_to(&out, 2)[..],
        [ServerMessage::RematchOffered { seat: Seat::A }]
    ));
    let out = w.send(2, ClientMessage::Rematch);
    assert!(matches!(
        out[0],
        Output::Room(RoomOutput::Store(StoreOp::GameStarted { number: 2, .. }))
    ));
    for conn in [1, 2] {
        match sent_to(&out, conn)[..] {
            [ServerMessage::GameStarted { snapshot }] => {
                assert_eq!(snapshot.game_number, 2);
                assert_eq!(snapshot.game.turn(), 0);
            }
            ref other => panic!("{other:?}"),
        }
    }
    assert_eq!(w.game(&room).turn(), 0);
}

#[test]
fn a_record_is_fetched_without_a_seat_but_only_after_hello() {
    let mut w = World::new();
    let room = RoomCode::parse("K7QX2M4B").unwrap();
    w.hub.connected(w.now, 5, PEER);
    let out = w.send(
        5,
        ClientMessage::FetchRecord {
            room: room.clone(),
            game: None,
        },
    );
    assert!(matches!(
        out.last(),
        Some(Output::Room(RoomOutput::Close { conn: 5, .. }))
    ));
    assert!(!out.iter().any(|o| matches!(o, Output::SendRecord { .. })));

    w.greet(6);
    let out = w.send(
        6,
        ClientMessage::FetchRecord {
            room: room.clone(),
            game: Some(1),
        },
    );
    assert!(
        matches!(&out[..], [Output::SendRecord { to: 6, room: r, game: Some(1) }] if *r == room),
        "{out:?}"
    );
}

#[test]
fn failed_entries_spend_an_address_budget_that_refills_and_successes_are_free() {
    let mut w = World::new();
    let budget = Limits::default().entry_burst;
    // Two players seated: their successful entries cost nothing.
    let (room, _, _) = w.pair(Settings::offline());
    w.greet(3);
    let guess = |n: u32| ClientMessage::Join {
        room: RoomCode::from_random([n as u8; breakshot_shared::protocol::limits::ROOM_CODE_LEN]),
        name: "eve".into(),
    };
    for n in 0..budget {
        let out = w.send(3, guess(n + 1));
        assert_eq!(
            error_code(&out, 3),
            Some(ErrorCode::NoSuchRoom),
            "guess {n}"
        );
    }
    // Spent: even a real code is refused, from another connection of the same address.
    w.greet(4);
    let out = w.send(4, ClientMessage::Spectate { room: room.clone() });
    assert_eq!(error_code(&out, 4), Some(ErrorCode::RateLimited));
    // One refill later, one more attempt.
    w.now += Limits::default().entry_refill;
    let out = w.send(4, ClientMessage::Spectate { room });
    assert!(got(&out, 4, |m| matches!(m, ServerMessage::Joined { .. })));
}

#[test]
fn an_address_may_hold_only_so_many_open_rooms() {
    let mut w = World::new();
    let cap = Limits::default().rooms_per_address;
    let create = create_room(Settings::offline(), "ann");
    for conn in 0..cap as ConnId {
        w.greet(100 + conn);
        let out = w.send(100 + conn, create.clone());
        joined(&out, 100 + conn);
    }
    w.greet(99);
    let out = w.send(99, create.clone());
    assert_eq!(error_code(&out, 99), Some(ErrorCode::ServerBusy));
    // A room that closes (its creator left and nobody joined) frees a place.
    w.hub.disconnected(w.now, w.now, 100);
    w.advance(WINDOW + Duration::from_secs(1));
    let out = w.send(99, create);
    joined(&out, 99);
}

#[test]
fn ipv6_addresses_of_one_64_share_one_entry_budget() {
    let mut w = World::new();
    let budget = Limits::default().entry_burst;
    let guess = |n: u64| ClientMessage::Join {
        room: RoomCode::from_random([n as u8; breakshot_shared::protocol::limits::ROOM_CODE_LEN]),
        name: "eve".into(),
    };
    // A host rotating through its /64: every guess from a fresh address.
    let mut codes = Vec::new();
    for n in 0..u64::from(budget) + 5 {
        let conn = 200 + n;
        let addr: std::net::IpAddr = format!("2001:db8:7:8::{:x}", n + 1).parse().unwrap();
        w.hub.connected(w.now, conn, addr);
        w.handshake(conn);
        codes.push(error_code(&w.send(conn, guess(n + 1)), conn));
    }
    let guessed = codes
        .iter()
        .filter(|c| **c == Some(ErrorCode::NoSuchRoom))
        .count();
    assert_eq!(guessed, budget as usize, "{codes:?}");
    assert_eq!(codes.last(), Some(&Some(ErrorCode::RateLimited)));
    // Another /64 has its own budget.
    let addr: std::net::IpAddr = "2001:db8:7:9::1".parse().unwrap();
    w.hub.connected(w.now, 999, addr);
    w.handshake(999);
    assert_eq!(
        error_code(&w.send(999, guess(1)), 999),
        Some(ErrorCode::NoSuchRoom)
    );
}

#[test]
fn a_practice_session_ends_at_its_length_limit_and_its_record_stays_bounded() {
    let mut w = World::new();
    let limit = Limits::default().max_practice_commands;
    w.greet(1);
    let out = w.send(
        1,
        ClientMessage::CreateRoom {
            variant: Variant::Practice,
            mode: Settings::offline(),
            aim_aid: AimAid::Off,
            name: "solo".into(),
        },
    );
    let (room, _) = joined(&out, 1);
    let mut over = None;
    let mut sent = 0;
    while over.is_none() {
        assert!(sent < limit, "still playing after {sent} commands");
        // Within the message rate.
        w.now += Duration::from_millis(25);
        let game = w.game(&room);
        let pos = [0.4 + 0.001 * f64::from(sent as u32 % 100), 0.6];
        let out = w.send(
            1,
            ClientMessage::PlaceCueBall {
                turn: game.turn(),
                pos,
            },
        );
        assert_eq!(error_code(&out, 1), None, "command {sent}");
        sent += 1;
        over = sent_to(&out, 1).into_iter().find_map(|m| match m {
            ServerMessage::GameOver { reason, .. } => Some(reason.clone()),
            _ => None,
        });
    }
    // The last place went to the concession that ended the session.
    assert_eq!(sent, limit - 1);
    let record = w.hub.room(&room).unwrap().record().clone();
    assert_eq!(record.entries.len(), limit);
    assert_eq!(record.entries.last().unwrap().command, Command::Concede);
    assert_eq!(record.replay().unwrap(), w.game(&room));
    let out = w.send(
        1,
        ClientMessage::PlaceCueBall {
            turn: w.game(&room).turn(),
            pos: [0.5, 0.5],
        },
    );
    assert_eq!(error_code(&out, 1), Some(ErrorCode::GameOver));
}

#[test]
fn a_player_away_when_the_game_ended_is_told_the_result_after_the_room_is_gone() {
    let (mut w, room, _, token_b) = World::paired(Settings::offline());
    // B drops; A takes the last shot (concedes here), then leaves too.
    w.hub.disconnected(w.now, w.now, 2);
    let out = w.send(1, ClientMessage::Concede);
    assert!(got(&out, 1, |m| matches!(
        m,
        ServerMessage::GameOver { .. }
    )));
    w.hub.disconnected(w.now, w.now, 1);
    w.advance(WINDOW + Duration::from_secs(1));
    assert!(w.hub.room(&room).is_none(), "the room is still open");

    w.greet(3);
    let out = w.send(3, ClientMessage::Rejoin { token: token_b });
    match sent_to(&out, 3)[..] {
        [ServerMessage::GameFinished {
            room: r,
            game: 1,
            seat: Seat::B,
            winner: Some(Seat::B),
            reason,
        }] => {
            assert_eq!(*r, room);
            assert!(reason.contains("conceded"), "{reason}");
        }
        ref other => panic!("{other:?}"),
    }
    // Not in a room: the connection may create or join another.
    let out = w.send(3, ClientMessage::Spectate { room: room.clone() });
    assert_eq!(error_code(&out, 3), Some(ErrorCode::NoSuchRoom));
    // Kept only for a while.
    w.advance(Limits::default().finished_retention);
    w.greet(4);
    let out = w.send(4, ClientMessage::Rejoin { token: token_b });
    assert_eq!(error_code(&out, 4), Some(ErrorCode::BadToken));
}

#[test]
fn a_finished_room_no_longer_counts_against_its_creators_limit() {
    let mut w = World::new();
    let cap = Limits::default().rooms_per_address;
    let create = create_room(Settings::offline(), "ann");
    let mut rooms = Vec::new();
    for conn in 0..cap as ConnId {
        w.greet(100 + conn);
        rooms.push(joined(&w.send(100 + conn, create.clone()), 100 + conn).0);
    }
    w.greet(99);
    assert_eq!(
        error_code(&w.send(99, create.clone()), 99),
        Some(ErrorCode::ServerBusy)
    );
    // One game ends (its creator concedes): the room stays open, its players may still talk
    // or ask for a rematch, but it is not in play any more.
    let out = w.send(100, ClientMessage::Concede);
    assert_eq!(
        error_code(&out, 100),
        Some(ErrorCode::Unexpected),
        "no opponent yet"
    );
    w.greet(200);
    let out = w.send(200, join_room(&rooms[0], "ben"));
    joined(&out, 200);
    let out = w.send(100, ClientMessage::Concede);
    assert!(got(&out, 100, |m| matches!(
        m,
        ServerMessage::GameOver { .. }
    )));
    assert!(w.hub.room(&rooms[0]).is_some());
    joined(&w.send(99, create), 99);
}

#[test]
fn a_room_out_on_a_long_shot_holds_only_its_own_events_and_keeps_their_order() {
    let (mut w, slow, _, _) = World::paired(Settings::offline());
    w.greet(3);
    w.greet(4);
    let create = create_room(Settings::offline(), "cy");
    let (fast, _) = joined(&w.send(3, create.clone()), 3);
    let join = ClientMessage::Join {
        room: fast.clone(),
        name: "di".into(),
    };
    joined(&w.send(4, join), 4);

    // A shot in the slow room sends the room out with it, and nothing is answered yet.
    let shot = break_shot(&w.game(&slow));
    let mut out = w.hub.handle(w.now, 1, shot);
    assert_eq!(out.len(), 1, "{out:?}");
    let Some(Output::Run(slow_work)) = out.pop() else {
        panic!("the shot is not lent out with its room");
    };
    assert_eq!(slow_work.room(), &slow);
    assert!(w.hub.room(&slow).is_none());
    assert_eq!(w.hub.room_count(), 2);

    // While its simulation has not even started, the room's own events wait...
    let chat = ClientMessage::Chat {
        text: "good luck".into(),
    };
    assert!(w.hub.handle(w.now, 2, chat).is_empty());
    w.greet(5);
    let spectate = ClientMessage::Spectate { room: slow.clone() };
    assert!(w.hub.handle(w.now, 5, spectate.clone()).is_empty());
    assert_eq!(
        error_code(&w.hub.handle(w.now, 5, spectate), 5),
        Some(ErrorCode::Unexpected),
        "a second entry while the first waits"
    );

    // ...while the other room plays a shot through to its result,
    let out = w.send(3, break_shot(&w.game(&fast)));
    for conn in [3, 4] {
        assert!(
            sent_to(&out, conn)
                .iter()
                .any(|m| matches!(m, ServerMessage::ShotResolved { turn: 0, .. })),
            "conn {conn}: {out:?}"
        );
    }
    // and a new player is greeted and given a room.
    w.greet(6);
    joined(&w.send(6, create), 6);

    // The slow shot finishes: its results first, then the held events in the order they came.
    let (worked, back) = slow_work.run(w.now);
    assert!(matches!(
        worked[0],
        RoomOutput::Store(StoreOp::Command { .. })
    ));
    let worked = super::lift(worked);
    assert!(got(&worked, 2, |m| matches!(
        m,
        ServerMessage::ShotResolved { turn: 0, .. }
    )));
    let after = w.hub.returned(w.now, back);
    assert!(
        matches!(&after[..], [Output::Run(work)] if work.room() == &slow),
        "the held chat goes out with the room before the spectator enters: {after:?}"
    );
    let after = w.settle(after);
    assert!(got(
        &after,
        2,
        |m| matches!(m, ServerMessage::Chat { text, .. } if text == "good luck")
    ));
    let to_spectator = sent_to(&after, 5);
    assert!(
        matches!(&to_spectator[..], [ServerMessage::Joined { snapshot, .. }] if snapshot.game.turn() == 1),
        "the spectator enters after the chat and sees the shot played: {to_spectator:?}"
    );
    assert!(w.hub.room(&slow).is_some());
}

#[test]
fn a_player_who_leaves_while_the_room_is_out_is_seen_leaving_after_its_results() {
    let (mut w, room, _, _) = World::paired(Settings::offline());
    let shot = break_shot(&w.game(&room));
    let mut out = w.hub.handle(w.now, 1, shot);
    let Some(Output::Run(work)) = out.pop() else {
        panic!("the shot is not lent out with its room");
    };
    assert!(w.hub.disconnected(w.now, w.now, 2).is_empty());
    let (worked, back) = work.run(w.now);
    let worked = super::lift(worked);
    assert!(got(&worked, 2, |m| matches!(
        m,
        ServerMessage::ShotResolved { .. }
    )));
    let after = w.hub.returned(w.now, back);
    assert!(got(&after, 1, |m| matches!(
        m,
        ServerMessage::PlayerLeft { seat: Seat::B, .. }
    )));
    // The seat is held for its window, as for any dropped player.
    assert!(w.hub.room(&room).unwrap().next_deadline().is_some());
}

#[test]
fn with_a_shared_store_an_unknown_seat_is_claimed_and_its_room_rebuilt_or_refused() {
    let mut owner = World::with_store(true);
    let (room, token_a, _) = owner.pair(Settings::offline());
    let shot = break_shot(&owner.game(&room));
    owner.send(1, shot);
    let left = owner.hub.room(&room).unwrap();
    let (meta, number, record) = (left.meta(), left.game_number(), left.record().clone());
    let game = left.game().clone();

    let mut other = World::with_store(true);
    other.greet(1);
    let out = other.send(1, ClientMessage::Rejoin { token: token_a });
    assert!(
        matches!(&out[..], [Output::Claim { conn: 1, .. }]),
        "{out:?}"
    );
    // While the store is asked, the connection waits.
    let out = other.send(1, ClientMessage::Concede);
    assert_eq!(error_code(&out, 1), Some(ErrorCode::Unexpected));
    let out = other.hub.claimed(other.now, 1, token_a, Claimed::Elsewhere);
    assert_eq!(error_code(&out, 1), Some(ErrorCode::ServerBusy));
    assert_eq!(other.hub.room_count(), 0);

    other.send(1, ClientMessage::Rejoin { token: token_a });
    let restored = Restored {
        meta,
        number,
        record,
        game: game.clone(),
        clock: None,
        rated: None,
        listed: None,
    };
    let out = other
        .hub
        .claimed(other.now, 1, token_a, Claimed::Taken(Box::new(restored)));
    let rejoined = sent_to(&out, 1).into_iter().find_map(|m| match m {
        ServerMessage::Joined { role, snapshot, .. } => Some((*role, snapshot.game.clone())),
        _ => None,
    });
    assert_eq!(rejoined, Some((Role::Player(Seat::A), game)));
    // The token is known here now: the next rejoin asks the store nothing.
    other.greet(3);
    let out = other.send(3, ClientMessage::Rejoin { token: token_a });
    assert!(!out.iter().any(|o| matches!(o, Output::Claim { .. })));

    // A hub that owns its store alone never asks it.
    let mut alone = World::new();
    alone.greet(1);
    let out = alone.send(1, ClientMessage::Rejoin { token: token_a });
    assert_eq!(error_code(&out, 1), Some(ErrorCode::BadToken));
}

/// Connection `conn` from its own address (10.0.0.`conn`), welcomed.
fn greet_from(w: &mut World, conn: ConnId, addr: [u8; 4]) {
    w.hub.connected(w.now, conn, std::net::IpAddr::from(addr));
    w.handshake(conn);
}

/// A hub with two players greeted (connections 1 and 2), each from an address of its own.
fn strangers() -> World {
    let mut w = World::new();
    greet_from(&mut w, 1, [10, 0, 0, 1]);
    greet_from(&mut w, 2, [10, 0, 0, 2]);
    w
}

fn quick(name: &str) -> ClientMessage {
    ClientMessage::QuickMatch {
        variant: Variant::EightBall(EightBallRules::Wpa),
        mode: Settings::online(),
        name: name.into(),
    }
}

fn lobby_page(w: &mut World, conn: ConnId) -> (usize, usize) {
    match sent_to(&w.send(conn, ClientMessage::ListGames { page: 0 }), conn)[..] {
        [ServerMessage::Games {
            waiting, playing, ..
        }] => (waiting.len(), playing.len()),
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn a_public_room_is_listed_until_it_closes_and_a_private_one_never() {
    let mut w = World::new();
    w.greet(1);
    w.greet(2);
    w.greet(3);
    w.send(1, create_room(Settings::online(), "ann"));
    assert_eq!(lobby_page(&mut w, 3), (0, 0), "private until published");
    // Only its creator lists a room, and only from inside it.
    assert_eq!(
        error_code(&w.send(3, ClientMessage::Publish), 3),
        Some(ErrorCode::Unexpected)
    );
    let out = w.send(1, ClientMessage::Publish);
    let Some(ServerMessage::Published { room }) = sent_to(&out, 1).first().cloned().cloned() else {
        panic!("{out:?}");
    };
    w.now += Duration::from_secs(7);
    match sent_to(&w.send(3, ClientMessage::ListGames { page: 0 }), 3)[..] {
        [ServerMessage::Games {
            waiting,
            playing,
            pages,
            ..
        }] => {
            assert_eq!(*pages, 1);
            assert!(playing.is_empty());
            assert_eq!(waiting[0].room, room);
            assert_eq!(waiting[0].host, "ann");
            assert_eq!(waiting[0].waited_s, 7);
            assert_eq!(waiting[0].rating, None, "no rated game yet");
        }
        ref other => panic!("{other:?}"),
    }
    // Page 1 is empty; a page past the end is not an error.
    match sent_to(&w.send(3, ClientMessage::ListGames { page: u32::MAX }), 3)[..] {
        [ServerMessage::Games { waiting, .. }] => assert!(waiting.is_empty()),
        ref other => panic!("{other:?}"),
    }
    // Once its second player comes, it is a game to watch.
    w.send(2, join_room(&room, "bob"));
    assert_eq!(lobby_page(&mut w, 3), (0, 1));
    assert_eq!(
        error_code(&w.send(1, ClientMessage::Publish), 1),
        Some(ErrorCode::Unexpected),
        "nothing to list once full"
    );
    // Both leave: the room closes and leaves the lobby.
    w.hub.disconnected(w.now, w.now, 1);
    w.hub.disconnected(w.now, w.now, 2);
    w.now += WINDOW + Duration::from_secs(1);
    let out = w.hub.tick(w.now);
    w.settle(out);
    let out = w.hub.tick(w.now);
    w.settle(out);
    assert_eq!(w.hub.listed(), 0);
}

/// The listings a hub's output stores, in order.
fn listings_stored(out: &[Output]) -> Vec<[Option<PlayerKey>; 2]> {
    out.iter()
        .filter_map(|o| match o {
            Output::Room(RoomOutput::Store(StoreOp::Listed { players, .. })) => Some(*players),
            _ => None,
        })
        .collect()
}

#[test]
fn a_listed_room_restarted_or_taken_over_is_listed_again_as_it_was() {
    let mut w = strangers();
    let (ann, bob) = (identity(1).public(), identity(2).public());
    w.send(1, create_room(Settings::online(), "ann"));
    let out = w.send(1, ClientMessage::Publish);
    assert_eq!(listings_stored(&out), vec![[Some(ann), None]]);
    let Some(ServerMessage::Published { room }) = sent_to(&out, 1).first().cloned().cloned() else {
        panic!("{out:?}");
    };
    // The room as the store gives it back, waiting for its second player.
    let restored = |w: &World, listed| {
        let left = w.hub.room(&room).unwrap();
        Restored {
            meta: left.meta(),
            number: 1,
            record: left.record().clone(),
            game: left.game().clone(),
            clock: None,
            rated: None,
            listed,
        }
    };
    let mut other = strangers();
    other
        .hub
        .restore(other.now, restored(&w, Some([Some(ann), None])));
    assert_eq!(lobby_page(&mut other, 2), (1, 0), "waiting again");
    // Once bob joins, the listing is stored again with both keys; brought back then, the
    // room is a game to watch.
    let out = w.send(2, join_room(&room, "bob"));
    assert_eq!(listings_stored(&out), vec![[Some(ann), Some(bob)]]);
    let mut other = strangers();
    other
        .hub
        .restore(other.now, restored(&w, Some([Some(ann), Some(bob)])));
    assert_eq!(lobby_page(&mut other, 1), (0, 1), "in play again");
    // A private room stays private.
    let mut other = strangers();
    other.hub.restore(other.now, restored(&w, None));
    assert_eq!(other.hub.listed(), 0);
}

#[test]
fn a_lobby_flood_is_rate_limited_and_costs_nothing_else() {
    let mut w = World::new();
    w.greet(1);
    let mut limited = 0;
    // 40 messages: under the per-connection message limit, which would close it.
    for _ in 0..20 {
        let out = w.send(1, ClientMessage::ListGames { page: 0 });
        if error_code(&out, 1) == Some(ErrorCode::RateLimited) {
            limited += 1;
        }
        let out = w.send(1, ClientMessage::Leaderboard { page: 3 });
        if error_code(&out, 1) == Some(ErrorCode::RateLimited) {
            limited += 1;
        }
    }
    assert_eq!(limited, 40 - LOBBY_BURST as usize);
    // A second later one more page is earned.
    w.now += Duration::from_secs(1);
    assert_eq!(lobby_page(&mut w, 1), (0, 0));
}

#[test]
fn two_strangers_are_matched_into_one_room_and_a_concession_rates_them() {
    let mut w = strangers();
    let out = w.send(1, quick("ann"));
    assert!(matches!(
        sent_to(&out, 1)[..],
        [ServerMessage::Queued { waiting: 1, .. }]
    ));
    let out = w.send(2, quick("bob"));
    let joined = |conn| {
        sent_to(&out, conn)
            .into_iter()
            .find_map(|m| match m {
                ServerMessage::Joined { role, .. } => Some(*role),
                _ => None,
            })
            .unwrap_or_else(|| panic!("{conn} not seated: {out:?}"))
    };
    assert_eq!(
        joined(1),
        Role::Player(Seat::A),
        "the longer wait takes seat A"
    );
    assert_eq!(joined(2), Role::Player(Seat::B));
    let told_ratings = |out: &[Output], conn| {
        sent_to(out, conn).into_iter().find_map(|m| match m {
            ServerMessage::Ratings { ratings } => Some(*ratings),
            _ => None,
        })
    };
    let room = sent_to(&out, 1)
        .into_iter()
        .find_map(|m| match m {
            ServerMessage::Joined { snapshot, .. } => Some(snapshot.room.clone()),
            _ => None,
        })
        .expect("a room");
    for conn in [1, 2] {
        assert_eq!(
            told_ratings(&out, conn),
            Some([1500, 1500]),
            "both seated players see both ratings from the start"
        );
    }
    assert_eq!(lobby_page(&mut w, 1), (0, 1), "listed to watch");
    // Seat B concedes: a loss like any other.
    let out = w.send(2, ClientMessage::Concede);
    let ratings: Vec<(PlayerKey, f64)> = out
        .iter()
        .filter_map(|o| match o {
            Output::Room(RoomOutput::Store(StoreOp::Rating { key, rating })) => {
                Some((*key, rating.rating))
            }
            _ => None,
        })
        .collect();
    assert_eq!(ratings.len(), 2, "{out:?}");
    // skillratings' own numbers for two new players, a win: 1662 and 1338.
    let (ann, bob) = (identity(1).public(), identity(2).public());
    assert_eq!(ratings[0].0, ann);
    assert_eq!(ratings[0].1.round(), 1662.0);
    assert_eq!(ratings[1].0, bob);
    assert_eq!(ratings[1].1.round(), 1338.0);
    for conn in [1, 2] {
        let told: Vec<_> = sent_to(&out, conn)
            .into_iter()
            .filter(|m| matches!(m, ServerMessage::Rated { .. }))
            .cloned()
            .collect();
        assert_eq!(
            told,
            vec![
                ServerMessage::Rated {
                    seat: Seat::A,
                    before: 1500,
                    after: 1662
                },
                ServerMessage::Rated {
                    seat: Seat::B,
                    before: 1500,
                    after: 1338
                }
            ]
        );
    }
    // Whoever comes to watch sees the ratings as they are now.
    greet_from(&mut w, 3, [10, 0, 0, 3]);
    let out = w.send(3, ClientMessage::Spectate { room });
    assert_eq!(told_ratings(&out, 3), Some([1662, 1338]));
    // Rated once: a rematch is a friendly.
    w.send(1, ClientMessage::Rematch);
    w.send(2, ClientMessage::Rematch);
    let out = w.send(1, ClientMessage::Concede);
    assert!(!out
        .iter()
        .any(|o| matches!(o, Output::Room(RoomOutput::Store(StoreOp::Rating { .. })))));
    match sent_to(&w.send(1, ClientMessage::Leaderboard { page: 0 }), 1)[..] {
        [ServerMessage::Leaders { players, .. }] => {
            assert_eq!(players[0].name, "ann");
            assert_eq!(players[0].rating, 1662);
            assert_eq!(players[1].key, bob.short());
        }
        ref other => panic!("{other:?}"),
    }
}

/// The ratings a hub's output stores, in order.
fn ratings_stored(out: &[Output]) -> Vec<(PlayerKey, i32)> {
    out.iter()
        .filter_map(|o| match o {
            Output::Room(RoomOutput::Store(StoreOp::Rating { key, rating })) => {
                Some((*key, rating.rating.round() as i32))
            }
            _ => None,
        })
        .collect()
}

#[test]
fn a_rated_room_restarted_or_taken_over_is_rated_where_its_first_game_ends() {
    let mut w = strangers();
    w.send(1, quick("ann"));
    let out = w.send(2, quick("bob"));
    let ((room, token_a), (_, token_b)) = (joined(&out, 1), joined(&out, 2));
    let (ann, bob) = (identity(1).public(), identity(2).public());
    let stored = out.iter().find_map(|o| match o {
        Output::Room(RoomOutput::Store(StoreOp::RatedRoom { room, players })) => {
            Some((room.clone(), *players))
        }
        _ => None,
    });
    assert_eq!(
        stored,
        Some((room.clone(), [ann, bob])),
        "the room is stored as rated, with its players' keys by seat"
    );
    // The room as the store gives it back to a restarted server or another instance.
    let left = w.hub.room(&room).unwrap();
    let restored = |number| Restored {
        meta: left.meta(),
        number,
        record: left.record().clone(),
        game: left.game().clone(),
        clock: None,
        rated: Some([ann, bob]),
        listed: None,
    };
    let back_at = |number| {
        let mut other = strangers();
        other.hub.restore(other.now, restored(number));
        assert_eq!(other.hub.listed(), 1, "listed again as a game to watch");
        let back = other.send(1, ClientMessage::Rejoin { token: token_a });
        assert!(
            got(&back, 1, |m| matches!(m, ServerMessage::Ratings { .. })),
            "a player back in a rated room is told the ratings: {back:?}"
        );
        other.send(2, ClientMessage::Rejoin { token: token_b });
        let out = other.send(2, ClientMessage::Concede);
        let told = sent_to(&out, 1)
            .into_iter()
            .filter(|m| matches!(m, ServerMessage::Rated { .. }))
            .count();
        (ratings_stored(&out), told)
    };
    // skillratings' own numbers for two new players, a win: 1662 and 1338.
    assert_eq!(
        back_at(1),
        (vec![(ann, 1662), (bob, 1338)], 2),
        "the first game ended on the server that brought the room back: rated there"
    );
    assert_eq!(
        back_at(2),
        (vec![], 0),
        "a later game of the room is a friendly (the first was rated where it ended)"
    );
}

#[test]
fn the_queue_handles_leaving_dropping_waiting_too_long_and_a_second_key_at_one_address() {
    let mut w = World::new();
    greet_from(&mut w, 1, [10, 0, 0, 1]);
    greet_from(&mut w, 2, [10, 0, 0, 1]);
    greet_from(&mut w, 3, [10, 0, 0, 3]);
    w.send(1, quick("ann"));
    // A second key from ann's address: never her opponent, however long they wait.
    let out = w.send(2, quick("ann2"));
    assert!(matches!(
        sent_to(&out, 2)[..],
        [ServerMessage::Queued { waiting: 2, .. }]
    ));
    w.now += Duration::from_secs(60);
    let out = w.hub.tick(w.now);
    assert!(sent_to(&out, 1).is_empty() && sent_to(&out, 2).is_empty());
    // While queued, no other entry; and one queue at a time.
    assert_eq!(
        error_code(&w.send(1, create_room(Settings::online(), "ann")), 1),
        Some(ErrorCode::Unexpected)
    );
    assert_eq!(
        error_code(&w.send(1, quick("ann")), 1),
        Some(ErrorCode::Unexpected)
    );
    // Ann leaves; her second key drops: neither is matched with the newcomer.
    assert!(matches!(
        sent_to(&w.send(1, ClientMessage::LeaveQueue), 1)[..],
        [ServerMessage::Unqueued { .. }]
    ));
    w.hub.disconnected(w.now, w.now, 2);
    let out = w.send(3, quick("cat"));
    assert!(matches!(
        sent_to(&out, 3)[..],
        [ServerMessage::Queued { waiting: 1, .. }]
    ));
    assert_eq!(
        error_code(&w.send(1, ClientMessage::LeaveQueue), 1),
        Some(ErrorCode::Unexpected),
        "not queued"
    );
    // Cat waits too long.
    w.now += QUEUE_TIMEOUT;
    let out = w.hub.tick(w.now);
    assert!(matches!(
        sent_to(&out, 3)[..],
        [ServerMessage::Unqueued { reason }] if reason.contains("in time")
    ));
    assert!(w.hub.queue_lengths().is_empty());
    // Practice has no opponent; a storm of joins and leaves is limited.
    let practice = ClientMessage::QuickMatch {
        variant: Variant::Practice,
        mode: Settings::online(),
        name: "cat".into(),
    };
    assert_eq!(
        error_code(&w.send(3, practice), 3),
        Some(ErrorCode::Invalid)
    );
    let mut limited = 0;
    for n in 0..50 {
        let msg = if n % 2 == 0 {
            quick("cat")
        } else {
            ClientMessage::LeaveQueue
        };
        if error_code(&w.send(3, msg), 3) == Some(ErrorCode::RateLimited) {
            limited += 1;
        }
    }
    assert!(limited >= 40, "{limited}");
    assert!(w.hub.queue_lengths().iter().all(|(_, _, n)| *n <= 1));
}

#[test]
fn a_drain_tells_every_player_and_empties_the_queues() {
    let mut w = strangers();
    w.send(1, quick("ann"));
    w.send(2, create_room(Settings::online(), "bob"));
    let out = w.hub.drain();
    assert!(matches!(
        sent_to(&out, 1)[..],
        [
            ServerMessage::Unqueued { .. },
            ServerMessage::Draining { .. }
        ]
    ));
    assert!(matches!(
        sent_to(&out, 2)[..],
        [ServerMessage::Draining { message }] if message.contains("your game goes on")
    ));
    assert!(w.hub.drain().is_empty(), "told once");
    assert_eq!(
        error_code(&w.send(1, quick("ann")), 1),
        Some(ErrorCode::ServerBusy)
    );
}
