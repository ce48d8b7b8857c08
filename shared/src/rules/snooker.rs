//! Snooker (WPBSA rules) as a [`Game`]: frames of 15 reds, or 10 or 6 for short games, in a
//! match of the best of N frames. The table's landmarks, the rack, re-spotting and the sight
//! tests are in `snooker/table.rs`; the state between strokes and the judgement of a stroke
//! in `snooker/frame.rs`; this file moves the game on from a judgement.
//!
//! Ball indices: 0 = cue ball, 1 to 15 = the reds (unused reds of a short game are off the
//! table from the start), 16 to 21 = yellow, green, brown, blue, pink, black.
//!
//! What is implemented, and the choices made where a game needs a definite answer:
//! - The cue ball is in hand in the D ([`InHand::D`]) to break off and after an in-off.
//! - The ball on: a red; after a red, a colour, nominated with [`Choice::Nominate`] before
//!   the stroke (without a nomination, the colour hit first is taken as nominated, and any
//!   foul costs 7, "a foul before nominating"); with the reds gone, the colours in order.
//!   Several reds in one stroke all score. Colours potted while reds remain (and the colour
//!   after the last red) are re-spotted: own spot, else the highest free, else as near the
//!   own spot as possible towards the top cushion.
//! - Fouls and their values, the highest of the stroke, 4 to 7: the cue ball hitting no ball,
//!   a ball not on hit first, two balls hit at once (but two reds, or the free ball with the
//!   ball on), a ball not on potted, an in-off, a ball forced off the table, a push stroke
//!   (the cue ball driven into a ball it touched), a foul before nominating (7). Jump shots
//!   and playing with a ball other than the cue ball cannot happen here (the cue strikes
//!   the cue ball only) or are not judged (a jump over a ball).
//! - After a foul the next player plays on ([`Choice::AcceptTable`]) or has the offender play
//!   again ([`Choice::OffenderPlaysAgain`]); after a foul and a miss also
//!   [`Choice::ReplaceBalls`]: the balls go back to where they were and the offender plays
//!   again. A miss is called when a foul failed to hit a ball on first, unless the striker
//!   needed snookers. A third miss in a row from replaced positions with a clear view of a
//!   ball on (a straight path to a full-ball contact that neither a ball not on nor a jaw
//!   blocks: the WPBSA miss rule asks that "central, full-ball contact is available") forfeits
//!   the frame; the second is warned.
//! - A free ball when the next player plays on and is snookered: any other ball may be
//!   nominated and acts as the ball on, and is re-spotted when potted. Snookered follows
//!   WPBSA Section 2 Rule 16 (the official text is reposted at
//!   chinadaily.com.cn/sports/2007-03/23/content_835320_3.htm): no ball on can be hit at
//!   both extreme edges by a straight stroke free of obstruction by a ball not on. The cue
//!   ball cannot be snookered by a cushion (16(e)): on a stroke where the curved face of a
//!   pocket jaw is met before any ball not on, the cue ball is angled, not snookered, and no
//!   free ball is given. In hand, the cue ball is snookered only if it is so from every
//!   position in the D where it may be placed (16(a)); the D is searched exactly but for
//!   views open only from patches too small to hold a disc a tenth of a millimetre in radius.
//! - Touching ball: playing away from a touching ball that is on is no foul.
//! - The frame ends on the last black potted, or, with only the black left, on the first
//!   foul, if the scores then differ; tied, the black is re-spotted, the cue ball in hand
//!   for the player drawn by lot, and the next score or foul decides. [`Command::Concede`](super::Command::Concede)
//!   concedes the frame (at any time: there is no referee to judge it unsporting); the match
//!   is won by the first to win more than half its frames.
//! - Out of time on a stroke: a foul of the ball on's value (at least 4); the next player
//!   chooses as after any foul.
//! - Leaving the cue ball snookered behind the free ball is a foul (WPBSA Section 3 Rule 10).
//! - Not judged: the six-red "five misses" variant rule.

pub mod frame;
pub mod table;

use crate::physics::{simulate, BallState, Strike};

use super::{
    off_table, Choice, Game, InHand, Next, Pending, Phase, RuleError, Seat, ShotFacts, ShotReport,
    Variant, Verdict,
};
use frame::{AfterFoul, Foul, Judgement, Restore, Snooker, Stroke};
use table::{ball_name, is_colour, BLACK, CUE};

