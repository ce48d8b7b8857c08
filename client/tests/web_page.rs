//! The web client as a person meets it: the host runs `breakshot host` (the real program, in
//! a window under Xvfb) with the web bundle built, and a friend opens the link it prints in a
//! browser on a phone: the page joins the room, draws the table and the balls, and a finger
//! aims and shoots on the practice table. The page is the bundle `web/build.sh` makes, in
//! headless Chromium.
//!
//! Needs `xvfb-run`, the wasm32 target and Chromium; where one is missing the tests say why
//! and pass (CI installs them and requires the web and browser tests).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use breakshot_client::view::palette::{CLOTH, CUE_BALL};
use breakshot_client::view::{menu_buttons, Frame, Layout};
use breakshot_shared::rules::{EightBallRules, Game, Variant};
use breakshot_testkit::browser::{browser_or_skip, near, Browser, LaunchOptions, Page, Viewport};
use breakshot_testkit::web::{bundle, skip_web};
use breakshot_testkit::{read_line, scratch, Spawned, TempDir};

#[allow(dead_code)]
mod common;

use common::page::{
    events, keep_screenshot, said_starting, tapped_until, wait_for_event, wait_for_input, PATIENCE,
};

/// A ball's colours: strongly coloured, unlike the cloth, the wood and the text.
fn coloured(p: [u8; 4]) -> bool {
    let (hi, lo) = (p[..3].iter().max().copied(), p[..3].iter().min().copied());
    hi.zip(lo).is_some_and(|(h, l)| h as i32 - l as i32 > 120) && !near(p, CLOTH, 30)
}

/// `xvfb-run`, or None with the reason printed.
fn xvfb_run() -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    let found = std::env::split_paths(&path)
        .map(|d| d.join("xvfb-run"))
        .find(|p| p.is_file());
    if found.is_none() {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
    }
    found
}

/// A running `breakshot host` serving the web bundle, the invite and the link it printed, and
/// a browser to open the link in.
struct Hosted {
    browser: Browser,
    invite: String,
    link: String,
    // Kept to the end of the test: dropping them stops the host and removes its folder.
    _host: Spawned,
    _dir: TempDir,
}

/// The host for test `name`, or None with the reason printed where the bundle, `xvfb-run` or
/// the browser is missing.
fn hosted(name: &str) -> Option<Hosted> {
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => {
            skip_web("web_page", &why);
            return None;
        }
    };
    let dir = scratch(name);
    let (host, invite, link) = host(dir.path(), bundle)?;
    let browser = browser_or_skip(LaunchOptions::default())?;
    Some(Hosted {
        browser,
        invite,
        link,
        _host: host,
        _dir: dir,
    })
}

/// Where the scene's point `p` is on the screen, in the page's pixels.
fn on_screen(layout: &Layout, p: glam::DVec2) -> (f64, f64) {
    let [x, y] = layout.to_screen(p);
    (x as f64, y as f64)
}

/// `breakshot host` in a window, serving `bundle`; with the invite and the link it printed.
fn host(dir: &Path, bundle: &Path) -> Option<(Spawned, String, String)> {
    let xvfb = xvfb_run()?;
    let mut host = Spawned::start(
        Command::new(xvfb)
            .args(["-a", "-f"])
            .arg(dir.join("Xauthority"))
            .args(["-s", "-screen 0 1280x800x24"])
            .arg(env!("CARGO_BIN_EXE_breakshot"))
            .arg("--data")
            .arg(dir.join("data"))
            .args(["host", "--bind", "127.0.0.1:0", "--name", "Hostess"])
            .env("BREAKSHOT_WEB", bundle)
            .stdout(Stdio::piped())
            .stderr(Stdio::null()),
    );
    let out = host.child().stdout.take().expect("the host's output");
    let (invite, out) = read_line(out, PATIENCE);
    // The same reader: the second line may already be in its buffer.
    let (link, _out) = read_line(out, PATIENCE);
    Some((host, invite.trim().to_owned(), link.trim().to_owned()))
}

