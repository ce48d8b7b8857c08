//! The window under a virtual display: `breakshot practice SCENE --screenshot` must draw the
//! cloth over the table and each ball, in its colour, where the layout puts it.
//!
//! Needs `xvfb-run`; without it the test says why and passes (CI installs it).

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command as Process, Output};
use std::time::Duration;

use breakshot_client::play::{Aim, ReplayViewer};
use breakshot_client::view::aids::{predict, PathPoint};
use breakshot_client::view::palette::{
    ball_look, Rgb, BALL_WHITE, CLOTH, CUE_BALL, CUE_WOOD, CUSHION, DIAMOND, POCKET, RAIL_WOOD,
};
use breakshot_client::view::{flight, Camera, Frame, Layout, Orbit};
use breakshot_shared::physics::Simulator;
use breakshot_shared::physics::{BallState, EventKind, MotionState, Outcome, Params, Shot, Strike};
#[cfg(feature = "host")]
use breakshot_shared::protocol::{Invite, RoomCode, SeatToken, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command, EightBallRules, Game, Settings, Variant};
use breakshot_shared::scene::Scene;
use glam::{DVec2, DVec3};

mod common;

use common::screen::{
    assert_ran, close, eight_ball, find_in_path, hosting_the_computer, reports, shaded, xvfb_run,
    Picture,
};
#[cfg(feature = "host")]
use common::{next, within};

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

/// Runs `breakshot` under a virtual display with `args`, saving its window to `out` after four
/// frames at 1280x720; None if there is no `xvfb-run` (the reason is printed). Fails the test
/// if the window has not closed within two minutes.
fn window(args: &[&OsStr], out: &Path) -> Option<Output> {
    window_at(args, out, 4)
}

/// As [`window`], of frame `frames` (the window steps 1/60 s of animation a frame).
fn window_at(args: &[&OsStr], out: &Path, frames: u32) -> Option<Output> {
    window_sized(args, out, frames, (1280, 720))
}

/// As [`window_at`], in a window of `size` pixels, with a fresh data directory.
fn window_sized(args: &[&OsStr], out: &Path, frames: u32, size: (u32, u32)) -> Option<Output> {
    common::screen::window_sized(args, out, frames, size, Duration::from_secs(120))
}

/// The screenshot `window` saved, checked to be the size asked for.
fn picture(out: &Path) -> Picture {
    Picture::sized(out, (1280, 720))
}

/// Runs `breakshot` with `args` and a file `name` holding `contents`; None if there is no
/// `xvfb-run` (the reason is printed).
fn screenshot(name: &str, contents: &[u8], args: &[&str]) -> Option<Picture> {
    screenshot_at(name, contents, args, 4)
}

/// As [`screenshot`], of frame `frames`.
fn screenshot_at(name: &str, contents: &[u8], args: &[&str], frames: u32) -> Option<Picture> {
    let dir = breakshot_testkit::scratch("window");
    let input = dir.path().join(name);
    let out = dir.path().join("out.png");
    std::fs::write(&input, contents).expect("input written");
    let mut all: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    all.push(input.as_os_str());
    ran_to_picture(&all, &out, frames)
}

/// The screenshot of `breakshot ARGS` at frame `frames`, saved to `out`, once it has exited
/// cleanly; None if there is no `xvfb-run` (the reason is printed).
fn ran_to_picture(args: &[&OsStr], out: &Path, frames: u32) -> Option<Picture> {
    assert_ran(&window_at(args, out, frames)?);
    Some(picture(out))
}

/// [`screenshot`] of the scene `json` saved as `name`, with the scene and its shot; None if
/// there is no `xvfb-run`.
fn scene_screenshot(name: &str, json: &str, args: &[&str]) -> Option<(Picture, Scene, Shot)> {
    let pic = screenshot(name, json.as_bytes(), args)?;
    let scene = Scene::from_json(json).expect("valid scene");
    let shot = scene.to_shot().expect("valid shot");
    Some((pic, scene, shot))
}

