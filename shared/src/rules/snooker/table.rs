//! The snooker table's landmarks and geometry as the rules use them: the balls and their
//! values, the baulk line, the D and the six spots (WPBSA rules, section 1), the rack,
//! re-spotting a colour, and the two sight tests of the rules: "snookered" (for the free
//! ball) and "a clear view of a ball on" (for the three-miss rule).
//!
//! Coordinates are the scene frame: `x` across the table (0..1.778 m), `y` along it from the
//! baulk cushion (0) to the top cushion (3.569 m).

use glam::DVec2;

use crate::physics::{ball_cushion, BallState, MotionState, Params, Shot, Table, TableKind};

use super::super::rack::SplitMix64;

/// The cue ball's index.
pub const CUE: u8 = 0;
/// The highest red's index: reds are 1 to 15 (`r1` to `r15` in scenes).
pub const LAST_RED: u8 = 15;
/// The yellow's index; the colours follow in the order of their values.
pub const YELLOW: u8 = 16;
/// The green's index.
pub const GREEN: u8 = 17;
/// The brown's index.
pub const BROWN: u8 = 18;
/// The blue's index.
pub const BLUE: u8 = 19;
/// The pink's index.
pub const PINK: u8 = 20;
/// The black's index.
pub const BLACK: u8 = 21;
/// Balls in the list of a snooker game, whatever the number of reds (unused reds are off the
/// table from the start).
pub const BALL_COUNT: usize = 22;

/// The six colours, lowest value first.
pub const COLOURS: [u8; 6] = [YELLOW, GREEN, BROWN, BLUE, PINK, BLACK];

/// Baulk line: 737 mm (29 in) from the face of the bottom cushion (WPBSA 1.3).
pub const BAULK_LINE: f64 = 0.737;
/// The D's radius: 292 mm (11½ in), centred on the middle of the baulk line.
pub const D_RADIUS: f64 = 0.292;
/// The black spot's distance from the top cushion: 324 mm (12¾ in).
pub const BLACK_FROM_TOP: f64 = 0.324;
/// The gap left between the reds of the triangle and between the apex and the pink (m): the
/// rule says "as close as possible without touching".
const RACK_GAP: f64 = 2e-4;
/// How far a racked red may sit from its ideal place (m), as for the pool racks.
const RACK_JITTER: f64 = 1e-4;
/// The step (m) with which a colour searches along the long string when every spot is taken.
const SPOT_STEP: f64 = 5e-4;

/// Is `ball` a red?
pub fn is_red(ball: u8) -> bool {
    (1..=LAST_RED).contains(&ball)
}

/// Is `ball` one of the six colours?
pub fn is_colour(ball: u8) -> bool {
    (YELLOW..=BLACK).contains(&ball)
}

/// The ball's value: 1 for a red, 2 (yellow) to 7 (black) for the colours, 0 for the cue ball.
pub fn value(ball: u8) -> u32 {
    match ball {
        1..=LAST_RED => 1,
        YELLOW..=BLACK => u32::from(ball - YELLOW) + 2,
        _ => 0,
    }
}

/// "the blue", "a red", "the cue ball".
pub fn ball_name(ball: u8) -> String {
    match ball {
        CUE => "the cue ball".into(),
        1..=LAST_RED => "a red".into(),
        YELLOW..=BLACK => format!("the {}", colour_name(ball)),
        other => format!("ball {other}"),
    }
}

/// "blue" for the blue.
pub fn colour_name(ball: u8) -> &'static str {
    match ball {
        YELLOW => "yellow",
        GREEN => "green",
        BROWN => "brown",
        BLUE => "blue",
        PINK => "pink",
        BLACK => "black",
        _ => "red",
    }
}

/// The ball's id in scenes: `cue`, `r1`..`r15`, `yellow`, ..., `black`.
pub fn scene_id(ball: u8) -> String {
    match ball {
        CUE => "cue".into(),
        1..=LAST_RED => format!("r{ball}"),
        other => colour_name(other).into(),
    }
}

fn size() -> (f64, f64) {
    TableKind::Snooker.size().unwrap_or((1.778, 3.569))
}

/// The snooker ball's radius.
pub fn radius() -> f64 {
    Params::for_table(TableKind::Snooker).ball_radius
}

/// The middle of the baulk line: the brown's spot and the D's centre.
pub fn d_centre() -> DVec2 {
    DVec2::new(0.5 * size().0, BAULK_LINE)
}

