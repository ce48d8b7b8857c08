//! The browser's *Find a game*: a server serving the web client (the real server, in this
//! process, with the bundle `web/build.sh` makes), a native player waiting on it, and a
//! friend who opens the server's link (no room in it) on a phone in headless Chromium, taps
//! *Find a game* on the menu, then *Join* beside the waiting room, or *Quick match*; both end
//! up seated in one game, each with the other's name.
//!
//! Needs the wasm32 target and Chromium; where one is missing the tests say why and pass (CI
//! requires them: `BREAKSHOT_REQUIRE_WEB=1`, `BREAKSHOT_REQUIRE_BROWSER=1`).
#![cfg(feature = "host")]

use std::net::SocketAddr;
use std::time::Duration;

use breakshot_client::net::{Client, EmbeddedServer, Reconnect};
use breakshot_client::view::palette::CLOTH;
use breakshot_client::view::{lobby_bar, lobby_rows, menu_buttons, Rect};
use breakshot_shared::protocol::{ClientMessage, Role, ServerMessage, WebLink};
use breakshot_shared::rules::{EightBallRules, Seat, Settings, Variant};
use breakshot_testkit::browser::{browser_or_skip, near, Browser, LaunchOptions, Page, Viewport};
use breakshot_testkit::web::{bundle, skip_web};
use breakshot_testkit::{scratch, TempDir};

#[allow(dead_code)]
mod common;

use common::page::{
    events, keep_screenshot, tapped_until, wait_for_event, wait_for_input, PATIENCE,
};
use common::{next, opened_room, within};

/// The page's menu when its link names a server but no room, as `ui/menu.rs` lists it:
/// *Find a game* first, then practice, drills, the computer and two players.
const MENU_BUTTONS: usize = 5;
const FIND_A_GAME: usize = 0;

/// The lobby's bar, as `ui/lobby.rs` lists it: quick match first.
const QUICK_MATCH: usize = 0;

/// The friend's name, given by the link.
const FRIEND: &str = "Pia";

/// A server serving the web client, its page's link (no room) naming the friend, and a
/// browser to open it in; `None` where the machine cannot run the test (the reason printed).
struct Served {
    /// The test's name, which its screenshots start with.
    test: &'static str,
    runtime: tokio::runtime::Runtime,
    server: EmbeddedServer,
    link: String,
    browser: Browser,
    _dir: TempDir,
}

fn served(test: &'static str) -> Option<Served> {
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => {
            skip_web(test, &why);
            return None;
        }
    };
    let browser = browser_or_skip(LaunchOptions::default())?;
    let dir = scratch(test);
    let mut config = breakshot_server::Config::new(
        SocketAddr::from(([127, 0, 0, 1], 0)),
        dir.path().join("server"),
    );
    config.web_dir = Some(bundle.to_path_buf());
    // The page and the native player connect from this machine: the server lets one address
    // be paired by quick match (a public one does not).
    config.limits.match_one_address = true;
    let server = EmbeddedServer::start(config).expect("a server on loopback");
    let link = WebLink {
        name: Some(FRIEND.into()),
        ..server.web_link().expect("the page's link").clone()
    };
    Some(Served {
        test,
        runtime: tokio::runtime::Runtime::new().expect("a runtime"),
        server,
        link: link.to_string(),
        browser,
        _dir: dir,
    })
}

/// The middle of `r`, in the page's pixels.
fn middle(r: Rect) -> (f64, f64) {
    let [x, y] = r.center();
    (x as f64, y as f64)
}

/// The page on the server's link, on a phone, with its lobby open from the menu and the
/// lobby's first page shown (`waiting` rooms in it); the phone's size.
fn open_lobby(served: &Served, waiting: usize) -> (Page<'_>, (f32, f32)) {
    let phone = Viewport::phone();
    let size = (phone.width as f32, phone.height as f32);
    let mut page = served
        .browser
        .open(&served.link, phone)
        .expect("the page opens");
    wait_for_event(&mut page, "screen menu", PATIENCE);
    wait_for_input(&mut page);
    keep_screenshot(&mut page, &format!("{}-menu.png", served.test));
    let find = menu_buttons(size.0, size.1, MENU_BUTTONS)[FIND_A_GAME];
    tapped_until(&mut page, middle(find), "screen lobby");
    wait_for_event(
        &mut page,
        &format!("lobby page 1 of 1: waiting={waiting}"),
        PATIENCE,
    );
    // A frame or two to draw the page just come.
    std::thread::sleep(Duration::from_millis(300));
    keep_screenshot(&mut page, &format!("{}.png", served.test));
    (page, size)
}

