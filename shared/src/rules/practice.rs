//! Practice: a sandbox with no turns and no fouls. Any ball can be placed anywhere free, a
//! whole layout can be loaded (for example from a scene file), and any shot can be played.

use glam::DVec2;

use crate::physics::{engine, BallState, Effects, Models, MotionState, Params, Shot, Strike};
use crate::scene::{Scene, SceneBall};

use super::facts::ShotFacts;
use super::{
    ball_name, capitalise, off_table, pocket_name, rack, Game, InHand, Judged, Next, RuleError,
    Seat, Settings, Variant,
};

/// A practice table a player set up (the window's practice: a rack, or any scene file): its
/// own physics, its balls' names, which ball is the cue ball and where it comes back to.
/// A practice room of the server has none and keeps the plain practice rules, so the
/// records of those rooms replay as they were played.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Sandbox {
    /// The scene's names of the balls, index = ball.
    ids: Vec<String>,
    /// The ball struck.
    cue: usize,
    /// Where the cue ball started: a pocketed cue ball comes back here, or as near as is
    /// free up the table's long axis.
    home: DVec2,
    params: Params,
    models: Models,
    effects: Effects,
    horizon: Option<f64>,
}

impl Game {
    /// A practice table laid out as `scene` is: its table, physics and balls (at rest: a
    /// scene's velocities and spins are not kept). The cue ball is the one the scene's
    /// strike names, else the ball called "cue" or "0", else the first. Shots go through
    /// [`Game::apply`] like any game's; a pocketed cue ball comes back to where it started.
    pub fn practice(scene: &Scene) -> Result<Game, RuleError> {
        let shot = scene
            .to_shot()
            .map_err(|e| RuleError::NotAllowed(format!("the scene is not valid: {e}")))?;
        if shot.balls.is_empty() {
            return Err(RuleError::NotAllowed(
                "the scene has no ball: practice needs at least one".into(),
            ));
        }
        let ids: Vec<String> = scene.balls.iter().map(|b| b.id.clone()).collect();
        let named = ids.iter().position(|id| id == "cue" || id == "0");
        let cue = shot.strike.map(|(i, _)| i).or(named).unwrap_or(0);
        let settings = Settings {
            table: shot.table,
            ..Settings::offline()
        };
        let mut game = Game::new(Variant::Practice, settings, 0);
        game.balls = shot
            .balls
            .iter()
            .map(|b| BallState::at_rest(b.pos))
            .collect();
        game.sandbox = Some(Box::new(Sandbox {
            ids,
            cue,
            home: game.balls[cue].pos,
            params: shot.params,
            models: shot.models,
            effects: shot.effects,
            horizon: shot.horizon,
        }));
        Ok(game)
    }

    /// The names of the balls of a practice table set up from a scene, index = ball.
    pub fn scene_ids(&self) -> Option<&[String]> {
        self.sandbox.as_ref().map(|s| s.ids.as_slice())
    }

    /// The names scenes give this game's balls, index = ball: a practice table's own, else
    /// the pool balls by number ("cue" for the cue ball), the three-cushion balls by colour,
    /// the snooker balls as the scene format names them.
    pub fn ball_ids(&self) -> Vec<String> {
        if let Some(ids) = self.scene_ids() {
            return ids.to_vec();
        }
        let count = self.balls.len() as u8;
        match self.variant {
            Variant::ThreeCushion { .. } => ["white", "yellow", "red"].map(String::from).to_vec(),
            Variant::Snooker { .. } => (0..count).map(super::snooker::table::scene_id).collect(),
            _ => (0..count)
                .map(|n| if n == 0 { "cue".into() } else { n.to_string() })
                .collect(),
        }
    }

