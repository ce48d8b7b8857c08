//! Two friends in real windows: the computer's thinking said off the cloth in a small window,
//! an earlier game of a room watched from the menu, and the opponent's aim seen moving in the
//! other player's window, top-down and in 3-D, whoever aims. The windows run under a virtual
//! display of their own (Xvfb), driven with `xdotool` and photographed with ImageMagick's
//! `import`.
//!
//! Without Xvfb, xdotool or ImageMagick each test says why and passes (CI installs them).
#![cfg(feature = "host")]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use breakshot_client::view::palette::{CLOTH, CUE_WOOD};
use breakshot_client::view::{area, menu_buttons, replay_page, Frame, Layout, Rect};
use breakshot_shared::protocol::{ClientMessage, Invite, RoomCode, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Game, Settings};
use breakshot_testkit::Spawned;

#[allow(dead_code)]
mod common;
#[path = "friends/display.rs"]
mod display;

use common::screen::eight_ball;
use common::{next, within};
use display::{balls_not_seen, close, Display, Picture};

const BREAKSHOT: &str = env!("CARGO_BIN_EXE_breakshot");
/// How long a window is given to show or say what a test waits for, on a loaded machine.
const PATIENCE: Duration = Duration::from_secs(60);

/// The menu's buttons, in order, as `ui/menu.rs` lists them; "Watch a replay" is the one
/// before "Quit".
const MENU_BUTTONS: usize = 10;
const WATCH_A_REPLAY: usize = MENU_BUTTONS - 2;

fn middle(r: &Rect) -> (f32, f32) {
    (r.x + 0.5 * r.w, r.y + 0.5 * r.h)
}

/// Clicks window `wid` at (`x`, `y`) of its own.
fn click(display: &Display, wid: &str, (x, y): (f32, f32)) {
    let (x, y) = (x.round().to_string(), y.round().to_string());
    display.xdotool(&["mousemove", "--window", wid, &x, &y]);
    std::thread::sleep(Duration::from_millis(300));
    display.xdotool(&["click", "1"]);
}

/// Grabs `wid` every half second until `ready` holds of its picture; fails the test after
/// `limit`, naming `what`.
fn until_shown(
    display: &Display,
    wid: &str,
    out: &Path,
    limit: Duration,
    what: &str,
    ready: impl Fn(&Picture) -> bool,
) -> Picture {
    until_shown_telling(display, wid, out, limit, what, ready, String::new)
}

/// As [`until_shown`], adding `context()` (what the window reported, say) to the failure.
fn until_shown_telling(
    display: &Display,
    wid: &str,
    out: &Path,
    limit: Duration,
    what: &str,
    ready: impl Fn(&Picture) -> bool,
    context: impl Fn() -> String,
) -> Picture {
    let deadline = Instant::now() + limit;
    loop {
        let pic = display.grab(wid, out);
        if ready(&pic) {
            return pic;
        }
        assert!(
            Instant::now() < deadline,
            "{what}: not shown within {limit:?}{}",
            context()
        );
        std::thread::sleep(Duration::from_millis(500));
    }
}

/// While the computer thinks in a 640x480 window, the words say so under the trays and the
/// rack stays in view: every ball in its colour, the cloth between the middle and the rack
/// bare (the box that said it lay over both).
#[test]
fn in_a_small_window_the_computer_thinks_under_the_trays_and_the_rack_stays_in_view() {
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("friends-thinking");
    let out = dir.path().join("thinking.png");
    let run = breakshot_testkit::run(
        display
            .on(&mut Command::new(BREAKSHOT))
            .env("BREAKSHOT_DATA", dir.path().join("data"))
            .args(["vs-computer", "--level", "1", "--break", "computer"])
            .args(["--seed", "4", "--size", "640x480", "--frames", "10"])
            .arg("--screenshot")
            .arg(&out),
        None,
        Duration::from_secs(120),
    );
    common::screen::assert_ran(&run);
    let pic = Picture::load(&out);
    assert_eq!((pic.width, pic.height), (640, 480));
    let rack = eight_ball(Settings::offline(), 4);
    let layout = Layout::new(640.0, 480.0, Frame::new(rack.table(), rack.balls()));
    let ids = rack.ball_ids();
    let hidden = balls_not_seen(&pic, &layout, &ids, rack.balls());
    assert!(hidden.is_empty(), "balls covered: {hidden:?}");
    // The cloth from its middle to the rack's apex (its ball nearest the middle), clear of
    // the balls: bare.
    let apex = rack.balls()[1..]
        .iter()
        .map(|b| layout.to_screen(b.pos))
        .min_by(|a, b| a[0].total_cmp(&b[0]))
        .expect("a rack");
    let c = layout.cloth;
    let centre = [c.x + 0.5 * c.w, c.y + 0.5 * c.h];
    let r = layout.px(rack.params().ball_radius);
    for k in 0..=20 {
        let t = k as f32 / 20.0;
        let p = [
            centre[0] + t * (apex[0] - 2.0 * r - centre[0]),
            centre[1] + t * (apex[1] - centre[1]),
        ];
        let got = pic.at(p[0], p[1]);
        assert!(close(got, CLOTH, 8), "covered cloth at {p:?}: {got:?}");
    }
    // The words, white, on the notice line under the trays.
    let n = layout.notice;
    let white = (0..n.w as u32)
        .flat_map(|x| (0..n.h as u32).map(move |y| (x, y)))
        .filter(|&(x, y)| {
            pic.at(n.x + x as f32, n.y + y as f32)
                .iter()
                .all(|&v| v > 200)
        })
        .count();
    assert!(white > 40, "{white} white points: no thinking line");
}

