//! The state of a snooker match between strokes (scores, the ball on, nominations, the
//! choice after a foul, the miss count) and the judgement of one stroke from what the engine
//! saw. Pure: it never simulates; `rules/snooker.rs` plays it as a `Game`.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::physics::{BallState, EventKind, MotionState, Outcome};

use super::super::Seat;
use super::table::{self, ball_name, is_colour, is_red, value, BLACK, COLOURS, CUE, PINK};

/// The lowest and highest penalty of a foul (WPBSA 3.12).
pub const MIN_PENALTY: u32 = 4;
/// The highest penalty of a foul.
pub const MAX_PENALTY: u32 = 7;
/// Misses from a clear view that forfeit the frame, the last of them (WPBSA 3.14).
pub const MISSES_TO_FORFEIT: u8 = 3;

/// What the striker must hit first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum BallOn {
    /// Any red (reds remain and the striker has not just potted one).
    Red,
    /// A colour, having potted a red: the nominated one, or any if none was nominated.
    Colour(Option<u8>),
    /// The colours in order, reds gone: this one.
    Sequence(u8),
}

/// The balls as they were before a stroke that was called a foul and a miss, to be put
/// back if the next player asks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Restore {
    /// Every ball, as before the stroke.
    pub balls: Vec<BallState>,
    /// The striker was on a colour after a red.
    pub on_colour: bool,
}

/// The choice the next player has after a foul.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AfterFoul {
    /// Who fouled.
    pub offender: Seat,
    /// The foul was also a miss: the balls may be replaced.
    pub restore: Option<Restore>,
}

/// A snooker match: frames, and the frame being played.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snooker {
    /// Reds racked each frame (15, or 10 or 6 for short games).
    pub reds: u8,
    /// Frames in the match: the first to win more than half wins.
    pub best_of: u8,
    /// Frames won by seats A and B.
    pub frames: [u8; 2],
    /// The frame's scores of seats A and B.
    pub scores: [u32; 2],
    /// The current break: points scored by the striker in this visit.
    pub break_points: u32,
    /// Who broke off this frame (the players alternate).
    pub starter: Seat,
    /// The striker potted a red (or a free ball for one) and is on a colour.
    pub on_colour: bool,
    /// The colour nominated for the coming stroke, or the free ball.
    pub nominated: Option<u8>,
    /// The striker was given a free ball and may nominate any ball.
    pub free_ball: bool,
    /// The choice after a foul, while it is due.
    pub after_foul: Option<AfterFoul>,
    /// Fouls and misses in a row by the striker from replaced positions (0 when the last
    /// stroke was not one).
    pub misses: u8,
    /// The coming stroke is played from a position replaced after a miss.
    pub replayed: bool,
    /// The frame is in its re-spotted black: the next score or foul decides it.
    pub respotted_black: bool,
}

impl Snooker {
    /// A match of `reds`-red frames, best of `best_of`, seat A breaking off the first.
    pub fn new(reds: u8, best_of: u8) -> Snooker {
        Snooker {
            reds: reds.clamp(1, table::LAST_RED),
            best_of: best_of.max(1),
            frames: [0; 2],
            scores: [0; 2],
            break_points: 0,
            starter: Seat::A,
            on_colour: false,
            nominated: None,
            free_ball: false,
            after_foul: None,
            misses: 0,
            replayed: false,
            respotted_black: false,
        }
    }

    /// A new frame, `starter` breaking off: scores and the stroke's state cleared.
    pub fn start_frame(&mut self, starter: Seat) {
        *self = Snooker {
            frames: self.frames,
            starter,
            ..Snooker::new(self.reds, self.best_of)
        };
    }

    /// Frames needed to win the match.
    pub fn frames_to_win(&self) -> u8 {
        self.best_of / 2 + 1
    }

    /// The ball on for the coming stroke, from the balls on the table.
    pub fn ball_on(&self, balls: &[BallState]) -> BallOn {
        if self.on_colour {
            return BallOn::Colour(self.nominated.filter(|&b| is_colour(b)));
        }
        if reds_left(balls) > 0 {
            return BallOn::Red;
        }
        BallOn::Sequence(lowest_colour(balls).unwrap_or(BLACK))
    }

