//! A whole 8-ball game between a page in headless Chromium and a native bot, through a real
//! server on loopback: the page is the web client built by `web/build.sh`, served by the
//! server itself (`Config::web_dir`), opened on the server's own link with its computer
//! player at level 1 in the seat the link joins (`computer=1`). Every shot's hash is confirmed
//! by both sides, nobody desyncs, and the stored record verifies. Once over the Noise
//! WebSocket, once over WebTransport.
//!
//! Where the wasm32 target or Chromium is missing the tests say why and pass; CI
//! (`BREAKSHOT_REQUIRE_WEB=1`, `BREAKSHOT_REQUIRE_BROWSER=1`) requires them.

use std::collections::HashSet;
use std::net::SocketAddr;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use breakshot_client::bot::{open_room, BotConfig, Report};
use breakshot_client::net::fetch_record;
use breakshot_shared::ai::Level;
use breakshot_shared::protocol::{RoomCode, WebLink, WebTransportChoice};
use breakshot_shared::replay::GameRecord;
use breakshot_testkit::browser::{browser_or_skip, near, Browser, LaunchOptions, Rgba, Viewport};
use breakshot_testkit::web::{bundle, skip_web};
use breakshot_tests::{scratch, TestServer};

/// A whole game: the page's computer thinks a few simulations a frame.
const GAME_LIMIT: Duration = Duration::from_secs(600);

/// The page's last report of the game (`game over seat=B confirmed=N desyncs=M …`).
fn last_game_line(events: &serde_json::Value) -> String {
    events
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|e| e.as_str())
        .rfind(|e| e.starts_with("game "))
        .unwrap_or_default()
        .to_owned()
}

/// The number after `name=` in a page report.
fn count(line: &str, name: &str) -> Option<u32> {
    line.split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{name}=")))
        .and_then(|n| n.parse().ok())
}

/// A server serving the web client, a native bot that opened a room on it (and plays it
/// once someone joins), and a browser: what every test here starts from. `None`: the
/// machine cannot run the test (the reason was printed).
struct Table {
    runtime: tokio::runtime::Runtime,
    server: TestServer,
    link: WebLink,
    room: RoomCode,
    bot: tokio::task::JoinHandle<Report>,
    browser: Browser,
    _data: tempfile::TempDir,
}

fn open_table(test: &str) -> Result<Option<Table>> {
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => {
            skip_web(test, &why);
            return Ok(None);
        }
    };
    let Some(browser) = browser_or_skip(LaunchOptions::default()) else {
        return Ok(None);
    };
    let runtime = tokio::runtime::Runtime::new()?;
    let data = scratch(test);
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.web_dir = Some(bundle.to_path_buf());
    let server = runtime.block_on(TestServer::start_with(config))?;
    // The native bot opens the room and breaks; pages join it from the link.
    let (opened, code) = tokio::sync::oneshot::channel();
    let bot_config = BotConfig::new(server.invite.clone(), 1);
    let bot = runtime.spawn(async move { open_room(&bot_config, opened).await });
    let room = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(30), code).await })
        .context("the bot opened no room in 30 s")??;
    let Some(link) = server.web_link.clone() else {
        bail!("a server serving the web client has no link");
    };
    Ok(Some(Table {
        runtime,
        server,
        link,
        room,
        bot,
        browser,
        _data: data,
    }))
}

