//! Table landmarks, the racks, and spotting a ball.
//!
//! Coordinates are the scene frame: `x` across the table (0..width), `y` along it
//! (0..length). The head string is the line `y = length/4`; the kitchen is the quarter of the
//! table behind it (`y < length/4`). The foot spot is `(width/2, 3·length/4)` and the racks
//! grow from it towards the foot rail (`+y`).
//!
//! Rack positions come from [`SplitMix64`], a tiny PRNG written out here so that a seed gives
//! the same rack in every build, forever.

use glam::DVec2;

use crate::physics::{ball_cushion, BallState, MotionState, Params, Table, TableKind};

/// How far a racked ball may sit from its ideal spot (m). A real rack is never perfectly
/// frozen: its balls touch some neighbours and miss others by a fraction of a millimetre,
/// and those gaps are what spread a break (a perfectly frozen rack, hit head on, sends the
/// cue ball's momentum down the two edges of the triangle to the back corners and leaves
/// the rest of the pack in place). Spots are spaced `2R + 2·RACK_JITTER` apart and each ball
/// but the apex is moved off its spot by up to `RACK_JITTER` in a seeded random direction, so
/// neighbours never overlap and their gaps range from 0 to 0.4 mm.
pub const RACK_JITTER: f64 = 1e-4;
/// Space between neighbouring spots of a rack beyond touching (m).
pub const RACK_GAP: f64 = 2.0 * RACK_JITTER;

/// SplitMix64 (Steele, Lea and Flood, 2014): a 64-bit state advanced by a fixed odd constant
/// and mixed by two multiply–xorshift rounds. Small, fast, and fully specified here, which is
/// what a rack needs (stable output across versions), not cryptographic quality.
#[derive(Clone, Copy, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator that starts from `seed`; equal seeds give equal sequences.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n > 0`), by rejection so every value is equally likely.
    pub fn below(&mut self, n: u64) -> u64 {
        let zone = u64::MAX - u64::MAX % n;
        loop {
            let x = self.next_u64();
            if x < zone {
                return x % n;
            }
        }
    }

    /// Fisher–Yates shuffle.
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A vector of length at most `radius`, uniform over the disc.
    pub fn offset(&mut self, radius: f64) -> DVec2 {
        let angle = 2.0 * std::f64::consts::PI * self.unit();
        let r = radius * self.unit().sqrt();
        DVec2::new(r * libm::cos(angle), r * libm::sin(angle))
    }

    /// Shuffles `items` in place (Fisher–Yates), every order equally likely.
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.below(i as u64 + 1) as usize;
            items.swap(i, j);
        }
    }
}

/// The seed of the `rack`-th rack of a game (0 for the opening rack), so that every re-rack
/// is different yet fixed by the game's seed.
pub fn rack_seed(seed: u64, rack: u32) -> u64 {
    let mut mix = SplitMix64::new(seed ^ u64::from(rack).wrapping_mul(0xD1B5_4A32_D192_ED03));
    mix.next_u64()
}

/// Width and length of the playing surface; the open table has no landmarks, so the rules
/// use a 9-foot table's instead.
pub fn table_size(kind: TableKind) -> (f64, f64) {
    kind.size()
        .or(TableKind::NineFoot.size())
        .unwrap_or((1.27, 2.54))
}

/// The foot spot, where the apex ball of a rack sits.
pub fn foot_spot(kind: TableKind) -> DVec2 {
    let (w, l) = table_size(kind);
    DVec2::new(0.5 * w, 0.75 * l)
}

/// The head string's `y`: the cue ball in hand "behind the head string" must have its centre
/// at `y` below this.
pub fn head_string(kind: TableKind) -> f64 {
    0.25 * table_size(kind).1
}

/// Where the cue ball waits for a break: on the long string, midway into the kitchen.
pub fn break_spot(kind: TableKind) -> DVec2 {
    let (w, l) = table_size(kind);
    DVec2::new(0.5 * w, 0.125 * l)
}

/// The ball radius the rules use (the physics default).
pub fn ball_radius() -> f64 {
    Params::default().ball_radius
}

/// Distance between the centres of neighbouring balls in a rack.
fn spacing() -> f64 {
    2.0 * ball_radius() + RACK_GAP
}

