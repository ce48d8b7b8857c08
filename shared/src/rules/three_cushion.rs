//! Three-cushion billiards under the UMB's World Rules of Carom Billiard: a match between two
//! seats on the carom table, seat A with the white ball, seat B with the yellow, both playing
//! the red. [`super::Game`] plays it as [`super::Variant::ThreeCushion`] (see `carom.rs`).
//!
//! - Start (art. 23): the red on the top spot, the opponent's ball on the bottom spot, the
//!   starter's ball on a starting spot of the starting line, [`START_OFFSET`] to the side of
//!   the bottom spot. The opening shot must hit the red first. The offset is that of the
//!   spots marked on a match table (2.84 m): 182.5 mm, half the 365 mm between the two
//!   starting spots in the table drawing of the German Billiard Union's material standard
//!   (reproduced in Wikipedia's "Billardtisch (Karambolage)",
//!   <https://de.zxc.wiki/wiki/Turnierbillard>); the US carom rules give the same spots as
//!   7 3/16 in (182.6 mm) either side of the head spot
//!   (<https://14dot1.com/NMT_BAC/house_rules/general_carom.html>).
//! - A point (art. 83): the cue ball touches both object balls, and cushions at least three
//!   times before it first touches the second of them. Cushion contacts are counted, so the
//!   same cushion twice counts twice, as the rule counts them.
//! - A point lets the shooter play on; a miss or a foul ends the inning and the opponent
//!   plays from the table as it lies. The first seat to reach the race (default 15) wins.
//!   Running out of time ends the inning ([`Match::time_out`]).
//! - Balls in contact (art. 27): when the shooter's ball rests against another ball, the
//!   shooter may have the balls set up as at the start ([`Match::respot`]) or play on, but
//!   not into the ball it touches: a first contact with that ball is a foul.
//! - Jumped balls (art. 28): a ball that leaves the table is a foul; the balls that left are
//!   spotted, a white or yellow on the bottom spot, the red on the top spot, each on the next
//!   free spot of bottom, top, centre when its own is taken. The engine reports a ball that
//!   left the table as a `ball_off_table` event ([`super::facts::departures`]), which
//!   [`CaromFacts::from_outcome`] reads.
//!
//! The rules are pure: [`Match::shoot`] simulates the shot with the physics engine, judges it
//! from the events and applies the verdict; [`Match::apply_facts`] does the same for facts
//! already read.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::{RuleError, Seat};
use crate::physics::{
    engine, simulate, BallState, EventKind, MotionState, Outcome, Shot, Strike, TableKind,
};

/// Ball numbers (indices in the ball list): the white, seat A's ball.
pub const WHITE: u8 = 0;
/// The yellow, seat B's ball.
pub const YELLOW: u8 = 1;
/// The red, the object ball of both seats.
pub const RED: u8 = 2;
/// Points that win a match unless another race is agreed.
pub const DEFAULT_RACE: u32 = 15;
/// Starting spots: on the starting line, this far (m) either side of the bottom spot.
pub const START_OFFSET: f64 = 0.1825;
/// Balls closer than this beyond touching (m) are in contact.
const CONTACT_GAP: f64 = 1e-6;
/// Most points in a race (a match must end).
pub const MAX_RACE: u32 = 1000;

fn size() -> DVec2 {
    let (w, l) = TableKind::Carom.size().unwrap_or((1.42, 2.84));
    DVec2::new(w, l)
}

/// The three spots on the long axis: bottom (a quarter of the length from the bottom
/// cushion), centre and top.
pub fn bottom_spot() -> DVec2 {
    let s = size();
    DVec2::new(0.5 * s.x, 0.25 * s.y)
}

/// The centre spot, in the middle of the table (scene coordinates, m).
pub fn centre_spot() -> DVec2 {
    let s = size();
    DVec2::new(0.5 * s.x, 0.5 * s.y)
}

/// The top spot, a quarter of the length from the top cushion (scene coordinates, m).
pub fn top_spot() -> DVec2 {
    let s = size();
    DVec2::new(0.5 * s.x, 0.75 * s.y)
}