#[test]
fn practice_screenshot_shows_cloth_and_balls_where_the_layout_puts_them() {
    let Some((pic, scene, shot)) = scene_screenshot("scene.json", SCENE, &["practice"]) else {
        return;
    };
    let layout = pic.layout(Frame::new(shot.table, &shot.balls));
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

/// Every ball of `game`'s table drawn where the layout puts it.
fn rack_is_drawn(pic: &Picture, game: &Game) {
    let layout = pic.layout(Frame::new(game.table(), game.balls()));
    let ids = game.ball_ids();
    let ids: Vec<&str> = ids.iter().map(|s| s.as_str()).collect();
    balls_are_drawn(pic, &layout, &ids, game.balls());
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
    let breaker = game.to_move();
    let verdict = game.apply(breaker, &shot).expect("a legal break");
    record.push(breaker, shot, verdict.shot.map(|s| s.hash));

    let Some(pic) = screenshot("game.rec", &record.encode(), &["replay"]) else {
        return;
    };
    // Four frames are well inside the pause before the first shot: the rack is shown.
    let racked = Game::new(variant, Settings::offline(), 5);
    rack_is_drawn(&pic, &racked);
}

#[test]
fn a_host_shows_the_invite_while_waiting_for_the_opponent() {
    let dir = breakshot_testkit::scratch("window-host");
    let out = dir.path().join("out.png");
    let data = dir.path().join("server");
    let args = ["host", "--bind", "127.0.0.1:0", "--data"].map(OsStr::new);
    let Some(run) = window(&[&args[..], &[data.as_os_str()]].concat(), &out) else {
        return;
    };
    assert_ran(&run);
    // The first line on standard output is the invite, naming the bound loopback address.
    let stdout = String::from_utf8_lossy(&run.stdout);
    let invite: breakshot_shared::protocol::Invite = stdout
        .lines()
        .next()
        .expect("an invite line")
        .parse()
        .expect("a valid invite");
    assert_eq!(invite.first().host, "127.0.0.1");
    assert!(invite.room.is_some());

    let pic = picture(&out);
    let (width, height) = (pic.width, pic.height);
    // The table is drawn behind the panel: cloth above it ...
    let racked = eight_ball(Settings::online(), 0);
    let layout = Layout::new(
        width as f32,
        height as f32,
        Frame::new(racked.table(), racked.balls()),
    );
    let c = layout.cloth;
    let above = pic.at(c.x + 0.45 * c.w, c.y + 0.1 * c.h);
    assert!(close(above, CLOTH, 6), "cloth {above:?}");
    // ... and the panel in the middle: dark, with the invite in yellow across it.
    let [mx, my] = layout.outer.center();
    let mid = (mx, my);
    let dark = pic.at(mid.0, mid.1 - 90.0);
    assert!(dark.iter().all(|&v| v < 60), "panel background {dark:?}");
    // The invite's line, in the upper half of the panel (the HUD's yellow is far above).
    // Its pixels are yellow however bright: how bright the thin glyphs come out depends on
    // where they fall on the pixel grid, which moves with the invite's characters (from
    // 190 to 143 in red at their brightest). About 2 000 of them; a yellow ball in the band
    // with no panel over it would give a few hundred.
    let band = (mid.1 - 60.0) as u32..(mid.1 - 15.0) as u32;
    let yellow = (0..width)
        .flat_map(|x| band.clone().map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let p = pic.at(x as f32, y as f32);
            p[0] > 100 && p[1] > 100 && p[2] < 60
        })
        .count();
    assert!(
        yellow > 1_000,
        "{yellow} yellow pixels: no invite drawn; the window said:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

/// The arguments of `breakshot join INVITE`, its data in `data`.
fn joining<'a>(invite: &'a str, data: &'a Path) -> [&'a OsStr; 4] {
    [
        OsStr::new("join"),
        OsStr::new(invite),
        OsStr::new("--data"),
        data.as_os_str(),
    ]
}

/// A scratch folder for test `name` and a loopback server keeping its data in the folder's
/// `server`; None (the reason printed) where xvfb-run is missing.
#[cfg(feature = "host")]
fn served_to_a_window(
    name: &str,
) -> Option<(
    breakshot_testkit::TempDir,
    breakshot_client::net::EmbeddedServer,
)> {
    xvfb_run()?;
    let dir = breakshot_testkit::scratch(name);
    let server = common::loopback_server(dir.path().join("server"));
    Some((dir, server))
}

#[test]
#[cfg(feature = "host")]
fn replay_from_a_server_shows_the_fetched_games_table() {
    use breakshot_client::net::fetch_game_blocking;

    let Some((dir, server)) = served_to_a_window("window-fetch") else {
        return;
    };
    let invite = server.loopback_invite();
    // Two bots play a game on the server; its rack depends on the room's random seed.
    let room = common::bots_game(&server);
    let fetched = fetch_game_blocking(&invite, &room, None).expect("the record");
    let record = GameRecord::decode(&fetched.bytes).expect("a record");

    let out = dir.path().join("out.png");
    let invite_text = invite.to_string();
    let args = ["replay", "--server", &invite_text, "--game", room.as_str()].map(OsStr::new);
    let run = window(&args, &out).expect("xvfb-run is installed");
    drop(server);
    assert_ran(&run);
    let pic = picture(&out);
    // Four frames are well inside the pause before the first shot: this game's rack.
    let racked = Game::new(record.variant, record.settings, record.seed);
    rack_is_drawn(&pic, &racked);
}

/// `host` opens an online 8-ball room on the server of `invite` and Bob joins it; then Bob's
/// connection closes and the host is told he left. The host's client, the room and Bob's seat
/// token.
#[cfg(feature = "host")]
async fn left_by_bob(
    invite: &Invite,
    host: &str,
) -> (breakshot_client::net::Client, RoomCode, SeatToken) {
    let (mut hosting, snapshot) = common::opened_room(invite, host).await;
    let (bob, _) = common::joined_room(invite, &snapshot.room, "bob").await;
    let token = bob.token().expect("Bob's seat token");
    bob.close(Duration::from_millis(100)).await;
    next(&mut hosting, |m| {
        matches!(m, ServerMessage::PlayerLeft { .. })
    })
    .await;
    (hosting, snapshot.room, token)
}

/// A window that ends (here after its screenshot, through the same path as a window closed
/// or a Ctrl-C: the frame loop stops and the screens are dropped) closes its connection, so
/// the other player is told at once that it left, not after the idle timeout.
#[test]
#[cfg(feature = "host")]
fn a_window_that_ends_is_seen_gone_at_once_not_after_the_idle_timeout() {
    use breakshot_shared::protocol::limits::IDLE_TIMEOUT;
    use std::time::Instant;

    let Some((dir, server)) = served_to_a_window("window-ends") else {
        return;
    };
    let mut invite = server.loopback_invite();
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let (mut alice, room) = within(&runtime, "the room", async {
        let (alice, snapshot) = common::opened_room(&invite, "alice").await;
        (alice, snapshot.room)
    });
    invite.room = Some(room);
    let text = invite.to_string();
    let out = dir.path().join("out.png");
    let data = dir.path().join("client");
    let window = std::thread::spawn(move || {
        let args = joining(&text, &data);
        let run = window_sized(&args, &out, 30, (640, 480));
        (run, Instant::now())
    });
    let left_at = within(&runtime, "the window's join, then its leaving", async {
        next(&mut alice, |m| {
            matches!(m, ServerMessage::PlayerJoined { .. })
        })
        .await;
        next(&mut alice, |m| {
            matches!(m, ServerMessage::PlayerLeft { .. })
        })
        .await;
        Instant::now()
    });
    let (run, ended_at) = window.join().expect("the window's thread");
    assert_ran(&run.expect("xvfb-run is installed"));
    // Told before the window's process had been gone for the idle timeout: its connection
    // was closed, not left to time out.
    assert!(
        left_at < ended_at + IDLE_TIMEOUT / 2,
        "told {:?} after the window ended",
        left_at.saturating_duration_since(ended_at)
    );
}

/// A player whose opponent ended the game while they were away, with the server restarted
/// since, runs the same `join` again (through an invite whose first address is down): the
/// window shows how the game came out for them, and the remembered seat is forgotten.
#[test]
#[cfg(feature = "host")]
fn a_game_that_ended_while_away_shows_its_result_and_forgets_the_seat() {
    use breakshot_client::net::SeatStore;
    use breakshot_shared::protocol::{ClientMessage, ServerAddress};

    let Some((dir, server)) = served_to_a_window("window-away") else {
        return;
    };
    let (data, seats) = (dir.path().join("server"), dir.path().join("client"));
    let invite = server.loopback_invite();

    // Alice hosts, Bob joins; Bob's connection drops and Alice concedes while he is away.
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let (room, token) = within(&runtime, "the game", async {
        let (mut alice, room, token) = left_by_bob(&invite, "alice").await;
        alice.send(&ClientMessage::Concede).await.expect("sent");
        next(&mut alice, |m| matches!(m, ServerMessage::GameOver { .. })).await;
        (room, token)
    });
    drop(server);

    // Bob's computer remembers his seat; the server comes back on the same data. His invite
    // lists first an address where nothing answers (an invite may name several instances of
    // a server): the window gives it its few seconds and goes on to the next.
    let store = SeatStore::new(&seats);
    let server = common::loopback_server(data);
    let silent = std::net::UdpSocket::bind(("127.0.0.1", 0)).expect("a UDP port");
    let mut again: Invite = server.loopback_invite().with_room(room);
    again.servers.insert(
        0,
        ServerAddress {
            host: "127.0.0.1".into(),
            port: silent.local_addr().expect("its address").port(),
        },
    );
    store.save(&again, token).expect("the seat remembered");

    let out = dir.path().join("out.png");
    let text = again.to_string();
    let run = window(&joining(&text, &seats), &out).expect("xvfb-run");
    drop(server);
    assert_ran(&run);
    assert_eq!(
        store.load(&again),
        None,
        "the finished game's seat is forgotten"
    );
    // "You won" in gold across the middle of the window, at the headline's height.
    let pic = picture(&out);
    let y = 0.4 * pic.height as f32;
    let gold = (0..pic.width)
        .flat_map(|x| ((y - 40.0) as u32..y as u32).map(move |y| (x, y)))
        .filter(|&(x, y)| close(pic.at(x as f32, y as f32), [255, 203, 0], 40))
        .count();
    assert!(gold > 300, "{gold} gold pixels: no result headline");
}

/// In 9-ball the ball on is ringed in yellow for the player to shoot, and the words above
/// the table name it.
#[test]
fn a_nine_ball_game_rings_the_ball_on() {
    let dir = breakshot_testkit::scratch("window-nine");
    let out = dir.path().join("out.png");
    let args = ["local", "--mode", "9ball", "--seed", "3"].map(OsStr::new);
    let Some(run) = window(&args, &out) else {
        return;
    };
    assert_ran(&run);
    let pic = picture(&out);
    let game = Game::new(Variant::NineBall, Settings::offline(), 3);
    let layout = pic.layout(Frame::new(game.table(), game.balls()));
    let ring = |n: usize| {
        let [x, y] = layout.to_screen(game.balls()[n].pos);
        let r = layout.px(Params::default().ball_radius) + 4.0;
        (0..72)
            .map(|k| f32::from(k as u8) * std::f32::consts::TAU / 72.0)
            .filter(|a| {
                let p = pic.at(x + r * a.cos(), y + r * a.sin());
                p[0] > 200 && p[1] > 200 && p[2] < 90
            })
            .count()
    };
    // Most of the 1's ring is yellow where no other ball covers it; the 9 has none.
    assert!(ring(1) > 20, "{} yellow points around the 1", ring(1));
    assert!(ring(9) < 8, "{} yellow points around the 9", ring(9));
}

const JUMP: &str = include_str!("../../examples/jump_9ft.json");
const MASSE: &str = include_str!("../../examples/masse_9ft.json");

/// The cue in the panel's side view is drawn at `elevation_deg`: wood along its line, not
/// along the line of another elevation.
fn side_view_shows(pic: &Picture, layout: &Layout, elevation_deg: f64) {
    let (tip, butt) = layout.elevation_cue(elevation_deg);
    let along = |k: f32| {
        [
            tip[0] + k * (butt[0] - tip[0]),
            tip[1] + k * (butt[1] - tip[1]),
        ]
    };
    for k in [0.4, 0.6, 0.8] {
        let [x, y] = along(k);
        let got = pic.at(x, y);
        assert!(
            close(got, CUE_WOOD, 10),
            "the side view's cue at {elevation_deg} deg: {got:?} at ({x}, {y})"
        );
    }
    let other = if elevation_deg > 45.0 { 10.0 } else { 80.0 };
    let (tip, butt) = layout.elevation_cue(other);
    let [x, y] = [0.3 * tip[0] + 0.7 * butt[0], 0.3 * tip[1] + 0.7 * butt[1]];
    assert!(
        !close(pic.at(x, y), CUE_WOOD, 30),
        "a cue at {other} deg too"
    );
}

#[test]
fn a_masse_set_up_shows_its_elevation_and_its_curving_path() {
    let Some((pic, _, shot)) = scene_screenshot("masse.json", MASSE, &["practice"]) else {
        return;
    };
    let layout = Layout::new(1280.0, 720.0, Frame::new(shot.table, &shot.balls));
    let strike = shot.strike.expect("a strike").1;
    side_view_shows(&pic, &layout, strike.elevation_deg);

    // The practice screen predicts the strike the panel shows (the scene's, elevation and
    // all): the same prediction here.
    let aim = Aim::from_strike(&strike);
    assert_eq!(aim.elevation_deg, strike.elevation_deg);
    let mut struck = shot.clone();
    struck.strike = Some((0, aim.strike()));
    let p = predict(&mut Simulator::new(), &struck, 0).expect("a prediction");
    // The point of the path on the cloth furthest off the cue's line.
    let start = p.cue_path[0].pos;
    let off_line = |q: &PathPoint| (q.pos - start).perp_dot(strike.dir).abs();
    let on_cloth: Vec<&PathPoint> = p
        .cue_path
        .windows(3)
        .filter(|w| w.iter().all(|q| q.lift == 0.0))
        .map(|w| &w[1])
        .collect();
    let far = on_cloth
        .iter()
        .copied()
        .max_by(|a, b| off_line(a).total_cmp(&off_line(b)))
        .expect("a path on the cloth");
    assert!(off_line(far) > 0.1, "the massé strays {} m", off_line(far));
    // The path is drawn there, a pale line over the cloth.
    let [x, y] = layout.to_screen(far.pos);
    let lit = (-1..=1)
        .flat_map(|dx| (-1..=1).map(move |dy| (dx as f32, dy as f32)))
        .map(|(dx, dy)| pic.at(x + dx, y + dy))
        .any(|c| c.iter().zip(CLOTH).all(|(&g, w)| g as i32 > w as i32 + 40));
    assert!(lit, "no path drawn at ({x}, {y}), off the cue's line");
}

/// A practice game's record: the scene's layout, then `strike`; and the game after them.
fn practice_record(scene: &Scene, strike: Strike) -> (Game, GameRecord) {
    let mut game = Game::new(Variant::Practice, Settings::offline(), 1);
    let mut record = GameRecord::of(&game);
    for command in [
        Command::LoadLayout {
            balls: breakshot_shared::rules::layout_from_scene(scene).expect("a layout"),
        },
        Command::Shot { strike, call: None },
    ] {
        let seat = game.to_move();
        let verdict = game.apply(seat, &command).expect("accepted");
        record.push(seat, command, verdict.shot.map(|s| s.hash));
    }
    (game, record)
}

/// The jump scene played as a practice game (its layout, then its shot).
struct Jump {
    /// The game after the shot, and its record.
    game: Game,
    record: GameRecord,
    /// The shot's strike and where the cue ball stood.
    strike: Strike,
    start: DVec2,
    /// The frame at which a replay shows the cue ball highest (the replay steps as the window
    /// does, 1/60 s a frame), and the cue ball then.
    frame: u32,
    best: BallState,
}

impl Jump {
    /// The window's screenshot of the jump's replay (`view` the options before `replay`) at
    /// the frame the cue ball is highest; None if there is no `xvfb-run`.
    fn shown(&self, view: &[&str]) -> Option<Picture> {
        let args = [view, &["replay"]].concat();
        screenshot_at("jump.rec", &self.record.encode(), &args, self.frame)
    }

    /// The layout of the 1280x720 window's table after the shot.
    fn layout(&self) -> Layout {
        Layout::new(
            1280.0,
            720.0,
            Frame::new(self.game.table(), self.game.balls()),
        )
    }
}

/// The jump scene played, with the frame its cue ball is highest at; fails the test unless
/// the ball then rises more than `radii` ball radii off the cloth.
fn jump_at_its_highest(radii: f64) -> Jump {
    let scene = Scene::from_json(JUMP).expect("valid scene");
    let shot = scene.to_shot().expect("valid shot");
    let strike = shot.strike.expect("a strike").1;
    let (game, record) = practice_record(&scene, strike);
    let mut viewer = ReplayViewer::new(record.clone()).expect("a record of this version");
    let (mut frame, mut best) = (0u32, BallState::at_rest(DVec2::ZERO));
    for n in 1..=400 {
        viewer.tick(1.0 / 60.0);
        let cue = viewer.balls()[0];
        if cue.lift > best.lift {
            (frame, best) = (n, cue);
        }
    }
    assert!(
        best.lift > radii * Params::default().ball_radius,
        "the cue ball rises only {} m",
        best.lift
    );
    Jump {
        game,
        record,
        strike,
        start: shot.balls[0].pos,
        frame,
        best,
    }
}

#[test]
fn a_replayed_jump_shows_the_ball_in_flight_bigger_with_its_shadow_on_the_cloth() {
    let jump = jump_at_its_highest(0.5);
    let (strike, best) = (jump.strike, jump.best);
    let r_m = Params::default().ball_radius;

    let Some(pic) = jump.shown(&[]) else {
        return;
    };
    let layout = jump.layout();
    side_view_shows(&pic, &layout, strike.elevation_deg);
    let r = layout.px(r_m);
    let air = flight(best.lift, r_m);
    let [x, y] = layout.to_screen(best.pos);
    // The ball is drawn bigger than on the cloth: white beyond its resting radius (up and
    // left, away from the shadow) ...
    let reach = 0.5 * (1.0 + air.scale as f32) * r;
    for (dx, dy) in [(-reach, 0.0), (0.0, -reach)] {
        let got = pic.at(x + dx, y + dy);
        assert!(
            shaded(got, CUE_BALL, 30.0),
            "no ball at {reach} px ({} R at rest) from its centre: {got:?}",
            reach / r
        );
    }
    // ... and its shadow lies on the cloth beyond it, down and right.
    let [sx, sy] = [x + air.shadow[0] as f32 * r, y + air.shadow[1] as f32 * r];
    let apart = ((sx - x).powi(2) + (sy - y).powi(2)).sqrt();
    assert!(
        apart > air.scale as f32 * r + 2.0,
        "the shadow is under the ball"
    );
    let got = pic.at(sx, sy);
    let sum = |c: Rgb| c.iter().map(|&v| v as f32).sum::<f32>();
    assert!(
        sum(got) < 0.9 * sum(CLOTH) && got.iter().zip(CLOTH).all(|(&g, c)| g <= c),
        "no shadow at ({sx}, {sy}): {got:?}"
    );
    // Beyond the shadow, the cloth.
    let far = pic.at(sx + 2.0 * r, sy + 2.0 * r);
    assert!(close(far, CLOTH, 8), "cloth beyond the shadow: {far:?}");
}

/// A screenshot of `breakshot ARGS` after `frames` frames, without input files; None if there
/// is no `xvfb-run` (the reason is printed).
fn screenshot_of(name: &str, args: &[&str], frames: u32) -> Option<Picture> {
    let dir = breakshot_testkit::scratch(&format!("window-{name}"));
    let out = dir.path().join("out.png");
    let args: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    ran_to_picture(&args, &out, frames)
}

/// The computer at level 1 breaking rack 4 of 8-ball.
const THE_COMPUTER_BREAKS: [&str; 7] = [
    "vs-computer",
    "--level",
    "1",
    "--break",
    "computer",
    "--seed",
    "4",
];

#[test]
fn the_computer_thinks_then_breaks_and_the_break_is_shown() {
    let args = THE_COMPUTER_BREAKS;
    let rack = eight_ball(Settings::offline(), 4);
    let ids: Vec<String> = (0..rack.balls().len())
        .map(|n| if n == 0 { "cue".into() } else { n.to_string() })
        .collect();
    let ids: Vec<&str> = ids.iter().map(|s| s.as_str()).collect();
    // Frame 10 is inside the time the thinking is shown: the rack stands, and the words
    // say so.
    let Some(thinking) = screenshot_of("thinking", &args, 10) else {
        return;
    };
    let layout = Layout::new(1280.0, 720.0, Frame::new(rack.table(), rack.balls()));
    balls_are_drawn(&thinking, &layout, &ids, rack.balls());
    // The words are white on the notice line under the trays, off the cloth.
    let n = layout.notice;
    let white_words = |pic: &Picture| {
        (0..n.w as u32)
            .flat_map(|x| (0..n.h as u32).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let p = pic.at(n.x + x as f32, n.y + y as f32);
                p.iter().all(|&v| v > 200)
            })
            .count()
    };
    // A ball is in its rack spot when its colour is seen left of the spot's centre (clear of
    // the number).
    let r = layout.px(Params::default().ball_radius);
    let in_place = |pic: &Picture| {
        ids.iter()
            .zip(rack.balls())
            .skip(1)
            .filter(|(id, b)| {
                let [x, y] = layout.to_screen(b.pos);
                shaded(pic.at(x - 0.75 * r, y), ball_look(id).color, 14.0)
            })
            .count()
    };
    assert_eq!(in_place(&thinking), 15);
    let white = white_words(&thinking);
    assert!(white > 40, "no thinking line: {white} white points");

    // Five seconds later the computer has broken: the balls have left the rack, and the
    // words are gone.
    let Some(broken) = screenshot_of("broken", &args, 300) else {
        return;
    };
    let in_place = in_place(&broken);
    assert!(in_place <= 3, "{in_place} of 15 balls still racked");
    let white = white_words(&broken);
    assert!(
        white < 5,
        "the thinking line is still shown: {white} white points"
    );
}

