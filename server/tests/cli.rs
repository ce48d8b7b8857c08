//! The `breakshot-server` command as an operator uses it.

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use breakshot_testkit::Spawned;

use breakshot_server::output::{RoomMeta, StoreOp};
use breakshot_server::store::Store;
use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{AimAid, Invite, RoomCode};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command as Cmd, EightBallRules, Game, Settings, Variant};
use glam::DVec2;

const BIN: &str = env!("CARGO_BIN_EXE_breakshot-server");

/// Runs `breakshot-server` with `args`; fails the test if it has not ended within a minute.
fn server(args: &[&OsStr]) -> Output {
    breakshot_testkit::run(Command::new(BIN).args(args), None, Duration::from_secs(60))
}

fn verify(data: &Path) -> Output {
    server(&[OsStr::new("verify"), OsStr::new("--data"), data.as_os_str()])
}

/// Starts `breakshot-server --bind 127.0.0.1:0 ARGS --data DATA` and reads the first
/// `lines` lines it prints (the invite, then the web link), each within a minute.
fn serve(args: &[&str], data: &Path, lines: usize) -> (Spawned, Vec<String>) {
    let mut serving = Spawned::start(
        Command::new(BIN)
            .args(["--bind", "127.0.0.1:0"])
            .args(args)
            .arg("--data")
            .arg(data)
            .stdout(Stdio::piped())
            .stderr(Stdio::null()),
    );
    let mut out: Box<dyn std::io::Read + Send> =
        Box::new(serving.child().stdout.take().expect("piped"));
    let mut printed = Vec::new();
    for _ in 0..lines {
        let (line, rest) = breakshot_testkit::read_line(out, Duration::from_secs(60));
        printed.push(line.trim().to_owned());
        out = Box::new(rest);
    }
    (serving, printed)
}

/// Stops a server started by [`serve`] with Ctrl-C and expects a clean exit within a minute.
fn stop(mut serving: Spawned) {
    serving.interrupt();
    assert!(serving.wait(Duration::from_secs(60)).success());
}

