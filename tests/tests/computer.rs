//! The computer player where players meet it online: as a bot against the ghost-ball bot
//! through a real server, and seated in a hosted room with a friend watching.

use std::time::{Duration, Instant};

use breakshot_client::bot::BotConfig;
use breakshot_client::net::{EmbeddedServer, Host, HostOptions, NetLink, SeatedComputer, Session};
use breakshot_client::play::{GameEvent, GameFlow, GameLink, Prompt};
use breakshot_client::view::hud::Connection;
use breakshot_server::Config;
use breakshot_shared::ai::{self, Level};
use breakshot_shared::protocol::{AimAid, ClientMessage};
use breakshot_shared::rules::{Command, Game, Phase, Seat, Settings, Variant};
use breakshot_tests::{bot_game, eight_ball, hosting_here, scratch, TestServer, PATIENCE};

/// One game of `variant`: the computer player at level 1 opens the room, the ghost-ball bot
/// joins. Every command the computer sent was accepted, both players confirmed every shot,
/// and the game ended by the rules (the record holds no concession).
async fn computer_against_ghost(variant: Variant, name: &str) -> anyhow::Result<()> {
    let data = scratch(name);
    let server = TestServer::start(data.path()).await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.variant = variant;
    config.levels = [Some(Level::new(1)), None];
    let (report, record) = bot_game(server, &config, 4 * PATIENCE).await?;
    assert_eq!(
        report.games[0].refused[0], 0,
        "the computer made a refused move"
    );
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
        report.tally.shots, report.games[0].reason
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

/// The player at `link` makes the move a level-1 computer would when the game waits for
/// them, and asks for a rematch (once) when it is over.
fn play_own_seat(link: &mut dyn GameLink, flow: &GameFlow, asked: &mut bool) {
    if flow.connection != Connection::Connected {
        return;
    }
    match flow.prompt(link.seat()) {
        Prompt::Shoot { seat, .. } | Prompt::Decide { seat, .. } => {
            // A game in play: its end is a new one to ask a rematch for, even when it
            // comes on this very move (the 9 on the break) with no wait in between.
            *asked = false;
            let game = flow.game().expect("a game").clone();
            let command =
                ai::decide(&game, Level::new(1), u64::from(game.turn())).expect("the game is on");
            link.send(&game, seat, command);
        }
        Prompt::Wait
            if flow
                .game()
                .is_some_and(|g| matches!(g.phase(), Phase::Over { .. })) =>
        {
            if !*asked {
                link.rematch();
                *asked = true;
            }
        }
        Prompt::Wait => *asked = false,
    }
}

#[test]
fn a_host_plays_the_seated_computer_while_a_friend_with_the_invite_watches() -> anyhow::Result<()> {
    let data = scratch("host-computer");
    let options = HostOptions {
        computer: Some(Level::new(1)),
        ..hosting_here(data.path().join("server"))
    };
    let mut host = Host::start(&options)?;
    assert_eq!(host.computer(), Some(Level::new(1)));
    assert_eq!(host.seat(), Some(Seat::A));
    let mut host_flow = GameFlow::new(Connection::Connecting);

    // The friend opens the invite as printed: both seats are taken, so the friend watches.
    let invite = host.invite().to_string().parse()?;
    let mut friend = NetLink::join(invite, "friend", None)?;
    let mut friend_flow = GameFlow::new(Connection::Connecting);

    // The host plays its seat; the computer answers from the other. The friend sees the
    // host's shots and then the computer's, which comes only once the shot before it has
    // played out on the screens (the balls stopped).
    let mut last_host_shot: Option<(Instant, f64)> = None;
    let mut computer_after = None;
    let mut asked = false;
    let start = Instant::now();
    while computer_after.is_none() {
        assert!(start.elapsed() < 2 * PATIENCE, "the computer never shot");
        pump(&mut host, &mut host_flow);
        while let Some(event) = friend.poll() {
            let shot = match &event {
                GameEvent::Accepted {
                    seat,
                    command: Command::Shot { .. },
                    ..
                } => Some(*seat),
                _ => None,
            };
            friend_flow.handle(event);
            match shot {
                Some(Seat::A) => {
                    let shown = friend_flow.shot().map_or(0.0, |p| p.outcome().duration);
                    last_host_shot = Some((Instant::now(), shown));
                }
                Some(Seat::B) => {
                    let (at, shown) = last_host_shot.expect("the host breaks first");
                    computer_after = Some((at.elapsed().as_secs_f64(), shown));
                }
                None => {}
            }
        }
        // The host starts once the friend is watching, so the friend sees every shot.
        if friend_flow.game().is_some() {
            play_own_seat(&mut host, &host_flow, &mut asked);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let (waited, shown) = computer_after.expect("the computer shot");
    assert!(
        waited >= shown,
        "the computer shot {waited:.2} s after a shot that plays for {shown:.2} s"
    );
    assert!(friend.watching(), "the friend holds no seat");
    assert_eq!(friend.seat(), None);
    settle(&mut friend, &mut friend_flow);
    assert_eq!(host_flow.replica().desyncs(), 0);
    assert_eq!(friend_flow.replica().desyncs(), 0);
    Ok(())
}

/// Polls a watcher until every shot it saw is confirmed by the server's hash.
fn settle(link: &mut NetLink<Session>, flow: &mut GameFlow) {
    let start = Instant::now();
    while flow.replica().confirmed() < flow.replica().shots() {
        assert!(start.elapsed() < PATIENCE, "a shot's result never came");
        while let Some(event) = link.poll() {
            flow.handle(event);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn the_seated_computer_plays_game_after_game() -> anyhow::Result<()> {
    let data = scratch("computer-rematch");
    let server = EmbeddedServer::start(Config::new(
        ([127, 0, 0, 1], 0).into(),
        data.path().to_path_buf(),
    ))?;
    let session = Session::connect(server.loopback_invite());
    session.send(ClientMessage::CreateRoom {
        variant: Variant::NineBall,
        mode: Settings::offline(),
        aim_aid: AimAid::Full,
        name: "host".into(),
    });
    let mut host = NetLink::new(session);
    let mut flow = GameFlow::new(Connection::Connecting);
    let start = Instant::now();
    let room = loop {
        assert!(start.elapsed() < PATIENCE, "no room was opened");
        pump(&mut host, &mut flow);
        if let Some(room) = host.session().room() {
            break room.clone();
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    // Unpaced: it moves as soon as it has chosen, so games go by quickly.
    let computer = SeatedComputer::join(
        server.loopback_invite().with_room(room),
        Level::new(1),
        7,
        false,
    )?;

    // The host asks for a rematch whenever a game ends; the computer agrees and plays on.
    let mut started = 0;
    let mut computer_shots = 0;
    let mut asked = false;
    let start = Instant::now();
    while started < 2 || computer_shots == 0 {
        assert!(
            start.elapsed() < 4 * PATIENCE,
            "games started {started}, the computer's shots in the last {computer_shots}; \
             the host's game: {}",
            flow.game().map_or("none".to_string(), |g| format!(
                "turn {}, {:?} to move, {:?}",
                g.turn(),
                g.to_move(),
                g.phase()
            ))
        );
        while let Some(event) = host.poll() {
            match &event {
                GameEvent::Started(_) => {
                    started += 1;
                    computer_shots = 0;
                }
                GameEvent::Accepted {
                    seat: Seat::B,
                    command: Command::Shot { .. },
                    ..
                } => computer_shots += 1,
                _ => {}
            }
            flow.handle(event);
        }
        flow.skip();
        play_own_seat(&mut host, &flow, &mut asked);
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(flow.replica().desyncs(), 0);
    drop((host, computer));
    Ok(())
}
