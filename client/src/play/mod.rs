//! Playing without a window: the shot being set up, the mapping from mouse and keys to
//! commands, and the offline practice table.

mod aim;
mod chat;
mod computer;
mod controls;
mod game_flow;
pub mod leave;
mod link;
mod practice;
mod replay;
mod replica;

pub use aim::{Aim, AimShare};
pub use chat::{Chat, ChatKey, ChatLine};
pub use computer::ComputerLink;
pub use controls::{Context, Controls, Drag, InputFrame, Intent, Key, Stage};
pub use game_flow::{GameFlow, Turn};
pub use link::{AwayResult, GameEvent, GameLink, LocalLink};
pub use practice::{rack_scene, Practice, PracticeError};
pub use replay::{ReplayOpenError, ReplayViewer};
pub use replica::{Check, Replica};

pub(crate) use link::game_events;
