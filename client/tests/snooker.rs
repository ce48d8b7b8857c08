//! Snooker in the window under a virtual display: the table's markings (baulk line, the D,
//! the six spots), the 22 balls in their colours, the HUD, and a 6-red frame between the
//! computer and a bot watched in the window through a real server.
//!
//! Needs `xvfb-run`; without it each test says why and passes (CI installs it).
#![cfg(feature = "host")]

use std::ffi::OsStr;
use std::time::Duration;

use breakshot_client::bot::{open_room, BotConfig};
use breakshot_client::net::{fetch_game_blocking, SeatedComputer};
use breakshot_client::view::palette::{ball_look, Rgb, CLOTH};
use breakshot_client::view::snooker::{markings, SPOT_RADIUS};
use breakshot_client::view::{Frame, Layout, Rect};
use breakshot_shared::ai::Level;
use breakshot_shared::physics::{BallState, TableKind};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::snooker::table::scene_id;
use breakshot_shared::rules::{Game, Phase, Settings, Variant};
use breakshot_shared::scene::Scene;
use glam::DVec2;

mod common;

use common::screen::{assert_ran, shaded, window, Picture};

/// A practice scene on the snooker table with the colours off their spots, so that every
/// spot shows.
const OPEN_SPOTS: &str = r#"{
  "table": "snooker",
  "balls": [
    {"id": "cue",   "pos": [0.50, 1.30]},
    {"id": "r1",    "pos": [1.30, 2.40]},
    {"id": "blue",  "pos": [0.40, 2.10]},
    {"id": "black", "pos": [1.40, 3.00]}
  ]
}"#;

/// One window's run: the screenshot at frame `frames` of `breakshot ARGS`; None without
/// `xvfb-run`.
fn shown(name: &str, args: &[&OsStr], frames: u32, patience: Duration) -> Option<Picture> {
    let dir = breakshot_testkit::scratch(&format!("snooker-{name}"));
    let out = dir.path().join("out.png");
    assert_ran(&window(args, &out, frames, patience)?);
    Some(Picture::read(&out))
}

/// A chalk line over the cloth: lighter than the cloth in every channel.
fn chalk(p: Rgb) -> bool {
    p.iter()
        .zip(CLOTH)
        .all(|(&c, cloth)| c as i32 >= cloth as i32 + 50)
}

/// How many of `points` (scene coordinates) show a chalk line within a pixel.
fn chalked(pic: &Picture, layout: &Layout, points: &[DVec2]) -> usize {
    points
        .iter()
        .filter(|p| {
            let [x, y] = layout.to_screen(**p);
            pic.near(x, y, 1, chalk)
        })
        .count()
}

/// The baulk line's points, every tenth of the width, and the D's.
fn baulk_and_d() -> (Vec<DVec2>, Vec<DVec2>) {
    let m = markings();
    let baulk = (1..10)
        .map(|k| m.baulk.0.lerp(m.baulk.1, k as f64 / 10.0))
        .collect();
    (baulk, m.d_arc.clone())
}

/// Each ball on the table (named by `ids`) drawn in its own colour above and below its
/// centre.
fn balls_are_drawn(
    pic: &Picture,
    layout: &Layout,
    ids: &[String],
    balls: &[BallState],
    radius: f64,
) {
    let r = layout.px(radius);
    for (id, b) in ids.iter().zip(balls) {
        if b.motion.is_gone() {
            continue;
        }
        let [x, y] = layout.to_screen(b.pos);
        let want = ball_look(id).color;
        // Above and below its centre: clear of an aim line drawn along the table.
        for dy in [-0.6 * r, 0.6 * r] {
            let got = pic.at(x, y + dy);
            assert!(
                shaded(got, want, 16.0),
                "{id} at ({x}, {y}): saw {got:?}, want {want:?}"
            );
        }
    }
}

/// Pixels of text in `r`: light (white, grey or yellow) on the HUD's dark bar.
fn text_pixels(pic: &Picture, r: Rect) -> usize {
    let mut n = 0;
    for x in (r.x as u32)..((r.x + r.w) as u32) {
        for y in (r.y as u32)..((r.y + r.h) as u32) {
            let [r, g, _] = pic.at(x as f32, y as f32);
            n += usize::from(r > 150 && g > 150);
        }
    }
    n
}

#[test]
fn the_snooker_table_shows_its_baulk_line_the_d_and_the_six_spots() {
    let dir = breakshot_testkit::scratch("snooker-scene");
    let path = dir.path().join("open.json");
    std::fs::write(&path, OPEN_SPOTS).expect("scene written");
    let args = [OsStr::new("practice"), path.as_os_str()];
    let Some(pic) = shown("spots", &args, 4, Duration::from_secs(120)) else {
        return;
    };
    let scene = Scene::from_json(OPEN_SPOTS).expect("a scene");
    let shot = scene.to_shot().expect("a shot");
    let layout = pic.layout(Frame::new(TableKind::Snooker, &shot.balls));
    let (baulk, d) = baulk_and_d();
    assert_eq!(
        chalked(&pic, &layout, &baulk),
        baulk.len(),
        "the baulk line"
    );
    assert_eq!(chalked(&pic, &layout, &d), d.len(), "the D");
    // Each spot's ring, and cloth in its middle.
    for s in markings().spots {
        let rim: Vec<DVec2> = [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y]
            .iter()
            .map(|&d| s + SPOT_RADIUS * d)
            .collect();
        assert!(chalked(&pic, &layout, &rim) >= 3, "the spot at {s}");
    }
    // Away from the lines the cloth is plain.
    let [x, y] = layout.to_screen(DVec2::new(0.3, 1.6));
    assert!(!pic.near(x, y, 1, chalk), "chalk where there is none");
    let ids: Vec<String> = scene.balls.iter().map(|b| b.id.clone()).collect();
    balls_are_drawn(&pic, &layout, &ids, &shot.balls, shot.params.ball_radius);
}