/// The most points of `points` on one row and on one column.
fn spans(points: &[(u32, u32)]) -> (usize, usize) {
    let mut rows = std::collections::HashMap::new();
    let mut columns = std::collections::HashMap::new();
    for (x, y) in points {
        *rows.entry(y).or_insert(0) += 1;
        *columns.entry(x).or_insert(0) += 1;
    }
    let most = |m: std::collections::HashMap<_, usize>| m.into_values().max().unwrap_or(0);
    (most(rows), most(columns))
}

/// The page on its own (no room) on a phone, with its practice table open from the menu;
/// with the table's layout and rack.
fn open_practice(hosted: &Hosted) -> (Page<'_>, Layout, Game) {
    let page_url = hosted.link.split('?').next().expect("the page's address");
    let phone = Viewport::phone();
    let mut page = hosted
        .browser
        .open(page_url, phone)
        .expect("the page opens");
    wait_for_event(&mut page, "screen menu", PATIENCE);
    wait_for_input(&mut page);
    keep_screenshot(&mut page, "web-menu.png");
    let buttons = menu_buttons(phone.width as f32, phone.height as f32, 4);
    let [x, y] = buttons[0].center();
    tapped_until(&mut page, (x as f64, y as f64), "screen practice");
    std::thread::sleep(Duration::from_millis(500));
    let (layout, practice) = phone_practice();
    (page, layout, practice)
}

/// The practice table's layout on a phone, and its rack (the cue ball first).
fn phone_practice() -> (Layout, Game) {
    let phone = Viewport::phone();
    let practice =
        Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 1).expect("the practice rack");
    let layout = Layout::new(
        phone.width as f32,
        phone.height as f32,
        Frame::new(practice.table(), practice.balls()),
    );
    (layout, practice)
}

/// A practice shot as the page reported it: the aim's direction, the tip offset and the
/// elevation (`practice shot N dir=X,Y tip=S,H elevation=E`).
#[derive(Debug)]
struct Reported {
    dir: glam::DVec2,
    tip: glam::DVec2,
    elevation: f64,
}

/// The page's report of practice shot `n`, waiting for it at most `limit`.
fn practice_shot(page: &mut Page<'_>, n: u32, limit: Duration) -> Result<Reported, String> {
    let prefix = format!("practice shot {n} ");
    let condition = said_starting(&prefix);
    page.wait_until(&condition, limit)
        .map_err(|e| format!("no shot {n}: {e}"))?;
    let all = events(page);
    let list: Vec<String> = serde_json::from_str(&all).map_err(|e| e.to_string())?;
    let line = list
        .iter()
        .find(|e| e.starts_with(&prefix))
        .ok_or("the report went away")?;
    let field = |name: &str| -> Result<Vec<f64>, String> {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(name))
            .ok_or(format!("no {name} in {line:?}"))?
            .split(',')
            .map(|v| v.parse::<f64>().map_err(|e| format!("{line:?}: {e}")))
            .collect()
    };
    let (dir, tip, elevation) = (field("dir=")?, field("tip=")?, field("elevation=")?);
    match (&dir[..], &tip[..], &elevation[..]) {
        ([dx, dy], [ts, th], [e]) => Ok(Reported {
            dir: glam::DVec2::new(*dx, *dy),
            tip: glam::DVec2::new(*ts, *th),
            elevation: *e,
        }),
        _ => Err(format!("a malformed report: {line:?}")),
    }
}

/// Aims at `aim` with a tap and pulls the finger back from it towards the cue ball at `cue`:
/// a shot along the line from the cue ball to `aim`.
fn tap_and_pull(page: &mut Page<'_>, cue: (f64, f64), aim: (f64, f64)) -> (f64, f64) {
    page.tap(aim).expect("a tap to aim");
    std::thread::sleep(Duration::from_millis(200));
    let pulled = (aim.0 + 0.6 * (cue.0 - aim.0), aim.1 + 0.6 * (cue.1 - aim.1));
    page.touch_drag(aim, pulled, 12).expect("a drag");
    pulled
}

