//! The computer's advice on the table as it stands: the shot it would play, with its chance
//! of success under a chosen level's noise. It is exactly what `breakshot-sim suggest` says
//! of the same scene, targets, level and seed ([`Request::command_line`]), and it is
//! searched in steps ([`Advisor::step`]) so a frame loop (the browser's too) keeps drawing.

use std::task::Poll;

use breakshot_shared::ai::{Decision, Kind, Level, Player, Rng, Suggestion, Thinking};
use breakshot_shared::hash::state_hash;
use breakshot_shared::physics::{EventKind, MotionState, Outcome, Shot, Simulator, Strike};
use breakshot_shared::rules::{pocket_name, Command, Game, ShotFacts};
use breakshot_shared::scene::Scene;
use glam::DVec2;

/// What is asked: the table as a scene of the simulator's, the balls the shot may pot, the
/// level whose noise the chance is for, and the seed.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The table as it stands (`Game::scene`).
    pub scene: Scene,
    /// The object balls' ids (every ball on the cloth but the cue ball).
    pub targets: Vec<String>,
    /// Whose noise the chance is measured under.
    pub level: Level,
    /// The search's seed: the table's own hash, so one table always gets the same advice.
    pub seed: u64,
}

impl Request {
    /// The advice asked for `game`'s table at `level`; Err says why there is none (no
    /// object ball left, no cue ball on the cloth).
    pub fn for_table(game: &Game, level: Level) -> Result<Request, String> {
        let scene = game.scene();
        let cue = game.ball_ids().get(game.cue_ball()).cloned();
        let cue = cue.ok_or("the table has no cue ball")?;
        if !scene.balls.iter().any(|b| b.id == cue) {
            return Err("the cue ball is not on the table".into());
        }
        let targets: Vec<String> = scene
            .balls
            .iter()
            .filter(|b| b.id != cue)
            .map(|b| b.id.clone())
            .collect();
        if targets.is_empty() {
            return Err("no object ball is left on the table".into());
        }
        Ok(Request {
            scene,
            targets,
            level,
            seed: state_hash(game.balls()),
        })
    }

    /// The simulator's command that gives the same answer for the scene saved as `path`.
    pub fn command_line(&self, path: &str) -> String {
        format!(
            "breakshot-sim suggest {path} --targets {} --level {} --seed {}",
            self.targets.join(","),
            self.level.number(),
            self.seed
        )
    }

    /// The scene's shot, the cue ball's index and the targets' indices.
    fn indices(&self) -> Result<(Shot, usize, Vec<usize>), String> {
        let index = |id: &str| self.scene.balls.iter().position(|b| b.id == id);
        let cue = index("cue").ok_or("the table has no ball named \"cue\"")?;
        let targets = self
            .targets
            .iter()
            .map(|t| index(t).ok_or_else(|| format!("no ball \"{t}\" on the table")))
            .collect::<Result<Vec<_>, _>>()?;
        let shot = self.scene.to_shot().map_err(|e| e.to_string())?;
        Ok((shot, cue, targets))
    }
}

/// The shot advised and what it leads to when played as meant.
#[derive(Clone, Debug, PartialEq)]
pub struct Advice {
    /// The strike on the cue ball.
    pub strike: Strike,
    /// Its chance of success under the level's noise (share of the search's trials).
    pub p_success: f64,
    /// How many trials that share is of ([`Advice::error`]).
    pub trials: usize,
    /// What the search took it for.
    pub kind: Kind,
    /// The ball it pots played as meant, and the pocket's name (the pocket it calls).
    pub pots: Option<(String, String)>,
    /// Where the cue ball stops played as meant: the position it plays for.
    pub leave: Option<DVec2>,
    /// Asked after a miss: the chance the shot the player chose had, under the same noise.
    pub played: Option<Chance>,
}

/// A share of trials that succeeded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chance {
    /// Successes over trials.
    pub share: f64,
    /// How many trials.
    pub trials: usize,
}

impl Chance {
    /// The share's standard error, as Agresti and Coull's interval gives it (two successes
    /// and two failures added), so that 16 of 16 is not quoted as certain.
    pub fn error(&self) -> f64 {
        let n = self.trials as f64 + 4.0;
        let p = (self.share * self.trials as f64 + 2.0) / n;
        libm::sqrt(p * (1.0 - p) / n)
    }

