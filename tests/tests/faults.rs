//! Crashes: a server process killed with SIGKILL while bots play and the store is being
//! written, then started again on the same data directory. Nothing a player was shown may
//! be lost, verification must pass, and the bots must rejoin with their tokens and finish.
//!
//! The server process is this test binary run again with [`CHILD`] set: it serves like
//! `breakshot-server` (the same library, store and invite line) until it is killed.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use breakshot_client::bot::{run, BotConfig};
use breakshot_client::net::{endpoint, Channel};
use breakshot_server::store::Store;
use breakshot_server::verify::verify_dir;
use breakshot_server::{Config, Limits};
use breakshot_shared::protocol::{AimAid, ClientMessage, Invite, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Settings, Variant};
use breakshot_tests::{printed_invite, scratch, serve_until_killed, TempDir};

/// Set (to `BIND DATA`) in the server process this test starts.
const CHILD: &str = "BREAKSHOT_FAULTS_SERVER";
/// Games played at once while the server is killed.
const GAMES: usize = 4;
/// Times the server is killed.
const KILLS: usize = 3;
/// How long a test waits for an answer before calling the server stuck.
const PATIENCE: Duration = Duration::from_secs(60);

/// The server process: serves until killed. Does nothing in a normal test run.
#[test]
fn server_process() {
    let Ok(spec) = std::env::var(CHILD) else {
        return;
    };
    let (bind, data) = spec.split_once(' ').expect("BIND DATA");
    serve_until_killed(&Config::new(
        bind.parse().expect("a socket address"),
        data.into(),
    ));
}

/// Starts the server on `bind` and returns it with its invite line.
fn start(bind: &str, data: &Path) -> (Child, Invite) {
    let me = std::env::current_exe().expect("this test binary");
    let mut child = Command::new(me)
        .args([
            "--exact",
            "server_process",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, format!("{bind} {}", data.display()))
        .env(
            "RUST_LOG",
            std::env::var("FAULTS_LOG").unwrap_or_else(|_| "warn".into()),
        )
        .stdout(Stdio::piped())
        .stderr(
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(data.with_extension("log"))
                .expect("log file"),
        )
        .spawn()
        .expect("starting the server process");
    let stdout = child.stdout.take().expect("stdout");
    let Some(invite) = printed_invite(stdout) else {
        let _ = child.kill();
        let _ = child.wait();
        panic!("the server printed no invite");
    };
    (child, invite)
}

/// Where the server process runs each time it starts: a data directory in a scratch folder,
/// and a [`fixed_address`].
struct Home {
    data: PathBuf,
    bind: String,
    _scratch: TempDir,
}

impl Home {
    fn new(name: &str) -> Home {
        let folder = scratch(name);
        Home {
            data: folder.path().join("data"),
            bind: fixed_address(),
            _scratch: folder,
        }
    }

    /// [`start`]s the server here.
    fn start(&self) -> (Child, Invite) {
        start(&self.bind, &self.data)
    }
}

/// Commands stored so far, over all games.
fn stored_commands(data: &Path) -> usize {
    verify_dir(data)
        .map(|checks| checks.iter().map(|c| c.commands).sum())
        .unwrap_or(0)
}

/// Every game's record, by room.
fn records(data: &Path) -> Vec<(String, GameRecord)> {
    let store = Store::open(data).expect("store");
    store
        .all()
        .expect("games")
        .into_iter()
        .map(|g| (g.meta.code.to_string(), g.record.expect("record")))
        .collect()
}

/// A free loopback port, as an address to bind the server to each time it starts: fixed, so
/// that an invite stays valid across restarts.
fn fixed_address() -> String {
    let port = std::net::UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .expect("a free port")
        .port();
    format!("127.0.0.1:{port}")
}

fn verify_passes(data: &Path) {
    let checks = verify_dir(data).expect("verifying");
    for c in &checks {
        assert!(c.result.is_ok(), "verify failed: {:?}", c.result);
    }
}

#[test]
fn killing_the_server_loses_nothing_and_players_rejoin() {
    let home = Home::new("faults");
    let (mut server, invite) = home.start();

    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    let mut config = BotConfig::new(invite, GAMES);
    config.think = Duration::from_millis(20);
    let bots = runtime.spawn(async move { run(&config).await });

    let started = std::time::Instant::now();
    let mut kills = 0;
    let mut seen = 0;
    while kills < KILLS && !bots.is_finished() {
        // A hang becomes a failure (the bots' own retries give up after two minutes).
        assert!(
            started.elapsed() < Duration::from_secs(300),
            "no progress after {kills} kills"
        );
        // Kill once a few more commands have been stored: the bots are mid-game and shots
        // are being resolved and written.
        let stored = stored_commands(&home.data);
        if stored < seen + 8 {
            std::thread::sleep(Duration::from_millis(50));
            continue;
        }
        server.kill().expect("SIGKILL");
        server.wait().expect("reaped");
        kills += 1;
        let before = records(&home.data);
        verify_passes(&home.data);
        seen = before.iter().map(|(_, r)| r.entries.len()).sum();
        eprintln!(
            "kill {kills} at {:.1} s: {seen} commands stored",
            started.elapsed().as_secs_f64()
        );
        let (next, _) = home.start();
        server = next;
    }

    // The games may end before every planned kill on a fast machine; at least one must have
    // landed mid-game.
    assert!(
        kills >= 1,
        "the games ended before the server could be killed"
    );
    // The bots give up reconnecting after two minutes; anything longer is a hang.
    let report = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(300), bots).await })
        .expect("the bots never finished")
        .expect("bots");
    eprintln!(
        "games over at {:.1} s: {} shots, {} rejoins",
        started.elapsed().as_secs_f64(),
        report.tally.shots,
        report.tally.rejoins
    );
    let _ = server.kill();
    let _ = server.wait();
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed as usize, GAMES);
    assert_eq!(report.tally.desyncs, 0);
    assert!(report.tally.rejoins > 0);
    verify_passes(&home.data);

    // Every result a host was shown is in its game's stored record, in order.
    let stored = records(&home.data);
    for game in &report.games {
        let room = game.room.as_ref().expect("room").to_string();
        let record = &stored
            .iter()
            .find(|(r, _)| *r == room)
            .expect("stored game")
            .1;
        // A result stored just before a kill may never have been shown, and a host away
        // during a restart misses some: what was shown is a subsequence of what is stored.
        let mut stored_hashes = record.entries.iter().filter_map(|e| e.hash);
        for (turn, shown) in &game.resolved {
            assert!(
                stored_hashes.any(|h| h == *shown),
                "room {room}: the result of turn {turn} was shown but is not stored"
            );
        }
    }
}

