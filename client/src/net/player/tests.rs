//! The core fed scripted server frames and times: no sockets, no clock.

use std::time::Duration;

use breakshot_shared::protocol::{
    encode_frame, AimAid, ClientMessage, ErrorCode, Identity, Invite, PlayerKey, Role, RoomCode,
    SeatToken, ServerMessage, Snapshot, PROTOCOL_VERSION,
};
use breakshot_shared::rules::{EightBallRules, Seat, Settings, Variant};

use super::*;
use crate::net::polled::{MemoryServer, MemoryTransport, Polled};
use crate::test_games::eight_ball;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn room() -> RoomCode {
    RoomCode::parse("K7QX2M4B").unwrap()
}

/// An invite naming `n` addresses.
fn invite(n: usize) -> Invite {
    let mut invite: Invite = format!("breakshot://10.0.0.1:4433/K7QX2M4B#{}", "ab".repeat(32))
        .parse()
        .unwrap();
    for k in 1..n {
        let mut other = invite.servers[0].clone();
        other.port += k as u16;
        invite.servers.push(other);
    }
    invite
}

fn retrying() -> Reconnect {
    Reconnect {
        first_for: Duration::from_secs(5),
        rejoin_for: Duration::from_secs(30),
        pause: ms(100),
        max_pause: ms(400),
    }
}

fn joined(role: Role, token: Option<SeatToken>) -> ServerMessage {
    ServerMessage::Joined {
        role,
        token,
        snapshot: Box::new(Snapshot {
            room: room(),
            game_number: 1,
            game: eight_ball(1),
            seats: [None, None],
            aim_aid: AimAid::Full,
            called: None,
            shot_clock_ms: None,
        }),
    }
}

fn error(code: ErrorCode) -> ServerMessage {
    ServerMessage::Error {
        code,
        message: format!("{code:?}"),
    }
}

fn identity() -> Identity {
    Identity::from_seed(&[3; 32])
}

const NONCE: [u8; 32] = [9; 32];

fn welcome() -> ServerMessage {
    ServerMessage::Welcome {
        protocol: PROTOCOL_VERSION,
    }
}

/// A core and the scripted far end of its in-memory transport.
struct Script {
    driver: Polled<MemoryTransport>,
    server: MemoryServer,
    now: Duration,
}

impl Script {
    fn new(invite: Invite, policy: Reconnect) -> Script {
        let (transport, server) = MemoryTransport::pair();
        let core = PlayerCore::new(invite, policy, identity(), Duration::ZERO);
        let mut driver = Polled::new(core, transport);
        driver.update(Duration::ZERO);
        Script {
            driver,
            server,
            now: Duration::ZERO,
        }
    }

    /// Advances the clock by `by` and pumps the driver.
    fn wait(&mut self, by: Duration) {
        self.now += by;
        self.driver.update(self.now);
    }

    /// The server says `msg`; pumps the driver.
    fn say(&mut self, msg: &ServerMessage) {
        self.server.say(msg);
        self.driver.update(self.now);
    }

    /// Accepts the connection being opened and answers its `Hello`.
    fn greet(&mut self) {
        self.server.accept();
        self.driver.update(self.now);
        let heard = self.server.heard();
        let [ClientMessage::Hello {
            protocol,
            physics,
            key,
        }] = heard.as_slice()
        else {
            panic!("no Hello: {heard:?}");
        };
        assert_eq!(*protocol, PROTOCOL_VERSION);
        assert_eq!(key.as_slice(), identity().public().0.as_slice());
        self.say(&ServerMessage::Challenge { nonce: NONCE });
        // The core proves its key over this challenge and this Hello's context.
        let heard = self.server.heard();
        let [ClientMessage::Prove { signature }] = heard.as_slice() else {
            panic!("no Prove: {heard:?}");
        };
        let player = PlayerKey::from_wire(key).expect("a key");
        assert_eq!(
            player.verify(&NONCE, *protocol, *physics, signature),
            Ok(())
        );
        self.say(&welcome());
    }

