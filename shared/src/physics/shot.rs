//! What a shot is and what it gives: the shot and its validation, the outcome, and the
//! counts of the work it took. The event loop that turns one into the other is `engine.rs`.

use glam::DVec2;
use thiserror::Error;

use super::ball_cushion;
use super::cue::{Strike, StrikeError};
use super::event::Event;
use super::motion::{BallState, MotionModel, Piece};
use super::params::{Effects, Models, Params};
use super::table::{Table, TableKind};

/// A shot stops with an error past this many events: a safety net that no real shot nears
/// (a 15-ball break takes a few hundred).
pub const MAX_EVENTS: usize = 100_000;
/// Overlap between two balls (m) that a shot may start with: rounding, not a real overlap.
pub const OVERLAP_TOLERANCE: f64 = 1e-9;
/// Most balls a shot may have (a pool rack has 16, snooker 22).
pub const MAX_BALLS: usize = 128;

/// Everything that defines a shot.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    /// The table played on; its pockets are left out when `effects.pockets` is off.
    pub table: TableKind,
    /// The physical parameters (radius, mass, friction, restitution, ...).
    pub params: Params,
    /// Which ball–ball and cushion models resolve the impacts.
    pub models: Models,
    /// The effects simulated; an effect that is off costs nothing.
    pub effects: Effects,
    /// Stop at this time (s) even if balls still move.
    pub horizon: Option<f64>,
    /// Balls in scene coordinates (origin at a corner of the playing surface).
    pub balls: Vec<BallState>,
    /// A cue strike at t = 0 on one ball.
    pub strike: Option<(usize, Strike)>,
}

impl Shot {
    /// `balls` on `table` with the default physics, models and effects: no horizon, no strike.
    pub fn new(table: TableKind, balls: Vec<BallState>) -> Shot {
        Shot {
            table,
            params: Params::for_table(table),
            models: Models::default(),
            effects: Effects::default(),
            horizon: None,
            balls,
            strike: None,
        }
    }

    /// The same shot with the cue striking ball `ball` at t = 0.
    pub fn struck(self, ball: usize, strike: Strike) -> Shot {
        Shot {
            strike: Some((ball, strike)),
            ..self
        }
    }
}

/// Why a shot cannot be simulated. Ball numbers are indices into [`Shot::balls`].
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ShotError {
    /// A physical parameter is out of range; the text names it.
    #[error("{0}")]
    Params(String),
    /// A ball's position, velocity or spin holds a NaN or an infinity.
    #[error("ball {ball}: {field} must be finite numbers")]
    NotFinite {
        /// The ball at fault.
        ball: usize,
        /// Which of its fields: `pos`, `vel` or `spin`.
        field: &'static str,
    },
    /// Two balls on the table overlap by more than [`OVERLAP_TOLERANCE`].
    #[error("balls {a} and {b} overlap")]
    Overlap {
        /// The lower-numbered ball of the pair.
        a: usize,
        /// The higher-numbered ball of the pair.
        b: usize,
    },
    /// A ball's height or vertical velocity is not finite, its height is negative, or it is in
    /// flight with the `airborne` effect off.
    #[error("ball {ball}: lift must be a finite height, not negative, and zero (with vz) when the airborne effect is off")]
    Lift {
        /// The ball at fault.
        ball: usize,
    },
    /// A ball's centre is where no ball can rest: off the bed, into a cushion nose, or inside
    /// a pocket's capture circle.
    #[error("ball {ball} is not on the playing surface")]
    OffTable {
        /// The ball at fault.
        ball: usize,
    },
    /// No horizon, and a friction is off, so the balls might never come to rest.
    #[error("horizon is required when slide_friction, roll_friction or spin_friction is off")]
    HorizonRequired,
    /// The horizon is not a positive finite number of seconds.
    #[error("horizon must be a positive finite number of seconds")]
    Horizon,
    /// The strike names a ball index out of range, or a ball pocketed or off the table.
    #[error("strike.ball names no ball on the table")]
    StrikeBall,
    /// The strike itself is refused (speed, aim, tip or elevation).
    #[error("{0}")]
    Strike(#[from] StrikeError),
    /// More than [`MAX_BALLS`] balls.
    #[error("a shot has at most {MAX_BALLS} balls")]
    TooManyBalls,
    /// The simulation passed [`MAX_EVENTS`] events and was stopped.
    #[error("the shot exceeded {MAX_EVENTS} events")]
    EventLimit,
}

/// The result of a simulated shot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Every event in time order.
    pub events: Vec<Event>,
    /// Each ball's trajectory: its pieces in time order (engine coordinates).
    pub history: Vec<Vec<Piece>>,
    /// Each ball's state at `duration`, in scene coordinates.
    pub finals: Vec<BallState>,
    /// When each ball came to rest or was pocketed (None if still moving at the end).
    pub rest_time: Vec<Option<f64>>,
    /// When the last ball stopped, or the horizon.
    pub duration: f64,
    /// How much prediction work the shot took.
    pub work: Work,
    /// Engine-to-scene offset (half the table).
    pub(super) offset: DVec2,
    pub(super) radius: f64,
}

impl Outcome {
    /// The state of `ball` at time `t` (clamped to the shot), in scene coordinates.
    pub fn state_at(&self, ball: usize, t: f64) -> BallState {
        let pieces = &self.history[ball];
        let idx = pieces.partition_point(|p| p.t0 <= t).max(1) - 1;
        let piece = &pieces[idx];
        let t = t.max(piece.t0).min(piece.t_end);
        let mut s = piece.state_at(t, self.radius);
        s.pos += self.offset;
        s
    }