    /// The balls that are on: the ones a stroke must hit first.
    pub fn balls_on(&self, balls: &[BallState]) -> Vec<u8> {
        match self.ball_on(balls) {
            BallOn::Red => (1..=table::LAST_RED)
                .filter(|&b| on_table(balls, b))
                .collect(),
            BallOn::Colour(Some(c)) => vec![c],
            BallOn::Colour(None) => COLOURS
                .into_iter()
                .filter(|&c| on_table(balls, c))
                .collect(),
            BallOn::Sequence(c) => vec![c],
        }
    }

    /// Points left on the table for the striker: each red with a black, then the colours.
    pub fn points_remaining(&self, balls: &[BallState]) -> u32 {
        let reds = reds_left(balls);
        let colours: u32 = COLOURS
            .into_iter()
            .filter(|&c| on_table(balls, c))
            .map(value)
            .sum();
        let pending_colour = if self.on_colour { value(BLACK) } else { 0 };
        if reds > 0 || self.on_colour {
            reds * (1 + value(BLACK)) + pending_colour + 27
        } else {
            colours
        }
    }

    /// Does `seat` need snookers: is it behind by more than the points left?
    pub fn snookers_required(&self, seat: Seat, balls: &[BallState]) -> bool {
        let (own, other) = self.score_pair(seat);
        other > own + self.points_remaining(balls)
    }

    /// (seat's score, opponent's score).
    pub fn score_pair(&self, seat: Seat) -> (u32, u32) {
        (self.scores[seat.index()], self.scores[seat.other().index()])
    }
}

/// Is `ball` on the table?
pub fn on_table(balls: &[BallState], ball: u8) -> bool {
    balls
        .get(usize::from(ball))
        .is_some_and(|b| b.motion != MotionState::Pocketed)
}

/// Reds on the table.
pub fn reds_left(balls: &[BallState]) -> u32 {
    (1..=table::LAST_RED)
        .filter(|&b| on_table(balls, b))
        .count() as u32
}

/// The lowest-valued colour on the table.
pub fn lowest_colour(balls: &[BallState]) -> Option<u8> {
    COLOURS.into_iter().find(|&c| on_table(balls, c))
}

/// What the engine saw of one stroke, as a referee needs it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stroke {
    /// The balls the cue ball touched first, all at the same instant (two or more: hit at
    /// once), in index order; empty if it touched none.
    pub first: Vec<u8>,
    /// When it first touched a ball.
    pub first_time: Option<f64>,
    /// Balls pocketed, in order (the cue ball included).
    pub potted: Vec<u8>,
    /// Balls that left the table other than by a pocket.
    pub off_table: Vec<u8>,
    /// Balls the cue ball flew over before it first touched a ball (a jump shot).
    pub jumped_over: Vec<u8>,
}

impl Stroke {
    /// Reads the stroke from the engine's outcome.
    pub fn read(outcome: &Outcome) -> Stroke {
        let mut stroke = Stroke::default();
        for e in &outcome.events {
            match e.kind {
                EventKind::BallBall { a, b } => {
                    let other = if a == u16::from(CUE) {
                        b
                    } else if b == u16::from(CUE) {
                        a
                    } else {
                        continue;
                    };
                    match stroke.first_time {
                        None => {
                            stroke.first_time = Some(e.t);
                            stroke.first.push(other as u8);
                        }
                        Some(t) if t == e.t && !stroke.first.contains(&(other as u8)) => {
                            stroke.first.push(other as u8);
                        }
                        _ => {}
                    }
                }
                EventKind::BallPocket { ball, .. } => stroke.potted.push(ball as u8),
                EventKind::BallOffTable { ball } if !stroke.off_table.contains(&(ball as u8)) => {
                    stroke.off_table.push(ball as u8);
                }
                _ => {}
            }
        }
        stroke.first.sort_unstable();
        stroke.jumped_over = jumped_over(outcome, stroke.first_time);
        // The ball first hit is met, not passed over: met in flight, the cue ball's centre
        // is within two radii of it seen from above.
        stroke.jumped_over.retain(|b| !stroke.first.contains(b));
        stroke
    }

    /// Every ball that went down or off, the cue ball included.
    fn gone(&self) -> impl Iterator<Item = u8> + '_ {
        self.potted.iter().chain(&self.off_table).copied()
    }

    /// The cue ball went in a pocket or off the table.
    pub fn cue_gone(&self) -> bool {
        self.gone().any(|b| b == CUE)
    }
}

