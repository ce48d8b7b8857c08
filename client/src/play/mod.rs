//! Playing without a window: the shot being set up and the mapping from mouse and keys to
//! commands ([`Controls`]), what a screen hears ([`GameEvent`]) and where the game is
//! decided ([`GameLink`]: at this computer, or over the network in `net`), the copy of the
//! game ([`Replica`]) and a screen's state around it ([`GameFlow`]), who chooses a seat's
//! moves when no person does ([`ComputerLink`] at one computer, [`Chooser`] online), and replays.

mod advice;
mod advice_offer;
mod aim;
mod chat;
mod chooser;
mod computer;
mod controls;
pub mod drill;
mod dropped;
mod event;
mod game_flow;
mod history;
pub mod leave;
mod link;
pub mod position;
mod replay;
mod replica;
mod touch;

pub use advice::{next_level, succeeded, Advice, Advisor, Chance, Measure, Request, PLAYED_TRIALS};
pub use advice_offer::AdviceOffer;
pub use aim::{Aim, AimShare};
pub use chat::{Chat, ChatKey, ChatLine};
pub use chooser::Chooser;
pub use computer::{ComputerLink, PlayedByComputer};
pub use controls::{Context, Controls, CueMode, Drag, InputFrame, Intent, Key, Tool};
pub use dropped::{open_dropped, Dropped};
pub use event::{AwayResult, GameEvent};
pub use game_flow::{GameFlow, Prompt};
pub use history::{History, Position};
pub use link::{GameLink, LocalLink, Shown};
pub use replay::{ReplayOpenError, ReplayViewer};
pub use replica::{Check, Replica};
pub use touch::{Gesture, TwoFingers};

pub(crate) use event::game_events;
