//! The physics built for the browser gives the same bits as the native build: the golden shots
//! (`shared/tests/golden/shots.rs`) compiled to `wasm32-unknown-unknown` and run under Node must
//! give every entry of `shared/tests/golden/hashes.txt` (the native truth, which the golden test
//! checks in debug and release) and of the same shots simulated natively in this run.
//!
//! The module is built with its own target folder (`target/web-golden`), so this build never
//! waits for the lock of the cargo that runs the test. Where the wasm32 target or Node is
//! missing the test says so and passes; with `BREAKSHOT_REQUIRE_WEB=1` (set by CI, which
//! installs both) it fails instead.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

use breakshot_testkit::run_ok;
use breakshot_testkit::web::{has_wasm_target, skip_web, workspace, WASM_TARGET as TARGET};

/// Skips the test with `why`, or fails it when CI requires the browser check.
fn skip(why: &str) {
    skip_web("wasm_golden", why)
}

/// A release build of the physics from nothing, on a slow machine.
const BUILD_LIMIT: Duration = Duration::from_secs(20 * 60);
/// Node simulating the golden shots (well under a second in practice).
const RUN_LIMIT: Duration = Duration::from_secs(120);

/// Name → `events hash` of each line of a hash list; comment lines are skipped, and a name
/// listed twice is an error.
fn entries(text: &str, what: &str) -> BTreeMap<String, String> {
    let mut entries = BTreeMap::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let (name, value) = line
            .split_once(' ')
            .unwrap_or_else(|| panic!("{what}: a line without a result: {line:?}"));
        let earlier = entries.insert(name.to_string(), value.trim().to_string());
        assert!(earlier.is_none(), "{what}: {name} is listed twice");
    }
    entries
}

/// Every difference of `got` from `want`, by name.
fn differences(want: &BTreeMap<String, String>, got: &BTreeMap<String, String>) -> Vec<String> {
    let mut out = Vec::new();
    for (name, w) in want {
        match got.get(name) {
            Some(g) if g == w => {}
            Some(g) => out.push(format!("{name}: want {w}, got {g}")),
            None => out.push(format!("{name}: missing")),
        }
    }
    for name in got.keys().filter(|n| !want.contains_key(*n)) {
        out.push(format!("{name}: not in the stored list ({})", got[name]));
    }
    out
}

/// The `node` program on the `PATH`, if there is one.
fn node() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("node"))
        .find(|p| p.is_file())
}

#[test]
fn the_browser_build_gives_the_native_bits() {
    let root = workspace();
    let stored_text = std::fs::read_to_string(root.join("shared/tests/golden/hashes.txt"))
        .expect("the stored golden hashes");
    let stored = entries(&stored_text, "hashes.txt");
    assert!(!stored.is_empty(), "hashes.txt lists no shots");

    // The native side, in this very run: the list the golden test checks.
    let native = entries(breakshot_web_golden::text(), "native");
    let changed = differences(&stored, &native);
    assert!(
        changed.is_empty(),
        "the native results differ from hashes.txt (run the golden test):\n{}",
        changed.join("\n")
    );

    let Some(node) = node() else {
        return skip("no `node` on the PATH; install Node.js (Debian: apt-get install nodejs)");
    };
    if !has_wasm_target() {
        return skip(&format!(
            "the {TARGET} target is not installed (rustup target add {TARGET})"
        ));
    }

    let target_dir = root.join("target/web-golden");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo"));
    run_ok(
        Command::new(cargo)
            .args(["build", "--release", "--locked", "--target", TARGET])
            .args(["-p", "breakshot-web-golden", "--target-dir"])
            .arg(&target_dir)
            .current_dir(&root),
        None,
        BUILD_LIMIT,
        "building the wasm module failed",
    );
    let module = target_dir.join(format!("{TARGET}/release/breakshot_web_golden.wasm"));

    let ran = run_ok(
        Command::new(node)
            .arg(root.join("web/golden/run.mjs"))
            .arg(&module),
        None,
        RUN_LIMIT,
        "node could not run the wasm module",
    );
    let text = String::from_utf8(ran.stdout).expect("the module's text is UTF-8");
    let wasm = entries(&text, "wasm");

    let from_stored = differences(&stored, &wasm);
    let from_native = differences(&native, &wasm);
    assert!(
        from_stored.is_empty() && from_native.is_empty(),
        "the wasm32 build gives other bits.\nAgainst hashes.txt:\n{}\nAgainst this run's native build:\n{}",
        from_stored.join("\n"),
        from_native.join("\n")
    );
    println!(
        "wasm_golden: all {} golden entries give the same bits in wasm32 (Node) as natively",
        wasm.len()
    );
}
