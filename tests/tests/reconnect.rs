//! Dropped connections and server restarts: seats are held, tokens bring players back, and
//! nothing the server accepted is lost.

use std::time::Duration;

use breakshot_client::bot::{run, BotConfig};
use breakshot_client::play::Chooser;
use breakshot_server::store::Store;
use breakshot_shared::protocol::{ClientMessage, Role, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::Seat;
use breakshot_tests::{break_shot, scratch, seated_pair, Player, Reads, TestServer, PATIENCE};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_dropped_player_rejoins_with_its_token_and_play_continues() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("rejoin").await?;
    let (mut a, b, _room) = seated_pair(&server.invite).await?;
    let token = b.client.token().expect("seat B got a token");

    // B's connection dies; A is told, with the reconnect window.
    b.pull_cable();
    let left = a
        .until("PlayerLeft", |m| {
            matches!(m, ServerMessage::PlayerLeft { .. })
        })
        .await?;
    let ServerMessage::PlayerLeft { seat, reconnect_ms } = left else {
        unreachable!()
    };
    assert_eq!(seat, Seat::B);
    assert!(reconnect_ms > 0);

    // A breaks while B is away; the seat is held.
    let game = a.game().expect("A has the game").clone();
    a.send(break_shot(&game)).await?;
    a.turn_changed().await?;
    let turn_after_break = a.game().expect("game").turn();

    // B comes back on a new connection with its token and sees the table as it is now.
    let mut b2 = Player::connect(&server.invite).await?;
    b2.send(ClientMessage::Rejoin { token }).await?;
    let joined = b2
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    let ServerMessage::Joined { role, snapshot, .. } = joined else {
        unreachable!()
    };
    assert_eq!(role, Role::Player(Seat::B));
    assert_eq!(snapshot.game, *a.game().expect("game"));
    assert_eq!(snapshot.game.turn(), turn_after_break);
    a.until("PlayerBack", |m| {
        matches!(m, ServerMessage::PlayerBack { seat: Seat::B })
    })
    .await?;

    // And play continues: whoever is to move shoots, both see the result with equal hashes.
    let game = b2.game().expect("game").clone();
    let shooter = if game.to_move() == Seat::B {
        &mut b2
    } else {
        &mut a
    };
    let mv = Chooser::new(7).choose(&game).expect("the game is on");
    let shot = matches!(mv, ClientMessage::Shot { .. });
    shooter.send(mv).await?;
    for p in [&mut a, &mut b2] {
        p.turn_over().await?;
        assert!(p.game().expect("game").turn() > turn_after_break);
    }
    assert_eq!(a.replica.desyncs() + b2.replica.desyncs(), 0);
    if shot {
        assert_eq!(b2.replica.confirmed(), 1);
    }
    drop(b);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_restarted_on_its_data_loses_no_shot() -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("restart").await?;
    let addr = server.addr;
    let invite = server.invite.clone();
    let mut config = BotConfig::new(invite, 1);
    // Thinking time keeps the game going while the test stops the server.
    config.think = Duration::from_millis(100);
    let bots = tokio::spawn(async move { run(&config).await });

    // Let a few commands be stored, then stop the server mid-game.
    let store = Store::open(data.path())?;
    let mut stored = 0;
    while stored < 3 {
        tokio::time::sleep(Duration::from_millis(5)).await;
        stored = store
            .unfinished()?
            .first()
            .and_then(|g| g.record.as_ref().ok())
            .map_or(0, |r| r.entries.len());
        anyhow::ensure!(
            !bots.is_finished(),
            "the game ended before the server could be stopped"
        );
    }
    server.stop().await?;

    // Start again on the same address and data: the game is restored by replaying it.
    let again = TestServer::start_at(addr, data.path()).await?;
    assert_eq!(again.restored, 1);
    // The bots retry for two minutes at most; anything longer is a hang.
    let report = tokio::time::timeout(3 * PATIENCE, bots)
        .await
        .map_err(|_| anyhow::anyhow!("the bots never finished"))??;
    again.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert!(
        report.tally.rejoins >= 2,
        "both players rejoined ({} rejoins)",
        report.tally.rejoins
    );
    assert_eq!(report.tally.desyncs, 0);
    // Every shot result a player saw, before and after the restart, is in the stored record
    // at its turn, with the same hash.
    let summary = &report.games[0];
    let room = summary.room.clone().expect("room");
    let record = GameRecord::decode(&store.record(&room, 1)?.expect("stored game"))?;
    assert!(!summary.resolved.is_empty());
    for (turn, hash) in &summary.resolved {
        assert_eq!(
            record.entries[*turn as usize].hash,
            Some(*hash),
            "turn {turn}"
        );
    }
    Ok(())
}