    /// "71 ± 9 %".
    pub fn percent(&self) -> String {
        format!("{:.0} ± {:.0} %", 100.0 * self.share, 100.0 * self.error())
    }
}

impl Advice {
    /// The advised shot's chance.
    pub fn chance(&self) -> Chance {
        Chance {
            share: self.p_success,
            trials: self.trials,
        }
    }

    /// The chance's standard error ([`Chance::error`]).
    pub fn error(&self) -> f64 {
        self.chance().error()
    }

    /// One line for the screen; after a miss it begins with the chance the shot played had
    /// ("That shot: 31 ± 6 %; the computer's Safety: 84 ± 9 % ...").
    pub fn summary(&self, level: Level) -> String {
        let s = &self.strike;
        let angle = libm::atan2(s.dir.y, s.dir.x).to_degrees();
        let aim = match &self.pots {
            Some((ball, pocket)) => format!("{:?} the {ball} into the {pocket}", self.kind),
            None => format!("{:?}", self.kind),
        };
        let aim = match &self.played {
            Some(played) => format!("That shot: {}; the computer's {aim}", played.percent()),
            None => aim,
        };
        format!(
            "{aim}: {} at level {}  |  {:.1} m/s at {angle:.1} deg, tip ({:.2}, {:.2}), elevation {:.0} deg",
            self.chance().percent(),
            level.number(),
            s.speed,
            s.tip.x,
            s.tip.y,
            s.elevation_deg,
        )
    }
}

/// The level advice asked again is for: the next, after the last the first (I again on an
/// advice shown).
pub fn next_level(level: Level) -> Level {
    Level::new(level.number() % Level::MAX + 1)
}

/// The search for one table's advice, stepped.
pub struct Advisor {
    search: Search,
    level: Level,
    /// After a miss: the shot played, measured before the search runs.
    played: Option<Measure>,
    done: Option<Result<Advice, String>>,
}

/// Trials the chance of a shot played is measured over: more than the search gives its
/// own candidates, as it is the one number the player compares with the advice.
pub const PLAYED_TRIALS: usize = 64;

/// The chance of one strike under a level's noise, measured in steps: `trials` strikes
/// perturbed by a generator from `seed`, each a success as [`succeeded`] counts one.
pub struct Measure {
    trial: Trial,
    strike: Strike,
    level: Level,
    rng: Rng,
    sim: Simulator,
    trials: usize,
    run: usize,
    made: usize,
}

/// What one trial plays and how it is judged.
enum Trial {
    /// A practice table's shot (its cue ball ball 0), a success as [`succeeded`] says.
    Scene { shot: Box<Shot>, targets: Vec<u8> },
    /// A rules game's stroke by the player to move with `call`: a success as the computer
    /// counts one ([`Verdict::succeeded_for`](breakshot_shared::rules::Verdict::succeeded_for)).
    Game { game: Box<Game>, call: Option<u8> },
}

impl Trial {
    /// `shot` on a practice table, its cue ball ball 0, a success pocketing one of `targets`.
    fn scene(shot: &Shot, targets: &[u8]) -> Trial {
        let shot = Box::new(shot.clone());
        Trial::Scene {
            shot,
            targets: targets.to_vec(),
        }
    }

    /// A stroke by the player to move in `game`, calling `call`.
    fn game(game: &Game, call: Option<u8>) -> Trial {
        let game = Box::new(game.clone());
        Trial::Game { game, call }
    }
}

impl Measure {
    /// Measures `strike` played as `trial` says: `trials` strikes under `level`'s noise.
    fn new(trial: Trial, strike: Strike, level: Level, trials: usize, seed: u64) -> Measure {
        Measure {
            trial,
            strike,
            level,
            rng: Rng::new(seed),
            sim: Simulator::new(),
            trials,
            run: 0,
            made: 0,
        }
    }

