//! Drills: a position with a goal the engine judges, scored over attempts. A drill file is
//! `{"name": ..., "scene": SCENE, "goal": GOAL}`, the scene one of the simulator's
//! (docs/scene.md) and the goal any of: `pot` (a ball's id), `pocket` (its pocket's name,
//! `lb` `lc` `lt` `rb` `rc` `rt`), `cue_stops_in` (`[[x0, y0], [x1, y1]]`, m),
//! `cushions_first` (cue-ball cushions before the first ball it hits) and `point` (a
//! three-cushion point: both object balls, three cushions before the second). A drill may
//! carry an `example`, a strike in the scene's format that makes it: the screen shows it
//! when asked, and the tests play every shipped drill's to prove it can be made. A `ladder`
//! lists further rungs, `[{"balls": [...], "example": STRIKE}, ...]`, each the scene's table
//! and physics with other balls: an attempt made climbs a rung, one missed goes down one.

use breakshot_shared::physics::{EventKind, MotionState, Outcome, Strike, Table};
use breakshot_shared::rules::three_cushion::{self, CaromFacts};
use breakshot_shared::rules::Game;
use breakshot_shared::scene::{Scene, SceneStrike};
use serde::Deserialize;

/// The drills that ship with the game, as their files (`client/drills/`), in the order the
/// menu lists them.
pub const SHIPPED: [&str; 4] = [
    include_str!("../../drills/straight-in.json"),
    include_str!("../../drills/cut-angles.json"),
    include_str!("../../drills/cut-to-a-zone.json"),
    include_str!("../../drills/three-cushion-corner.json"),
];

/// What an attempt must do; every part given must happen.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Goal {
    /// This ball is pocketed.
    #[serde(default)]
    pub pot: Option<String>,
    /// In this pocket (with `pot`).
    #[serde(default)]
    pub pocket: Option<String>,
    /// The cue ball stops inside this box, corners in scene coordinates (m).
    #[serde(default)]
    pub cue_stops_in: Option<[[f64; 2]; 2]>,
    /// The cue ball touches at least this many cushions before any ball.
    #[serde(default)]
    pub cushions_first: Option<u32>,
    /// The cue ball scores a three-cushion point: it touches both object balls and at
    /// least three cushions before the second.
    #[serde(default)]
    pub point: bool,
}

/// A drill as shipped or written by a player.
#[derive(Clone, Debug, PartialEq)]
pub struct Drill {
    /// Its name, as the screen and the scores name it.
    pub name: String,
    /// What an attempt must do, on every rung.
    pub goal: Goal,
    /// The positions attempts start from: one, or a ladder climbed a rung for each attempt
    /// made and gone down a rung for each missed.
    pub rungs: Vec<Rung>,
}

