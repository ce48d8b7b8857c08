//! The headless browser driver against small pages served from loopback: JavaScript, the
//! console, WebGL pixels, touch and mouse input, timeouts, and cleaning up.
//!
//! Where Chromium is not installed these tests say they were skipped; CI installs it and
//! sets `BREAKSHOT_REQUIRE_BROWSER=1`, so there they must run.

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use breakshot_testkit::browser::{
    browser_or_skip, near, Browser, Error, LaunchOptions, Page, Viewport,
};
use serde_json::{json, Value};

/// A page drawing a green WebGL canvas (200 × 100 CSS pixels at the top left, on white),
/// logging to the console, and recording touch, mouse and key events in `window.seen`.
const PAGE: &str = r#"<!doctype html>
<html><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
  html, body { margin: 0; padding: 0; overflow: hidden; background: #fff; }
  canvas { position: absolute; left: 0; top: 0; width: 200px; height: 100px; }
</style></head>
<body><canvas id="c" width="200" height="100" tabindex="0"></canvas>
<script>
  window.seen = [];
  window.frames = 0;
  const canvas = document.getElementById('c');
  const gl = canvas.getContext('webgl');
  function draw() {
    if (gl) { gl.clearColor(0.0, 0.6, 0.2, 1.0); gl.clear(gl.COLOR_BUFFER_BIT); }
    window.frames += 1;
    requestAnimationFrame(draw);
  }
  requestAnimationFrame(draw);
  const point = (type, x, y, extra) => window.seen.push(Object.assign({ type, x, y }, extra));
  for (const type of ['touchstart', 'touchmove', 'touchend']) {
    document.addEventListener(type, e => {
      const t = e.changedTouches[0];
      point(type, t.clientX, t.clientY, { touches: e.touches.length });
      e.preventDefault();
    }, { passive: false });
  }
  for (const type of ['mousedown', 'mousemove', 'mouseup', 'click']) {
    document.addEventListener(type, e => point(type, e.clientX, e.clientY, { buttons: e.buttons }));
  }
  canvas.addEventListener('keydown', e => window.seen.push({ type: 'keydown', code: e.code }));
  canvas.addEventListener('keypress', e => window.seen.push({ type: 'keypress', char: e.charCode }));
  console.log('page ready', 42, { webgl: !!gl });
  console.warn('a warning');
  setTimeout(() => { throw new Error('thrown later'); }, 0);
</script></body></html>
"#;

/// Serves `PAGE` at every path but `/favicon.ico` on 127.0.0.1 from a thread of its own,
/// until dropped (or for a minute at most).
struct Server {
    url: String,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// The test page opened in `browser` in `viewport`.
    fn page<'b>(&self, browser: &'b Browser, viewport: Viewport) -> Page<'b> {
        browser.open(&self.url, viewport).expect("the page opens")
    }

    /// The test page in a small desktop window.
    fn desktop_page<'b>(&self, browser: &'b Browser) -> Page<'b> {
        self.page(browser, Viewport::desktop(400, 300))
    }

    fn start() -> Server {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a loopback port");
        listener
            .set_nonblocking(true)
            .expect("a non-blocking listener");
        let url = format!("http://{}/", listener.local_addr().expect("its address"));
        let stop = Arc::new(AtomicBool::new(false));
        let stopping = stop.clone();
        let thread = thread::spawn(move || {
            let end = Instant::now() + Duration::from_secs(60);
            while !stopping.load(Ordering::Relaxed) && Instant::now() < end {
                match listener.accept() {
                    Ok((stream, _)) => answer(stream),
                    Err(_) => thread::sleep(Duration::from_millis(10)),
                }
            }
        });
        Server {
            url,
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Answers one HTTP request; a client that sends nothing within two seconds gets nothing.
fn answer(stream: TcpStream) {
    let _ = stream.set_nonblocking(false);
    let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
    let mut reader = BufReader::new(&stream);
    let mut request = String::new();
    if reader.read_line(&mut request).is_err() {
        return;
    }
    let mut line = String::new();
    while reader.read_line(&mut line).is_ok_and(|n| n > 2) {
        line.clear();
    }
    let path = request.split_whitespace().nth(1).unwrap_or("/");
    let (status, body) = if path == "/favicon.ico" {
        ("404 Not Found", "")
    } else {
        ("200 OK", PAGE)
    };
    let _ = write!(
        &stream,
        "HTTP/1.1 {status}\r\nContent-Type: text/html; charset=utf-8\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
}

fn launch() -> Option<Browser> {
    let browser = browser_or_skip(LaunchOptions::default())?;
    eprintln!(
        "{} started in {:?}",
        browser.version(),
        browser.launched_in()
    );
    Some(browser)
}

const WAIT: Duration = Duration::from_secs(10);

/// What `query` gives of the events the page has seen, once one of them is a `kind`.
fn seen_after(page: &mut Page, kind: &str, query: &str) -> Value {
    page.wait_until(&format!("seen.some(e => e.type === '{kind}')"), WAIT)
        .unwrap_or_else(|e| panic!("no {kind} arrived: {e}"));
    page.eval(query).expect("eval")
}

#[test]
fn eval_returns_values_and_the_console_is_collected() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    assert_eq!(page.eval("1 + 2").expect("eval"), json!(3));
    assert_eq!(
        page.eval("({ a: [1, 'two'], b: null })").expect("eval"),
        json!({ "a": [1, "two"], "b": null })
    );
    assert_eq!(page.eval("undefined").expect("eval"), Value::Null);
    assert_eq!(
        page.eval("new Promise(r => setTimeout(() => r('later'), 50))")
            .expect("a promise is awaited"),
        json!("later")
    );
    let line = page
        .wait_for_console("page ready", WAIT)
        .expect("the page logs");
    assert_eq!(line, r#"log: page ready 42 Object"#);
    page.wait_for_console("warning: a warning", WAIT)
        .expect("warnings are collected");
    page.eval("console.error('from eval', 7)").expect("eval");
    page.wait_for_console("error: from eval 7", WAIT)
        .expect("a message logged by eval");
    let console = page.console().expect("the console");
    assert!(
        console.iter().position(|l| l.contains("page ready"))
            < console.iter().position(|l| l.contains("from eval")),
        "in order: {console:?}"
    );
}

#[test]
fn exceptions_are_errors_and_are_reported() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    match page.eval("(() => { throw new Error('nope'); })()") {
        Err(Error::Js(text)) => assert!(text.contains("Error: nope"), "{text}"),
        other => panic!("a thrown error must be Error::Js, not {other:?}"),
    }
    match page.eval("Promise.reject(new Error('rejected'))") {
        Err(Error::Js(text)) => assert!(text.contains("rejected"), "{text}"),
        other => panic!("a rejected promise must be Error::Js, not {other:?}"),
    }
    match page.eval("no_such_variable") {
        Err(Error::Js(text)) => assert!(text.contains("ReferenceError"), "{text}"),
        other => panic!("a reference error must be Error::Js, not {other:?}"),
    }
    let line = page
        .wait_for_console("thrown later", WAIT)
        .expect("the uncaught exception is reported");
    assert!(line.starts_with("exception: Error: thrown later"), "{line}");
}

#[test]
fn webgl_draws_and_the_screenshot_shows_it() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut viewport = Viewport::desktop(400, 300);
    viewport.device_scale = 2.0;
    let mut page = server.page(&browser, viewport);
    assert_eq!(
        page.eval("!!document.createElement('canvas').getContext('webgl')")
            .expect("eval"),
        json!(true),
        "WebGL is available; the browser's log:\n{}",
        browser.log()
    );
    eprintln!(
        "WebGL renderer: {}",
        page.eval(
            "(() => { const gl = document.createElement('canvas').getContext('webgl'); \
             const i = gl.getExtension('WEBGL_debug_renderer_info'); \
             return i ? gl.getParameter(i.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER); })()"
        )
        .expect("eval")
    );
    page.wait_until("window.frames > 3", WAIT)
        .expect("the canvas is drawn");
    let shot = page.screenshot().expect("a screenshot");
    assert_eq!((shot.width, shot.height), (800, 600), "device pixels");
    let inside = shot.pixel(100, 100).expect("a pixel in the canvas");
    assert!(
        near(inside, [0, 153, 51], 3),
        "the canvas's green, not {inside:?}"
    );
    let outside = shot.pixel(600, 400).expect("a pixel beside the canvas");
    assert!(
        near(outside, [255, 255, 255], 0),
        "the page's white, not {outside:?}"
    );
    let png = page.screenshot_png().expect("a PNG");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
}

#[test]
fn a_touch_drag_on_a_phone_arrives_where_it_was_sent() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.page(&browser, Viewport::phone());
    assert_eq!(
        page.eval(
            "[innerWidth, innerHeight, navigator.maxTouchPoints > 0, 'ontouchstart' in window]"
        )
        .expect("eval"),
        json!([390, 844, true, true])
    );
    page.touch_drag((100.0, 700.0), (300.0, 200.0), 4)
        .expect("the drag is sent");
    let seen = seen_after(
        &mut page,
        "touchend",
        "seen.filter(e => e.type.startsWith('touch'))",
    );
    let expected = json!([
        { "type": "touchstart", "x": 100, "y": 700, "touches": 1 },
        { "type": "touchmove", "x": 150, "y": 575, "touches": 1 },
        { "type": "touchmove", "x": 200, "y": 450, "touches": 1 },
        { "type": "touchmove", "x": 250, "y": 325, "touches": 1 },
        { "type": "touchmove", "x": 300, "y": 200, "touches": 1 },
        { "type": "touchend", "x": 300, "y": 200, "touches": 0 },
    ]);
    assert_eq!(seen, expected);
    page.eval("seen.length = 0").expect("eval");
    page.tap((20.0, 30.0)).expect("the tap is sent");
    let seen = seen_after(
        &mut page,
        "touchend",
        "seen.filter(e => e.type.startsWith('touch')).map(e => [e.type, e.x, e.y])",
    );
    assert_eq!(seen, json!([["touchstart", 20, 30], ["touchend", 20, 30]]));

    // Two fingers: put down (a touchstart for each), moved together in one event a step,
    // lifted (a touchend for each).
    page.eval(
        "window.fingers = []; for (const type of ['touchstart', 'touchmove', 'touchend']) \
         document.addEventListener(type, e => fingers.push([type, e.changedTouches.length, \
         ...Array.from(e.touches).map(t => [t.clientX, t.clientY])]))",
    )
    .expect("eval");
    page.two_finger_drag(
        [(100.0, 400.0), (200.0, 400.0)],
        [(50.0, 400.0), (250.0, 420.0)],
        2,
        Duration::from_millis(10),
    )
    .expect("the pinch is sent");
    page.wait_until("fingers.some(e => e[0] === 'touchend')", WAIT)
        .expect("the pinch ends");
    assert_eq!(
        page.eval("fingers").expect("eval"),
        json!([
            ["touchstart", 1, [100, 400]],
            ["touchstart", 1, [100, 400], [200, 400]],
            ["touchmove", 2, [75, 400], [225, 410]],
            ["touchmove", 2, [50, 400], [250, 420]],
            ["touchend", 1, [250, 420]],
            ["touchend", 1],
        ])
    );
}