/// Waits until the page plays in seat `seat` of a game it shares with `other`, and shows its
/// table: the page's players line names both (that line is returned), and the cloth covers
/// much of the screen.
fn seated_with(served: &Served, page: &mut Page<'_>, seat: Seat, other: &str) -> String {
    wait_for_event(page, &format!("game playing seat={seat:?}"), PATIENCE);
    wait_for_event(page, "players ", PATIENCE);
    let said = events(page);
    assert!(said.contains("connection=Connected"), "{said}");
    let players: Vec<String> = serde_json::from_str(&said).expect("the page's events");
    let line = players
        .iter()
        .rfind(|e| e.starts_with("players "))
        .expect("a players line");
    assert!(
        line.contains(other) && line.contains(FRIEND),
        "the page's players are not {other} and {FRIEND}: {line:?}"
    );
    std::thread::sleep(Duration::from_millis(500));
    let shot = page.screenshot().expect("a screenshot");
    keep_screenshot(page, &format!("{}-game.png", served.test));
    let cloth = shot.points(|p| near(p, CLOTH, 8)).len();
    let area = (shot.width * shot.height) as usize;
    assert!(
        cloth * 4 > area,
        "no table: the cloth covers only {cloth} of {area} pixels"
    );
    line.clone()
}

/// Waits until the native player `client` is told that the friend took `seat`.
fn told_of_the_friend(served: &Served, client: &mut Client, seat: Seat) {
    let joined = within(&served.runtime, "the native player told of the friend", {
        next(client, |m| matches!(m, ServerMessage::PlayerJoined { .. }))
    });
    let want = ServerMessage::PlayerJoined {
        seat,
        name: FRIEND.into(),
    };
    assert_eq!(joined, want);
}

#[test]
fn a_page_on_the_servers_link_finds_a_public_room_in_the_lobby_and_joins_it_with_one_tap() {
    let Some(served) = served("web-lobby-join") else {
        return;
    };
    // Rosa opens a room and lists it in the lobby.
    let invite = served.server.loopback_invite();
    let (mut rosa, _) = within(&served.runtime, "Rosa's room", opened_room(&invite, "Rosa"));
    within(&served.runtime, "Rosa's room listed", async {
        rosa.send(&ClientMessage::Publish).await.expect("sent");
        next(&mut rosa, |m| matches!(m, ServerMessage::Published { .. })).await
    });

    let (mut page, (w, h)) = open_lobby(&served, 1);
    let (join, _) = lobby_rows(w, h, 1, 0);
    tapped_until(&mut page, middle(join[0]), "screen game");
    seated_with(&served, &mut page, Seat::B, "Rosa");
    // And Rosa is told her room's other seat is the friend's.
    told_of_the_friend(&served, &mut rosa, Seat::B);
}

#[test]
fn a_page_on_the_servers_link_is_paired_by_the_lobbys_quick_match_with_a_native_player() {
    let Some(served) = served("web-lobby-quick") else {
        return;
    };
    // Quinn waits in the 8-ball queue the lobby's quick match asks for.
    let invite = served.server.loopback_invite();
    let mut quinn = within(&served.runtime, "Quinn queued", async {
        let mut quinn = Client::connect(invite, Reconnect::never())
            .await
            .expect("connected");
        let ask = ClientMessage::QuickMatch {
            variant: Variant::EightBall(EightBallRules::Wpa),
            mode: Settings::online(),
            name: "Quinn".into(),
        };
        quinn.send(&ask).await.expect("sent");
        next(&mut quinn, |m| matches!(m, ServerMessage::Queued { .. })).await;
        quinn
    });

    let (mut page, (w, h)) = open_lobby(&served, 0);
    let quick = lobby_bar(w, h)[QUICK_MATCH];
    // Tapped until the page queues (a tap after that would leave the queue).
    tapped_until(&mut page, middle(quick), "lobby queued");
    wait_for_event(&mut page, "screen game", PATIENCE);
    let joined = within(&served.runtime, "Quinn seated", {
        next(&mut quinn, |m| matches!(m, ServerMessage::Joined { .. }))
    });
    let ServerMessage::Joined { role, snapshot, .. } = joined else {
        unreachable!("matched above")
    };
    let seat = match role {
        Role::Player(seat) => seat,
        other => panic!("Quinn is not seated: {other:?}"),
    };
    // The friend is in the other seat: already in the room's picture, or announced.
    let theirs = seat.other();
    let seated = snapshot.seats[theirs.index()].as_ref();
    if seated.map(|s| s.name.as_str()) != Some(FRIEND) {
        told_of_the_friend(&served, &mut quinn, theirs);
    }
    // A quick match is rated: both new players' ratings come (after the room) and stand
    // beside their names.
    let rated = "(window.breakshotEvents || [])\
        .some(e => e.startsWith('players ') && e.split(' 1500').length == 3)";
    if let Err(e) = page.wait_until(rated, PATIENCE) {
        panic!("no ratings beside the names: {e}\n{}", events(&mut page));
    }
    let players = seated_with(&served, &mut page, theirs, "Quinn");
    assert!(
        players.contains("Quinn (") && players.matches(" 1500").count() == 2,
        "{players}"
    );
}
