//! Three-cushion billiards as a [`Game`]: the generic game (seats, turns, choices, verdicts,
//! records) around the match rules of [`three_cushion`], which alone judge a shot.
//!
//! What the game adds to the match:
//! - The table is always the carom table, whatever the settings named, and no ball is ever
//!   in hand: the balls are played as they lie.
//! - When the shooter's ball rests against another ball, the shot's options offer
//!   [`Choice::Respot`] (the balls set up as at the start, art. 27); the shooter may also
//!   play on, away from the ball it touches.
//! - The shot clock running out ends the inning, without a point.
//! - Nothing is called and there is no stalemate: a match ends at the race or by conceding.
//!
//! The match's balls are the source: after each change the game copies them into its own
//! list, which every generic reader (the client, hashes, records) sees.

use super::three_cushion::{self, Match};
use super::{Choice, Game, Next, RuleError, Seat, ShotReport, Variant, Verdict};
use crate::physics::Strike;

impl Game {
    /// The three-cushion match, in a three-cushion game.
    pub fn carom(&self) -> Option<&Match> {
        self.carom.as_ref()
    }

    /// The match for `variant`'s first rack, if it is three-cushion.
    pub(super) fn start_carom(variant: Variant) -> Option<Match> {
        match variant {
            Variant::ThreeCushion { race } => Some(Match::starting(race)),
            _ => None,
        }
    }

    /// Plays and judges a three-cushion shot.
    pub(super) fn carom_shot(&mut self, seat: Seat, strike: &Strike) -> Result<Verdict, RuleError> {
        let m = self.carom.as_mut().ok_or(RuleError::NotAllowed(
            "this game is not three-cushion".into(),
        ))?;
        let (carom, outcome) = m.shoot(seat, strike)?;
        let race = m.race();
        self.balls = m.balls().to_vec();
        let mut reasons = carom.judgement.reasons;
        reasons.push(self.score_line());
        let next = match carom.winner {
            Some(winner) => {
                let points = if race == 1 { "point" } else { "points" };
                let reason = format!("{winner} reaches {race} {points} and wins");
                reasons.push(reason.clone());
                Next::Over {
                    winner: Some(winner),
                    reason,
                }
            }
            None => {
                if carom.next != seat {
                    reasons.push(format!("{} to play", carom.next));
                }
                Next::Shoot {
                    seat: carom.next,
                    in_hand: None,
                    options: self.carom_options(),
                }
            }
        };
        let report = ShotReport {
            hash: outcome.hash(),
            events: outcome.events.clone(),
            pocketed: Vec::new(),
        };
        let mut verdict = self.enact(next, reasons, carom.judgement.foul, Some(report));
        verdict.outcome = Some(outcome);
        Ok(verdict)
    }

    /// The shooter has the touching balls set up as at the start.
    pub(super) fn carom_respot(&mut self, seat: Seat, mut reasons: Vec<String>) -> Verdict {
        if let Some(m) = self.carom.as_mut() {
            if m.respot(seat).is_ok() {
                self.balls = m.balls().to_vec();
                reasons.push("The balls are set up as at the start".into());
            }
        }
        let next = Next::Shoot {
            seat,
            in_hand: None,
            options: self.carom_options(),
        };
        self.enact(next, reasons, false, None)
    }

    /// `seat` ran out of time: the inning ends.
    pub(super) fn carom_time_out(&mut self, seat: Seat) -> Verdict {
        let opponent = seat.other();
        if let Some(m) = self.carom.as_mut() {
            // The game checked the turn; a refusal here would leave the match unchanged.
            let _ = m.time_out(seat);
        }
        let reasons = vec![
            format!("Foul: {seat} ran out of time: no point"),
            self.score_line(),
            format!("{opponent} to play"),
        ];
        let next = Next::Shoot {
            seat: opponent,
            in_hand: None,
            options: self.carom_options(),
        };
        self.enact(next, reasons, true, None)
    }