#[test]
fn a_three_cushion_game_shows_the_carom_table_and_its_three_balls() {
    let Some(pic) = screenshot_of("carom", &["local", "--mode", "3cushion", "--seed", "1"], 4)
    else {
        return;
    };
    let game = Game::new(Variant::three_cushion(), Settings::offline(), 1);
    let layout = pic.layout(Frame::new(game.table(), game.balls()));
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
    let ids = game.ball_ids();
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

/// In a small window every menu button is inside it and every label inside its button.
#[test]
fn the_menu_fits_a_small_window() {
    let dir = breakshot_testkit::scratch("window-menu");
    let out = dir.path().join("out.png");
    let Some(run) = window_sized(&[], &out, 3, (640, 480)) else {
        return;
    };
    assert_ran(&run);
    let pic = Picture::sized(&out, (640, 480));
    const FILL: Rgb = [24, 104, 74];
    let buttons = breakshot_client::view::menu_buttons(640.0, 480.0, 10);
    for b in &buttons {
        let mid = b.y + 0.5 * b.h;
        // The button is drawn, and no letter reaches its sides.
        assert!(close(pic.at(b.x + 0.5 * b.w, b.y + 3.0), FILL, 30), "{b:?}");
        for x in [b.x + 4.0, b.x + 7.0, b.x + b.w - 7.0, b.x + b.w - 4.0] {
            for dy in [-4.0, 0.0, 4.0] {
                let got = pic.at(x, mid + dy);
                assert!(
                    close(got, FILL, 30),
                    "a label reaches the side of {b:?}: {got:?}"
                );
            }
        }
    }
}

/// A player whose game window closed chooses *Resume game* in the menu: the window takes
/// the remembered seat back, and the opponent is told the player is back.
#[test]
#[cfg(feature = "host")]
fn resume_game_in_the_menu_takes_the_remembered_seat_back() {
    use breakshot_client::net::SeatStore;
    use breakshot_shared::rules::Seat;

    let (Some(xvfb), Some(_)) = (find_in_path("xvfb-run"), find_in_path("xdotool")) else {
        eprintln!("skipped: xvfb-run and xdotool are needed (apt-get install xvfb xdotool)");
        return;
    };
    let dir = breakshot_testkit::scratch("window-resume");
    let seats = dir.path().join("client");
    let server = common::loopback_server(dir.path().join("server"));
    let invite = server.loopback_invite();
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    // Ann hosts; Bob joined from this computer, which kept his seat, then his window closed.
    let (mut ann, room, token) = within(&runtime, "the host's seat", left_by_bob(&invite, "ann"));
    SeatStore::new(&seats)
        .save(&invite.with_room(room), token)
        .expect("the seat remembered");

    // The menu, in a real window: click its first button, "Resume game".
    let first = breakshot_client::view::menu_buttons(1280.0, 720.0, 10)[0];
    let (x, y) = (first.x + 0.5 * first.w, first.y + 0.5 * first.h);
    let script = format!(
        "\"$0\" --data \"$1\" --size 1280x720 & \
         wid=$(timeout 60 xdotool search --sync --name Breakshot | head -n 1) && sleep 1 && \
         xdotool mousemove --window \"$wid\" {x} {y} click 1 && wait"
    );
    let _window = breakshot_testkit::Spawned::start(
        Process::new(xvfb)
            .args(["-a", "-f"])
            .arg(dir.path().join("Xauthority"))
            .args(["-s", "-screen 0 1280x800x24", "sh", "-c", &script])
            .arg(env!("CARGO_BIN_EXE_breakshot"))
            .arg(&seats)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null()),
    );
    let back = within(&runtime, "Bob's return", async move {
        next(&mut ann, |m| matches!(m, ServerMessage::PlayerBack { .. })).await
    });
    assert_eq!(back, ServerMessage::PlayerBack { seat: Seat::B });
    drop(server);
}