#[test]
fn a_friend_opens_the_hosts_link_on_a_phone_joins_and_sees_the_table() {
    let Some(hosted) = hosted("web-page-join") else {
        return;
    };
    assert!(
        hosted.invite.starts_with("breakshot://127.0.0.1:"),
        "{}",
        hosted.invite
    );
    // The link the invite panel shows: on the same port number, with the room and the key.
    assert!(
        hosted.link.starts_with("http://127.0.0.1:"),
        "{}",
        hosted.link
    );
    let room = hosted
        .invite
        .rsplit_once('/')
        .and_then(|(_, r)| r.split('#').next())
        .expect("the invite's room");
    assert!(
        hosted.link.contains(&format!("room={room}")),
        "{}",
        hosted.link
    );
    let mut page = hosted
        .browser
        .open(&hosted.link, Viewport::phone())
        .expect("the page opens");
    wait_for_event(&mut page, "game playing seat=B", PATIENCE);
    let line = events(&mut page);
    assert!(line.contains("connection=Connected"), "{line}");
    // Let a few frames draw the table as it stands.
    std::thread::sleep(Duration::from_millis(500));
    let shot = page.screenshot().expect("a screenshot");
    keep_screenshot(&mut page, "web-phone.png");
    let cloth_points = shot.points(|p| near(p, CLOTH, 8));
    let cloth = cloth_points.len();
    let area = (shot.width * shot.height) as usize;
    // Upright, the table is turned: its length down the screen, its width across most of
    // it (drawn beside the panel it covered a tenth of the screen).
    assert!(
        cloth * 4 > area,
        "the cloth covers only {cloth} of {area} pixels"
    );
    let (widest, tallest) = spans(&cloth_points);
    assert!(
        widest as f64 > 0.55 * shot.width as f64,
        "the cloth is {widest} of {} pixels wide",
        shot.width
    );
    assert!(
        tallest as f64 > 0.45 * shot.height as f64,
        "the cloth is {tallest} of {} pixels tall",
        shot.height
    );
    let balls = shot.points(coloured).len();
    assert!(
        balls > 300,
        "only {balls} pixels of coloured balls: no rack drawn"
    );
    let white = shot.points(|p| near(p, CUE_BALL, 12)).len();
    assert!(white > 30, "only {white} white pixels: no cue ball");
    let names = events(&mut page);
    assert!(!names.contains("desyncs=1"), "{names}");
}

#[test]
fn a_finger_aims_and_shoots_on_the_practice_table_of_a_phone() {
    let Some(hosted) = hosted("web-page-touch") else {
        return;
    };
    // Where the practice rack puts the cue ball and the rack on this screen (the rack's
    // order changes from rack to rack; its place and the cue ball's do not).
    let (mut page, layout, practice) = open_practice(&hosted);
    let cue = on_screen(&layout, practice.balls()[0].pos);
    let others = &practice.balls()[1..];
    let rack_at = on_screen(
        &layout,
        others.iter().map(|b| b.pos).sum::<glam::DVec2>() / others.len() as f64,
    );
    let shot = page.screenshot().expect("a screenshot");
    let r = layout.px(breakshot_shared::physics::Params::default().ball_radius) as f64;
    let white = (0..8).any(|k| {
        let a = k as f64 * std::f64::consts::FRAC_PI_4;
        let (x, y) = (
            cue.0 + 0.5 * r * libm::cos(a),
            cue.1 + 0.5 * r * libm::sin(a),
        );
        shot.pixel(x as u32, y as u32)
            .is_some_and(|p| near(p, CUE_BALL, 40))
    });
    assert!(white, "no cue ball drawn at {cue:?}");
    // Aim at a point towards the rack but off its middle (so a mirrored or unturned aim
    // would go elsewhere), then pull the finger back from it towards the ball.
    let aim = (
        cue.0 + 0.5 * (rack_at.0 - cue.0) + 40.0,
        cue.1 + 0.5 * (rack_at.1 - cue.1),
    );
    let pulled = tap_and_pull(&mut page, cue, aim);
    let shot = practice_shot(&mut page, 1, Duration::from_secs(10));
    keep_screenshot(&mut page, "web-practice.png");
    let shot = shot.unwrap_or_else(|e| {
        panic!("no shot after aiming at {aim:?} from the cue ball at {cue:?} and pulling back to {pulled:?}: {e}\nevents: {}", events(&mut page))
    });
    // The ball went where the finger tapped.
    let want =
        (layout.to_scene([aim.0 as f32, aim.1 as f32]) - practice.balls()[0].pos).normalize();
    let off = want.angle_to(shot.dir).to_degrees().abs();
    assert!(
        off < 2.0,
        "tapped towards {want}, shot along {} ({off:.1} degrees off)",
        shot.dir
    );
}

