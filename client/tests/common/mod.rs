//! What the client's integration tests share: a server on loopback and a game played on it,
//! the window under a virtual display and its pictures, and a window's reports.

#[cfg(feature = "host")]
mod served;
#[cfg(feature = "host")]
pub use served::*;

pub mod reported;
pub mod screen;