/// One position of a drill.
#[derive(Clone, Debug, PartialEq)]
pub struct Rung {
    /// The position an attempt starts from.
    pub scene: Scene,
    /// A strike that makes it, on the cue ball, if the drill's author gave one.
    pub example: Option<Strike>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDrill {
    name: String,
    scene: serde_json::Value,
    goal: Goal,
    #[serde(default)]
    example: Option<SceneStrike>,
    /// Further rungs: each the scene's table and physics with these balls.
    #[serde(default)]
    ladder: Vec<RawRung>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRung {
    balls: serde_json::Value,
    #[serde(default)]
    example: Option<SceneStrike>,
}

impl Drill {
    /// The drill in `text`; Err names what is wrong (a goal naming a ball that is not there,
    /// an unknown pocket, a scene the rules refuse), and on which rung of a ladder.
    pub fn from_json(text: &str) -> Result<Drill, String> {
        let raw: RawDrill =
            serde_json::from_str(text).map_err(|e| format!("invalid drill: {e}"))?;
        let goal = raw.goal;
        if goal == Goal::default() {
            return Err("the drill's goal asks for nothing".into());
        }
        let first = (raw.scene.clone(), raw.example);
        let further = raw.ladder.into_iter().map(|rung| {
            let mut scene = raw.scene.clone();
            scene["balls"] = rung.balls;
            (scene, rung.example)
        });
        let count = 1 + further.len();
        let rungs = std::iter::once(first)
            .chain(further)
            .enumerate()
            .map(|(k, (scene, example))| {
                Rung::read(&scene, example, &goal).map_err(|e| match count {
                    1 => e,
                    _ => format!("rung {} of {count}: {e}", k + 1),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Drill {
            name: raw.name,
            goal,
            rungs,
        })
    }

    /// The first position (the only one but in a ladder).
    pub fn first(&self) -> &Rung {
        &self.rungs[0]
    }

    /// The shipped drills, read (a shipped drill that does not read is a bug the tests
    /// catch, so here it is left out rather than stopping the menu).
    pub fn shipped() -> Vec<Drill> {
        SHIPPED
            .iter()
            .filter_map(|text| Drill::from_json(text).ok())
            .collect()
    }

    /// Whether an attempt from rung `rung` whose shot came out as `outcome` (balls indexed
    /// as the rung's scene's, the cue ball `cue`) met the goal.
    pub fn judge(&self, rung: usize, outcome: &Outcome, cue: usize) -> bool {
        let goal = &self.goal;
        let Some(Rung { scene, .. }) = self.rungs.get(rung) else {
            return false;
        };
        let index = |id: &str| scene.balls.iter().position(|b| b.id == id);
        let table = Table::new(scene.table);
        let potted = goal.pot.as_deref().is_none_or(|id| {
            let ball = index(id);
            outcome.events.iter().any(|e| match e.kind {
                EventKind::BallPocket { ball: b, pocket } => {
                    Some(usize::from(b)) == ball
                        && goal.pocket.as_deref().is_none_or(|name| {
                            table.pockets.get(usize::from(pocket)).map(|p| p.name) == Some(name)
                        })
                }
                _ => false,
            })
        });
        let stopped = goal.cue_stops_in.is_none_or(|[a, b]| {
            outcome.finals.get(cue).is_some_and(|f| {
                f.motion != MotionState::Pocketed
                    && (a[0].min(b[0])..=a[0].max(b[0])).contains(&f.pos.x)
                    && (a[1].min(b[1])..=a[1].max(b[1])).contains(&f.pos.y)
            })
        });
        let cushions = goal.cushions_first.is_none_or(|n| {
            let cue = cue as u16;
            let mut rails = 0;
            for e in &outcome.events {
                match e.kind {
                    EventKind::BallCushion { ball, .. } if ball == cue => rails += 1,
                    EventKind::BallBall { a, b } if a == cue || b == cue => break,
                    _ => {}
                }
            }
            rails >= n
        });
        let point = !goal.point || {
            let facts = CaromFacts::from_outcome(outcome, cue as u8);
            three_cushion::judge(&facts, cue as u8, None, false).point
        };
        potted && stopped && cushions && point
    }
}

impl Rung {
    /// A rung's scene checked against the goal, and its example read.
    fn read(
        scene: &serde_json::Value,
        example: Option<SceneStrike>,
        goal: &Goal,
    ) -> Result<Rung, String> {
        let scene = Scene::from_json(&scene.to_string()).map_err(|e| e.to_string())?;
        let cue = Game::practice(&scene)
            .map_err(|e| e.to_string())?
            .cue_ball();
        if let Some(ball) = &goal.pot {
            if !scene.balls.iter().any(|b| &b.id == ball) {
                return Err(format!(
                    "the goal pots ball \"{ball}\", which is not on the table"
                ));
            }
        }
        if let Some(pocket) = &goal.pocket {
            if goal.pot.is_none() {
                return Err("the goal names a pocket but no ball to pot".into());
            }
            if !Table::new(scene.table)
                .pockets
                .iter()
                .any(|p| p.name == pocket)
            {
                return Err(format!("the table has no pocket \"{pocket}\""));
            }
        }
        if goal.point && scene.balls.len() != 3 {
            return Err(format!(
                "a three-cushion point needs the cue ball and two object balls, not {} balls",
                scene.balls.len()
            ));
        }
        let example = match example {
            None => None,
            Some(strike) => {
                if strike.ball != scene.balls[cue].id {
                    return Err(format!(
                        "the example strikes \"{}\", not the cue ball \"{}\"",
                        strike.ball, scene.balls[cue].id
                    ));
                }
                let with = Scene {
                    strike: Some(strike),
                    ..scene.clone()
                };
                let shot = with.to_shot().map_err(|e| format!("the example: {e}"))?;
                shot.strike.map(|(_, s)| s)
            }
        };
        Ok(Rung { scene, example })
    }
}

/// The rung a ladder of `rungs` goes to from `rung` after an attempt: up one when it was
/// made (the top rung played again), down one when it was missed (the first played again).
pub fn climb(rung: usize, made: bool, rungs: usize) -> usize {
    if made {
        (rung + 1).min(rungs.saturating_sub(1))
    } else {
        rung.saturating_sub(1)
    }
}

/// A drill's score over attempts: "7 of 10; best streak 4".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Score {
    /// Attempts that met the goal.
    pub made: u32,
    /// Attempts in all.
    pub attempts: u32,
    /// Made in a row, now.
    pub streak: u32,
    /// The longest run of made attempts.
    pub best: u32,
}

impl Score {
    /// Counts one attempt.
    pub fn attempt(&mut self, made: bool) {
        self.attempts += 1;
        if made {
            self.made += 1;
            self.streak += 1;
            self.best = self.best.max(self.streak);
        } else {
            self.streak = 0;
        }
    }

    /// As the screen says it.
    pub fn line(&self) -> String {
        format!(
            "{} of {}; best streak {}",
            self.made, self.attempts, self.best
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{Simulator, Strike};
    use glam::DVec2;

    const STRAIGHT: &str = include_str!("../../drills/straight-in.json");

    /// Every drill that ships reads, its example makes it, and the goal is not met by any
    /// shot at all: the example turned by up to three degrees either way misses some.
    #[test]
    fn every_shipped_drill_can_be_made_and_missed() {
        let drills = Drill::shipped();
        assert_eq!(drills.len(), SHIPPED.len(), "every shipped drill reads");
        let mut sim = Simulator::new();
        for drill in drills {
            for (k, rung) in drill.rungs.iter().enumerate() {
                let name = format!("{} (rung {})", drill.name, k + 1);
                let cue = Game::practice(&rung.scene).expect("a table").cue_ball();
                let example = rung.example.unwrap_or_else(|| panic!("{name}: an example"));
                let mut shot = rung.scene.to_shot().expect("a shot");
                let mut made = |strike: Strike| {
                    shot.strike = Some((cue, strike));
                    drill.judge(k, sim.run(&shot).expect("simulated"), cue)
                };
                assert!(made(example), "{name}: the example makes it");
                let missed = (-15..=15).filter(|k| {
                    let turn = (0.2 * f64::from(*k)).to_radians();
                    let dir = DVec2::from_angle(turn).rotate(example.dir);
                    !made(Strike { dir, ..example })
                });
                assert!(missed.count() > 10, "{name}: turning the cue misses");
            }
        }
    }

    /// Why the straight-in drill is refused with `from` written as `to`.
    fn refused_when(from: &str, to: &str, what: &str) -> String {
        Drill::from_json(&STRAIGHT.replace(from, to)).expect_err(what)
    }

    #[test]
    fn a_drill_s_example_must_strike_its_cue_ball_and_a_point_needs_three_balls() {
        let why = refused_when(
            "\"ball\": \"cue\"",
            "\"ball\": \"1\"",
            "the example strikes the 1",
        );
        assert!(why.contains("not the cue ball"), "{why}");
        let why = refused_when(
            "\"pocket\": \"lt\"",
            "\"pocket\": \"lt\", \"point\": true",
            "a point with one object ball",
        );
        assert!(why.contains("two object balls"), "{why}");
    }

    #[test]
    fn a_made_and_a_missed_attempt_are_judged_and_scored() {
        let drill = Drill::from_json(STRAIGHT).expect("a drill");
        let mut shot = drill.first().scene.to_shot().expect("a shot");
        let cue = 0;
        // Straight at the 1 (on the line to the top-left corner), and then wide of it.
        let mut score = Score::default();
        let at = DVec2::new(-0.4, 0.48).normalize();
        for (dir, made) in [(at, true), (DVec2::from_angle(0.3).rotate(at), false)] {
            shot.strike = Some((
                cue,
                Strike {
                    speed: 2.5,
                    dir,
                    tip: DVec2::ZERO,
                    elevation_deg: 0.0,
                },
            ));
            let outcome = Simulator::new().run(&shot).expect("simulated").clone();
            assert_eq!(drill.judge(0, &outcome, cue), made, "{dir}");
            score.attempt(made);
        }
        assert_eq!(score.line(), "1 of 2; best streak 1");
    }

    #[test]
    fn the_rules_verdict_of_a_practice_shot_is_judged_like_its_simulation() {
        use breakshot_shared::rules::{Command, Seat};
        let drill = Drill::from_json(STRAIGHT).expect("a drill");
        let mut game = Game::practice(&drill.first().scene).expect("a table");
        let strike = Strike {
            speed: 2.5,
            dir: DVec2::new(-0.4, 0.48).normalize(),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let verdict = game
            .apply(Seat::A, &Command::Shot { strike, call: None })
            .expect("a shot");
        let outcome = verdict.outcome.expect("the trajectory");
        assert!(drill.judge(0, &outcome, game.cue_ball()));
    }

    #[test]
    fn a_ladder_is_climbed_by_made_attempts_and_gone_down_by_missed_ones() {
        let mut rung = 0;
        let mut seen = Vec::new();
        for made in [false, true, true, true, false, false, false] {
            rung = climb(rung, made, 3);
            seen.push(rung);
        }
        assert_eq!(seen, [0, 1, 2, 2, 1, 0, 0]);
        assert_eq!(climb(0, true, 1), 0, "a single position stays");
    }

    #[test]
    fn a_ladder_s_rungs_are_read_and_a_bad_rung_is_named() {
        let drill = Drill::from_json(STRAIGHT).expect("a drill");
        assert_eq!(drill.rungs.len(), 3, "the straight-in ladder");
        let far = &drill.rungs[2].scene;
        assert_eq!(far.table, drill.first().scene.table);
        assert_ne!(far.balls, drill.first().scene.balls);
        let why = refused_when("[1.032, 1.302]", "[0.2, 2.3]", "two balls on one spot");
        assert!(why.starts_with("rung 3 of 3: "), "{why}");
    }

    #[test]
    fn a_goal_naming_a_ball_that_is_not_there_is_refused() {
        let why = refused_when("\"pot\": \"1\"", "\"pot\": \"9\"", "no 9 on the table");
        assert!(why.contains("\"9\""), "{why}");
        let why = refused_when("\"pocket\": \"lt\"", "\"pocket\": \"xx\"", "no such pocket");
        assert!(why.contains("xx"), "{why}");
        assert!(Drill::from_json("{").is_err());
    }
}
