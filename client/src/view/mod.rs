//! What the window shows, computed without a window: where things go on the screen, the
//! colours of the balls, the aiming aids, balls in flight, the animation of a shot, the 3-D
//! view's camera and the cue ball's trail.

pub mod aids;
pub mod camera;
pub mod choice;
pub mod flight;
pub mod hud;
pub mod layout;
pub mod orientation;
pub mod palette;
pub mod playback;
pub mod sound;
pub mod sphere;
pub mod trail;
pub mod tray;
