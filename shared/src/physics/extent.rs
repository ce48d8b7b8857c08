//! What the pair predictions read first of each ball's current piece (how it moves, and a
//! box holding its path), and the pass that finds, among every ball, those within reach of
//! another.

use glam::DVec2;

use super::motion::{MotionState, Piece};
use super::shot::Ctx;

/// How far (m) a box narrowed to a ball's path up to its next own event is widened
/// ([`Extent::narrow`]): far above the rounding of the box's corners (some 1e-15 m), so
/// that the paths of two balls whose widened boxes are more than a diameter apart stay
/// that far apart by much more than the root solver could ever miss.
pub(super) const HORIZON_MARGIN: f64 = 1e-9;

/// A set of balls, bit `i` for ball `i` (a shot has at most `MAX_BALLS`, 128, balls).
pub(super) type Balls = u128;

/// The set holding ball `i` alone.
#[inline]
pub(super) fn ball(i: usize) -> Balls {
    1 << i
}

/// The balls of `set`, in increasing order. Word by word: a bit of a 64-bit word is found
/// and cleared in one instruction each, of the 128-bit set in several, and most shots have
/// no ball past the first 64.
#[inline]
pub(super) fn members(set: Balls) -> Members {
    Members {
        words: [set as u64, (set >> 64) as u64],
        word: 0,
    }
}

/// The iterator of [`members`].
pub(super) struct Members {
    words: [u64; 2],
    word: usize,
}

impl Iterator for Members {
    type Item = usize;

    #[inline]
    fn next(&mut self) -> Option<usize> {
        while self.word < 2 {
            let bits = &mut self.words[self.word];
            if *bits != 0 {
                let bit = bits.trailing_zeros() as usize;
                *bits &= *bits - 1;
                return Some(64 * self.word + bit);
            }
            self.word += 1;
        }
        None
    }
}