/// The balls the cue ball passed over in flight before its first contact (by `first_time`;
/// the whole shot if it touched none): seen from above it came within two radii of their
/// centres with no contact, so it went over them. In flight its path seen from above is
/// straight, so each piece of flight is one segment. A cue ball that meets a ball in flight
/// has not jumped it; one that meets it and then lands beyond it is not told apart (the
/// rules' third kind of jump shot is not judged).
fn jumped_over(outcome: &Outcome, first_time: Option<f64>) -> Vec<u8> {
    let end = first_time.unwrap_or(f64::INFINITY);
    let cue = usize::from(CUE);
    let Some(pieces) = outcome.history.get(cue) else {
        return Vec::new();
    };
    let reach = 2.0 * table::radius() - 1e-9;
    let mut over = Vec::new();
    for (k, piece) in pieces.iter().enumerate() {
        if piece.t0 >= end {
            break;
        }
        if piece.start.motion != MotionState::Airborne {
            continue;
        }
        let next = pieces.get(k + 1).map_or(piece.t_end, |p| p.t0);
        let t1 = next.min(piece.t_end).min(end).min(outcome.duration);
        let a = outcome.state_at(cue, piece.t0).pos;
        let b = outcome.state_at(cue, t1).pos;
        for ball in 1..outcome.history.len().min(table::BALL_COUNT) {
            // Before the cue ball's first contact every other ball lies where it was.
            let at = outcome.state_at(ball, 0.0);
            if matches!(at.motion, MotionState::Pocketed | MotionState::OffTable) {
                continue;
            }
            let ball = ball as u8;
            if distance_to_segment(at.pos, a, b) < reach && !over.contains(&ball) {
                over.push(ball);
            }
        }
    }
    over
}

/// How far `p` is from the segment `a`–`b`.
fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// One foul of a stroke: its value and what happened ("the blue was hit first").
#[derive(Clone, Debug, PartialEq)]
pub struct Foul {
    /// Penalty points, 4 to 7.
    pub value: u32,
    /// What happened, in words.
    pub what: String,
}

/// The referee's reading of a stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct Judgement {
    /// The fouls, the highest first; empty for a fair stroke.
    pub fouls: Vec<Foul>,
    /// The striker failed to hit a ball on first (a miss may be called).
    pub missed_ball_on: bool,
    /// Points the striker scored (0 on a foul).
    pub points: u32,
    /// The balls that count as potted fairly: the striker stays at the table.
    pub scored: Vec<u8>,
    /// The colours to put back on their spots, highest value first.
    pub respot: Vec<u8>,
    /// The colour deemed nominated when none was (the first ball hit).
    pub deemed: Option<u8>,
}

impl Judgement {
    /// The penalty of the stroke: the highest of its fouls.
    pub fn penalty(&self) -> u32 {
        self.fouls.first().map_or(0, |f| f.value)
    }
}

/// The penalty for a foul involving balls of `values` with `on` the ball on's value.
fn penalty(on: u32, concerned: &[u32]) -> u32 {
    concerned
        .iter()
        .copied()
        .fold(on, u32::max)
        .clamp(MIN_PENALTY, MAX_PENALTY)
}

