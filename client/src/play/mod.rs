//! Playing without a window: the shot being set up, the mapping from mouse and keys to
//! commands, and the offline practice table.

pub mod aim;
pub mod chat;
pub mod computer;
pub mod controls;
pub mod game_flow;
pub mod leave;
pub mod link;
pub mod practice;
pub mod replay;
pub mod replica;
