//! The operator's view (`--admin`): the metrics move while a game is played, readiness turns
//! off on a drain, a draining server opens no new room, and it stops by itself once the
//! game in play has ended.

use std::net::SocketAddr;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use breakshot_server::admin;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, ServerMessage};
use breakshot_shared::rules::Settings;
use breakshot_tests::{
    break_shot, create_eight_ball, eight_ball, scratch, seated_pair, Player, Reads, TestServer,
};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

/// How long the test waits for an answer before calling it stuck.
const PATIENCE: Duration = Duration::from_secs(30);

/// `METHOD path` over HTTP/1.1: (status, body).
async fn http(addr: SocketAddr, method: &str, path: &str) -> Result<(u16, String)> {
    tokio::time::timeout(PATIENCE, async {
        let mut stream = tokio::net::TcpStream::connect(addr).await?;
        let request = format!("{method} {path} HTTP/1.1\r\nHost: admin\r\n\r\n");
        stream.write_all(request.as_bytes()).await?;
        let mut answer = String::new();
        stream.read_to_string(&mut answer).await?;
        let status = answer
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .context("a status line")?;
        let body = answer.split_once("\r\n\r\n").map_or("", |(_, b)| b);
        Ok((status, body.to_owned()))
    })
    .await
    .context("the admin address did not answer")?
}

/// A sample's value in a scrape of /metrics.
fn sample(text: &str, series: &str) -> f64 {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .find_map(|l| l.strip_prefix(series)?.strip_prefix(' ')?.parse().ok())
        .unwrap_or_else(|| panic!("no {series} in\n{text}"))
}

/// Scrapes until `series` has the value `want` (the room census is taken once a second).
async fn until_sample(addr: SocketAddr, series: &str, want: f64) -> Result<String> {
    let deadline = tokio::time::Instant::now() + PATIENCE;
    loop {
        let (status, text) = http(addr, "GET", "/metrics").await?;
        assert_eq!(status, 200);
        if sample(&text, series) == want {
            return Ok(text);
        }
        if tokio::time::Instant::now() > deadline {
            bail!("{series} never became {want}:\n{text}");
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn metrics_move_during_a_game_and_a_drain_lets_it_finish() -> Result<()> {
    let data = scratch("admin");
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.drain_timeout = Duration::from_secs(120);
    let server = TestServer::start_with(config).await?;
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await?;
    let admin_addr = listener.local_addr()?;
    let admin_task = tokio::spawn(admin::serve(listener, server.stats.clone()));

    let (status, before) = http(admin_addr, "GET", "/metrics").await?;
    assert_eq!(status, 200);
    assert_eq!(sample(&before, "breakshot_command_seconds_count"), 0.0);
    assert_eq!(http(admin_addr, "GET", "/healthz").await?.0, 200);
    assert_eq!(http(admin_addr, "GET", "/readyz").await?.0, 200);

    let (mut a, mut b, _room) = seated_pair(&server.invite).await?;
    let text = until_sample(admin_addr, "breakshot_rooms{state=\"playing\"}", 1.0).await?;
    assert_eq!(sample(&text, "breakshot_players_connected"), 2.0);
    let game = a.game().context("a's game")?.clone();
    a.send(break_shot(&game)).await?;
    for p in [&mut a, &mut b] {
        p.shot_resolved().await?;
    }
    let (_, after) = http(admin_addr, "GET", "/metrics").await?;
    assert!(
        sample(&after, "breakshot_command_seconds_count") >= 1.0,
        "{after}"
    );
    assert!(
        sample(&after, "breakshot_store_write_seconds_count") >= 1.0,
        "{after}"
    );
    // Each stage of the shot's time is counted: each message's read, the hub's queue and its
    // own time for every message, a worker's for the shot it simulated, the writer's queue,
    // and each message's wait to be written on its connection.
    for stage in [
        "breakshot_read_seconds_count",
        "breakshot_hub_wait_seconds_count",
        "breakshot_hub_seconds_count",
        "breakshot_worker_wait_seconds_count",
        "breakshot_worker_seconds_count",
        "breakshot_writer_wait_seconds_count",
        "breakshot_send_wait_seconds_count",
    ] {
        assert!(sample(&after, stage) >= 1.0, "{stage}: {after}");
    }

    // A player waiting for a quick match, and a desync a client reports, are counted.
    let mut queued = Player::connect(&server.invite).await?;
    queued
        .send(ClientMessage::QuickMatch {
            variant: eight_ball(),
            mode: Settings::online(),
            name: "dave".into(),
        })
        .await?;
    until_sample(
        admin_addr,
        "breakshot_queue_players{game=\"eight_ball\"}",
        1.0,
    )
    .await?;
    a.send(ClientMessage::ReportDesync { turn: 0, hash: 1 })
        .await?;
    until_sample(admin_addr, "breakshot_desyncs_reported_total", 1.0).await?;

    // The drain: unready at once, no new room, the game in play goes on, and every player
    // is told (the one waiting for a match is out of the queue).
    assert_eq!(http(admin_addr, "POST", "/drain").await?.0, 202);
    assert_eq!(http(admin_addr, "GET", "/readyz").await?.0, 503);
    queued
        .until("out of the queue", |m| {
            matches!(m, ServerMessage::Unqueued { .. })
        })
        .await?;
    for p in [&mut a, &mut b] {
        match p
            .until("the drain", |m| matches!(m, ServerMessage::Draining { .. }))
            .await?
        {
            ServerMessage::Draining { message } => {
                assert!(message.contains("your game goes on"), "{message}")
            }
            other => bail!("{other:?}"),
        }
    }
    until_sample(
        admin_addr,
        "breakshot_queue_players{game=\"eight_ball\"}",
        0.0,
    )
    .await?;
    let mut late = Player::connect(&server.invite).await?;
    late.send(create_eight_ball("carol")).await?;
    match late.error().await? {
        ServerMessage::Error { code, message } => {
            assert_eq!(code, ErrorCode::ServerBusy);
            assert!(message.contains("shutting down"), "{message}");
        }
        other => bail!("expected an error, got {other:?}"),
    }
    until_sample(
        admin_addr,
        "breakshot_refusals_total{reason=\"draining\"}",
        1.0,
    )
    .await?;
    // Still serving the game in play: the next player to move concedes, which ends it.
    let to_move = b.game().context("b's game")?.to_move();
    let mover = if a.client.role() == Some(breakshot_shared::protocol::Role::Player(to_move)) {
        &mut a
    } else {
        &mut b
    };
    mover.send(ClientMessage::Concede).await?;
    mover
        .until("GameOver", |m| matches!(m, ServerMessage::GameOver { .. }))
        .await?;
    assert!(
        server.stopped_by_itself(PATIENCE).await?,
        "a drained server with no game in play stops by itself"
    );
    admin_task.abort();
    Ok(())
}
