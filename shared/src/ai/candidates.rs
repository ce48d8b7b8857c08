//! Candidate shots: what a player would consider before choosing.
//!
//! Pots are aimed in two steps. First the object ball's way into the pocket is found by
//! rolling it alone towards the pocket in a fan of directions (the real engine, jaws and
//! rails included) and taking the middle of the widest window that drops; banks are found
//! the same way, fanning around the pocket's mirror image in a rail. Then the cue ball is
//! aimed at the ghost ball for that direction and the aim is corrected by trial shots until
//! the object ball leaves the collision along it, which takes throw and squirt into account
//! without a model of either. Safeties and kicks are a spread of contacts and speeds; the
//! simulations under noise judge them all.

use glam::DVec2;

use super::geometry::{angle_between, rotate, Layout, PocketView};
use super::lab::{first_hit, Lab};
use crate::physics::Strike;

/// What a candidate is, for reports and for ordering ties.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The cue ball sends an object ball directly into a pocket.
    Pot,
    /// The object ball goes into the pocket off a rail.
    Bank,
    /// A legal ball is played into a pottable one near it.
    Combination,
    /// The cue ball reaches a legal ball off one rail.
    Kick,
    /// A contact meant to leave the opponent nothing rather than to pot.
    Safety,
    /// A break: the head ball hit full or slightly off, at 7 to 11 m/s.
    Break,
    /// A three-cushion stroke.
    Carom,
}

/// A shot the search may choose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Candidate {
    pub strike: Strike,
    /// The pocket called (the pocket aimed at, for a pot).
    pub call: Option<u8>,
    pub kind: Kind,
    /// A rough chance of success from geometry, to order candidates before simulating.
    pub prior: f64,
}

/// How widely to look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Breadth {
    /// At most this many (ball, pocket) pots, the most promising first.
    pub pots: usize,
    /// Speeds tried per pot (1 to 3).
    pub speeds: usize,
    /// Also try side spin.
    pub side: bool,
    /// Also try banks.
    pub banks: bool,
    /// Also try combinations.
    pub combinations: bool,
    /// Also try one-rail kicks (tried anyway when nothing else reaches a legal ball).
    pub kicks: bool,
    /// Also try safeties.
    pub safeties: bool,
    /// Aim corrections by trial shots per candidate.
    pub corrections: usize,
}

/// The shooter's view of a table.
pub(super) struct View<'a> {
    pub layout: &'a Layout,
    /// Balls the cue ball may hit first (empty = any).
    pub targets: &'a [u8],
    /// Balls that count when pocketed.
    pub pottable: &'a [u8],
    pub aim_sigma: f64,
}

impl View<'_> {
    fn may_hit(&self, ball: u8) -> bool {
        ball != 0 && (self.targets.is_empty() || self.targets.contains(&ball))
    }

    fn may_pot(&self, ball: u8) -> bool {
        ball != 0 && (self.pottable.is_empty() || self.pottable.contains(&ball))
    }

    /// The balls on the table, with their centres, that pass `keep`, in the layout's order.
    fn balls_where(&self, keep: impl Fn(u8) -> bool) -> Vec<(u8, DVec2)> {
        let balls = self.layout.balls.iter().copied();
        balls.filter(|(b, _)| keep(*b)).collect()
    }

    fn first_balls(&self) -> Vec<(u8, DVec2)> {
        self.balls_where(|b| self.may_hit(b))
    }

    fn pottable_balls(&self) -> Vec<(u8, DVec2)> {
        self.balls_where(|b| self.may_pot(b))
    }

    /// The balls to pot directly: those that may be hit first and count when pocketed.
    fn first_pottable_balls(&self) -> Vec<(u8, DVec2)> {
        self.balls_where(|b| self.may_hit(b) && self.may_pot(b))
    }
}

/// Ball speed (m/s) the object ball needs to reach a pocket `d` metres away with some pace.
fn needed_ball_speed(d: f64) -> f64 {
    libm::sqrt(0.25 * 0.25 + 2.0 * 0.25 * d)
}