/// The most frames a match may have.
pub const MAX_BEST_OF: u8 = 35;
/// The red counts a frame may be played with.
pub const RED_COUNTS: [u8; 3] = [6, 10, 15];

impl Game {
    /// The snooker match, in a snooker game.
    pub fn snooker(&self) -> Option<&Snooker> {
        self.snooker.as_ref()
    }

    /// The match for `variant`, if it is snooker.
    pub(super) fn start_snooker(variant: Variant) -> Option<Snooker> {
        match variant {
            Variant::Snooker { reds, best_of } => Some(Snooker::new(reds, best_of)),
            _ => None,
        }
    }

    /// The balls a snooker striker must hit first.
    pub(super) fn snooker_balls_on(&self) -> Vec<u8> {
        match &self.snooker {
            Some(m) => m.balls_on(&self.balls),
            None => Vec::new(),
        }
    }

    /// Plays and judges one snooker stroke.
    pub(super) fn snooker_shot(
        &mut self,
        seat: Seat,
        strike: &Strike,
    ) -> Result<Verdict, RuleError> {
        let outcome =
            simulate(&self.shot_for(strike)).map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let Some(mut m) = self.snooker.take() else {
            return Err(RuleError::NotAllowed("this game is not snooker".into()));
        };
        let stroke = Stroke::read(&outcome);
        let before = self.balls.clone();
        let mut judgement = frame::judge(&m, &before, &stroke, frame::touching(&before));
        let mut finals = outcome.finals.clone();
        for &b in &stroke.off_table {
            if let Some(ball) = finals.get_mut(usize::from(b)) {
                *ball = off_table();
            }
        }
        self.balls = finals;
        // A foul only the balls at rest show.
        judgement.fouls.extend(frame::snookered_behind_free_ball(
            &m,
            &before,
            &self.balls,
            &judgement,
        ));
        self.stalemate = [false; 2];
        let facts = ShotFacts::from_outcome(&outcome, self.table());
        let report = ShotReport {
            hash: outcome.hash(),
            events: outcome.events.clone(),
            pocketed: facts.pocketed,
        };
        let (next, reasons, foul) = self.judged(&mut m, seat, &judgement, before);
        self.snooker = Some(m);
        let mut verdict = self.enact(next, reasons, foul, Some(report));
        verdict.outcome = Some(outcome);
        Ok(verdict)
    }

    /// Moves the match on from the judgement of a stroke by `seat` played from `before`
    /// (the balls now lie as it left them): what comes next, the reasons, and whether it was
    /// a foul.
    fn judged(
        &mut self,
        m: &mut Snooker,
        seat: Seat,
        judgement: &Judgement,
        before: Vec<BallState>,
    ) -> (Next, Vec<String>, bool) {
        let mut reasons = Vec::new();
        for &c in &judgement.respot {
            let how = table::respot(&mut self.balls, c);
            reasons.push(format!(
                "{} is re-spotted {}",
                capital(&ball_name(c)),
                how.describe()
            ));
        }
        if judgement.fouls.is_empty() {
            let next = self.fair_stroke(m, seat, judgement, &before, &mut reasons);
            (next, reasons, false)
        } else {
            let next = self.foul_stroke(
                m,
                seat,
                &judgement.fouls,
                Some(judgement),
                before,
                &mut reasons,
            );
            (next, reasons, true)
        }
    }

    fn fair_stroke(
        &mut self,
        m: &mut Snooker,
        seat: Seat,
        judgement: &Judgement,
        before: &[BallState],
        reasons: &mut Vec<String>,
    ) -> Next {
        let on = m.ball_on(before);
        let was_free = m.free_ball && m.nominated.is_some();
        m.nominated = None;
        m.free_ball = false;
        m.misses = 0;
        m.replayed = false;
        if judgement.points == 0 {
            let ended = m.break_points;
            m.break_points = 0;
            m.on_colour = false;
            let mut words = vec![if ended > 0 {
                format!("{seat}'s break ends at {ended}")
            } else {
                format!("{seat} does not score")
            }];
            words.push(score_line(m));
            words.push(format!("{} to play", seat.other()));
            reasons.splice(0..0, words);
            return self.snooker_next(m, seat.other());
        }
        m.scores[seat.index()] += judgement.points;
        m.break_points += judgement.points;
        let potted: Vec<String> = judgement.scored.iter().map(|&b| ball_name(b)).collect();
        let free = if was_free { " (free ball)" } else { "" };
        reasons.insert(
            0,
            format!(
                "{seat} pots {}{free}: {} (break {})",
                potted.join(" and "),
                judgement.points,
                m.break_points
            ),
        );
        m.on_colour = matches!(on, frame::BallOn::Red);
        let black_down = matches!(on, frame::BallOn::Sequence(BLACK));
        if black_down || m.respotted_black {
            reasons.push(score_line(m));
            return self.frame_over(m, reasons);
        }
        reasons.push(score_line(m));
        self.snooker_next(m, seat)
    }

