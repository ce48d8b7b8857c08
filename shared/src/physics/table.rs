//! Table geometry: cushion noses (straight rails and the rounded jaws at the pockets) and the
//! pocket capture circles.
//!
//! The engine works in coordinates centred on the table (`x` from −W/2 to W/2, `y` from −L/2
//! to L/2) so that a mirror image of a shot (x → −x) is an exact negation in floating point and
//! a mirror-symmetric break stays symmetric to the last bit; scenes and results use the
//! contract's frame with the origin at a corner, and [`Table::to_engine`] /
//! [`Table::to_scene`] convert.
//!
//! Pocket layout (all six are the same shape as their mirror images):
//! - a rail ends `CORNER_MOUTH/√2` from the corner along each side of a corner pocket, and
//!   `SIDE_MOUTH/2` either side of the middle of a long side;
//! - at each rail end a jaw, a circle tangent to the nose line at the rail's end and lying
//!   behind it, rounds the nose into the pocket;
//! - a ball falls when its centre enters the pocket's capture circle.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// Corner pocket mouth, measured across between the two cushion noses (m).
pub const CORNER_MOUTH: f64 = 0.116;
/// Side pocket mouth along the rail (m).
pub const SIDE_MOUTH: f64 = 0.137;
/// Radius of the rounded nose at a corner pocket's jaws (m).
pub const CORNER_JAW_RADIUS: f64 = 0.0209;
/// Radius of the rounded nose at a side pocket's jaws (m).
pub const SIDE_JAW_RADIUS: f64 = 0.008;
/// Radius of a corner pocket's capture circle (m).
pub const CORNER_POCKET_RADIUS: f64 = 0.062;
/// How far a corner pocket's capture circle lies outside the corner along each axis (m).
pub const CORNER_POCKET_OFFSET: f64 = 0.02;
/// Radius of a side pocket's capture circle (m).
pub const SIDE_POCKET_RADIUS: f64 = 0.0645;
/// How far a side pocket's capture circle lies behind the nose line (m).
pub const SIDE_POCKET_OFFSET: f64 = 0.05;

// The snooker table's pockets. The WPBSA's pocket templates are not published; these are
// pooltool's tuned `SNOOKER_GENERIC` table (objects/table/collection.py, 2026), converted to
// this model: pooltool gives each mouth as the narrowest gap between its two jaw circles,
// and puts a jaw's rail end `r·(√2 − 1)` beyond the mouth's corner point at a corner pocket
// (a 45° jaw) and `r` beyond it at a middle pocket (a square jaw).
/// Snooker corner pocket: narrowest gap between the jaws (m).
pub const SNOOKER_CORNER_MOUTH: f64 = 0.08014;
/// Snooker corner pocket: radius of the rounded jaws (m).
pub const SNOOKER_CORNER_JAW_RADIUS: f64 = 0.0889;
/// Snooker corner pocket: radius of the capture circle (m).
pub const SNOOKER_CORNER_POCKET_RADIUS: f64 = 0.0889;
/// Snooker corner pocket: depth of the capture circle's centre along the diagonal (m).
pub const SNOOKER_CORNER_POCKET_DEPTH: f64 = 0.06735;
/// Snooker middle pocket: narrowest gap between the jaws (m).
pub const SNOOKER_SIDE_MOUTH: f64 = 0.08457;
/// Snooker middle pocket: radius of the rounded jaws (m).
pub const SNOOKER_SIDE_JAW_RADIUS: f64 = 0.0669;
/// Snooker middle pocket: radius of the capture circle (m).
pub const SNOOKER_SIDE_POCKET_RADIUS: f64 = 0.05319;
/// Snooker middle pocket: how far the capture circle lies behind the nose line (m).
pub const SNOOKER_SIDE_POCKET_OFFSET: f64 = 0.05159;

/// The shape of a pocket table's six pockets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PocketShape {
    /// How far a rail ends from the corner (the meeting of the nose lines) it runs to (m).
    pub corner_rail_end: f64,
    /// How far a rail ends from the middle of its long side (m).
    pub side_rail_end: f64,
    /// Radius of a corner pocket's jaws (m).
    pub corner_jaw_radius: f64,
    /// Radius of a middle pocket's jaws (m).
    pub side_jaw_radius: f64,
    /// Radius of a corner pocket's capture circle (m).
    pub corner_pocket_radius: f64,
    /// How far a corner pocket's capture circle lies outside the corner along each axis (m).
    pub corner_pocket_offset: f64,
    /// Radius of a middle pocket's capture circle (m).
    pub side_pocket_radius: f64,
    /// How far a middle pocket's capture circle lies behind the nose line (m).
    pub side_pocket_offset: f64,
}