/// Cue stick speed that sends the cue ball `d1` metres to a contact with cut cosine `cos_cut`
/// leaving the object ball with `v_ob`.
fn cue_speed(d1: f64, cos_cut: f64, v_ob: f64) -> f64 {
    let arrive = v_ob / cos_cut.max(0.3) * 1.1;
    let start = libm::sqrt(arrive * arrive + 2.0 * 0.6 * d1);
    (start / 1.54).clamp(0.4, 7.0)
}

/// The spread of speeds and spins tried for one aimed shot.
pub(super) fn variants(base: f64, breadth: &Breadth) -> Vec<(f64, DVec2)> {
    let speeds: &[f64] = match breadth.speeds {
        0 | 1 => &[1.4],
        2 => &[1.1, 2.0],
        _ => &[1.0, 1.6, 2.6],
    };
    let mut out = Vec::new();
    for &k in speeds {
        for height in [0.0, 0.35, -0.35] {
            out.push(((base * k).min(8.0), DVec2::new(0.0, height)));
        }
    }
    if breadth.side {
        let mid = speeds[speeds.len() / 2];
        for side in [0.3, -0.3] {
            out.push(((base * mid).min(8.0), DVec2::new(side, 0.0)));
        }
    }
    out
}

/// The window of directions in which `ball` rolled alone drops into `pocket`, searched in a
/// fan of `half_width` radians either side of `toward`: its middle direction and its width.
async fn window(
    lab: &mut Lab,
    ball: u8,
    toward: DVec2,
    half_width: f64,
    probes: usize,
    speed: f64,
) -> Option<(DVec2, f64)> {
    let n = probes.max(3) | 1;
    let step = 2.0 * half_width / (n - 1) as f64;
    let mut drops = Vec::with_capacity(n);
    for k in 0..n {
        let a = -half_width + step * k as f64;
        drops.push(
            lab.rolls_in(usize::from(ball), rotate(toward, a), speed)
                .await,
        );
    }
    // The widest run of directions that drop.
    let (mut best, mut start) = ((0usize, 0usize), None);
    for (k, &d) in drops.iter().chain(std::iter::once(&false)).enumerate() {
        match (d, start) {
            (true, None) => start = Some(k),
            (false, Some(s)) => {
                if k - s > best.1 - best.0 {
                    best = (s, k);
                }
                start = None;
            }
            _ => {}
        }
    }
    if best.1 == best.0 {
        return None;
    }
    let mid = -half_width + step * 0.5 * (best.0 + best.1 - 1) as f64;
    Some((rotate(toward, mid), step * (best.1 - best.0) as f64))
}

/// The cue aim that sends ball `first` off along `want` (a ghost-ball aim, corrected by trial
/// shots): `None` if the cue ball cannot reach it first.
async fn aim_at(
    lab: &mut Lab,
    cue: DVec2,
    first: u8,
    want: DVec2,
    speed: f64,
    tip: DVec2,
    corrections: usize,
) -> Option<DVec2> {
    let ob = lab.balls().get(usize::from(first))?.pos;
    let ghost = ob - want * (2.0 * crate::rules::rack::ball_radius());
    let mut dir = (ghost - cue).normalize_or_zero();
    if dir == DVec2::ZERO {
        return None;
    }
    let mut last: Option<(f64, f64)> = None; // (aim angle offset, error)
    let mut offset = 0.0;
    let base = dir;
    for _ in 0..corrections {
        let strike = Strike {
            speed,
            dir,
            tip,
            elevation_deg: 0.0,
        };
        let out = lab.strike(0, strike).await?;
        let (hit, leaves) = first_hit(out, 0)?;
        if hit != usize::from(first) || leaves == DVec2::ZERO {
            return None;
        }
        let err = angle_between(want, leaves);
        if err.abs() < 2e-5 {
            break;
        }
        let next = match last {
            Some((o0, e0)) if (err - e0).abs() > 1e-9 => offset - err * (offset - o0) / (err - e0),
            // The object ball turns the opposite way to the aim, by about d/(2R·cos cut).
            _ => {
                let d = (ghost - cue).length();
                let cos_cut = base.dot(want).max(0.2);
                offset + err * 2.0 * crate::rules::rack::ball_radius() * cos_cut / d.max(0.01)
            }
        };
        last = Some((offset, err));
        offset = next.clamp(-0.2, 0.2);
        dir = rotate(base, offset);
    }
    Some(dir)
}

