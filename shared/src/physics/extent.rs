//! What the pair predictions read first of each ball's current piece (how it moves, and a
//! box holding its path), and the pass that finds, among every ball, those within reach of
//! another.

use glam::DVec2;

use super::motion::{MotionState, Piece};
use super::shot::Ctx;

/// A set of balls, bit `i` for ball `i` (a shot has at most `MAX_BALLS`, 128, balls).
pub(super) type Balls = u128;

/// The set holding ball `i` alone.
#[inline]
pub(super) fn ball(i: usize) -> Balls {
    1 << i
}

/// How a ball's current piece moves, as far as pair predictions care.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mobility {
    /// Pocketed or off the table: it meets nothing.
    Gone,
    /// At rest or spinning on the spot: it meets only balls that move.
    Still,
    /// Sliding or rolling on the cloth.
    Cloth,
    /// In flight.
    Flying,
}

/// What the pair predictions read first of a ball's current piece, kept together and apart
/// from the piece so that a pass over every other ball stays quick.
#[derive(Clone, Copy, Debug)]
pub(super) struct Extent {
    pub(super) mobility: Mobility,
    /// A box holding the piece's whole path (up to the horizon), and its low corner less a
    /// ball's diameter.
    pub(super) lo: DVec2,
    pub(super) hi: DVec2,
    lo_reach: DVec2,
}

impl Extent {
    pub(super) fn of(p: &Piece, ctx: &Ctx) -> Extent {
        let motion = p.start.motion;
        let mobility = if motion.is_gone() {
            Mobility::Gone
        } else if motion == MotionState::Airborne {
            Mobility::Flying
        } else if motion.is_translating() {
            Mobility::Cloth
        } else {
            Mobility::Still
        };
        let end = p.t_end.min(ctx.limit);
        let (lo, hi) = if end.is_finite() || !motion.is_translating() {
            p.path_box(p.t0, end.max(p.t0))
        } else {
            (DVec2::NEG_INFINITY, DVec2::INFINITY)
        };
        let d = 2.0 * ctx.params.ball_radius;
        Extent {
            mobility,
            lo,
            hi,
            lo_reach: lo - DVec2::splat(d),
        }
    }

    /// False when the balls cannot meet whatever their paths: one is gone, or neither moves.
    #[inline]
    pub(super) fn may_meet(&self, other: &Extent) -> bool {
        let (a, b) = (self.mobility, other.mobility);
        !(a == Mobility::Gone
            || b == Mobility::Gone
            || (a == Mobility::Still && b == Mobility::Still))
    }

    /// True when the two boxes are more than a diameter apart, so the balls cannot meet.
    /// (Every test is made, without branches: the pass runs it on every ball.)
    #[inline]
    pub(super) fn apart(&self, other: &Extent) -> bool {
        (self.lo_reach.x > other.hi.x)
            | (other.lo_reach.x > self.hi.x)
            | (self.lo_reach.y > other.hi.y)
            | (other.lo_reach.y > self.hi.y)
    }
}

/// The balls whose boxes are within reach of ball `i`'s (not [`Extent::apart`]), ball `i`
/// among them: a few branch-free tests per ball, so that only the balls within reach are
/// looked at further.
pub(super) fn within_reach(extents: &[Extent], i: usize) -> Balls {
    let a = &extents[i];
    let mut near: Balls = 0;
    // From the last ball down, so that each ball's bit is shifted into place one step at a
    // time (cheaper than a shift by its index).
    for b in extents.iter().rev() {
        near = near << 1 | Balls::from(!a.apart(b));
    }
    near
}
