//! The window under a virtual display: the `breakshot` binary run under `xvfb-run` with a
//! screenshot, and the picture it saved, read pixel by pixel.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command as Process, Output};
use std::time::Duration;

use breakshot_client::view::palette::Rgb;
use breakshot_client::view::{Frame, Layout};
use breakshot_shared::rules::{EightBallRules, Game, Settings, Variant};

/// The window's size in these tests.
pub const SIZE: (u32, u32) = (1280, 720);

/// The program `name` on the `PATH`, if installed.
pub fn find_in_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

/// `xvfb-run`, or None with the reason printed (the test is then skipped).
pub fn xvfb_run() -> Option<PathBuf> {
    let found = find_in_path("xvfb-run");
    if found.is_none() {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
    }
    found
}

/// Runs `breakshot ARGS` under a virtual display, saving its window to `out` at frame
/// `frames`, with a fresh data directory; None without `xvfb-run`. Fails the test if the
/// window has not closed within `patience`.
pub fn window(args: &[&OsStr], out: &Path, frames: u32, patience: Duration) -> Option<Output> {
    window_sized(args, out, frames, SIZE, patience)
}

/// As [`window`], in a window of `size` pixels. The window's data directory is a fresh one
/// (unless `args` give `--data`), so nothing the user chose before (the view, the name)
/// changes what it shows.
pub fn window_sized(
    args: &[&OsStr],
    out: &Path,
    frames: u32,
    (w, h): (u32, u32),
    patience: Duration,
) -> Option<Output> {
    let xvfb = xvfb_run()?;
    let data = breakshot_testkit::scratch("window-data");
    Some(breakshot_testkit::run(
        Process::new(xvfb)
            .env("BREAKSHOT_DATA", data.path())
            // The window tells standard error what it did ("report: ..." lines).
            .env("BREAKSHOT_REPORT", "1")
            // A host serves no web client here, even where one was built beside the binary.
            .env("BREAKSHOT_WEB", data.path().join("no-web-client"))
            // The X authority file in the test's own folder: xvfb-run leaves nothing in /tmp,
            // even when it is stopped.
            .args(["-a", "-f"])
            .arg(out.with_file_name("Xauthority"))
            .args(["-s", "-screen 0 1280x800x24"])
            .arg(env!("CARGO_BIN_EXE_breakshot"))
            .args(args)
            .arg("--screenshot")
            .arg(out)
            .args(["--frames", &frames.to_string()])
            .arg(format!("--size={w}x{h}")),
        None,
        patience,
    ))
}

/// Runs `breakshot ARGS --screenshot OUT --frames FRAMES` in a window of `size` under a
/// virtual display while `xdotool` plays `keys` on it (one xdotool command a line, `$wid`
/// the window, a short pause before each), its data in `data`; None if xvfb-run or xdotool
/// is missing (the reason is printed). Fails the test if it has not ended within `patience`.
///
/// A line `await TEXT` is no xdotool command: the script waits (at most a minute) until
/// the window has reported a line starting with TEXT (a `grep` pattern), so a key that needs something done
/// first is pressed after it however loaded the machine is.
pub fn played(
    args: &[&OsStr],
    out: &Path,
    frames: u32,
    keys: &[&str],
    (w, h): (u32, u32),
    data: &Path,
    patience: Duration,
) -> Option<Output> {
    let (Some(xvfb), Some(_)) = (find_in_path("xvfb-run"), find_in_path("xdotool")) else {
        eprintln!("skipped: needs xvfb-run and xdotool (apt-get install xvfb xdotool)");
        return None;
    };
    // The window's standard error goes to a file the script can read, then to its own.
    let log = out.with_file_name("window.log");
    let mut script = format!(
        "log=\"{}\"\n\
         \"$0\" \"$@\" --screenshot \"{}\" --frames {frames} --size {w}x{h} 2>\"$log\" &\n\
         pid=$!\nwid=$(xdotool search --sync --name Breakshot | head -n 1)\n",
        log.display(),
        out.display()
    );
    for key in keys {
        match key.strip_prefix("await ") {
            Some(text) => script.push_str(&format!(
                "n=0; until grep -q '^report: {text}' \"$log\" || [ $n -ge 600 ]; \
                 do sleep 0.1; n=$((n+1)); done\n"
            )),
            None => script.push_str(&format!("sleep 0.3\nxdotool {key}\n")),
        }
    }
    script.push_str("wait $pid; status=$?; cat \"$log\" >&2; rm -f \"$log\"; exit $status\n");
    Some(breakshot_testkit::run(
        Process::new(xvfb)
            .env("BREAKSHOT_DATA", data)
            // The window tells standard error what it did ("report: ..." lines).
            .env("BREAKSHOT_REPORT", "1")
            .args(["-a", "-s", "-screen 0 1280x800x24", "sh", "-c", &script])
            .arg(env!("CARGO_BIN_EXE_breakshot"))
            .args(args),
        None,
        patience,
    ))
}

