//! Breakshot's shared core, the same in the server, every client and the simulator: the
//! physics engine (`physics`), the rules of every game (`rules`), the computer player (`ai`),
//! the wire protocol and invites (`protocol`), game records (`replay`), scene files
//! (`scene`) and the state hash (`hash`). Pure and deterministic: no I/O, no clock, no
//! threads, the same bits on every platform (the browser's wasm32 included).

#![warn(missing_docs, unreachable_pub)]

pub mod ai;
pub mod hash;
pub mod physics;
pub mod protocol;
pub mod replay;
pub mod rules;
pub mod scene;
pub mod scene_code;