/// A colour's own spot.
pub fn spot(colour: u8) -> DVec2 {
    let (w, l) = size();
    let centre = d_centre();
    match colour {
        // Yellow on the right-hand corner of the D seen from the baulk end, green on the left.
        YELLOW => DVec2::new(centre.x + D_RADIUS, BAULK_LINE),
        GREEN => DVec2::new(centre.x - D_RADIUS, BAULK_LINE),
        BLUE => DVec2::new(0.5 * w, 0.5 * l),
        // Midway between the centre spot and the face of the top cushion.
        PINK => DVec2::new(0.5 * w, 0.75 * l),
        BLACK => DVec2::new(0.5 * w, l - BLACK_FROM_TOP),
        _ => centre,
    }
}

/// Is `p` in the D: on or behind the baulk line, within the D's radius of its centre?
pub fn in_d(p: DVec2) -> bool {
    p.y <= BAULK_LINE && (p - d_centre()).length() <= D_RADIUS
}

/// Can `ball` be put at `p` without touching another ball or a cushion?
pub fn is_free(balls: &[BallState], ball: usize, p: DVec2) -> bool {
    if !p.is_finite() {
        return false;
    }
    let params = Params::for_table(TableKind::Snooker);
    let table = Table::new(TableKind::Snooker);
    let inside = table.fits(table.to_engine(p), ball_cushion::contact_distance(&params));
    // "Occupied" means a ball cannot be placed without touching another (WPBSA 2.18).
    inside
        && balls.iter().enumerate().all(|(i, b)| {
            i == ball
                || b.motion == MotionState::Pocketed
                || (b.pos - p).length() > 2.0 * params.ball_radius
        })
}

/// The frame's start: `reds` reds in a triangle behind the pink (its apex as close to the pink
/// as possible without touching), the colours on their spots, the cue ball in the D; reds
/// beyond `reds` are off the table. `seed` moves each red but the apex by up to a tenth of a
/// millimetre, as a real rack is never perfect.
pub fn rack(reds: u8, seed: u64) -> Vec<BallState> {
    let r = radius();
    let d = 2.0 * r + RACK_GAP;
    let mut rng = SplitMix64::new(seed);
    let off = BallState {
        motion: MotionState::Pocketed,
        pocket: None,
        ..BallState::at_rest(DVec2::ZERO)
    };
    let mut balls = vec![off; BALL_COUNT];
    balls[usize::from(CUE)] =
        BallState::at_rest(d_centre() + DVec2::new(0.5 * D_RADIUS, -0.5 * D_RADIUS));
    let apex = spot(PINK) + DVec2::new(0.0, d);
    let row_step = d * 0.866_025_403_784_438_6;
    let mut placed = 0u8;
    let mut row = 0u8;
    while placed < reds.min(LAST_RED) {
        for k in 0..=row {
            if placed >= reds.min(LAST_RED) {
                break;
            }
            let x = (f64::from(k) - 0.5 * f64::from(row)) * d;
            let mut p = apex + DVec2::new(x, f64::from(row) * row_step);
            if placed > 0 {
                p += rng.offset(RACK_JITTER);
            }
            placed += 1;
            balls[usize::from(placed)] = BallState::at_rest(p);
        }
        row += 1;
    }
    for c in COLOURS {
        balls[usize::from(c)] = BallState::at_rest(spot(c));
    }
    balls
}

/// Where a re-spotted colour goes, and where it was put.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Respot {
    /// On its own spot.
    Own,
    /// Its own spot was taken: on the highest-value spot free, this colour's.
    Spot(u8),
    /// Every spot was taken: as near its own spot as possible, towards the top cushion (or,
    /// if there is no room that way, towards the baulk cushion), on the long string.
    NearOwnSpot,
}

impl Respot {
    /// "on its spot", "on the pink's spot", "as near its spot as possible".
    pub fn describe(self) -> String {
        match self {
            Respot::Own => "on its spot".into(),
            Respot::Spot(c) => format!("on the {}'s spot (its own is taken)", colour_name(c)),
            Respot::NearOwnSpot => "as near its spot as possible (every spot is taken)".into(),
        }
    }
}