#[test]
fn a_client_killed_mid_shot_rejoins_and_gets_its_seat_back() -> anyhow::Result<()> {
    let main = tokio::runtime::Runtime::new()?;
    // The victim runs on a runtime of its own; shutting it down stops its QUIC driver at
    // once, so the server gets no goodbye, as when a process is killed.
    let victim = tokio::runtime::Runtime::new()?;
    let data = scratch("killed-client");
    let server = main.block_on(TestServer::start(data.path()))?;
    let mut a = victim.block_on(async {
        let mut a = Player::connect(&server.invite).await?;
        breakshot_tests::create_room(&mut a, "ann").await?;
        anyhow::Ok(a)
    })?;
    let room = a.client.room().cloned().expect("room");
    let token = a.client.token().expect("token");
    let mut b = main.block_on(async {
        let mut b = Player::connect(&server.invite).await?;
        b.join(&room, "ben").await?;
        anyhow::Ok(b)
    })?;
    victim.block_on(a.until("PlayerJoined", |m| {
        matches!(m, ServerMessage::PlayerJoined { .. })
    }))?;

    // A shoots and dies before it sees the result.
    let game = a.game().expect("game").clone();
    victim.block_on(a.send(break_shot(&game)))?;
    main.block_on(b.until("ShotResolved", |m| {
        matches!(m, ServerMessage::ShotResolved { .. })
    }))?;
    victim.shutdown_background();
    std::mem::forget(a);

    // A comes back with its token: its seat, the table after its shot, and play goes on.
    main.block_on(async {
        b.turn_changed().await?;
        let mut a2 = Player::connect(&server.invite).await?;
        a2.send(ClientMessage::Rejoin { token }).await?;
        let ServerMessage::Joined { role, snapshot, .. } = a2
            .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
            .await?
        else {
            unreachable!()
        };
        assert_eq!(role, Role::Player(Seat::A));
        assert_eq!(snapshot.game, *b.game().expect("game"));
        assert!(snapshot.game.turn() > game.turn());
        let now = snapshot.game.clone();
        let mv = Chooser::new(3).choose(&now).expect("the game is on");
        let shooter = if now.to_move() == Seat::A {
            &mut a2
        } else {
            &mut b
        };
        shooter.send(mv).await?;
        for p in [&mut a2, &mut b] {
            p.turn_over().await?;
            assert!(p.game().expect("game").turn() > now.turn());
        }
        server.stop().await
    })
}

/// A player away when the game ended (their opponent made its last move), with the server
/// restarted before they come back, is told the result for their seat instead of being told
/// their token is unknown.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_player_away_when_the_game_ended_is_told_the_result_after_a_restart() -> anyhow::Result<()>
{
    let (data, server) = TestServer::start_fresh("ended-away").await?;
    let addr = server.addr;
    let (mut a, b, room) = seated_pair(&server.invite).await?;
    let token = b.client.token().expect("seat B got a token");
    b.pull_cable();
    a.until("PlayerLeft", |m| {
        matches!(m, ServerMessage::PlayerLeft { .. })
    })
    .await?;
    // The game's last command while B is away.
    a.send(ClientMessage::Concede).await?;
    a.until("GameOver", |m| matches!(m, ServerMessage::GameOver { .. }))
        .await?;
    server.stop().await?;

    let again = TestServer::start_at(addr, data.path()).await?;
    assert_eq!(again.restored, 0, "a finished game is not played again");
    let mut b2 = Player::connect(&again.invite).await?;
    b2.send(ClientMessage::Rejoin { token }).await?;
    match b2.recv().await? {
        ServerMessage::GameFinished {
            room: r,
            game,
            seat,
            winner,
            reason,
        } => {
            assert_eq!(r, room);
            assert_eq!(game, 1);
            assert_eq!(seat, Seat::B);
            assert_eq!(winner, Some(Seat::B));
            assert!(reason.contains("conceded"), "{reason}");
        }
        other => anyhow::bail!("expected the game's result, got {other:?}"),
    }
    drop(b);
    again.stop().await
}