/// Sends `msg` and reads until the table is ready again, within [`PATIENCE`]. Returns the
/// turn to answer next, or `None` if the game ended instead.
async fn command(conn: &mut Channel, msg: &ClientMessage) -> Option<u32> {
    conn.send(msg).await.expect("sending");
    loop {
        let next = tokio::time::timeout(PATIENCE, conn.recv())
            .await
            .expect("no answer from the server")
            .expect("the connection");
        match next {
            ServerMessage::TurnChanged { turn, .. } => return Some(turn),
            ServerMessage::GameOver { .. } => return None,
            ServerMessage::Error { code, message } => panic!("refused: {code:?} {message}"),
            _ => {}
        }
    }
}

/// Waits for the answer to the first message of a connection.
async fn answer(conn: &mut Channel) -> ServerMessage {
    tokio::time::timeout(PATIENCE, conn.recv())
        .await
        .expect("no answer from the server")
        .expect("the connection")
}

/// A practice session driven to the longest the limits allow: the longest unfinished game
/// is stored, survives a SIGKILL and is restored and verified; its last command then ends
/// it at the limit, and that game verifies too.
#[test]
fn the_longest_game_the_limits_allow_survives_a_kill_and_verifies() {
    let home = Home::new("faults-longest");
    let (mut server, invite) = home.start();
    let limit = Limits::default().max_practice_commands;
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    let started = std::time::Instant::now();

    // Position `i` of a walk of the cue ball around a free part of the table.
    let pos = |i: usize| [0.4 + 0.002 * (i % 100) as f64, 0.6];
    let (token, turn) = runtime.block_on(async {
        let endpoint = endpoint().expect("endpoint");
        let mut conn = Channel::open(&endpoint, &invite).await.expect("connect");
        conn.send(&ClientMessage::CreateRoom {
            variant: Variant::Practice,
            mode: Settings::offline(),
            aim_aid: AimAid::Off,
            name: "solo".into(),
        })
        .await
        .expect("create");
        let ServerMessage::Joined {
            token: Some(token),
            snapshot,
            ..
        } = answer(&mut conn).await
        else {
            panic!("not seated");
        };
        // The longest game that is not over: one more command would leave one place, which
        // goes to the concession that ends it.
        let mut turn = snapshot.game.turn();
        for i in 0..limit - 2 {
            // Within the per-connection message rate.
            tokio::time::sleep(Duration::from_millis(22)).await;
            let place = ClientMessage::PlaceCueBall { turn, pos: pos(i) };
            turn = command(&mut conn, &place).await.expect("still playing");
        }
        (token, turn)
    });
    server.kill().expect("SIGKILL");
    server.wait().expect("reaped");
    eprintln!(
        "{} commands stored in {:.1} s, then killed",
        limit - 2,
        started.elapsed().as_secs_f64()
    );
    let checks = verify_dir(&home.data).expect("verify");
    assert_eq!(checks.len(), 1);
    assert_eq!(checks[0].commands, limit - 2);
    assert!(checks[0].result.is_ok(), "{checks:?}");
    verify_passes(&home.data);

    let (mut server, _) = home.start();
    runtime.block_on(async {
        let endpoint = endpoint().expect("endpoint");
        let mut conn = Channel::open(&endpoint, &invite).await.expect("reconnect");
        conn.send(&ClientMessage::Rejoin { token })
            .await
            .expect("rejoin");
        let ServerMessage::Joined { snapshot, .. } = answer(&mut conn).await else {
            panic!("the restored game did not take the player back");
        };
        assert_eq!(snapshot.game.turn(), turn);
        let place = ClientMessage::PlaceCueBall {
            turn,
            pos: pos(limit),
        };
        conn.send(&place).await.expect("the last command");
        loop {
            match answer(&mut conn).await {
                ServerMessage::GameOver { reason, .. } => {
                    eprintln!("at the limit: {reason}");
                    break;
                }
                ServerMessage::Error { code, message } => panic!("refused: {code:?} {message}"),
                _ => {}
            }
        }
    });
    let _ = server.kill();
    let _ = server.wait();
    let checks = verify_dir(&home.data).expect("verify");
    assert_eq!(checks[0].commands, limit);
    assert!(checks[0].finished);
    verify_passes(&home.data);
}