    fn events(&mut self) -> Vec<PlayerEvent> {
        std::iter::from_fn(|| self.driver.poll_event()).collect()
    }
}

#[test]
fn a_version_refusal_is_final_and_says_why() {
    let mut s = Script::new(invite(1), retrying());
    s.server.accept();
    s.wait(ms(1));
    let reject = ServerMessage::Reject {
        reason: "protocol version 9 is not 8".into(),
    };
    s.say(&reject);
    assert_eq!(
        s.events(),
        [PlayerEvent::Closed(NetError::Rejected(
            "protocol version 9 is not 8".into()
        ))]
    );
    // Refused: no second attempt, however long one waits.
    s.wait(Duration::from_secs(60));
    assert_eq!(s.server.opened().len(), 1);
    assert!(s.driver.core().is_closed());
}

#[test]
fn a_silent_address_is_given_up_for_the_next() {
    let mut s = Script::new(invite(2), Reconnect::never());
    assert_eq!(s.server.opened().len(), 1);
    s.wait(ATTEMPT_LIMIT - ms(1));
    assert_eq!(s.server.opened().len(), 1, "given up too soon");
    s.wait(ms(1));
    let opened = s.server.opened();
    assert_eq!(opened.len(), 2);
    assert_eq!(opened[1].port, 4434);
    s.greet();
    assert_eq!(s.events(), [PlayerEvent::Connected]);
    assert_eq!(s.driver.core().address_index(), 1);
}

#[test]
fn the_first_connection_is_retried_with_growing_pauses_then_given_up() {
    let mut s = Script::new(invite(1), retrying());
    let down = || NetError::Connect("refused by the network".into());
    s.server.fail(down());
    s.wait(ms(1));
    s.wait(ms(99));
    assert_eq!(s.server.opened().len(), 1, "the pause is 100 ms");
    s.wait(ms(1));
    assert_eq!(s.server.opened().len(), 2);
    s.server.fail(down());
    s.wait(Duration::ZERO);
    s.wait(ms(199));
    assert_eq!(s.server.opened().len(), 2, "then 200 ms");
    s.wait(ms(1));
    assert_eq!(s.server.opened().len(), 3);
    // Past `first_for` the core gives up with the last reason, the address tried and what
    // to check.
    s.wait(Duration::from_secs(5));
    s.server.fail(down());
    s.wait(ms(1));
    let events = s.events();
    let [PlayerEvent::Closed(error)] = events.as_slice() else {
        panic!("{events:?}");
    };
    assert!(
        matches!(error, NetError::Unreachable { why, .. } if why == "refused by the network"),
        "{error:?}"
    );
    let words = error.to_string();
    let address = s.driver.core().invite().servers[0].to_string();
    assert!(words.contains(&address), "{words}");
    assert!(words.contains("UDP port is open"), "{words}");
}

#[test]
fn a_stale_token_falls_back_to_the_free_seat_and_a_full_room_is_watched() {
    let mut s = Script::new(invite(1), retrying());
    s.driver.enter(Entry::Rejoin {
        token: SeatToken([7; 16]),
        otherwise: Some(Box::new(Entry::Join {
            room: room(),
            name: "bob".into(),
            watch_if_full: true,
        })),
    });
    s.greet();
    assert_eq!(
        s.server.heard(),
        [ClientMessage::Rejoin {
            token: SeatToken([7; 16])
        }]
    );
    s.say(&error(ErrorCode::BadToken));
    assert_eq!(
        s.server.heard(),
        [ClientMessage::Join {
            room: room(),
            name: "bob".into()
        }]
    );
    s.say(&error(ErrorCode::RoomFull));
    assert_eq!(s.server.heard(), [ClientMessage::Spectate { room: room() }]);
    s.say(&joined(Role::Spectator, None));
    let events = s.events();
    // The refusals were answered by the core; the user hears the seat is gone, then the
    // room it watches.
    assert_eq!(events[0], PlayerEvent::Connected);
    assert_eq!(events[1], PlayerEvent::SeatGone);
    assert!(matches!(&events[2], PlayerEvent::Seated(seating) if seating.watching()));
    assert!(matches!(
        &events[3],
        PlayerEvent::Message(ServerMessage::Joined { .. })
    ));
    assert_eq!(events.len(), 4);
    assert_eq!(s.driver.seating().token, None);
}

