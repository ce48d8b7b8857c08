//! What the window shows, computed without a window: where things go on the screen, the
//! colours of the balls, the aiming aids, balls in flight, the animation of a shot, the 3-D
//! view's camera and the cue ball's trail.

pub mod aids;
mod camera;
mod choices;
mod flight;
pub mod hud;
mod layout;
mod orientation;
pub mod palette;
mod playback;
pub mod snooker;
pub mod sound;
pub mod sphere;
pub mod text;
mod trail;
pub mod tray;

pub use camera::{area, Camera, Orbit, ViewKind};
pub use choices::{choice_at, choice_buttons};
pub use flight::{flight, Flight};
pub use layout::{
    lobby_bar, lobby_line, lobby_row, lobby_rows, lobby_top, menu_buttons, replay_page, Frame,
    Layout, Rect, ReplayPageBoxes, CUSHION_WIDTH, LOBBY_BAR, RAIL_WIDTH,
};
pub use orientation::Orientations;
pub use playback::{Playback, PocketDrop, Stroke};
pub use trail::{Trail, TrailPoint};

pub(crate) use playback::{MAX_SPEED, MIN_SPEED};