/// How many balls `set` holds: one word's count when the high word is empty (a shot of at most
/// 64 balls), which without a population-count instruction costs half as much.
#[inline]
pub(super) fn count(set: Balls) -> u32 {
    let (low, high) = (set as u64, (set >> 64) as u64);
    if high == 0 {
        low.count_ones()
    } else {
        low.count_ones() + high.count_ones()
    }
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
        Extent {
            mobility,
            lo,
            hi,
            key: key(lo, hi, 2.0 * ctx.params.ball_radius),
        }
    }

    /// Narrows the box that [`Extent::apart`] and [`within_reach`] test to `lo`, `hi`, a box
    /// holding the path of a ball on the cloth from now up to its next own event (or later):
    /// no pair's prediction looks past either ball's next own event, so a pair whose boxes
    /// up to those are apart cannot meet before one of its balls changes (and re-predicts
    /// it). The box is widened by [`HORIZON_MARGIN`]; the box of the whole path (`lo`, `hi`
    /// of the extent) is left as it is.
    #[inline]
    pub(super) fn narrow(&mut self, lo: DVec2, hi: DVec2, diameter: f64) {
        let margin = DVec2::splat(HORIZON_MARGIN);
        self.key = key(lo - margin, hi + margin, diameter);
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

/// The key of the box from `lo` to `hi` for balls of diameter `d` (see [`Extent`]).
#[inline(always)]
fn key(lo: DVec2, hi: DVec2, d: f64) -> [f64; 4] {
    let lo_reach = lo - DVec2::splat(d);
    [hi.x, hi.y, -lo_reach.x, -lo_reach.y]
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
    // From the last ball down, so that each ball's bit is shifted into place one step at a
    // time (cheaper than a shift by its index); in one machine word when the balls fit.
    if extents.len() <= 64 {
        let mut near: u64 = 0;
        for b in extents.iter().rev() {
            near = near << 1 | u64::from(!apart(&probe, &b.key));
        }
        return Balls::from(near);
    }
    let mut near: Balls = 0;
    for b in extents.iter().rev() {
        near = near << 1 | Balls::from(!apart(&probe, &b.key));
    }
    near
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_are_the_set_bits_in_order() {
        let mut rng = crate::ai::Rng::new(0x9e37_79b9_7f4a_7c15u64);
        for k in 0..2_000 {
            let words = [rng.next_u64(), rng.next_u64()];
            // Sparse sets too, and sets with only one of the words.
            let sparse = [rng.next_u64() & rng.next_u64(), 0, u64::MAX][k % 3];
            let set = Balls::from(words[0] & sparse) | Balls::from(words[1]) << 64;
            let set = if k % 5 == 0 { set >> 64 } else { set };
            let scan: Vec<usize> = (0..128).filter(|&b| set & ball(b) != 0).collect();
            assert_eq!(members(set).collect::<Vec<_>>(), scan, "{set:#x}");
        }
        assert_eq!(members(0).next(), None);
        assert_eq!(members(ball(127)).collect::<Vec<_>>(), [127]);
    }

    #[test]
    fn narrowed_boxes_apart_have_no_contact() {
        // Random pairs of balls on the cloth (one of them now and then at rest), each with a
        // next own event somewhere along its piece: whenever their boxes narrowed to their
        // paths up to those events are apart, the solver finds no contact before the
        // earlier of the two. Many of the balls at rest sit within a few nanometres of the
        // margin, on either side of it.
        use super::super::ball_ball::collision_time;
        use super::super::motion::{BallState, MotionModel};
        use super::super::params::{Effects, Params};
        use glam::DVec3;
        let params = Params::default();
        let model = MotionModel::new(&params, &Effects::default());
        let (r, d) = (params.ball_radius, 2.0 * params.ball_radius);
        let mut rng = crate::ai::Rng::new(0x2545_f491_4f6c_dd1du64);
        let mut unit = || rng.unit();
        let extent = |p: &Piece, own: f64| {
            let (lo, hi) = p.path_box(p.t0, p.t_end);
            let mut e = Extent {
                mobility: Mobility::Cloth,
                lo,
                hi,
                key: key(lo, hi, d),
            };
            if p.start.motion.is_translating() {
                let (lo, hi) = p.path_box(p.t0, own);
                e.narrow(lo, hi, d);
            }
            e
        };
        let (mut dismissed, mut close, mut met) = (0, 0, 0);
        for k in 0..40_000 {
            let moving = |unit: &mut dyn FnMut() -> f64, pos: DVec2| {
                let mut s = BallState::at_rest(pos);
                s.vel = DVec2::new(unit() - 0.5, unit() - 0.5) * [0.2, 2.0, 12.0][k % 3];
                s.spin = DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) * 200.0;
                s.motion = MotionState::Sliding;
                s.classify(r);
                let p = Piece::new(0.0, s, &model);
                let own = p.t_end * [1e-3, 0.1, 0.5, 1.0][k % 4] * unit();
                (p, own)
            };
            let pos = DVec2::new(unit() - 0.5, unit() - 0.5) * 0.3;
            let (a, own_a) = moving(&mut unit, pos);
            let (b, own_b) = if k % 2 == 0 {
                let pos = DVec2::new(unit() - 0.5, unit() - 0.5) * 0.3;
                moving(&mut unit, pos)
            } else {
                // At rest a diameter (give or take a few nanometres) from the first ball's
                // place at its own event, across the side of its narrowed box that place
                // is on (when it is on one): as near to the margin as can be.
                let (lo, hi) = a.path_box(0.0, own_a);
                let end = a.pos_at(own_a.min(a.t_end));
                let off = d + (unit() - 0.5) * 8.0 * HORIZON_MARGIN;
                let side = if end.x == hi.x {
                    DVec2::X
                } else if end.x == lo.x {
                    -DVec2::X
                } else if end.y == hi.y {
                    DVec2::Y
                } else {
                    -DVec2::Y
                };
                let pos = end + side * off;
                let s = BallState::at_rest(pos);
                (Piece::new(0.0, s, &model), f64::INFINITY)
            };
            let (ea, eb) = (extent(&a, own_a), extent(&b, own_b));
            let until = own_a.min(own_b);
            let t = collision_time(&a, &b, 0.0, until, r);
            met += usize::from(t.is_some());
            if ea.apart(&eb) {
                dismissed += 1;
                assert_eq!(t, None, "{a:?} {b:?} {until}");
                if !b.start.motion.is_translating() {
                    close += 1;
                }
            }
        }
        assert!(
            dismissed > 5_000 && close > 5_000 && met > 5_000,
            "{dismissed} {close} {met}"
        );
    }

    #[test]
    fn within_reach_agrees_with_apart() {
        let mut rng = crate::ai::Rng::new(0x9e37_79b9_7f4a_7c15u64);
        let mut unit = || rng.unit();
        for n in [1, 2, 16, 63, 64, 65, 100, 128] {
            let extents: Vec<Extent> = (0..n)
                .map(|_| {
                    let lo = DVec2::new(unit() * 2.0, unit());
                    let hi = lo + DVec2::new(unit() * 0.3, unit() * 0.3);
                    Extent {
                        mobility: Mobility::Cloth,
                        lo,
                        hi,
                        key: key(lo, hi, 0.05715),
                    }
                })
                .collect();
            for i in 0..n {
                let mut expected: Balls = 0;
                for (j, b) in extents.iter().enumerate() {
                    let (a, b) = (&extents[i], b);
                    let (ra, rb) = (a.lo - DVec2::splat(0.05715), b.lo - DVec2::splat(0.05715));
                    let apart =
                        (ra.x > b.hi.x) | (rb.x > a.hi.x) | (ra.y > b.hi.y) | (rb.y > a.hi.y);
                    assert_eq!(a.apart(b), apart);
                    if !apart {
                        expected |= ball(j);
                    }
                }
                assert_eq!(within_reach(&extents, i), expected, "{n} {i}");
                assert_eq!(count(expected), expected.count_ones());
            }
        }
    }
}