    /// A foul by `seat`: the penalty to the opponent, then the end of the frame, the miss
    /// rule or the choice after a foul.
    fn foul_stroke(
        &mut self,
        m: &mut Snooker,
        seat: Seat,
        fouls: &[Foul],
        judgement: Option<&Judgement>,
        before: Vec<BallState>,
        reasons: &mut Vec<String>,
    ) -> Next {
        let opponent = seat.other();
        let penalty = fouls.first().map_or(frame::MIN_PENALTY, |f| f.value);
        let on_before = m.balls_on(&before);
        let miss =
            judgement.is_some_and(|j| j.missed_ball_on) && !m.snookers_required(seat, &before);
        let clear = frame::clear_view(&before, &on_before);
        let only_black = frame::reds_left(&before) == 0
            && !m.on_colour
            && frame::lowest_colour(&before) == Some(BLACK);
        let was_on_colour = m.on_colour;
        m.scores[opponent.index()] += penalty;
        m.break_points = 0;
        m.on_colour = false;
        m.nominated = None;
        m.free_ball = false;
        let misses = match (miss, m.replayed) {
            (true, true) => m.misses.saturating_add(1),
            (true, false) => 1,
            _ => 0,
        };
        m.misses = misses;
        m.replayed = false;
        let head = if miss { "Foul and a miss" } else { "Foul" };
        let what = fouls.first().map_or("a foul".into(), |f| f.what.clone());
        let mut words = vec![format!("{head}: {what}, {penalty} to {opponent}")];
        words.extend(fouls.iter().skip(1).map(|f| format!("Also: {}", f.what)));
        words.push(score_line(m));
        reasons.splice(0..0, words);
        if only_black || m.respotted_black {
            return self.frame_over(m, reasons);
        }
        if miss && clear && misses >= frame::MISSES_TO_FORFEIT {
            let reason = format!(
                "{seat} missed a ball on {misses} times in a row from a clear view: the frame goes to {opponent}"
            );
            reasons.push(reason);
            return self.frame_won(m, opponent, reasons);
        }
        if miss && clear && misses + 1 == frame::MISSES_TO_FORFEIT {
            reasons.push(format!(
                "Warning: another miss from here forfeits the frame for {seat}"
            ));
        }
        let mut options = vec![Choice::AcceptTable, Choice::OffenderPlaysAgain];
        let restore = miss.then(|| {
            options.push(Choice::ReplaceBalls);
            Restore {
                balls: before,
                on_colour: was_on_colour,
            }
        });
        m.after_foul = Some(AfterFoul {
            offender: seat,
            restore,
        });
        Next::Decide {
            seat: opponent,
            options,
            pending: Pending::SnookerFoul,
        }
    }

    /// The next stroke by `seat` from the table as it lies.
    fn snooker_next(&self, m: &Snooker, seat: Seat) -> Next {
        let cue_off = self.balls.first().is_none_or(super::is_off_table);
        Next::Shoot {
            seat,
            in_hand: cue_off.then_some(InHand::D),
            options: nominations(m, &self.balls),
        }
    }

