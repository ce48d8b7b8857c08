//! Closed-form motion of one ball between events.
//!
//! Between two events a ball is in one motion state and its position is a quadratic in time:
//! `r(t) = r0 + v0·τ + ½·a·τ²` with τ = t − t0 and a constant acceleration `a` that depends
//! on the state (Leckie & Greenspan 2005; pooltool's motion model):
//!
//! - sliding: the contact point slips with velocity `u = v − R·(ω × ẑ)`; Coulomb friction
//!   `−μs·m·g·û` acts at the contact, so `a = −μs·g·û` and `ω̇ = (5μs·g/2R)·(ẑ × û)`; `û` keeps
//!   its direction and `|u|` shrinks at `7/2·μs·g`, so slipping ends at `τ = 2|u0|/(7μs·g)`;
//! - rolling: `a = −μr·g·v̂`, ω follows v (no slip); the ball stops at `τ = |v0|/(μr·g)`;
//! - spinning: only ω_z, decaying at `5μsp·g/(2R)`; stationary and pocketed: nothing moves.
//!
//! Spin about the vertical decays at that same rate in every state and does not change the
//! path, so it is clamped at zero rather than given an event of its own.
//!
//! - airborne: a ball in flight (after an elevated strike, a bounce or a collision that
//!   lifted it) follows a ballistic arc: its centre keeps its horizontal velocity, its height
//!   above rest `z(τ) = z0 + vz·τ − ½·g·τ²`, and its spin is kept; the piece ends when it lands
//!   (see `airborne.rs` for the landing, the bounces and what a ball in flight meets);
//! - off the table: a ball that flew over a rail; like a pocketed one, it no longer moves.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::params::{Effects, Params};

/// Slip speeds (m/s) below this count as rolling: the slide would last under 1e-10 s.
pub const SLIP_EPS: f64 = 1e-10;
/// Speeds (m/s) and spins (rad/s) below this count as zero when a state is classified.
/// Far below any speed the engine is asked to keep (1e-6 m/s moves a ball).
pub const REST_EPS: f64 = 1e-12;

/// The motion state of a ball; its name is what scenes and results call it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionState {
    /// At rest on the cloth: no velocity, no spin.
    Stationary,
    /// The centre at rest, the ball turning about the vertical only.
    Spinning,
    /// Moving with its contact point slipping on the cloth: sliding friction acts.
    Sliding,
    /// Moving with no slip at the cloth (`v = R·(ω × ẑ)`): rolling resistance acts.
    Rolling,
    /// Fell into a pocket; it stays there for the rest of the shot.
    Pocketed,
    /// In flight above the cloth.
    Airborne,
    /// Flew over a rail and left the table.
    OffTable,
}

impl MotionState {
    /// The name scenes and results give the state; a transition event joins two
    /// (`sliding_to_rolling`).
    pub fn name(self) -> &'static str {
        match self {
            MotionState::Stationary => "stationary",
            MotionState::Spinning => "spinning",
            MotionState::Sliding => "sliding",
            MotionState::Rolling => "rolling",
            MotionState::Pocketed => "pocketed",
            MotionState::Airborne => "airborne",
            MotionState::OffTable => "off_table",
        }
    }

    /// True when the ball's centre moves.
    pub fn is_translating(self) -> bool {
        matches!(
            self,
            MotionState::Sliding | MotionState::Rolling | MotionState::Airborne
        )
    }

    /// True when the ball is no longer on the table (pocketed or flown off it).
    pub fn is_gone(self) -> bool {
        matches!(self, MotionState::Pocketed | MotionState::OffTable)
    }
}

