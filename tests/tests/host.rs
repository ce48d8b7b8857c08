//! Hosting from the game: the embedded server, the host's own seat over loopback QUIC, and a
//! second player who joins through nothing but the invite text.

use std::time::{Duration, Instant};

use breakshot_client::net::{Host, HostOptions, NetLink, Session, SessionEvent};
use breakshot_client::play::{GameEvent, GameFlow, GameLink};
use breakshot_client::view::hud::Connection;
use breakshot_shared::protocol::{AimAid, ClientMessage, Invite, Role, ServerMessage};
use breakshot_shared::rules::{Command, Seat, Settings};
use breakshot_tests::{
    break_shot, create_eight_ball, hosting_here, poll_link_until, poll_until, scratch, TestServer,
    PATIENCE,
};

#[test]
fn a_hosted_game_is_joined_through_its_invite_and_plays_a_shot() -> anyhow::Result<()> {
    let data = scratch("host");
    let options = HostOptions {
        aim_aid: AimAid::FirstContact,
        ..hosting_here(data.path().join("server"))
    };
    let mut host = Host::start(&options)?;
    let mut host_flow = GameFlow::new(Connection::Connecting);
    let mut guest_flow = GameFlow::new(Connection::Connecting);

    // The invite is text naming the bound address, a room and the server's certificate.
    let text = host.invite().to_string();
    let invite: Invite = text.parse()?;
    assert_eq!(invite.first().port, host.server().local_addr().port());
    assert_eq!(invite.first().host, "127.0.0.1");
    assert!(!host.needs_address());
    let room = invite.room.clone().expect("the invite names the room");
    assert!(data.path().join("server").join("cert.der").is_file());

    // The host holds seat A and waits for the opponent, with the room's aid policy.
    let GameEvent::Started(game) = poll_link_until(&mut host, &mut host_flow, "Started", |e| {
        matches!(e, GameEvent::Started(_))
    }) else {
        unreachable!()
    };
    assert_eq!(host.seat(), Some(Seat::A));

    let guest = Session::connect(invite);
    guest.send(ClientMessage::Join {
        room,
        name: "ben".into(),
    });
    let mut guest = NetLink::new(guest);
    let policy = poll_link_until(&mut guest, &mut guest_flow, "the aid policy", |e| {
        matches!(e, GameEvent::AimAid(_))
    });
    assert_eq!(policy, GameEvent::AimAid(AimAid::FirstContact));
    poll_link_until(&mut guest, &mut guest_flow, "Started", |e| {
        matches!(e, GameEvent::Started(_))
    });
    assert_eq!(guest.seat(), Some(Seat::B));
    poll_link_until(&mut host, &mut host_flow, "the opponent", |e| {
        *e == GameEvent::Connection(Connection::Connected)
    });

    // The host breaks; both sides simulate it and the server's hash confirms both. While
    // the host aims, the guest sees the host's cue where the host holds it.
    let ClientMessage::Shot { strike, .. } = break_shot(&game) else {
        unreachable!()
    };
    host.aim(game.turn(), strike);
    poll_link_until(&mut guest, &mut guest_flow, "the host's aim", |e| {
        matches!(e, GameEvent::Aim { .. })
    });
    let shown = guest_flow
        .opponent_aim(Some(Seat::B))
        .expect("the host's aim");
    assert_eq!(shown.dir, strike.validated()?.dir);
    assert_eq!(host_flow.opponent_aim(Some(Seat::A)), None, "not one's own");
    host.send(&game, Seat::A, Command::Shot { strike, call: None });
    let mut hashes = Vec::new();
    for (link, flow) in [
        (&mut host as &mut dyn GameLink, &mut host_flow),
        (&mut guest, &mut guest_flow),
    ] {
        let GameEvent::Judged { hash, .. } = poll_link_until(link, flow, "Judged", |e| {
            matches!(e, GameEvent::Judged { .. })
        }) else {
            unreachable!()
        };
        hashes.push(hash.expect("a shot has a hash"));
    }
    assert_eq!(hashes[0], hashes[1]);
    for flow in [&host_flow, &guest_flow] {
        let replica = flow.replica();
        assert_eq!((replica.confirmed(), replica.desyncs()), (1, 0));
    }

    // Both screens know both names, and what one player says the other reads.
    let names = [Some("ann".to_string()), Some("ben".to_string())];
    assert_eq!((&host_flow.names, &guest_flow.names), (&names, &names));
    assert!(host.chats() && guest.chats());
    host.chat("good luck".into());
    poll_link_until(&mut guest, &mut guest_flow, "the chat line", |e| {
        matches!(e, GameEvent::Chat(_))
    });
    let heard: Vec<String> = guest_flow.chat.lines().map(|l| l.shown()).collect();
    assert_eq!(heard, ["ann: good luck"]);
    drop(guest);
    drop(host);
    // The server stopped with the host: its port is free again.
    Ok(())
}