    /// The frame ended on the black (or a foul with only the black left): the higher score
    /// wins it; tied, the black is re-spotted.
    fn frame_over(&mut self, m: &mut Snooker, reasons: &mut Vec<String>) -> Next {
        let [a, b] = m.scores;
        if a == b {
            m.respotted_black = true;
            m.on_colour = false;
            table::respot(&mut self.balls, BLACK);
            if let Some(cue) = self.balls.get_mut(usize::from(CUE)) {
                *cue = off_table();
            }
            let seat = if table::draw_lots(self.seed ^ u64::from(self.racks)) {
                Seat::A
            } else {
                Seat::B
            };
            reasons.push(format!(
                "Scores level at {a}: the black is re-spotted; {seat} is drawn to play, cue ball in hand in the D"
            ));
            return Next::Shoot {
                seat,
                in_hand: Some(InHand::D),
                options: Vec::new(),
            };
        }
        let winner = if a > b { Seat::A } else { Seat::B };
        reasons.push(format!("{winner} wins the frame {}-{}", a.max(b), a.min(b)));
        self.frame_won(m, winner, reasons)
    }

    /// `winner` takes the frame: the match ends, or the next frame is racked.
    fn frame_won(&mut self, m: &mut Snooker, winner: Seat, reasons: &mut Vec<String>) -> Next {
        m.frames[winner.index()] += 1;
        let [fa, fb] = m.frames;
        if m.frames[winner.index()] >= m.frames_to_win() {
            let reason = if m.best_of == 1 {
                format!("{winner} wins")
            } else {
                format!("{winner} wins the match {}-{}", fa.max(fb), fa.min(fb))
            };
            reasons.push(reason.clone());
            return Next::Over {
                winner: Some(winner),
                reason,
            };
        }
        let breaker = m.starter.other();
        reasons.push(format!(
            "Frames: {} {fa}, {} {fb}; {breaker} breaks off the next frame",
            Seat::A,
            Seat::B
        ));
        Next::Rerack { breaker }
    }

    /// Whether a snooker decision is acceptable now, with the reason if not.
    pub(super) fn check_snooker_choice(&self, choice: Choice) -> Result<(), RuleError> {
        let Some(m) = &self.snooker else {
            return Err(RuleError::NotAllowed("this game is not snooker".into()));
        };
        let options = match &self.phase {
            Phase::Deciding { options } | Phase::Shooting { options, .. } => options,
            Phase::Over { .. } => return Err(RuleError::GameOver),
        };
        match choice {
            Choice::Nominate(ball) => check_nomination(m, &self.balls, &self.phase, ball),
            Choice::ReplaceBalls if !options.contains(&choice) => Err(RuleError::InvalidChoice(
                "the balls are replaced only after a foul and a miss".into(),
            )),
            _ if options.contains(&choice) => Ok(()),
            _ => Err(RuleError::InvalidChoice(format!("you cannot {choice} now"))),
        }
    }

    /// Applies a snooker decision (checked).
    pub(super) fn snooker_decide(&mut self, seat: Seat, choice: Choice) -> Verdict {
        let Some(mut m) = self.snooker.take() else {
            return self.verdict(Vec::new());
        };
        if let Choice::Nominate(ball) = choice {
            m.nominated = Some(ball);
            let words = if m.free_ball {
                format!("Free ball: {} is nominated", ball_name(ball))
            } else {
                format!("{seat} nominates {}", ball_name(ball))
            };
            self.snooker = Some(m);
            return self.verdict(vec![words]);
        }
        let mut reasons = vec![format!("{seat} chooses to {choice}")];
        let after = m.after_foul.take();
        let offender = after.as_ref().map_or(seat.other(), |a| a.offender);
        m.misses = if choice == Choice::ReplaceBalls {
            m.misses
        } else {
            0
        };
        let next = match choice {
            Choice::ReplaceBalls => {
                if let Some(restore) = after.and_then(|a| a.restore) {
                    self.balls = restore.balls;
                    m.on_colour = restore.on_colour;
                }
                m.replayed = true;
                reasons.push(format!("The balls are replaced; {offender} plays again"));
                self.snooker_next(&m, offender)
            }
            Choice::OffenderPlaysAgain => {
                reasons.push(format!("{offender} plays again"));
                self.snooker_next(&m, offender)
            }
            _ => {
                let on = m.balls_on(&self.balls);
                if frame::snookered(&self.balls, &on) {
                    m.free_ball = true;
                    reasons.push(format!(
                        "Free ball: {seat} is snookered and may nominate any ball as the ball on"
                    ));
                }
                self.snooker_next(&m, seat)
            }
        };
        self.snooker = Some(m);
        self.enact(next, reasons, false, None)
    }

