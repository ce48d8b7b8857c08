//! Whole games between bots through a real server.

use breakshot_client::bot::{run, BotConfig};
use breakshot_server::verify::verify_dir;
use breakshot_tests::{TempDir, TestServer, PATIENCE};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_bots_play_a_full_eight_ball_game_and_every_hash_agrees() -> anyhow::Result<()> {
    let data = TempDir::new("full-game");
    let server = TestServer::start(data.path()).await?;
    let report = tokio::time::timeout(PATIENCE, run(&BotConfig::new(server.invite.clone(), 1)))
        .await
        .expect("the game never finished");
    server.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert!(report.shots > 0, "{:?}", report.games);
    assert_eq!(report.desyncs, 0);
    // Both players predicted every shot and the server confirmed each prediction.
    assert_eq!(report.confirmed, 2 * report.shots);
    let game = &report.games[0];
    assert_eq!(game.resolved.len() as u32, report.shots);
    eprintln!("game over after {} shots: {}", report.shots, game.reason);

    // The stored record replays to the same hashes.
    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 1);
    assert!(checks[0].result.is_ok(), "{:?}", checks[0].result);
    assert!(checks[0].finished);
    Ok(())
}