/// The ball `seat` plays with.
pub fn cue_ball(seat: Seat) -> u8 {
    match seat {
        Seat::A => WHITE,
        Seat::B => YELLOW,
    }
}

/// The starting position for `starter`: red on the top spot, the opponent's ball on the
/// bottom spot, the starter's ball on the starting spot to the right of it.
pub fn start_position(starter: Seat) -> Vec<BallState> {
    let mut balls = vec![BallState::at_rest(DVec2::ZERO); 3];
    balls[usize::from(RED)] = BallState::at_rest(top_spot());
    balls[usize::from(cue_ball(starter.other()))] = BallState::at_rest(bottom_spot());
    balls[usize::from(cue_ball(starter))] =
        BallState::at_rest(bottom_spot() + DVec2::new(START_OFFSET, 0.0));
    balls
}

/// What the shooter's ball touched, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Touch {
    /// A bounce off any cushion.
    Cushion,
    /// A contact with the ball of this number.
    Ball(u8),
}

/// The facts of a carom shot that the rules judge.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CaromFacts {
    /// What the shooter's ball touched, in order.
    pub touches: Vec<Touch>,
    /// Balls that left the table, in the order they left.
    pub off_table: Vec<u8>,
}

impl CaromFacts {
    /// Reads the facts of a simulated shot in which `cue` was struck.
    pub fn from_outcome(outcome: &Outcome, cue: u8) -> CaromFacts {
        let cue16 = u16::from(cue);
        let touches = outcome
            .events
            .iter()
            .filter_map(|e| match e.kind {
                EventKind::BallBall { a, b } if a == cue16 => Some(Touch::Ball(b as u8)),
                EventKind::BallBall { a, b } if b == cue16 => Some(Touch::Ball(a as u8)),
                EventKind::BallCushion { ball, .. } if ball == cue16 => Some(Touch::Cushion),
                _ => None,
            })
            .collect();
        CaromFacts {
            touches,
            off_table: super::facts::departures(outcome)
                .iter()
                .map(|d| d.ball)
                .collect(),
        }
    }
}

/// The judgement of one shot.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Judgement {
    /// The shot scored: both object balls touched, three cushions before the second.
    pub point: bool,
    /// A ball left the table, the shooter's ball played into the one it touched, or the
    /// opening shot missed the red first; a foul scores no point.
    pub foul: bool,
    /// Readable reasons, the decisive one first.
    pub reasons: Vec<String>,
}

/// A ball's name in verdicts.
pub fn name(ball: u8) -> &'static str {
    match ball {
        WHITE => "the white",
        YELLOW => "the yellow",
        RED => "the red",
        _ => "a ball",
    }
}

fn cushions(n: usize) -> String {
    match n {
        1 => "1 cushion".into(),
        n => format!("{n} cushions"),
    }
}