    /// The table as it stands, as a scene file of the simulator's: its table, physics and
    /// the balls on the cloth (those off the table are left out), no strike.
    pub fn scene(&self) -> Scene {
        let shot = match &self.sandbox {
            Some(sandbox) => sandbox.shot(self, Vec::new(), None),
            None => Shot::new(self.table(), Vec::new()),
        };
        let balls = self
            .ball_ids()
            .into_iter()
            .zip(&self.balls)
            .filter(|(_, b)| b.motion != MotionState::Pocketed)
            .map(|(id, b)| SceneBall {
                id,
                pos: b.pos.to_array(),
                vel: [0.0; 2],
                spin: [0.0; 3],
            })
            .collect();
        Scene {
            table: shot.table,
            physics: shot.params,
            models: shot.models,
            effects: shot.effects,
            horizon: shot.horizon,
            balls,
            strike: None,
        }
    }

    /// A practice table laid out as `variant`'s opening position (its rack shuffled by
    /// `seed`: a 9-ball diamond, the three-cushion start on the carom table, ...).
    pub fn practice_rack(variant: Variant, seed: u64) -> Result<Game, RuleError> {
        Game::practice(&Game::new(variant, Settings::offline(), seed).scene())
    }
}

impl Sandbox {
    pub(super) fn cue(&self) -> usize {
        self.cue
    }

    pub(super) fn params(&self) -> Params {
        self.params
    }

    /// The physics shot of `balls` with `strike` on the cue ball.
    pub(super) fn shot(&self, game: &Game, balls: Vec<BallState>, strike: Option<Strike>) -> Shot {
        Shot {
            table: game.table(),
            params: self.params,
            models: self.models,
            effects: self.effects,
            horizon: self.horizon,
            balls,
            strike: strike.map(|s| (self.cue, s)),
        }
    }
}

/// May `ball` lie at `pos` on a set-up practice table? The engine's own check decides, with
/// the table's physics, so a place accepted here is one every shot from it accepts.
pub(super) fn sandbox_free(game: &Game, sandbox: &Sandbox, ball: usize, pos: DVec2) -> bool {
    let mut balls = game.balls.clone();
    let Some(b) = balls.get_mut(ball) else {
        return false;
    };
    *b = BallState::at_rest(pos);
    engine::check(&sandbox.shot(game, balls, None)).is_ok()
}

/// After a set-up practice table's shot: balls a horizon stopped mid-roll stay where they
/// are, at rest, and a pocketed cue ball comes back to its starting place or the nearest
/// free place up the table's long axis (it stays off the table when none is free).
fn settle_sandbox(game: &mut Game) {
    let Some(sandbox) = game.sandbox.take() else {
        return;
    };
    for b in &mut game.balls {
        if b.motion != MotionState::Pocketed {
            *b = BallState::at_rest(b.pos);
        }
    }
    if game.balls[sandbox.cue].motion == MotionState::Pocketed {
        let step = 2.1 * sandbox.params.ball_radius;
        let spots = (0..200).flat_map(|k| {
            let d = DVec2::new(0.0, f64::from(k) * step);
            [sandbox.home + d, sandbox.home - d]
        });
        if let Some(spot) = spots
            .into_iter()
            .find(|&p| sandbox_free(game, &sandbox, sandbox.cue, p))
        {
            game.balls[sandbox.cue] = BallState::at_rest(spot);
        }
    }
    game.sandbox = Some(sandbox);
}

/// Practice layouts hold the cue ball and the fifteen object balls.
pub(super) const PRACTICE_BALLS: usize = 16;

pub(super) fn check_place_ball(
    game: &Game,
    ball: u8,
    pos: Option<[f64; 2]>,
) -> Result<(), RuleError> {
    let index = usize::from(ball);
    if index >= game.balls.len() {
        return Err(RuleError::IllegalPlacement(format!(
            "there is no ball {ball} (0 = cue ball, up to {})",
            game.balls.len() - 1
        )));
    }
    match pos {
        None => Ok(()),
        Some(p) if game.is_free(index, DVec2::from_array(p)) => Ok(()),
        Some(_) => Err(RuleError::IllegalPlacement(format!(
            "{} must lie on the cloth, clear of the cushions, pockets and other balls",
            ball_name(ball)
        ))),
    }
}