impl PocketShape {
    /// The pool tables' pockets (the constants above).
    pub fn pool() -> PocketShape {
        PocketShape {
            corner_rail_end: CORNER_MOUTH / std::f64::consts::SQRT_2,
            side_rail_end: 0.5 * SIDE_MOUTH,
            corner_jaw_radius: CORNER_JAW_RADIUS,
            side_jaw_radius: SIDE_JAW_RADIUS,
            corner_pocket_radius: CORNER_POCKET_RADIUS,
            corner_pocket_offset: CORNER_POCKET_OFFSET,
            side_pocket_radius: SIDE_POCKET_RADIUS,
            side_pocket_offset: SIDE_POCKET_OFFSET,
        }
    }

    /// The snooker table's pockets (the `SNOOKER_` constants above).
    pub fn snooker() -> PocketShape {
        let sqrt2 = std::f64::consts::SQRT_2;
        PocketShape {
            corner_rail_end: SNOOKER_CORNER_MOUTH / sqrt2
                + SNOOKER_CORNER_JAW_RADIUS * (sqrt2 - 1.0),
            side_rail_end: 0.5 * SNOOKER_SIDE_MOUTH + SNOOKER_SIDE_JAW_RADIUS,
            corner_jaw_radius: SNOOKER_CORNER_JAW_RADIUS,
            side_jaw_radius: SNOOKER_SIDE_JAW_RADIUS,
            corner_pocket_radius: SNOOKER_CORNER_POCKET_RADIUS,
            corner_pocket_offset: SNOOKER_CORNER_POCKET_DEPTH / sqrt2,
            side_pocket_radius: SNOOKER_SIDE_POCKET_RADIUS,
            side_pocket_offset: SNOOKER_SIDE_POCKET_OFFSET,
        }
    }
}

/// The tables a scene can name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum TableKind {
    /// Unbounded cloth: no cushions, no pockets.
    #[serde(rename = "open")]
    Open,
    /// A 7-foot pool table: 1.9812 × 0.9906 m, six pockets.
    #[serde(rename = "7ft")]
    SevenFoot,
    /// An 8-foot pool table: 2.2352 × 1.1176 m, six pockets.
    #[serde(rename = "8ft")]
    EightFoot,
    /// A 9-foot pool table: 2.54 × 1.27 m, six pockets; the default.
    #[default]
    #[serde(rename = "9ft")]
    NineFoot,
    /// A UMB match table for carom games: no pockets, cushions all round.
    #[serde(rename = "carom")]
    Carom,
    /// A 12-foot snooker table: 3.569 × 1.778 m, six pockets shaped for snooker balls.
    #[serde(rename = "snooker")]
    Snooker,
}

impl TableKind {
    /// The name scenes give the table: `open`, `7ft`, `8ft`, `9ft`, `carom` or `snooker`.
    pub fn name(self) -> &'static str {
        match self {
            TableKind::Open => "open",
            TableKind::SevenFoot => "7ft",
            TableKind::EightFoot => "8ft",
            TableKind::NineFoot => "9ft",
            TableKind::Carom => "carom",
            TableKind::Snooker => "snooker",
        }
    }

    /// Playing surface (width across, length along) between the cushion noses, in metres.
    pub fn size(self) -> Option<(f64, f64)> {
        match self {
            TableKind::Open => None,
            TableKind::SevenFoot => Some((0.9906, 1.9812)),
            TableKind::EightFoot => Some((1.1176, 2.2352)),
            TableKind::NineFoot => Some((1.27, 2.54)),
            // UMB rules, art. 3: 2.84 m × 1.42 m between the cushion noses.
            TableKind::Carom => Some((1.42, 2.84)),
            // WPBSA, section 1: 11 ft 8½ in × 5 ft 10 in between the cushion noses.
            TableKind::Snooker => Some((1.778, 3.569)),
        }
    }

    /// Does this table have pockets?
    pub fn has_pockets(self) -> bool {
        !matches!(self, TableKind::Open | TableKind::Carom)
    }

    /// The shape of the pockets, on a table that has them.
    pub fn pocket_shape(self) -> PocketShape {
        match self {
            TableKind::Snooker => PocketShape::snooker(),
            _ => PocketShape::pool(),
        }
    }
}

