//! The physics engine: closed-form motion between events, exact event times, and the
//! collision models. Pure and deterministic (see docs/physics.md).

pub mod airborne;
pub mod ball_ball;
pub mod ball_cushion;
pub mod cue;
mod earliest;
pub mod engine;
pub mod event;
mod extent;
mod group_impact;
pub mod mathavan;
pub mod motion;
mod mouths;
mod octic;
pub mod params;
pub mod roots;
mod shot;
pub mod stronge;
pub mod table;

pub use cue::{Launch, Strike, StrikeError};
pub use engine::{
    kinetic_energy, mechanical_energy, simulate, simulations_on_this_thread, Outcome, Shot,
    ShotError, Simulator, Work,
};
pub use event::{Event, EventKind};
pub use motion::{BallState, MotionState, Piece};
pub use params::{BallBallModel, BallFriction, CushionModel, Effects, Models, Params};
pub use table::{Cushion, Table, TableKind};