/// Is `cue`'s straight path to hitting `ball` at `contact` (a ghost position) open?
fn reachable(layout: &Layout, cue: DVec2, contact: DVec2, ball: u8) -> bool {
    layout.clear(cue, contact, &[0, ball])
}

/// The rail lines a ball's centre bounces on: (axis, coordinate) with axis 0 = x.
fn rail_lines(layout: &Layout) -> [(usize, f64); 4] {
    let r = layout.radius;
    [
        (0, r),
        (0, layout.size.x - r),
        (1, r),
        (1, layout.size.y - r),
    ]
}

fn mirror(p: DVec2, (axis, at): (usize, f64)) -> DVec2 {
    if axis == 0 {
        DVec2::new(2.0 * at - p.x, p.y)
    } else {
        DVec2::new(p.x, 2.0 * at - p.y)
    }
}

/// One way of potting: `first` is struck by the cue ball and (directly, or via `carom`)
/// `pocketed` drops.
struct Route {
    first: u8,
    /// Direction `first` must leave along.
    want: DVec2,
    pocket: u8,
    kind: Kind,
    prior: f64,
    /// Distance the cue ball travels and the cut, for the speed.
    d1: f64,
    cos_cut: f64,
    /// Distance the pocketed ball travels.
    d2: f64,
}

/// Every shot worth simulating from this table.
pub(super) async fn generate(lab: &mut Lab, view: &View<'_>, breadth: &Breadth) -> Vec<Candidate> {
    let layout = view.layout;
    let Some(cue) = layout.cue() else {
        return Vec::new();
    };
    let r = layout.radius;
    let mut routes = direct_routes(lab, view, cue, 2 * breadth.pots).await;
    if breadth.banks {
        routes.extend(bank_routes(lab, view, cue).await);
    }
    if breadth.combinations {
        routes.extend(combination_routes(lab, view, cue).await);
    }
    routes.sort_by(|a, b| b.prior.total_cmp(&a.prior));
    routes.truncate(breadth.pots);
    let mut out = Vec::new();
    for route in &routes {
        let base = cue_speed(route.d1, route.cos_cut, needed_ball_speed(route.d2));
        for (speed, tip) in variants(base, breadth) {
            if let Some(dir) = aim_at(
                lab,
                cue,
                route.first,
                route.want,
                speed,
                tip,
                breadth.corrections,
            )
            .await
            {
                out.push(Candidate {
                    strike: Strike {
                        speed,
                        dir,
                        tip,
                        elevation_deg: 0.0,
                    },
                    call: Some(route.pocket),
                    kind: route.kind,
                    prior: route.prior,
                });
            }
        }
    }
    if breadth.safeties || out.is_empty() {
        out.extend(safeties(view, cue, r));
    }
    if breadth.kicks || out.is_empty() {
        out.extend(kicks(view, cue));
    }
    out
}

async fn direct_routes(lab: &mut Lab, view: &View<'_>, cue: DVec2, limit: usize) -> Vec<Route> {
    let layout = view.layout;
    // Rank every (ball, pocket) by geometry first; only the best few are worth probing.
    let mut open = Vec::new();
    for (ball, ob) in view.first_pottable_balls() {
        for pocket in &layout.pockets {
            let prior = layout.pot_chance(cue, ball, pocket, view.aim_sigma);
            if prior > 0.0 {
                open.push((prior, ball, ob, *pocket));
            }
        }
    }
    open.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut routes = Vec::new();
    for (prior, ball, ob, pocket) in open.into_iter().take(limit) {
        let to_pocket = pocket.center - ob;
        let d2 = to_pocket.length();
        let toward = to_pocket / d2.max(1e-9);
        let ghost = ob - toward * (2.0 * layout.radius);
        let d1 = (ghost - cue).length();
        let cos_cut = (ghost - cue).normalize_or_zero().dot(toward);
        let spread = libm::atan(0.1 / d2.max(0.1)).min(0.14);
        let Some((want, width)) = window(lab, ball, toward, spread, 13, 1.5).await else {
            continue;
        };
        routes.push(Route {
            first: ball,
            want,
            pocket: pocket.index,
            kind: Kind::Pot,
            // A wide window is an easy pot: weigh the geometry by what the probes found.
            prior: prior * (0.5 + width * d2.max(0.1) * 10.0).min(1.5),
            d1,
            cos_cut,
            d2,
        });
    }
    routes
}

