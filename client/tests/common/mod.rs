//! What the client's integration tests share: a server on loopback and a game played on it,
//! the window under a virtual display and its pictures, and a window's reports.

#[cfg(feature = "host")]
mod served;
#[cfg(feature = "host")]
#[allow(unused_imports)] // not every test file uses the server
pub use served::*;

pub mod reported;
pub mod screen;
