//! The computer player where players meet it online: as a bot against the ghost-ball bot
//! through a real server, and seated in a hosted room with a friend watching.

use std::time::{Duration, Instant};

use breakshot_client::bot::{run, BotConfig};
use breakshot_client::net::{fetch_record, Host, HostOptions, NetLink};
use breakshot_client::play::game_flow::{GameFlow, Turn};
use breakshot_client::play::link::{GameEvent, GameLink};
use breakshot_client::view::hud::Connection;
use breakshot_shared::ai::{self, Level};
use breakshot_shared::protocol::AimAid;
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command, Game, Phase, Seat, Settings, Variant};
use breakshot_tests::{eight_ball, TempDir, TestServer, PATIENCE};

/// One game of `variant`: the computer player at level 1 opens the room, the ghost-ball bot
/// joins. Every command the computer sent was accepted, both players confirmed every shot,
/// and the game ended by the rules (the record holds no concession).
async fn computer_against_ghost(variant: Variant, name: &str) -> anyhow::Result<()> {
    let data = TempDir::new(name);
    let server = TestServer::start(data.path()).await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.variant = variant;
    config.levels = [Some(Level::new(1)), None];
    let report = tokio::time::timeout(4 * PATIENCE, run(&config))
        .await
        .expect("the game never finished");
    let room = report.games[0].room.clone().expect("a room was opened");
    let fetched = fetch_record(&server.invite, &room).await?;
    server.stop().await?;

    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert_eq!(
        report.games[0].refused[0], 0,
        "the computer made a refused move"
    );
    assert_eq!(report.desyncs, 0);
    assert_eq!(report.confirmed, 2 * report.shots);
    let record = GameRecord::decode(&fetched.bytes)?;
    assert!(fetched.finished);
    let mut game = Game::new(record.variant, record.settings, record.seed);
    let mut computer_shots = 0;
    for e in &record.entries {
        assert_ne!(e.command, Command::Concede, "{}", report.games[0].reason);
        computer_shots +=
            usize::from(e.seat == Seat::A && matches!(e.command, Command::Shot { .. }));
        game.apply(e.seat, &e.command)?;
    }
    assert!(computer_shots > 0);
    assert!(matches!(game.phase(), Phase::Over { .. }));
    eprintln!(
        "{name}: over after {} shots ({computer_shots} by the computer): {}",
        report.shots, report.games[0].reason
    );
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_computer_player_plays_a_whole_eight_ball_game_against_the_ghost_ball_bot(
) -> anyhow::Result<()> {
    computer_against_ghost(eight_ball(), "computer-8ball").await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_computer_player_plays_a_whole_nine_ball_game_against_the_ghost_ball_bot(
) -> anyhow::Result<()> {
    computer_against_ghost(Variant::NineBall, "computer-9ball").await
}

/// Polls `link` into `flow` as a game screen does, skipping shots as they start.
fn pump(link: &mut dyn GameLink, flow: &mut GameFlow) {
    while let Some(event) = link.poll() {
        flow.handle(event);
    }
    flow.skip();
}

#[test]
fn a_host_plays_the_seated_computer_while_a_friend_with_the_invite_watches() -> anyhow::Result<()> {
    let data = TempDir::new("host-computer");
    let options = HostOptions {
        bind: ([127, 0, 0, 1], 0).into(),
        data: data.path().join("server"),
        variant: eight_ball(),
        settings: Settings::online(),
        aim_aid: AimAid::Full,
        address: None,
        resume: true,
        computer: Some(Level::new(1)),
    };
    let mut host = Host::start(&options)?;
    assert_eq!(host.computer(), Some(Level::new(1)));
    assert_eq!(host.seat(), Some(Seat::A));
    let mut host_flow = GameFlow::new(Connection::Connecting);

    // The friend opens the invite as printed: both seats are taken, so the friend watches.
    let invite = host.invite().to_string().parse()?;
    let mut friend = NetLink::join(invite, "friend", None)?;
    let mut friend_flow = GameFlow::new(Connection::Connecting);

    // The host plays its seat (as a level-1 computer would, a legal move each turn) and asks
    // for a rematch when a game ends; the computer answers from the other seat, game after
    // game. The friend sees the shots of both, in the first game and the next.
    let mut started = 0;
    let mut asked = false;
    let mut watched = [0u32; 2];
    let start = Instant::now();
    while started < 2 || watched.iter().any(|&n| n == 0) {
        assert!(
            start.elapsed() < 4 * PATIENCE,
            "games started {started}, shots watched in the last (host, computer): {watched:?}"
        );
        pump(&mut host, &mut host_flow);
        while let Some(event) = friend.poll() {
            match &event {
                GameEvent::Started(_) => {
                    started += 1;
                    watched = [0; 2];
                }
                GameEvent::Accepted {
                    seat,
                    command: Command::Shot { .. },
                    ..
                } => watched[usize::from(*seat == Seat::B)] += 1,
                _ => {}
            }
            friend_flow.handle(event);
        }
        friend_flow.skip();
        if host_flow.connection == Connection::Connected {
            match host_flow.turn(host.seat()) {
                Turn::Shoot { .. } | Turn::Decide { .. } => {
                    let game = host_flow.game().expect("a game").clone();
                    let command = ai::decide(&game, Level::new(1), u64::from(game.turn()))
                        .expect("the game is on");
                    host.send(&game, Seat::A, command);
                }
                Turn::Wait
                    if host_flow
                        .game()
                        .is_some_and(|g| matches!(g.phase(), Phase::Over { .. })) =>
                {
                    if !asked {
                        host.rematch();
                        asked = true;
                    }
                }
                Turn::Wait => asked = false,
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(friend.watching(), "the friend holds no seat");
    assert_eq!(friend.seat(), None);
    // Every shot the friend saw is confirmed by the server's hash once its result arrives.
    let start = Instant::now();
    while friend_flow.replica().confirmed() < friend_flow.replica().shots() {
        assert!(start.elapsed() < PATIENCE, "a shot's result never came");
        while let Some(event) = friend.poll() {
            friend_flow.handle(event);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    eprintln!("the friend watched {} shots", friend_flow.replica().shots());
    assert_eq!(host_flow.replica().desyncs(), 0);
    assert_eq!(friend_flow.replica().desyncs(), 0);
    Ok(())
}