/// Judges a shot of `cue`. `frozen_to`: the ball the cue ball rested against before the
/// shot (when the shooter chose to play on); `opening`: the match's first shot.
pub fn judge(facts: &CaromFacts, cue: u8, frozen_to: Option<u8>, opening: bool) -> Judgement {
    let mut reasons = Vec::new();
    let mut foul = false;
    if !facts.off_table.is_empty() {
        foul = true;
        for &b in &facts.off_table {
            let who = if b == cue {
                "the cue ball".into()
            } else {
                name(b).to_string()
            };
            reasons.push(format!("Foul: {who} left the table: no point"));
        }
    }
    let first_ball = facts.touches.iter().find_map(|t| match t {
        Touch::Ball(b) => Some(*b),
        Touch::Cushion => None,
    });
    if let (Some(f), Some(b)) = (frozen_to, first_ball) {
        if f == b {
            foul = true;
            reasons.push(format!(
                "Foul: played into {}, which it touched: no point",
                name(b)
            ));
        }
    }
    if opening && first_ball.is_some_and(|b| b != RED) {
        foul = true;
        reasons.push("Foul: the opening shot must hit the red first: no point".into());
    }
    // The cushions counted before the second object ball, and which ball that was.
    let mut seen: Vec<u8> = Vec::new();
    let mut count = 0;
    let mut second = None;
    for t in &facts.touches {
        match *t {
            Touch::Cushion => count += 1,
            Touch::Ball(b) if b != cue && !seen.contains(&b) => {
                seen.push(b);
                if seen.len() == 2 {
                    second = Some((b, count));
                    break;
                }
            }
            Touch::Ball(_) => {}
        }
    }
    let point = match (seen.first(), second) {
        (None, _) => {
            reasons.push("Missed both balls: no point".into());
            false
        }
        (Some(&first), None) => {
            let other = [WHITE, YELLOW, RED]
                .into_iter()
                .find(|&b| b != cue && b != first)
                .unwrap_or(RED);
            reasons.push(format!("Missed {}: no point", name(other)));
            false
        }
        (Some(_), Some((b, n))) if n < 3 => {
            reasons.push(format!("{} before {}: no point", cushions(n), name(b)));
            false
        }
        (Some(_), Some((b, n))) => {
            if foul {
                reasons.push(format!(
                    "{} before {}, but the foul counts",
                    cushions(n),
                    name(b)
                ));
                false
            } else {
                reasons.insert(0, format!("Point: {} before {}", cushions(n), name(b)));
                true
            }
        }
    };
    if foul {
        // The foul is the decisive reason.
        reasons.sort_by_key(|r| !r.starts_with("Foul"));
    }
    Judgement {
        point,
        foul,
        reasons,
    }
}

/// The result of a shot applied to a match.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaromVerdict {
    /// What the rules made of the shot.
    pub judgement: Judgement,
    /// The seat to shoot next.
    pub next: Seat,
    /// Points of seats A and B.
    pub scores: [u32; 2],
    /// The match is over: the winner.
    pub winner: Option<Seat>,
}

/// A three-cushion match.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Match {
    race: u32,
    balls: Vec<BallState>,
    to_move: Seat,
    scores: [u32; 2],
    /// Innings begun (the opening inning is 1).
    innings: u32,
    shots: u32,
    winner: Option<Seat>,
}

impl Match {
    /// A match to `race` points (1 to [`MAX_RACE`]), seat A starting.
    pub fn new(race: u32) -> Result<Match, RuleError> {
        if !(1..=MAX_RACE).contains(&race) {
            return Err(RuleError::NotAllowed(format!(
                "a race must be between 1 and {MAX_RACE} points"
            )));
        }
        Ok(Match::starting(race))
    }

    /// A match to `race` points, brought within 1 to [`MAX_RACE`]: for a race that was
    /// checked before (a room's settings) or read from a record, where a game must start.
    pub fn starting(race: u32) -> Match {
        Match {
            race: race.clamp(1, MAX_RACE),
            balls: start_position(Seat::A),
            to_move: Seat::A,
            scores: [0, 0],
            innings: 1,
            shots: 0,
            winner: None,
        }
    }

    /// The three balls, by number, in scene coordinates.
    pub fn balls(&self) -> &[BallState] {
        &self.balls
    }

    /// The seat to shoot next.
    pub fn to_move(&self) -> Seat {
        self.to_move
    }

    /// Points of seats A and B.
    pub fn scores(&self) -> [u32; 2] {
        self.scores
    }

    /// Innings begun, the opening one counted as 1.
    pub fn innings(&self) -> u32 {
        self.innings
    }

    /// The points that win the match, 1 to [`MAX_RACE`].
    pub fn race(&self) -> u32 {
        self.race
    }

    /// The seat that reached the race; `None` while the match goes on.
    pub fn winner(&self) -> Option<Seat> {
        self.winner
    }

    /// The same match with the balls at `balls` (tests lay out situations with it).
    #[cfg(test)]
    pub(super) fn with_balls(self, balls: Vec<BallState>) -> Match {
        Match { balls, ..self }
    }

    /// The next shot is the match's first, which must hit the red first.
    pub fn is_opening(&self) -> bool {
        self.shots == 0
    }

