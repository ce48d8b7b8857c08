//! Breakshot's game client. The window (the `breakshot` binary) only reads input and draws;
//! everything that can be computed without a window lives here and is tested here.

#![warn(missing_docs, unreachable_pub)]

#[cfg(not(target_arch = "wasm32"))]
pub mod bot;
pub mod memory;
pub mod net;
pub mod play;
#[cfg(test)]
mod test_games;
pub mod view;