/// Position, velocity and spin of one ball at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BallState {
    /// Centre on the cloth (m): scene coordinates in a [`super::Shot`] and its results,
    /// centred ones inside the engine.
    pub pos: DVec2,
    /// Horizontal velocity of the centre (m/s).
    pub vel: DVec2,
    /// Angular velocity (rad/s) in the table frame: rolling along +y at `v` is `[-v/R, 0, 0]`.
    pub spin: DVec3,
    /// The motion state, which decides the closed form that carries the ball on.
    pub motion: MotionState,
    /// The pocket the ball fell into, if it did (index into the table's pockets).
    pub pocket: Option<u8>,
    /// Height of the centre above its resting height `R` (m): zero on the cloth.
    /// Not carried by the wire protocol or records, which only hold balls at rest.
    #[serde(skip)]
    pub lift: f64,
    /// Vertical velocity (m/s), up positive: zero on the cloth. Not carried on the wire.
    #[serde(skip)]
    pub vz: f64,
}

impl BallState {
    /// A ball at rest at `pos`.
    pub fn at_rest(pos: DVec2) -> Self {
        BallState {
            pos,
            vel: DVec2::ZERO,
            spin: DVec3::ZERO,
            motion: MotionState::Stationary,
            pocket: None,
            lift: 0.0,
            vz: 0.0,
        }
    }

    /// A ball at `pos` with the given velocity and spin; its motion state is derived.
    pub fn moving(pos: DVec2, vel: DVec2, spin: DVec3, radius: f64) -> Self {
        let mut s = BallState {
            pos,
            vel,
            spin,
            motion: MotionState::Stationary,
            pocket: None,
            lift: 0.0,
            vz: 0.0,
        };
        s.classify(radius);
        s
    }

    /// Velocity of the contact point with the cloth: `v − R·(ω × ẑ)`.
    pub fn slip(&self, radius: f64) -> DVec2 {
        DVec2::new(
            self.vel.x - radius * self.spin.y,
            self.vel.y + radius * self.spin.x,
        )
    }

    /// Ends the slip as friction would: the ball rolls at `v − 2/7·u`, which keeps its
    /// angular momentum about the contact point and never adds energy (setting the spin
    /// from the velocity instead could, by a rounding's worth, when the slip is tiny).
    fn end_slip(&mut self, radius: f64) {
        let u = self.slip(radius);
        self.vel -= u * (2.0 / 7.0);
        self.spin.x = -self.vel.y / radius;
        self.spin.y = self.vel.x / radius;
        self.motion = MotionState::Rolling;
    }

    /// Sets the motion state from velocity and spin, snapping values within rounding of a
    /// state onto it (a rolling ball gets the exact rolling spin, a ball at rest exact zeros).
    /// A ball above the cloth or leaving it is airborne whatever its other values.
    pub fn classify(&mut self, radius: f64) {
        if self.motion.is_gone() {
            return;
        }
        if self.lift > 0.0 || self.vz > 0.0 {
            self.motion = MotionState::Airborne;
            return;
        }
        let speed = self.vel.length();
        let slip = self.slip(radius).length();
        if speed <= REST_EPS && slip <= REST_EPS {
            self.vel = DVec2::ZERO;
            self.spin.x = 0.0;
            self.spin.y = 0.0;
            if self.spin.z.abs() <= REST_EPS {
                self.spin.z = 0.0;
                self.motion = MotionState::Stationary;
            } else {
                self.motion = MotionState::Spinning;
            }
        } else if slip <= SLIP_EPS {
            self.end_slip(radius);
        } else {
            self.motion = MotionState::Sliding;
        }
    }
}

/// The constants of the motion model, with effects that are off already zeroed.
#[derive(Clone, Copy, Debug)]
pub struct MotionModel {
    /// Ball radius R (m).
    pub radius: f64,
    /// μs·g, or 0 without sliding friction.
    slide_decel: f64,
    /// μr·g, or 0 without rolling friction.
    roll_decel: f64,
    /// 5μsp·g/(2R), or 0 without spin friction.
    spin_decel: f64,
    /// g, for balls in flight.
    gravity: f64,
}