/// Judges `stroke` played from `before` by a striker in `state`. `touching`: the ball the
/// cue ball touched before the stroke, if any.
pub fn judge(
    state: &Snooker,
    before: &[BallState],
    stroke: &Stroke,
    touching: Option<u8>,
) -> Judgement {
    let on = state.ball_on(before);
    let free = state.nominated.filter(|_| state.free_ball);
    let reds_before = reds_left(before);
    // The value a foul is at least: the ball on's (7 for a foul before nominating).
    let (on_value, nominated_missing) = match on {
        BallOn::Red => (1, false),
        BallOn::Colour(Some(c)) => (value(c), false),
        BallOn::Colour(None) => (MAX_PENALTY, true),
        BallOn::Sequence(c) => (value(c), false),
    };
    let is_on = |b: u8| match on {
        BallOn::Red => is_red(b),
        BallOn::Colour(Some(c)) | BallOn::Sequence(c) => b == c,
        BallOn::Colour(None) => is_colour(b),
    };
    // The free ball acts as the ball on.
    let acts_on = |b: u8| is_on(b) || Some(b) == free;
    let mut fouls = Vec::new();
    let mut foul = |concerned: &[u32], what: String| {
        fouls.push(Foul {
            value: penalty(on_value, concerned),
            what,
        })
    };
    let mut missed = false;
    let deemed = match on {
        BallOn::Colour(None) => stroke.first.first().copied().filter(|&b| is_colour(b)),
        _ => None,
    };
    let target = |b: u8| match deemed {
        Some(d) => b == d,
        None => acts_on(b),
    };
    match stroke.first.as_slice() {
        [] => {
            // Playing away from a touching ball that is on is no foul (WPBSA 3.14).
            if !touching.is_some_and(acts_on) {
                missed = true;
                foul(&[], "the cue ball hit no ball".into());
            }
        }
        [b] => {
            if !target(*b) {
                missed = true;
                foul(&[value(*b)], format!("{} was hit first", ball_name(*b)));
            }
        }
        several => {
            let all_reds = several.iter().all(|&b| is_red(b)) && on == BallOn::Red;
            let free_with_on = free.is_some_and(|f| several.contains(&f))
                && several.len() == 2
                && several.iter().all(|&b| acts_on(b));
            if !all_reds && !free_with_on {
                missed = true;
                let names: Vec<String> = several.iter().map(|&b| ball_name(b)).collect();
                let values: Vec<u32> = several.iter().map(|&b| value(b)).collect();
                foul(&values, format!("{} were hit at once", names.join(" and ")));
            }
        }
    }
    if let (Some(t), Some(time)) = (touching, stroke.first_time) {
        if stroke.first.contains(&t) && time <= 1e-9 {
            foul(
                &[value(t)],
                format!("push stroke: the cue ball was touching {}", ball_name(t)),
            );
        }
    }
    for &b in &stroke.jumped_over {
        // A jump shot costs the value of the ball on (the WPBSA penalty section).
        foul(
            &[],
            format!("jump shot: the cue ball jumped over {}", ball_name(b)),
        );
    }
    if stroke.potted.contains(&CUE) {
        foul(&[], "in-off: the cue ball was potted".into());
    }
    for &b in &stroke.off_table {
        let what = if b == CUE {
            "the cue ball left the table".to_string()
        } else {
            format!("{} was forced off the table", ball_name(b))
        };
        foul(&[value(b)], what);
    }
    // Pots: on reds, any reds (and the free ball); on a colour, that colour alone.
    let object_pots: Vec<u8> = stroke
        .potted
        .iter()
        .copied()
        .filter(|&b| b != CUE)
        .collect();
    let colour_target = match on {
        BallOn::Colour(Some(c)) => Some(c),
        BallOn::Colour(None) => deemed,
        _ => None,
    };
    let mut scored = Vec::new();
    for &b in &object_pots {
        let fair = match on {
            BallOn::Red => is_red(b) || Some(b) == free,
            BallOn::Colour(_) => Some(b) == colour_target || Some(b) == free,
            BallOn::Sequence(c) => b == c || Some(b) == free,
        };
        if fair {
            scored.push(b);
        } else {
            foul(&[value(b)], format!("{} was potted", ball_name(b)));
        }
    }
    if nominated_missing {
        // WPBSA 3.12(e): a foul after potting a red, before nominating, costs 7.
        for f in &mut fouls {
            f.value = MAX_PENALTY;
            f.what.push_str(" before a colour was nominated");
        }
    }
    // The highest foul first; equal values keep the order they were found in.
    fouls.sort_by_key(|f| std::cmp::Reverse(f.value));
    let is_foul = !fouls.is_empty();
    // Points of a fair stroke. With both the free ball and the ball on down, only the ball on
    // counts in the colours; on the reds each ball counts (WPBSA 3.10).
    let points = if is_foul {
        0
    } else {
        match on {
            BallOn::Red => scored.len() as u32,
            BallOn::Colour(_) => {
                let c = colour_target.filter(|c| scored.contains(c));
                match (c, free.filter(|f| scored.contains(f))) {
                    (Some(c), _) => value(c),
                    (None, Some(_)) => on_value,
                    (None, None) => 0,
                }
            }
            BallOn::Sequence(c) => {
                if scored.contains(&c) || free.is_some_and(|f| scored.contains(&f)) {
                    value(c)
                } else {
                    0
                }
            }
        }
    };
    // Colours that go back: all colours down on a foul; while reds remain (or just after the
    // last red) every colour potted; in the sequence only the free ball.
    let mut respot: Vec<u8> = stroke
        .gone()
        .filter(|&b| is_colour(b))
        .filter(|&b| {
            is_foul
                || reds_before > 0
                || matches!(on, BallOn::Colour(_))
                || Some(b) == free
                || !scored.contains(&b)
        })
        .collect();
    respot.sort_unstable_by(|a, b| b.cmp(a));
    respot.dedup();
    Judgement {
        fouls,
        missed_ball_on: missed,
        points,
        scored,
        respot,
        deemed,
    }
}

