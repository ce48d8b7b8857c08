//! Scene files (the contract in docs/scene.md): a table, parameters, balls and an optional
//! strike, in JSON; and the JSON result of simulating one.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::hash::hash_hex;
use crate::physics::{
    BallState, Effects, Models, MotionState, Outcome, Params, Shot, ShotError, Strike, TableKind,
};

/// Version of the result format.
pub const RESULT_VERSION: u32 = 1;
/// Most ball states `--sample` may produce (samples × balls).
pub const MAX_SAMPLES: usize = 1_000_000;

/// A scene as read from a scene file: the table, the physics, the balls at t = 0 and an
/// optional strike (docs/scene.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, try_from = "RawScene")]
pub struct Scene {
    /// The table played on; `"9ft"` if not given.
    #[serde(default)]
    pub table: TableKind,
    /// The table's default parameters ([`Params::for_table`]) with the scene's overrides.
    #[serde(default)]
    pub physics: Params,
    /// Which ball–ball and cushion models the engine uses.
    #[serde(default)]
    pub models: Models,
    /// Effects switched on or off; all those the table has are on by default.
    #[serde(default)]
    pub effects: Effects,
    /// Stop simulating at this time (s) even if balls still move; required when nothing can
    /// stop them (every friction off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizon: Option<f64>,
    /// The balls at t = 0, ids unique.
    pub balls: Vec<SceneBall>,
    /// A cue strike on one ball at t = 0, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strike: Option<SceneStrike>,
}

/// A scene as written: `physics` holds only the parameters it overrides, since the defaults
/// of the others depend on the table.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default)]
    table: TableKind,
    #[serde(default)]
    physics: serde_json::Map<String, serde_json::Value>,
    #[serde(default)]
    models: Models,
    #[serde(default)]
    effects: Effects,
    #[serde(default)]
    horizon: Option<f64>,
    balls: Vec<SceneBall>,
    #[serde(default)]
    strike: Option<SceneStrike>,
}

impl TryFrom<RawScene> for Scene {
    type Error = String;

    fn try_from(raw: RawScene) -> Result<Scene, String> {
        let physics = physics_over_defaults(raw.table, raw.physics)?;
        Ok(Scene {
            table: raw.table,
            physics,
            models: raw.models,
            effects: raw.effects,
            horizon: raw.horizon,
            balls: raw.balls,
            strike: raw.strike,
        })
    }
}

/// The parameters of a scene's `physics` object: the table's defaults, with those the
/// object names replaced. An unknown name or a value of the wrong type is refused, naming
/// it (the values' ranges are checked with the shot, [`Params::validate`]).
pub fn physics_over_defaults(
    table: TableKind,
    overrides: serde_json::Map<String, serde_json::Value>,
) -> Result<Params, String> {
    let mut physics = match serde_json::to_value(Params::for_table(table)) {
        Ok(serde_json::Value::Object(map)) => map,
        _ => return Err("physics: the table's defaults cannot be encoded".into()),
    };
    physics.extend(overrides);
    serde_json::from_value(serde_json::Value::Object(physics)).map_err(|e| format!("physics: {e}"))
}

/// A ball of a scene at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneBall {
    /// The ball's name in the result and in `strike.ball`; unique and not empty.
    pub id: String,
    /// Centre on the cloth (m, scene coordinates: origin at a corner of the playing surface).
    pub pos: [f64; 2],
    /// Velocity of the centre (m/s); zero if not given.
    #[serde(default)]
    pub vel: [f64; 2],
    /// Angular velocity (rad/s) in the table frame; zero if not given.
    #[serde(default)]
    pub spin: [f64; 3],
}

/// A cue strike in a scene: exactly one of `dir` and `angle_deg` gives the aim.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneStrike {
    /// The `id` of the ball struck.
    pub ball: String,
    /// Cue stick speed (m/s), not the ball's: 0 to 15.
    pub speed: f64,
    /// Aim direction in the table plane, of any non-zero length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dir: Option<[f64; 2]>,
    /// Aim in degrees from +x (90 = +y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_deg: Option<f64>,
    /// Tip offset `[side, height]` in units of R, within 0.5 R of the centre; centre if not given.
    #[serde(default)]
    pub tip: [f64; 2],
    /// Cue elevation in degrees (0 level, 90 straight down).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub elevation_deg: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// A scene that cannot be simulated; the message names the field or balls at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("invalid scene: {0}")]
pub struct SceneError(pub String);