    /// The balls the shooter may hit first: the red on the opening shot, else either object
    /// ball but the one the shooter's ball touches.
    pub(super) fn carom_first_balls(&self) -> Vec<u8> {
        let Some(m) = &self.carom else {
            return Vec::new();
        };
        if m.is_opening() {
            return vec![three_cushion::RED];
        }
        let cue = three_cushion::cue_ball(m.to_move());
        [
            three_cushion::WHITE,
            three_cushion::YELLOW,
            three_cushion::RED,
        ]
        .into_iter()
        .filter(|&b| b != cue && Some(b) != m.frozen())
        .collect()
    }

    /// The declarations open before a shot: the respot when the shooter's ball touches
    /// another.
    fn carom_options(&self) -> Vec<Choice> {
        match &self.carom {
            Some(m) if m.frozen().is_some() => vec![Choice::Respot],
            _ => Vec::new(),
        }
    }

    /// "Score: Player A 3, Player B 1 (race to 15)".
    fn score_line(&self) -> String {
        match &self.carom {
            Some(m) => {
                let [a, b] = m.scores();
                format!(
                    "Score: {} {a}, {} {b} (race to {})",
                    Seat::A,
                    Seat::B,
                    m.race()
                )
            }
            None => String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::three_cushion::{bottom_spot, top_spot, CaromFacts, RED, WHITE, YELLOW};
    use super::*;
    use crate::physics::{simulate, BallState, MotionState, Params, TableKind};
    use crate::replay::GameRecord;
    use crate::rules::{Command, Phase, Settings};

    fn game(race: u32) -> Game {
        Game::new(Variant::ThreeCushion { race }, Settings::offline(), 7)
    }

    fn shot(strike: Strike) -> Command {
        Command::Shot { strike, call: None }
    }

    /// Strikes on the shooter's ball, fanned around the direction of `target`.
    fn fan(game: &Game, target: u8) -> impl Iterator<Item = Strike> {
        let from = game.balls()[game.cue_ball()].pos;
        let to = game.balls()[usize::from(target)].pos - from;
        let base = libm::atan2(to.y, to.x);
        // Quarter-degree steps either side of the line to the target.
        let step = 0.25 * std::f64::consts::PI / 180.0;
        (-40..=40).flat_map(move |k| {
            let a = base + step * f64::from(k);
            [3.0, 4.0, 5.0].into_iter().flat_map(move |speed| {
                [-0.4, 0.0, 0.4].into_iter().map(move |side| Strike {
                    speed,
                    dir: DVec2::new(libm::cos(a), libm::sin(a)),
                    tip: DVec2::new(side, 0.0),
                    elevation_deg: 0.0,
                })
            })
        })
    }

    /// Does `strike` score from `game`, as the match rules judge the engine's events?
    fn scores(game: &Game, strike: &Strike) -> bool {
        let Some(m) = game.carom() else { return false };
        let cue = three_cushion::cue_ball(m.to_move());
        simulate(&game.shot_for(strike)).is_ok_and(|o| {
            let facts = CaromFacts::from_outcome(&o, cue);
            three_cushion::judge(&facts, cue, m.frozen(), m.is_opening()).point
        })
    }

    /// A scoring opening shot: the engine finds some from the UMB start.
    fn opening_point(game: &Game) -> Strike {
        let found = fan(game, RED).find(|s| scores(game, s));
        found.expect("some opening shot around the red scores")
    }

    #[test]
    fn the_game_starts_umb_on_the_carom_table_with_nothing_in_hand() {
        let g = game(15);
        assert_eq!(
            g.table(),
            TableKind::Carom,
            "the settings named a 9-foot table"
        );
        assert_eq!(g.params(), Params::for_table(TableKind::Carom));
        assert_eq!(g.balls(), three_cushion::start_position(Seat::A).as_slice());
        let (white, yellow) = (g.balls()[0].pos, g.balls()[1].pos);
        assert_eq!(yellow, bottom_spot());
        assert_eq!(white, bottom_spot() + DVec2::new(0.1825, 0.0));
        assert_eq!(g.balls()[2].pos, top_spot());
        assert_eq!(
            g.phase(),
            &Phase::Shooting {
                in_hand: None,
                options: Vec::new(),
                push_out: false
            }
        );
        assert!(!g.needs_call() && !g.is_break());
        assert_eq!((g.cue_ball(), g.legal_first_balls()), (0, vec![RED]));
        assert!(g.legal_cue_placement([0.5, 0.5]).is_err());
        assert!(g
            .check(Seat::A, &Command::PlaceCueBall { pos: [0.5, 0.5] })
            .is_err());
        assert!(g.check(Seat::A, &Command::ProposeStalemate).is_err());
        // A call names a pocket, and the carom table has none.
        let call = Command::Shot {
            strike: Strike::at_angle(3.0, 90.0, DVec2::ZERO),
            call: Some(0),
        };
        assert!(g.check(Seat::A, &call).is_err());
    }

    #[test]
    fn a_point_scores_and_the_shooter_plays_on() {
        let mut g = game(15);
        let strike = opening_point(&g);
        let v = g.apply(Seat::A, &shot(strike)).expect("a legal shot");
        assert!(v.reasons[0].starts_with("Point: "), "{:?}", v.reasons);
        assert!(
            v.reasons[0].ends_with("before the yellow"),
            "{:?}",
            v.reasons
        );
        assert!(v
            .reasons
            .contains(&"Score: Player A 1, Player B 0 (race to 15)".into()));
        assert_eq!((v.foul, v.next, v.over.clone()), (false, Seat::A, None));
        assert_eq!(g.carom().map(|m| m.scores()), Some([1, 0]));
        assert!(v.shot.is_some_and(|s| s.pocketed.is_empty()));
        let out = v.outcome.expect("the trajectory");
        assert_eq!(g.balls(), out.finals.as_slice());
        // Still the white's shot, from where the balls lie.
        assert_eq!(g.cue_ball(), usize::from(WHITE));
    }

    #[test]
    fn a_miss_passes_the_inning_to_the_yellow() {
        let mut g = game(15);
        // Straight at the red and back: the red, no yellow.
        let red = top_spot() - g.balls()[0].pos;
        let strike = Strike {
            speed: 2.0,
            dir: red.normalize(),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let v = g.apply(Seat::A, &shot(strike)).expect("a legal shot");
        assert_eq!(v.reasons[0], "Missed the yellow: no point");
        assert_eq!(
            v.reasons[1..],
            [
                "Score: Player A 0, Player B 0 (race to 15)".to_string(),
                "Player B to play".to_string()
            ]
        );
        assert_eq!((v.foul, v.next, g.to_move()), (false, Seat::B, Seat::B));
        assert_eq!(g.cue_ball(), usize::from(YELLOW));
        assert_eq!(g.carom().map(|m| m.innings()), Some(2));
        // Seat A may not shoot now; seat B strikes the yellow.
        let any = Strike::at_angle(2.0, 0.0, DVec2::ZERO);
        assert_eq!(g.check(Seat::A, &shot(any)), Err(RuleError::NotYourTurn));
        assert_eq!(
            g.shot_for(&any).strike.map(|s| s.0),
            Some(usize::from(YELLOW))
        );
    }

    #[test]
    fn reaching_the_race_wins() {
        let mut g = game(1);
        let strike = opening_point(&g);
        let v = g.apply(Seat::A, &shot(strike)).expect("a legal shot");
        let won = "Player A reaches 1 point and wins".to_string();
        assert_eq!(v.over, Some((Some(Seat::A), won.clone())));
        assert_eq!(v.reasons.last(), Some(&won));
        assert!(matches!(
            g.phase(),
            Phase::Over {
                winner: Some(Seat::A),
                ..
            }
        ));
        assert_eq!(g.check(Seat::A, &shot(strike)), Err(RuleError::GameOver));
    }

    #[test]
    fn touching_balls_are_offered_a_respot() {
        let mut g = game(15);
        let r = g.params().ball_radius;
        let mut balls = g.balls().to_vec();
        balls[usize::from(WHITE)] =
            BallState::at_rest(balls[usize::from(RED)].pos - DVec2::new(2.0 * r, 0.0));
        g.carom = g.carom.take().map(|m| m.with_balls(balls.clone()));
        g.balls = balls;
        g.phase = Phase::Shooting {
            in_hand: None,
            options: g.carom_options(),
            push_out: false,
        };
        assert_eq!(
            g.legal_first_balls(),
            vec![RED],
            "the opening still needs the red"
        );
        let v = g
            .apply(Seat::A, &Command::Decide(Choice::Respot))
            .expect("offered");
        assert_eq!(
            v.reasons,
            [
                "Player A chooses to have the balls set up as at the start",
                "The balls are set up as at the start"
            ]
        );
        assert_eq!(g.balls(), three_cushion::start_position(Seat::A).as_slice());
        assert!(matches!(g.phase(), Phase::Shooting { options, .. } if options.is_empty()));
        assert!(g.check(Seat::A, &Command::Decide(Choice::Respot)).is_err());
    }

    #[test]
    fn a_jumped_ball_is_a_foul_and_is_spotted() {
        let mut g = game(15);
        // Elevated and hard into the near side cushion: the engine lifts the white over it.
        let strike = Strike::at_angle(5.0, 0.0, DVec2::ZERO).elevated(30.0);
        let v = g.apply(Seat::A, &shot(strike)).expect("a legal shot");
        assert!(v.foul, "{:?}", v.reasons);
        assert_eq!(v.reasons[0], "Foul: the cue ball left the table: no point");
        assert_eq!(v.next, Seat::B);
        // The white went back on its own spot, the bottom one, which the yellow holds: the
        // next free spot is the top one, which the red holds, so it is the centre.
        let white = g.balls()[usize::from(WHITE)];
        assert_eq!(white.motion, MotionState::Stationary);
        assert_eq!(white.pos, three_cushion::centre_spot());
    }

    #[test]
    fn running_out_of_time_ends_the_inning() {
        let mut g = Game::new(three(), Settings::online(), 1);
        let v = g
            .apply(Seat::A, &Command::TimeExpired)
            .expect("A is on the clock");
        assert_eq!(v.reasons[0], "Foul: Player A ran out of time: no point");
        assert_eq!((v.foul, v.next, g.cue_ball()), (true, Seat::B, 1));
        assert_eq!(g.carom().map(|m| m.to_move()), Some(Seat::B));
    }

    fn three() -> Variant {
        Variant::three_cushion()
    }

    #[test]
    fn a_record_of_a_match_replays_to_the_same_game() {
        let mut g = game(3);
        let mut record = GameRecord::of(&g);
        let mut strikes = vec![opening_point(&g)];
        strikes
            .extend((0..4).map(|k| Strike::at_angle(2.5, 40.0 + 70.0 * f64::from(k), DVec2::ZERO)));
        for strike in strikes {
            let seat = g.to_move();
            let cmd = shot(strike);
            let v = g.apply(seat, &cmd).expect("a legal shot");
            record.push(seat, cmd, v.shot.map(|s| s.hash));
        }
        let decoded = GameRecord::decode(&record.encode()).expect("decodes");
        assert_eq!(decoded, record);
        assert_eq!(decoded.variant, Variant::ThreeCushion { race: 3 });
        assert_eq!(decoded.replay().expect("replays"), g);
        // A race outside the bounds, as a hostile record could hold, still starts a game.
        let wild = Game::new(Variant::ThreeCushion { race: 0 }, Settings::offline(), 1);
        assert_eq!(wild.carom().map(|m| m.race()), Some(1));
    }
}