/// The foul of leaving the cue ball snookered behind the free ball (WPBSA Section 3 Rule
/// 10): after a free-ball stroke that was otherwise fair and potted nothing, no ball on (every
/// red, or the colour in sequence) can be hit at both extreme edges, and it could be but for
/// the free ball — unless only the pink and the black remain. `after` is the table at rest.
pub fn snookered_behind_free_ball(
    state: &Snooker,
    before: &[BallState],
    after: &[BallState],
    judgement: &Judgement,
) -> Option<Foul> {
    let free = state.nominated.filter(|_| state.free_ball)?;
    if !judgement.fouls.is_empty() || !judgement.scored.is_empty() || !on_table(after, free) {
        return None;
    }
    let objects: Vec<u8> = (1..table::BALL_COUNT as u8)
        .filter(|&b| on_table(before, b))
        .collect();
    if objects == [PINK, BLACK] {
        return None;
    }
    let (on, on_value): (Vec<u8>, u32) = match state.ball_on(before) {
        BallOn::Red => (
            (1..table::BALL_COUNT as u8)
                .filter(|&b| is_red(b) && on_table(after, b))
                .collect(),
            1,
        ),
        BallOn::Sequence(c) if c != free && on_table(after, c) => (vec![c], value(c)),
        _ => return None,
    };
    if on.is_empty() || !snookered(after, &on) {
        return None;
    }
    let mut without_free = after.to_vec();
    without_free[usize::from(free)].motion = MotionState::Pocketed;
    if snookered(&without_free, &on) {
        return None;
    }
    Some(Foul {
        value: penalty(on_value, &[]),
        what: format!(
            "the cue ball was left snookered behind the free ball, {}",
            ball_name(free)
        ),
    })
}

/// The ball the cue ball touches before the stroke, if any (within a micrometre).
pub fn touching(balls: &[BallState]) -> Option<u8> {
    let cue = balls.get(usize::from(CUE))?;
    if cue.motion == MotionState::Pocketed {
        return None;
    }
    let r = table::radius();
    (1..table::BALL_COUNT as u8).find(|&b| {
        balls.get(usize::from(b)).is_some_and(|s| {
            s.motion != MotionState::Pocketed && (s.pos - cue.pos).length() <= 2.0 * r + 1e-6
        })
    })
}

/// The cue ball, unless it is pocketed.
fn cue_on_table(balls: &[BallState]) -> Option<&BallState> {
    balls
        .get(usize::from(CUE))
        .filter(|b| b.motion != MotionState::Pocketed)
}

/// Is the cue ball snookered on every ball of `on` (WPBSA 2.16): can no ball on be hit at
/// both extreme edges without a ball not on in the way, a jaw met first being no snooker?
/// With the cue ball in hand (off the table), snookered from every position in the D.
pub fn snookered(balls: &[BallState], on: &[u8]) -> bool {
    let obstacles = table::Obstacles::new(blockers(balls, on));
    let targets: Vec<DVec2> = on
        .iter()
        .filter(|&&b| on_table(balls, b))
        .filter_map(|&b| balls.get(usize::from(b)).map(|t| t.pos))
        .collect();
    match cue_on_table(balls) {
        Some(cue) => targets
            .iter()
            .all(|&t| table::snookered_on(cue.pos, t, &obstacles)),
        None => table::snookered_in_the_d(balls, &targets, &obstacles),
    }
}

/// Has the cue ball a clear view of some ball on: a full-ball contact that no ball not on
/// and no jaw blocks?
pub fn clear_view(balls: &[BallState], on: &[u8]) -> bool {
    let Some(cue) = cue_on_table(balls) else {
        return false;
    };
    let obstacles = table::Obstacles::new(blockers(balls, on));
    on.iter().any(|&b| {
        balls
            .get(usize::from(b))
            .is_some_and(|t| table::full_ball_in_view(cue.pos, t.pos, &obstacles))
    })
}

/// The centres of the balls on the table that are neither the cue ball nor on.
fn blockers(balls: &[BallState], on: &[u8]) -> Vec<DVec2> {
    (1..balls.len().min(table::BALL_COUNT) as u8)
        .filter(|b| !on.contains(b) && on_table(balls, *b))
        .filter_map(|b| balls.get(usize::from(b)).map(|s| s.pos))
        .collect()
}
