//! A game in progress: [`Game::check`] and [`Game::apply`], the one place a game changes,
//! and the steps every variant shares (seats, choices, the shot clock, racks, verdicts).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::physics::{simulate, BallState, MotionState, Params, Shot, Strike, Table, TableKind};

use super::{
    eight, facts, nine, practice, rack, snooker, three_cushion, Choice, Command, Group, InHand,
    Judged, Next, Pending, Phase, RuleError, Seat, Settings, ShotFacts, ShotReport, TurnId,
    Variant, Verdict,
};

/// A game in progress.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Game {
    pub(super) variant: Variant,
    pub(super) settings: Settings,
    pub(super) seed: u64,
    /// Racks played before the current one (re-racks included).
    pub(super) racks: u32,
    pub(super) balls: Vec<BallState>,
    pub(super) turn: TurnId,
    pub(super) to_move: Seat,
    pub(super) breaker: Seat,
    pub(super) phase: Phase,
    /// The next shot is a break.
    pub(super) breaking: bool,
    /// 8-ball: seat A's group once assigned.
    pub(super) group_a: Option<Group>,
    /// 9-ball: consecutive fouls of each seat.
    pub(super) fouls: [u8; 2],
    pub(super) pending: Option<Pending>,
    /// Stalemate offers since the last shot.
    pub(super) stalemate: [bool; 2],
    /// Three-cushion: the match (its scores, innings and balls).
    pub(super) carom: Option<three_cushion::Match>,
    /// Snooker: the match (its frames, scores and the state between strokes).
    pub(super) snooker: Option<snooker::frame::Snooker>,
    /// A practice table set up by a player here (never sent: a server's games have none).
    #[serde(skip)]
    pub(super) sandbox: Option<Box<practice::Sandbox>>,
}

impl Game {
    /// A new game: the first rack, seat A to break.
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> Game {
        let settings = Settings {
            table: variant.table(settings.table),
            ..settings
        };
        let mut game = Game {
            variant,
            settings,
            seed,
            racks: 0,
            balls: Vec::new(),
            turn: 0,
            to_move: Seat::A,
            breaker: Seat::A,
            phase: Phase::Deciding {
                options: Vec::new(),
            },
            breaking: false,
            group_a: None,
            fouls: [0; 2],
            pending: None,
            stalemate: [false; 2],
            carom: None,
            snooker: None,
            sandbox: None,
        };
        game.rack(Seat::A);
        game
    }

    /// The game played, fixed for the whole game.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// The settings, with the table the variant plays on.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// The seed every rack's random layout derives from.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The table played on (the carom table for three-cushion, whatever was asked).
    pub fn table(&self) -> TableKind {
        self.settings.table
    }

    /// The balls, index = ball number (0 = cue ball), in scene coordinates.
    pub fn balls(&self) -> &[BallState] {
        &self.balls
    }

    /// The number of commands applied so far: a command must answer this turn.
    pub fn turn(&self) -> TurnId {
        self.turn
    }

    /// The seat that shoots or decides next.
    pub fn to_move(&self) -> Seat {
        self.to_move
    }

    /// What the game waits for now.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// How many racks came before the current one (re-racks included; 0 for the opening).
    pub fn rack_number(&self) -> u32 {
        self.racks
    }

    /// The seat that broke (or breaks) the current rack.
    pub fn breaker(&self) -> Seat {
        self.breaker
    }

    /// The next shot is a break.
    pub fn is_break(&self) -> bool {
        self.breaking
    }

    /// 8-ball: the group of `seat`, once the table is no longer open.
    pub fn group_of(&self, seat: Seat) -> Option<Group> {
        match seat {
            Seat::A => self.group_a,
            Seat::B => self.group_a.map(Group::other),
        }
    }

    /// 9-ball: consecutive fouls of `seat` (three lose).
    pub fn consecutive_fouls(&self, seat: Seat) -> u8 {
        self.fouls[seat.index()]
    }

    /// Seats that have offered a stalemate since the last shot.
    pub fn stalemate_offered(&self, seat: Seat) -> bool {
        self.stalemate[seat.index()]
    }

    /// The balls the shooter may legally strike first now (empty in practice: anything goes).
    pub fn legal_first_balls(&self) -> Vec<u8> {
        match self.variant {
            Variant::EightBall(_) => eight::legal_first_balls(self, self.to_move),
            Variant::NineBall => nine::lowest_ball(&self.balls).into_iter().collect(),
            Variant::Practice => Vec::new(),
            Variant::ThreeCushion { .. } => self.carom_first_balls(),
            Variant::Snooker { .. } => self.snooker_balls_on(),
        }
    }