impl Scene {
    /// Parses a scene from JSON and checks it.
    pub fn from_json(text: &str) -> Result<Scene, SceneError> {
        let scene: Scene = serde_json::from_str(text).map_err(|e| SceneError(e.to_string()))?;
        scene.to_shot()?;
        Ok(scene)
    }

    /// The scene as pretty-printed JSON that [`Scene::from_json`] reads back.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The engine's view of the scene, with every check done.
    pub fn to_shot(&self) -> Result<Shot, SceneError> {
        let mut ids: Vec<&str> = Vec::with_capacity(self.balls.len());
        for (k, b) in self.balls.iter().enumerate() {
            if b.id.is_empty() {
                return Err(SceneError(format!("balls[{k}].id must not be empty")));
            }
            if ids.contains(&b.id.as_str()) {
                return Err(SceneError(format!("balls: duplicate id \"{}\"", b.id)));
            }
            ids.push(&b.id);
        }
        let balls = self
            .balls
            .iter()
            .map(|b| BallState {
                pos: DVec2::from_array(b.pos),
                vel: DVec2::from_array(b.vel),
                spin: DVec3::from_array(b.spin),
                motion: MotionState::Stationary,
                pocket: None,
                lift: 0.0,
                vz: 0.0,
            })
            .collect();
        let strike = match &self.strike {
            None => None,
            Some(s) => {
                let Some(idx) = ids.iter().position(|id| *id == s.ball) else {
                    return Err(SceneError(format!(
                        "strike.ball \"{}\" names no ball in the scene",
                        s.ball
                    )));
                };
                let tip = DVec2::from_array(s.tip);
                let strike = match (s.dir, s.angle_deg) {
                    (Some(dir), None) => Strike {
                        speed: s.speed,
                        dir: DVec2::from_array(dir),
                        tip,
                        elevation_deg: 0.0,
                    },
                    (None, Some(angle)) if angle.is_finite() => {
                        Strike::at_angle(s.speed, angle, tip)
                    }
                    (None, Some(_)) => {
                        return Err(SceneError(
                            "strike.angle_deg must be a finite number".into(),
                        ))
                    }
                    _ => {
                        return Err(SceneError(
                            "strike needs exactly one of dir and angle_deg".into(),
                        ))
                    }
                };
                Some((idx, strike.elevated(s.elevation_deg)))
            }
        };
        let shot = Shot {
            table: self.table,
            params: self.physics,
            models: self.models,
            effects: self.effects,
            horizon: self.horizon,
            balls,
            strike,
        };
        crate::physics::engine::check(&shot).map_err(|e| self.explain(e))?;
        Ok(shot)
    }

    /// Turns an engine error into a message that names the scene's fields and ball ids.
    pub fn explain(&self, e: ShotError) -> SceneError {
        let id = |i: usize| self.balls.get(i).map_or("?", |b| b.id.as_str());
        SceneError(match e {
            ShotError::NotFinite { ball, field } => {
                format!(
                    "balls[{ball}].{field} (ball \"{}\") must be finite numbers",
                    id(ball)
                )
            }
            ShotError::Overlap { a, b } => {
                format!("balls \"{}\" and \"{}\" overlap", id(a), id(b))
            }
            ShotError::OffTable { ball } => format!(
                "balls[{ball}].pos: ball \"{}\" is not on the {} table's playing surface",
                id(ball),
                self.table.name()
            ),
            ShotError::Params(msg) => msg,
            other => other.to_string(),
        })
    }

    /// Simulates the scene and builds its result (with samples every `sample` seconds).
    pub fn run(&self, sample: Option<f64>) -> Result<SceneResult, SceneError> {
        let shot = self.to_shot()?;
        if let Some(dt) = sample {
            if !dt.is_finite() || dt <= 0.0 {
                return Err(SceneError(
                    "--sample must be a positive number of seconds".into(),
                ));
            }
        }
        let outcome = crate::physics::simulate(&shot).map_err(|e| self.explain(e))?;
        self.result(&shot, &outcome, sample)
    }

