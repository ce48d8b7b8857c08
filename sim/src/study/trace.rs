//! What every method reports about a shot, in one form: the collisions and pockets in
//! order, and where each ball ended.

use breakshot_shared::physics::{EventKind, MotionState, Outcome, Shot, Table};
use glam::DVec2;

/// A collision or a pocket, as the study compares them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Contact {
    /// Two balls (lower index first).
    Balls(u16, u16),
    /// A ball and a rail or jaw.
    Cushion(u16),
    /// A ball fell into a pocket.
    Pocket(u16, u8),
}

/// A method's result for one shot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Collisions and pockets in the order the method found them.
    pub contacts: Vec<Contact>,
    /// Final position of each ball in scene coordinates; a pocketed ball counts as lying at
    /// its pocket's centre, so that a wrong pocket or a ball wrongly pocketed is an error
    /// of the size of the mistake.
    pub finals: Vec<DVec2>,
    /// The pocket each ball fell into.
    pub pockets: Vec<Option<u8>>,
}

impl Trace {
    /// The event-based engine's result in the study's form.
    pub fn from_outcome(shot: &Shot, outcome: &Outcome) -> Trace {
        let table = Table::new(shot.table);
        let contacts = outcome
            .events
            .iter()
            .filter_map(|e| match e.kind {
                EventKind::BallBall { a, b } => Some(Contact::Balls(a.min(b), a.max(b))),
                EventKind::BallCushion { ball, .. } => Some(Contact::Cushion(ball)),
                EventKind::BallPocket { ball, pocket } => Some(Contact::Pocket(ball, pocket)),
                _ => None,
            })
            .collect();
        let mut trace = Trace {
            contacts,
            ..Trace::default()
        };
        for s in &outcome.finals {
            let pocket = (s.motion == MotionState::Pocketed)
                .then_some(s.pocket)
                .flatten();
            trace.push_final(&table, s.pos, pocket);
        }
        trace
    }

    /// Records a ball's final place: `pos` in scene coordinates.
    pub fn push_final(&mut self, table: &Table, pos: DVec2, pocket: Option<u8>) {
        let place = match pocket.and_then(|k| table.pockets.get(k as usize)) {
            Some(p) => table.to_scene(p.center),
            None => pos,
        };
        self.finals.push(place);
        self.pockets.push(pocket);
    }

    /// The balls that were pocketed, in ball order.
    pub fn pocketed(&self) -> Vec<usize> {
        (0..self.pockets.len())
            .filter(|&i| self.pockets[i].is_some())
            .collect()
    }
}