/// A straight cushion nose from `a` to `b`; `normal` points into the playing area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rail {
    /// One end of the nose line (engine coordinates, m).
    pub a: DVec2,
    /// The other end.
    pub b: DVec2,
    /// Unit normal, pointing into the playing area.
    pub normal: DVec2,
}

/// A rounded cushion nose (a pocket jaw): a vertical cylinder of `radius` about `center`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jaw {
    /// The cylinder's axis (engine coordinates, m), behind the nose line.
    pub center: DVec2,
    /// The nose's radius (m): the table's [`PocketShape`] corner or side jaw radius.
    pub radius: f64,
}

/// A pocket: a ball whose centre comes within `radius` of `center` falls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pocket {
    /// `l` or `r` (the side, x < 0 or x > 0) then `b`, `c` or `t` (y < 0, middle, y > 0).
    pub name: &'static str,
    /// The capture circle's centre (engine coordinates, m), outside the playing area.
    pub center: DVec2,
    /// The capture circle's radius (m).
    pub radius: f64,
}

/// A table in engine coordinates (centred).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The table this is.
    pub kind: TableKind,
    /// Half the width and half the length of the playing surface (0 for the open table).
    pub half: DVec2,
    /// The straight cushion noses: six on a pocket table, four on a closed one, none open.
    pub rails: Vec<Rail>,
    /// The rounded noses at the pockets' jaws, two per rail of a pocket table.
    pub jaws: Vec<Jaw>,
    /// The six pockets in index order (`lb`, `lc`, `lt`, `rb`, `rc`, `rt`), or none.
    pub pockets: Vec<Pocket>,
}

/// Which cushion a ball touched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Cushion {
    /// A straight rail: index into [`Table::rails`].
    Rail(u8),
    /// A pocket jaw: index into [`Table::jaws`].
    Jaw(u8),
}

impl Table {
    /// The table of `kind` with its pockets (if it has any), centred on the origin.
    pub fn new(kind: TableKind) -> Table {
        let Some((width, length)) = kind.size() else {
            return Table {
                kind,
                half: DVec2::ZERO,
                rails: Vec::new(),
                jaws: Vec::new(),
                pockets: Vec::new(),
            };
        };
        let hw = 0.5 * width;
        let hl = 0.5 * length;
        if !kind.has_pockets() {
            return Table::closed(kind, DVec2::new(hw, hl));
        }
        let shape = kind.pocket_shape();
        let c = shape.corner_rail_end;
        let s = shape.side_rail_end;
        let rail = |a: DVec2, b: DVec2, normal: DVec2| Rail { a, b, normal };
        let rails = vec![
            rail(DVec2::new(-hw + c, -hl), DVec2::new(hw - c, -hl), DVec2::Y),
            rail(DVec2::new(-hw + c, hl), DVec2::new(hw - c, hl), -DVec2::Y),
            rail(DVec2::new(-hw, -hl + c), DVec2::new(-hw, -s), DVec2::X),
            rail(DVec2::new(-hw, s), DVec2::new(-hw, hl - c), DVec2::X),
            rail(DVec2::new(hw, -hl + c), DVec2::new(hw, -s), -DVec2::X),
            rail(DVec2::new(hw, s), DVec2::new(hw, hl - c), -DVec2::X),
        ];
        let mut jaws = Vec::with_capacity(12);
        for r in &rails {
            for end in [r.a, r.b] {
                let at_side = end.y.abs() < 0.5 * hl;
                let radius = if at_side && r.normal.y == 0.0 {
                    shape.side_jaw_radius
                } else {
                    shape.corner_jaw_radius
                };
                jaws.push(Jaw {
                    center: end - r.normal * radius,
                    radius,
                });
            }
        }
        let k = shape.corner_pocket_offset;
        let corner = |name, x: f64, y: f64| Pocket {
            name,
            center: DVec2::new(x + k * x.signum(), y + k * y.signum()),
            radius: shape.corner_pocket_radius,
        };
        let side = |name, x: f64| Pocket {
            name,
            center: DVec2::new(x + shape.side_pocket_offset * x.signum(), 0.0),
            radius: shape.side_pocket_radius,
        };
        let pockets = vec![
            corner("lb", -hw, -hl),
            side("lc", -hw),
            corner("lt", -hw, hl),
            corner("rb", hw, -hl),
            side("rc", hw),
            corner("rt", hw, hl),
        ];
        Table {
            kind,
            half: DVec2::new(hw, hl),
            rails,
            jaws,
            pockets,
        }
    }