async fn bank_routes(lab: &mut Lab, view: &View<'_>, cue: DVec2) -> Vec<Route> {
    let layout = view.layout;
    let mut routes = Vec::new();
    for (ball, ob) in view.first_pottable_balls() {
        for pocket in &layout.pockets {
            for line in rail_lines(layout) {
                let image = mirror(pocket.center, line);
                let toward = (image - ob).normalize_or_zero();
                let ghost = ob - toward * (2.0 * layout.radius);
                let cos_cut = (ghost - cue).normalize_or_zero().dot(toward);
                if cos_cut < 0.5 || !reachable(layout, cue, ghost, ball) {
                    continue;
                }
                // The bank must meet its rail away from the pockets: the ball has to come
                // off a rail, not fall short of it.
                let d2 = (image - ob).length();
                let Some((want, _)) = window(lab, ball, toward, 0.09, 11, 2.2).await else {
                    continue;
                };
                routes.push(Route {
                    first: ball,
                    want,
                    pocket: pocket.index,
                    kind: Kind::Bank,
                    prior: 0.05 * cos_cut,
                    d1: (ghost - cue).length(),
                    cos_cut,
                    d2: d2 * 1.3,
                });
            }
        }
    }
    routes
}

async fn combination_routes(lab: &mut Lab, view: &View<'_>, cue: DVec2) -> Vec<Route> {
    let layout = view.layout;
    let mut routes = Vec::new();
    for (first, fp) in view.first_balls() {
        for (second, sp) in view.pottable_balls() {
            if second == first || (fp - sp).length() > 0.7 {
                continue;
            }
            for pocket in &layout.pockets {
                let to_pocket = pocket.center - sp;
                let d2 = to_pocket.length();
                let toward = to_pocket / d2.max(1e-9);
                let ghost2 = sp - toward * (2.0 * layout.radius);
                let via = (ghost2 - fp).normalize_or_zero();
                let ghost1 = fp - via * (2.0 * layout.radius);
                let cos2 = via.dot(toward);
                let cos1 = (ghost1 - cue).normalize_or_zero().dot(via);
                if cos2 < 0.8 || cos1 < 0.5 {
                    continue;
                }
                if !reachable(layout, cue, ghost1, first)
                    || !layout.clear(fp, ghost2, &[0, first, second])
                    || !layout.clear(sp, pocket.mouth, &[0, first, second])
                {
                    continue;
                }
                let Some((want2, _)) = window(lab, second, toward, 0.06, 9, 1.5).await else {
                    continue;
                };
                let ghost2 = sp - want2 * (2.0 * layout.radius);
                let want = (ghost2 - fp).normalize_or_zero();
                routes.push(Route {
                    first,
                    want,
                    pocket: pocket.index,
                    kind: Kind::Combination,
                    prior: 0.08 * cos1 * cos2,
                    d1: (ghost1 - cue).length(),
                    cos_cut: cos1 * cos2,
                    d2: d2 + (ghost2 - fp).length(),
                });
            }
        }
    }
    routes
}

/// Pocket nearest to `p`, to call on shots that are not pots.
fn nearest_pocket(layout: &Layout, p: DVec2) -> Option<u8> {
    layout
        .pockets
        .iter()
        .min_by(|a, b| (a.center - p).length().total_cmp(&(b.center - p).length()))
        .map(|pk: &PocketView| pk.index)
}