#[test]
fn clicks_drags_and_keys_reach_the_page() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    page.click((50.0, 40.0)).expect("the click is sent");
    let seen = seen_after(
        &mut page,
        "click",
        "seen.filter(e => e.type !== 'mousemove').map(e => [e.type, e.x, e.y])",
    );
    assert_eq!(
        seen,
        json!([
            ["mousedown", 50, 40],
            ["mouseup", 50, 40],
            ["click", 50, 40]
        ])
    );
    page.eval("seen.length = 0").expect("eval");
    page.mouse_drag((10.0, 10.0), (110.0, 60.0), 2)
        .expect("the drag is sent");
    let seen = seen_after(
        &mut page,
        "mouseup",
        "seen.filter(e => e.type !== 'click').map(e => [e.type, e.x, e.y, e.buttons])",
    );
    assert_eq!(
        seen,
        json!([
            ["mousemove", 10, 10, 0],
            ["mousedown", 10, 10, 1],
            ["mousemove", 60, 35, 1],
            ["mousemove", 110, 60, 1],
            ["mouseup", 110, 60, 0],
        ])
    );
    page.eval("seen.length = 0; document.getElementById('c').focus()")
        .expect("eval");
    page.key("a").expect("a letter");
    page.key("Escape").expect("a named key");
    page.wait_until("seen.filter(e => e.type === 'keydown').length === 2", WAIT)
        .expect("the keys arrive");
    assert_eq!(
        page.eval("seen").expect("eval"),
        json!([
            { "type": "keydown", "code": "KeyA" },
            { "type": "keypress", "char": 97 },
            { "type": "keydown", "code": "Escape" },
        ])
    );
    assert!(matches!(page.key("NoSuchKey"), Err(Error::Protocol(_))));
}