pub(super) fn place_ball(game: &mut Game, ball: u8, pos: Option<[f64; 2]>) {
    if let Some(b) = game.balls.get_mut(usize::from(ball)) {
        *b = match pos {
            Some(p) => BallState::at_rest(DVec2::from_array(p)),
            None => off_table(),
        };
    }
}

pub(super) fn check_layout(game: &Game, layout: &[Option<[f64; 2]>]) -> Result<(), RuleError> {
    if layout.len() != game.balls.len() {
        return Err(RuleError::IllegalPlacement(format!(
            "a layout gives {} balls (0 = cue ball), not {}",
            game.balls.len(),
            layout.len()
        )));
    }
    let balls = layout_balls(layout);
    for (i, b) in balls.iter().enumerate() {
        if b.motion != MotionState::Pocketed && !rack::is_free(&balls, i, b.pos, game.table()) {
            return Err(RuleError::IllegalPlacement(format!(
                "{} must lie on the cloth, clear of the cushions, pockets and other balls",
                ball_name(i as u8)
            )));
        }
    }
    Ok(())
}

fn layout_balls(layout: &[Option<[f64; 2]>]) -> Vec<BallState> {
    layout
        .iter()
        .map(|p| match p {
            Some(p) => BallState::at_rest(DVec2::from_array(*p)),
            None => off_table(),
        })
        .collect()
}

pub(super) fn load_layout(game: &mut Game, layout: &[Option<[f64; 2]>]) {
    game.balls = layout_balls(layout);
    game.phase = super::Phase::Shooting {
        in_hand: Some(InHand::Anywhere),
        options: Vec::new(),
        push_out: false,
    };
}

/// The practice layout of a scene file: its balls must be named `cue` (or `0`) and `1` to
/// `15`; balls it does not name are off the table. Velocities, spins and the strike of the
/// scene are not part of a layout (shots are played with [`super::Command::Shot`]).
pub fn layout_from_scene(scene: &Scene) -> Result<Vec<Option<[f64; 2]>>, RuleError> {
    let mut layout = vec![None; PRACTICE_BALLS];
    for b in &scene.balls {
        let number = match b.id.as_str() {
            "cue" => Some(0),
            id => id.parse::<usize>().ok().filter(|&n| n < PRACTICE_BALLS),
        };
        let Some(n) = number else {
            return Err(RuleError::IllegalPlacement(format!(
                "scene ball \"{}\" is not a pool ball (use \"cue\" and \"1\" to \"15\")",
                b.id
            )));
        };
        if layout[n].is_some() {
            return Err(RuleError::IllegalPlacement(format!(
                "scene names {} twice",
                ball_name(n as u8)
            )));
        }
        layout[n] = Some(b.pos);
    }
    Ok(layout)
}