/// Alice and Bob play two games in one room on the server of `invite`: the first ends at
/// once (Alice concedes), then both ask for a rematch. The room and the two games' seeds.
async fn two_games(invite: &Invite) -> (RoomCode, [u64; 2]) {
    let (mut alice, snapshot) = common::opened_room(invite, "alice").await;
    let room = snapshot.room.clone();
    let (mut bob, snapshot) = common::joined_room(invite, &room, "bob").await;
    let first = snapshot.game.seed();
    alice.send(&ClientMessage::Concede).await.expect("sent");
    for p in [&mut alice, &mut bob] {
        next(p, |m| matches!(m, ServerMessage::GameOver { .. })).await;
    }
    for p in [&mut alice, &mut bob] {
        p.send(&ClientMessage::Rematch).await.expect("sent");
    }
    let ServerMessage::GameStarted { snapshot } = next(&mut alice, |m| {
        matches!(m, ServerMessage::GameStarted { .. })
    })
    .await
    else {
        unreachable!("matched above")
    };
    assert_eq!(snapshot.game_number, 2);
    (room, [first, snapshot.game.seed()])
}

/// After a rematch, the menu's *Watch a replay* lists the room's games from its invite, and
/// *Game 1* opens the first game: its rack, not the second's.
#[test]
fn the_menu_lists_a_room_s_games_and_opens_the_first_after_a_rematch() {
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("friends-replays");
    let server = common::loopback_server(dir.path().join("server"));
    let invite = server.loopback_invite();
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let (room, seeds) = within(&runtime, "two games", two_games(&invite));
    assert_ne!(seeds[0], seeds[1], "the rematch has a rack of its own");

    let _window = Spawned::start(
        display
            .on(&mut Command::new(BREAKSHOT))
            .args(["--size", "1280x720", "--data"])
            .arg(dir.path().join("client"))
            .stdout(Stdio::null())
            .stderr(Stdio::null()),
    );
    let wid = display.new_window(&[]);
    std::thread::sleep(Duration::from_secs(1));
    let buttons = menu_buttons(1280.0, 720.0, MENU_BUTTONS);
    click(&display, &wid, middle(&buttons[WATCH_A_REPLAY]));
    // The game's invite typed on the page's line, then its games listed.
    std::thread::sleep(Duration::from_secs(1));
    let text = invite.with_room(room.clone()).to_string();
    display.xdotool(&["type", "--delay", "20", &text]);
    let page = replay_page(1280.0, 720.0, 2);
    click(&display, &wid, middle(&page.list));
    let out = dir.path().join("page.png");
    // Two game buttons appear where the page puts them.
    let button_fill = |p: &Picture, r: &Rect| close(p.at(r.x + 4.0, r.y + 4.0), [24, 104, 74], 30);
    until_shown(
        &display,
        &wid,
        &out,
        Duration::from_secs(30),
        "the games",
        |p| page.games.iter().all(|r| button_fill(p, r)),
    );
    assert_eq!(page.games.len(), 2);
    click(&display, &wid, middle(&page.games[0]));

    // Game 1's rack: its balls where its seed racked them.
    let first = GameRecord::decode(
        &breakshot_client::net::fetch_game_blocking(&invite, &room, Some(1))
            .expect("game 1")
            .bytes,
    )
    .expect("a record");
    assert_eq!(first.seed, seeds[0]);
    let rack = Game::new(first.variant, first.settings, first.seed);
    let second = Game::new(first.variant, first.settings, seeds[1]);
    let layout = Layout::new(1280.0, 720.0, Frame::new(rack.table(), rack.balls()));
    let ids = rack.ball_ids();
    let shown = until_shown(
        &display,
        &wid,
        &out,
        Duration::from_secs(30),
        "game 1",
        |p| balls_not_seen(p, &layout, &ids, rack.balls()).is_empty(),
    );
    // Not the second game's rack (which puts some balls elsewhere).
    let not_second = balls_not_seen(&shown, &layout, &ids, second.balls());
    assert!(!not_second.is_empty(), "the two racks look the same");
    drop(server);
}

