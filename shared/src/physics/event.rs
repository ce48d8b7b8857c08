//! What happens during a shot, in time order.

use serde::{Deserialize, Serialize};

use super::motion::MotionState;
use super::table::Cushion;

/// One event of a simulated shot. Ball indices refer to the shot's ball list.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// When it happened (s after the strike).
    pub t: f64,
    /// What happened, and to which balls.
    pub kind: EventKind,
}

/// The kinds of event, each with the balls it involves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// The cue struck this ball at t = 0.
    Strike {
        /// The ball struck.
        ball: u16,
    },
    /// Two balls collided (`a < b`).
    BallBall {
        /// The lower-numbered ball.
        a: u16,
        /// The higher-numbered ball.
        b: u16,
    },
    /// A ball bounced off a rail or a pocket jaw.
    BallCushion {
        /// The ball that bounced.
        ball: u16,
        /// The rail or jaw it touched (indices into the table's rails or jaws).
        cushion: Cushion,
    },
    /// A ball fell into a pocket (index into the table's pockets).
    BallPocket {
        /// The ball that fell.
        ball: u16,
        /// The pocket, 0..6 in the table's order (`lb`, `lc`, `lt`, `rb`, `rc`, `rt`).
        pocket: u8,
    },
    /// A ball's motion state changed by itself (friction, or a ball in flight settling on
    /// the cloth).
    Transition {
        /// The ball whose state changed.
        ball: u16,
        /// Its state before.
        from: MotionState,
        /// Its state after.
        to: MotionState,
    },
    /// A ball in flight bounced on the cloth and flies on.
    BallTable {
        /// The ball that bounced.
        ball: u16,
    },
    /// A ball flew over a rail and left the table; it stays off the table (its final state
    /// is `OffTable` and its rest time the time it left).
    BallOffTable {
        /// The ball that left.
        ball: u16,
    },
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