/// Centres of a triangle-like rack: `rows[r]` balls in row `r`, rows `√3/2·d` apart along
/// `+y` from the foot spot, each row centred on the long string; every ball but the apex
/// moved off its spot by up to [`RACK_JITTER`], drawn from a stream of `seed` of its own.
fn rack_positions(kind: TableKind, rows: &[usize], seed: u64) -> Vec<DVec2> {
    let mut jitter = SplitMix64::new(seed ^ JITTER_SALT);
    let d = spacing();
    let row_step = d * (3.0f64.sqrt() * 0.5);
    let apex = foot_spot(kind);
    let mut out = Vec::new();
    for (r, &n) in rows.iter().enumerate() {
        let y = apex.y + r as f64 * row_step;
        for k in 0..n {
            let x = apex.x + (k as f64 - 0.5 * (n as f64 - 1.0)) * d;
            let spot = DVec2::new(x, y);
            out.push(if r == 0 {
                spot
            } else {
                spot + jitter.offset(RACK_JITTER)
            });
        }
    }
    out
}

/// Salt that separates the stream of rack jitter from the stream that places the balls.
const JITTER_SALT: u64 = 0x6a09_e667_f3bc_c909;

fn pocketed() -> BallState {
    BallState {
        motion: MotionState::Pocketed,
        ..BallState::at_rest(DVec2::ZERO)
    }
}

/// Sixteen balls (index = number, 0 = cue) racked for 8-ball: the 8 in the middle of the
/// third row, a solid and a stripe on the two back corners, the rest shuffled; the cue ball
/// on the break spot.
pub fn eight_ball(kind: TableKind, seed: u64) -> Vec<BallState> {
    let mut rng = SplitMix64::new(seed);
    let spots = rack_positions(kind, &[1, 2, 3, 4, 5], seed);
    // Spot indices: row 2 middle is 1 + 2 + 1 = 4; back corners are 10 and 14.
    let (middle, corners) = (4, [10, 14]);
    let mut solids: Vec<usize> = (1..=7).collect();
    let mut stripes: Vec<usize> = (9..=15).collect();
    rng.shuffle(&mut solids);
    rng.shuffle(&mut stripes);
    let (solid, stripe) = (solids.pop(), stripes.pop());
    let mut corner_balls = [solid.unwrap_or(1), stripe.unwrap_or(9)];
    rng.shuffle(&mut corner_balls);
    let mut rest: Vec<usize> = solids.into_iter().chain(stripes).collect();
    rng.shuffle(&mut rest);
    let fixed = [
        (8, middle),
        (corner_balls[0], corners[0]),
        (corner_balls[1], corners[1]),
    ];
    racked(kind, 16, &spots, &fixed, rest)
}

/// Ten balls (0 = cue, 1..=9) racked for 9-ball: a diamond with the 1 at the apex on the
/// foot spot, the 9 in the centre, the rest shuffled; the cue ball on the break spot.
pub fn nine_ball(kind: TableKind, seed: u64) -> Vec<BallState> {
    let mut rng = SplitMix64::new(seed);
    let spots = rack_positions(kind, &[1, 2, 3, 2, 1], seed);
    // Spot 0 is the apex, spot 4 the middle of the third row (the centre of the diamond).
    let mut rest: Vec<usize> = (2..=8).collect();
    rng.shuffle(&mut rest);
    racked(kind, 10, &spots, &[(1, 0), (9, 4)], rest)
}

/// `count` balls (index = number) racked on `spots`: the cue ball on the break spot, each
/// `(ball, spot)` of `fixed` on its spot, the `rest` on the other spots in order; any ball
/// left over is off the table.
fn racked(
    kind: TableKind,
    count: usize,
    spots: &[DVec2],
    fixed: &[(usize, usize)],
    rest: Vec<usize>,
) -> Vec<BallState> {
    let mut balls = vec![pocketed(); count];
    balls[0] = BallState::at_rest(break_spot(kind));
    for &(ball, spot) in fixed {
        balls[ball] = BallState::at_rest(spots[spot]);
    }
    let free = (0..spots.len()).filter(|s| fixed.iter().all(|&(_, f)| f != *s));
    for (spot, ball) in free.zip(rest) {
        balls[ball] = BallState::at_rest(spots[spot]);
    }
    balls
}