/// Points of `r` where `after` differs from `before` (the two windows' layouts are the same).
fn changed_in(before: &Picture, after: &Picture, r: Rect) -> usize {
    (0..r.w as u32)
        .flat_map(|x| (0..r.h as u32).map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let (x, y) = (r.x + x as f32, r.y + y as f32);
            !close(before.at(x, y), after.at(x, y), 40)
        })
        .count()
}

/// Where to click the first of the choice buttons `pic` shows over the trays, if any: inside
/// the leftmost stretch of their fill (`ui/game.rs` draws them in a row there) on the
/// tray's rows, wider than any ball that lies in a tray.
fn first_choice(pic: &Picture, layout: &Layout) -> Option<(f32, f32)> {
    const FILL: [u8; 3] = [30, 60, 120];
    let t = layout.tray;
    let run = 3.0 * layout.px(breakshot_shared::physics::Params::default().ball_radius);
    (0..t.h as u32)
        .map(|y| t.y + y as f32)
        .filter_map(|y| {
            let mut from = None;
            for x in (0..t.w as u32).map(|x| t.x + x as f32) {
                if close(pic.at(x, y), FILL, 25) {
                    let start = *from.get_or_insert(x);
                    if x - start >= run {
                        return Some((start, y));
                    }
                } else {
                    from = None;
                }
            }
            None
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(x, y)| (x + 0.5 * run, y))
}

/// Ann hosts and Ben joins, each in a real window. As Ann moves the mouse over the table,
/// Ben's window shows her cue turn with it, top-down and then in the 3-D view (V); Ann then
/// shoots until Ben is to aim, and his cue turns in her window as he aims.
#[test]
fn the_opponent_s_cue_moves_in_the_other_window_in_both_views_as_either_player_aims() {
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("friends-aim");
    let size = ["--size", "640x480"];
    let mut host = Spawned::start(
        display
            .on(&mut Command::new(BREAKSHOT))
            .args(["host", "--bind", "127.0.0.1:0", "--name", "ann"])
            .args(size)
            .arg("--data")
            .arg(dir.path().join("ann"))
            .stdout(Stdio::piped())
            .stderr(Stdio::null()),
    );
    let stdout = host.child().stdout.take().expect("the host's output");
    let (line, _rest) = breakshot_testkit::read_line(stdout, PATIENCE);
    let invite: Invite = line.trim().parse().expect("the invite is the first line");
    let ann = display.new_window(&[]);
    let join = Spawned::start(
        display
            .on(&mut Command::new(BREAKSHOT))
            .args(["join", &invite.to_string(), "--name", "ben"])
            .args(size)
            .arg("--data")
            .arg(dir.path().join("ben"))
            .stdout(Stdio::null())
            .stderr(Stdio::null()),
    );
    let windows = [ann.clone(), display.new_window(&[ann])];
    display.xdotool(&["windowmove", &windows[1], "650", "0"]);
    const NAMES: [&str; 2] = ["ann", "ben"];

    // Both show the racked table (the host's invite panel has gone: Ben is seated), on
    // cloth off the line the player to move aims along.
    let rack = eight_ball(Settings::online(), 0);
    let layout = Layout::new(640.0, 480.0, Frame::new(rack.table(), rack.balls()));
    let c = layout.cloth;
    let pictures = [dir.path().join("ann.png"), dir.path().join("ben.png")];
    for (wid, out) in windows.iter().zip(&pictures) {
        until_shown(&display, wid, out, PATIENCE, "the table", |p| {
            close(p.at(c.x + 0.5 * c.w, c.y + 0.25 * c.h), CLOTH, 8)
        });
    }
    let grab = |k: usize| display.grab(&windows[k], &pictures[k]);
    let point = |k: usize, (x, y): (f32, f32)| {
        display.xdotool(&[
            "mousemove",
            "--window",
            &windows[k],
            &x.to_string(),
            &y.to_string(),
        ]);
    };
    // Aims are shared every 0.1 s; a loaded machine draws a frame in about that.
    let settle = || std::thread::sleep(Duration::from_secs(2));
    let aim_at = |k: usize, (fx, fy): (f32, f32)| {
        point(k, (c.x + fx * c.w, c.y + fy * c.h));
        settle();
    };
    // A key for window `k` (the display has no window manager: keys go to the window under
    // the pointer), pressed with the pointer on its bar, off the table.
    let press = |k: usize, key: &str| {
        point(k, (c.x + 0.5 * c.w, 0.5 * layout.hud.h));
        std::thread::sleep(Duration::from_millis(300));
        display.xdotool(&["key", key]);
        settle();
    };
    // Who is to move, from either window's bar (Ann's line first in both): the line of the
    // player to move is yellow.
    let to_move = |p: &Picture| {
        let yellow = |r: &Rect| {
            (0..r.w as u32).any(|x| {
                let q = p.at(r.x + x as f32, r.y + 0.5 * r.h);
                q[0] > 200 && q[1] > 200 && q[2] < 80
            })
        };
        usize::from(!yellow(&layout.players[0]))
    };
    // The table with its rails: wherever the cue ball lies, the cue behind it is over them.
    let t = layout.outer;
    let cue_points = |p: &Picture| {
        (0..t.w as u32)
            .flat_map(|x| (0..t.h as u32).map(move |y| (x, y)))
            .filter(|&(x, y)| close(p.at(t.x + x as f32, t.y + y as f32), CUE_WOOD, 30))
            .count()
    };
    // `mover` aims at the cloth's top left corner, then at its bottom right one (from
    // anywhere on the cloth the two are at least a right angle apart); the other's window
    // as it was after each.
    let watch = |mover: usize| {
        let watcher = 1 - mover;
        aim_at(mover, (0.1, 0.1));
        let before = grab(watcher);
        aim_at(mover, (0.9, 0.9));
        let after = grab(watcher);
        assert_eq!(
            to_move(&grab(0)),
            mover,
            "the turn left {} while they aimed",
            NAMES[mover]
        );
        (before, after)
    };
    let top_down_cue_moved = |mover: usize| {
        let (before, after) = watch(mover);
        let seen = (
            cue_points(&before),
            cue_points(&after),
            changed_in(&before, &after, t),
        );
        eprintln!(
            "{} aims, top-down (cue points before, after, table points changed): {seen:?}",
            NAMES[mover]
        );
        assert!(
            seen.0 > 20 && seen.1 > 20,
            "{}'s cue is not drawn in the other window: {seen:?}",
            NAMES[mover]
        );
        assert!(
            seen.2 > 100,
            "{}'s cue did not move in the other window: {seen:?}",
            NAMES[mover]
        );
    };

    assert_eq!(to_move(&grab(0)), 0, "the host breaks");
    top_down_cue_moved(0);

    // Ben turns to the 3-D view: the table region is drawn anew. There Ann's cue is lit and
    // seen in perspective, so its moving is counted as points changed over the table
    // region, while nothing else there moves.
    let table = area(&layout);
    let flat = grab(1);
    press(1, "v");
    let tilted = grab(1);
    let redrawn = changed_in(&flat, &tilted, table);
    eprintln!("3-D view: {redrawn} of the table region's points redrawn");
    assert!(
        redrawn as f32 > 0.3 * table.w * table.h,
        "V did not turn Ben's window to the 3-D view ({redrawn} points changed)"
    );
    let still = changed_in(&tilted, &grab(1), table);
    let (before, after) = watch(0);
    let moved = changed_in(&before, &after, table);
    eprintln!("ann aims, 3-D: {moved} table points changed ({still} with nothing moving)");
    assert!(
        moved > 100 && moved > 10 * still,
        "Ann's cue did not move in Ben's 3-D view: {moved} points changed, {still} at rest"
    );

    // Ben goes back to top-down: he aims, or picks a choice, with the mouse over the
    // layout's table and its tray row.
    press(1, "v");
    // Ann shoots at the rack until Ben is to aim: a ball potted keeps her at the table, and
    // an illegal break (the window's first power is soft) leaves him to choose how play
    // goes on; he takes the first choice.
    let mut turns = Vec::new();
    loop {
        let mover = to_move(&grab(0));
        // Ben's window may end the shot a little later: his choices are read once it too
        // gives him the turn.
        let choice = (mover == 1)
            .then(|| {
                let ben = until_shown(
                    &display,
                    &windows[1],
                    &pictures[1],
                    Duration::from_secs(20),
                    "Ben's turn in his window",
                    |p| to_move(p) == 1,
                );
                first_choice(&ben, &layout)
            })
            .flatten();
        if mover == 1 && choice.is_none() {
            break;
        }
        assert!(
            turns.len() < 4,
            "Ben was not left to aim after Ann's shots and his choices: {turns:?}"
        );
        if let Some(button) = choice {
            turns.push("Ben chose");
            click(&display, &windows[1], button);
            settle();
            continue;
        }
        turns.push("Ann shot");
        point(0, (c.x + 0.75 * c.w, c.y + 0.5 * c.h));
        std::thread::sleep(Duration::from_secs(1));
        display.xdotool(&["key", "space"]);
        std::thread::sleep(Duration::from_secs(1));
        // The shot is over when the turn passes or the cloth is still.
        let deadline = Instant::now() + Duration::from_secs(40);
        let mut last = grab(0);
        loop {
            std::thread::sleep(Duration::from_millis(500));
            let now = grab(0);
            if to_move(&now) == 1 || changed_in(&last, &now, c) < 5 {
                break;
            }
            assert!(Instant::now() < deadline, "Ann's shot did not end in 40 s");
            last = now;
        }
    }
    eprintln!("Ben is to aim after: {turns:?}");
    top_down_cue_moved(1);
    drop((join, host));
}

/// The hint bar's lit columns of `pic`: how far right its text reaches (pixels from its left).
fn hint_reach(pic: &Picture, layout: &Layout) -> f32 {
    let f = layout.footer;
    (0..f.w as u32)
        .rev()
        .find(|&x| {
            (0..f.h as u32).any(|y| {
                pic.at(f.x + x as f32, f.y + y as f32)
                    .iter()
                    .all(|&v| v > 150)
            })
        })
        .map_or(0.0, |x| x as f32)
}

/// Ann hosts in a window and breaks against Bob; her window's process is stopped and started
/// again on the same data: it shows the game as it stood, saying "Game resumed" on the hint
/// bar (a short line where a new game lists the keys). At each of the three window sizes.
#[test]
fn a_host_restarted_on_its_data_says_game_resumed_in_a_small_window() {
    game_resumed_in_a_window_of(SIZES[0]);
}

#[test]
fn a_host_restarted_on_its_data_says_game_resumed() {
    game_resumed_in_a_window_of(SIZES[1]);
}

#[test]
fn a_host_restarted_on_its_data_says_game_resumed_in_a_tall_window() {
    game_resumed_in_a_window_of(SIZES[2]);
}

fn game_resumed_in_a_window_of((w, h): (u32, u32)) {
    let Some(display) = Display::start() else {
        return;
    };
    let size = format!("{w}x{h}");
    let dir = breakshot_testkit::scratch("friends-resumed");
    let data = dir.path().join("ann");
    // Each host window says what it shows on its standard error (`BREAKSHOT_REPORT`).
    let host = |bind: &str| {
        let mut host = Spawned::start(
            display
                .on(&mut Command::new(BREAKSHOT))
                .args(["host", "--bind", bind, "--name", "ann", "--size", &size])
                .arg("--data")
                .arg(&data)
                .env("BREAKSHOT_REPORT", "1")
                .stdout(Stdio::piped())
                .stderr(Stdio::piped()),
        );
        let stdout = host.child().stdout.take().expect("the host's output");
        let stderr = host.child().stderr.take().expect("the host's reports");
        let (line, rest) = breakshot_testkit::read_line(stdout, PATIENCE);
        let invite: Invite = line.trim().parse().expect("the invite is the first line");
        // The rest of the output is read, so the host never blocks on a full pipe.
        std::thread::spawn(move || std::io::copy(&mut { rest }, &mut std::io::sink()));
        let said = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let heard = said.clone();
        std::thread::spawn(move || {
            use std::io::BufRead;
            for line in std::io::BufReader::new(stderr)
                .lines()
                .map_while(Result::ok)
            {
                heard.lock().expect("the reports").push(line);
            }
        });
        (host, invite, said)
    };
    let (first, invite, _) = host("127.0.0.1:0");
    let wid = display.new_window(&[]);
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let mut bob = within(&runtime, "Bob's seat", async {
        let room = invite.room.clone().expect("the invite's room");
        common::joined_room(&invite, &room, "bob").await.0
    });
    let rack = eight_ball(Settings::online(), 0);
    let layout = Layout::new(w as f32, h as f32, Frame::new(rack.table(), rack.balls()));
    // Bare cloth, a quarter of the width from the line from the cue ball to the rack's apex,
    // halfway along it (in a tall window the table is turned).
    let (cue, apex) = (rack.balls()[0].pos, rack.balls()[1].pos);
    let (width, _) = rack.table().size().expect("a pool table");
    let across = (apex - cue).perp().normalize() * 0.25 * width;
    let bare = layout.to_screen(0.5 * (cue + apex) + across);
    let cloth_shown = |p: &Picture| close(p.at(bare[0], bare[1]), CLOTH, 8);
    let out = dir.path().join("ann.png");
    let new_game = until_shown(&display, &wid, &out, PATIENCE, "the table", cloth_shown);
    // A new game lists the keys across the bar.
    let keys = hint_reach(&new_game, &layout);
    assert!(
        keys > 0.45 * layout.footer.w,
        "{size}: the keys reach {keys} px of {}",
        layout.footer.w
    );

    // Ann, who breaks, aims at the rack and shoots with Space; Bob sees the shot end.
    let [x, y] = layout.to_screen(apex);
    display.xdotool(&[
        "mousemove",
        "--window",
        &wid,
        &x.to_string(),
        &y.to_string(),
    ]);
    std::thread::sleep(Duration::from_secs(1));
    display.xdotool(&["key", "space"]);
    within(&runtime, "the break", async {
        next(&mut bob, |m| {
            matches!(m, ServerMessage::ShotResolved { .. })
        })
        .await;
    });

    // Her window is closed (SIGTERM, as a Ctrl-C) and opened again on the same data and port.
    first.terminate();
    let mut first = first;
    assert!(
        first.wait(Duration::from_secs(30)).success(),
        "the host ended"
    );
    drop(bob);
    let bind = format!("127.0.0.1:{}", invite.first().port);
    let (_again, _, said) = host(&bind);
    let wid = display.new_window(&[]);
    let out = dir.path().join("again.png");
    let reports = || {
        let said = said.lock().expect("the reports");
        format!("; the restarted host said: {said:?}")
    };
    let resumed = until_shown_telling(
        &display,
        &wid,
        &out,
        PATIENCE,
        "the game",
        |p| {
            // The table, and a short line where the keys were.
            cloth_shown(p) && {
                let reach = hint_reach(p, &layout);
                reach > 20.0 && reach < keys / 3.0
            }
        },
        reports,
    );
    let reach = hint_reach(&resumed, &layout);
    eprintln!(
        "{size}: hint bar text reaches {keys} px in a new game, {reach} px after the restart"
    );
    if (w, h) == (1280, 720) {
        // "Game resumed": 12 letters of 6 to 10 px at the bar's size (the keys' are about
        // 8.4 px).
        assert!(
            (72.0..120.0).contains(&reach),
            "{reach} px: not a line of 12 letters"
        );
    }
    let ids = rack.ball_ids();
    let racked = balls_not_seen(&resumed, &layout, &ids, rack.balls());
    assert!(
        racked.len() > 3,
        "{size}: the break was not kept: {racked:?} moved"
    );
    // And the line it shows is the one it says: "Game resumed".
    let said = said.lock().expect("the reports").clone();
    assert!(
        said.iter().any(|l| l == "report: message Game resumed"),
        "the restarted host did not say Game resumed: {said:?}"
    );
}

/// The three window sizes the layout is made for: small, common and tall.
const SIZES: [(u32, u32); 3] = [(640, 480), (1280, 720), (720, 1280)];

/// Ann hosts and Ben joins, each in a real window of `size`, reporting what it shows; once
/// both are seated. The windows are told apart by the order they open.
fn ann_and_ben(
    display: &Display,
    dir: &Path,
    (w, h): (u32, u32),
) -> [(common::reported::Reported, String); 2] {
    use common::reported::Reported;
    let size = format!("{w}x{h}");
    let window = |name: &str, sub: &[&str]| {
        let mut command = Command::new(BREAKSHOT);
        display
            .on(&mut command)
            .args(sub)
            .args(["--name", name, "--size", &size, "--data"])
            .arg(dir.join(name));
        command
    };
    let (ann, invite) = Reported::host(&mut window("ann", &["host", "--bind", "127.0.0.1:0"]));
    let ann_wid = display.new_window(&[]);
    let ben = Reported::start(&mut window("ben", &["join", &invite.to_string()]));
    let ben_wid = display.new_window(std::slice::from_ref(&ann_wid));
    // Beside Ann's window, or under it, so hers is seen whole (ImageMagick grabs what the
    // screen shows).
    let (x, y) = if w <= 640 {
        (w + 10, 0)
    } else if h <= 720 {
        (0, h)
    } else {
        (w, 0)
    };
    display.xdotool(&["windowmove", &ben_wid, &x.to_string(), &y.to_string()]);
    for (who, window) in [("ann", &ann), ("ben", &ben)] {
        window.wait_for(0, PATIENCE, &format!("{who} seated"), |l| {
            l.starts_with("game playing")
        });
    }
    [(ann, ann_wid), (ben, ben_wid)]
}

/// Presses `keys` in window `wid`, one after the other. A chord ("ctrl+v") is pressed as a
/// keyboard does (XTEST, to the window under the pointer): sent to a window instead, its
/// Control reaches the window as no key held and its V as the letter typed.
fn keys(display: &Display, wid: &str, keys: &[&str]) {
    for key in keys {
        std::thread::sleep(Duration::from_millis(300));
        if key.contains('+') {
            display.xdotool(&["mousemove", "--window", wid, "20", "20"]);
            std::thread::sleep(Duration::from_millis(200));
            let (held, key) = key.split_once('+').expect("a chord");
            display.xdotool(&["keydown", held]);
            std::thread::sleep(Duration::from_millis(200));
            display.xdotool(&["key", key]);
            std::thread::sleep(Duration::from_millis(200));
            display.xdotool(&["keyup", held]);
        } else {
            display.xdotool(&["key", "--window", wid, key]);
        }
    }
}

/// The points of `r` in `pic` lit grey, well above the dark box (small letters are mostly
/// edges blended with the box, so their cores alone are too few to count on).
fn grey_in(pic: &Picture, r: Rect) -> usize {
    (0..r.w as u32)
        .flat_map(|x| (0..r.h as u32).map(move |y| (x, y)))
        .map(|(x, y)| pic.at(r.x + x as f32, r.y + y as f32))
        .filter(|p| {
            let (lo, hi) = (p.iter().min(), p.iter().max());
            matches!((lo, hi), (Some(&lo), Some(&hi)) if lo > 80 && hi - lo < 25)
        })
        .count()
}

/// The size, in pixels, of the largest font at which `line` fits `r` in a window `height`
/// high, at most `max` (as `ui/draw.rs` fits a line to its box).
fn fitting_px(line: &str, r: Rect, max: f32, height: f32) -> f32 {
    use breakshot_client::view::text;
    let scale = text::scale(height);
    let size = max.min(r.h / scale);
    let wide = text::width(line, size, height);
    size.min(size * r.w / wide.max(1.0)) * scale
}

/// After a game ends (Ann concedes), R in Ann's window says whom the rematch waits for, in
/// words that fit the line under the result; Ben's R then starts the next game in both
/// windows. At each of the three window sizes; the turn lines and verdicts both windows
/// showed name the players.
#[test]
fn a_rematch_asked_for_says_whom_it_waits_for_until_the_other_accepts_naming_both() {
    let Some(display) = Display::start() else {
        return;
    };
    for (w, h) in SIZES {
        let dir = breakshot_testkit::scratch("friends-rematch");
        let [(ann, ann_wid), (ben, ben_wid)] = ann_and_ben(&display, dir.path(), (w, h));
        let limit = Duration::from_secs(30);
        // Escape asks whether to leave; C concedes, once the question is up (a loaded
        // machine may take a while to draw the frame that asks it).
        keys(&display, &ann_wid, &["Escape"]);
        std::thread::sleep(Duration::from_millis(1500));
        keys(&display, &ann_wid, &["c"]);
        let mut over = [0; 2];
        for (k, (who, window)) in [("ann", &ann), ("ben", &ben)].into_iter().enumerate() {
            over[k] = window
                .wait_for(0, limit, &format!("{w}x{h}: {who}'s game over"), |l| {
                    l.starts_with("game over")
                })
                .0;
        }
        keys(&display, &ann_wid, &["r"]);
        let (_, line) = ann.wait_for(over[0], limit, "the rematch asked", |l| {
            l.starts_with("after the game Rematch")
        });
        let line = line.strip_prefix("after the game ").expect("matched above");
        assert_eq!(
            line, "Rematch asked: waiting for ben to accept  -  Esc: menu",
            "{w}x{h}"
        );
        let rack = eight_ball(Settings::online(), 0);
        let layout = Layout::new(w as f32, h as f32, Frame::new(rack.table(), rack.balls()));
        let row = layout.banner_rows()[2];
        // Drawn at 20 (`ui/game.rs`), shrunk to fit the row if need be: still readable.
        let px = fitting_px(line, row, 20.0, h as f32);
        eprintln!("{w}x{h}: the rematch line fits {row:?} at {px:.1} px");
        assert!(
            px >= 12.0,
            "{w}x{h}: the rematch line fits only at {px:.1} px"
        );
        // And the window draws its line there: light grey letters in the row (her window
        // raised, in case Ben's still lies over it: ImageMagick grabs what the screen shows).
        display.xdotool(&["windowraise", &ann_wid]);
        let pic = until_shown(
            &display,
            &ann_wid,
            &dir.path().join("asked.png"),
            limit,
            &format!("{w}x{h}: the rematch line"),
            |p| grey_in(p, row) > 30,
        );
        assert_eq!((pic.width, pic.height), (w, h));

        keys(&display, &ben_wid, &["r"]);
        for (k, (who, window)) in [("ann", &ann), ("ben", &ben)].into_iter().enumerate() {
            window.wait_for(
                over[k],
                limit,
                &format!("{w}x{h}: {who}'s next game"),
                |l| l.starts_with("game playing"),
            );
        }
        // Both windows word the turn lines and verdicts with the players' names, never their
        // seats: the break, the concession and the next game's break.
        let said: Vec<String> = [&ann, &ben].iter().flat_map(|w| w.said()).collect();
        let worded: Vec<&String> = said
            .iter()
            .filter(|l| l.starts_with("status ") || l.starts_with("verdict "))
            .collect();
        for name in ["ann", "ben"] {
            assert!(
                worded.iter().any(|l| l.contains(name)),
                "{w}x{h}: no turn line or verdict names {name}: {worded:?}"
            );
        }
        assert!(
            worded
                .iter()
                .any(|l| l.starts_with("status Game over") && l.contains("ann")),
            "{w}x{h}: the game-over line does not name ann: {worded:?}"
        );
        assert!(
            !worded
                .iter()
                .any(|l| l.contains("Player A") || l.contains("Player B")),
            "{w}x{h}: a seat named, not a player: {worded:?}"
        );
        drop((ben, ann));
    }
}

/// Ctrl+V types the clipboard's text in the chat line (T opens it) of a game, and in the
/// replay page's invite line, in real windows; each says what was sent or listed.
#[test]
fn ctrl_v_pastes_the_clipboard_in_the_chat_line_and_the_replay_page_s_invite_line() {
    use common::reported::Reported;
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("friends-paste");
    let limit = Duration::from_secs(30);
    let chat = dir.path().join("chat.txt");
    std::fs::write(&chat, "good shot, ann\nnot this line\n").expect("written");
    let Some(clipboard) = display.clipboard(&chat) else {
        return;
    };
    // Ann hosts against the computer: a game with a chat line.
    let (ann, invite) = Reported::host(
        display
            .on(&mut Command::new(BREAKSHOT))
            .args(common::screen::hosting_the_computer(
                &dir.path().join("ann"),
            ))
            .args(["--size", "1280x720"]),
    );
    let wid = display.new_window(&[]);
    ann.wait_for(0, PATIENCE, "the game", |l| l.starts_with("game playing"));
    keys(&display, &wid, &["t", "ctrl+v", "Return"]);
    // Its first line only.
    ann.wait_for(0, limit, "the pasted chat line", |l| {
        l == "chat sent good shot, ann"
    });
    drop(ann);
    drop(clipboard);

    // The replay page opened from the menu, its line empty (the clipboard holds no invite
    // then); the game's invite copied, then pasted and listed with Enter.
    let menu = Reported::start(
        display
            .on(&mut Command::new(BREAKSHOT))
            .args(["--size", "1280x720", "--data"])
            .arg(dir.path().join("menu")),
    );
    let wid = display.new_window(&[]);
    std::thread::sleep(Duration::from_secs(1));
    let buttons = menu_buttons(1280.0, 720.0, MENU_BUTTONS);
    click(&display, &wid, middle(&buttons[WATCH_A_REPLAY]));
    std::thread::sleep(Duration::from_secs(1));
    let copied = dir.path().join("invite.txt");
    std::fs::write(&copied, format!("  {invite}\n")).expect("written");
    let Some(clipboard) = display.clipboard(&copied) else {
        return;
    };
    keys(&display, &wid, &["ctrl+v", "Return"]);
    let want = format!("replays list {invite}");
    menu.wait_for(0, limit, "the pasted invite listed", |l| l == want);
    drop((menu, clipboard));
}
