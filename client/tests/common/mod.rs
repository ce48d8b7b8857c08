//! What the client's integration tests share: a server on loopback and a game played on it,
//! the window under a virtual display and its pictures, a window's reports, and a page of the
//! web client in a browser.

#[cfg(feature = "host")]
mod served;
#[cfg(feature = "host")]
#[allow(unused_imports)] // not every test file uses the server
pub use served::*;

pub mod page;
pub mod reported;
pub mod screen;