    /// The ball the shooter strikes: the cue ball, or in three-cushion the shooter's own
    /// ball (the white for seat A, the yellow for seat B).
    pub fn cue_ball(&self) -> usize {
        match (&self.carom, &self.sandbox) {
            (Some(m), _) => usize::from(three_cushion::cue_ball(m.to_move())),
            (None, Some(sandbox)) => sandbox.cue(),
            (None, None) => usize::from(facts::CUE),
        }
    }

    /// The physics shot that `strike` on the cue ball would be from the current table.
    pub fn shot_for(&self, strike: &Strike) -> Shot {
        match &self.sandbox {
            Some(sandbox) => sandbox.shot(self, self.balls.clone(), Some(*strike)),
            None => Shot::new(self.table(), self.balls.clone()).struck(self.cue_ball(), *strike),
        }
    }

    /// The physical parameters every shot of this game is simulated with.
    pub fn params(&self) -> Params {
        match &self.sandbox {
            Some(sandbox) => sandbox.params(),
            None => Shot::new(self.table(), Vec::new()).params,
        }
    }

    /// May `ball` lie at rest at `pos`: on the cloth, clear of the cushions, the pockets and
    /// the other balls?
    pub(super) fn is_free(&self, ball: usize, pos: DVec2) -> bool {
        match (&self.sandbox, &self.snooker) {
            (Some(sandbox), _) => practice::sandbox_free(self, sandbox, ball, pos),
            (None, Some(_)) => snooker::table::is_free(&self.balls, ball, pos),
            (None, None) => rack::is_free(&self.balls, ball, pos, self.table()),
        }
    }

    /// Must the next shot name a pocket? The same answer [`Game::check`] enforces: never on
    /// a break; in 8-ball when shooting at the 8; with `call_every_shot`, every shot.
    pub fn needs_call(&self) -> bool {
        self.missing_call().is_some()
    }