/// An invite whose fingerprint is not the server's says so in plain words, wrapped inside a
/// small window rather than cut off at its edge.
#[test]
#[cfg(feature = "host")]
fn a_wrong_fingerprint_is_said_in_words_that_fit_the_window() {
    use breakshot_shared::protocol::Fingerprint;

    let dir = breakshot_testkit::scratch("window-fingerprint");
    let server = common::loopback_server(dir.path().join("server"));
    let mut invite = server.loopback_invite();
    invite.fingerprint = Fingerprint([0xab; 32]);
    invite.room = Some(RoomCode::parse("ABCDEFGH").expect("a room code"));
    let out = dir.path().join("out.png");
    let text = invite.to_string();
    let data = dir.path().join("client");
    let args = joining(&text, &data);
    let Some(run) = window_sized(&args, &out, 3, (640, 480)) else {
        return;
    };
    drop(server);
    assert_ran(&run);
    let pic = Picture::sized(&out, (640, 480));
    let (width, height) = (pic.width, pic.height);
    // Light text rows under the headline: the reason takes two lines, and no letter touches
    // the window's right edge.
    let lit = |y: u32, xs: std::ops::Range<u32>| {
        xs.into_iter()
            .any(|x| pic.at(x as f32, y as f32).iter().all(|&v| v > 150))
    };
    let rows = (100..200).filter(|&y| lit(y, 0..width)).count();
    assert!(
        rows > 20,
        "{rows} rows of text: the reason is not on two lines"
    );
    assert!(
        !(0..height).any(|y| lit(y, width - 12..width)),
        "text runs into the window's edge"
    );
}