/// Puts `colour` back on the table (WPBSA 3.4): its own spot if free, else the highest-value
/// spot free, else as near its own spot as possible towards the top cushion.
pub fn respot(balls: &mut [BallState], colour: u8) -> Respot {
    let i = usize::from(colour);
    let own = spot(colour);
    let (place, how) = if is_free(balls, i, own) {
        (own, Respot::Own)
    } else if let Some(c) = COLOURS
        .iter()
        .rev()
        .copied()
        .find(|&c| is_free(balls, i, spot(c)))
    {
        (spot(c), Respot::Spot(c))
    } else {
        (nearest_free(balls, i, own), Respot::NearOwnSpot)
    };
    if let Some(b) = balls.get_mut(i) {
        *b = BallState::at_rest(place);
    }
    how
}

/// The free place on the long string nearest `own`, looking towards the top cushion first.
fn nearest_free(balls: &[BallState], i: usize, own: DVec2) -> DVec2 {
    let l = size().1;
    let steps = (l / SPOT_STEP) as u32;
    for dir in [1.0, -1.0] {
        for k in 1..=steps {
            let p = own + DVec2::new(0.0, dir * f64::from(k) * SPOT_STEP);
            if p.y <= 0.0 || p.y >= l {
                break;
            }
            if is_free(balls, i, p) {
                return p;
            }
        }
    }
    own
}