#[test]
fn waits_that_cannot_succeed_time_out_quickly_with_what_they_waited_for() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    let started = Instant::now();
    let failed = page.wait_until("window.never === true", Duration::from_millis(500));
    let took = started.elapsed();
    match failed {
        Err(Error::Timeout(what)) => assert!(what.contains("window.never === true"), "{what}"),
        other => panic!("a condition never met must time out, not {other:?}"),
    }
    assert!(
        took >= Duration::from_millis(400) && took < Duration::from_secs(2),
        "{took:?}"
    );

    let started = Instant::now();
    match page.wait_for_console("never logged", Duration::from_millis(500)) {
        Err(Error::Timeout(what)) => assert!(what.contains("never logged"), "{what}"),
        other => panic!("a message never logged must time out, not {other:?}"),
    }
    assert!(started.elapsed() < Duration::from_secs(2));
    // The condition's exception is named in the timeout.
    match page.wait_until("not_defined_yet.ok", Duration::from_millis(300)) {
        Err(Error::Timeout(what)) => assert!(what.contains("ReferenceError"), "{what}"),
        other => panic!("{other:?}"),
    }
    // The page is still usable after the timeouts.
    assert_eq!(page.eval("2 * 21").expect("eval"), json!(42));
}

#[test]
fn a_page_on_loopback_is_a_secure_context_with_webtransport() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    let found = page
        .eval("[isSecureContext, typeof WebTransport]")
        .expect("eval");
    eprintln!(
        "{}: [isSecureContext, typeof WebTransport] = {found}",
        browser.version()
    );
    assert_eq!(found, json!([true, "function"]));
}