#[test]
fn a_link_with_another_key_or_a_browser_without_webgl_says_why_on_the_page() {
    let Some(hosted) = hosted("web-page-bad") else {
        return;
    };
    // The key of another server: the WebSocket's handshake fails, and the page says so.
    let mut parsed: breakshot_shared::protocol::WebLink = hosted.link.parse().expect("a web link");
    parsed.key[0] ^= 1;
    parsed.transport = breakshot_shared::protocol::WebTransportChoice::WebSocket;
    let mut page = hosted
        .browser
        .open(&parsed.to_string(), Viewport::desktop(1280, 720))
        .expect("the page opens");
    wait_for_event(
        &mut page,
        "game waiting seat=- confirmed=0 desyncs=0 connection=Closed",
        PATIENCE,
    );
    drop(page);

    // Without WebGL the page says what it needs instead of leaving a blank canvas.
    let Some(blind) = browser_or_skip(
        LaunchOptions::default()
            .arg("--disable-gpu")
            .arg("--disable-software-rasterizer"),
    ) else {
        return;
    };
    let mut page = blind
        .open(&hosted.link, Viewport::desktop(800, 600))
        .expect("the page opens");
    let said = "(document.getElementById('status').textContent || '').includes('WebGL')";
    if let Err(e) = page.wait_until(said, PATIENCE) {
        panic!("no word about WebGL: {e}");
    }
}

/// Drops a file holding `bytes` on the page, as a person dragging it from their files would.
fn drop_file(page: &mut Page<'_>, bytes: &[u8]) {
    let list: Vec<String> = bytes.iter().map(u8::to_string).collect();
    page.eval(&format!(
        "(() => {{ const file = new File([new Uint8Array([{}])], 'game.rec'); \
         const data = new DataTransfer(); data.items.add(file); \
         window.dispatchEvent(new DragEvent('drop', {{ dataTransfer: data }})); }})()",
        list.join(",")
    ))
    .expect("the drop");
}

/// Drops `bytes` until the page says `said` (a drop the page was too busy to take is made
/// again, as a person would drag the file again), a few times.
fn dropped_until(page: &mut Page<'_>, bytes: &[u8], said: &str) {
    let condition = said_starting(said);
    for _ in 0..4 {
        drop_file(page, bytes);
        if page.wait_until(&condition, Duration::from_secs(10)).is_ok() {
            return;
        }
    }
    panic!(
        "dropping the file never made the page say {said:?}: {}",
        events(page)
    );
}

