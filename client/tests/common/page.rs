//! A page of the web client in headless Chromium as its tests read it: the events it reports
//! (`window.breakshotEvents`), waiting for one, a tap made again until the page answers it,
//! and screenshots kept for a person to look at.
#![allow(dead_code)] // not every test file uses every part

use std::path::Path;
use std::time::Duration;

use breakshot_testkit::browser::Page;

/// How long a page may take to say what a test waits for.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// Saves a screenshot of `page` as `name` in the folder `BREAKSHOT_SCREENSHOTS` names, if any.
pub fn keep_screenshot(page: &mut Page<'_>, name: &str) {
    if let Ok(dir) = std::env::var("BREAKSHOT_SCREENSHOTS") {
        let png = page.screenshot_png().expect("a screenshot");
        std::fs::write(Path::new(&dir).join(name), png).expect("saved");
    }
}

/// The page's condition that one of its events starts with `prefix`.
pub fn said_starting(prefix: &str) -> String {
    format!("(window.breakshotEvents || []).some(e => e.startsWith({prefix:?}))")
}

/// Every event the page has reported, as JSON.
pub fn events(page: &mut Page<'_>) -> String {
    page.eval("JSON.stringify(window.breakshotEvents || [])")
        .map(|v| v.as_str().unwrap_or_default().to_owned())
        .unwrap_or_default()
}

/// Waits until the page reports an event starting with `prefix`; fails the test, with the
/// events reported, if none comes within `limit`.
pub fn wait_for_event(page: &mut Page<'_>, prefix: &str, limit: Duration) {
    let condition = said_starting(prefix);
    if let Err(e) = page.wait_until(&condition, limit) {
        panic!(
            "the page never said {prefix:?}: {e}\nits events: {}",
            events(page)
        );
    }
}

/// Waits until the page takes input: the game's first screen is made before the loader
/// installs its mouse, touch and drop handlers, so a tap sent at once would be lost.
pub fn wait_for_input(page: &mut Page<'_>) {
    if let Err(e) = page.wait_until("typeof window.ondrop === 'function'", PATIENCE) {
        panic!("the page never took input: {e}");
    }
}

/// Taps `at` until the page reports an event starting with `said`: a slow machine may take
/// the tap before the screen's first frame, so it is made again, as a person would, a few
/// times. Fails the test if the page never says it.
pub fn tapped_until(page: &mut Page<'_>, at: (f64, f64), said: &str) {
    let condition = said_starting(said);
    let answered = (0..6).any(|_| {
        page.tap(at).expect("a tap");
        page.wait_until(&condition, Duration::from_secs(10)).is_ok()
    });
    assert!(
        answered,
        "tapping {at:?} never made the page say {said:?}: {}",
        events(page)
    );
}