#[test]
fn a_join_to_a_port_with_no_game_gives_up_within_seconds_naming_the_address_and_what_to_check() {
    let dir = breakshot_testkit::scratch("window-unreachable");
    // A port nothing listens on: bound by this test, then let go.
    let port = std::net::UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .expect("a free port")
        .port();
    let text = format!("breakshot://127.0.0.1:{port}/ABCDEFGH#{}", "ab".repeat(32));
    let out = dir.path().join("out.png");
    let data = dir.path().join("client");
    let args = joining(&text, &data);
    let started = std::time::Instant::now();
    // The screenshot waits for the connection's outcome, so the run ends when it gives up.
    let Some(run) = window_sized(&args, &out, 3, (640, 480)) else {
        return;
    };
    let waited = started.elapsed();
    assert_ran(&run);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains(&format!("cannot reach the game at 127.0.0.1:{port}")),
        "the terminal names the address: {err}"
    );
    assert!(err.contains("UDP port is open"), "and what to check: {err}");
    // About 5 s of trying, plus starting a window on a loaded machine; it used to take
    // minutes.
    assert!(
        waited < Duration::from_secs(30),
        "gave up only after {waited:?}"
    );
}

/// Whether `got` is `want` lit, allowing for the 3-D view's glints: the same colour scaled by
/// one factor up to 1.4, within 30 per channel.
fn glinting(got: Rgb, want: Rgb) -> bool {
    let dot = |a: Rgb, b: Rgb| {
        a.iter()
            .zip(b)
            .map(|(&x, y)| x as f32 * y as f32)
            .sum::<f32>()
    };
    let k = (dot(got, want) / dot(want, want).max(1.0)).clamp(0.3, 1.4);
    got.iter()
        .zip(want)
        .all(|(&x, y)| (x as f32 - k * y as f32).abs() <= 30.0)
}

/// Each ball's colour, shaded, around its centre as `camera` projects it: a few points left
/// and right of the middle and above it (clear of the cue stick and the ghost ball below, the
/// aim line through the middle and the number spot on top); three of four must show it.
fn balls_are_drawn_in_3d(pic: &Picture, camera: &Camera, ids: &[&str], balls: &[BallState]) {
    let radius = Params::default().ball_radius;
    for (id, state) in ids.iter().zip(balls) {
        let centre = state.pos.extend(radius);
        let [x, y] = camera.project(centre).expect("in front of the camera");
        let r = camera.pixels_at(centre, radius);
        let look = ball_look(id);
        let seen: Vec<Rgb> = [(-0.3, -0.15), (0.3, -0.15), (-0.3, -0.45), (0.3, -0.45)]
            .iter()
            .map(|(dx, dy)| pic.at(x + dx * r, y + dy * r))
            .collect();
        let hits = seen.iter().filter(|&&c| glinting(c, look.color)).count();
        assert!(
            hits >= 3,
            "ball {id} at ({x}, {y}) r {r}: saw {seen:?}, want {:?} shaded",
            look.color
        );
    }
}

#[test]
fn the_3d_view_shows_the_cloth_the_rails_and_the_balls_where_the_physics_puts_them() {
    let Some((pic, scene, shot)) =
        scene_screenshot("scene.json", SCENE, &["--view", "3d", "practice"])
    else {
        return;
    };
    let layout = pic.layout(Frame::new(shot.table, &shot.balls));
    let radius = Params::default().ball_radius;
    // The window opens behind the cue ball along the scene's aim, as the camera code says.
    let camera = Orbit::default().camera(&layout, shot.balls[0].pos, Aim::default().dir(), radius);

    // The cloth: points of the playing surface clear of the balls and the aim line, in the
    // part of the window the table is drawn in (not under the tray).
    let (mut cloth, mut total) = (0, 0);
    for i in 1..12 {
        for j in 1..24 {
            let p = DVec2::new(1.27 * i as f64 / 12.0, 2.54 * j as f64 / 24.0);
            let clear = shot
                .balls
                .iter()
                .all(|b| (b.pos - p).length() > 3.0 * radius)
                && (p.x - shot.balls[0].pos.x).abs() > 0.05;
            let Some(px) = camera.project(p.extend(0.0)) else {
                continue;
            };
            if !clear || px[1] >= layout.tray.y || px[0] >= layout.elevation_view.x || px[1] < 0.0 {
                continue;
            }
            total += 1;
            cloth += shaded(pic.at(px[0], px[1]), CLOTH, 8.0) as u32;
        }
    }
    assert!(total > 100, "only {total} points of the cloth in view");
    assert!(
        cloth * 100 >= total * 95,
        "cloth at {cloth} of {total} points"
    );

    // The rails: the wood's top and the cushions' tops along both long sides, between the
    // diamonds.
    let h = Params::default().cushion_height;
    let (mut wood, mut cushion, mut seen) = (0, 0, 0);
    for k in 2..8 {
        let y = 2.54 * (k as f64 + 0.5) / 8.0;
        for (wood_x, cushion_x) in [(-0.09, -0.02), (1.27 + 0.09, 1.27 + 0.02)] {
            let (Some(w), Some(c)) = (
                camera.project(DVec3::new(wood_x, y, h)),
                camera.project(DVec3::new(cushion_x, y, h)),
            ) else {
                continue;
            };
            if w[0] < 0.0 || w[0] >= layout.elevation_view.x || w[1] >= layout.tray.y {
                continue;
            }
            seen += 1;
            wood += shaded(pic.at(w[0], w[1]), RAIL_WOOD, 12.0) as u32;
            cushion += shaded(pic.at(c[0], c[1]), CUSHION, 12.0) as u32;
        }
    }
    assert!(seen >= 8, "only {seen} rail points in view");
    assert_eq!(
        (wood, cushion),
        (seen, seen),
        "wood and cushion tops of {seen} points"
    );

    let ids: Vec<&str> = scene.balls.iter().map(|b| b.id.as_str()).collect();
    balls_are_drawn_in_3d(&pic, &camera, &ids, &shot.balls);
    // Not the flat picture: where the top-down view draws the blue 2 is cloth here.
    let flat = layout.to_screen(shot.balls[2].pos);
    assert!(!shaded(
        pic.at(flat[0], flat[1]),
        ball_look("2").color,
        40.0
    ));
}