/// Contacts of every fullness on the legal balls the cue ball can reach, at a few speeds.
fn safeties(view: &View, cue: DVec2, r: f64) -> Vec<Candidate> {
    let layout = view.layout;
    let mut balls = view.first_balls();
    balls.sort_by(|a, b| (a.1 - cue).length().total_cmp(&(b.1 - cue).length()));
    let mut out = Vec::new();
    for (ball, ob) in balls.into_iter().take(4) {
        let d = (ob - cue).length();
        for frac in [-0.8, -0.45, 0.0, 0.45, 0.8] {
            let Some(contact) = contact_at(cue, ob, frac, r) else {
                continue;
            };
            if !reachable(layout, cue, contact, ball) {
                continue;
            }
            let dir = (contact - cue).normalize_or_zero();
            for speed in [0.5 + 0.3 * d, 1.2 + 0.4 * d, 2.5] {
                for height in [0.0, -0.3] {
                    out.push(safety(dir, speed, height, nearest_pocket(layout, ob)));
                }
            }
        }
    }
    out
}

/// Where the cue ball's centre is when it meets the ball at `ob`, coming from `cue` and
/// taking `frac` of a full ball on its left (negative: on its right); None when the two
/// centres are one.
pub(super) fn contact_at(cue: DVec2, ob: DVec2, frac: f64, r: f64) -> Option<DVec2> {
    let to = ob - cue;
    let d = to.length();
    if d < 1e-9 {
        return None;
    }
    let u = to / d;
    let side = DVec2::new(-u.y, u.x);
    Some(ob + side * (frac * 2.0 * r) - u * (2.0 * r * libm::sqrt(1.0 - frac * frac)))
}

/// A safety played along `dir` at `speed`, with the tip `height` above centre.
pub(super) fn safety(dir: DVec2, speed: f64, height: f64, call: Option<u8>) -> Candidate {
    Candidate {
        strike: Strike {
            speed,
            dir,
            tip: DVec2::new(0.0, height),
            elevation_deg: 0.0,
        },
        call,
        kind: Kind::Safety,
        prior: 0.0,
    }
}

/// One-rail kicks at each legal ball: the cue ball aimed at the ball's mirror image in a rail.
fn kicks(view: &View, cue: DVec2) -> Vec<Candidate> {
    let layout = view.layout;
    let mut out = Vec::new();
    for (_, ob) in view.first_balls() {
        for line in rail_lines(layout) {
            let image = mirror(ob, line);
            let dir = (image - cue).normalize_or_zero();
            if dir == DVec2::ZERO {
                continue;
            }
            for speed in [1.5, 3.0] {
                out.push(Candidate {
                    strike: Strike {
                        speed,
                        dir,
                        tip: DVec2::ZERO,
                        elevation_deg: 0.0,
                    },
                    call: nearest_pocket(layout, ob),
                    kind: Kind::Kick,
                    prior: 0.0,
                });
            }
        }
    }
    out
}

/// Break shots: the cue ball driven into the head ball of the rack, full and a little off.
pub(super) fn breaks(layout: &Layout, targets: &[u8]) -> Vec<Candidate> {
    let Some(cue) = layout.cue() else {
        return Vec::new();
    };
    let head = layout
        .balls
        .iter()
        .filter(|(b, _)| *b != 0 && (targets.is_empty() || targets.contains(b)))
        .min_by(|a, b| (a.1 - cue).length().total_cmp(&(b.1 - cue).length()))
        .map(|(_, p)| *p);
    let Some(head) = head else {
        return Vec::new();
    };
    let u = (head - cue).normalize_or_zero();
    let side = DVec2::new(-u.y, u.x);
    let mut out = Vec::new();
    for off in [-0.3, -0.15, 0.0, 0.15, 0.3] {
        let dir = (head + side * (off * layout.radius) - cue).normalize_or_zero();
        for speed in [7.0, 9.0, 11.0] {
            out.push(Candidate {
                strike: Strike {
                    speed,
                    dir,
                    tip: DVec2::new(0.0, -0.15),
                    elevation_deg: 0.0,
                },
                call: None,
                kind: Kind::Break,
                prior: 0.0,
            });
        }
    }
    out
}
