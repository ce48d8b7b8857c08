//! A virtual display that several real `breakshot` windows share, driven by `xdotool` and
//! photographed from outside with ImageMagick's `import`, for tests where windows live on
//! while the test acts on them.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use breakshot_client::view::palette::ball_look;
use breakshot_client::view::Layout;
use breakshot_shared::physics::{BallState, MotionState, Params};
use breakshot_testkit::Spawned;

use crate::common::screen::find_in_path;
pub use crate::common::screen::{close, shaded, Picture};

/// An X server of its own (Xvfb), kept from resetting when a window closes.
pub struct Display {
    server: Spawned,
    name: String,
}

impl Display {
    /// A 1300x1400 screen; None, with the reason printed, when Xvfb, xdotool or ImageMagick
    /// is not installed.
    pub fn start() -> Option<Display> {
        let missing: Vec<&str> = ["Xvfb", "xdotool", "import"]
            .into_iter()
            .filter(|t| find_in_path(t).is_none())
            .collect();
        if !missing.is_empty() {
            eprintln!(
                "skipped: {missing:?} not installed (apt-get install xvfb xdotool imagemagick)"
            );
            return None;
        }
        // The server picks a free display number and writes it on its standard output.
        let mut server = Spawned::start(
            Command::new("Xvfb")
                .args(["-displayfd", "1", "-screen", "0", "1300x1400x24"])
                .args(["-noreset", "-nolisten", "tcp"])
                .stdout(Stdio::piped())
                .stderr(Stdio::null()),
        );
        let out = server.child().stdout.take().expect("Xvfb's output");
        let (line, _) = breakshot_testkit::read_line(out, Duration::from_secs(30));
        let number: u32 = line.trim().parse().expect("a display number");
        Some(Display {
            server,
            name: format!(":{number}"),
        })
    }

    /// `command` set to open its windows here.
    pub fn on<'a>(&self, command: &'a mut Command) -> &'a mut Command {
        command.env("DISPLAY", &self.name)
    }

    /// Runs `xdotool ARGS` here; its output. Fails the test if it fails or hangs.
    pub fn xdotool(&self, args: &[&str]) -> String {
        let out = self.ran(
            self.on(&mut Command::new("xdotool")).args(args),
            &format!("xdotool {args:?}"),
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// `command` run to its end (at most a minute); fails the test, naming `what` and showing
    /// its standard error, unless it succeeded.
    fn ran(&self, command: &mut Command, what: &str) -> std::process::Output {
        let out = breakshot_testkit::run(command, None, Duration::from_secs(60));
        assert!(
            out.status.success(),
            "{what}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    }

    /// The game window opened after those of `known`, once it is shown (at most a minute).
    /// (The window names no process id, so windows are told apart by the order they open.)
    pub fn new_window(&self, known: &[String]) -> String {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let found = breakshot_testkit::run(
                self.on(&mut Command::new("xdotool"))
                    .args(["search", "--name", "Breakshot"]),
                None,
                Duration::from_secs(20),
            );
            let text = String::from_utf8_lossy(&found.stdout);
            if let Some(wid) = text
                .lines()
                .find(|l| !l.is_empty() && !known.iter().any(|k| k == l))
            {
                return wid.to_owned();
            }
            assert!(Instant::now() < deadline, "no new window within a minute");
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// The clipboard here holding the text of file `text`, for as long as the returned
    /// process runs (`xclip` serves it in the foreground and is stopped when dropped, so
    /// none is left behind); None, with the reason printed, when xclip is not installed.
    pub fn clipboard(&self, text: &Path) -> Option<Spawned> {
        if find_in_path("xclip").is_none() {
            eprintln!("skipped: xclip is not installed (apt-get install xclip)");
            return None;
        }
        let xclip = Spawned::start(
            self.on(&mut Command::new("xclip"))
                .args(["-selection", "clipboard", "-quiet"])
                .arg(text)
                .stdout(Stdio::null())
                .stderr(Stdio::null()),
        );
        // It owns the selection once it has started.
        std::thread::sleep(Duration::from_millis(500));
        Some(xclip)
    }

    /// What window `wid` shows now, saved to `out`.
    pub fn grab(&self, wid: &str, out: &Path) -> Picture {
        self.ran(
            self.on(&mut Command::new("import"))
                .args(["-window", wid])
                .arg(format!("PNG32:{}", out.display())),
            "import",
        );
        Picture::load(out)
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        // Asked to end, so it removes its socket and lock file.
        self.server.terminate();
        let _ = self.server.wait(Duration::from_secs(10));
    }
}

/// The balls of `balls` (ids `ids`) not seen in their colour, left and right of where the
/// layout puts them (clear of the number in the middle).
pub fn balls_not_seen(
    pic: &Picture,
    layout: &Layout,
    ids: &[String],
    balls: &[BallState],
) -> Vec<String> {
    let r = layout.px(Params::default().ball_radius);
    ids.iter()
        .zip(balls)
        .filter(|(_, b)| b.motion != MotionState::Pocketed)
        .filter(|(id, b)| {
            let [x, y] = layout.to_screen(b.pos);
            let want = ball_look(id).color;
            ![-0.75 * r, 0.75 * r]
                .iter()
                .all(|dx| shaded(pic.at(x + dx, y), want, 14.0))
        })
        .map(|(id, _)| id.clone())
        .collect()
}