    /// Runs at most `simulations` more trials; the chance once all have run.
    pub fn step(&mut self, simulations: usize) -> Option<Chance> {
        let upto = self.trials.min(self.run.saturating_add(simulations));
        while self.run < upto {
            let strike = self.level.noise().perturb(&self.strike, &mut self.rng);
            let made = match &self.trial {
                Trial::Scene { shot, targets } => {
                    let mut s = (**shot).clone();
                    s.strike = Some((0, strike));
                    self.sim.run(&s).is_ok_and(|o| succeeded(o, &s, targets))
                }
                Trial::Game { game, call } => {
                    let seat = game.to_move();
                    game.preview(seat, &strike, *call)
                        .is_ok_and(|v| v.succeeded_for(seat))
                }
            };
            self.made += usize::from(made);
            self.run += 1;
        }
        (self.run == self.trials).then(|| Chance {
            share: self.made as f64 / self.trials.max(1) as f64,
            trials: self.trials,
        })
    }

    /// The share of the trials run, 0 to 1.
    fn fraction(&self) -> f64 {
        self.run as f64 / self.trials.max(1) as f64
    }
}

/// What is searched: a practice table's scene (as `breakshot-sim suggest`), or a rules
/// game's next move (as the computer opponent plans it, legal balls and calls included).
enum Search {
    Scene {
        request: Box<Request>,
        shot: Box<Shot>,
        cue: usize,
        search: Thinking<Result<Suggestion, String>>,
    },
    Game {
        game: Box<Game>,
        search: Thinking<Option<Decision>>,
    },
}

impl Advisor {
    /// Starts advising on `request`.
    pub fn start(request: Request) -> Result<Advisor, String> {
        let (shot, cue, targets) = request.indices()?;
        let search = Thinking::suggest(&shot, cue, &targets, request.level, request.seed);
        Ok(Advisor {
            level: request.level,
            search: Search::Scene {
                request: Box::new(request),
                shot: Box::new(shot),
                cue,
                search,
            },
            played: None,
            done: None,
        })
    }

    /// Starts advising on `request`, the table a shot was missed from, with `played` (the
    /// strike missed) measured first under the same level's noise, so the advice can say
    /// what that shot's chance was beside its own. The cue ball must be the scene's ball 0
    /// (as on every pool practice table); on another table the shot played is not measured.
    pub fn after_miss(request: Request, played: Strike) -> Result<Advisor, String> {
        let (shot, cue, targets) = request.indices()?;
        let targets: Vec<u8> = targets
            .iter()
            .filter_map(|&t| u8::try_from(t).ok())
            .collect();
        let level = request.level;
        let seed = request.seed;
        let mut advisor = Advisor::start(request)?;
        if cue == 0 {
            advisor.played = Some(Measure::new(
                Trial::scene(&shot, &targets),
                played,
                level,
                PLAYED_TRIALS,
                seed,
            ));
        }
        Ok(advisor)
    }

    /// Starts advising the player to move in a rules game (a local game, against the
    /// computer): the shot the computer at `level` would mean to play there.
    pub fn for_game(game: &Game, level: Level) -> Advisor {
        let seed = state_hash(game.balls());
        Advisor {
            level,
            search: Search::Game {
                game: Box::new(game.clone()),
                search: Thinking::plan(game, &Player::from(level), seed),
            },
            played: None,
            done: None,
        }
    }

    /// [`Advisor::for_game`] on the table a shot `played` (with `call`) was missed from:
    /// that shot's chance under the same level's noise is measured first, so the advice can
    /// say it beside its own.
    pub fn for_game_after_miss(
        game: &Game,
        level: Level,
        played: Strike,
        call: Option<u8>,
    ) -> Advisor {
        let mut advisor = Advisor::for_game(game, level);
        let seed = state_hash(game.balls());
        advisor.played = Some(Measure::new(
            Trial::game(game, call),
            played,
            level,
            PLAYED_TRIALS,
            seed,
        ));
        advisor
    }

    /// What was asked of a practice table (None for a rules game).
    pub fn request(&self) -> Option<&Request> {
        match &self.search {
            Search::Scene { request, .. } => Some(request),
            Search::Game { .. } => None,
        }
    }

