//! Breakshot's game client. The window (the `breakshot` binary) only reads input and draws;
//! everything that can be computed without a window lives here and is tested here.

pub mod play;
pub mod view;