#[test]
fn the_window_opens_on_the_view_chosen_last_unless_told_otherwise() {
    let dir = breakshot_testkit::scratch("window-view-choice");
    let data = dir.path().join("data");
    std::fs::create_dir_all(&data).expect("data directory");
    // What pressing V into the 3-D view leaves behind.
    std::fs::write(data.join(breakshot_client::memory::VIEW_FILE), "3d").expect("written");
    let scene = dir.path().join("scene.json");
    std::fs::write(&scene, SCENE).expect("scene written");
    let parsed = Scene::from_json(SCENE).expect("valid scene");
    let shot = parsed.to_shot().expect("valid shot");
    let layout = Layout::new(1280.0, 720.0, Frame::new(shot.table, &shot.balls));
    let radius = Params::default().ball_radius;
    let camera = Orbit::default().camera(&layout, shot.balls[0].pos, Aim::default().dir(), radius);
    let ids: Vec<&str> = parsed.balls.iter().map(|b| b.id.as_str()).collect();
    let run = |extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args: Vec<&OsStr> = vec!["--data".as_ref(), data.as_os_str()];
        args.extend(extra.iter().map(OsStr::new));
        args.extend(["practice".as_ref(), scene.as_os_str()]);
        let run = window(&args, &out)?;
        assert_ran(&run);
        Some(picture(&out))
    };
    let Some(remembered) = run(&[], "remembered.png") else {
        return;
    };
    balls_are_drawn_in_3d(&remembered, &camera, &ids, &shot.balls);
    let Some(told) = run(&["--view", "top"], "told.png") else {
        return;
    };
    balls_are_drawn(&told, &layout, &ids, &shot.balls);
    // Being told is not a choice: the remembered view stays.
    let kept = std::fs::read_to_string(data.join(breakshot_client::memory::VIEW_FILE));
    assert_eq!(kept.expect("still there"), "3d");
}

#[test]
fn the_3d_view_shows_a_jumping_ball_at_its_height_above_the_cloth() {
    // The jump scene replayed, as in the top-down test above.
    let jump = jump_at_its_highest(0.8);
    let Some(pic) = jump.shown(&["--view", "3d"]) else {
        return;
    };
    // Until the shot starts the camera looks at the cue ball along the shot.
    let radius = Params::default().ball_radius;
    let camera = Orbit::default().camera(&jump.layout(), jump.start, jump.strike.dir, radius);
    let flying = jump.best.pos.extend(radius + jump.best.lift);
    let [x, y] = camera.project(flying).expect("in view");
    let r = camera.pixels_at(flying, radius);
    // The ball is where its height puts it: white around its centre and near its top ...
    for (dx, dy) in [(-0.3, -0.2), (0.3, -0.2), (0.0, -0.75)] {
        let got = pic.at(x + dx * r, y + dy * r);
        assert!(
            glinting(got, CUE_BALL),
            "no ball at ({dx}, {dy}) R: {got:?}"
        );
    }
    // ... and not where it would be on the cloth: below it, the cloth (or the shadow).
    let [lx, ly] = camera
        .project(jump.best.pos.extend(radius))
        .expect("in view");
    let low = pic.at(
        lx,
        ly + 0.6 * camera.pixels_at(jump.best.pos.extend(radius), radius),
    );
    assert!(
        !glinting(low, CUE_BALL),
        "a ball on the cloth under the flying one: {low:?}"
    );
}

/// Runs `breakshot ARGS --screenshot OUT --frames FRAMES` under a virtual display while
/// `xdotool` plays `keys` on its window (one xdotool command a line, `$wid` the window, a
/// short pause before each); None if xvfb-run or xdotool is missing (the reason is printed).
fn played(args: &[&OsStr], out: &Path, frames: u32, keys: &[&str]) -> Option<Output> {
    played_sized(args, out, frames, keys, (1280, 720))
}

/// [`played`] in a window of `size`, with a fresh data directory.
fn played_sized(
    args: &[&OsStr],
    out: &Path,
    frames: u32,
    keys: &[&str],
    size: (u32, u32),
) -> Option<Output> {
    let data = breakshot_testkit::scratch("window-data");
    let patience = Duration::from_secs(120);
    common::screen::played(args, out, frames, keys, size, data.path(), patience)
}

/// [`played_sized`] on `breakshot host` against the computer, its data and its screenshot
/// (`out.png`) in `dir`: what the window reported, once it has run to its end.
#[cfg(feature = "host")]
fn against_the_computer(
    dir: &Path,
    frames: u32,
    keys: &[&str],
    size: (u32, u32),
) -> Option<Vec<String>> {
    let args = hosting_the_computer(&dir.join("data"));
    let args: Vec<&OsStr> = args.iter().map(|a| a.as_os_str()).collect();
    let run = played_sized(&args, &dir.join("out.png"), frames, keys, size)?;
    assert_ran(&run);
    Some(reports(&run))
}

#[cfg(feature = "host")]
#[test]
fn m_and_the_brackets_typed_in_the_chat_line_are_said_not_taken_as_sound_keys() {
    let dir = breakshot_testkit::scratch("window-chat");
    // T opens the chat line, "m[]" is typed and sent with Enter; then M, outside the line,
    // mutes.
    let keys = [
        "sleep 2",
        "key --window \"$wid\" t",
        "type --window \"$wid\" 'm[]'",
        "key --window \"$wid\" Return",
        "key --window \"$wid\" m",
    ];
    let Some(said) = against_the_computer(dir.path(), 480, &keys, (1280, 720)) else {
        return;
    };
    let sent = said.iter().position(|l| l == "chat sent m[]");
    let muted = said.iter().position(|l| l == "sound muted");
    assert!(
        matches!((sent, muted), (Some(s), Some(m)) if s < m),
        "the line is said, then M mutes: {said:?}"
    );
    assert_eq!(
        said.iter().filter(|l| l.starts_with("sound")).count(),
        1,
        "only the M outside the line turned the sound: {said:?}"
    );
}