    /// Runs at most `simulations` more of the search; the advice once it is found.
    pub fn step(&mut self, mut simulations: usize) -> Option<&Result<Advice, String>> {
        let mut that_shot = None;
        if let Some(measure) = &mut self.played {
            let before = measure.run;
            that_shot = measure.step(simulations);
            simulations = simulations.saturating_sub(measure.run - before);
            // Nothing is searched before the shot played is measured.
            that_shot?;
        }
        if self.done.is_none() {
            let trials = self.level.schedule().samples[2];
            self.done = match &mut self.search {
                Search::Scene {
                    request,
                    shot,
                    cue,
                    search,
                } => match search.step(simulations) {
                    Poll::Ready(Ok(found)) => {
                        let ids: Vec<String> =
                            request.scene.balls.iter().map(|b| b.id.clone()).collect();
                        let mut shot = (**shot).clone();
                        shot.strike = Some((*cue, found.strike));
                        let (pots, leave) = played(&shot, *cue, &ids);
                        Some(Ok(Advice {
                            strike: found.strike,
                            p_success: found.p_success,
                            trials,
                            kind: found.kind,
                            pots,
                            leave,
                            played: that_shot,
                        }))
                    }
                    Poll::Ready(Err(why)) => Some(Err(why.clone())),
                    Poll::Pending => None,
                },
                Search::Game { game, search } => match search.step(simulations) {
                    Poll::Ready(Some(Decision {
                        command: Command::Shot { strike, call },
                        p_success,
                        kind,
                        ..
                    })) => {
                        let shot = game.shot_for(strike);
                        let (mut pots, leave) = played(&shot, game.cue_ball(), &game.ball_ids());
                        if let (Some(call), Some((_, pocket))) = (call, &mut pots) {
                            *pocket = pocket_name(game.table(), *call);
                        }
                        Some(Ok(Advice {
                            strike: *strike,
                            p_success: p_success.unwrap_or(0.0),
                            trials,
                            kind: kind.unwrap_or(Kind::Safety),
                            pots,
                            leave,
                            played: that_shot,
                        }))
                    }
                    Poll::Ready(Some(other)) => Some(Err(format!(
                        "the computer would not shoot: {:?}",
                        other.command
                    ))),
                    Poll::Ready(None) => Some(Err("the game is over".into())),
                    Poll::Pending => None,
                },
            };
        }
        self.done.as_ref()
    }

    /// The share of the search done, 0 to 1.
    pub fn fraction(&self) -> f64 {
        let search = match &self.search {
            Search::Scene { search, .. } => search.fraction(),
            Search::Game { search, .. } => search.fraction(),
        };
        match &self.played {
            // The measure's trials and the search's share the bar by halves.
            Some(m) if m.fraction() < 1.0 => 0.5 * m.fraction(),
            Some(_) => 0.5 + 0.5 * search,
            None => search,
        }
    }
}

/// `shot` played as meant: the first object ball it pots with the pocket's name, and where
/// the cue ball (ball `cue`) stops if it stays on the table. `ids` names the balls.
fn played(shot: &Shot, cue: usize, ids: &[String]) -> (Option<(String, String)>, Option<DVec2>) {
    let mut sim = Simulator::new();
    let Ok(outcome) = sim.run(shot) else {
        return (None, None);
    };
    let pots = outcome.events.iter().find_map(|e| match e.kind {
        EventKind::BallPocket { ball, pocket } if usize::from(ball) != cue => {
            let id = ids.get(usize::from(ball))?.clone();
            Some((id, pocket_name(shot.table, pocket)))
        }
        _ => None,
    });
    let leave = outcome
        .finals
        .get(cue)
        .filter(|b| b.motion != MotionState::Pocketed)
        .map(|b| b.pos);
    (pots, leave)
}