    /// The table a shot plays on: without pockets (the `pockets` effect off) its rails run
    /// unbroken around the bed, as on a carom table, so no ball can leave through a mouth.
    pub fn for_shot(kind: TableKind, pockets: bool) -> Table {
        match kind.size() {
            Some((w, l)) if !pockets => Table::closed(kind, DVec2::new(0.5 * w, 0.5 * l)),
            _ => Table::new(kind),
        }
    }

    /// Four unbroken rails around a bed of half-extents `h`: no jaws, no pockets.
    fn closed(kind: TableKind, h: DVec2) -> Table {
        let rail = |a: DVec2, b: DVec2, normal: DVec2| Rail { a, b, normal };
        Table {
            kind,
            half: h,
            rails: vec![
                rail(DVec2::new(-h.x, -h.y), DVec2::new(h.x, -h.y), DVec2::Y),
                rail(DVec2::new(-h.x, h.y), DVec2::new(h.x, h.y), -DVec2::Y),
                rail(DVec2::new(-h.x, -h.y), DVec2::new(-h.x, h.y), DVec2::X),
                rail(DVec2::new(h.x, -h.y), DVec2::new(h.x, h.y), -DVec2::X),
            ],
            jaws: Vec::new(),
            pockets: Vec::new(),
        }
    }

    /// Whether a ball can fall anywhere (not on the open or carom table, nor with pockets off).
    pub fn has_pockets(&self) -> bool {
        !self.pockets.is_empty()
    }

    /// Whether there are rails at all (not on the open table).
    pub fn has_cushions(&self) -> bool {
        !self.rails.is_empty()
    }

    /// Scene (corner-origin) coordinates to engine (centred) coordinates.
    pub fn to_engine(&self, p: DVec2) -> DVec2 {
        p - self.half
    }

    /// Engine coordinates back to scene coordinates.
    pub fn to_scene(&self, p: DVec2) -> DVec2 {
        p + self.half
    }

    /// Half the sides of a box about the centre every point of which [`Table::fits`] with
    /// `contact` (by a margin far above the rounding of those tests: a micrometre), or `None`
    /// when no such box was found. A check of many balls passes those well inside it at two
    /// comparisons each: a box `DEEP_INSET` inside the rails' reach, kept only when it is
    /// clear of every rail, jaw and pocket.
    pub fn deep_interior(&self, contact: f64) -> Option<DVec2> {
        const DEEP_INSET: f64 = 0.15;
        const SLACK: f64 = 1e-6;
        let half = self.half - DVec2::splat(contact + DEEP_INSET);
        if !(self.has_cushions() && half.x > 0.0 && half.y > 0.0 && contact.is_finite()) {
            return None;
        }
        // The box's nearest approach to each: a rail's line (its normal points into the
        // table), a jaw's circle less the touch, a pocket's capture circle.
        let clear_of_rails = self.rails.iter().all(|rail| {
            let n = rail.normal;
            -(n.x.abs() * half.x + n.y.abs() * half.y) - n.dot(rail.a) >= contact + SLACK
        });
        let gap = |center: DVec2| (center.clamp(-half, half) - center).length();
        let clear_of_jaws = self
            .jaws
            .iter()
            .all(|j| gap(j.center) >= j.radius + contact + SLACK);
        let clear_of_pockets = self
            .pockets
            .iter()
            .all(|pk| gap(pk.center) >= pk.radius + SLACK);
        (clear_of_rails && clear_of_jaws && clear_of_pockets).then_some(half)
    }