#[test]
fn a_record_dropped_on_the_page_plays_back_and_anything_else_is_refused_with_a_reason() {
    use breakshot_shared::physics::Strike;
    use breakshot_shared::replay::GameRecord;
    use breakshot_shared::rules::{Command, EightBallRules, Game, Settings, Variant};

    let Some(hosted) = hosted("web-page-drop") else {
        return;
    };
    let page_url = hosted.link.split('?').next().expect("the page's address");
    let mut page = hosted
        .browser
        .open(page_url, Viewport::desktop(1280, 720))
        .expect("the page opens");
    wait_for_event(&mut page, "screen menu", PATIENCE);

    wait_for_input(&mut page);
    // Noise first: the page says why it opens nothing.
    dropped_until(
        &mut page,
        &[0xff, 0, 0x12, 7],
        "status The dropped file is neither",
    );

    // A recorded break.
    let variant = Variant::EightBall(EightBallRules::Wpa);
    let mut game = Game::new(variant, Settings::offline(), 5);
    let mut record = GameRecord::new(variant, Settings::offline(), 5);
    let shot = Command::Shot {
        strike: Strike::at_angle(9.0, 90.0, glam::DVec2::ZERO),
        call: None,
    };
    let breaker = game.to_move();
    let verdict = game.apply(breaker, &shot).expect("a legal break");
    record.push(breaker, shot, verdict.shot.map(|s| s.hash));
    dropped_until(&mut page, &record.encode(), "screen replay");
}

/// The number of pixels that differ (beyond a little noise) between two screenshots.
fn changed(a: &breakshot_testkit::browser::Rgba, b: &breakshot_testkit::browser::Rgba) -> usize {
    a.points(|_| true)
        .into_iter()
        .filter(|&(x, y)| match (a.pixel(x, y), b.pixel(x, y)) {
            (Some(p), Some(q)) => !near(p, [q[0], q[1], q[2]], 24),
            _ => true,
        })
        .count()
}

#[test]
fn on_a_phone_taps_set_the_tip_and_the_elevation_and_two_fingers_turn_and_pinch_the_camera() {
    let Some(hosted) = hosted("web-page-fingers") else {
        return;
    };
    let (mut page, layout, practice) = open_practice(&hosted);
    // Long enough for a frame of a loaded machine between the touch events.
    let pause = Duration::from_millis(150);

    // A tap on the tip face, up and to the right of its centre: top and right spin.
    let [cx, cy] = layout.tip_center;
    let tr = layout.tip_radius;
    page.tap(((cx + 0.45 * tr) as f64, (cy - 0.45 * tr) as f64))
        .expect("a tap on the tip face");
    std::thread::sleep(Duration::from_millis(200));
    // A tap on the side view where the cue lies at 25 degrees.
    let (_, butt) = layout.elevation_cue(25.0);
    let toward = layout.elevation_ball;
    let on_cue = (
        (butt[0] + 0.3 * (toward[0] - butt[0])) as f64,
        (butt[1] + 0.3 * (toward[1] - butt[1])) as f64,
    );
    page.tap(on_cue).expect("a tap on the side view");
    std::thread::sleep(Duration::from_millis(200));

    // Two fingers tapped on the table open the 3-D view.
    let table = layout.cloth.center();
    let (tx, ty) = (table[0] as f64, table[1] as f64);
    let top_down = page.screenshot().expect("a screenshot");
    let fingers = [(tx - 60.0, ty), (tx + 60.0, ty)];
    page.two_finger_drag(fingers, fingers, 1, pause)
        .expect("a two-finger tap");
    std::thread::sleep(Duration::from_millis(600));
    let three_d = page.screenshot().expect("a screenshot");
    let pixels = (three_d.width * three_d.height) as usize;
    let switched = changed(&top_down, &three_d);
    assert!(
        switched * 5 > pixels,
        "a two-finger tap left the view as it was ({switched} of {pixels} pixels changed)"
    );
    keep_screenshot(&mut page, "web-3d.png");
    // Left alone, the picture stays; two fingers dragged sideways turn the camera.
    std::thread::sleep(Duration::from_millis(300));
    let still = page.screenshot().expect("a screenshot");
    let idle = changed(&three_d, &still);
    let right = [(tx - 60.0 + 160.0, ty), (tx + 60.0 + 160.0, ty)];
    page.two_finger_drag(fingers, right, 8, pause)
        .expect("a two-finger drag");
    std::thread::sleep(Duration::from_millis(600));
    let turned = page.screenshot().expect("a screenshot");
    let moved = changed(&still, &turned);
    assert!(
        moved > 10 * idle + pixels / 20,
        "dragging two fingers did not turn the camera ({moved} pixels changed, {idle} when idle)"
    );
    // Spreading them brings the camera nearer: the cue ball grows.
    let white =
        |shot: &breakshot_testkit::browser::Rgba| shot.points(|p| near(p, CUE_BALL, 30)).len();
    let before = white(&turned);
    let apart = [(tx - 150.0, ty), (tx + 150.0, ty)];
    page.two_finger_drag([(tx - 40.0, ty), (tx + 40.0, ty)], apart, 8, pause)
        .expect("a pinch");
    std::thread::sleep(Duration::from_millis(600));
    let nearer = page.screenshot().expect("a screenshot");
    let after = white(&nearer);
    assert!(
        after as f64 > 1.3 * before.max(20) as f64,
        "spreading two fingers did not bring the camera nearer ({before} white pixels, then {after})"
    );
    // And a two-finger tap goes back to the table from above, where one finger aims.
    page.two_finger_drag(fingers, fingers, 1, pause)
        .expect("a two-finger tap");
    std::thread::sleep(Duration::from_millis(600));
    let back = page.screenshot().expect("a screenshot");
    let differs = changed(&top_down, &back);
    assert!(
        differs * 20 < pixels,
        "a second two-finger tap did not go back to the view from above ({differs} of {pixels} pixels differ)"
    );

    let cue = on_screen(&layout, practice.balls()[0].pos);
    let aim = (cue.0, cue.1 - 150.0);
    tap_and_pull(&mut page, cue, aim);
    let shot = practice_shot(&mut page, 1, Duration::from_secs(10))
        .unwrap_or_else(|e| panic!("{e}\nevents: {}", events(&mut page)));
    assert!(
        shot.tip.x > 0.2 && shot.tip.y > 0.2 && (shot.tip.x - shot.tip.y).abs() < 0.1,
        "the tap up and right on the tip face gave the tip {}",
        shot.tip
    );
    assert!(
        (shot.elevation - 25.0).abs() < 2.0,
        "the tap on the side view at 25 degrees gave {} degrees",
        shot.elevation
    );
}

