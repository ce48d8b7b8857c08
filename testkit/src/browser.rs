//! Headless Chromium for the browser tests, driven over the Chrome DevTools Protocol: open a
//! page on a phone-sized or desktop viewport, run JavaScript in it, read its console, take
//! screenshots, and touch, click and type.
//!
//! This is full Chromium (Debian's `chromium`) in its new headless mode, which has WebGL
//! (through SwiftShader, rendering in software) and WebTransport; the separate
//! `chrome-headless-shell` lacks WebTransport. Each [`Browser`] has a fresh profile in a
//! scratch folder, so no certificate verdict or cache carries over between tests, and its
//! temporary files and home folder are in there too. Dropping it ends Chromium and every
//! process it started, and removes the folder.
//!
//! Where Chromium is not installed, [`Browser::launch`] says so with [`Unavailable`], and
//! [`browser_or_skip`] lets the test skip, or fail when `BREAKSHOT_REQUIRE_BROWSER=1` (set by
//! CI, which installs Chromium).

mod cdp;
mod image;
mod keys;
mod page;
mod process;

use std::cell::RefCell;
use std::fmt;
use std::net::{Ipv4Addr, SocketAddr};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

pub use image::{near, Rgba};
pub use page::{Page, Viewport};

use cdp::{Cdp, Event};
use process::Process;

/// The flags every launch passes, before the caller's own.
pub const FLAGS: &[&str] = &[
    "--headless=new",
    // Root in a container has no user namespaces for the sandbox.
    "--no-sandbox",
    "--no-first-run",
    // The machine's network is closed: no update checks, sync, or other calls home.
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-default-apps",
    "--password-store=basic",
    // Shared memory in the scratch folder's temporary files, not /dev/shm, which containers
    // often make too small for a few canvases (Chromium then crashes).
    "--disable-dev-shm-usage",
    "--mute-audio",
    // WebGL without a GPU: ANGLE on SwiftShader, which Chromium allows only when asked.
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    // Pages in windows that are not in front keep their timers and animation frames.
    "--disable-background-timer-throttling",
    "--disable-renderer-backgrounding",
    "--disable-backgrounding-occluded-windows",
    // Any free port; Chromium writes the one it took into DevToolsActivePort.
    "--remote-debugging-port=0",
];

/// How a browser is started.
#[derive(Debug, Clone)]
pub struct LaunchOptions {
    /// The Chromium program to run; when `None`, the one named by `BREAKSHOT_CHROMIUM`, else
    /// `/usr/bin/chromium`, else `chromium` or `chromium-browser` on the `PATH`.
    pub program: Option<PathBuf>,
    /// Flags after [`FLAGS`], such as `--origin-to-force-quic-on=127.0.0.1:4433` or
    /// `--ignore-certificate-errors-spki-list=HASH`.
    pub args: Vec<String>,
    /// How long Chromium may take to start and open its DevTools socket.
    pub launch_timeout: Duration,
    /// How long any one command may take to be answered (loading a page, evaluating a
    /// script, a screenshot).
    pub timeout: Duration,
}

impl Default for LaunchOptions {
    fn default() -> Self {
        LaunchOptions {
            program: None,
            args: Vec::new(),
            // A first start on a busy machine with two cores takes a few seconds.
            launch_timeout: Duration::from_secs(30),
            timeout: Duration::from_secs(20),
        }
    }
}

impl LaunchOptions {
    /// Adds one flag.
    pub fn arg(mut self, flag: impl Into<String>) -> Self {
        self.args.push(flag.into());
        self
    }
}

/// Why no browser could be started: Chromium is not installed, or it did not come up.
#[derive(Debug, Clone)]
pub struct Unavailable(pub String);

impl fmt::Display for Unavailable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unavailable {}