impl MotionModel {
    /// The model for `params`, with the frictions `effects` switches off set to zero.
    pub fn new(params: &Params, effects: &Effects) -> Self {
        let on = |flag: bool, value: f64| if flag { value } else { 0.0 };
        MotionModel {
            radius: params.ball_radius,
            slide_decel: on(effects.slide_friction, params.mu_slide * params.gravity),
            roll_decel: on(
                effects.roll_friction,
                params.rolling_resistance() * params.gravity,
            ),
            spin_decel: on(effects.spin_friction, params.spin_decel()),
            gravity: params.gravity,
        }
    }
}

/// One piece of a ball's trajectory: its state at `t0` and the closed form that carries it
/// until `t_end`, when its motion state changes by itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// When the piece starts (s after the strike).
    pub t0: f64,
    /// The ball's state at `t0`, already classified.
    pub start: BallState,
    /// Acceleration of the centre (m/s²).
    pub acc: DVec2,
    /// Angular acceleration of the horizontal spin while sliding (rad/s²).
    spin_acc: DVec2,
    /// Deceleration of |ω_z| (rad/s²).
    spin_decel: f64,
    /// Downward acceleration of a ball in flight (g), zero on the cloth.
    gravity: f64,
    /// When the motion state next changes by itself (∞ if never).
    pub t_end: f64,
}

impl Piece {
    /// The piece that starts at `t0` in `start` (whose state is already classified).
    #[inline]
    pub fn new(t0: f64, start: BallState, model: &MotionModel) -> Self {
        let mut acc = DVec2::ZERO;
        let mut spin_acc = DVec2::ZERO;
        let mut duration = f64::INFINITY;
        match start.motion {
            MotionState::Sliding => {
                let u = start.slip(model.radius);
                let speed = u.length();
                if model.slide_decel > 0.0 && speed > 0.0 {
                    let dir = u / speed;
                    acc = -model.slide_decel * dir;
                    // ẑ × û = (−û_y, û_x)
                    let k = 2.5 * model.slide_decel / model.radius;
                    spin_acc = DVec2::new(-k * dir.y, k * dir.x);
                    duration = 2.0 * speed / (7.0 * model.slide_decel);
                }
            }
            MotionState::Rolling => {
                let speed = start.vel.length();
                if model.roll_decel > 0.0 && speed > 0.0 {
                    acc = -model.roll_decel * (start.vel / speed);
                    duration = speed / model.roll_decel;
                }
            }
            MotionState::Spinning => {
                if model.spin_decel > 0.0 {
                    duration = start.spin.z.abs() / model.spin_decel;
                }
            }
            MotionState::Airborne => duration = flight_time(start.lift, start.vz, model.gravity),
            MotionState::Stationary | MotionState::Pocketed | MotionState::OffTable => {}
        }
        // Nothing slows the spin of a ball in flight or gone.
        let spin_decel = if start.motion.is_gone() || start.motion == MotionState::Airborne {
            0.0
        } else {
            model.spin_decel
        };
        let gravity = if start.motion == MotionState::Airborne {
            model.gravity
        } else {
            0.0
        };
        Piece {
            t0,
            start,
            acc,
            spin_acc,
            spin_decel,
            gravity,
            t_end: t0 + duration,
        }
    }

    /// Position at absolute time `t` (within this piece).
    #[inline]
    pub fn pos_at(&self, t: f64) -> DVec2 {
        let dt = t - self.t0;
        self.start.pos + self.start.vel * dt + self.acc * (0.5 * dt * dt)
    }

    /// Velocity at absolute time `t`.
    #[inline]
    pub fn vel_at(&self, t: f64) -> DVec2 {
        self.start.vel + self.acc * (t - self.t0)
    }

    /// Height above rest and vertical velocity at absolute time `t` (zero on the cloth).
    #[inline]
    pub fn height_at(&self, t: f64) -> (f64, f64) {
        let dt = t - self.t0;
        let s = &self.start;
        (
            s.lift + s.vz * dt - 0.5 * self.gravity * dt * dt,
            s.vz - self.gravity * dt,
        )
    }