/// Is `pos` a free place for ball `ball` on `kind`: on the playing surface, clear of the
/// cushions and pockets, and not overlapping any other ball on the table?
pub fn is_free(balls: &[BallState], ball: usize, pos: DVec2, kind: TableKind) -> bool {
    if !pos.is_finite() {
        return false;
    }
    let params = Params::default();
    let table = Table::new(kind);
    if !table.fits(
        table.to_engine(pos),
        ball_cushion::contact_distance(&params),
    ) {
        return false;
    }
    let min = 2.0 * params.ball_radius;
    balls.iter().enumerate().all(|(i, b)| {
        i == ball || b.motion == MotionState::Pocketed || (b.pos - pos).length() >= min
    })
}

/// Where [`spot`] put a ball (WPA 1.4 Spotting Balls).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spotted {
    /// On the foot spot.
    FootSpot,
    /// On the long string behind the foot spot (towards the foot rail), as near it as
    /// possible.
    BehindFootSpot,
    /// On the long string in front of the foot spot, as near it as possible: the string
    /// behind it was full.
    InFrontOfFootSpot,
    /// The whole long string was full: the free place nearest the foot spot.
    NearFootSpot,
}

impl Spotted {
    /// "on the foot spot", for a reason text.
    pub fn describe(self) -> &'static str {
        match self {
            Spotted::FootSpot => "on the foot spot",
            Spotted::BehindFootSpot => "behind the foot spot",
            Spotted::InFrontOfFootSpot => "in front of the foot spot",
            Spotted::NearFootSpot => "as near the foot spot as the table allows",
        }
    }
}

/// Puts `ball` back on the table (WPA 1.4): on the foot spot if it is free, else on the long
/// string as near to it as possible behind it (towards the foot rail), else in front of it.
/// The string holds about forty balls, so it is never full in play; if it were, the ball
/// goes to the free place nearest the foot spot. Spotting always succeeds: a game never
/// waits on a ball that could not be put back. (A ball number out of range changes
/// nothing.)
#[must_use]
pub fn spot(balls: &mut [BallState], ball: usize, kind: TableKind) -> Spotted {
    let (place, spotted) = spot_place(balls, ball, kind);
    if let Some(b) = balls.get_mut(ball) {
        *b = BallState::at_rest(place);
    }
    spotted
}