/// Stores one game of two real shots, with `tamper` flipping a bit of the second hash.
fn store_game(dir: &Path, tamper: bool) {
    let variant = Variant::EightBall(EightBallRules::Wpa);
    let settings = Settings::offline();
    let mut game = Game::new(variant, settings, 42);
    let mut record = GameRecord::new(variant, settings, 42);
    for speed in [9.0, 3.0] {
        let seat = game.to_move();
        let cue = game.balls()[0].pos;
        let command = Cmd::Shot {
            strike: Strike {
                speed,
                dir: nearest_ball(&game) - cue,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
            call: None,
        };
        let Ok(verdict) = game.apply(seat, &command) else {
            // After the break the rules may want the cue ball placed first: one shot is
            // enough then.
            break;
        };
        record.push(seat, command, verdict.shot.map(|s| s.hash));
    }
    if tamper {
        let last = record.entries.last_mut().unwrap();
        last.hash = last.hash.map(|h| h ^ 1);
    }
    let code = RoomCode::parse("K7QX2M4B").unwrap();
    let ops = [StoreOp::Room(RoomMeta {
        code: code.clone(),
        variant,
        settings,
        aim_aid: AimAid::Off,
        seats: [None, None],
    })]
    .into_iter()
    .chain(StoreOp::whole_game(&code, 1, &record))
    .collect::<Vec<_>>();
    Store::open(dir)
        .unwrap()
        .apply(&ops.iter().collect::<Vec<_>>())
        .unwrap();
}

/// The position of the object ball nearest the cue ball.
fn nearest_ball(game: &Game) -> DVec2 {
    let cue = game.balls()[0].pos;
    game.balls()[1..]
        .iter()
        .map(|b| b.pos)
        .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
        .unwrap()
}

#[test]
fn verify_reports_each_game_and_fails_on_a_tampered_one() {
    let scratch = breakshot_testkit::scratch("cli-verify");
    let dir = scratch.path();
    store_game(dir, false);
    let out = verify(dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("verified K7QX2M4B game 1"), "{text}");
    assert!(text.contains("1 games: 1 verified, 0 failed"), "{text}");

    store_game(dir, true);
    let out = verify(dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("FAILED   K7QX2M4B game 1"), "{text}");
    assert!(text.contains("state hash differs"), "{text}");

    let out = verify(&dir.join("nothing"));
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_server_prints_its_invite_first_and_stops_cleanly_on_ctrl_c() {
    let dir = breakshot_testkit::scratch("cli-serve");
    let (server, printed) = serve(&[], dir.path(), 1);
    let invite: Invite = printed[0].parse().unwrap();
    assert_eq!(invite.first().host, "127.0.0.1");
    assert_ne!(invite.first().port, 0);
    assert!(invite.room.is_none());
    stop(server);
}

#[test]
fn the_invite_names_the_public_host_then_the_other_instances_in_order() {
    let dir = breakshot_testkit::scratch("cli-also");
    let (serving, printed) = serve(
        &[
            "--host",
            "pool.example.org",
            "--also",
            "b.example.org:4434",
            "--also",
            "[2001:db8::7]:4433",
        ],
        dir.path(),
        1,
    );
    let invite: Invite = printed[0].parse().unwrap();
    let servers: Vec<String> = invite.servers.iter().map(|s| s.to_string()).collect();
    let port = invite.first().port;
    assert_eq!(
        servers,
        [
            format!("pool.example.org:{port}"),
            "b.example.org:4434".into(),
            "[2001:db8::7]:4433".into()
        ]
    );
    stop(serving);

    // An address that is not HOST:PORT is refused before anything starts.
    let out = server(&[
        OsStr::new("--also"),
        OsStr::new("b.example.org"),
        OsStr::new("--data"),
        dir.path().as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("HOST:PORT"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_store_that_is_not_a_postgres_url_is_refused_and_an_unreachable_one_is_an_error() {
    let scratch = breakshot_testkit::scratch("cli-store");
    let data = scratch.path().as_os_str();
    let out = server(&[
        OsStr::new("--data"),
        data,
        OsStr::new("--store"),
        OsStr::new("sqlite:games.db"),
    ]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("is not a postgres:// URL"), "{text}");

    // Nothing listens on this socket folder: the store cannot be read, exit 2.
    let nowhere = format!(
        "postgresql://breakshot@/postgres?host={}&connect_timeout=5",
        scratch.path().display()
    );
    let out = server(&[
        OsStr::new("verify"),
        OsStr::new("--store"),
        OsStr::new(&nowhere),
    ]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("PostgreSQL"), "{text}");
}

/// `GET`/`POST` `path` on the admin address: (status, body). Bounded by socket timeouts.
fn http(addr: &str, method: &str, path: &str) -> (u16, String) {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(addr).expect("the admin address accepts");
    stream
        .set_read_timeout(Some(Duration::from_secs(30)))
        .expect("a timeout");
    write!(stream, "{method} {path} HTTP/1.1\r\nHost: admin\r\n\r\n").expect("request sent");
    let mut answer = String::new();
    stream.read_to_string(&mut answer).expect("an answer");
    let status = answer
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {answer:?}"));
    let body = answer.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    (status, body.to_owned())
}

#[test]
fn the_admin_address_serves_metrics_and_sigterm_drains_an_idle_server_to_a_stop() {
    let dir = breakshot_testkit::scratch("server-admin");
    let mut server = Spawned::start(
        Command::new(BIN)
            .args([
                "--bind",
                "127.0.0.1:0",
                "--admin",
                "127.0.0.1:0",
                "--log-json",
            ])
            .arg("--data")
            .arg(dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::piped()),
    );
    // The log says where the admin address is bound, as a JSON object per line.
    let stderr = server.child().stderr.take().expect("piped");
    let (lines_tx, lines) = std::sync::mpsc::channel::<String>();
    std::thread::spawn(move || {
        use std::io::BufRead;
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            if lines_tx.send(line).is_err() {
                return;
            }
        }
    });
    let next_line = || {
        lines
            .recv_timeout(Duration::from_secs(60))
            .expect("the server logs within a minute")
    };
    let addr = loop {
        let line = next_line();
        if line.contains("admin:") {
            assert!(line.starts_with('{') && line.ends_with('}'), "{line}");
            let after = line.split("\"addr\":\"").nth(1).expect("an addr field");
            break after.split('"').next().expect("quoted").to_owned();
        }
    };
    let (status, metrics) = http(&addr, "GET", "/metrics");
    assert_eq!(status, 200);
    assert!(
        metrics.contains("# TYPE breakshot_connections gauge"),
        "{metrics}"
    );
    assert!(
        metrics.contains("breakshot_command_seconds_bucket{le=\"+Inf\"} 0"),
        "{metrics}"
    );
    assert_eq!(http(&addr, "GET", "/readyz").0, 200);
    assert_eq!(http(&addr, "GET", "/nothing/../../etc/passwd").0, 404);
    // SIGTERM drains; with no game in play the server then stops by itself, cleanly.
    server.terminate();
    let status = server.wait(Duration::from_secs(30));
    assert!(status.success(), "{status:?}");
    let mut log = Vec::new();
    while let Ok(line) = lines.recv_timeout(Duration::from_secs(5)) {
        log.push(line);
    }
    assert!(
        log.iter().any(|l| l.contains("drained")),
        "the log says the drain ended: {log:?}"
    );
}

#[test]
fn help_lists_the_web_flag() {
    let out = server(&[OsStr::new("--help")]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("--web <DIR>"), "{help}");
}

#[test]
fn with_web_the_server_prints_its_web_link_after_the_invite() {
    use breakshot_shared::protocol::WebLink;
    let dir = breakshot_testkit::scratch("cli-web");
    let web = dir.path().join("web");
    std::fs::create_dir_all(&web).unwrap();
    let web = web.to_str().expect("a UTF-8 scratch path");
    let data = dir.path().join("data");
    let (serving, printed) = serve(&["--host", "pool.example.org", "--web", web], &data, 2);
    let invite: Invite = printed[0].parse().unwrap();
    let link: WebLink = printed[1].parse().unwrap();
    let port = invite.first().port;
    assert_eq!(
        link.page.as_deref(),
        Some(format!("http://pool.example.org:{port}/").as_str())
    );
    assert!(link.room.is_none());
    assert!(
        !link.cert.is_empty(),
        "the link carries the browsers' certificate hashes"
    );
    stop(serving);
    // The key is the one kept in the data directory: the same after a restart.
    let (again, printed) = serve(&["--web", web], &data, 2);
    let second: WebLink = printed[1].parse().unwrap();
    assert_eq!(second.key, link.key);
    stop(again);
}

#[test]
fn with_web_page_the_link_opens_the_published_site_and_names_this_server() {
    use breakshot_shared::protocol::WebLink;
    let dir = breakshot_testkit::scratch("cli-web-page");
    let (serving, printed) = serve(
        &[
            "--host",
            "pool.example.org",
            "--web-page",
            "https://play.example.org/breakshot",
        ],
        &dir.path().join("data"),
        2,
    );
    let invite: Invite = printed[0].parse().unwrap();
    let link: WebLink = printed[1].parse().unwrap();
    assert_eq!(
        link.page.as_deref(),
        Some("https://play.example.org/breakshot/")
    );
    assert_eq!(link.server.as_ref(), Some(invite.first()));
    assert!(!link.cert.is_empty());
    stop(serving);

    // An address that is not a page's is refused before anything starts.
    let out = server(&[OsStr::new("--web-page"), OsStr::new("play.example.org?x")]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("https://"), "{err}");
}