#[test]
fn a_stale_token_with_nothing_to_fall_back_to_is_reported() {
    let mut s = Script::new(invite(1), retrying());
    s.driver.enter(Entry::Rejoin {
        token: SeatToken([7; 16]),
        otherwise: None,
    });
    s.greet();
    s.server.heard();
    s.say(&error(ErrorCode::BadToken));
    let events = s.events();
    assert_eq!(events[1], PlayerEvent::SeatGone);
    assert_eq!(events[2], PlayerEvent::Message(error(ErrorCode::BadToken)));
}

#[test]
fn a_seat_is_taken_back_after_a_drop_and_a_busy_instance_sends_it_to_the_next() {
    let mut s = Script::new(invite(2), retrying());
    s.driver.enter(Entry::Join {
        room: room(),
        name: "bob".into(),
        watch_if_full: false,
    });
    s.greet();
    s.server.heard();
    let token = SeatToken([3; 16]);
    s.say(&joined(Role::Player(Seat::B), Some(token)));
    s.events();

    // The connection drops: the core connects again to the same address and asks back.
    s.server.fail(NetError::Lost("cable".into()));
    s.wait(ms(1));
    assert!(
        matches!(s.events().as_slice(), [PlayerEvent::Reconnecting(why)] if why.contains("cable"))
    );
    assert_eq!(s.server.opened().len(), 2);
    assert_eq!(s.server.opened()[1].port, 4433);
    s.greet();
    assert_eq!(s.events(), [PlayerEvent::Reconnected]);
    assert_eq!(s.server.heard(), [ClientMessage::Rejoin { token }]);

    // That instance no longer plays the game: after a pause, the next address is asked.
    let closes = s.server.closes();
    s.say(&error(ErrorCode::ServerBusy));
    assert!(s.server.closes() > closes, "the busy instance is left");
    assert!(matches!(
        s.events().as_slice(),
        [PlayerEvent::Reconnecting(_)]
    ));
    s.wait(ms(99));
    assert_eq!(s.server.opened().len(), 2, "asked again without a pause");
    s.wait(ms(1));
    assert_eq!(s.server.opened().len(), 3);
    assert_eq!(s.server.opened()[2].port, 4434);
    s.greet();
    assert_eq!(s.server.heard(), [ClientMessage::Rejoin { token }]);
    s.say(&joined(Role::Player(Seat::B), None));
    let events = s.events();
    assert_eq!(events[0], PlayerEvent::Reconnected);
    assert!(matches!(&events[1], PlayerEvent::Seated(seating)
        if seating.seat() == Some(Seat::B) && seating.token == Some(token)));
    assert_eq!(s.driver.core().address_index(), 1);
}

#[test]
fn a_game_that_ended_while_away_leaves_no_seat() {
    let mut s = Script::new(invite(1), retrying());
    let token = SeatToken([5; 16]);
    s.driver.enter(Entry::Rejoin {
        token,
        otherwise: Some(Box::new(Entry::Join {
            room: room(),
            name: "bob".into(),
            watch_if_full: true,
        })),
    });
    s.greet();
    s.server.heard();
    let finished = ServerMessage::GameFinished {
        room: room(),
        game: 1,
        seat: Seat::A,
        winner: Some(Seat::A),
        reason: "the 8 was potted".into(),
    };
    s.say(&finished);
    let events = s.events();
    assert_eq!(
        &events[1..],
        [PlayerEvent::SeatGone, PlayerEvent::Message(finished)]
    );
    assert_eq!(s.driver.seating(), &Seating::default());
    // No fallback was asked: the player sees how the game ended.
    assert!(s.server.heard().is_empty());
    // With no seat, a drop is the end.
    s.server.fail(NetError::Lost("bye".into()));
    s.wait(ms(1));
    assert!(matches!(s.events().as_slice(), [PlayerEvent::Closed(_)]));
}