#[test]
fn the_invite_names_the_address_the_host_gives() -> anyhow::Result<()> {
    let data = scratch("host-address");
    let options = HostOptions {
        settings: Settings::offline(),
        address: Some("pool.example.org".into()),
        ..hosting_here(data.path().to_path_buf())
    };
    let host = Host::start(&options)?;
    let invite = host.invite();
    assert_eq!(invite.first().host, "pool.example.org");
    assert_eq!(invite.first().port, host.server().local_addr().port());
    assert!(!host.needs_address());
    Ok(())
}

#[test]
fn a_port_in_use_is_a_clear_error() -> anyhow::Result<()> {
    let data = scratch("host-busy");
    let taken = std::net::UdpSocket::bind("127.0.0.1:0")?;
    let options = HostOptions {
        bind: taken.local_addr()?,
        settings: Settings::offline(),
        ..hosting_here(data.path().to_path_buf())
    };
    let Err(e) = Host::start(&options) else {
        panic!("a second server bound the same port");
    };
    // As a player reads it: the error with its causes.
    let said = format!("{:#}", anyhow::Error::new(e));
    assert!(said.contains("binding"), "{said}");
    Ok(())
}

#[test]
fn a_session_reconnects_and_takes_its_seat_back_after_a_server_restart() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    let data = scratch("session-restart");
    let server = runtime.block_on(TestServer::start(data.path()))?;
    let addr = server.addr;

    let mut a = Session::connect(server.invite.clone());
    a.send(create_eight_ball("ann"));
    poll_until(&mut a, "Joined", |e| {
        matches!(e, SessionEvent::Message(ServerMessage::Joined { .. }))
    });
    let room = a.room().cloned().expect("room");
    let mut b = Session::connect(server.invite.clone());
    b.send(ClientMessage::Join {
        room: room.clone(),
        name: "ben".into(),
    });
    poll_until(&mut a, "PlayerJoined", |e| {
        matches!(e, SessionEvent::Message(ServerMessage::PlayerJoined { .. }))
    });

    // A session with no seat is not reconnected: it reports the loss.
    let mut watcher = Session::connect(server.invite.clone());
    watcher.send(ClientMessage::Spectate { room });
    poll_until(&mut watcher, "Joined", |e| {
        matches!(e, SessionEvent::Message(ServerMessage::Joined { .. }))
    });

    runtime.block_on(server.stop())?;
    for s in [&mut a, &mut b] {
        poll_until(s, "Reconnecting", |e| *e == SessionEvent::Reconnecting);
    }
    let start = Instant::now();
    let closed = loop {
        match watcher.try_recv() {
            Some(SessionEvent::Closed(why)) => break why,
            Some(SessionEvent::Reconnecting) => panic!("a spectator has no seat to take back"),
            _ => {}
        }
        assert!(
            start.elapsed() < PATIENCE,
            "the spectator never heard of the loss"
        );
        std::thread::sleep(Duration::from_millis(5));
    };
    assert!(!closed.is_empty());

    // The server comes back on the same address; the session rejoins its seat by itself.
    let server = runtime.block_on(TestServer::start_at(addr, data.path()))?;
    for (s, seat) in [(&mut a, Seat::A), (&mut b, Seat::B)] {
        poll_until(s, "Joined again", |e| {
            matches!(e, SessionEvent::Message(ServerMessage::Joined { .. }))
        });
        assert_eq!(s.role(), Some(Role::Player(seat)));
    }
    drop((a, b, watcher));
    runtime.block_on(server.stop())
}