    /// Downward acceleration of the centre: g in flight, zero on the cloth.
    #[inline]
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// The full state at absolute time `t` (within this piece); the motion state is the
    /// piece's own.
    pub fn state_at(&self, t: f64, radius: f64) -> BallState {
        let dt = t - self.t0;
        let mut s = self.start;
        if s.motion.is_gone() || s.motion == MotionState::Stationary {
            return s;
        }
        if s.motion == MotionState::Airborne {
            s.pos = self.pos_at(t);
            (s.lift, s.vz) = self.height_at(t);
            return s;
        }
        s.pos = self.pos_at(t);
        s.vel = self.vel_at(t);
        match s.motion {
            MotionState::Sliding => {
                s.spin.x += self.spin_acc.x * dt;
                s.spin.y += self.spin_acc.y * dt;
            }
            MotionState::Rolling => {
                s.spin.x = -s.vel.y / radius;
                s.spin.y = s.vel.x / radius;
            }
            _ => {}
        }
        let wz = self.start.spin.z;
        let decayed = (wz.abs() - self.spin_decel * dt).max(0.0);
        s.spin.z = if wz < 0.0 { -decayed } else { decayed };
        s
    }

    /// The state in which the ball continues after this piece ends by itself at `t_end`,
    /// with the values each state implies set exactly.
    pub fn state_after_end(&self, radius: f64) -> BallState {
        let mut s = self.state_at(self.t_end, radius);
        match self.start.motion {
            MotionState::Sliding => {
                // Slip has just reached zero (to rounding): the ball rolls, spins or rests.
                s.classify(radius);
                if s.motion == MotionState::Sliding {
                    s.end_slip(radius);
                }
            }
            MotionState::Rolling => {
                s.vel = DVec2::ZERO;
                s.spin.x = 0.0;
                s.spin.y = 0.0;
                s.motion = if s.spin.z != 0.0 {
                    MotionState::Spinning
                } else {
                    MotionState::Stationary
                };
            }
            MotionState::Spinning => {
                s.spin = DVec3::ZERO;
                s.motion = MotionState::Stationary;
            }
            // A landing is resolved by the engine (`airborne::land`), not here.
            MotionState::Stationary
            | MotionState::Pocketed
            | MotionState::Airborne
            | MotionState::OffTable => {}
        }
        s
    }

    /// A box that holds the centre's path between absolute times `from` and `to` (within the
    /// piece): the path is a parabola, a quadratic Bézier curve, so it lies in the hull of
    /// its three control points.
    #[inline]
    pub fn path_box(&self, from: f64, to: f64) -> (DVec2, DVec2) {
        let p0 = self.pos_at(from);
        if !self.start.motion.is_translating() {
            return (p0, p0);
        }
        let to = to.min(self.t_end);
        let p1 = p0 + self.vel_at(from) * (0.5 * (to - from));
        let p2 = self.pos_at(to);
        (p0.min(p1).min(p2), p0.max(p1).max(p2))
    }

    /// An upper bound on how far the centre can move between `t0`-relative times 0 and `dt`.
    #[inline]
    pub fn reach(&self, from: f64, to: f64) -> f64 {
        if !self.start.motion.is_translating() {
            return 0.0;
        }
        let v = self.vel_at(from).length();
        let dt = to - from;
        v * dt + 0.5 * self.acc.length() * dt * dt
    }
}

/// How long a ball at height `lift` above rest, rising at `vz`, flies before it lands.
fn flight_time(lift: f64, vz: f64, g: f64) -> f64 {
    let root = (vz * vz + 2.0 * g * lift).sqrt();
    if vz > 0.0 {
        (vz + root) / g
    } else if root - vz > 0.0 {
        // The same root, written without cancellation for a falling ball.
        2.0 * lift / (root - vz)
    } else {
        0.0
    }
}
