//! The golden shots (`shared/tests/golden/shots.rs`) compiled to a WebAssembly module with a
//! plain C interface, so a JavaScript engine runs the very physics the browser client will,
//! and its results can be compared bit for bit with the native ones.
//!
//! The host calls [`golden_run`], which simulates every golden shot and returns the length of
//! the result text (the lines of `shared/tests/golden/hashes.txt`: `name events hash`), then
//! reads that many bytes of the module's memory from [`golden_ptr`]. `run.mjs` does this under
//! Node. No imports are needed and no JavaScript glue is generated.

#![warn(missing_docs)]

use std::sync::OnceLock;

#[path = "../../../shared/tests/golden/shots.rs"]
mod shots;

/// The result text, computed once and kept, so the pointer handed out stays valid.
static TEXT: OnceLock<String> = OnceLock::new();

/// The golden results as `hashes.txt` lists them, without its comment line.
pub fn text() -> &'static str {
    TEXT.get_or_init(|| shots::to_text(&shots::results()))
}

/// Simulates every golden shot (on the first call only) and returns the length in bytes of the
/// result text at [`golden_ptr`].
// `no_mangle` counts as unsafe code: it is what exports the function under its own name for
// the JavaScript host, and there is no other way to do that without generated glue.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn golden_run() -> usize {
    text().len()
}

/// Where the result text starts in the module's memory (UTF-8, [`golden_run`] bytes long);
/// null before [`golden_run`] has been called.
// `no_mangle`: as for `golden_run`.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn golden_ptr() -> *const u8 {
    TEXT.get().map_or(std::ptr::null(), |text| text.as_ptr())
}