/// The distance from `q` to the straight path of the cue ball's centre from `from` to `to`,
/// and where along the path (0 at `from`, 1 at `to`) its point nearest `q` lies.
fn gap(from: DVec2, to: DVec2, q: DVec2) -> (f64, f64) {
    let along = to - from;
    let len2 = along.length_squared();
    let k = if len2 > 0.0 {
        (along.dot(q - from) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((q - (from + along * k)).length(), k)
}

/// How far the cue ball's centre travels along the straight path from `from` to `to` before
/// it comes within `reach` of `q`, or `None` if it never does. Coming to exactly `reach` (a
/// touch) is not meeting, so a ball touching the path's end is not in the way.
fn meets(from: DVec2, to: DVec2, q: DVec2, reach: f64) -> Option<f64> {
    if gap(from, to, q).0 >= reach - 1e-9 {
        return None;
    }
    let along = to - from;
    let len = along.length();
    if len == 0.0 {
        return Some(0.0);
    }
    let w = q - from;
    let proj = along.dot(w) / len;
    let side2 = (w.length_squared() - proj * proj).max(0.0);
    let back = (reach * reach - side2).max(0.0).sqrt();
    Some((proj - back).clamp(0.0, len))
}

/// What a straight stroke of the cue ball may meet on its way to a ball on: the balls not on
/// and the curved faces of the pocket jaws.
///
/// Straight cushion faces are left out. A straight nose is a side of the bed, which is
/// convex, so it never lies between the cue ball and a ball on: the segment between two
/// centres on the cloth stays on the cloth. The cue ball's disc can brush one only on the
/// stroke at the edge of a ball on lying within a ball's width of that cushion, on the
/// cushion's side of it; that stroke is judged by the balls alone, as the rule names the
/// curved face as the cushion that may come first.
#[derive(Clone, Debug)]
pub struct Obstacles {
    /// The centres of the balls not on: the cue ball's centre meets one `2R` from it.
    balls: Vec<DVec2>,
    /// Each jaw's axis, and the distance from it at which the cue ball's centre meets the
    /// jaw's curved face.
    jaws: Vec<(DVec2, f64)>,
}

impl Obstacles {
    /// The balls not on at `balls` and the snooker table's twelve jaws, met where the engine
    /// meets them in every snooker stroke: `ρ + contact` from a jaw's axis, `contact` being
    /// the horizontal distance at which the game's cushion model touches a nose.
    pub fn new(balls: Vec<DVec2>) -> Obstacles {
        let shot = Shot::new(TableKind::Snooker, Vec::new());
        let contact = ball_cushion::model_contact_distance(&shot.params, shot.models.cushion);
        let table = Table::new(TableKind::Snooker);
        let jaws = table
            .jaws
            .iter()
            .map(|j| (table.to_scene(j.center), j.radius + contact))
            .collect();
        Obstacles { balls, jaws }
    }

    /// Is the straight stroke of the cue ball's centre from `cue` to `end` obstructed by a
    /// ball not on that it meets before any jaw? WPBSA 2.16(e): "The cue-ball cannot be
    /// snookered by a cushion. If the curved face of a cushion obstructs the cue-ball and is
    /// closer to the cue-ball than any obstructing ball not on, the cue-ball is not
    /// snookered." Closer is measured along the stroke: the first thing the cue ball's disc
    /// would meet. A jaw and a ball met at the same point leave the ball obstructing.
    fn obstruct(&self, cue: DVec2, end: DVec2) -> bool {
        let r = radius();
        let balls = self.balls.iter().map(|&q| meets(cue, end, q, 2.0 * r));
        let Some(ball) = balls.flatten().reduce(f64::min) else {
            return false;
        };
        let jaws = self
            .jaws
            .iter()
            .map(|&(j, reach)| meets(cue, end, j, reach));
        jaws.flatten()
            .reduce(f64::min)
            .is_none_or(|jaw| jaw >= ball)
    }

    /// Does the straight stroke of the cue ball's centre from `cue` to `end` meet nothing,
    /// neither a ball not on nor a jaw?
    fn clear(&self, cue: DVec2, end: DVec2) -> bool {
        let r = radius();
        let balls = self.balls.iter().map(|&q| (q, 2.0 * r));
        balls
            .chain(self.jaws.iter().copied())
            .all(|(q, reach)| meets(cue, end, q, reach).is_none())
    }

    /// Is every straight stroke of the cue ball from a position within `h` of `cue` to a
    /// point within `e` of `end` obstructed as in [`Obstacles::obstruct`]? The point of
    /// such a stroke a fraction `k` along lies within `(1 − k)·h + k·e` of the same point of
    /// the stroke from `cue` to `end` (both ends move by no more). Sure when some ball lies
    /// farther inside the stroke's reach than that at the stroke's point nearest it, and no
    /// jaw comes within `max(h, e)` of the reach of the stroke up to that point: the nearby
    /// stroke then meets the ball there or earlier, and no jaw before it.
    fn obstruct_all_near(&self, cue: DVec2, end: DVec2, h: f64, e: f64) -> bool {
        let r = radius();
        self.balls.iter().any(|&q| {
            let (d, k) = gap(cue, end, q);
            let nearest = cue + (end - cue) * k;
            d < 2.0 * r - ((1.0 - k) * h + k * e) - 1e-9
                && self
                    .jaws
                    .iter()
                    .all(|&(j, reach)| gap(cue, nearest, j).0 >= reach + h.max(e))
        })
    }
}

/// The ends of the two straight strokes of the cue ball's centre from `cue` that graze the
/// ball at `target` at its extreme edges, or `None` when the two balls touch (a ball the cue
/// ball touches is in view whatever lies around). The grazing strokes are the two tangent
/// lines: the cue ball's centre ends `2R` from the target's, `√(D² − 4R²)` along.
fn edge_strokes(cue: DVec2, target: DVec2) -> Option<[DVec2; 2]> {
    let r = radius();
    let (to, dist) = apart(cue, target)?;
    let u = to / dist;
    let n = DVec2::new(-u.y, u.x);
    let along = (dist * dist - 4.0 * r * r).sqrt();
    let (cos_a, sin_a) = (along / dist, 2.0 * r / dist);
    Some([1.0, -1.0].map(|side| cue + (u * cos_a + n * (side * sin_a)) * along))
}

/// Is the cue ball at `cue` snookered on the ball at `target` (WPBSA 2.16): is a straight
/// stroke at one of its extreme edges obstructed by a ball not on, met before any jaw? A
/// ball on is in view when both its extreme edges can be hit free of such obstruction.
pub fn snookered_on(cue: DVec2, target: DVec2, obstacles: &Obstacles) -> bool {
    edge_strokes(cue, target)
        .is_some_and(|ends| ends.iter().any(|&end| obstacles.obstruct(cue, end)))
}

/// Is the cue ball snookered on the ball at `target` from every position within `h` of `c`?
/// Each stroke of [`snookered_on`] then starts within `h` of the one from `c`, and ends (at
/// the tangent point on the circle of radius `2R` about the target) within `2R` times the
/// turn of the tangent: at most `h/d` for the direction to the target and
/// `2R·h / (d·√(d² − 4R²))` for the tangent's angle to it, `d` the least distance from the
/// positions to the target.
fn snookered_on_all_near(c: DVec2, h: f64, target: DVec2, obstacles: &Obstacles) -> bool {
    let r = radius();
    let d = (target - c).length() - h;
    if d <= 2.0 * r {
        return false;
    }
    let turn = h / d * (1.0 + 2.0 * r / (d * d - 4.0 * r * r).sqrt());
    edge_strokes(c, target).is_some_and(|ends| {
        ends.iter()
            .any(|&end| obstacles.obstruct_all_near(c, end, h, 2.0 * r * turn))
    })
}

/// The radius (m) of the smallest disc of the D from which the search for a view from the
/// cue ball in hand is sure to find one, a tenth of a millimetre: finer than a player places
/// a ball.
const D_SEARCH_TOLERANCE: f64 = 1e-4;

/// The most squares the search of the D tries. Squares are halved only near the edges of
/// the shadows, so they grow with the inverse of the tolerance at worst (the layouts of the
/// tests take under a hundred); this bounds the work whatever the layout.
const D_SEARCH_SQUARES: usize = 1 << 20;

/// Is the cue ball in hand snookered: from every position on or within the lines of the D
/// where it may be placed (clear of the other balls, all of `balls`), is it snookered on
/// every ball at `targets` (WPBSA 2.16(a))?
///
/// The D is searched by squares, halved where undecided, largest first. A square is ruled
/// out when all its positions are taken by a ball, or when [`snookered_on_all_near`] proves
/// every position of it snookered on every ball on; the centre of each square is tried, and
/// a placeable centre with a ball on in view ends the search: not snookered, exactly. When
/// no centre has a view the cue ball is called snookered, which is exact but for views
/// from small patches: a view from every point of a disc of radius [`D_SEARCH_TOLERANCE`]
/// in the D, clear of the balls, is always found (no square holding the disc's centre can
/// be ruled out, so they are halved until one is smaller than the disc and its centre,
/// inside the disc, is tried). A view from no such disc may be missed, as may any view
/// after [`D_SEARCH_SQUARES`] squares.
pub fn snookered_in_the_d(balls: &[BallState], targets: &[DVec2], obstacles: &Obstacles) -> bool {
    let r = radius();
    let centre = d_centre();
    let occupied: Vec<DVec2> = balls
        .iter()
        .skip(1)
        .filter(|b| b.motion != MotionState::Pocketed)
        .map(|b| b.pos)
        .collect();
    let half = 0.5 * D_RADIUS;
    let mut squares: std::collections::VecDeque<(DVec2, f64)> = [-1.0, 1.0]
        .map(|side| (centre + DVec2::new(side * half, -half), half))
        .into();
    let mut tried = 0;
    while let Some((c, a)) = squares.pop_front() {
        tried += 1;
        if tried > D_SEARCH_SQUARES {
            break;
        }
        let h = a * std::f64::consts::SQRT_2;
        // The square's point nearest the D's centre.
        let near = centre.clamp(c - a, c + a);
        let outside = c.y - a > BAULK_LINE || (near - centre).length() > D_RADIUS;
        let taken = occupied.iter().any(|&q| (c - q).length() + h <= 2.0 * r);
        if outside || taken {
            continue;
        }
        if in_d(c)
            && is_free(balls, usize::from(CUE), c)
            && targets.iter().any(|&t| !snookered_on(c, t, obstacles))
        {
            return false;
        }
        let ruled_out = targets
            .iter()
            .all(|&t| snookered_on_all_near(c, h, t, obstacles));
        if ruled_out || h < D_SEARCH_TOLERANCE {
            continue;
        }
        let q = 0.5 * a;
        for (dx, dy) in [(-q, -q), (q, -q), (-q, q), (q, q)] {
            squares.push_back((c + DVec2::new(dx, dy), q));
        }
    }
    true
}

/// `target − cue` and its length, or `None` when the two balls touch: a ball the cue ball
/// touches is in view whatever lies around.
fn apart(cue: DVec2, target: DVec2) -> Option<(DVec2, f64)> {
    let to = target - cue;
    let dist = to.length();
    if dist <= 2.0 * radius() {
        None
    } else {
        Some((to, dist))
    }
}

/// Can the cue ball at `cue` hit the ball at `target` full in the face, by a straight stroke
/// that meets nothing on its way, neither a ball not on nor a jaw (the "clear view" of the
/// three-miss rule: "a clear path in a straight line ... such that central, full-ball
/// contact is available"; a jaw in that path leaves no such contact, however far the
/// balls are)?
pub fn full_ball_in_view(cue: DVec2, target: DVec2, obstacles: &Obstacles) -> bool {
    let r = radius();
    let Some((to, dist)) = apart(cue, target) else {
        return true;
    };
    let end = cue + to * ((dist - 2.0 * r) / dist);
    obstacles.clear(cue, end)
}

/// The seat that wins the drawing of lots for the re-spotted black, from the game's seed.
pub fn draw_lots(seed: u64) -> bool {
    SplitMix64::new(seed ^ 0xB1AC_B1AC_B1AC_B1AC).next_u64() & 1 == 0
}