/// What went wrong talking to a browser that did start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Error {
    /// What was waited for did not come in time; the text says what and how long.
    Timeout(String),
    /// The page's JavaScript threw or rejected; the text is the exception's description.
    Js(String),
    /// The browser refused a command or answered what cannot be understood.
    Protocol(String),
    /// The connection to the browser is gone.
    Closed(String),
    /// The page's renderer crashed or the page was detached.
    Crashed(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Timeout(what) => write!(f, "timed out: {what}"),
            Error::Js(text) => write!(f, "JavaScript error: {text}"),
            Error::Protocol(text) => write!(f, "browser error: {text}"),
            Error::Closed(why) => write!(f, "browser connection closed: {why}"),
            Error::Crashed(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for Error {}

/// A running headless Chromium; ended, with everything it started, when dropped.
pub struct Browser {
    cdp: RefCell<Cdp>,
    timeout: Duration,
    version: String,
    launched_in: Duration,
    /// Last, so that the connection closes before the process is stopped.
    process: Process,
}

impl Browser {
    /// Starts Chromium (see [`LaunchOptions::program`]) and connects to it.
    pub fn launch(options: LaunchOptions) -> Result<Browser, Unavailable> {
        let started = Instant::now();
        let program = match &options.program {
            Some(program) if program.is_file() => program.clone(),
            Some(program) => {
                return Err(Unavailable(format!("{} is not a file", program.display())))
            }
            None => find_chromium()?,
        };
        let dir = crate::scratch("chromium");
        let profile = dir.path().join("profile");
        let home = dir.path().join("home");
        let tmp = dir.path().join("tmp");
        for d in [&profile, &home, &tmp] {
            std::fs::create_dir(d)
                .map_err(|e| Unavailable(format!("creating {}: {e}", d.display())))?;
        }
        let log_path = dir.path().join("chromium.log");
        let log = std::fs::File::create(&log_path)
            .map_err(|e| Unavailable(format!("creating {}: {e}", log_path.display())))?;
        let mut command = Command::new(&program);
        command
            .args(FLAGS)
            .arg(format!("--user-data-dir={}", profile.display()))
            .args(&options.args)
            .arg("about:blank")
            // Chromium's own temporary files, its crash reports and whatever it keeps in the
            // home folder all stay in the scratch folder.
            .env("TMPDIR", &tmp)
            .env("HOME", &home)
            .env("XDG_CONFIG_HOME", home.join(".config"))
            .env("XDG_CACHE_HOME", home.join(".cache"))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log);
        let mut process = Process::start(command, dir, log_path)
            .map_err(|e| Unavailable(format!("starting {}: {e}", program.display())))?;

        let deadline = started + options.launch_timeout;
        let (port, path) = process
            .devtools_address(&profile, deadline)
            .map_err(|why| {
                Unavailable(format!(
                    "{} did not open its DevTools socket: {why}; its log ends:\n{}",
                    program.display(),
                    process.log_tail()
                ))
            })?;
        let addr = SocketAddr::from((Ipv4Addr::LOCALHOST, port));
        let left = deadline.saturating_duration_since(Instant::now());
        let cdp = Cdp::connect(addr, &path, left.max(Duration::from_secs(1))).map_err(|why| {
            Unavailable(format!(
                "the DevTools socket of {}: {why}",
                program.display()
            ))
        })?;
        let mut browser = Browser {
            cdp: RefCell::new(cdp),
            timeout: options.timeout,
            version: String::new(),
            launched_in: Duration::ZERO,
            process,
        };
        let version = browser
            .call(None, "Browser.getVersion", json!({}), deadline)
            .map_err(|e| Unavailable(format!("asking {} its version: {e}", program.display())))?;
        browser.version = version
            .get("product")
            .and_then(Value::as_str)
            .unwrap_or("unknown")
            .to_string();
        browser.launched_in = started.elapsed();
        Ok(browser)
    }

    /// Opens `url` in a new page shown on `viewport`, once its `load` event has fired.
    pub fn open(&self, url: &str, viewport: Viewport) -> Result<Page<'_>, Error> {
        Page::open(self, url, viewport)
    }

    /// The browser's name and version, such as `Chrome/148.0.7778.167`.
    pub fn version(&self) -> &str {
        &self.version
    }

    /// How long [`Browser::launch`] took, up to the browser answering its first command.
    pub fn launched_in(&self) -> Duration {
        self.launched_in
    }

    /// Chromium's main process.
    pub fn pid(&self) -> u32 {
        self.process.pid()
    }

    /// The scratch folder holding the profile, temporary files and log; removed on drop.
    pub fn folder(&self) -> &Path {
        self.process.folder()
    }

    /// What Chromium has written to its standard error so far (its log), for a failing
    /// test's message.
    pub fn log(&self) -> String {
        self.process.log_tail()
    }

    fn call(
        &self,
        session: Option<&str>,
        method: &str,
        params: Value,
        deadline: Instant,
    ) -> Result<Value, Error> {
        let limit = deadline.saturating_duration_since(Instant::now());
        self.cdp
            .borrow_mut()
            .call(session, method, params, deadline)
            .map_err(|e| match e {
                Error::Timeout(what) => Error::Timeout(format!("{what} (waited {limit:?})")),
                other => other,
            })
    }

    fn pump(&self, deadline: Instant) -> Result<(), Error> {
        self.cdp.borrow_mut().pump(deadline)
    }

    fn take_events(&self, session: &str) -> std::collections::VecDeque<Event> {
        self.cdp.borrow_mut().take_events(session)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // Asked to close, Chromium ends its child processes and removes its lock files itself; the
        // process guard then makes sure, with signals if it must.
        let asked = self
            .cdp
            .get_mut()
            .send(None, "Browser.close", json!({}))
            .is_ok();
        self.process.stop(if asked {
            Duration::from_secs(5)
        } else {
            Duration::ZERO
        });
    }
}