#[test]
fn two_pages_both_keep_animating() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut first = server.page(&browser, Viewport::phone());
    let mut second = server.page(&browser, Viewport::phone());
    let before = first.eval("window.frames").expect("eval");
    second
        .wait_until("window.frames > 10", WAIT)
        .expect("the page in front animates");
    first
        .wait_until(&format!("window.frames > {before} + 10"), WAIT)
        .expect("the page behind animates too");
}

#[test]
fn an_init_script_runs_before_the_page_s_own() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = browser
        .open("about:blank", Viewport::desktop(400, 300))
        .expect("a blank page opens");
    page.add_init_script("window.early = typeof window.seen;")
        .expect("the script is added");
    page.navigate(&server.url).expect("the page loads");
    assert_eq!(
        page.eval("[early, typeof seen]").expect("eval"),
        json!(["undefined", "object"])
    );
}

#[test]
fn a_refused_page_is_an_error() {
    let Some(browser) = launch() else { return };
    // A port that was free a moment ago and now has no listener.
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a port")
        .port();
    match browser.open(
        &format!("http://127.0.0.1:{port}/"),
        Viewport::desktop(200, 200),
    ) {
        Err(Error::Protocol(what)) => assert!(what.contains("ERR_CONNECTION_REFUSED"), "{what}"),
        Err(other) => panic!("{other:?}"),
        Ok(_) => panic!("a refused connection must be an error"),
    };
}

