//! The polling session a frame loop uses: it never blocks, and it predicts and confirms
//! shots like the bots do.

use breakshot_client::net::{Check, NetLink, Session, SessionEvent};
use breakshot_client::play::link::{GameEvent, GameLink};
use breakshot_shared::protocol::{AimAid, ClientMessage, Role, ServerMessage};
use breakshot_shared::rules::{Command, Seat, Settings};
use breakshot_tests::{break_shot, eight_ball, poll_link_until, poll_until, TempDir, TestServer};

#[test]
fn a_polled_session_plays_and_confirms_a_shot() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    let data = TempDir::new("session");
    let server = runtime.block_on(TestServer::start(data.path()))?;

    let a = Session::connect(server.invite.clone());
    poll_until(&a, "Connected", |e| matches!(e, SessionEvent::Connected));
    a.send(ClientMessage::CreateRoom {
        variant: eight_ball(),
        mode: Settings::offline(),
        aim_aid: AimAid::Full,
        name: "ann".into(),
    });
    let SessionEvent::Message(ServerMessage::Joined { snapshot, .. }) =
        poll_until(&a, "Joined", |e| {
            matches!(e, SessionEvent::Message(ServerMessage::Joined { .. }))
        })
    else {
        unreachable!()
    };
    assert_eq!(a.mirror().role(), Some(Role::Player(Seat::A)));
    assert!(a.mirror().token().is_some());

    let b = Session::connect(server.invite.with_room(snapshot.room.clone()));
    poll_until(&b, "Connected", |e| matches!(e, SessionEvent::Connected));
    b.send(ClientMessage::Join {
        room: snapshot.room.clone(),
        name: "ben".into(),
    });
    poll_until(&a, "PlayerJoined", |e| {
        matches!(e, SessionEvent::Message(ServerMessage::PlayerJoined { .. }))
    });

    a.send(break_shot(&snapshot.game));
    for s in [&a, &b] {
        poll_until(s, "the check", |e| {
            matches!(e, SessionEvent::Check(Check::Confirmed { turn: 0 }))
        });
        assert_eq!(s.mirror().desyncs(), 0);
    }
    drop((a, b));
    runtime.block_on(server.stop())
}

#[test]
fn a_network_link_gives_a_game_screen_the_server_s_events() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    let data = TempDir::new("link");
    let server = runtime.block_on(TestServer::start(data.path()))?;

    let host = Session::connect(server.invite.clone());
    host.send(ClientMessage::CreateRoom {
        variant: eight_ball(),
        mode: Settings::offline(),
        aim_aid: AimAid::Full,
        name: "ann".into(),
    });
    let mut a = NetLink::new(host);
    let GameEvent::Started(game) =
        poll_link_until(&mut a, "Started", |e| matches!(e, GameEvent::Started(_)))
    else {
        unreachable!()
    };
    assert_eq!(a.seat(), Some(Seat::A));
    let room = a.session().mirror().room().cloned().expect("room");
    let guest = Session::connect(server.invite.with_room(room.clone()));
    guest.send(ClientMessage::Join {
        room,
        name: "ben".into(),
    });
    let mut b = NetLink::new(guest);
    poll_link_until(&mut b, "Started", |e| matches!(e, GameEvent::Started(_)));
    assert_eq!(b.seat(), Some(Seat::B));

    // B may not break; A's break reaches both screens as accepted, then judged with the
    // hash the rules give here.
    let ClientMessage::Shot { strike, .. } = break_shot(&game) else {
        unreachable!()
    };
    let command = Command::Shot { strike, call: None };
    b.send(Seat::B, command.clone());
    poll_link_until(&mut b, "Refused", |e| matches!(e, GameEvent::Refused(_)));
    a.send(Seat::A, command.clone());
    let mut local = (*game).clone();
    let expected = local.apply(
        Seat::A,
        &Command::Shot {
            strike: strike.validated()?,
            call: None,
        },
    )?;
    for link in [&mut a, &mut b] {
        let accepted = poll_link_until(link, "Accepted", |e| {
            matches!(e, GameEvent::Accepted { .. })
        });
        assert!(matches!(
            accepted,
            GameEvent::Accepted { seat: Seat::A, .. }
        ));
        let GameEvent::Judged(judgement) =
            poll_link_until(link, "Judged", |e| matches!(e, GameEvent::Judged(_)))
        else {
            unreachable!()
        };
        assert_eq!(judgement.hash, expected.shot.as_ref().map(|s| s.hash));
        assert_eq!(judgement.reasons, expected.reasons);
    }
    drop((a, b));
    runtime.block_on(server.stop())
}