    /// Why a shot without a call would be refused now, if it would.
    pub(super) fn missing_call(&self) -> Option<&'static str> {
        if self.breaking {
            return None;
        }
        match self.variant {
            Variant::EightBall(_) if eight::on_eight(self, self.to_move) => {
                Some("call a pocket for the 8")
            }
            Variant::EightBall(_) | Variant::NineBall if self.settings.call_every_shot => {
                Some("this game requires a called pocket on every shot")
            }
            _ => None,
        }
    }

    /// The part of the cloth where the cue ball may go when in hand in `area`: the corners
    /// (min, max) of a rectangle in scene coordinates. The cue ball must also lie clear of
    /// the cushions and the other balls ([`Game::legal_cue_placement`]).
    pub fn in_hand_area(&self, area: InHand) -> (DVec2, DVec2) {
        let (w, l) = rack::table_size(self.table());
        match area {
            InHand::Kitchen => (DVec2::ZERO, DVec2::new(w, rack::head_string(self.table()))),
            InHand::Anywhere => (DVec2::ZERO, DVec2::new(w, l)),
            InHand::D => {
                let c = snooker::table::d_centre();
                let r = snooker::table::D_RADIUS;
                (DVec2::new(c.x - r, c.y - r), DVec2::new(c.x + r, c.y))
            }
        }
    }

    /// May the cue ball, in hand, go at `pos` (scene coordinates)?
    pub fn legal_cue_placement(&self, pos: [f64; 2]) -> Result<(), RuleError> {
        let area = match (&self.phase, self.variant) {
            (Phase::Over { .. }, _) => return Err(RuleError::GameOver),
            (_, Variant::Practice) => InHand::Anywhere,
            (
                Phase::Shooting {
                    in_hand: Some(area),
                    ..
                },
                _,
            ) => *area,
            _ => return Err(RuleError::WrongPhase("the cue ball is not in hand".into())),
        };
        self.placement_in(area, pos)
    }

    pub(super) fn placement_in(&self, area: InHand, pos: [f64; 2]) -> Result<(), RuleError> {
        let p = DVec2::from_array(pos);
        if !p.is_finite() {
            return Err(RuleError::IllegalPlacement(
                "the position must be finite numbers".into(),
            ));
        }
        if area == InHand::Kitchen && p.y >= self.in_hand_area(area).1.y {
            return Err(RuleError::IllegalPlacement(
                "the cue ball must be behind the head string".into(),
            ));
        }
        if area == InHand::D && !snooker::table::in_d(p) {
            return Err(RuleError::IllegalPlacement(
                "the cue ball must be placed in the D".into(),
            ));
        }
        if !self.is_free(self.cue_ball(), p) {
            return Err(RuleError::IllegalPlacement(
                "the cue ball must lie on the cloth, clear of the cushions, pockets and other balls"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Would `cmd` from `seat` be accepted now? Changes nothing.
    pub fn check(&self, seat: Seat, cmd: &Command) -> Result<(), RuleError> {
        if let Phase::Over { .. } = self.phase {
            return Err(RuleError::GameOver);
        }
        let practice = self.variant == Variant::Practice;
        match cmd {
            Command::Concede | Command::Forfeit => Ok(()),
            Command::ProposeStalemate => {
                if practice || self.carom.is_some() {
                    return Err(RuleError::NotAllowed(format!(
                        "there is no stalemate in {}",
                        if practice {
                            "practice"
                        } else {
                            "three-cushion"
                        }
                    )));
                }
                if self.stalemate[seat.index()] {
                    return Err(RuleError::WrongPhase(
                        "you have already offered a stalemate".into(),
                    ));
                }
                Ok(())
            }
            Command::TimeExpired => {
                if practice || self.settings.shot_clock.is_none() {
                    return Err(RuleError::NotAllowed("this game has no shot clock".into()));
                }
                self.check_seat(seat)
            }
            Command::PlaceBall { ball, pos } => {
                if !practice {
                    return Err(RuleError::NotAllowed(
                        "balls can be placed freely only in practice".into(),
                    ));
                }
                practice::check_place_ball(self, *ball, *pos)
            }
            Command::LoadLayout { balls } => {
                if !practice {
                    return Err(RuleError::NotAllowed(
                        "a layout can be loaded only in practice".into(),
                    ));
                }
                practice::check_layout(self, balls)
            }
            Command::PlaceCueBall { pos } => {
                if !practice {
                    self.check_seat(seat)?;
                }
                self.legal_cue_placement(*pos)
            }
            Command::Decide(choice) => {
                if practice {
                    return Err(RuleError::NotAllowed(
                        "there are no choices in practice".into(),
                    ));
                }
                self.check_seat(seat)?;
                if self.snooker.is_some() {
                    return self.check_snooker_choice(*choice);
                }
                let options = match &self.phase {
                    Phase::Deciding { options } | Phase::Shooting { options, .. } => options,
                    Phase::Over { .. } => return Err(RuleError::GameOver),
                };
                if options.contains(choice) {
                    Ok(())
                } else {
                    Err(RuleError::InvalidChoice(format!("you cannot {choice} now")))
                }
            }
            Command::Shot { strike, call } => {
                if !practice {
                    self.check_seat(seat)?;
                }
                self.check_shot(strike, *call)
            }
        }
    }

    pub(super) fn check_seat(&self, seat: Seat) -> Result<(), RuleError> {
        if seat == self.to_move {
            Ok(())
        } else {
            Err(RuleError::NotYourTurn)
        }
    }

    pub(super) fn check_shot(&self, strike: &Strike, call: Option<u8>) -> Result<(), RuleError> {
        strike
            .validated()
            .map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let in_hand = match &self.phase {
            Phase::Shooting { in_hand, .. } => *in_hand,
            Phase::Deciding { .. } => {
                return Err(RuleError::WrongPhase("a choice must be made first".into()))
            }
            Phase::Over { .. } => return Err(RuleError::GameOver),
        };
        let cue = match self.balls.get(self.cue_ball()) {
            Some(b) if !is_off_table(b) => *b,
            _ => return Err(RuleError::WrongPhase("place the cue ball first".into())),
        };
        if let (Some(area), false) = (in_hand, self.variant == Variant::Practice) {
            self.placement_in(area, cue.pos.to_array())?;
        }
        let pockets = Table::new(self.table()).pockets.len();
        if let Some(p) = call {
            if usize::from(p) >= pockets {
                return Err(RuleError::InvalidShot(format!(
                    "pocket {p} does not exist (the table has {pockets})"
                )));
            }
        }
        match (call, self.missing_call()) {
            (None, Some(why)) => Err(RuleError::InvalidShot(why.into())),
            _ => Ok(()),
        }
    }

    /// What the rules would say of `seat` playing `strike` (naming pocket `call`) now: the
    /// very judgement [`Game::apply`] makes, on a copy, with the shot's trajectory in the
    /// verdict's `outcome`. Aiming aids show it before the shot (a foul, a loss) in the
    /// rules' own words. Changes nothing.
    pub fn preview(
        &self,
        seat: Seat,
        strike: &Strike,
        call: Option<u8>,
    ) -> Result<Verdict, RuleError> {
        let shot = Command::Shot {
            strike: *strike,
            call,
        };
        self.clone().apply(seat, &shot)
    }

    /// Applies `cmd` from `seat`: the only way a game changes. On error nothing changes.
    pub fn apply(&mut self, seat: Seat, cmd: &Command) -> Result<Verdict, RuleError> {
        self.check(seat, cmd)?;
        let verdict = match cmd {
            Command::Shot { strike, call } => self.shoot(seat, strike, *call)?,
            Command::PlaceCueBall { pos } => {
                let cue = self.cue_ball();
                if let Some(cue) = self.balls.get_mut(cue) {
                    *cue = BallState::at_rest(DVec2::from_array(*pos));
                }
                if self.variant == Variant::Practice {
                    self.to_move = seat;
                }
                self.verdict(vec![format!("{seat} places the cue ball")])
            }
            Command::PlaceBall { ball, pos } => {
                practice::place_ball(self, *ball, *pos);
                self.to_move = seat;
                self.verdict(Vec::new())
            }
            Command::LoadLayout { balls } => {
                practice::load_layout(self, balls);
                self.to_move = seat;
                self.verdict(vec!["Layout loaded".into()])
            }
            Command::Decide(choice) => self.decide(seat, *choice),
            Command::TimeExpired => self.time_expired(seat),
            Command::Concede if self.snooker.is_some() => self.snooker_concede(seat),
            Command::Concede | Command::Forfeit => {
                let how = match cmd {
                    Command::Forfeit => "left and forfeited",
                    _ => "conceded",
                };
                let (winner, reason) = if self.variant == Variant::Practice {
                    (None, "Practice ended".to_string())
                } else {
                    (
                        Some(seat.other()),
                        format!("{seat} {how}; {} wins", seat.other()),
                    )
                };
                self.enact(
                    Next::Over {
                        winner,
                        reason: reason.clone(),
                    },
                    vec![reason],
                    false,
                    None,
                )
            }
            Command::ProposeStalemate => {
                self.stalemate[seat.index()] = true;
                if self.stalemate[seat.other().index()] {
                    let breaker = self.breaker;
                    let reasons = vec![format!(
                        "Stalemate agreed by both players: re-rack, {breaker} breaks again"
                    )];
                    self.enact(Next::Rerack { breaker }, reasons, false, None)
                } else {
                    self.verdict(vec![format!("{seat} offers a stalemate")])
                }
            }
        };
        self.turn = self.turn.wrapping_add(1);
        Ok(verdict)
    }

    /// A verdict for a command that leaves the turn where it is.
    pub(super) fn verdict(&self, reasons: Vec<String>) -> Verdict {
        Verdict {
            reasons,
            foul: false,
            shot: None,
            next: self.to_move,
            over: None,
            outcome: None,
        }
    }

    pub(super) fn shoot(
        &mut self,
        seat: Seat,
        strike: &Strike,
        call: Option<u8>,
    ) -> Result<Verdict, RuleError> {
        if self.carom.is_some() {
            return self.carom_shot(seat, strike);
        }
        if self.snooker.is_some() {
            return self.snooker_shot(seat, strike);
        }
        let outcome =
            simulate(&self.shot_for(strike)).map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let facts = ShotFacts::from_outcome(&outcome, self.table());
        let report = ShotReport {
            hash: outcome.hash(),
            events: outcome.events.clone(),
            pocketed: facts.pocketed.clone(),
        };
        let mut verdict = self.judge_shot(seat, call, outcome.finals.clone(), &facts, report);
        verdict.outcome = Some(outcome);
        Ok(verdict)
    }

    /// Judges a shot that left the balls at `finals` with `facts`, and moves the game on.
    pub(super) fn judge_shot(
        &mut self,
        seat: Seat,
        call: Option<u8>,
        finals: Vec<BallState>,
        facts: &ShotFacts,
        report: ShotReport,
    ) -> Verdict {
        let before = std::mem::replace(&mut self.balls, finals);
        for &b in &facts.off_table {
            if let Some(ball) = self.balls.get_mut(usize::from(b)) {
                *ball = off_table();
            }
        }
        self.stalemate = [false; 2];
        let push_out = matches!(self.phase, Phase::Shooting { push_out: true, .. });
        let ruling = match self.variant {
            Variant::EightBall(rules) => eight::judge(self, rules, seat, call, facts, &before),
            Variant::NineBall => nine::judge(self, seat, call, facts, &before, push_out),
            Variant::Practice => practice::judge(self, seat, facts),
            // Three-cushion shots are judged by the match (`carom_shot`), never here: the
            // turn stays as it is.
            Variant::ThreeCushion { .. } | Variant::Snooker { .. } => Judged {
                reasons: Vec::new(),
                foul: false,
                next: Next::Shoot {
                    seat: self.to_move,
                    in_hand: None,
                    options: Vec::new(),
                },
            },
        };
        self.breaking = false;
        self.enact(ruling.next, ruling.reasons, ruling.foul, Some(report))
    }

    pub(super) fn decide(&mut self, seat: Seat, choice: Choice) -> Verdict {
        if self.snooker.is_some() {
            return self.snooker_decide(seat, choice);
        }
        let mut reasons = vec![format!("{seat} chooses to {choice}")];
        if choice == Choice::SpotNearestBall {
            reasons.extend(self.spot_nearest_ball());
            return self.verdict(reasons);
        }
        if choice == Choice::Respot {
            return self.carom_respot(seat, reasons);
        }
        if choice == Choice::PushOut {
            if let Phase::Shooting { in_hand, .. } = self.phase {
                self.phase = Phase::Shooting {
                    in_hand,
                    options: Vec::new(),
                    push_out: true,
                };
            }
            return self.verdict(reasons);
        }
        let next = match (self.pending.take(), choice) {
            (Some(Pending::IllegalBreak { scratched, .. }), Choice::AcceptTable) => Next::Shoot {
                seat,
                in_hand: scratched.then_some(InHand::Kitchen),
                options: Vec::new(),
            },
            (Some(Pending::IllegalBreak { offender, .. }), Choice::OpponentRebreaks) => {
                Next::Rerack { breaker: offender }
            }
            (Some(Pending::EightOnBreak { foul }), Choice::SpotEightAndContinue) => {
                let kind = self.table();
                let spotted = rack::spot(&mut self.balls, 8, kind);
                reasons.push(format!("The 8 is spotted {}", spotted.describe()));
                Next::Shoot {
                    seat,
                    in_hand: foul.then_some(InHand::Kitchen),
                    options: Vec::new(),
                }
            }
            (Some(Pending::JumpedOnBreak), choice) => Next::Shoot {
                seat,
                in_hand: (choice == Choice::CueBallInKitchen).then_some(InHand::Kitchen),
                options: Vec::new(),
            },
            (Some(Pending::PushOut { .. }), Choice::AcceptTable) => Next::Shoot {
                seat,
                in_hand: None,
                options: Vec::new(),
            },
            (Some(Pending::PushOut { pusher }), Choice::HandBack) => Next::Shoot {
                seat: pusher,
                in_hand: None,
                options: Vec::new(),
            },
            // Re-rack (after an illegal break or the 8 on the break): the chooser breaks.
            _ => Next::Rerack { breaker: seat },
        };
        self.enact(next, reasons, false, None)
    }

    pub(super) fn time_expired(&mut self, seat: Seat) -> Verdict {
        if let Phase::Deciding { options } = &self.phase {
            // Out of time on a choice: the first option offered is taken (no foul).
            let choice = options.first().copied().unwrap_or(Choice::AcceptTable);
            let mut verdict = self.decide(seat, choice);
            verdict.reasons.insert(
                0,
                format!("{seat} ran out of time; the first option is taken"),
            );
            return verdict;
        }
        if self.carom.is_some() {
            return self.carom_time_out(seat);
        }
        if self.snooker.is_some() {
            return self.snooker_time_out(seat);
        }
        let mut reasons = vec![format!("Foul: {seat} ran out of time")];
        self.stalemate = [false; 2];
        let opponent = seat.other();
        let mut next = if self.breaking {
            // The break was never taken: the opponent breaks the same rack.
            self.breaker = opponent;
            reasons.push(format!("{opponent} breaks"));
            Next::Shoot {
                seat: opponent,
                in_hand: Some(InHand::Kitchen),
                options: Vec::new(),
            }
        } else {
            reasons.push(format!("{opponent} has ball in hand"));
            Next::Shoot {
                seat: opponent,
                in_hand: Some(InHand::Anywhere),
                options: Vec::new(),
            }
        };
        if self.variant == Variant::NineBall {
            if let Some(over) = nine::count_foul(self, seat, &mut reasons) {
                next = over;
            }
        }
        self.enact(next, reasons, true, None)
    }

    /// Moves the game to `next` and builds the verdict.
    pub(super) fn enact(
        &mut self,
        next: Next,
        reasons: Vec<String>,
        foul: bool,
        shot: Option<ShotReport>,
    ) -> Verdict {
        let mut over = None;
        match next {
            Next::Shoot {
                seat,
                mut in_hand,
                options,
            } => {
                let cue_off = self.balls.first().is_none_or(is_off_table);
                if cue_off && in_hand.is_none() {
                    in_hand = Some(if self.snooker.is_some() {
                        InHand::D
                    } else {
                        InHand::Anywhere
                    });
                }
                self.to_move = seat;
                self.pending = None;
                self.phase = Phase::Shooting {
                    in_hand,
                    options,
                    push_out: false,
                };
                self.offer_spot_nearest_ball();
            }
            Next::Decide {
                seat,
                options,
                pending,
            } => {
                self.to_move = seat;
                self.pending = Some(pending);
                self.phase = Phase::Deciding { options };
            }
            Next::Over { winner, reason } => {
                self.pending = None;
                over = Some((winner, reason.clone()));
                self.phase = Phase::Over { winner, reason };
            }
            Next::Rerack { breaker } => {
                self.racks = self.racks.wrapping_add(1);
                self.rack(breaker);
            }
        }
        Verdict {
            reasons,
            foul,
            shot,
            next: self.to_move,
            over,
            outcome: None,
        }
    }

    /// Racks the balls for the current rack number; `breaker` breaks from the kitchen.
    pub(super) fn rack(&mut self, breaker: Seat) {
        let seed = rack::rack_seed(self.seed, self.racks);
        self.carom = Game::start_carom(self.variant);
        self.snooker = match self.snooker.take() {
            Some(mut m) => {
                m.start_frame(breaker);
                Some(m)
            }
            None => Game::start_snooker(self.variant),
        };
        self.balls = match (self.variant, &self.carom) {
            (Variant::NineBall, _) => rack::nine_ball(self.table(), seed),
            (Variant::EightBall(_) | Variant::Practice, _) => rack::eight_ball(self.table(), seed),
            // The match sets up its own start.
            (Variant::ThreeCushion { .. }, m) => {
                m.iter().flat_map(|m| m.balls()).copied().collect()
            }
            (Variant::Snooker { reds, .. }, _) => snooker::table::rack(reds, seed),
        };
        self.breaker = breaker;
        self.to_move = breaker;
        self.group_a = None;
        self.fouls = [0; 2];
        self.pending = None;
        self.stalemate = [false; 2];
        let practice = self.variant == Variant::Practice;
        let carom = self.carom.is_some();
        let snooker = self.snooker.is_some();
        self.breaking = !practice && !carom && !snooker;
        // In practice the cue ball is always in hand: it can be put anywhere free. In
        // three-cushion no ball is ever in hand.
        self.phase = Phase::Shooting {
            in_hand: match (practice, carom, snooker) {
                (true, _, _) => Some(InHand::Anywhere),
                (false, true, _) => None,
                (false, false, true) => Some(InHand::D),
                (false, false, false) => Some(InHand::Kitchen),
            },
            options: Vec::new(),
            push_out: false,
        };
    }
}

/// Is `ball` off the table (pocketed, or gone over a rail)? Balls off the table keep their
/// place in the list.
pub fn is_off_table(ball: &BallState) -> bool {
    ball.motion == MotionState::Pocketed
}

/// A ball that left the table (not through a pocket).
pub(super) fn off_table() -> BallState {
    BallState {
        motion: MotionState::Pocketed,
        pocket: None,
        ..BallState::at_rest(DVec2::ZERO)
    }
}