    /// Can a ball rest with its centre at `p` (engine coordinates)? It must be clear of every
    /// rail and jaw (`contact` is the horizontal distance at which a ball touches a cushion
    /// nose), not inside a pocket's capture circle, and either within the rails or hanging in
    /// a pocket's mouth.
    pub fn fits(&self, p: DVec2, contact: f64) -> bool {
        if !self.has_cushions() {
            return true;
        }
        let eps = 1e-9;
        let inside =
            p.x.abs() <= self.half.x - contact + eps && p.y.abs() <= self.half.y - contact + eps;
        // Only asked when not inside (as a closure, so that a ball inside pays nothing).
        let in_a_mouth = || {
            self.pockets.iter().any(|pk| {
                (p - pk.center).length() <= pk.radius + 2.0 * contact
                    || self.between_jaws(pk, p, contact)
            })
        };
        let clear_of_rails = self.rails.iter().all(|rail| {
            let along = rail.b - rail.a;
            let k = along.dot(p - rail.a) / along.length_squared();
            !(0.0..=1.0).contains(&k) || rail.normal.dot(p - rail.a) >= contact - eps
        });
        (inside || in_a_mouth())
            && clear_of_rails
            && self
                .jaws
                .iter()
                .all(|j| (p - j.center).length() >= j.radius + contact - eps)
            && self
                .pockets
                .iter()
                .all(|pk| (p - pk.center).length() > pk.radius)
    }

    /// Whether `p` lies in the mouth of pocket `pk`: between its two jaws (within the span
    /// of the line through their centres) and on the table's side of that line. A ball can
    /// come to rest there against a jaw's curve, past the line of the rails beside it; the
    /// rails and jaws themselves are checked apart.
    fn between_jaws(&self, pk: &Pocket, p: DVec2, contact: f64) -> bool {
        let mut nearest = self
            .jaws
            .iter()
            .map(|j| ((j.center - pk.center).length_squared(), j));
        let Some(first) = nearest.next() else {
            return false;
        };
        // The two jaws nearest the pocket, without sorting (and without allocating).
        let (mut a, mut b) = (first, (f64::INFINITY, first.1));
        for jaw in nearest {
            if jaw.0 < a.0 {
                (a, b) = (jaw, a);
            } else if jaw.0 < b.0 {
                b = jaw;
            }
        }
        let (a, b) = (a.1, b.1);
        let along = b.center - a.center;
        let k = along.dot(p - a.center) / along.length_squared();
        // Signed distance from the line through the jaws' centres, positive on the table's
        // side. The rails beside the mouth are tangent to the jaws, so a ball touching them
        // or past them is within a jaw's radius and a touch of that line.
        let unit = along.normalize();
        let side = |q: DVec2| unit.perp_dot(q - a.center);
        let towards_table = side(DVec2::ZERO).signum();
        let depth = side(p) * towards_table;
        (0.0..=1.0).contains(&k) && depth > 0.0 && depth <= a.radius.max(b.radius) + contact
    }

    /// Names of the six pockets in index order.
    pub fn pocket_names(&self) -> Vec<&'static str> {
        self.pockets.iter().map(|p| p.name).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_of_the_deep_interior_fits() {
        let mut rng = crate::ai::Rng::new(0x9e37_79b9_7f4a_7c15u64);
        let mut unit = || rng.unit();
        let kinds = [
            TableKind::SevenFoot,
            TableKind::EightFoot,
            TableKind::NineFoot,
            TableKind::Carom,
            TableKind::Snooker,
        ];
        for kind in kinds {
            for pockets in [true, false] {
                let table = Table::for_shot(kind, pockets);
                for contact in [0.0, 0.01, 0.02858, 0.04] {
                    let half = table.deep_interior(contact).expect("a deep interior");
                    for k in 0..2_000 {
                        // Corners and edges of the box, and points inside it.
                        let mut along = || match k % 3 {
                            0 => [-1.0, 1.0][(unit() * 2.0) as usize],
                            _ => 2.0 * unit() - 1.0,
                        };
                        let p = DVec2::new(along() * half.x, along() * half.y);
                        assert!(table.fits(p, contact), "{kind:?} {contact} {p}");
                    }
                }
            }
        }
        assert_eq!(Table::new(TableKind::Open).deep_interior(0.0), None);
    }

