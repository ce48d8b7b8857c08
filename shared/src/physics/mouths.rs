//! The pockets' mouths: each pocket with the jaws beside it, in one box, so that a ball's own
//! events look at a pocket and its jaws only when the ball's path comes near them.

use glam::DVec2;

use super::table::Table;

/// A pocket (if the table has any) and the jaws nearest to it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Mouth {
    /// A box holding the pocket's capture circle and the jaws' noses, less the distance at
    /// which a ball touches a nose (the shot's, added by [`Mouth::reach`]).
    lo: DVec2,
    hi: DVec2,
    /// The box widened for the shot being simulated ([`Mouth::reach`]).
    reach_lo: DVec2,
    reach_hi: DVec2,
    pub(super) pocket: Option<u8>,
    pub(super) jaws: Vec<u8>,
}

/// How far (m) a mouth's box is widened beyond its circles: a box dismissed by it is out of
/// reach of every circle by far more than the rounding of that test.
const MARGIN: f64 = 1e-9;

impl Mouth {
    /// The mouths of `table`: each jaw goes with its nearest pocket (the first of equally
    /// near ones); without pockets each jaw is a mouth of its own.
    pub(super) fn of(table: &Table) -> Vec<Mouth> {
        let square = |center: DVec2, radius: f64| {
            let r = DVec2::splat(radius);
            (center - r, center + r)
        };
        let mut mouths: Vec<Mouth> = table
            .pockets
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let (lo, hi) = square(p.center, p.radius);
                Mouth {
                    lo,
                    hi,
                    reach_lo: lo,
                    reach_hi: hi,
                    pocket: Some(k as u8),
                    jaws: Vec::new(),
                }
            })
            .collect();
        for (k, jaw) in table.jaws.iter().enumerate() {
            let (lo, hi) = square(jaw.center, jaw.radius);
            let nearest = table
                .pockets
                .iter()
                .enumerate()
                .map(|(m, p)| (m, (p.center - jaw.center).length_squared()))
                .fold(None, |best: Option<(usize, f64)>, (m, d)| match best {
                    Some((_, b)) if b <= d => best,
                    _ => Some((m, d)),
                });
            match nearest {
                Some((m, _)) => {
                    let mouth = &mut mouths[m];
                    mouth.lo = mouth.lo.min(lo);
                    mouth.hi = mouth.hi.max(hi);
                    mouth.jaws.push(k as u8);
                }
                None => mouths.push(Mouth {
                    lo,
                    hi,
                    reach_lo: lo,
                    reach_hi: hi,
                    pocket: None,
                    jaws: vec![k as u8],
                }),
            }
        }
        mouths
    }

    /// Widens the box for a shot in which a ball touches a nose at `contact` from its centre,
    /// once, for every [`Mouth::near`] of the shot.
    pub(super) fn reach(&mut self, contact: f64) {
        let reach = DVec2::splat(contact + MARGIN);
        (self.reach_lo, self.reach_hi) = (self.lo - reach, self.hi + reach);
    }

    /// False when the box from `lo` to `hi` is out of reach of the pocket and of every jaw
    /// nose, for a ball touching a nose at the `contact` last given to [`Mouth::reach`]: then
    /// none of them can be near that box.
    #[inline]
    pub(super) fn near(&self, lo: DVec2, hi: DVec2) -> bool {
        let (mlo, mhi) = (self.reach_lo, self.reach_hi);
        (lo.x <= mhi.x) & (mlo.x <= hi.x) & (lo.y <= mhi.y) & (mlo.y <= hi.y)
    }
}
