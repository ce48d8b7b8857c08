//! What a shot did, as the rules see it, read from the physics events.

use serde::{Deserialize, Serialize};

use crate::physics::{EventKind, Outcome};

/// The cue ball's number (and index in the ball list).
pub const CUE: u8 = 0;

/// The facts of one shot that the rules judge.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShotFacts {
    /// The first ball the cue ball touched, if any.
    pub first_contact: Option<u8>,
    /// Some ball (the cue ball included) touched a cushion (rail or jaw) after the first
    /// contact.
    pub cushion_after_contact: bool,
    /// Object balls that touched a cushion at any time in the shot, each once, in order.
    pub object_balls_to_cushion: Vec<u8>,
    /// Balls that fell, with the pocket, in the order they fell (the cue ball included).
    pub pocketed: Vec<(u8, u8)>,
    /// Balls driven off the table, in order. The engine is two-dimensional and never lifts a
    /// ball, so this is always empty for simulated shots; the rules still judge it so that
    /// the clauses stay whole if a future engine can jump balls.
    pub off_table: Vec<u8>,
}

impl ShotFacts {
    /// Reads the facts from a simulated shot whose ball indices are ball numbers.
    pub fn from_outcome(outcome: &Outcome) -> ShotFacts {
        let mut facts = ShotFacts::default();
        for event in &outcome.events {
            match event.kind {
                EventKind::BallBall { a, b } => {
                    if facts.first_contact.is_none() {
                        if a == u16::from(CUE) {
                            facts.first_contact = Some(b as u8);
                        } else if b == u16::from(CUE) {
                            facts.first_contact = Some(a as u8);
                        }
                    }
                }
                EventKind::BallCushion { ball, .. } => {
                    if facts.first_contact.is_some() {
                        facts.cushion_after_contact = true;
                    }
                    let ball = ball as u8;
                    if ball != CUE && !facts.object_balls_to_cushion.contains(&ball) {
                        facts.object_balls_to_cushion.push(ball);
                    }
                }
                EventKind::BallPocket { ball, pocket } => facts.pocketed.push((ball as u8, pocket)),
                EventKind::Strike { .. }
                | EventKind::Transition { .. }
                | EventKind::BallTable { .. }
                | EventKind::BallOffTable { .. } => {}
            }
        }
        facts
    }

    /// The cue ball fell in a pocket or left the table.
    pub fn scratched(&self) -> bool {
        self.fell(CUE) || self.off_table.contains(&CUE)
    }

    /// `ball` fell in a pocket.
    pub fn fell(&self, ball: u8) -> bool {
        self.pocketed.iter().any(|&(b, _)| b == ball)
    }

    /// The pocket `ball` fell into.
    pub fn pocket_of(&self, ball: u8) -> Option<u8> {
        self.pocketed
            .iter()
            .find(|&&(b, _)| b == ball)
            .map(|&(_, p)| p)
    }

    /// Object balls that fell, in order.
    pub fn object_balls_pocketed(&self) -> impl Iterator<Item = u8> + '_ {
        self.pocketed.iter().map(|&(b, _)| b).filter(|&b| b != CUE)
    }

    /// Some object ball fell.
    pub fn any_object_ball_pocketed(&self) -> bool {
        self.object_balls_pocketed().next().is_some()
    }

    /// The common foul of a shot that hits a ball but sends nothing to a pocket or a cushion.
    pub fn no_cushion_after_contact(&self) -> bool {
        self.first_contact.is_some() && !self.cushion_after_contact && self.pocketed.is_empty()
    }
}