fn whole_game(test: &str, transport: WebTransportChoice) -> Result<()> {
    let Some(table) = open_table(test)? else {
        return Ok(());
    };
    let (runtime, browser) = (&table.runtime, &table.browser);
    let mut link = table.link.with_room(table.room.clone());
    link.computer = Some(Level::new(1));
    link.transport = transport;
    let url = link.to_string();

    let mut page = browser.open(&url, Viewport::desktop(1280, 720))?;
    let finished = page.wait_until(
        "(window.breakshotEvents || []).some(e => e.startsWith('game over'))",
        GAME_LIMIT,
    );
    let events = page.eval("window.breakshotEvents || []")?;
    if let Err(e) = finished {
        bail!(
            "the page never saw the game end: {e}\npage events: {events}\nbrowser: {}",
            browser.log()
        );
    }
    let report = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(60), table.bot).await })
        .context("the bot did not finish after the game ended")??;
    assert!(report.errors.is_empty(), "the bot: {:?}", report.errors);
    assert_eq!(report.games_completed, 1, "the bot saw the game end");
    assert_eq!(report.tally.desyncs, 0, "the bot desynced");
    let line = last_game_line(&events);
    let resolved = report.games[0].resolved.clone();
    assert_eq!(
        count(&line, "desyncs"),
        Some(0),
        "the page desynced: {line}"
    );
    assert_eq!(
        count(&line, "confirmed"),
        Some(resolved.len() as u32),
        "the page confirmed every shot the server resolved: {line}"
    );
    assert!(resolved.len() >= 2, "both sides shot: {resolved:?}");

    // The server's record of the game replays to the same hashes.
    let fetched = runtime.block_on(fetch_record(&table.server.invite, &table.room))?;
    assert!(fetched.finished);
    let record = GameRecord::decode(&fetched.bytes)?;
    record
        .replay()
        .context("the stored record does not verify")?;
    let recorded: Vec<u64> = record.entries.iter().filter_map(|e| e.hash).collect();
    let announced: Vec<u64> = resolved.iter().map(|(_, h)| *h).collect();
    assert_eq!(recorded, announced);
    println!(
        "{test}: {} shots, all confirmed by the page and the bot",
        resolved.len()
    );
    drop(page);

    // The same game watched again in a page: its record fetched from the server.
    let mut replay = link.with_room(table.room.clone());
    replay.replay = true;
    replay.transport = transport;
    let mut page = browser.open(&replay.to_string(), Viewport::desktop(1280, 720))?;
    if let Err(e) = page.wait_until(
        "(window.breakshotEvents || []).includes('screen replay')",
        Duration::from_secs(60),
    ) {
        let events = page.eval("window.breakshotEvents || []")?;
        bail!("the page never showed the replay: {e}\npage events: {events}");
    }
    drop(page);

    runtime.block_on(table.server.stop())?;
    Ok(())
}

#[test]
fn a_page_plays_a_whole_game_against_a_native_bot_over_the_web_socket() -> Result<()> {
    whole_game("web_play_ws", WebTransportChoice::WebSocket)
}

#[test]
fn a_page_plays_a_whole_game_against_a_native_bot_over_web_transport() -> Result<()> {
    whole_game("web_play_wt", WebTransportChoice::WebTransport)
}

/// Pixels of a screenshot near the cue's wood colour.
fn cue_pixels(shot: &Rgba) -> HashSet<(u32, u32)> {
    let wood = breakshot_client::view::palette::CUE_WOOD;
    shot.points(|p| near(p, wood, 12)).into_iter().collect()
}

#[test]
fn a_page_watching_sees_the_players_cue_move_while_they_aim() -> Result<()> {
    let Some(Table {
        runtime,
        server,
        link,
        room,
        browser,
        _data,
        ..
    }) = open_table("web_aim")?
    else {
        return Ok(());
    };
    let mut player_link = link.with_room(room.clone());
    player_link.transport = WebTransportChoice::WebSocket;
    let mut watcher_link = player_link.clone();
    watcher_link.watch = true;

    // The person at the first page plays seat B; the second page watches.
    let mut player = browser.open(&player_link.to_string(), Viewport::desktop(1280, 720))?;
    player.wait_until(
        "(window.breakshotEvents || []).some(e => e.startsWith('game playing seat=B') && e.endsWith('turn=mine'))",
        Duration::from_secs(120),
    )?;
    let mut watcher = browser.open(&watcher_link.to_string(), Viewport::desktop(1280, 720))?;
    watcher.wait_until(
        "(window.breakshotEvents || []).includes('screen game')",
        Duration::from_secs(60),
    )?;
    std::thread::sleep(Duration::from_secs(2));
    let before = cue_pixels(&watcher.screenshot()?);

    // The player moves the mouse across the table, as one lines up a shot.
    for k in 0..=20 {
        let x = 420.0 + 20.0 * k as f64;
        let y = 200.0 + 12.0 * k as f64;
        player.call(
            "Input.dispatchMouseEvent",
            serde_json::json!({ "type": "mouseMoved", "x": x, "y": y }),
        )?;
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_secs(1));
    let after = cue_pixels(&watcher.screenshot()?);
    let changed = before.symmetric_difference(&after).count();
    assert!(
        after.len() > 100,
        "the watcher sees no cue ({} pixels of its wood)",
        after.len()
    );
    assert!(
        changed > 100,
        "the watcher's picture of the cue did not move while the player aimed ({changed} pixels changed)"
    );
    drop(player);
    drop(watcher);
    runtime.block_on(server.stop())?;
    Ok(())
}