/// A practice shot is never a foul: report what fell, and play on (the cue ball stays in
/// hand, as it always is in practice).
pub(super) fn judge(game: &mut Game, shooter: Seat, facts: &ShotFacts) -> Judged {
    // A scene's own names where they are not the pool numbers ("the red ball").
    let name = |b: u8| match game.scene_ids().and_then(|ids| ids.get(usize::from(b))) {
        Some(id) if *id != b.to_string() && !(b == 0 && id == "cue") => format!("the {id} ball"),
        _ => ball_name(b),
    };
    let reasons = facts
        .pocketed
        .iter()
        .map(|&(b, p)| {
            format!(
                "{} fell in the {}",
                capitalise(&name(b)),
                pocket_name(game.table(), p)
            )
        })
        .collect();
    settle_sandbox(game);
    Judged {
        reasons,
        foul: false,
        next: Next::Shoot {
            seat: shooter,
            in_hand: Some(InHand::Anywhere),
            options: Vec::new(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::{simulate, Strike};
    use crate::rules::{Command, Phase};

    fn table(json: &str) -> Game {
        Game::practice(&Scene::from_json(json).expect("valid scene")).expect("a practice table")
    }

    fn shoot(game: &mut Game, strike: Strike) -> super::super::Verdict {
        let shot = Command::Shot { strike, call: None };
        game.apply(Seat::A, &shot).expect("a legal shot")
    }

    #[test]
    fn a_shot_plays_the_scenes_physics_and_its_final_table_stays() {
        let mut game = table(
            r#"{"table":"9ft","physics":{"mu_roll":0.02},
                "balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[0.15,0.15]}]}"#,
        );
        assert_eq!(game.params().mu_roll, 0.02);
        let strike = Strike::at_angle(3.0, 225.0, DVec2::ZERO);
        let expected = simulate(&game.shot_for(&strike)).expect("valid");
        let verdict = shoot(&mut game, strike);
        assert_eq!(verdict.shot.expect("a shot").hash, expected.hash());
        assert_eq!(game.balls()[1].motion, MotionState::Pocketed);
        assert_eq!(
            verdict.reasons,
            vec!["The 1 fell in the bottom-left corner"]
        );
    }

    #[test]
    fn a_scratch_brings_the_cue_ball_back_to_where_it_started() {
        // The cue ball rolls straight into the bottom-left pocket.
        let mut game =
            table(r#"{"balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[1.0,2.0]}]}"#);
        shoot(&mut game, Strike::at_angle(3.0, 225.0, DVec2::ZERO));
        assert_eq!(game.balls()[0], BallState::at_rest(DVec2::new(0.3, 0.3)));
        assert!(matches!(
            game.phase(),
            Phase::Shooting {
                in_hand: Some(InHand::Anywhere),
                ..
            }
        ));
    }

    #[test]
    fn a_scratch_onto_a_taken_start_comes_back_on_the_nearest_free_place_up_the_table() {
        let mut game =
            table(r#"{"balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[1.0,2.0]}]}"#);
        // The cue ball goes nearer the pocket and the 1 takes its starting place.
        for command in [
            Command::PlaceCueBall { pos: [0.15, 0.15] },
            Command::PlaceBall {
                ball: 1,
                pos: Some([0.3, 0.3]),
            },
        ] {
            game.apply(Seat::A, &command).expect("a free place");
        }
        shoot(&mut game, Strike::at_angle(2.0, 225.0, DVec2::ZERO));
        let back = game.balls()[0];
        assert_eq!(back.motion, MotionState::Stationary);
        assert_eq!(back.pos.x, 0.3);
        let off = (back.pos.y - 0.3).abs();
        assert!(off > 0.05 && off < 0.07, "{back:?}");
    }

    #[test]
    fn the_ball_the_strike_names_is_the_cue_ball_and_balls_keep_their_scene_names() {
        let mut game = table(
            r#"{"balls":[{"id":"a","pos":[0.3,0.3]},{"id":"b","pos":[0.6,0.6]}],
                "strike":{"ball":"b","speed":3.0,"angle_deg":225}}"#,
        );
        assert_eq!(game.cue_ball(), 1);
        assert_eq!(
            game.scene_ids(),
            Some(&["a".to_string(), "b".to_string()][..])
        );
        // b drives a into the bottom-left pocket, and follows it in: b comes back.
        let verdict = shoot(&mut game, Strike::at_angle(3.0, 225.0, DVec2::ZERO));
        assert!(verdict
            .reasons
            .contains(&"The a ball fell in the bottom-left corner".into()));
        assert_eq!(game.balls()[1].motion, MotionState::Stationary);
    }

    #[test]
    fn a_horizon_leaves_the_balls_where_it_stopped_them_at_rest() {
        let mut game = table(r#"{"horizon":0.2,"balls":[{"id":"cue","pos":[0.3,0.3]}]}"#);
        shoot(&mut game, Strike::at_angle(2.0, 90.0, DVec2::ZERO));
        let cue = game.balls()[0];
        assert_eq!(cue.motion, MotionState::Stationary);
        assert!(cue.pos.y > 0.5, "{cue:?}");
    }

    #[test]
    fn placements_on_a_ball_off_the_cloth_or_not_a_number_are_refused_and_change_nothing() {
        let mut game = table(
            r#"{"table":"carom","balls":[{"id":"white","pos":[0.4,0.4]},{"id":"red","pos":[0.7,1.0]}]}"#,
        );
        let before = game.clone();
        for pos in [[0.7, 1.0], [-0.1, 0.5], [f64::NAN, 0.5]] {
            let place = Command::PlaceCueBall { pos };
            assert!(game.apply(Seat::A, &place).is_err(), "{pos:?}");
        }
        assert_eq!(game, before);
        game.apply(Seat::A, &Command::PlaceCueBall { pos: [0.4, 0.8] })
            .expect("a free place");
        assert_eq!(game.balls()[0].pos, DVec2::new(0.4, 0.8));
    }

    #[test]
    fn a_scene_with_no_ball_or_a_broken_one_is_refused() {
        for json in [
            r#"{"balls":[]}"#,
            r#"{"balls":[{"id":"cue","pos":[9.0,9.0]}]}"#,
        ] {
            let scene = Scene::from_json(json);
            if let Ok(scene) = scene {
                assert!(Game::practice(&scene).is_err(), "{json}");
            }
        }
    }

    #[test]
    fn a_table_saved_as_a_scene_opens_as_the_same_table() {
        for variant in [
            Variant::NineBall,
            Variant::three_cushion(),
            Variant::snooker(),
        ] {
            let game = Game::practice_rack(variant, 7).expect("a rack");
            let scene = game.scene();
            let again = Game::practice(&Scene::from_json(&scene.to_json()).expect("valid"))
                .expect("a practice table");
            assert_eq!(again.balls(), game.balls(), "{variant:?}");
            assert_eq!(again.ball_ids(), game.ball_ids(), "{variant:?}");
            assert_eq!(again.params(), game.params(), "{variant:?}");
            assert_eq!(again.scene(), scene, "{variant:?}");
        }
    }
}

#[cfg(test)]
mod position_tests {
    use crate::rules::Game;
    use crate::scene::Scene;
    use crate::scene_code;

    /// A practice table from `json`, or the reason it is refused.
    fn table(json: &str) -> Result<Game, String> {
        Game::practice(&Scene::from_json(json).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn overlapping_balls_or_a_ball_off_the_cloth_are_refused_with_a_reason() {
        let overlap =
            table(r#"{"balls":[{"id":"cue","pos":[0.6,1.0]},{"id":"1","pos":[0.61,1.0]}]}"#);
        let off = table(r#"{"balls":[{"id":"cue","pos":[0.6,1.0]},{"id":"1","pos":[3.0,1.0]}]}"#);
        let why = overlap.expect_err("overlapping balls");
        assert!(why.contains("overlap"), "{why}");
        let why = off.expect_err("a ball off the cloth");
        assert!(why.contains("playing surface"), "{why}");
        // The same positions as codes: they decode, and the table refuses them the same way.
        let fine = r#"{"balls":[{"id":"cue","pos":[0.6,1.0]},{"id":"1","pos":[0.9,1.0]}]}"#;
        for (x, what) in [(0.61, "overlap"), (3.0, "playing surface")] {
            let mut scene = Scene::from_json(fine).expect("a scene");
            scene.balls[1].pos[0] = x;
            let code = scene_code::encode(&scene).expect("a code");
            let back = scene_code::decode(&code).expect("decodes");
            let why = Game::practice(&back).expect_err("refused from its code");
            assert!(why.to_string().contains(what), "{why}");
        }
    }
}