    /// The ball the shooter's cue ball rests against, if any.
    pub fn frozen(&self) -> Option<u8> {
        let cue = cue_ball(self.to_move);
        let r = crate::physics::Params::for_table(TableKind::Carom).ball_radius;
        let p = self.balls[usize::from(cue)].pos;
        (0..3u8)
            .filter(|&b| b != cue)
            .find(|&b| (self.balls[usize::from(b)].pos - p).length() <= 2.0 * r + CONTACT_GAP)
    }

    /// The physics shot that `strike` on the shooter's ball would be.
    pub fn shot_for(&self, strike: &Strike) -> Shot {
        Shot::new(TableKind::Carom, self.balls.clone())
            .struck(usize::from(cue_ball(self.to_move)), *strike)
    }

    fn check_turn(&self, seat: Seat) -> Result<(), RuleError> {
        if self.winner.is_some() {
            return Err(RuleError::GameOver);
        }
        if seat != self.to_move {
            return Err(RuleError::NotYourTurn);
        }
        Ok(())
    }

    /// Balls in contact: the shooter has the balls set up as at the start, with their own
    /// ball on the starting spot.
    pub fn respot(&mut self, seat: Seat) -> Result<(), RuleError> {
        self.check_turn(seat)?;
        if self.frozen().is_none() {
            return Err(RuleError::WrongPhase(
                "the balls may be set up again only when your ball touches another".into(),
            ));
        }
        self.balls = start_position(seat);
        Ok(())
    }

    /// Simulates `strike` by `seat`, judges it and applies the verdict; returns it with the
    /// shot's whole outcome.
    pub fn shoot(
        &mut self,
        seat: Seat,
        strike: &Strike,
    ) -> Result<(CaromVerdict, Outcome), RuleError> {
        self.check_turn(seat)?;
        let shot = self.shot_for(strike);
        engine::check(&shot).map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let outcome = simulate(&shot).map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let facts = CaromFacts::from_outcome(&outcome, cue_ball(seat));
        Ok((self.apply_facts(seat, &facts, &outcome.finals), outcome))
    }

    /// `seat` ran out of time: a foul that ends the inning, the balls as they lie.
    pub fn time_out(&mut self, seat: Seat) -> Result<(), RuleError> {
        self.check_turn(seat)?;
        self.to_move = seat.other();
        self.innings += 1;
        Ok(())
    }

    /// Applies a shot's facts and the balls' resting states (`finals`).
    pub fn apply_facts(
        &mut self,
        seat: Seat,
        facts: &CaromFacts,
        finals: &[BallState],
    ) -> CaromVerdict {
        let cue = cue_ball(seat);
        let judgement = judge(facts, cue, self.frozen(), self.shots == 0);
        self.shots += 1;
        self.balls = finals.to_vec();
        self.spot_jumped(&facts.off_table);
        let i = if seat == Seat::A { 0 } else { 1 };
        if judgement.point {
            self.scores[i] += 1;
            if self.scores[i] >= self.race {
                self.winner = Some(seat);
            }
        } else {
            self.to_move = seat.other();
            self.innings += 1;
        }
        CaromVerdict {
            judgement,
            next: self.to_move,
            scores: self.scores,
            winner: self.winner,
        }
    }

