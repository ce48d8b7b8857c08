//! Two strangers in real windows find each other through a server's lobby: each opens *Find
//! a game* from the menu and asks for a quick match; the server seats them in one rated room,
//! and both windows show both players' ratings beside their names from the start; when the
//! server is drained, both are told under the table that their game goes on. The
//! windows run under a virtual display of their own (Xvfb), driven with `xdotool` and
//! photographed with ImageMagick's `import`.
//!
//! Without Xvfb, xdotool or ImageMagick the test says why and passes (CI installs them).
#![cfg(feature = "host")]

use std::process::Command;
use std::time::Duration;

use breakshot_client::net::EmbeddedServer;
use breakshot_client::view::palette::CLOTH;
use breakshot_client::view::{lobby_bar, menu_buttons, Rect};

#[allow(dead_code)]
mod common;
// The two-window tests' display; not every part of it is used here.
#[allow(dead_code, unused_imports)]
#[path = "friends/display.rs"]
mod display;

use common::reported::Reported;
use display::{close, Display};

const BREAKSHOT: &str = env!("CARGO_BIN_EXE_breakshot");

/// The menu's buttons, in order, as `ui/menu.rs` lists them; "Find a game" is the sixth.
const MENU_BUTTONS: usize = 10;
const FIND_A_GAME: usize = 5;

/// The lobby's bar, as `ui/lobby.rs` lists it: quick match first.
const QUICK_MATCH: usize = 0;

const SIZE: (u32, u32) = (1280, 640);

/// Clicks window `wid` in the middle of `r`.
fn click(display: &Display, wid: &str, r: Rect) {
    let (x, y) = (r.x + 0.5 * r.w, r.y + 0.5 * r.h);
    display.xdotool(&["mousemove", "--window", wid, &x.to_string(), &y.to_string()]);
    std::thread::sleep(Duration::from_millis(300));
    display.xdotool(&["click", "1"]);
}

#[test]
fn strangers_meet_through_the_lobby_s_quick_match_and_see_both_ratings_beside_the_names() {
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("lobby-quick-match");
    // Both windows connect from this machine: the server lets one address be paired (a
    // public one does not).
    let mut config = breakshot_server::Config::new(
        std::net::SocketAddr::from(([127, 0, 0, 1], 0)),
        dir.path().join("server"),
    );
    config.limits.match_one_address = true;
    let server = EmbeddedServer::start(config).expect("a server on loopback");
    let (w, h) = SIZE;
    let size = format!("{w}x{h}");
    let limit = Duration::from_secs(60);

    let mut known = Vec::new();
    let mut windows = Vec::new();
    for name in ["ann", "ben"] {
        // The lobby opens on the server remembered from last time.
        let data = dir.path().join(name);
        std::fs::create_dir_all(&data).expect("a data directory");
        breakshot_client::memory::remember_server(&data, &server.loopback_invite())
            .expect("the server remembered");
        // The name played under, remembered as `--name` would (the menu has no such option).
        breakshot_client::memory::player_name(&data, Some(name)).expect("a valid name");
        let mut command = Command::new(BREAKSHOT);
        display
            .on(&mut command)
            .args(["--size", &size, "--data"])
            .arg(&data);
        let window = Reported::start(&mut command);
        let wid = display.new_window(&known);
        known.push(wid.clone());
        // Ben's window under Ann's, so both are seen whole.
        let y = if name == "ben" { h + 10 } else { 0 };
        display.xdotool(&["windowmove", &wid, "0", &y.to_string()]);
        window.wait_for(0, limit, &format!("{name}'s menu"), |l| l == "screen menu");
        std::thread::sleep(Duration::from_millis(500));
        click(
            &display,
            &wid,
            menu_buttons(w as f32, h as f32, MENU_BUTTONS)[FIND_A_GAME],
        );
        window.wait_for(0, limit, &format!("{name}'s lobby"), |l| {
            l == "screen lobby"
        });
        // Connected once the lobby's page has come (an empty one says so).
        std::thread::sleep(Duration::from_secs(2));
        click(&display, &wid, lobby_bar(w as f32, h as f32)[QUICK_MATCH]);
        windows.push((name, window, wid));
    }
    let mut lines = Vec::new();
    for (name, window, _) in &windows {
        window.wait_for(0, limit, &format!("{name} seated by quick match"), |l| {
            l.starts_with("game playing")
        });
        let (_, players) = window.wait_for(0, limit, &format!("{name}'s players"), |l| {
            l.starts_with("players ") && l.contains("1500")
        });
        eprintln!("{name}: {players}");
        lines.push(players);
    }
    // Both new players start at 1500, beside their names, in both windows.
    for (k, line) in lines.iter().enumerate() {
        for (other, seat) in [("ann", "A"), ("ben", "B")] {
            let you = if k == usize::from(other == "ben") {
                " (you)"
            } else {
                ""
            };
            let want = format!("{other} ({seat}) 1500{you}");
            assert!(
                line.contains(&want),
                "{}'s window: no {want:?} in {line:?}",
                windows[k].0
            );
        }
    }
    // And Ben's window shows the table (bare cloth left of the rack, which the lobby's
    // dark page does not have).
    let deadline = std::time::Instant::now() + limit;
    loop {
        let pic = display.grab(&windows[1].2, &dir.path().join("ben.png"));
        assert_eq!((pic.width, pic.height), SIZE);
        if close(pic.at(0.4 * w as f32, 0.25 * h as f32), CLOTH, 12) {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "ben's window never showed the table"
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    // The operator drains the server (as SIGTERM or `POST /drain` would): both players are
    // told under the table that their game goes on but no new one starts here.
    server.stats().start_drain();
    for (name, window, _) in &windows {
        let (_, notice) = window.wait_for(0, limit, &format!("{name} told of the drain"), |l| {
            l.starts_with("chat heard Server: this server is shutting down")
        });
        assert!(
            notice.contains("your game goes on to its end"),
            "{name}: {notice:?}"
        );
    }
    display.grab(&windows[0].2, &dir.path().join("ann-drain.png"));
    if let Ok(keep) = std::env::var("BREAKSHOT_SCREENSHOTS") {
        for png in ["ben.png", "ann-drain.png"] {
            let _ = std::fs::copy(dir.path().join(png), std::path::Path::new(&keep).join(png));
        }
    }
    drop(windows);
    drop(server);
}
