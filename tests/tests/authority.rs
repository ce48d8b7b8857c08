//! The server is the authority: it checks every command and refuses bad ones without
//! changing the game; spectators watch but cannot act.

use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, Role, RoomCode, ServerMessage};
use breakshot_shared::rules::{Game, Seat};
use breakshot_tests::{break_shot, seated_pair, Player, Reads, TestServer};
use glam::DVec2;

/// The game as a fresh spectator is shown it: the server's own state.
async fn server_game(server: &TestServer, room: &RoomCode) -> anyhow::Result<Game> {
    let mut watcher = Player::connect(&server.invite).await?;
    watcher
        .send(ClientMessage::Spectate { room: room.clone() })
        .await?;
    match watcher
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    {
        ServerMessage::Joined { snapshot, .. } => Ok(snapshot.game),
        other => anyhow::bail!("expected Joined, got {other:?}"),
    }
}

async fn refused(p: &mut Player, msg: ClientMessage) -> anyhow::Result<ErrorCode> {
    p.send(msg).await?;
    match p.error().await? {
        ServerMessage::Error { code, .. } => Ok(code),
        other => anyhow::bail!("expected an error, got {other:?}"),
    }
}

fn shot(turn: u32, speed: f64, dir: DVec2, tip: DVec2) -> ClientMessage {
    ClientMessage::Shot {
        turn,
        strike: Strike {
            speed,
            dir,
            tip,
            elevation_deg: 0.0,
        },
        call: None,
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_commands_are_refused_and_change_nothing() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("authority").await?;
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;
    let before = server_game(&server, &room).await?;
    let turn = before.turn();
    assert_eq!(before.to_move(), Seat::A);

    // Out of turn: B shoots while A is to break.
    assert_eq!(
        refused(&mut b, break_shot(&before)).await?,
        ErrorCode::NotYourTurn
    );
    // A stale turn: A answers a turn that is not the table's.
    let stale = match break_shot(&before) {
        ClientMessage::Shot { strike, call, .. } => ClientMessage::Shot {
            turn: turn + 1,
            strike,
            call,
        },
        other => other,
    };
    assert_eq!(refused(&mut a, stale).await?, ErrorCode::StaleTurn);
    // Not numbers, or out of the cue's range.
    let (y, z) = (DVec2::Y, DVec2::ZERO);
    for bad in [
        shot(turn, f64::NAN, y, z),
        shot(turn, 3.0, DVec2::new(f64::NAN, 1.0), z),
        shot(turn, 3.0, y, DVec2::new(0.0, f64::INFINITY)),
        shot(turn, 40.0, y, z),
        shot(turn, -1.0, y, z),
        shot(turn, 3.0, z, z),
        shot(turn, 3.0, y, DVec2::new(0.45, 0.45)),
        ClientMessage::PlaceCueBall {
            turn,
            pos: [f64::NAN, 0.3],
        },
    ] {
        assert_eq!(
            refused(&mut a, bad.clone()).await?,
            ErrorCode::Invalid,
            "{bad:?}"
        );
    }
    // Placing the cue ball on another ball, or beyond the head string, is for the rules to
    // refuse.
    let on_a_ball = before.balls()[1].pos;
    for pos in [[on_a_ball.x, on_a_ball.y], [0.6, 2.0]] {
        assert_eq!(
            refused(&mut a, ClientMessage::PlaceCueBall { turn, pos }).await?,
            ErrorCode::Illegal
        );
    }

    // Nothing changed, and the right command from the right player still works.
    assert_eq!(server_game(&server, &room).await?, before);
    a.send(break_shot(&before)).await?;
    a.shot_resolved().await?;
    assert_ne!(server_game(&server, &room).await?.turn(), turn);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_spectator_sees_the_game_but_cannot_act() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("spectator").await?;
    let (mut a, _b, room) = seated_pair(&server.invite).await?;

    let mut watcher = Player::connect(&server.invite).await?;
    watcher
        .send(ClientMessage::Spectate { room: room.clone() })
        .await?;
    let joined = watcher
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    let ServerMessage::Joined { role, token, .. } = joined else {
        unreachable!()
    };
    assert_eq!(role, Role::Spectator);
    assert!(token.is_none(), "a spectator gets no seat token");

    let game = watcher.game().expect("snapshot").clone();
    for msg in [
        break_shot(&game),
        ClientMessage::Concede,
        ClientMessage::Rematch,
    ] {
        assert_eq!(refused(&mut watcher, msg).await?, ErrorCode::Spectator);
    }
    assert_eq!(server_game(&server, &room).await?, game);

    // The watcher sees A's break like the players do, and predicts it to the same hash.
    a.send(break_shot(&game)).await?;
    watcher.shot_resolved().await?;
    assert_eq!(watcher.replica.confirmed(), 1);
    assert_eq!(watcher.replica.desyncs(), 0);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_malformed_frame_closes_only_that_connection() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("malformed").await?;
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;
    // A length prefix over the limit.
    b.client.send_raw(&[0x7f, 0xff, 0xff, 0xff]).await?;
    let left = a
        .until("PlayerLeft", |m| {
            matches!(m, ServerMessage::PlayerLeft { .. })
        })
        .await?;
    assert!(matches!(
        left,
        ServerMessage::PlayerLeft { seat: Seat::B, .. }
    ));
    assert!(b.recv().await.is_err(), "the sender's connection is closed");
    // A's connection is fine and the game still takes commands.
    let game = server_game(&server, &room).await?;
    a.send(break_shot(&game)).await?;
    a.shot_resolved().await?;
    server.stop().await
}