/// Starts a browser, or, where none can be started, prints why and returns `None` so that
/// the test can return early as skipped; with `BREAKSHOT_REQUIRE_BROWSER=1` it fails instead.
pub fn browser_or_skip(options: LaunchOptions) -> Option<Browser> {
    match Browser::launch(options) {
        Ok(browser) => Some(browser),
        Err(Unavailable(why)) => {
            let required = std::env::var("BREAKSHOT_REQUIRE_BROWSER").is_ok_and(|v| v == "1");
            skip(&why, required);
            None
        }
    }
}

/// Says that the running test is skipped because of `why`, or fails it if a browser is
/// `required`.
fn skip(why: &str, required: bool) {
    let test = std::thread::current()
        .name()
        .unwrap_or("a browser test")
        .to_string();
    if required {
        panic!("{test} needs a browser, and BREAKSHOT_REQUIRE_BROWSER=1: {why}");
    }
    eprintln!("SKIPPED {test}: {why}");
}

/// The Chromium program to run, or why there is none.
fn find_chromium() -> Result<PathBuf, Unavailable> {
    if let Some(named) = std::env::var_os("BREAKSHOT_CHROMIUM") {
        let named = PathBuf::from(named);
        return if named.is_file() {
            Ok(named)
        } else {
            Err(Unavailable(format!(
                "BREAKSHOT_CHROMIUM names {}, which is not a file",
                named.display()
            )))
        };
    }
    let debian = PathBuf::from("/usr/bin/chromium");
    if debian.is_file() {
        return Ok(debian);
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .flat_map(|dir| [dir.join("chromium"), dir.join("chromium-browser")])
        .find(|p| p.is_file())
        .ok_or_else(|| {
            Unavailable(
                "no Chromium: not at /usr/bin/chromium, no chromium or chromium-browser on the \
                 PATH, and BREAKSHOT_CHROMIUM is not set; install Debian's chromium package"
                    .into(),
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_browser_skips_unless_one_is_required() {
        skip("no Chromium here", false);
        let message = crate::tests::panic_message(|| skip("no Chromium here", true));
        assert!(message.contains("no Chromium here"), "{message}");
        assert!(message.contains("BREAKSHOT_REQUIRE_BROWSER=1"), "{message}");
    }

    #[test]
    fn a_program_that_is_not_there_is_unavailable() {
        let options = LaunchOptions {
            program: Some("/nonexistent/chromium".into()),
            ..LaunchOptions::default()
        };
        let Err(Unavailable(why)) = Browser::launch(options) else {
            panic!("no browser can start");
        };
        assert!(why.contains("/nonexistent/chromium"), "{why}");
    }
}