#[test]
fn dropping_the_browser_leaves_no_process_and_no_folder() {
    let Some(browser) = launch() else { return };
    let server = Server::start();
    let mut page = server.desktop_page(&browser);
    page.wait_until("window.frames > 2", WAIT).expect("it runs");
    drop(page);
    let pid = browser.pid();
    let folder = browser.folder().to_path_buf();
    assert!(folder.join("profile").is_dir());
    assert!(
        !in_group(pid).is_empty(),
        "the browser's processes are found"
    );
    let started = Instant::now();
    drop(browser);
    eprintln!("the browser ended in {:?}", started.elapsed());
    assert!(!folder.exists(), "{} is left", folder.display());
    assert_eq!(
        in_group(pid),
        Vec::<u32>::new(),
        "processes of the browser's group still run"
    );
    let needle = folder.as_os_str().as_encoded_bytes();
    let mentioning: Vec<u32> = processes()
        .filter(|&p| {
            std::fs::read(format!("/proc/{p}/cmdline"))
                .is_ok_and(|cmd| cmd.windows(needle.len()).any(|w| w == needle))
        })
        .collect();
    assert_eq!(
        mentioning,
        Vec::<u32>::new(),
        "processes using the profile are left"
    );
}

fn processes() -> impl Iterator<Item = u32> {
    std::fs::read_dir("/proc")
        .expect("/proc")
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse().ok())
}

/// The processes of process group `group` still running (a zombie has ended), from
/// `/proc/PID/stat`: after the name in parentheses come the state, the parent and the group.
fn in_group(group: u32) -> Vec<u32> {
    processes()
        .filter(|p| {
            std::fs::read_to_string(format!("/proc/{p}/stat")).is_ok_and(|stat| {
                let fields: Vec<&str> = stat
                    .rsplit_once(')')
                    .map_or("", |(_, rest)| rest)
                    .split_whitespace()
                    .take(3)
                    .collect();
                fields.len() == 3 && fields[0] != "Z" && fields[2].parse() == Ok(group)
            })
        })
        .collect()
}

/// A stand-in for Chromium: a shell script in a scratch folder.
fn fake_browser(script: &str) -> (breakshot_testkit::TempDir, std::path::PathBuf) {
    let dir = breakshot_testkit::scratch("fake-chromium");
    let program = dir.path().join("chromium");
    // Written by a child process: a file this process had open for writing could be
    // inherited by a program another test thread is starting at that moment, and running
    // it would then fail with "text file busy".
    let made = breakshot_testkit::run(
        Command::new("sh")
            .arg("-c")
            .arg(r#"cat > "$0" && chmod 755 "$0""#)
            .arg(&program),
        Some(format!("#!/bin/sh\n{script}\n").as_bytes()),
        Duration::from_secs(30),
    );
    assert!(made.status.success(), "writing {}", program.display());
    (dir, program)
}

#[test]
fn a_browser_that_fails_to_start_is_unavailable_with_its_errors() {
    let (_dir, program) = fake_browser("echo 'no display, no luck' >&2; exit 3");
    let options = LaunchOptions {
        program: Some(program),
        ..LaunchOptions::default()
    };
    let Err(why) = Browser::launch(options) else {
        panic!("the stand-in cannot start");
    };
    assert!(why.0.contains("it ended"), "{why}");
    assert!(why.0.contains("no display, no luck"), "{why}");
}

#[test]
fn a_browser_that_never_listens_is_unavailable_in_time_and_stopped() {
    let (dir, program) = fake_browser(r#"echo $$ > "$(dirname "$0")/pid"; exec sleep 60"#);
    let options = LaunchOptions {
        program: Some(program),
        launch_timeout: Duration::from_millis(700),
        ..LaunchOptions::default()
    };
    let started = Instant::now();
    let Err(why) = Browser::launch(options) else {
        panic!("the stand-in never listens");
    };
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "{:?}",
        started.elapsed()
    );
    assert!(why.0.contains("did not open its DevTools socket"), "{why}");
    let pid = std::fs::read_to_string(dir.path().join("pid")).expect("the stand-in's pid");
    let pid = pid.trim();
    assert!(
        !std::path::Path::new(&format!("/proc/{pid}")).exists(),
        "the stand-in (pid {pid}) still runs"
    );
}
