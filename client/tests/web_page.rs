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
use breakshot_testkit::browser::{browser_or_skip, near, LaunchOptions, Page, Viewport};
use breakshot_testkit::web::{bundle, skip_web};
use breakshot_testkit::{read_line, scratch, Spawned};

const PATIENCE: Duration = Duration::from_secs(60);

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

fn events(page: &mut Page<'_>) -> String {
    page.eval("JSON.stringify(window.breakshotEvents || [])")
        .map(|v| v.as_str().unwrap_or_default().to_owned())
        .unwrap_or_default()
}

fn wait_for_event(page: &mut Page<'_>, prefix: &str, limit: Duration) {
    let condition = format!("(window.breakshotEvents || []).some(e => e.startsWith({prefix:?}))");
    if let Err(e) = page.wait_until(&condition, limit) {
        panic!(
            "the page never said {prefix:?}: {e}\nits events: {}",
            events(page)
        );
    }
}

/// Waits until the page takes input: the game's first screen is made before the loader
/// installs its mouse, touch and drop handlers, so a tap sent at once would be lost.
fn wait_for_input(page: &mut Page<'_>) {
    if let Err(e) = page.wait_until("typeof window.ondrop === 'function'", PATIENCE) {
        panic!("the page never took input: {e}");
    }
}

#[test]
fn a_friend_opens_the_hosts_link_on_a_phone_joins_and_sees_the_table() {
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => return skip_web("web_page", &why),
    };
    let dir = scratch("web-page-join");
    let Some((_host, invite, link)) = host(dir.path(), bundle) else {
        return;
    };
    assert!(invite.starts_with("breakshot://127.0.0.1:"), "{invite}");
    // The link the invite panel shows: on the same port number, with the room and the key.
    assert!(link.starts_with("http://127.0.0.1:"), "{link}");
    let room = invite
        .rsplit_once('/')
        .and_then(|(_, r)| r.split('#').next())
        .expect("the invite's room");
    assert!(link.contains(&format!("room={room}")), "{link}");
    let Some(browser) = browser_or_skip(LaunchOptions::default()) else {
        return;
    };
    let mut page = browser
        .open(&link, Viewport::phone())
        .expect("the page opens");
    wait_for_event(&mut page, "game playing seat=B", PATIENCE);
    let line = events(&mut page);
    assert!(line.contains("connection=Connected"), "{line}");
    // Let a few frames draw the table as it stands.
    std::thread::sleep(Duration::from_millis(500));
    let shot = page.screenshot().expect("a screenshot");
    if let Ok(dir) = std::env::var("BREAKSHOT_SCREENSHOTS") {
        let png = page.screenshot_png().expect("a screenshot");
        std::fs::write(Path::new(&dir).join("web-phone.png"), png).expect("saved");
    }
    let cloth = shot.points(|p| near(p, CLOTH, 8)).len();
    let area = (shot.width * shot.height) as usize;
    assert!(
        cloth * 20 > area,
        "the cloth covers only {cloth} of {area} pixels"
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
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => return skip_web("web_page", &why),
    };
    let dir = scratch("web-page-touch");
    let Some((_host, _invite, link)) = host(dir.path(), bundle) else {
        return;
    };
    let Some(browser) = browser_or_skip(LaunchOptions::default()) else {
        return;
    };
    // The page on its own, without a room: the menu, whose first button is Practice.
    let page_url = link.split('?').next().expect("the page's address");
    let phone = Viewport::phone();
    let mut page = browser.open(page_url, phone).expect("the page opens");
    wait_for_event(&mut page, "screen menu", PATIENCE);
    wait_for_input(&mut page);
    if let Ok(dir) = std::env::var("BREAKSHOT_SCREENSHOTS") {
        let png = page.screenshot_png().expect("a screenshot");
        std::fs::write(Path::new(&dir).join("web-menu.png"), png).expect("saved");
    }
    let buttons = menu_buttons(phone.width as f32, phone.height as f32, 3);
    let [x, y] = buttons[0].center();
    // A slow machine may take the tap before the menu's first frame: tap again, as a
    // person would, a few times.
    let practice = "(window.breakshotEvents || []).includes('screen practice')";
    let opened = (0..6).any(|_| {
        page.tap((x as f64, y as f64)).expect("a tap");
        page.wait_until(practice, Duration::from_secs(10)).is_ok()
    });
    assert!(
        opened,
        "tapping Practice opened nothing: {}",
        events(&mut page)
    );
    std::thread::sleep(Duration::from_millis(500));

    // Where the practice rack puts the cue ball and the rack on this screen (the rack's
    // order changes from rack to rack; its place and the cue ball's do not).
    let practice =
        Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 1).expect("the practice rack");
    let layout = Layout::new(
        phone.width as f32,
        phone.height as f32,
        Frame::new(practice.table(), practice.balls()),
    );
    let point = |p: glam::DVec2| {
        let [x, y] = layout.to_screen(p);
        (x as f64, y as f64)
    };
    let cue = point(practice.balls()[0].pos);
    let others = &practice.balls()[1..];
    let rack_at = point(others.iter().map(|b| b.pos).sum::<glam::DVec2>() / others.len() as f64);
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
    // Aim at a point towards the rack, then pull the finger back from it towards the ball.
    let aim = (
        cue.0 + 0.5 * (rack_at.0 - cue.0),
        cue.1 + 0.5 * (rack_at.1 - cue.1),
    );
    page.tap(aim).expect("a tap to aim");
    std::thread::sleep(Duration::from_millis(200));
    let pulled = (aim.0 + 0.6 * (cue.0 - aim.0), aim.1 + 0.6 * (cue.1 - aim.1));
    page.touch_drag(aim, pulled, 12).expect("a drag");
    let shot = page.wait_until(
        "(window.breakshotEvents || []).some(e => e.startsWith('practice shot 1'))",
        Duration::from_secs(10),
    );
    if let Ok(dir) = std::env::var("BREAKSHOT_SCREENSHOTS") {
        let png = page.screenshot_png().expect("a screenshot");
        std::fs::write(Path::new(&dir).join("web-practice.png"), png).expect("saved");
    }
    if let Err(e) = shot {
        panic!("no shot after aiming at {aim:?} from the cue ball at {cue:?} and pulling back to {pulled:?}: {e}\nevents: {}", events(&mut page));
    }
}

#[test]
fn a_link_with_another_key_or_a_browser_without_webgl_says_why_on_the_page() {
    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => return skip_web("web_page", &why),
    };
    let dir = scratch("web-page-bad");
    let Some((_host, _invite, link)) = host(dir.path(), bundle) else {
        return;
    };
    let Some(browser) = browser_or_skip(LaunchOptions::default()) else {
        return;
    };
    // The key of another server: the WebSocket's handshake fails, and the page says so.
    let mut parsed: breakshot_shared::protocol::WebLink = link.parse().expect("a web link");
    parsed.key[0] ^= 1;
    parsed.transport = breakshot_shared::protocol::WebTransportChoice::WebSocket;
    let mut page = browser
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
        .open(&link, Viewport::desktop(800, 600))
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
    let condition = format!("(window.breakshotEvents || []).some(e => e.startsWith({said:?}))");
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

    let bundle = match bundle() {
        Ok(b) => b,
        Err(why) => return skip_web("web_page", &why),
    };
    let dir = scratch("web-page-drop");
    let Some((_host, _invite, link)) = host(dir.path(), bundle) else {
        return;
    };
    let Some(browser) = browser_or_skip(LaunchOptions::default()) else {
        return;
    };
    let page_url = link.split('?').next().expect("the page's address");
    let mut page = browser
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