    /// `seat` ran out of time on a stroke: a foul of the ball on's value.
    pub(super) fn snooker_time_out(&mut self, seat: Seat) -> Verdict {
        let Some(mut m) = self.snooker.take() else {
            return self.verdict(Vec::new());
        };
        let on = m.balls_on(&self.balls);
        let value = on
            .iter()
            .map(|&b| table::value(b))
            .max()
            .unwrap_or(0)
            .clamp(frame::MIN_PENALTY, frame::MAX_PENALTY);
        let fouls = [Foul {
            value,
            what: format!("{seat} ran out of time"),
        }];
        let before = self.balls.clone();
        let mut reasons = Vec::new();
        let next = self.foul_stroke(&mut m, seat, &fouls, None, before, &mut reasons);
        self.snooker = Some(m);
        self.enact(next, reasons, true, None)
    }

    /// `seat` concedes the frame.
    pub(super) fn snooker_concede(&mut self, seat: Seat) -> Verdict {
        let Some(mut m) = self.snooker.take() else {
            return self.verdict(Vec::new());
        };
        let mut reasons = vec![format!("{seat} concedes the frame"), score_line(&m)];
        let next = self.frame_won(&mut m, seat.other(), &mut reasons);
        self.snooker = Some(m);
        self.enact(next, reasons, false, None)
    }
}

/// The nominations open before a stroke: a colour after a red, any other ball with a free
/// ball.
fn nominations(m: &Snooker, balls: &[BallState]) -> Vec<Choice> {
    if m.free_ball {
        let on = m.balls_on(balls);
        return (1..table::BALL_COUNT as u8)
            .filter(|b| frame::on_table(balls, *b) && !on.contains(b))
            .map(Choice::Nominate)
            .collect();
    }
    if m.on_colour {
        return table::COLOURS
            .into_iter()
            .filter(|&c| frame::on_table(balls, c))
            .map(Choice::Nominate)
            .collect();
    }
    Vec::new()
}

/// Why `ball` cannot be nominated now, if it cannot.
fn check_nomination(
    m: &Snooker,
    balls: &[BallState],
    phase: &Phase,
    ball: u8,
) -> Result<(), RuleError> {
    let refuse = |why: String| Err(RuleError::InvalidChoice(why));
    if !matches!(phase, Phase::Shooting { .. }) {
        return refuse("a ball is nominated before a stroke, not now".into());
    }
    if usize::from(ball) >= table::BALL_COUNT || ball == CUE {
        return refuse(format!("there is no ball {ball} to nominate"));
    }
    if !frame::on_table(balls, ball) {
        return refuse(format!("{} is not on the table", ball_name(ball)));
    }
    if m.free_ball {
        if m.balls_on(balls).contains(&ball) {
            return refuse(format!(
                "{} is on already: a free ball is another ball",
                ball_name(ball)
            ));
        }
        return Ok(());
    }
    if m.on_colour {
        if !is_colour(ball) {
            return refuse(format!(
                "{} is not a colour: nominate a colour",
                ball_name(ball)
            ));
        }
        return Ok(());
    }
    refuse(format!(
        "no free ball: the cue ball is not snookered after a foul, and {} cannot be nominated",
        ball_name(ball)
    ))
}

/// "Score: Player A 12, Player B 4".
fn score_line(m: &Snooker) -> String {
    let [a, b] = m.scores;
    format!("Score: {} {a}, {} {b}", Seat::A, Seat::B)
}

/// "The blue" from "the blue".
fn capital(s: &str) -> String {
    super::capitalise(s)
}

/// Positions for the tests of other modules of the crate (the computer player's).
#[cfg(test)]
impl Game {
    /// This snooker game with `balls` laid out, its match changed by `change`, and the seat
    /// to move shooting from where the cue ball lies, offered the nominations that follow.
    pub(crate) fn snooker_laid_out(
        mut self,
        balls: Vec<BallState>,
        change: impl FnOnce(&mut Snooker),
    ) -> Game {
        self.balls = balls;
        if let Some(m) = &mut self.snooker {
            change(m);
            self.phase = Phase::Shooting {
                in_hand: None,
                options: nominations(m, &self.balls),
                push_out: false,
            };
        }
        self
    }
}

#[cfg(test)]
mod tests;