/// A live game that ends shows "You lost" in its banner under the trays, not over the
/// cloth: the player concedes against the computer (Esc, then C).
#[cfg(feature = "host")]
#[test]
fn a_game_that_ends_shows_its_banner_off_the_cloth() {
    // Small, common and tall windows.
    for size in [(640, 480), (1280, 720), (720, 1280)] {
        let dir = breakshot_testkit::scratch("window-banner");
        let keys = [
            "sleep 2",
            "key --window \"$wid\" Escape",
            "key --window \"$wid\" c",
        ];
        let Some(said) = against_the_computer(dir.path(), 420, &keys, size) else {
            return;
        };
        assert!(
            said.iter().any(|l| l.starts_with("game over")),
            "{size:?}: the game ended: {said:?}"
        );
        let pic = Picture::sized(&dir.path().join("out.png"), size);
        let rack = eight_ball(Settings::online(), 0);
        let (w, h) = (size.0 as f32, size.1 as f32);
        let layout = Layout::new(w, h, Frame::new(rack.table(), rack.balls()));
        // The headline's yellow: in the banner's box, and nowhere on the cloth.
        let yellow = |r: breakshot_client::view::Rect| {
            (0..r.w as u32)
                .flat_map(|x| (0..r.h as u32).map(move |y| (x, y)))
                .filter(|&(x, y)| close(pic.at(r.x + x as f32, r.y + y as f32), [253, 249, 0], 40))
                .count()
        };
        assert!(
            yellow(layout.banner) > 50,
            "{size:?}: no headline in the banner's box"
        );
        assert_eq!(
            yellow(layout.cloth),
            0,
            "{size:?}: yellow text on the cloth"
        );
    }
}

#[test]
fn v_opens_the_3d_view_remembers_it_and_the_mouse_aims_through_the_camera() {
    let dir = breakshot_testkit::scratch("window-v");
    let (data, scene, out) = (
        dir.path().join("data"),
        dir.path().join("scene.json"),
        dir.path().join("out.png"),
    );
    std::fs::write(&scene, SCENE).expect("scene written");
    let parsed = Scene::from_json(SCENE).expect("valid scene");
    let shot = parsed.to_shot().expect("valid shot");
    let layout = Layout::new(1280.0, 720.0, Frame::new(shot.table, &shot.balls));
    let radius = Params::default().ball_radius;
    let cue = shot.balls[0].pos;
    // The player presses V, then points at the blue 2 as the 3-D view first shows it.
    let opened = Orbit::default().camera(&layout, cue, Aim::default().dir(), radius);
    let [x, y] = opened
        .project(shot.balls[2].pos.extend(radius))
        .expect("the 2 in view")
        .map(f32::round);
    let args = [
        OsStr::new("--data"),
        data.as_os_str(),
        OsStr::new("practice"),
        scene.as_os_str(),
    ];
    let keys = [
        "key --window \"$wid\" v".to_string(),
        "mousemove --window \"$wid\" 200 200".to_string(),
        format!("mousemove --window \"$wid\" {x} {y}"),
    ];
    let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
    let Some(run) = played(&args, &out, 600, &keys) else {
        return;
    };
    assert_ran(&run);
    let kept = std::fs::read_to_string(data.join(breakshot_client::memory::VIEW_FILE));
    assert_eq!(kept.expect("the view remembered").trim(), "3d");
    // The cue points at the spot under the mouse, and the camera has turned to look along it:
    // the 2 is drawn where that camera puts it, straight ahead of the cue ball.
    let spot = opened.onto_plane([x, y], radius).expect("on the cloth");
    let aimed = Orbit::default().camera(&layout, cue, spot - cue, radius);
    let pic = picture(&out);
    let ids: Vec<&str> = parsed.balls.iter().map(|b| b.id.as_str()).collect();
    balls_are_drawn_in_3d(&pic, &aimed, &ids[2..3], &shot.balls[2..3]);
    let [bx, _] = aimed
        .project(shot.balls[2].pos.extend(radius))
        .expect("in view");
    let [cx, _] = aimed.project(cue.extend(radius)).expect("in view");
    assert!(
        (bx - cx).abs() < 3.0,
        "the 2 is straight ahead: {bx} vs {cx}"
    );
}

#[test]
fn l_shows_the_cue_ball_s_trail_after_the_shot() {
    const CUT: &str = include_str!("../scenes/cut-shot.json");
    let dir = breakshot_testkit::scratch("window-trail");
    let (scene, out) = (dir.path().join("scene.json"), dir.path().join("out.png"));
    std::fs::write(&scene, CUT).expect("scene written");
    let args = [OsStr::new("practice"), scene.as_os_str()];
    let keys = ["key --window \"$wid\" l", "key --window \"$wid\" space"];
    let Some(run) = played(&args, &out, 240, &keys) else {
        return;
    };
    assert_ran(&run);
    let pic = picture(&out);
    let parsed = Scene::from_json(CUT).expect("valid scene");
    let shot = parsed.to_shot().expect("valid shot");
    let layout = Layout::new(1280.0, 720.0, Frame::new(shot.table, &shot.balls));
    let outcome = Simulator::new().run(&shot).expect("valid shot").clone();
    // After the cue ball meets the 3, where neither the cue stick nor the next shot's aids
    // are drawn: the trail's warm colour over the cloth (white aid lines are not warm).
    let contact = outcome
        .events
        .iter()
        .find(|e| {
            matches!(
                e.kind,
                EventKind::BallBall { a: 0, .. } | EventKind::BallBall { b: 0, .. }
            )
        })
        .expect("the cue ball meets the 3")
        .t;
    let warm = on_the_trail(
        &pic,
        &layout,
        &outcome,
        0,
        [0.2, 0.5, 0.8].map(|dt| contact + dt),
    );
    assert!(
        warm >= 2,
        "the trail is at {warm} of 3 points after the contact"
    );
}

/// How many of ball `ball`'s places at `times` in `outcome` the picture shows in the trail's
/// warm colour over the cloth.
fn on_the_trail(
    pic: &Picture,
    layout: &Layout,
    outcome: &Outcome,
    ball: usize,
    times: [f64; 3],
) -> usize {
    times
        .into_iter()
        .filter(|&t| {
            let [x, y] = layout.to_screen(outcome.state_at(ball, t).pos);
            let c = pic.at(x, y);
            c[0] >= CLOTH[0] + 25 && c[1] >= c[2] + 35
        })
        .count()
}

#[test]
fn a_practice_scratch_is_put_back_by_the_rules_where_the_cue_ball_started() {
    // The scene's strike sends the cue ball straight into the bottom-left pocket.
    const SCRATCH: &str = r#"{"balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[1.0,2.0]}],
        "strike":{"ball":"cue","speed":3.0,"angle_deg":225}}"#;
    let dir = breakshot_testkit::scratch("window-scratch");
    let (scene, out) = (dir.path().join("scene.json"), dir.path().join("out.png"));
    std::fs::write(&scene, SCRATCH).expect("scene written");
    let parsed = Scene::from_json(SCRATCH).expect("valid scene");
    let shot = parsed.to_shot().expect("valid shot");
    let outcome = Simulator::new().run(&shot).expect("valid shot").clone();
    assert_eq!(
        outcome.finals[0].motion,
        MotionState::Pocketed,
        "the shot must scratch"
    );
    let args = [OsStr::new("practice"), scene.as_os_str()];
    let Some(run) = played(&args, &out, 300, &["key --window \"$wid\" space"]) else {
        return;
    };
    assert_ran(&run);
    let pic = picture(&out);
    let layout = Layout::new(1280.0, 720.0, Frame::new(shot.table, &shot.balls));
    // The cue ball is back on its spot, where the practice rules put it.
    balls_are_drawn(&pic, &layout, &["cue"], &shot.balls[..1]);
    let game = breakshot_shared::rules::Game::practice(&parsed).expect("a practice table");
    let mut after = game.clone();
    after
        .apply(
            breakshot_shared::rules::Seat::A,
            &Command::Shot {
                strike: shot.strike.expect("a strike").1,
                call: None,
            },
        )
        .expect("a legal shot");
    assert_eq!(
        after.balls()[0],
        shot.balls[0],
        "the rules put the cue ball back"
    );
}

