//! The window under a virtual display: `breakshot practice SCENE --screenshot` must draw the
//! cloth over the table and each ball, in its colour, where the layout puts it.
//!
//! Needs `xvfb-run`; without it the test says why and passes (CI installs it).

use std::path::{Path, PathBuf};
use std::process::Command as Process;

use breakshot_client::view::layout::{Frame, Layout};
use breakshot_client::view::palette::{
    ball_ids, ball_look, Rgb, BALL_WHITE, CLOTH, CUSHION, DIAMOND, POCKET,
};
use breakshot_shared::physics::{BallState, MotionState, Params, Strike};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command, EightBallRules, Game, Settings, Variant};
use breakshot_shared::scene::Scene;
use glam::DVec2;

const SCENE: &str = r#"{
  "table": "9ft",
  "balls": [
    {"id": "cue", "pos": [0.635, 0.9]},
    {"id": "1",   "pos": [0.30, 1.60]},
    {"id": "2",   "pos": [0.95, 1.40]},
    {"id": "3",   "pos": [0.20, 2.20]},
    {"id": "8",   "pos": [0.635, 1.90]},
    {"id": "11",  "pos": [1.05, 2.30]},
    {"id": "14",  "pos": [0.45, 2.05]}
  ]
}"#;

fn find_in_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).expect("screenshot written");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

fn close(a: Rgb, b: Rgb, tolerance: i32) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, y)| (x as i32 - y as i32).abs() <= tolerance)
}

/// Whether `got` is `want` lit more or less brightly (a ball is a shaded sphere): the same
/// colour scaled by one factor in a plausible range, within `tolerance` per channel.
fn shaded(got: Rgb, want: Rgb, tolerance: f32) -> bool {
    let dot = |a: Rgb, b: Rgb| {
        a.iter()
            .zip(b)
            .map(|(&x, y)| x as f32 * y as f32)
            .sum::<f32>()
    };
    let k = dot(got, want) / dot(want, want).max(1.0);
    (0.3..=1.1).contains(&k)
        && got
            .iter()
            .zip(want)
            .all(|(&x, y)| (x as f32 - k * y as f32).abs() <= tolerance)
}

