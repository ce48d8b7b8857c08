//! Whole games between bots through a real server.

use std::net::SocketAddr;

use anyhow::Context;
use breakshot_client::bot::{run, BotConfig};
use breakshot_server::limits::Limits;
use breakshot_server::verify::verify_dir;
use breakshot_shared::rules::{Command, Game, Phase, Settings, Variant};
use breakshot_tests::{bot_game, bot_games, scratch, TestServer, PATIENCE};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_bots_play_a_full_eight_ball_game_and_every_hash_agrees() -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("full-game").await?;
    let report = bot_games(&server, 1).await?;
    server.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert!(report.tally.shots > 0, "{:?}", report.games);
    assert_eq!(report.tally.desyncs, 0);
    // Both players predicted every shot and the server confirmed each prediction.
    assert_eq!(report.tally.confirmed, 2 * report.tally.shots);
    let game = &report.games[0];
    assert_eq!(game.resolved.len() as u32, report.tally.shots);
    eprintln!(
        "game over after {} shots: {}",
        report.tally.shots, game.reason
    );

    // The stored record replays to the same hashes.
    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 1);
    assert!(checks[0].result.is_ok(), "{:?}", checks[0].result);
    assert!(checks[0].finished);
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bots_sharing_endpoints_play_their_games_through() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("shared-endpoints").await?;
    let mut config = BotConfig::new(server.invite.clone(), 3);
    // Six connections, four to an endpoint: two endpoints, one carrying two games' players.
    config.per_endpoint = 4;
    let report = tokio::time::timeout(PATIENCE, run(&config)).await?;
    server.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.endpoints, 2);
    assert_eq!(report.games_completed, 3);
    assert_eq!(report.tally.desyncs, 0);
    assert_eq!(report.tally.confirmed, 2 * report.tally.shots);
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_nine_ball_game_with_called_shots_is_played_through_the_client_core() -> anyhow::Result<()>
{
    let (_data, server) = TestServer::start_fresh("nine-called").await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.variant = Variant::NineBall;
    config.settings = Settings {
        call_every_shot: true,
        ..Settings::offline()
    };
    let (report, record) = bot_game(server, &config, PATIENCE).await?;
    // The rules asked for a pocket on every shot after the break, the players named one,
    // and the server accepted each: the game ended by the rules, not by a concession.
    let mut game = Game::new(record.variant, record.settings, record.seed);
    let mut called = 0;
    for e in &record.entries {
        if let Command::Shot { call, .. } = &e.command {
            assert_eq!(call.is_some(), game.needs_call(), "turn {}", game.turn());
            called += usize::from(call.is_some());
        }
        assert_ne!(e.command, Command::Concede, "{}", report.games[0].reason);
        game.apply(e.seat, &e.command)?;
    }
    assert!(called > 0, "no shot after the break");
    assert!(matches!(game.phase(), Phase::Over { .. }));
    eprintln!(
        "9-ball over after {} shots ({called} called): {}",
        report.tally.shots, report.games[0].reason
    );
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bots_checking_one_shot_in_three_play_on_the_server_s_game_after_the_others(
) -> anyhow::Result<()> {
    // A load run's bots stand for players on machines of their own: `--check-every 3`
    // simulates a third of the shots, and each player goes on from the game the server
    // sends with every other result. The game is played to its end all the same, and the
    // checked shots agree to the bit.
    let (_data, server) = TestServer::start_fresh("check-every").await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.check_every = 3;
    let (report, _record) = bot_game(server, &config, PATIENCE).await?;
    assert!(report.tally.shots >= 4, "too short a game to skip a shot");
    assert!(report.tally.unchecked > 0);
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_game_whose_second_player_never_gets_in_ends_rather_than_waits_for_ever(
) -> anyhow::Result<()> {
    // One connection at a time: the bot that opens the room takes it, so the one that joins
    // is refused until it gives up, as when a server too busy to finish handshakes drops
    // them under load. A room waits for its second player as long as its first stays, so
    // the first must leave by itself.
    let data = scratch("never-joined");
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.limits = Limits {
        max_connections: 1,
        address_share: 1,
        ..Limits::default()
    };
    let server = TestServer::start_with(config).await?;
    let bots = BotConfig::new(server.invite.clone(), 1);
    let report = tokio::time::timeout(PATIENCE, run(&bots))
        .await
        .context("the run did not end: the bot that opened the room still waits")?;
    eprintln!("{:#?}", report.errors);
    assert_eq!(report.games_completed, 0);
    // Both players say why: the one that never got in, and the one it left waiting.
    assert_eq!(report.errors.len(), 2, "{:?}", report.errors);
    assert!(
        report
            .errors
            .iter()
            .any(|e| e.contains("the opponent never took its seat")),
        "{:?}",
        report.errors
    );
    server.stop().await
}