#[test]
fn a_rematch_is_sent_and_its_game_arrives_as_a_message() {
    let mut s = Script::new(invite(1), Reconnect::never());
    s.driver.enter(Entry::Create(ClientMessage::CreateRoom {
        variant: Variant::EightBall(EightBallRules::Wpa),
        mode: Settings::offline(),
        aim_aid: AimAid::Full,
        name: "alice".into(),
    }));
    s.greet();
    assert!(matches!(
        s.server.heard().as_slice(),
        [ClientMessage::CreateRoom { .. }]
    ));
    s.say(&joined(Role::Player(Seat::A), Some(SeatToken([1; 16]))));
    s.driver.send(&ClientMessage::Rematch).unwrap();
    assert_eq!(s.server.heard(), [ClientMessage::Rematch]);
    let ServerMessage::Joined { snapshot, .. } = joined(Role::Player(Seat::A), None) else {
        unreachable!()
    };
    let started = ServerMessage::GameStarted { snapshot };
    s.say(&started);
    let events = s.events();
    assert_eq!(events.last(), Some(&PlayerEvent::Message(started)));
    assert_eq!(s.driver.seating().seat(), Some(Seat::A));
}

#[test]
fn frames_split_anywhere_are_put_back_together() {
    let mut core = PlayerCore::new(invite(1), Reconnect::never(), identity(), Duration::ZERO);
    assert!(matches!(
        core.poll_action(),
        Some(Action::Open { at: 0, .. })
    ));
    core.opened(ms(1));
    assert!(core.poll_transmit().is_some(), "Hello");
    let mut bytes = encode_frame(&ServerMessage::Challenge { nonce: NONCE }).unwrap();
    bytes.extend(encode_frame(&welcome()).unwrap());
    bytes.extend(encode_frame(&error(ErrorCode::NotYourTurn)).unwrap());
    for chunk in bytes.chunks(3) {
        core.received(chunk, ms(2));
    }
    assert_eq!(core.poll_event(), Some(PlayerEvent::Connected));
    assert_eq!(
        core.poll_event(),
        Some(PlayerEvent::Message(error(ErrorCode::NotYourTurn)))
    );
    // A hostile header ends the connection; with no seat, for good.
    core.received(&[0xff, 0xff, 0xff, 0xff], ms(3));
    assert!(matches!(
        core.poll_event(),
        Some(PlayerEvent::Closed(NetError::Frame(_)))
    ));
}

#[test]
fn nothing_is_sent_while_the_seat_is_being_taken_back() {
    let mut s = Script::new(invite(1), retrying());
    s.greet();
    s.say(&joined(Role::Player(Seat::A), Some(SeatToken([2; 16]))));
    s.server.fail(NetError::Lost("cable".into()));
    s.wait(ms(1));
    assert!(matches!(
        s.driver.send(&ClientMessage::Rematch),
        Err(NetError::Lost(_))
    ));
    // Past the window the server holds the seat, the core gives up.
    s.server.fail(NetError::Connect("down".into()));
    s.wait(Duration::from_secs(31));
    s.server.fail(NetError::Connect("down".into()));
    s.wait(ms(1));
    let events = s.events();
    assert!(
        matches!(events.last(), Some(PlayerEvent::Closed(NetError::Lost(why))) if why.contains("reconnecting failed")),
        "{events:?}"
    );
}
