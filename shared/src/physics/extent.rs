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
    /// A box holding the piece's whole path (up to the horizon).
    pub(super) lo: DVec2,
    pub(super) hi: DVec2,
    /// The box's high corner and its low corner less a ball's diameter, negated:
    /// `[hi.x, hi.y, −(lo.x − d), −(lo.y − d)]`, so that [`Extent::apart`] is four
    /// comparisons of the same sense, side by side.
    key: [f64; 4],
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
        let lo_reach = lo - DVec2::splat(d);
        Extent {
            mobility,
            lo,
            hi,
            key: [hi.x, hi.y, -lo_reach.x, -lo_reach.y],
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

    /// The other side of [`Extent::apart`]'s comparisons for this box:
    /// `[lo.x − d, lo.y − d, −hi.x, −hi.y]` (negation is exact).
    #[inline]
    fn probe(&self) -> [f64; 4] {
        let k = &self.key;
        [-k[2], -k[3], -k[0], -k[1]]
    }

    /// True when the two boxes are more than a diameter apart, so the balls cannot meet:
    /// one box's low corner less a diameter beyond the other's high corner, on either axis,
    /// either way. (Every test is made, without branches: the pass runs it on every ball.)
    #[inline]
    pub(super) fn apart(&self, other: &Extent) -> bool {
        apart(&self.probe(), &other.key)
    }
}

/// [`Extent::apart`] from the probe of one box and the key of the other.
#[inline(always)]
fn apart(probe: &[f64; 4], key: &[f64; 4]) -> bool {
    (probe[0] > key[0]) | (probe[1] > key[1]) | (probe[2] > key[2]) | (probe[3] > key[3])
}

/// The balls whose boxes are within reach of ball `i`'s (not [`Extent::apart`]), ball `i`
/// among them: a few branch-free tests per ball, so that only the balls within reach are
/// looked at further.
pub(super) fn within_reach(extents: &[Extent], i: usize) -> Balls {
    let probe = extents[i].probe();
    let mut near: Balls = 0;
    // From the last ball down, so that each ball's bit is shifted into place one step at a
    // time (cheaper than a shift by its index).
    for b in extents.iter().rev() {
        near = near << 1 | Balls::from(!apart(&probe, &b.key));
    }
    near
}