/// A screenshot taken by `breakshot ARGS --screenshot` at 1280x720 under a virtual display.
struct Picture {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

impl Picture {
    fn at(&self, x: f32, y: f32) -> Rgb {
        let (x, y) = (x.round() as usize, y.round() as usize);
        let i = (y * self.width as usize + x) * 4;
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }
}

/// Runs `breakshot` with `args` and a file `name` holding `contents`; None if there is no
/// `xvfb-run` (the reason is printed).
fn screenshot(name: &str, contents: &[u8], args: &[&str]) -> Option<Picture> {
    capture(name, args, Some((name, contents)))
}

/// Runs `breakshot ARGS [FILE] --screenshot` in a scratch directory named after `tag`, with
/// `input` (a file name and its contents) written there and passed last; None if there is
/// no `xvfb-run` (the reason is printed).
fn capture(tag: &str, args: &[&str], input: Option<(&str, &[u8])>) -> Option<Picture> {
    let Some(xvfb) = find_in_path("xvfb-run") else {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
        return None;
    };
    let dir = std::env::temp_dir().join(format!("breakshot-window-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = dir.join("out.png");
    let mut command = Process::new(xvfb);
    command
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_breakshot"))
        .args(args);
    if let Some((name, contents)) = input {
        let file = dir.join(name);
        std::fs::write(&file, contents).expect("input written");
        command.arg(file);
    }
    let status = command
        .arg("--screenshot")
        .arg(&out)
        .args(["--frames", "4", "--size", "1280x720"])
        .status()
        .expect("xvfb-run runs");
    assert!(status.success(), "breakshot exited with {status}");
    let (width, height, pixels) = read_png(&out);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!((width, height), (1280, 720));
    Some(Picture {
        width,
        height,
        pixels,
    })
}

#[test]
fn practice_screenshot_shows_cloth_and_balls_where_the_layout_puts_them() {
    let Some(pic) = screenshot("scene.json", SCENE.as_bytes(), &["practice"]) else {
        return;
    };
    let scene = Scene::from_json(SCENE).expect("valid scene");
    let shot = scene.to_shot().expect("valid shot");
    let layout = Layout::new(
        pic.width as f32,
        pic.height as f32,
        Frame::new(shot.table, &shot.balls),
    );
    let at = |x, y| pic.at(x, y);

    // The cloth colour fills most of the table (balls and aiming lines cover a little)...
    let c = layout.cloth;
    let (mut cloth, mut total) = (0, 0);
    for i in 1..40 {
        for j in 1..20 {
            let p = at(c.x + c.w * i as f32 / 40.0, c.y + c.h * j as f32 / 20.0);
            cloth += close(p, CLOTH, 6) as u32;
            total += 1;
        }
    }
    assert!(
        cloth * 100 > total * 90,
        "cloth colour at {cloth} of {total} points"
    );
    // ... and stops at the cushions.
    assert!(!close(at(c.x - layout.px(0.09), c.y + 0.3 * c.h), CLOTH, 6));

    let ids: Vec<&str> = scene.balls.iter().map(|b| b.id.as_str()).collect();
    balls_are_drawn(&pic, &layout, &ids, &shot.balls);
}

/// Each ball's colour, shaded, left and right of its centre (clear of the number in the
/// middle; the balls have not turned yet, so their numbers are on top).
fn balls_are_drawn(pic: &Picture, layout: &Layout, ids: &[&str], balls: &[BallState]) {
    let at = |x, y| pic.at(x, y);
    let r = layout.px(Params::default().ball_radius);
    for (id, state) in ids.iter().zip(balls) {
        if state.motion == MotionState::Pocketed {
            continue;
        }
        let [x, y] = layout.to_screen(state.pos);
        let look = ball_look(id);
        for dx in [-0.75 * r, 0.75 * r] {
            let got = at(x + dx, y);
            assert!(
                shaded(got, look.color, 14.0),
                "ball {id} at ({x}, {y}): saw {got:?}, want {:?}",
                look.color
            );
        }
        // A striped ball is white above and below its band.
        if look.stripe {
            let cap = at(x, y - 0.85 * r);
            assert!(shaded(cap, BALL_WHITE, 16.0), "ball {id} top: {cap:?}");
        }
    }
}

#[test]
fn replay_screenshot_shows_the_recorded_games_table() {
    // A recorded game: the break from the break spot, straight up the table.
    let variant = Variant::EightBall(EightBallRules::Wpa);
    let mut game = Game::new(variant, Settings::offline(), 5);
    let mut record = GameRecord::new(variant, Settings::offline(), 5);
    let strike = Strike::at_angle(9.0, 90.0, DVec2::ZERO);
    let shot = Command::Shot { strike, call: None };
    let verdict = game.apply(game.to_move(), &shot).expect("a legal break");
    record.push(game.to_move(), shot, verdict.shot.map(|s| s.hash));

    let Some(pic) = screenshot("game.rec", &record.encode(), &["replay"]) else {
        return;
    };
    // Four frames are well inside the pause before the first shot: the rack is shown.
    let racked = Game::new(variant, Settings::offline(), 5);
    let layout = Layout::new(
        pic.width as f32,
        pic.height as f32,
        Frame::new(racked.table(), racked.balls()),
    );
    let ids: Vec<String> = (0..racked.balls().len())
        .map(|n| if n == 0 { "cue".into() } else { n.to_string() })
        .collect();
    let ids: Vec<&str> = ids.iter().map(|s| s.as_str()).collect();
    balls_are_drawn(&pic, &layout, &ids, racked.balls());
}

#[test]
fn a_host_shows_the_invite_while_waiting_for_the_opponent() {
    let Some(xvfb) = find_in_path("xvfb-run") else {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
        return;
    };
    let dir = std::env::temp_dir().join(format!("breakshot-window-{}-host", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = dir.join("out.png");
    let run = Process::new(xvfb)
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_breakshot"))
        .args(["host", "--bind", "127.0.0.1:0", "--data"])
        .arg(dir.join("server"))
        .arg("--screenshot")
        .arg(&out)
        .args(["--frames", "4", "--size", "1280x720"])
        .output()
        .expect("xvfb-run runs");
    assert!(
        run.status.success(),
        "breakshot host exited with {}: {}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    // The first line on standard output is the invite, naming the bound loopback address.
    let stdout = String::from_utf8_lossy(&run.stdout);
    let invite: breakshot_shared::protocol::Invite = stdout
        .lines()
        .next()
        .expect("an invite line")
        .parse()
        .expect("a valid invite");
    assert_eq!(invite.host, "127.0.0.1");
    assert!(invite.room.is_some());

    let (width, height, pixels) = read_png(&out);
    let _ = std::fs::remove_dir_all(&dir);
    let pic = Picture {
        width,
        height,
        pixels,
    };
    // The table is drawn behind the panel: cloth above it ...
    let racked = Game::new(
        Variant::EightBall(EightBallRules::Wpa),
        Settings::online(),
        0,
    );
    let layout = Layout::new(
        width as f32,
        height as f32,
        Frame::new(racked.table(), racked.balls()),
    );
    let c = layout.cloth;
    let above = pic.at(c.x + 0.45 * c.w, c.y + 0.1 * c.h);
    assert!(close(above, CLOTH, 6), "cloth {above:?}");
    // ... and the panel in the middle: dark, with the invite in yellow across it.
    let mid = (0.5 * width as f32, 0.5 * height as f32);
    let dark = pic.at(mid.0, mid.1 - 90.0);
    assert!(dark.iter().all(|&v| v < 60), "panel background {dark:?}");
    // The invite's line, in the upper half of the panel (the HUD's yellow is far above).
    let band = (mid.1 - 60.0) as u32..(mid.1 - 15.0) as u32;
    let yellow = (0..width)
        .flat_map(|x| band.clone().map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let p = pic.at(x as f32, y as f32);
            p[0] > 200 && p[1] > 200 && p[2] < 80
        })
        .count();
    assert!(yellow > 200, "{yellow} yellow pixels: no invite drawn");
}

#[test]
#[cfg(feature = "host")]
fn replay_from_a_server_shows_the_fetched_games_table() {
    use breakshot_client::bot::{run, BotConfig};
    use breakshot_client::net::{fetch_record_blocking, EmbeddedServer};

    let Some(xvfb) = find_in_path("xvfb-run") else {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
        return;
    };
    let dir = std::env::temp_dir().join(format!("breakshot-window-{}-fetch", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let server = EmbeddedServer::start(breakshot_server::Config::new(
        std::net::SocketAddr::from(([127, 0, 0, 1], 0)),
        dir.join("server"),
    ))
    .expect("a server on loopback");
    let invite = server.loopback_invite();
    // Two bots play a game on the server; its rack depends on the room's random seed.
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let report = runtime.block_on(run(&BotConfig::new(invite.clone(), 1)));
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let room = report.games[0].room.clone().expect("the bots' room");
    let fetched = fetch_record_blocking(&invite, &room).expect("the record");
    let record = GameRecord::decode(&fetched.bytes).expect("a record");

    let out = dir.join("out.png");
    let run = Process::new(xvfb)
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_breakshot"))
        .args(["replay", "--server", &invite.to_string(), "--game"])
        .arg(room.as_str())
        .arg("--screenshot")
        .arg(&out)
        .args(["--frames", "4", "--size", "1280x720"])
        .output()
        .expect("xvfb-run runs");
    drop(server);
    assert!(
        run.status.success(),
        "breakshot replay --server exited with {}: {}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    let (width, height, pixels) = read_png(&out);
    let _ = std::fs::remove_dir_all(&dir);
    let pic = Picture {
        width,
        height,
        pixels,
    };
    // Four frames are well inside the pause before the first shot: this game's rack.
    let racked = Game::new(record.variant, record.settings, record.seed);
    let layout = Layout::new(
        pic.width as f32,
        pic.height as f32,
        Frame::new(racked.table(), racked.balls()),
    );
    let ids: Vec<String> = (0..racked.balls().len())
        .map(|n| if n == 0 { "cue".into() } else { n.to_string() })
        .collect();
    let ids: Vec<&str> = ids.iter().map(|s| s.as_str()).collect();
    balls_are_drawn(&pic, &layout, &ids, racked.balls());
}

#[test]
fn a_three_cushion_game_shows_the_carom_table_and_its_three_balls() {
    let Some(pic) = capture(
        "carom",
        &["local", "--mode", "3cushion", "--seed", "1"],
        None,
    ) else {
        return;
    };
    let game = Game::new(Variant::three_cushion(), Settings::offline(), 1);
    let layout = Layout::new(
        pic.width as f32,
        pic.height as f32,
        Frame::new(game.table(), game.balls()),
    );
    // The cloth has the carom table's proportions.
    let c = layout.cloth;
    assert!((c.w / c.h - 2.0).abs() < 0.01, "{c:?}");
    assert!(close(pic.at(c.x + 0.5 * c.w, c.y + 0.2 * c.h), CLOTH, 6));
    // No pockets: where a pool table has its corner and side pockets, the cushions go on.
    let (w, l) = (1.42, 2.84);
    let inset = 0.02;
    for p in [
        DVec2::new(-inset, -inset),
        DVec2::new(w + inset, l + inset),
        DVec2::new(-inset, 0.5 * l),
        DVec2::new(w + inset, 0.5 * l),
    ] {
        let [x, y] = layout.to_screen(p);
        let got = pic.at(x, y);
        assert!(close(got, CUSHION, 8), "cushion at {p}: {got:?}");
        assert!(!close(got, POCKET, 20), "a pocket at {p}");
    }
    // A diamond on each long rail's middle, where a pool table has its side pockets.
    let back = 0.045 + 0.5 * (0.12 - 0.045);
    for p in [DVec2::new(-back, 0.5 * l), DVec2::new(w + back, 0.5 * l)] {
        let [x, y] = layout.to_screen(p);
        assert!(close(pic.at(x, y), DIAMOND, 12), "no diamond at {p}");
    }
    // The white, the yellow and the red, each in its colour where the layout puts it.
    let ids = ball_ids(&game);
    let ids: Vec<&str> = ids.iter().map(|s| s.as_str()).collect();
    assert_eq!(ids, ["white", "yellow", "red"]);
    balls_are_drawn(&pic, &layout, &ids, game.balls());
    let [x, y] = layout.to_screen(game.balls()[2].pos);
    let red = pic.at(x - 0.5 * layout.px(game.params().ball_radius), y);
    assert!(
        red[0] > 120 && red[1] < 50 && red[2] < 50,
        "the red ball: {red:?}"
    );
}