#[test]
fn the_cue_is_seen_going_through_the_cue_ball_as_a_shot_starts() {
    const CUT: &str = include_str!("../scenes/cut-shot.json");
    let scene = Scene::from_json(CUT).expect("valid scene");
    let shot = scene.to_shot().expect("valid shot");
    let strike = shot.strike.expect("a strike").1;
    let (game, record) = practice_record(&scene, strike);
    // The frames the window shows the shot's start and, later, the shot under way.
    let mut viewer = ReplayViewer::new(record.clone()).expect("a record of this version");
    let started = (1..=400u32)
        .find(|_| {
            viewer.tick(1.0 / 60.0);
            viewer.shot().is_some()
        })
        .expect("the shot starts");
    let layout = Layout::new(1280.0, 720.0, Frame::new(game.table(), game.balls()));
    let radius = Params::default().ball_radius;
    let cue = shot.balls[0].pos;
    let dir = strike.dir.normalize();
    // Wood along the line behind where the cue ball was, clear of its shadow.
    let wood = |pic: &Picture| {
        [4.0, 8.0, 12.0]
            .iter()
            .filter(|&&k| {
                let [x, y] = layout.to_screen(cue - dir * k * radius);
                close(pic.at(x, y), CUE_WOOD, 30)
            })
            .count()
    };
    let Some(striking) = screenshot_at("cut.rec", &record.encode(), &["replay"], started + 2)
    else {
        return;
    };
    assert_eq!(wood(&striking), 3, "no cue at the strike");
    let Some(later) = screenshot_at("cut.rec", &record.encode(), &["replay"], started + 30) else {
        return;
    };
    assert_eq!(wood(&later), 0, "the cue is still shown half a second on");
}

#[test]
fn a_three_cushion_shot_struck_with_the_yellow_leaves_its_trail_on_the_yellow() {
    let start = Game::new(Variant::three_cushion(), Settings::offline(), 1);
    let mut game = start.clone();
    let mut record = GameRecord::of(&game);
    let strike = |dir: DVec2, speed: f64| Strike {
        speed,
        dir: dir.normalize(),
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    };
    // The white rolls a little way from the yellow and scores nothing: the yellow is to move.
    let mut outcome = None;
    for (dir, speed) in [(DVec2::new(1.0, 0.0), 0.3), (DVec2::new(0.25, 1.0), 2.5)] {
        let seat = game.to_move();
        let command = Command::Shot {
            strike: strike(dir, speed),
            call: None,
        };
        let verdict = game.apply(seat, &command).expect("accepted");
        record.push(seat, command, verdict.shot.map(|s| s.hash));
        outcome = verdict.outcome;
        if record.entries.len() == 1 {
            assert_eq!(game.cue_ball(), 1, "the yellow is to shoot next");
        }
    }
    let outcome = outcome.expect("the yellow's shot was simulated");
    // The frame 0.6 s into the yellow's shot, as the window steps a replay.
    let mut viewer = ReplayViewer::new(record.clone()).expect("a record of this version");
    let started = (1..=2000u32)
        .find(|_| {
            viewer.tick(1.0 / 60.0);
            // The white's shot is committed once shown: the yellow's is the one under way.
            viewer.position().0 == 1 && viewer.shot().is_some()
        })
        .expect("the yellow's shot starts");
    let dir = breakshot_testkit::scratch("window-yellow-trail");
    let (file, out) = (dir.path().join("carom.rec"), dir.path().join("out.png"));
    std::fs::write(&file, record.encode()).expect("record written");
    let args = [OsStr::new("replay"), file.as_os_str()];
    let Some(run) = played(&args, &out, started + 36, &["key --window \"$wid\" l"]) else {
        return;
    };
    assert_ran(&run);
    let pic = picture(&out);
    let layout = Layout::new(1280.0, 720.0, Frame::new(start.table(), start.balls()));
    // Where the yellow went in its shot's first 0.3 s, long gone from there: the trail's
    // warm colour over the cloth.
    let warm = on_the_trail(&pic, &layout, &outcome, 1, [0.1, 0.2, 0.3]);
    assert!(
        warm >= 2,
        "the trail is at {warm} of 3 points the yellow passed"
    );
}

/// Whether a pixel is the white of the status line (the panel's titles are light grey).
fn white_text(p: Rgb) -> bool {
    p.iter().all(|&v| v > 240)
}

/// Whether a pixel is lit text of any shade over the dark background.
fn lit(p: Rgb) -> bool {
    p.iter().all(|&v| v > 150)
}

/// The columns of `pic` in `xs` with a pixel passing `is_text` in the rows of `r`.
fn text_columns(
    pic: &Picture,
    r: breakshot_client::view::Rect,
    xs: std::ops::Range<u32>,
    is_text: fn(Rgb) -> bool,
) -> Vec<u32> {
    let rows = r.y.max(0.0) as u32..((r.y + r.h) as u32).min(pic.height);
    xs.filter(|&x| rows.clone().any(|y| is_text(pic.at(x as f32, y as f32))))
        .collect()
}

#[test]
fn in_a_small_window_the_panel_title_fits_and_the_status_line_stays_out_of_the_panel() {
    let dir = breakshot_testkit::scratch("window-small");
    let out = dir.path().join("out.png");
    let data = dir.path().join("data");
    let args: Vec<&OsStr> = THE_COMPUTER_BREAKS
        .map(OsStr::new)
        .into_iter()
        .chain([OsStr::new("--data"), data.as_os_str()])
        .collect();
    let size = (640, 480);
    let Some(run) = window_sized(&args, &out, 4, size) else {
        return;
    };
    assert_ran(&run);
    let pic = Picture::sized(&out, size);
    let racked = eight_ball(Settings::offline(), 0);
    let layout = Layout::new(640.0, 480.0, Frame::new(racked.table(), racked.balls()));

    // The status line ("Computer (level 1) to break, cue ball in hand ...") is written in
    // its box, and none of its white reaches the panel beside the table.
    let status = layout.status;
    let inside = text_columns(&pic, status, 0..(status.x + status.w) as u32, white_text);
    assert!(
        inside.len() > 40,
        "no status line: {} columns",
        inside.len()
    );
    let panel_from = (layout.panel.x - 4.0) as u32;
    let over_panel = text_columns(&pic, status, panel_from..pic.width, white_text);
    assert!(
        over_panel.is_empty(),
        "the status line runs over the panel at x = {over_panel:?}"
    );

    // The panel's title ("Tip (resets, K)") is drawn whole: inside its box, clear of the
    // window's right edge.
    let title = layout.tip_title;
    let lit_columns = text_columns(&pic, title, panel_from..pic.width, lit);
    let (Some(&first), Some(&last)) = (lit_columns.first(), lit_columns.last()) else {
        panic!("no panel title drawn");
    };
    assert!(lit_columns.len() > 40, "title too small: {lit_columns:?}");
    assert!(
        first as f32 >= title.x && last as f32 <= title.x + title.w,
        "title from x = {first} to {last}, its box {title:?}"
    );
    assert!(
        last + 3 < pic.width,
        "the title reaches the window's edge at {last}"
    );
}
