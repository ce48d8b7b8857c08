//! What happens during a shot, in time order.

use serde::{Deserialize, Serialize};

use super::motion::MotionState;
use super::table::Cushion;

/// One event of a simulated shot. Ball indices refer to the shot's ball list.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    pub t: f64,
    pub kind: EventKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// The cue struck this ball at t = 0.
    Strike { ball: u16 },
    /// Two balls collided (`a < b`).
    BallBall { a: u16, b: u16 },
    /// A ball bounced off a rail or a pocket jaw.
    BallCushion { ball: u16, cushion: Cushion },
    /// A ball fell into a pocket (index into the table's pockets).
    BallPocket { ball: u16, pocket: u8 },
    /// A ball's motion state changed by itself (friction, or a ball in flight settling on
    /// the cloth).
    Transition {
        ball: u16,
        from: MotionState,
        to: MotionState,
    },
    /// A ball in flight bounced on the cloth and flies on.
    BallTable { ball: u16 },
    /// A ball flew over a rail and left the table; it stays off the table (its final state
    /// is `OffTable` and its rest time the time it left).
    BallOffTable { ball: u16 },
}

impl EventKind {
    /// The name the scene contract gives this kind of event.
    pub fn name(&self) -> String {
        match self {
            EventKind::Strike { .. } => "strike".into(),
            EventKind::BallBall { .. } => "ball_ball".into(),
            EventKind::BallCushion { .. } => "ball_cushion".into(),
            EventKind::BallPocket { .. } => "ball_pocket".into(),
            EventKind::Transition { from, to, .. } => format!("{}_to_{}", from.name(), to.name()),
            EventKind::BallTable { .. } => "ball_table".into(),
            EventKind::BallOffTable { .. } => "ball_off_table".into(),
        }
    }

    /// The balls involved, in order.
    pub fn balls(&self) -> ([u16; 2], usize) {
        match *self {
            EventKind::Strike { ball }
            | EventKind::BallCushion { ball, .. }
            | EventKind::BallPocket { ball, .. }
            | EventKind::Transition { ball, .. }
            | EventKind::BallTable { ball }
            | EventKind::BallOffTable { ball } => ([ball, 0], 1),
            EventKind::BallBall { a, b } => ([a, b], 2),
        }
    }
}
