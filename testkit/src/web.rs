//! What the browser tests share: whether this machine can build the web client, and the
//! bundle itself, built once per test binary with `web/build.sh` (in its own target folder,
//! so the build never waits for the lock of the cargo that runs the tests).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::Duration;

use crate::run;

/// The browser's target.
pub const WASM_TARGET: &str = "wasm32-unknown-unknown";
/// A release build of the web client from nothing, on a slow machine.
const BUILD_LIMIT: Duration = Duration::from_secs(20 * 60);

/// The workspace's root folder.
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the test kit sits in the workspace")
        .to_path_buf()
}

/// Whether the compiler has the standard library for wasm32 (rustup's
/// `rustup target add wasm32-unknown-unknown`).
pub fn has_wasm_target() -> bool {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| OsString::from("rustc"));
    let out = run(
        Command::new(rustc)
            .args(["--print", "target-libdir", "--target", WASM_TARGET])
            .current_dir(workspace()),
        None,
        Duration::from_secs(60),
    );
    let dir = String::from_utf8_lossy(&out.stdout).trim().to_string();
    out.status.success()
        && std::fs::read_dir(&dir).is_ok_and(|mut files| {
            files.any(|f| f.is_ok_and(|f| f.file_name().to_string_lossy().starts_with("libstd-")))
        })
}

/// Skips the test `test` with `why`, or fails it when CI requires the web tests
/// (`BREAKSHOT_REQUIRE_WEB=1`).
pub fn skip_web(test: &str, why: &str) {
    let why = format!("SKIPPED {test}: {why}");
    if std::env::var("BREAKSHOT_REQUIRE_WEB").is_ok_and(|v| v == "1") {
        panic!("{why} (BREAKSHOT_REQUIRE_WEB=1)");
    }
    eprintln!("{why}");
}

/// The web bundle (`index.html`, the loader, `breakshot.wasm`), built by `web/build.sh`
/// into `target/web-bundle`; `Err` says why it could not be.
pub fn bundle() -> Result<&'static Path, String> {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BUILT
        .get_or_init(|| {
            if !has_wasm_target() {
                return Err(format!(
                    "the {WASM_TARGET} target is not installed (rustup target add {WASM_TARGET})"
                ));
            }
            let root = workspace();
            let out = root.join("target/web-bundle");
            let built = run(
                Command::new("bash")
                    .arg(root.join("web/build.sh"))
                    .arg(&out)
                    .env("CARGO_TARGET_DIR", root.join("target/web-client"))
                    .current_dir(&root),
                None,
                BUILD_LIMIT,
            );
            if !built.status.success() {
                return Err(format!(
                    "web/build.sh failed:\n{}",
                    String::from_utf8_lossy(&built.stderr)
                ));
            }
            Ok(out)
        })
        .as_deref()
        .map_err(Clone::clone)
}
