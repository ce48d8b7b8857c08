//! Dropped connections and server restarts: seats are held, tokens bring players back, and
//! nothing the server accepted is lost.

use std::time::Duration;

use breakshot_client::bot::{run, BotConfig, Chooser};
use breakshot_server::store::Store;
use breakshot_shared::protocol::{ClientMessage, Role, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::Seat;
use breakshot_tests::{break_shot, seated_pair, Player, TempDir, TestServer};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_dropped_player_rejoins_with_its_token_and_play_continues() -> anyhow::Result<()> {
    let data = TempDir::new("rejoin");
    let server = TestServer::start(data.path()).await?;
    let (mut a, b, _room) = seated_pair(&server.invite).await?;
    let token = b.mirror.token().expect("seat B got a token");

    // B's connection dies; A is told, with the reconnect window.
    b.conn.quic().close(0u32.into(), b"cable pulled");
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
    let game = a.mirror.game().expect("A has the game").clone();
    a.send(break_shot(&game)).await?;
    a.until("TurnChanged", |m| {
        matches!(m, ServerMessage::TurnChanged { .. })
    })
    .await?;
    let turn_after_break = a.mirror.game().expect("game").turn();

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
    assert_eq!(snapshot.game, *a.mirror.game().expect("game"));
    assert_eq!(snapshot.game.turn(), turn_after_break);
    a.until("PlayerBack", |m| {
        matches!(m, ServerMessage::PlayerBack { seat: Seat::B })
    })
    .await?;

    // And play continues: whoever is to move shoots, both see the result with equal hashes.
    let game = b2.mirror.game().expect("game").clone();
    let shooter = if game.to_move() == Seat::B {
        &mut b2
    } else {
        &mut a
    };
    let mv = Chooser::new(7).choose(&game).expect("the game is on");
    let shot = matches!(mv, ClientMessage::Shot { .. });
    shooter.send(mv).await?;
    for p in [&mut a, &mut b2] {
        p.until("TurnChanged", |m| {
            matches!(
                m,
                ServerMessage::TurnChanged { .. } | ServerMessage::GameOver { .. }
            )
        })
        .await?;
        assert!(p.mirror.game().expect("game").turn() > turn_after_break);
    }
    assert_eq!(a.mirror.desyncs() + b2.mirror.desyncs(), 0);
    if shot {
        assert_eq!(b2.mirror.confirmed(), 1);
    }
    drop(b);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_restarted_on_its_data_loses_no_shot() -> anyhow::Result<()> {
    let data = TempDir::new("restart");
    let server = TestServer::start(data.path()).await?;
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
            .and_then(|g| GameRecord::decode(&g.record).ok())
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
    let report = bots.await?;
    again.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert!(
        report.rejoins >= 2,
        "both players rejoined ({} rejoins)",
        report.rejoins
    );
    assert_eq!(report.desyncs, 0);
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