/// Whether `outcome` of a shot whose cue ball is ball 0 is a success as the advice counts
/// one: a target hit first and a target pocketed, the cue ball kept on the table.
pub fn succeeded(outcome: &Outcome, shot: &Shot, targets: &[u8]) -> bool {
    let facts = ShotFacts::from_outcome(outcome, shot.table);
    let hit = facts.first_contact.is_some_and(|b| targets.contains(&b));
    let potted = facts.object_balls_pocketed().any(|b| targets.contains(&b));
    hit && potted && !facts.scratched()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_games::eight_ball;
    use breakshot_shared::ai;
    use breakshot_shared::rules::Seat;

    const CUT: &str = include_str!("../../scenes/cut-shot.json");

    /// The share of `measure`'s strikes that succeed, measured at once: the chance
    /// measured, to check a quoted one.
    fn measured(mut measure: Measure) -> f64 {
        measure.step(usize::MAX).map_or(0.0, |c| c.share)
    }

    /// An advisor started on `request`.
    fn started(request: &Request) -> Advisor {
        Advisor::start(request.clone()).expect("an advisor")
    }

    /// `advisor` run to its advice, `per_step` simulations at a time, as the window runs it
    /// a frame at a time; the advice and how many steps it took.
    fn stepped(mut advisor: Advisor, per_step: usize) -> (Advice, usize) {
        for steps in 1..100_000 {
            if let Some(done) = advisor.step(per_step) {
                return (done.clone().expect("advice"), steps);
            }
        }
        panic!("the search does not end");
    }

    fn table() -> Game {
        Game::practice(&Scene::from_json(CUT).expect("a scene")).expect("a table")
    }

    #[test]
    fn the_stepped_advice_is_what_the_simulator_s_suggest_says_of_the_saved_scene() {
        let mut game = table();
        // After a shot, so the position is the table's own, not the file's.
        game.apply(
            Seat::A,
            &Command::Shot {
                strike: Strike {
                    speed: 1.5,
                    dir: DVec2::new(0.6, 0.8),
                    tip: DVec2::ZERO,
                    elevation_deg: 0.0,
                },
                call: None,
            },
        )
        .expect("a practice shot");
        let request = Request::for_table(&game, Level::new(2)).expect("a request");
        let (advice, frames) = stepped(started(&request), 3);
        assert!(frames > 2, "the search took several steps: {frames}");
        // What breakshot-sim suggest does with the scene file: parse it, find the balls by
        // id, and search once.
        let saved = Scene::from_json(&request.scene.to_json()).expect("the saved scene");
        let shot = saved.to_shot().expect("a shot");
        let index = |id: &str| saved.balls.iter().position(|b| b.id == id).expect("a ball");
        let targets: Vec<usize> = request.targets.iter().map(|t| index(t)).collect();
        let cli = Thinking::suggest(&shot, index("cue"), &targets, request.level, request.seed)
            .finish()
            .expect("a suggestion");
        assert_eq!(advice.strike, cli.strike);
        assert_eq!(advice.p_success, cli.p_success);
        assert_eq!(advice.kind, cli.kind);
        assert!(request
            .command_line("table.json")
            .starts_with("breakshot-sim suggest table.json --targets "));
    }

    #[test]
    fn the_quoted_chance_is_the_one_measured_under_the_level_s_noise() {
        // Figures (debug, 400 trials each) are printed for the record.
        for level in [2, 4] {
            let level = Level::new(level);
            let request = Request::for_table(&table(), level).expect("a request");
            let (advice, _) = stepped(started(&request), usize::MAX);
            let (shot, cue, targets) = request.indices().expect("indices");
            assert_eq!(cue, 0, "the scene's cue ball is ball 0");
            let targets: Vec<u8> = targets.iter().map(|&t| t as u8).collect();
            let trials = 400;
            let p = measured(Measure::new(
                Trial::scene(&shot, &targets),
                advice.strike,
                level,
                trials,
                0xC0FFEE,
            ));
            let sampling = libm::sqrt(p * (1.0 - p) / trials as f64);
            let both = libm::hypot(advice.error(), sampling).max(0.02);
            eprintln!(
                "level {}: quoted {:.3} ± {:.3} ({} trials), measured {p:.3} ± {sampling:.3}",
                level.number(),
                advice.p_success,
                advice.error(),
                advice.trials
            );
            assert!(
                (advice.p_success - p).abs() <= 3.0 * both,
                "level {}: quoted {} measured {p}",
                level.number(),
                advice.p_success
            );
        }
    }

    /// After a miss, the advice says the chance the shot missed had, measured under the
    /// same noise as `measured` measures it, and advises as it would have anyway.
    #[test]
    fn after_a_miss_the_shot_played_is_measured_beside_the_advice() {
        let level = Level::new(3);
        let request = Request::for_table(&table(), level).expect("a request");
        let (plain, _) = stepped(started(&request), usize::MAX);
        // The player's shot: the advised one, a degree off.
        let strike = Strike {
            dir: DVec2::from_angle(1f64.to_radians()).rotate(plain.strike.dir),
            ..plain.strike
        };
        let advisor = Advisor::after_miss(request.clone(), strike).expect("an advisor");
        let (advice, steps) = stepped(advisor, 5);
        assert!(
            steps > PLAYED_TRIALS / 5,
            "the trials were stepped too: {steps}"
        );
        let (shot, _, targets) = request.indices().expect("indices");
        let targets: Vec<u8> = targets.iter().map(|&t| t as u8).collect();
        let p = measured(Measure::new(
            Trial::scene(&shot, &targets),
            strike,
            level,
            PLAYED_TRIALS,
            request.seed,
        ));
        let played = advice.played.expect("the shot played measured");
        assert_eq!((played.share, played.trials), (p, PLAYED_TRIALS));
        assert!(p < 1.0, "a degree off misses sometimes: {p}");
        assert_eq!(advice.strike, plain.strike);
        assert_eq!(advice.p_success, plain.p_success);
        let line = advice.summary(level);
        assert!(
            line.starts_with(&format!("That shot: {:.0} ± ", 100.0 * p)),
            "{line}"
        );
    }

    #[test]
    fn a_rules_game_s_advice_is_the_computer_s_plan_for_the_player_to_move() {
        let game = eight_ball(3);
        let level = Level::new(1);
        let advisor = Advisor::for_game(&game, level);
        assert!(advisor.request().is_none());
        let (advice, _) = stepped(advisor, 5);
        let plan = ai::plan(&game, &Player::from(level), state_hash(game.balls())).expect("a plan");
        let Command::Shot { strike, .. } = plan.command else {
            panic!("a shot: {plan:?}");
        };
        assert_eq!(advice.strike, strike);
        assert_eq!(Some(advice.p_success), plan.p_success);
        assert_eq!(advice.kind, Kind::Break);
    }

    /// In a rules game, the shot missed is measured by the rules: a soft break is never a
    /// legal one, and the advice after it is the computer's own plan.
    #[test]
    fn after_a_miss_in_a_rules_game_the_shot_played_is_judged_by_the_rules() {
        let game = eight_ball(3);
        let level = Level::new(1);
        let soft = Strike {
            speed: 0.5,
            dir: DVec2::new(0.0, 1.0),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let run = |advisor| stepped(advisor, 5).0;
        let after = run(Advisor::for_game_after_miss(&game, level, soft, None));
        let plain = run(Advisor::for_game(&game, level));
        let played = after.played.expect("the shot missed measured");
        assert_eq!((played.share, played.trials), (0.0, PLAYED_TRIALS));
        assert_eq!(after.strike, plain.strike);
        assert!(plain.played.is_none());
        // The computer's break is measured as a success some of the time.
        let good = run(Advisor::for_game_after_miss(
            &game,
            level,
            plain.strike,
            None,
        ));
        assert!(good.played.expect("measured").share > 0.0, "{good:?}");
    }

    #[test]
    fn asking_again_goes_through_every_level_and_round() {
        let mut level = Level::new(3);
        let mut seen = Vec::new();
        for _ in 0..Level::MAX {
            level = next_level(level);
            seen.push(level.number());
        }
        seen.sort_unstable();
        assert_eq!(seen, (1..=Level::MAX).collect::<Vec<_>>());
        assert_eq!(level.number(), 3, "back where it began");
    }

    #[test]
    fn no_object_ball_no_advice() {
        let scene = Scene::from_json(r#"{"balls":[{"id":"cue","pos":[0.6,1.0]}]}"#).expect("scene");
        let game = Game::practice(&scene).expect("a table");
        let why = Request::for_table(&game, Level::new(3)).expect_err("nothing to pot");
        assert!(why.contains("no object ball"), "{why}");
    }
}
