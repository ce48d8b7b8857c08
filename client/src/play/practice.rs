//! The offline practice table: no rules, no server. Shots are simulated here and shown as
//! they play; a pocketed cue ball comes back in hand.

use breakshot_shared::physics::{
    engine, simulate, BallState, Effects, Models, MotionState, Params, Shot, ShotError, Strike,
    TableKind,
};
use breakshot_shared::scene::{Scene, SceneError};
use glam::DVec2;

use breakshot_shared::rules::{rack, Game, Settings, Variant};
use breakshot_shared::scene::SceneBall;

use super::aim::Aim;
use crate::view::{palette, Playback};

#[derive(Debug, thiserror::Error, PartialEq)]
/// Why a practice action was refused.
pub enum PracticeError {
    #[error("{0}")]
    /// The scene is not valid.
    Scene(#[from] SceneError),
    #[error("the balls are still moving")]
    /// A shot is playing.
    Busy,
    #[error("the cue ball is pocketed: place it first")]
    /// The cue ball is off the table.
    CueOffTable,
    #[error("the cue ball cannot go there: {0}")]
    /// The cue ball cannot go there.
    IllegalPlacement(String),
    #[error("invalid shot: {0}")]
    /// The engine refused the shot.
    Shot(#[from] ShotError),
}

/// The practice table.
#[derive(Clone, Debug)]
pub struct Practice {
    /// The table played on.
    pub table: TableKind,
    /// Physical parameters.
    pub params: Params,
    /// Collision models.
    pub models: Models,
    /// Optional effects.
    pub effects: Effects,
    /// When a shot stops being simulated (s), if before every ball rests.
    pub horizon: Option<f64>,
    /// The balls' names in the scene.
    pub ids: Vec<String>,
    /// The balls at rest between shots (scene coordinates).
    pub balls: Vec<BallState>,
    /// Index of the cue ball.
    pub cue: usize,
    /// Balls pocketed, in the order they fell.
    pub pocketed: Vec<usize>,
    /// The cue ball may be moved before the next shot.
    pub in_hand: bool,
    /// The shot being shown, if any.
    pub playback: Option<Playback>,
    /// The set-up a scene file came with.
    pub scene_aim: Option<Aim>,
    /// State hash of the last shot's final table.
    pub last_hash: Option<u64>,
    /// Where the cue ball started, for re-spotting it after a scratch.
    home: DVec2,
}

impl Practice {
    /// An 8-ball rack on `table` (shuffled by `seed`) with the cue ball in hand.
    pub fn rack(table: TableKind, seed: u64) -> Practice {
        let params = Params::default();
        let balls = rack::eight_ball(table, seed);
        let home = balls[0].pos;
        Practice {
            table,
            params,
            models: Models::default(),
            effects: Effects::default(),
            horizon: None,
            ids: rack_ids(balls.len()),
            balls,
            cue: 0,
            pocketed: Vec::new(),
            in_hand: true,
            playback: None,
            scene_aim: None,
            last_hash: None,
            home,
        }
    }

    /// The table of a scene file. The cue ball is the one the strike names, else "cue" or
    /// "0", else the first ball; the scene's strike becomes the initial set-up.
    pub fn from_scene(scene: &Scene) -> Result<Practice, PracticeError> {
        let shot = scene.to_shot()?;
        if shot.balls.is_empty() {
            return Err(SceneError("balls: practice needs at least one ball".into()).into());
        }
        let ids: Vec<String> = scene.balls.iter().map(|b| b.id.clone()).collect();
        let named = ids.iter().position(|id| id == "cue" || id == "0");
        let cue = shot.strike.map(|(i, _)| i).or(named).unwrap_or(0);
        // Practice starts from rest: a scene's initial velocities are not kept.
        let balls: Vec<BallState> = shot
            .balls
            .iter()
            .map(|b| BallState::at_rest(b.pos))
            .collect();
        Ok(Practice {
            table: shot.table,
            params: shot.params,
            models: shot.models,
            effects: shot.effects,
            horizon: shot.horizon,
            home: balls[cue].pos,
            ids,
            balls,
            cue,
            pocketed: Vec::new(),
            in_hand: false,
            playback: None,
            scene_aim: shot.strike.map(|(_, s)| Aim::from_strike(&s)),
            last_hash: None,
        })
    }

    /// True while a shot is being shown.
    pub fn busy(&self) -> bool {
        self.playback.is_some()
    }

    /// The balls as shown now.
    pub fn shown_balls(&self) -> Vec<BallState> {
        match &self.playback {
            Some(p) => p.balls(),
            None => self.balls.clone(),
        }
    }

    /// Balls to show in the tray now, in the order they fell.
    pub fn shown_pocketed(&self) -> Vec<usize> {
        let mut all = self.pocketed.clone();
        if let Some(p) = &self.playback {
            all.extend(p.pocketed_so_far());
        }
        all
    }

    /// The shot the table would play with `strike` on the cue ball.
    pub fn shot(&self, strike: Strike) -> Shot {
        Shot {
            table: self.table,
            params: self.params,
            models: self.models,
            effects: self.effects,
            horizon: self.horizon,
            balls: self.balls.clone(),
            strike: Some((self.cue, strike)),
        }
    }

    /// Plays a shot: simulates it and starts showing it.
    pub fn shoot(&mut self, strike: Strike) -> Result<(), PracticeError> {
        if self.busy() {
            return Err(PracticeError::Busy);
        }
        if self.balls[self.cue].motion == MotionState::Pocketed {
            return Err(PracticeError::CueOffTable);
        }
        let outcome = simulate(&self.shot(strike))?;
        self.last_hash = Some(outcome.hash());
        self.in_hand = false;
        self.playback = Some(Playback::new(outcome, self.cue));
        Ok(())
    }

    /// Moves the animation on; when the shot is over its final table becomes the table.
    pub fn tick(&mut self, wall_dt: f64, speed: f64) {
        let Some(p) = &mut self.playback else { return };
        p.advance(wall_dt, speed);
        if p.finished() {
            self.settle();
        }
    }

    /// Ends the shot being shown at once.
    pub fn skip(&mut self) {
        if let Some(p) = &mut self.playback {
            p.finish();
            self.settle();
        }
    }

    fn settle(&mut self) {
        let Some(p) = self.playback.take() else {
            return;
        };
        self.pocketed.extend(p.pocketed_so_far());
        // A horizon may stop balls mid-roll: practice keeps them where they are, at rest.
        self.balls = p
            .outcome()
            .finals
            .iter()
            .map(|b| match b.motion {
                MotionState::Pocketed => *b,
                _ => BallState::at_rest(b.pos),
            })
            .collect();
        if self.balls[self.cue].motion == MotionState::Pocketed {
            self.pocketed.retain(|&b| b != self.cue);
            self.respot_cue();
        }
    }

    /// Brings a pocketed cue ball back in hand, on its starting spot or the nearest free spot
    /// up the table's middle.
    fn respot_cue(&mut self) {
        self.in_hand = true;
        let r = self.params.ball_radius;
        let spots = (0..200).flat_map(|k| {
            let d = k as f64 * 2.1 * r;
            [
                self.home + DVec2::new(0.0, d),
                self.home - DVec2::new(0.0, d),
            ]
        });
        for spot in spots {
            if self.placement(spot).is_ok() {
                self.balls[self.cue] = BallState::at_rest(spot);
                return;
            }
        }
        // The table is full: leave the ball where it fell, in the tray.
        self.pocketed.push(self.cue);
    }

    /// Why the cue ball cannot be put at `pos`, if it cannot. The engine's own check decides,
    /// so a spot accepted here is one the engine accepts.
    pub fn placement(&self, pos: DVec2) -> Result<(), PracticeError> {
        let mut shot = self.shot(Strike {
            speed: 0.0,
            dir: DVec2::X,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        });
        shot.strike = None;
        shot.balls[self.cue] = BallState::at_rest(pos);
        engine::check(&shot).map_err(|e| PracticeError::IllegalPlacement(e.to_string()))
    }

    /// Puts the cue ball at `pos` if it is in hand and the spot is free.
    pub fn place_cue(&mut self, pos: DVec2) -> Result<(), PracticeError> {
        if self.busy() {
            return Err(PracticeError::Busy);
        }
        if !self.in_hand {
            return Err(PracticeError::IllegalPlacement(
                "the cue ball is not in hand".into(),
            ));
        }
        self.placement(pos)?;
        self.balls[self.cue] = BallState::at_rest(pos);
        Ok(())
    }
}

/// Ids of racked balls: "cue", then "1", "2", ...
/// The opening position of `variant`'s game (its rack shuffled by `seed`: the three-cushion
/// start on the carom table, a 9-ball diamond, ...) as a scene, the balls named as the game
/// names them ([`palette::ball_ids`]).
pub fn rack_scene(variant: Variant, seed: u64) -> Scene {
    let game = Game::new(variant, Settings::offline(), seed);
    let balls = palette::ball_ids(&game)
        .into_iter()
        .zip(game.balls())
        .map(|(id, b)| SceneBall {
            id,
            pos: b.pos.to_array(),
            vel: [0.0; 2],
            spin: [0.0; 3],
        })
        .collect();
    Scene {
        table: game.table(),
        physics: game.params(),
        models: Models::default(),
        effects: Effects::default(),
        horizon: None,
        balls,
        strike: None,
    }
}

fn rack_ids(count: usize) -> Vec<String> {
    std::iter::once("cue".to_string())
        .chain((1..count).map(|n| n.to_string()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(json: &str) -> Scene {
        Scene::from_json(json).expect("valid scene")
    }

    #[test]
    fn a_shot_plays_out_and_its_final_table_stays() {
        let mut p = Practice::from_scene(&scene(
            r#"{"table":"9ft","balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[0.15,0.15]}]}"#,
        ))
        .expect("valid");
        let strike = Strike::at_angle(3.0, 225.0, DVec2::ZERO);
        let expected = simulate(&p.shot(strike)).expect("valid");
        p.shoot(strike).expect("shot");
        assert!(p.busy());
        assert_eq!(p.shoot(strike), Err(PracticeError::Busy));
        p.tick(0.1, 1.0);
        assert_eq!(p.shown_balls()[0].pos, expected.state_at(0, 0.1).pos);
        p.tick(1e9, 1.0);
        assert!(!p.busy());
        assert_eq!(p.pocketed, vec![1]);
        assert_eq!(p.balls[1].motion, MotionState::Pocketed);
        assert_eq!(p.last_hash, Some(expected.hash()));
    }

    #[test]
    fn a_scratch_puts_the_cue_ball_back_in_hand() {
        // The cue ball rolls straight into the bottom-left pocket.
        let mut p = Practice::from_scene(&scene(
            r#"{"balls":[{"id":"cue","pos":[0.3,0.3]},{"id":"1","pos":[1.0,2.0]}]}"#,
        ))
        .expect("valid");
        p.shoot(Strike::at_angle(3.0, 225.0, DVec2::ZERO))
            .expect("shot");
        p.skip();
        assert!(p.in_hand);
        assert_eq!(p.balls[0], BallState::at_rest(DVec2::new(0.3, 0.3)));
        assert!(p.pocketed.is_empty());
    }

    #[test]
    fn illegal_placements_are_refused_and_change_nothing() {
        let mut p = Practice::rack(TableKind::NineFoot, 7);
        assert_eq!(p.ids.len(), 16);
        assert_eq!(p.ids[8], "8");
        let before = p.balls.clone();
        let on_ball = p.balls[1].pos;
        assert!(p.place_cue(on_ball).is_err());
        assert!(p.place_cue(DVec2::new(-0.1, 0.5)).is_err());
        assert!(p.place_cue(DVec2::new(f64::NAN, 0.5)).is_err());
        assert_eq!(p.balls, before);
        p.place_cue(DVec2::new(0.4, 0.5)).expect("free spot");
        assert_eq!(p.balls[0].pos, DVec2::new(0.4, 0.5));
    }

    #[test]
    fn scene_strike_becomes_the_set_up_and_names_the_cue_ball() {
        let p = Practice::from_scene(&scene(
            r#"{"balls":[{"id":"a","pos":[0.3,0.3]},{"id":"b","pos":[0.6,0.6]}],
                "strike":{"ball":"b","speed":3.0,"angle_deg":90}}"#,
        ))
        .expect("valid");
        assert_eq!(p.cue, 1);
        let aim = p.scene_aim.expect("set-up");
        assert!((aim.speed() - 3.0).abs() < 1e-9);
    }
}