#[test]
fn a_six_red_frame_shows_its_rack_in_colour_and_both_scores() {
    let args = [
        "local",
        "--mode",
        "snooker",
        "--reds",
        "6",
        "--best-of",
        "3",
        "--seed",
        "3",
    ]
    .map(OsStr::new);
    let Some(pic) = shown("rack", &args, 4, Duration::from_secs(120)) else {
        return;
    };
    let game = Game::new(
        Variant::Snooker {
            reds: 6,
            best_of: 3,
        },
        Settings::offline(),
        3,
    );
    let layout = pic.layout(Frame::new(game.table(), game.balls()));
    let ids: Vec<String> = (0..22).map(scene_id).collect();
    balls_are_drawn(&pic, &layout, &ids, game.balls(), game.params().ball_radius);
    // Six reds and the six colours on the table; the nine reds a short frame does not rack
    // are neither drawn nor counted as potted in the trays.
    let on: Vec<usize> = (1..22)
        .filter(|&n| !game.balls()[n].motion.is_gone())
        .collect();
    assert_eq!(on.len(), 12);
    let tray = layout.tray;
    let reds = (tray.x as u32..(tray.x + tray.w) as u32)
        .step_by(2)
        .flat_map(|x| (tray.y as u32..(tray.y + tray.h) as u32).map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b] = pic.at(x as f32, y as f32);
            r > 150 && g < 60 && b < 60
        })
        .count();
    assert_eq!(reds, 0, "reds drawn in the trays");
    // Both players' lines (with their scores) and the status line are written.
    for r in layout.players {
        assert!(text_pixels(&pic, r) > 40, "no player's line in {r:?}");
    }
    assert!(text_pixels(&pic, layout.status) > 100, "no status line");
}

/// The computer (level 1) and a bot play a 6-red frame on a real server; the window joins
/// the full room and watches it. The screenshot shows the snooker table with its markings
/// and the HUD; the frame the record keeps ended by the rules, with a winner.
#[test]
fn a_six_red_frame_between_the_computer_and_a_bot_is_watched_in_the_window() {
    if common::screen::xvfb_run().is_none() {
        return;
    }
    let dir = breakshot_testkit::scratch("snooker-watch");
    let server = common::loopback_server(dir.path().join("server"));
    let invite = server.loopback_invite();
    let variant = Variant::Snooker {
        reds: 6,
        best_of: 1,
    };
    let mut config = BotConfig::new(invite.clone(), 1);
    config.variant = variant;
    // The bot takes a moment over each stroke, so the window sees the frame in play.
    config.think = Duration::from_millis(300);
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let (opened, room) = tokio::sync::oneshot::channel();
    let bot = runtime.spawn(async move { open_room(&config, opened).await });
    let room = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(60), room).await })
        .expect("the bot opened a room within a minute")
        .expect("the room's code");
    let mut room_invite = invite.clone();
    room_invite.room = Some(room.clone());
    let computer = SeatedComputer::join(room_invite.clone(), Level::new(1), 7, false)
        .expect("the computer takes the other seat");

    // The window joins the full room: it watches.
    let text = room_invite.to_string();
    let args = ["join", text.as_str()].map(OsStr::new);
    let pic = shown("watch", &args, 240, Duration::from_secs(180)).expect("xvfb-run");

    let report = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(600), bot).await })
        .expect("the frame ended within ten minutes")
        .expect("the bot's task");
    drop(computer);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1, "{:?}", report.games);
    assert_eq!(report.tally.desyncs, 0);

    let fetched = fetch_game_blocking(&invite, &room, None).expect("the record");
    drop(server);
    let record = GameRecord::decode(&fetched.bytes).expect("a record");
    assert_eq!(record.variant, variant);
    let mut game = Game::new(record.variant, record.settings, record.seed);
    for e in &record.entries {
        game.apply(e.seat, &e.command).expect("the record replays");
    }
    let Phase::Over { winner, reason } = game.phase() else {
        panic!("the frame did not end: {:?}", game.phase());
    };
    assert!(winner.is_some(), "{reason}");
    let m = game.snooker().expect("snooker");
    eprintln!(
        "6-red frame, computer against a bot: {}-{} after {} commands: {reason}",
        m.scores[0],
        m.scores[1],
        record.entries.len()
    );

    // The window showed the snooker table: its cloth, the baulk line and the D (where no
    // ball lies on them), and both players' lines and the status over the table.
    let layout = pic.layout(Frame::new(TableKind::Snooker, &[]));
    let c = layout.cloth;
    let grid: Vec<(f32, f32)> = (1..20)
        .flat_map(|i| (1..10).map(move |j| (i as f32 / 20.0, j as f32 / 10.0)))
        .collect();
    let cloth = grid
        .iter()
        .filter(|(u, v)| shaded(pic.at(c.x + u * c.w, c.y + v * c.h), CLOTH, 20.0))
        .count();
    assert!(
        2 * cloth > grid.len(),
        "{cloth} of {} points are cloth",
        grid.len()
    );
    let (baulk, d) = baulk_and_d();
    let seen = chalked(&pic, &layout, &baulk) + chalked(&pic, &layout, &d);
    assert!(
        seen + 4 >= baulk.len() + d.len(),
        "{seen} of {} chalk points",
        baulk.len() + d.len()
    );
    for r in layout.players {
        assert!(text_pixels(&pic, r) > 40, "no player's line in {r:?}");
    }
    assert!(text_pixels(&pic, layout.status) > 100, "no status line");
}
