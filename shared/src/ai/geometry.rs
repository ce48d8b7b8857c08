//! The table as the player sees it: where the balls and pockets are, which paths are clear,
//! and how hard a pot looks before anything is simulated.

use glam::DVec2;

use crate::physics::{BallState, MotionState, Params, Table, TableKind};

/// A pocket seen from the table: its capture centre, the middle of its mouth, and the
/// direction a ball ideally enters it (outwards).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PocketView {
    pub index: u8,
    pub center: DVec2,
    pub mouth: DVec2,
    pub outward: DVec2,
    pub corner: bool,
}

/// A snapshot of the balls on the table, in scene coordinates.
#[derive(Clone, Debug)]
pub(super) struct Layout {
    pub size: DVec2,
    pub radius: f64,
    /// `(ball number, position)` of every ball on the table, the cue ball included.
    pub balls: Vec<(u8, DVec2)>,
    pub pockets: Vec<PocketView>,
}

/// Half-width (m) of the band a ball's centre can pass through a pocket's mouth, for a ball
/// coming straight in; an angled approach narrows it.
const CORNER_WINDOW: f64 = 0.03;
const SIDE_WINDOW: f64 = 0.034;

impl Layout {
    pub(super) fn new(kind: TableKind, balls: &[BallState]) -> Layout {
        let table = Table::new(kind);
        let (w, l) = crate::rules::rack::table_size(kind);
        let size = DVec2::new(w, l);
        let pockets = table
            .pockets
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let center = table.to_scene(p.center);
                let corner = p.name != "lc" && p.name != "rc";
                let sx = if center.x < 0.5 * w { -1.0 } else { 1.0 };
                let (mouth, outward) = if corner {
                    let sy = if center.y < 0.5 * l { -1.0 } else { 1.0 };
                    (
                        DVec2::new(0.5 * w + sx * 0.5 * w, 0.5 * l + sy * 0.5 * l),
                        DVec2::new(sx, sy).normalize(),
                    )
                } else {
                    (
                        DVec2::new(0.5 * w + sx * 0.5 * w, 0.5 * l),
                        DVec2::new(sx, 0.0),
                    )
                };
                PocketView {
                    index: i as u8,
                    center,
                    mouth,
                    outward,
                    corner,
                }
            })
            .collect();
        let on_table = balls
            .iter()
            .enumerate()
            .filter(|(_, b)| b.motion != MotionState::Pocketed)
            .map(|(i, b)| (i as u8, b.pos))
            .collect();
        Layout {
            size,
            radius: Params::default().ball_radius,
            balls: on_table,
            pockets,
        }
    }

    pub(super) fn pos(&self, ball: u8) -> Option<DVec2> {
        self.balls.iter().find(|(b, _)| *b == ball).map(|(_, p)| *p)
    }

    pub(super) fn cue(&self) -> Option<DVec2> {
        self.pos(0)
    }

    /// Does a ball moving from `a` to `b` pass clear of every ball but those in `skip`?
    pub(super) fn clear(&self, a: DVec2, b: DVec2, skip: &[u8]) -> bool {
        let d = 2.0 * self.radius;
        self.balls
            .iter()
            .filter(|(n, _)| !skip.contains(n))
            .all(|(_, p)| segment_distance(a, b, *p) >= d)
    }

    /// The chance of potting `ball` in `pocket` straight from the cue ball at `cue`, by the
    /// geometry alone, for a player whose aim errs with standard deviation `aim_sigma`
    /// (radians): zero if a path is blocked or the cut is too thin.
    pub(super) fn pot_chance(
        &self,
        cue: DVec2,
        ball: u8,
        pocket: &PocketView,
        aim_sigma: f64,
    ) -> f64 {
        let Some(ob) = self.pos(ball) else {
            return 0.0;
        };
        let to_pocket = pocket.center - ob;
        let d2 = to_pocket.length();
        if d2 < 1e-9 {
            return 0.0;
        }
        let u2 = to_pocket / d2;
        let ghost = ob - u2 * (2.0 * self.radius);
        let to_ghost = ghost - cue;
        let d1 = to_ghost.length().max(1e-6);
        let cos_cut = (to_ghost / d1).dot(u2);
        if cos_cut < 0.17 {
            return 0.0;
        }
        // The entry angle narrows the pocket: a side pocket refuses shallow approaches.
        let entry = u2.dot(pocket.outward);
        let half = if pocket.corner {
            CORNER_WINDOW * (0.55 + 0.45 * entry.max(0.0))
        } else {
            SIDE_WINDOW * ((entry - 0.45) / 0.55).max(0.0)
        };
        if half <= 0.0 {
            return 0.0;
        }
        if !self.clear(cue, ghost, &[0, ball]) || !self.clear(ob, pocket.mouth, &[0, ball]) {
            return 0.0;
        }
        // An aim error turns the object ball's path by d1/(2R·cos cut) times as much; the
        // floor stands for errors of speed and spin that no geometry removes.
        let sigma_ob = aim_sigma.max(1e-4) * d1 / (2.0 * self.radius * cos_cut) + 0.002;
        let tol = half / d2.max(0.05);
        libm::erf(tol / (sigma_ob * std::f64::consts::SQRT_2))
    }

    /// The best of [`Layout::pot_chance`] over `targets` and every pocket.
    pub(super) fn best_pot(&self, cue: DVec2, targets: &[u8], aim_sigma: f64) -> f64 {
        let mut best: f64 = 0.0;
        for &t in targets {
            for p in &self.pockets {
                best = best.max(self.pot_chance(cue, t, p, aim_sigma));
            }
        }
        best
    }
}

/// Distance from `p` to the segment `a`–`b`.
pub(super) fn segment_distance(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 == 0.0 {
        return (p - a).length();
    }
    let k = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    (a + ab * k - p).length()
}

/// `v` turned by `angle` radians.
pub(super) fn rotate(v: DVec2, angle: f64) -> DVec2 {
    let (s, c) = (libm::sin(angle), libm::cos(angle));
    DVec2::new(v.x * c - v.y * s, v.x * s + v.y * c)
}

/// The signed angle (radians) from `a` to `b`.
pub(super) fn angle_between(a: DVec2, b: DVec2) -> f64 {
    libm::atan2(a.x * b.y - a.y * b.x, a.dot(b))
}