    /// The state hash of the final table: every ball's exact bits.
    pub fn hash(&self) -> u64 {
        crate::hash::state_hash(&self.finals)
    }

    /// Total kinetic energy (translation and rotation) of all balls at time `t`.
    pub fn kinetic_energy(&self, t: f64, params: &Params) -> f64 {
        (0..self.history.len())
            .map(|i| kinetic_energy(&self.state_at(i, t), params))
            .sum()
    }

    /// Total kinetic and potential energy of all balls at time `t`.
    pub fn mechanical_energy(&self, t: f64, params: &Params) -> f64 {
        (0..self.history.len())
            .map(|i| mechanical_energy(&self.state_at(i, t), params))
            .sum()
    }
}

/// Kinetic energy of one ball.
pub fn kinetic_energy(s: &BallState, params: &Params) -> f64 {
    0.5 * params.ball_mass * (s.vel.length_squared() + s.vz * s.vz)
        + 0.5 * params.inertia() * s.spin.length_squared()
}

/// Kinetic plus potential energy of one ball (zero potential at rest on the cloth).
pub fn mechanical_energy(s: &BallState, params: &Params) -> f64 {
    kinetic_energy(s, params) + params.ball_mass * params.gravity * s.lift
}

/// Counts of event-time predictions made during a shot, by kind: what an effect that is
/// switched off must leave at zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// Ball pairs whose next collision was predicted.
    pub pair_checks: u64,
    /// Ball–rail and ball–jaw contact predictions.
    pub cushion_checks: u64,
    /// Ball–pocket capture predictions.
    pub pocket_checks: u64,
    /// Predictions for balls in flight (their own events and their pairs).
    pub flight_checks: u64,
}
/// The fixed facts of the shot being simulated, which every step of the loop and every
/// impact reads.
pub(super) struct Ctx<'a> {
    pub(super) table: &'a Table,
    pub(super) params: &'a Params,
    pub(super) models: Models,
    pub(super) effects: Effects,
    pub(super) motion: MotionModel,
    /// The horizontal distance from a ball's centre to a cushion nose it touches.
    pub(super) contact: f64,
    /// The horizon, or infinity.
    pub(super) limit: f64,
}

/// Checks a shot without simulating it.
pub fn check(shot: &Shot) -> Result<(), ShotError> {
    validate(shot, &Table::for_shot(shot.table, shot.effects.pockets))
}

pub(super) fn validate(shot: &Shot, table: &Table) -> Result<(), ShotError> {
    shot.params.validate().map_err(ShotError::Params)?;
    if shot.balls.len() > MAX_BALLS {
        return Err(ShotError::TooManyBalls);
    }
    if let Some(h) = shot.horizon {
        if !h.is_finite() || h <= 0.0 {
            return Err(ShotError::Horizon);
        }
    } else if !shot.effects.balls_come_to_rest() {
        return Err(ShotError::HorizonRequired);
    }
    for (i, b) in shot.balls.iter().enumerate() {
        if !b.pos.is_finite() {
            return Err(ShotError::NotFinite {
                ball: i,
                field: "pos",
            });
        }
        if !b.vel.is_finite() {
            return Err(ShotError::NotFinite {
                ball: i,
                field: "vel",
            });
        }
        if !b.spin.is_finite() {
            return Err(ShotError::NotFinite {
                ball: i,
                field: "spin",
            });
        }
        let flying = b.lift != 0.0 || b.vz != 0.0;
        if !(b.lift.is_finite() && b.vz.is_finite() && b.lift >= 0.0)
            || (flying && !shot.effects.airborne)
        {
            return Err(ShotError::Lift { ball: i });
        }
    }
    if let Some((i, strike)) = shot.strike {
        if i >= shot.balls.len() || shot.balls[i].motion.is_gone() {
            return Err(ShotError::StrikeBall);
        }
        strike.validated()?;
    }
    let r = shot.params.ball_radius;
    let contact = ball_cushion::model_contact_distance(&shot.params, shot.models.cushion);
    let on_table = |i: usize| !shot.balls[i].motion.is_gone();
    let n = shot.balls.len();
    // Most balls are well inside, where every place fits.
    let deep = table.deep_interior(contact);
    for i in (0..n).filter(|&i| on_table(i)) {
        // A ball in flight may be above the cushion noses' reach; its centre must still be
        // over the bed.
        let margin = if shot.balls[i].lift > 0.0 {
            0.0
        } else {
            contact
        };
        let p = table.to_engine(shot.balls[i].pos);
        let deep_inside =
            margin == contact && deep.is_some_and(|h| p.x.abs() <= h.x && p.y.abs() <= h.y);
        if !deep_inside && !table.fits(p, margin) {
            return Err(ShotError::OffTable { ball: i });
        }
    }
    // Touching is allowed, and so is the overlap rounding leaves between balls the engine
    // itself brought to rest touching; more is not.
    let min_dist = 2.0 * r - OVERLAP_TOLERANCE;
    for i in (0..n).filter(|&i| on_table(i)) {
        for j in (i + 1..n).filter(|&j| on_table(j)) {
            // Scene coordinates: the same distance as in the engine's, to rounding.
            let d = (shot.balls[j].pos - shot.balls[i].pos).length();
            // A ball in flight may be above another.
            let dz = shot.balls[j].lift - shot.balls[i].lift;
            if d < min_dist && (dz == 0.0 || d * d + dz * dz < min_dist * min_dist) {
                return Err(ShotError::Overlap { a: i, b: j });
            }
        }
    }
    Ok(())
}