/// Where [`spot`] puts `ball`.
fn spot_place(balls: &[BallState], ball: usize, kind: TableKind) -> (DVec2, Spotted) {
    let foot = foot_spot(kind);
    let d = 2.0 * ball_radius() + RACK_GAP;
    let free = |p: DVec2| is_free(balls, ball, p, kind);
    // Candidates: the spot itself and, for every ball near the string, the places just
    // touching it on either side. The first free one in order of preference wins.
    let mut behind = vec![foot.y];
    let mut front = Vec::new();
    for (i, b) in balls.iter().enumerate() {
        let dx = (b.pos.x - foot.x).abs();
        if i == ball || b.motion == MotionState::Pocketed || dx >= d {
            continue;
        }
        let dy = (d * d - dx * dx).sqrt();
        for y in [b.pos.y + dy, b.pos.y - dy] {
            if y >= foot.y {
                behind.push(y);
            } else {
                front.push(y);
            }
        }
    }
    behind.sort_by(f64::total_cmp);
    front.sort_by(|a, b| b.total_cmp(a));
    let on_string = |y: f64| DVec2::new(foot.x, y);
    if let Some(p) = behind.into_iter().map(on_string).find(|p| free(*p)) {
        let spotted = if p == foot {
            Spotted::FootSpot
        } else {
            Spotted::BehindFootSpot
        };
        return (p, spotted);
    }
    if let Some(p) = front.into_iter().map(on_string).find(|p| free(*p)) {
        return (p, Spotted::InFrontOfFootSpot);
    }
    // Off the string: a grid of places a quarter ball apart over the whole table, nearest
    // the foot spot first. Sixteen balls cannot cover it, so one is free; the foot spot
    // itself is only the answer the types need.
    let (w, l) = table_size(kind);
    let step = 0.5 * ball_radius();
    let (nx, ny) = ((w / step) as i64, (l / step) as i64);
    let mut grid: Vec<DVec2> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| DVec2::new(i as f64 * step, j as f64 * step)))
        .collect();
    grid.sort_by(|a, b| (*a - foot).length().total_cmp(&(*b - foot).length()));
    let place = grid.into_iter().find(|p| free(*p)).unwrap_or(foot);
    (place, Spotted::NearFootSpot)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_no_overlap(balls: &[BallState]) {
        let r = ball_radius();
        for (i, a) in balls.iter().enumerate() {
            for b in &balls[i + 1..] {
                assert!((a.pos - b.pos).length() >= 2.0 * r, "{a:?} {b:?}");
            }
        }
    }

    /// Asserts that `balls` are `count` balls (the cue ball among them), none overlapping another.
    fn assert_rack(balls: &[BallState], count: usize) {
        assert_eq!(balls.len(), count, "{balls:?}");
        assert_no_overlap(balls);
    }

    #[test]
    fn splitmix_matches_the_published_sequence() {
        // First outputs for seed 0 from the reference implementation.
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    }

    /// Asserts that `ball` is in the middle of a rack's third row, off it by the jitter at most.
    fn assert_in_the_middle_of_the_third_row(ball: BallState, kind: TableKind) {
        let (foot, row_step) = (foot_spot(kind), spacing() * (3.0f64.sqrt() * 0.5));
        assert!((ball.pos.x - foot.x).abs() <= RACK_JITTER, "{ball:?}");
        assert!(
            (ball.pos.y - (foot.y + 2.0 * row_step)).abs() <= RACK_JITTER,
            "{ball:?}"
        );
    }

    #[test]
    fn eight_ball_rack_layout() {
        let balls = eight_ball(TableKind::NineFoot, 7);
        assert_rack(&balls, 16);
        let foot = foot_spot(TableKind::NineFoot);
        let row_step = spacing() * (3.0f64.sqrt() * 0.5);
        // The 8 is in the middle of the third row.
        assert_in_the_middle_of_the_third_row(balls[8], TableKind::NineFoot);
        // A solid and a stripe on the back corners.
        let back_y = foot.y + 4.0 * row_step;
        let mut corners: Vec<usize> = (1..16)
            .filter(|&i| (balls[i].pos.y - back_y).abs() <= RACK_JITTER)
            .filter(|&i| (balls[i].pos.x - foot.x).abs() > 1.5 * (2.0 * ball_radius()))
            .collect();
        corners.sort();
        assert_eq!(corners.len(), 2);
        assert!(corners[0] < 8 && corners[1] > 8, "corners {corners:?}");
        // The apex is on the foot spot.
        assert!((1..16).any(|i| balls[i].pos == foot));
        // The cue ball is in the kitchen.
        assert!(balls[0].pos.y < head_string(TableKind::NineFoot));
    }

    #[test]
    fn racks_are_fixed_by_the_seed_and_vary_with_it() {
        let a = eight_ball(TableKind::NineFoot, 42);
        assert_eq!(a, eight_ball(TableKind::NineFoot, 42));
        assert_ne!(a, eight_ball(TableKind::NineFoot, 43));
        let n = nine_ball(TableKind::NineFoot, 42);
        assert_eq!(n, nine_ball(TableKind::NineFoot, 42));
        assert_ne!(n, nine_ball(TableKind::NineFoot, 44));
    }

    #[test]
    fn nine_ball_rack_layout() {
        let balls = nine_ball(TableKind::NineFoot, 3);
        assert_rack(&balls, 10);
        let foot = foot_spot(TableKind::NineFoot);
        assert_eq!(balls[1].pos, foot);
        assert_in_the_middle_of_the_third_row(balls[9], TableKind::NineFoot);
    }

    #[test]
    fn spotting_goes_behind_an_occupied_foot_spot() {
        let mut balls = eight_ball(TableKind::NineFoot, 1);
        balls[8].motion = MotionState::Pocketed;
        // The apex ball occupies the foot spot, so the 8 must go elsewhere on the string.
        assert_eq!(
            spot(&mut balls, 8, TableKind::NineFoot),
            Spotted::BehindFootSpot
        );
        let foot = foot_spot(TableKind::NineFoot);
        assert_eq!(balls[8].pos.x, foot.x);
        assert_ne!(balls[8].pos.y, foot.y);
        assert_no_overlap(&balls);
        // With the table clear, the 8 goes on the foot spot itself.
        let mut clear: Vec<BallState> = balls.iter().map(|_| pocketed()).collect();
        clear[0] = BallState::at_rest(break_spot(TableKind::NineFoot));
        assert_eq!(spot(&mut clear, 8, TableKind::NineFoot), Spotted::FootSpot);
        assert_eq!(clear[8].pos, foot);
    }
}