    #[test]
    fn pocket_table_is_mirror_symmetric() {
        let t = Table::new(TableKind::NineFoot);
        let mirror = |p: DVec2| DVec2::new(-p.x, p.y);
        for r in &t.rails {
            assert!(t.rails.iter().any(|q| {
                let ends = (q.a == mirror(r.a) && q.b == mirror(r.b))
                    || (q.a == mirror(r.b) && q.b == mirror(r.a));
                ends && q.normal == mirror(r.normal)
            }));
        }
        for j in &t.jaws {
            assert!(t
                .jaws
                .iter()
                .any(|k| k.center == mirror(j.center) && k.radius == j.radius));
        }
        for p in &t.pockets {
            assert!(t.pockets.iter().any(|q| q.center == mirror(p.center)));
        }
        assert_eq!(t.jaws.len(), 12);
    }

    #[test]
    fn carom_table_is_closed_and_umb_sized() {
        let t = Table::new(TableKind::Carom);
        assert_eq!(t.half, DVec2::new(0.71, 1.42));
        assert_eq!(t.rails.len(), 4);
        assert!(t.jaws.is_empty() && t.pockets.is_empty());
        assert_eq!(t, Table::for_shot(TableKind::Carom, true));
        // A carom ball (R = 30.75 mm) fits into a corner but not past the cushion noses.
        let contact = 0.03;
        assert!(t.fits(DVec2::new(0.71 - contact, 1.42 - contact), contact));
        assert!(!t.fits(DVec2::new(0.71 - 0.5 * contact, 0.0), contact));
    }

    #[test]
    fn snooker_table_is_wpbsa_sized_with_pooltools_pockets() {
        let t = Table::new(TableKind::Snooker);
        assert_eq!(t.half, DVec2::new(0.889, 1.7845));
        assert_eq!((t.rails.len(), t.jaws.len(), t.pockets.len()), (6, 12, 6));
        // The narrowest gap between a pocket's two jaws is the mouth pooltool gives.
        let gap = |a: &Jaw, b: &Jaw| (a.center - b.center).length() - a.radius - b.radius;
        let nearest = |j: &Jaw| {
            t.jaws
                .iter()
                .filter(|k| *k != j)
                .map(|k| gap(j, k))
                .fold(f64::INFINITY, f64::min)
        };
        let corner = t
            .jaws
            .iter()
            .find(|j| j.radius == SNOOKER_CORNER_JAW_RADIUS);
        let side = t.jaws.iter().find(|j| j.radius == SNOOKER_SIDE_JAW_RADIUS);
        let (Some(corner), Some(side)) = (corner, side) else {
            panic!("both jaw sizes are present");
        };
        assert!((nearest(corner) - SNOOKER_CORNER_MOUTH).abs() < 1e-12);
        assert!((nearest(side) - SNOOKER_SIDE_MOUTH).abs() < 1e-12);
    }

    #[test]
    fn a_ball_at_rest_against_a_jaw_past_the_rail_line_is_on_the_table_and_one_behind_it_is_not() {
        use crate::physics::{ball_cushion, Params};
        let t = Table::new(TableKind::Snooker);
        let contact = ball_cushion::contact_distance(&Params::for_table(TableKind::Snooker));
        // Where a random frame left the yellow: rolled into the right middle pocket's mouth
        // and stopped against its jaw, its centre 1.3 mm past the line of the rails.
        let rested = t.to_engine(DVec2::new(1.7552205780777315, 1.877500766985024));
        assert!(rested.x > t.half.x - contact);
        assert!(t.fits(rested, contact));
        // The same mouth across the pocket, mirrored.
        assert!(t.fits(DVec2::new(rested.x, -rested.y), contact));
        // Behind the pocket, outside the table: not on it, though clear of every rail and jaw.
        let behind = t.pockets[4].center + DVec2::new(0.12, 0.0);
        assert!(!t.fits(behind, contact));
        // Past the line through the jaws' centres, between them, the ball is over the pocket.
        let jaws_line = DVec2::new(0.9559, 0.05);
        assert!(!t.fits(jaws_line, contact));
    }

    #[test]
    fn pool_pockets_are_unchanged() {
        let shape = PocketShape::pool();
        assert_eq!(
            shape.corner_rail_end,
            CORNER_MOUTH / std::f64::consts::SQRT_2
        );
        assert_eq!(shape.side_rail_end, 0.5 * SIDE_MOUTH);
    }

    #[test]
    fn open_table_has_nothing() {
        let t = Table::new(TableKind::Open);
        assert!(t.rails.is_empty() && t.jaws.is_empty() && t.pockets.is_empty());
        assert!(t.fits(DVec2::new(1e6, -1e6), 0.028));
    }
}