/// The lines a window that has ended reported on standard error.
pub fn reports(run: &Output) -> Vec<String> {
    String::from_utf8_lossy(&run.stderr)
        .lines()
        .filter_map(|l| l.strip_prefix("report: "))
        .map(String::from)
        .collect()
}

/// `breakshot host` against the computer at level 1 on a free loopback port, its data in
/// `data`: a real server and a game that starts at once.
pub fn hosting_the_computer(data: &Path) -> Vec<std::ffi::OsString> {
    [
        "host",
        "--computer",
        "--level",
        "1",
        "--bind",
        "127.0.0.1:0",
        "--data",
    ]
    .map(std::ffi::OsString::from)
    .into_iter()
    .chain([data.as_os_str().to_owned()])
    .collect()
}

/// Fails the test unless `breakshot` exited cleanly, showing what it wrote to standard error.
pub fn assert_ran(run: &Output) {
    assert!(
        run.status.success(),
        "breakshot exited with {}: {}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
}

/// An 8-ball game under WPA rules with `settings`, racked from `seed`: the rack a window
/// opens on.
pub fn eight_ball(settings: Settings, seed: u64) -> Game {
    Game::new(Variant::EightBall(EightBallRules::Wpa), settings, seed)
}

/// A screenshot the window saved.
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pixels: Vec<u8>,
}

impl Picture {
    /// The PNG at `path`, checked to be the window's size.
    pub fn read(path: &Path) -> Picture {
        Picture::sized(path, SIZE)
    }

    /// The PNG at `path`, checked to be `size`.
    pub fn sized(path: &Path, size: (u32, u32)) -> Picture {
        let pic = Picture::load(path);
        assert_eq!((pic.width, pic.height), size);
        pic
    }

    /// The PNG at `path` (8-bit RGBA), of any size.
    pub fn load(path: &Path) -> Picture {
        let file = std::fs::File::open(path).expect("screenshot written");
        let decoder = png::Decoder::new(std::io::BufReader::new(file));
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

    /// The layout the window puts `frame` in at this picture's size.
    pub fn layout(&self, frame: Frame) -> Layout {
        Layout::new(self.width as f32, self.height as f32, frame)
    }

    /// The colour at pixel (x, y), rounded to the nearest pixel.
    pub fn at(&self, x: f32, y: f32) -> Rgb {
        let x = (x.round().max(0.0) as usize).min(self.width as usize - 1);
        let y = (y.round().max(0.0) as usize).min(self.height as usize - 1);
        let i = (y * self.width as usize + x) * 4;
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    /// Whether any pixel within `reach` pixels of (x, y) satisfies `want` (a thin line
    /// drawn with anti-aliasing lands on a pixel or its neighbour).
    pub fn near(&self, x: f32, y: f32, reach: i32, want: impl Fn(Rgb) -> bool) -> bool {
        (-reach..=reach)
            .any(|dx| (-reach..=reach).any(|dy| want(self.at(x + dx as f32, y + dy as f32))))
    }
}

/// Whether `a` and `b` differ by at most `tolerance` in each channel.
pub fn close(a: Rgb, b: Rgb, tolerance: i32) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, y)| (x as i32 - y as i32).abs() <= tolerance)
}

/// Whether `got` is `want` lit more or less brightly (a ball is a shaded sphere): the same
/// colour scaled by one factor in a plausible range, within `tolerance` per channel.
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
