//! Three-cushion billiards through a real server: rooms are created and played like 8-ball
//! and 9-ball, and every client's copy of each shot matches the server's.

use breakshot_client::bot::BotConfig;
use breakshot_server::verify::verify_dir;
use breakshot_shared::physics::TableKind;
use breakshot_shared::rules::{Command, Game, Phase, Settings, Variant};
use breakshot_tests::{bot_game, TestServer, PATIENCE};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_three_cushion_match_is_played_through_the_client_core_without_a_desync(
) -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("three-cushion").await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.variant = Variant::ThreeCushion { race: 1 };
    config.settings = Settings {
        table: TableKind::Carom,
        ..Settings::offline()
    };
    let (report, record) = bot_game(server, &config, PATIENCE).await?;
    assert!(report.tally.shots > 1, "{:?}", report.games);

    // The record is a three-cushion match on the carom table, judged shot by shot by the
    // three-cushion rules: every shot either scored (the shooter plays on) or passed the
    // inning, and the balls never went in hand.
    assert_eq!(record.variant, Variant::ThreeCushion { race: 1 });
    let mut game = Game::new(record.variant, record.settings, record.seed);
    assert_eq!(game.table(), TableKind::Carom);
    let (mut points, mut passes) = (0, 0);
    for e in &record.entries {
        let before = game.to_move();
        let verdict = game.apply(e.seat, &e.command)?;
        if let Command::Shot { call, .. } = &e.command {
            assert_eq!(*call, None);
            assert_eq!(verdict.shot.map(|s| s.hash), e.hash);
            let scored = verdict.reasons[0].starts_with("Point: ");
            assert!(
                scored || verdict.reasons[0].contains("no point"),
                "{:?}",
                verdict.reasons
            );
            points += u32::from(scored);
            passes += u32::from(verdict.next != before);
        }
        assert!(matches!(
            game.phase(),
            Phase::Shooting { in_hand: None, .. } | Phase::Over { .. }
        ));
    }
    assert!(
        passes > 0,
        "no inning passed in {} shots",
        report.tally.shots
    );
    assert!(matches!(game.phase(), Phase::Over { .. }));
    eprintln!(
        "three-cushion over after {} shots ({points} points, {passes} innings passed): {}",
        report.tally.shots, report.games[0].reason
    );

    // The stored record replays to the same hashes.
    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 1);
    assert!(checks[0].result.is_ok(), "{:?}", checks[0].result);
    Ok(())
}
