//! The polling session a frame loop uses: it never blocks, and it predicts and confirms
//! shots like the bots do.

use std::time::{Duration, Instant};

use breakshot_client::net::{NetLink, Session, SessionEvent};
use breakshot_client::play::{Check, GameEvent, GameFlow, GameLink, Replica};
use breakshot_client::view::hud::Connection;
use breakshot_shared::protocol::{ClientMessage, Role, ServerMessage};
use breakshot_shared::rules::{Command, Seat};
use breakshot_tests::{
    break_shot, create_eight_ball, poll_link_until, poll_until, scratch, TestServer, PATIENCE,
};

#[test]
fn a_polled_session_plays_and_confirms_a_shot() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    let data = scratch("session");
    let server = runtime.block_on(TestServer::start(data.path()))?;

    let mut a = Session::connect(server.invite.clone());
    poll_until(&mut a, "Connected", |e| {
        matches!(e, SessionEvent::Connected)
    });
    a.send(create_eight_ball("ann"));
    let SessionEvent::Message(ServerMessage::Joined { snapshot, .. }) =
        poll_until(&mut a, "Joined", |e| {
            matches!(e, SessionEvent::Message(ServerMessage::Joined { .. }))
        })
    else {
        unreachable!()
    };
    assert_eq!(a.role(), Some(Role::Player(Seat::A)));

    let mut b = Session::connect(server.invite.with_room(snapshot.room.clone()));
    poll_until(&mut b, "Connected", |e| {
        matches!(e, SessionEvent::Connected)
    });
    b.send(ClientMessage::Join {
        room: snapshot.room.clone(),
        name: "ben".into(),
    });
    poll_until(&mut a, "PlayerJoined", |e| {
        matches!(e, SessionEvent::Message(ServerMessage::PlayerJoined { .. }))
    });

    a.send(break_shot(&snapshot.game));
    for s in [&mut a, &mut b] {
        // The session's messages drive a replica, as the bot's and the screen's do.
        let mut replica = Replica::default();
        replica.start(snapshot.game.clone());
        let start = Instant::now();
        let checks = loop {
            assert!(start.elapsed() < PATIENCE, "no shot result");
            match s.recv_timeout(Duration::from_millis(50)) {
                Some(SessionEvent::Message(msg)) => {
                    let checks = replica.observe(&msg, s.seat());
                    if matches!(msg, ServerMessage::ShotResolved { .. }) {
                        break checks;
                    }
                }
                Some(SessionEvent::Closed(why)) => panic!("closed: {why}"),
                _ => {}
            }
        };
        assert_eq!(checks, vec![Check::Confirmed { turn: 0 }]);
        assert_eq!(replica.desyncs(), 0);
    }
    drop((a, b));
    runtime.block_on(server.stop())
}

#[test]
fn a_network_link_gives_a_game_screen_the_server_s_events() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    let data = scratch("link");
    let server = runtime.block_on(TestServer::start(data.path()))?;

    let host = Session::connect(server.invite.clone());
    host.send(create_eight_ball("ann"));
    let mut a = NetLink::new(host);
    let mut a_flow = GameFlow::new(Connection::Connecting);
    let mut b_flow = GameFlow::new(Connection::Connecting);
    let GameEvent::Started(game) = poll_link_until(&mut a, &mut a_flow, "Started", |e| {
        matches!(e, GameEvent::Started(_))
    }) else {
        unreachable!()
    };
    assert_eq!(a.seat(), Some(Seat::A));
    let room = a.session().room().cloned().expect("room");
    let guest = Session::connect(server.invite.with_room(room.clone()));
    guest.send(ClientMessage::Join {
        room,
        name: "ben".into(),
    });
    let mut b = NetLink::new(guest);
    poll_link_until(&mut b, &mut b_flow, "Started", |e| {
        matches!(e, GameEvent::Started(_))
    });
    assert_eq!(b.seat(), Some(Seat::B));

    // B may not break; A's break reaches both screens as accepted, then judged with the
    // hash the rules give here.
    let ClientMessage::Shot { strike, .. } = break_shot(&game) else {
        unreachable!()
    };
    let command = Command::Shot { strike, call: None };
    b.send(&game, Seat::B, command.clone());
    poll_link_until(&mut b, &mut b_flow, "Refused", |e| {
        matches!(e, GameEvent::Refused(_))
    });
    a.send(&game, Seat::A, command.clone());
    let mut local = (*game).clone();
    let expected = local.apply(
        Seat::A,
        &Command::Shot {
            strike: strike.validated()?,
            call: None,
        },
    )?;
    for (link, flow) in [(&mut a, &mut a_flow), (&mut b, &mut b_flow)] {
        let accepted = poll_link_until(link, flow, "Accepted", |e| {
            matches!(e, GameEvent::Accepted { .. })
        });
        assert!(matches!(
            accepted,
            GameEvent::Accepted { seat: Seat::A, .. }
        ));
        let GameEvent::Judged { hash, .. } = poll_link_until(link, flow, "Judged", |e| {
            matches!(e, GameEvent::Judged { .. })
        }) else {
            unreachable!()
        };
        assert_eq!(hash, expected.shot.as_ref().map(|s| s.hash));
        // What the rules said, shown as the copy of the game here judged it.
        let shown = flow.last_verdict.as_ref().expect("a verdict once judged");
        assert_eq!(shown.reasons, expected.reasons);
        assert_eq!(shown.shot.as_ref().map(|s| s.hash), hash);
    }
    drop((a, b));
    runtime.block_on(server.stop())
}
