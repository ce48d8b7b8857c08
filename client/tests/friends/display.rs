//! A virtual display that several real `breakshot` windows share, driven by `xdotool` and
//! photographed from outside with ImageMagick's `import`, for tests where windows live on
//! while the test acts on them.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use breakshot_client::view::palette::{ball_look, Rgb};
use breakshot_client::view::Layout;
use breakshot_shared::physics::{BallState, MotionState, Params};
use breakshot_testkit::Spawned;

fn find_in_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

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
        let out = breakshot_testkit::run(
            self.on(&mut Command::new("xdotool")).args(args),
            None,
            Duration::from_secs(60),
        );
        assert!(
            out.status.success(),
            "xdotool {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
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
        let run = breakshot_testkit::run(
            self.on(&mut Command::new("import"))
                .args(["-window", wid])
                .arg(format!("PNG32:{}", out.display())),
            None,
            Duration::from_secs(60),
        );
        assert!(
            run.status.success(),
            "import: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        Picture::read(out)
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        // Asked to end, so it removes its socket and lock file.
        self.server.terminate();
        let _ = self.server.wait(Duration::from_secs(10));
    }
}

/// A screenshot, RGBA.
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pixels: Vec<u8>,
}

impl Picture {
    /// The PNG at `path` (8-bit RGBA).
    pub fn read(path: &Path) -> Picture {
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|mut f| f.read_to_end(&mut bytes))
            .expect("screenshot written");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("PNG data");
        assert_eq!(info.color_type, png::ColorType::Rgba);
        buf.truncate(info.buffer_size());
        Picture {
            width: info.width,
            height: info.height,
            pixels: buf,
        }
    }

    pub fn at(&self, x: f32, y: f32) -> Rgb {
        let x = (x.round().max(0.0) as usize).min(self.width as usize - 1);
        let y = (y.round().max(0.0) as usize).min(self.height as usize - 1);
        let i = (y * self.width as usize + x) * 4;
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }
}

pub fn close(a: Rgb, b: Rgb, tolerance: i32) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, y)| (x as i32 - y as i32).abs() <= tolerance)
}

/// Whether `got` is `want` lit more or less brightly (a ball is a shaded sphere).
pub fn shaded(got: Rgb, want: Rgb, tolerance: f32) -> bool {
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
