//! Who may do what: seat tokens name one seat of one room, spectators cannot act, and the
//! per-address and per-server limits hold.

use std::net::SocketAddr;
use std::time::Duration;

use anyhow::{bail, Result};
use breakshot_server::{Limits, Stats};
use breakshot_shared::protocol::{ClientMessage, ErrorCode, Role, RoomCode, ServerMessage};
use breakshot_shared::rules::{Choice, Seat};
use breakshot_tests::{
    break_shot, create_room, scratch, seated_pair, Player, Reads, TempDir, TestServer,
};

/// A server with `limits` on a fresh scratch folder named after `name`, returned with it.
async fn start_limited(name: &str, limits: Limits) -> Result<(TempDir, TestServer)> {
    let data = scratch(name);
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.limits = limits;
    let server = TestServer::start_with(config).await?;
    Ok((data, server))
}

/// Sends `msg` and returns the code of the error the server answers it with.
async fn refusal(p: &mut Player, msg: ClientMessage) -> Result<ErrorCode> {
    p.send(msg).await?;
    match p.error().await? {
        ServerMessage::Error { code, .. } => Ok(code),
        other => bail!("expected an error, got {other:?}"),
    }
}

/// Rejoins with `token` and returns the room and role the server gave.
async fn rejoin(
    server: &TestServer,
    token: breakshot_shared::protocol::SeatToken,
) -> Result<(Player, RoomCode, Role)> {
    let mut p = Player::connect(&server.invite).await?;
    p.send(ClientMessage::Rejoin { token }).await?;
    match p
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    {
        ServerMessage::Joined { role, snapshot, .. } => Ok((p, snapshot.room, role)),
        _ => unreachable!(),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_seat_token_opens_only_its_own_room_and_seat() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("tokens").await?;
    let (a1, b1, room1) = seated_pair(&server.invite).await?;
    let (a2, b2, room2) = seated_pair(&server.invite).await?;
    assert_ne!(room1, room2);
    let tokens = [
        (a1.client.token().expect("token"), &room1, Seat::A),
        (b1.client.token().expect("token"), &room1, Seat::B),
        (a2.client.token().expect("token"), &room2, Seat::A),
        (b2.client.token().expect("token"), &room2, Seat::B),
    ];
    drop((a1, b1, a2, b2));
    for (token, room, seat) in tokens {
        let (_p, got_room, role) = rejoin(&server, token).await?;
        assert_eq!(&got_room, room);
        assert_eq!(role, Role::Player(seat));
    }
    // A token one bit away from a real one opens nothing.
    let mut forged = tokens[1].0;
    forged.0[0] ^= 1;
    let mut p = Player::connect(&server.invite).await?;
    let rejoin = ClientMessage::Rejoin { token: forged };
    assert_eq!(refusal(&mut p, rejoin).await?, ErrorCode::BadToken);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_spectator_cannot_send_any_game_command() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("spectator-commands").await?;
    let (a, _b, room) = seated_pair(&server.invite).await?;
    let mut watcher = Player::connect(&server.invite).await?;
    watcher.send(ClientMessage::Spectate { room }).await?;
    watcher
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    let game = a.game().expect("snapshot").clone();
    let turn = game.turn();
    for msg in [
        break_shot(&game),
        ClientMessage::PlaceCueBall {
            turn,
            pos: [0.5, 0.5],
        },
        ClientMessage::CallPocket { turn, pocket: 0 },
        ClientMessage::Decide {
            turn,
            choice: Choice::AcceptTable,
        },
        ClientMessage::Concede,
        ClientMessage::Rematch,
    ] {
        assert_eq!(refusal(&mut watcher, msg).await?, ErrorCode::Spectator);
    }
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn room_entries_are_rate_limited_per_address() -> Result<()> {
    let limits = Limits {
        entry_burst: 3,
        // Nothing is earned back during the test, so the count is exact. Successful entries
        // cost nothing; failed ones use the budget.
        entry_refill: Duration::from_secs(3_600),
        ..Limits::default()
    };
    let (_data, server) = start_limited("entry-rate", limits).await?;
    let mut host = Player::connect(&server.invite).await?;
    let room = create_room(&mut host, "host").await?;
    // Guessing codes: each wrong guess uses an entry.
    let mut guesser = Player::connect(&server.invite).await?;
    for guess in ["22222222", "33333333", "44444444"] {
        let join = ClientMessage::Join {
            room: RoomCode::parse(guess)?,
            name: "guess".into(),
        };
        assert_eq!(refusal(&mut guesser, join).await?, ErrorCode::NoSuchRoom);
    }
    // The budget is spent: even the right code is refused, on a new connection too.
    let mut again = Player::connect(&server.invite).await?;
    let join = ClientMessage::Join {
        room,
        name: "guess".into(),
    };
    assert_eq!(refusal(&mut again, join).await?, ErrorCode::RateLimited);
    let watch = ClientMessage::Spectate {
        room: RoomCode::parse("55555555")?,
    };
    assert_eq!(refusal(&mut guesser, watch).await?, ErrorCode::RateLimited);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rooms_per_address_and_connections_are_capped() -> Result<()> {
    let limits = Limits {
        rooms_per_address: 2,
        max_connections: 3,
        // Every player here comes from 127.0.0.1: the total is what is tested.
        address_share: 1,
        ..Limits::default()
    };
    let (_data, server) = start_limited("caps", limits).await?;
    let mut players = Vec::new();
    for name in ["one", "two"] {
        let mut p = Player::connect(&server.invite).await?;
        create_room(&mut p, name).await?;
        players.push(p);
    }
    let mut third = Player::connect(&server.invite).await?;
    let create = breakshot_tests::create_eight_ball("three");
    assert_eq!(refusal(&mut third, create).await?, ErrorCode::ServerBusy);
    // Three connections are open: a fourth is refused.
    assert!(Player::connect(&server.invite).await.is_err());
    assert!(Stats::get(&server.stats.refused) >= 1);
    drop(third);
    server.stop().await
}
