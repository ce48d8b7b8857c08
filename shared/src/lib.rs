//! Breakshot's shared core: the physics engine, scenes, and the state hash. Pure and
//! deterministic: no I/O, no clock, no threads.

#![warn(missing_docs, unreachable_pub)]

pub mod ai;
pub mod hash;
pub mod physics;
pub mod protocol;
pub mod replay;
pub mod rules;
pub mod scene;
pub mod scene_code;