    /// The result of a simulated scene in the contract's format.
    pub fn result(
        &self,
        shot: &Shot,
        outcome: &Outcome,
        sample: Option<f64>,
    ) -> Result<SceneResult, SceneError> {
        let names = crate::physics::Table::new(shot.table).pocket_names();
        let id = |i: u16| self.balls[i as usize].id.clone();
        let events = outcome
            .events
            .iter()
            .map(|e| {
                let (balls, count) = e.kind.balls();
                ResultEvent {
                    t: e.t,
                    kind: e.kind.name(),
                    balls: balls[..count].iter().map(|&b| id(b)).collect(),
                }
            })
            .collect();
        let balls = outcome
            .finals
            .iter()
            .enumerate()
            .map(|(i, s)| ResultBall {
                ball: self.sample_ball(i, s, shot),
                rest_time: outcome.rest_time[i],
                pocket: s
                    .pocket
                    .and_then(|p| names.get(p as usize))
                    .map(|n| n.to_string()),
            })
            .collect();
        let samples = match sample {
            None => None,
            Some(dt) => {
                let count = (outcome.duration / dt).floor();
                let states = (count + 1.0) * outcome.history.len().max(1) as f64;
                if count.is_nan() || states > MAX_SAMPLES as f64 {
                    return Err(SceneError(format!(
                        "--sample {dt} asks for more than {MAX_SAMPLES} ball states"
                    )));
                }
                let count = count as usize;
                Some(
                    (0..=count)
                        .map(|k| {
                            let t = k as f64 * dt;
                            Sample {
                                t,
                                balls: (0..outcome.history.len())
                                    .map(|i| self.sample_ball(i, &outcome.state_at(i, t), shot))
                                    .collect(),
                            }
                        })
                        .collect(),
                )
            }
        };
        Ok(SceneResult {
            version: RESULT_VERSION,
            events,
            balls,
            duration: outcome.duration,
            hash: hash_hex(outcome.hash()),
            samples,
        })
    }

    /// Ball `i` of the scene in state `s`, as results show it: the height of its centre
    /// above the cloth only while it flies.
    fn sample_ball(&self, i: usize, s: &BallState, shot: &Shot) -> SampleBall {
        SampleBall {
            id: self.balls[i].id.clone(),
            pos: s.pos.to_array(),
            z: (s.motion == MotionState::Airborne).then_some(shot.params.ball_radius + s.lift),
            vel: s.vel.to_array(),
            spin: s.spin.to_array(),
            state: s.motion.name().to_string(),
        }
    }
}

/// What `breakshot-sim run` prints: the events, the final table and its state hash.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneResult {
    /// The result format's version, [`RESULT_VERSION`].
    pub version: u32,
    /// Every event of the shot, in time order.
    pub events: Vec<ResultEvent>,
    /// The final state of every ball, in the scene's order.
    pub balls: Vec<ResultBall>,
    /// When the last ball stopped, or the horizon (s).
    pub duration: f64,
    /// The state hash of the final table as 16 hexadecimal digits; equal on every machine for
    /// equal inputs.
    pub hash: String,
    /// The balls every `--sample` seconds from t = 0 to `duration`; `None` without `--sample`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Vec<Sample>>,
}

/// One event of a result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultEvent {
    /// When it happened (s after the strike).
    pub t: f64,
    /// The contract's name for it: `strike`, `ball_ball`, `sliding_to_rolling`, ...
    pub kind: String,
    /// The ids of the balls involved (one, or two for `ball_ball`).
    pub balls: Vec<String>,
}

/// A ball at the end of the shot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultBall {
    /// Its id, where it is and how it moves, as in a sample; for a pocketed ball, `pos` is
    /// where it entered the pocket's capture circle and `state` is `pocketed`.
    #[serde(flatten)]
    pub ball: SampleBall,
    /// When the ball came to rest, was pocketed or left the table (s); `None` if it still
    /// moved at the horizon.
    pub rest_time: Option<f64>,
    /// The name of the pocket it fell in (`lb`, `lc`, `lt`, `rb`, `rc`, `rt`); `None` if not
    /// pocketed.
    pub pocket: Option<String>,
}

/// The table at one time, from the exact motion, not stepped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time of the sample (s).
    pub t: f64,
    /// Every ball at that time, in the scene's order.
    pub balls: Vec<SampleBall>,
}

/// One ball in a sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleBall {
    /// The ball's id in the scene.
    pub id: String,
    /// Centre on the cloth (m, scene coordinates).
    pub pos: [f64; 2],
    /// Height of the centre above the cloth, for a ball in flight only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// Velocity of the centre (m/s).
    pub vel: [f64; 2],
    /// Angular velocity (rad/s) in the table frame.
    pub spin: [f64; 3],
    /// A motion state (`stationary`, `spinning`, `sliding`, `rolling`, `airborne`), or
    /// `pocketed` or `off_table`.
    pub state: String,
}