#[test]
fn a_page_reloaded_during_the_game_takes_its_seat_back_under_the_name_it_was_given() {
    let Some(hosted) = hosted("web-page-reload") else {
        return;
    };
    let named = format!("{}&name=Ann%20Lee", hosted.link);
    let mut page = hosted
        .browser
        .open(&named, Viewport::phone())
        .expect("the page opens");
    wait_for_event(&mut page, "game playing seat=B", PATIENCE);
    let first = events(&mut page);
    assert!(first.contains("joining as Ann Lee"), "{first}");

    // Reloaded without the name: the page still knows it, and takes seat B back (a plain
    // join would find the room full, its seat B kept for the player who left, and watch).
    page.eval("window.breakshotBefore = true").expect("a mark");
    page.call("Page.reload", serde_json::json!({}))
        .expect("a reload");
    let seated = "!window.breakshotBefore && (window.breakshotEvents || []).some(e => e.startsWith('game playing seat=B'))";
    if let Err(e) = page.wait_until(seated, PATIENCE) {
        panic!(
            "the reloaded page did not take seat B back: {e}\nits events: {}",
            events(&mut page)
        );
    }
    let again = events(&mut page);
    assert!(again.contains("joining as Ann Lee"), "{again}");
    assert!(!again.contains("desyncs=1"), "{again}");

    // Opened again from the link without a name: the page remembers it.
    page.navigate(&hosted.link).expect("the link again");
    wait_for_event(&mut page, "joining as Ann Lee", PATIENCE);
    wait_for_event(&mut page, "game playing seat=B", PATIENCE);
}
