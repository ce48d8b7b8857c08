//! Watching a game again from the server: a fresh client fetches the record by room code,
//! and replaying it reproduces every hash and the server's table.

use anyhow::{bail, Result};
use breakshot_client::net::{fetch_game, fetch_record, FetchError};
use breakshot_shared::physics::BallState;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, RoomCode, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::Phase;
use breakshot_tests::{bot_games, break_shot, seated_pair, Player, Reads, TestServer};

/// `a` breaks the game just joined; returns the break's hash and balls once both players
/// have seen the turn pass.
async fn break_and_pass(a: &mut Player, b: &mut Player) -> Result<(u64, Vec<BallState>)> {
    let Some(game) = a.game() else {
        bail!("no game after joining");
    };
    a.send(break_shot(game)).await?;
    let resolved = a.shot_resolved().await?;
    a.turn_changed().await?;
    b.turn_changed().await?;
    Ok(resolved)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_game_in_play_is_fetched_by_room_code_and_replays_to_the_servers_table() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("fetch-in-play").await?;
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;

    let (hash, balls) = break_and_pass(&mut a, &mut b).await?;

    // A client that never joined the room.
    let fetched = fetch_record(&server.invite, &room).await?;
    assert_eq!(fetched.room, room);
    assert_eq!(fetched.game, 1);
    assert!(!fetched.finished);
    let record = GameRecord::decode(&fetched.bytes)?;
    assert_eq!(record.entries.len(), 1);
    assert_eq!(record.entries[0].hash, Some(hash));

    // Replaying checks every hash, and ends on the table the server announced.
    let replayed = record.replay()?;
    assert_eq!(replayed.balls(), &balls[..]);
    let Some(mirror) = a.game() else {
        bail!("the player lost its game");
    };
    assert_eq!(replayed.turn(), mirror.turn());
    assert_eq!(replayed.to_move(), mirror.to_move());

    server.stop().await?;
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_finished_bot_game_is_fetched_whole_and_every_hash_replays() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("fetch-finished").await?;
    let report = bot_games(&server, 1).await?;
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    let summary = &report.games[0];
    let Some(room) = summary.room.clone() else {
        bail!("the bots' game has no room");
    };

    // The players have left: the record comes from the store.
    let fetched = fetch_record(&server.invite, &room).await?;
    assert!(fetched.finished);
    let record = GameRecord::decode(&fetched.bytes)?;
    let recorded: Vec<u64> = record.entries.iter().filter_map(|e| e.hash).collect();
    let resolved: Vec<u64> = summary.resolved.iter().map(|(_, h)| *h).collect();
    assert_eq!(recorded, resolved);
    assert_eq!(recorded.len() as u32, report.tally.shots);
    let replayed = record.replay()?;
    assert!(matches!(replayed.phase(), Phase::Over { .. }));

    server.stop().await?;
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn fetching_an_unknown_room_is_no_such_room_and_changes_nothing() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("fetch-unknown").await?;
    let unknown = RoomCode::parse("ZZZZZZZZ")?;

    let mut p = Player::connect(&server.invite).await?;
    p.send(ClientMessage::FetchRecord {
        room: unknown.clone(),
        game: None,
    })
    .await?;
    match p.recv().await? {
        ServerMessage::Error {
            code: ErrorCode::NoSuchRoom,
            message,
        } => assert!(message.contains("ZZZZZZZZ"), "{message}"),
        other => bail!("expected NoSuchRoom, got {other:?}"),
    }
    // The connection is still usable: a refusal is not a failure.
    p.send(ClientMessage::Spectate {
        room: unknown.clone(),
    })
    .await?;
    assert!(matches!(
        p.recv().await?,
        ServerMessage::Error {
            code: ErrorCode::NoSuchRoom,
            ..
        }
    ));

    let fetched = fetch_record(&server.invite, &unknown).await;
    assert!(
        matches!(&fetched, Err(FetchError::NoSuchGame(r)) if *r == unknown),
        "{fetched:?}"
    );
    server.stop().await?;
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn after_a_rematch_the_first_game_is_fetched_by_its_number_and_replays() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("fetch-by-number").await?;
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;

    // Game 1: a break, then whoever is to move concedes.
    let first_hash = break_and_pass(&mut a, &mut b).await?.0;
    let to_move = a.game().map(|g| g.to_move());
    let conceder = if to_move == Some(breakshot_shared::rules::Seat::A) {
        &mut a
    } else {
        &mut b
    };
    conceder.send(ClientMessage::Concede).await?;
    for p in [&mut a, &mut b] {
        p.until("GameOver", |m| matches!(m, ServerMessage::GameOver { .. }))
            .await?;
    }
    // The rematch: game 2 starts and gets a shot of its own.
    a.send(ClientMessage::Rematch).await?;
    b.send(ClientMessage::Rematch).await?;
    for p in [&mut a, &mut b] {
        p.until("GameStarted", |m| {
            matches!(m, ServerMessage::GameStarted { .. })
        })
        .await?;
    }
    let Some(game) = a.game() else {
        bail!("no game after the rematch");
    };
    a.send(break_shot(game)).await?;
    a.shot_resolved().await?;

    // Game 1, by its number: finished, and it replays to its end.
    let first = fetch_game(&server.invite, &room, Some(1)).await?;
    assert_eq!(
        (first.room.clone(), first.game, first.finished),
        (room.clone(), 1, true)
    );
    let record = GameRecord::decode(&first.bytes)?;
    assert_eq!(record.entries.len(), 2);
    assert_eq!(record.entries[0].hash, Some(first_hash));
    assert!(matches!(record.replay()?.phase(), Phase::Over { .. }));
    // The record keeps the players' names, for a replay to show.
    assert_eq!(
        record.players,
        [Some("alice".to_string()), Some("bob".to_string())]
    );

    // Without a number, and with 2: the game being played.
    let latest = fetch_record(&server.invite, &room).await?;
    let second = fetch_game(&server.invite, &room, Some(2)).await?;
    assert_eq!((latest.game, latest.finished), (2, false));
    assert_eq!(latest, second);
    assert_ne!(GameRecord::decode(&second.bytes)?.seed, record.seed);

    // A number the room has not reached is refused, saying how many games there are.
    match fetch_game(&server.invite, &room, Some(3)).await {
        Err(FetchError::Refused {
            code: ErrorCode::NoSuchGame,
            message,
        }) => assert!(message.contains("numbered 1 to 2"), "{message}"),
        other => bail!("expected NoSuchGame, got {other:?}"),
    }
    server.stop().await?;
    Ok(())
}