    /// Puts the balls that left the table back: each on its own spot, or the next free one.
    fn spot_jumped(&mut self, off: &[u8]) {
        let r = crate::physics::Params::for_table(TableKind::Carom).ball_radius;
        for &b in off {
            if usize::from(b) >= self.balls.len() {
                continue;
            }
            let order = if b == RED {
                [top_spot(), bottom_spot(), centre_spot()]
            } else {
                [bottom_spot(), top_spot(), centre_spot()]
            };
            let free = |p: DVec2, balls: &[BallState]| {
                balls.iter().enumerate().all(|(k, s)| {
                    k == usize::from(b)
                        || s.motion == MotionState::Pocketed
                        || (s.pos - p).length() > 2.0 * r
                })
            };
            let spot = order
                .into_iter()
                .find(|&p| free(p, &self.balls))
                .unwrap_or(order[2]);
            self.balls[usize::from(b)] = BallState::at_rest(spot);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Touch::{Ball, Cushion};

    fn facts(touches: &[Touch]) -> CaromFacts {
        CaromFacts {
            touches: touches.to_vec(),
            off_table: Vec::new(),
        }
    }

    /// The white's judgement of an ordinary shot: not the opening, not frozen to a ball.
    fn white_plays(touches: &[Touch]) -> Judgement {
        judge(&facts(touches), WHITE, None, false)
    }

    #[test]
    fn three_cushions_before_the_second_ball_score() {
        let j = white_plays(&[Ball(RED), Cushion, Cushion, Cushion, Ball(YELLOW)]);
        assert!(j.point && !j.foul);
        assert_eq!(j.reasons[0], "Point: 3 cushions before the yellow");
        // Cushions before the first ball count too.
        let j = white_plays(&[Cushion, Cushion, Ball(YELLOW), Cushion, Ball(RED)]);
        assert!(j.point, "{:?}", j.reasons);
    }

    #[test]
    fn two_cushions_are_not_enough() {
        let j = white_plays(&[Ball(YELLOW), Cushion, Cushion, Ball(RED), Cushion]);
        assert!(!j.point);
        assert_eq!(j.reasons, vec!["2 cushions before the red: no point"]);
    }

    #[test]
    fn cushions_after_the_second_ball_do_not_count() {
        let j = white_plays(&[Ball(YELLOW), Cushion, Ball(RED), Cushion, Cushion, Cushion]);
        assert!(!j.point);
        assert_eq!(j.reasons, vec!["1 cushion before the red: no point"]);
    }

    #[test]
    fn a_miss_names_the_ball_missed() {
        let j = judge(
            &facts(&[Ball(RED), Cushion, Cushion, Cushion]),
            YELLOW,
            None,
            false,
        );
        assert_eq!(j.reasons, vec!["Missed the white: no point"]);
        let j = judge(&facts(&[Cushion]), YELLOW, None, false);
        assert_eq!(j.reasons, vec!["Missed both balls: no point"]);
        // Touching the same ball twice is still one ball.
        let j = white_plays(&[Ball(RED), Cushion, Ball(RED)]);
        assert_eq!(j.reasons, vec!["Missed the yellow: no point"]);
    }

    #[test]
    fn the_opening_shot_must_hit_the_red_first() {
        let j = judge(
            &facts(&[Ball(YELLOW), Cushion, Cushion, Cushion, Ball(RED)]),
            WHITE,
            None,
            true,
        );
        assert!(!j.point && j.foul);
        assert!(j.reasons[0].contains("opening shot"), "{:?}", j.reasons);
    }

    #[test]
    fn playing_into_a_touching_ball_is_a_foul() {
        let j = judge(
            &facts(&[Ball(RED), Cushion, Cushion, Cushion, Ball(YELLOW)]),
            WHITE,
            Some(RED),
            false,
        );
        assert!(!j.point && j.foul);
        assert_eq!(
            j.reasons[0],
            "Foul: played into the red, which it touched: no point"
        );
        // Playing away from it is fine.
        let j = judge(
            &facts(&[Cushion, Cushion, Cushion, Ball(YELLOW), Ball(RED)]),
            WHITE,
            Some(RED),
            false,
        );
        assert!(j.point);
    }

    #[test]
    fn a_point_continues_the_inning_and_a_miss_ends_it() {
        let mut m = Match::new(2).expect("race");
        let balls = m.balls().to_vec();
        let point = facts(&[Ball(RED), Cushion, Cushion, Cushion, Ball(YELLOW)]);
        let v = m.apply_facts(Seat::A, &point, &balls);
        assert_eq!((v.next, v.scores, v.winner), (Seat::A, [1, 0], None));
        let miss = facts(&[Ball(RED), Cushion]);
        let v = m.apply_facts(Seat::A, &miss, &balls);
        assert_eq!((v.next, v.scores), (Seat::B, [1, 0]));
        assert_eq!(m.innings(), 2);
        // Seat B plays the yellow: its point is on the red and the white.
        let point_b = facts(&[Ball(RED), Cushion, Cushion, Cushion, Ball(WHITE)]);
        let v = m.apply_facts(Seat::B, &point_b, &balls);
        let v2 = m.apply_facts(Seat::B, &point_b, &balls);
        assert_eq!(v.scores, [1, 1]);
        assert_eq!((v2.scores, v2.winner), ([1, 2], Some(Seat::B)));
        assert_eq!(
            m.shoot(Seat::B, &Strike::at_angle(1.0, 90.0, DVec2::ZERO)),
            Err(RuleError::GameOver)
        );
    }

    #[test]
    fn races_are_bounded_and_turns_are_kept() {
        assert!(Match::new(0).is_err());
        assert!(Match::new(MAX_RACE + 1).is_err());
        let mut m = Match::new(DEFAULT_RACE).expect("race");
        let s = Strike::at_angle(2.0, 90.0, DVec2::ZERO);
        assert_eq!(m.shoot(Seat::B, &s), Err(RuleError::NotYourTurn));
        let bad = Strike::at_angle(f64::NAN, 90.0, DVec2::ZERO);
        let before = m.clone();
        assert!(m.shoot(Seat::A, &bad).is_err());
        assert_eq!(m, before, "a refused shot changes nothing");
    }

    #[test]
    fn the_start_position_is_umb_and_the_opening_is_judged() {
        let balls = start_position(Seat::A);
        assert_eq!(balls[usize::from(RED)].pos, top_spot());
        assert_eq!(balls[usize::from(YELLOW)].pos, bottom_spot());
        let mut m = Match::new(DEFAULT_RACE).expect("race");
        // Straight at the red and back: a real simulated shot, judged from its events.
        let red = top_spot() - balls[usize::from(WHITE)].pos;
        let strike = Strike {
            speed: 3.0,
            dir: red.normalize(),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let (v, _) = m.shoot(Seat::A, &strike).expect("valid shot");
        assert!(!v.judgement.reasons.is_empty());
        assert!(!v.judgement.foul, "{:?}", v.judgement.reasons);
        assert!(m
            .balls()
            .iter()
            .all(|b| b.motion == MotionState::Stationary));
    }

    #[test]
    fn touching_balls_may_be_set_up_again() {
        let mut m = Match::new(DEFAULT_RACE).expect("race");
        assert!(m.respot(Seat::A).is_err(), "nothing touches at the start");
        let r = crate::physics::Params::for_table(TableKind::Carom).ball_radius;
        let mut balls = m.balls().to_vec();
        balls[usize::from(WHITE)] =
            BallState::at_rest(balls[usize::from(RED)].pos - DVec2::new(2.0 * r, 0.0));
        m.balls = balls;
        assert_eq!(m.frozen(), Some(RED));
        m.respot(Seat::A).expect("respot");
        assert_eq!(m.balls(), start_position(Seat::A).as_slice());
    }

    #[test]
    fn jumped_balls_are_a_foul_and_are_spotted() {
        let mut m = Match::new(DEFAULT_RACE).expect("race");
        let mut finals = m.balls().to_vec();
        // The yellow left the table; the red rests on the bottom spot, the yellow's own.
        finals[usize::from(RED)] = BallState::at_rest(bottom_spot());
        finals[usize::from(YELLOW)] = BallState::at_rest(DVec2::new(0.3, 0.3));
        let f = CaromFacts {
            touches: vec![Ball(RED), Cushion, Cushion, Cushion, Ball(YELLOW)],
            off_table: vec![YELLOW],
        };
        let v = m.apply_facts(Seat::A, &f, &finals);
        assert!(v.judgement.foul && !v.judgement.point);
        assert_eq!(
            v.judgement.reasons[0],
            "Foul: the yellow left the table: no point"
        );
        assert_eq!(v.next, Seat::B);
        assert_eq!(m.balls()[usize::from(YELLOW)].pos, top_spot());
    }
}
