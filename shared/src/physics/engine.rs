//! The event loop: from one event to the next, exactly.
//!
//! Every ball carries its current [`Piece`] (closed-form motion since its last change). The
//! loop keeps, for each ball, its next *own* event (state change, rail, jaw, pocket) and, for
//! each pair, its next collision; it takes the earliest, resolves it, and re-predicts only
//! what involves the balls that changed. Predictions never look past the end of either
//! ball's piece (after that the ball changes and is re-predicted anyway), so distant pairs
//! are dismissed by a reach bound without solving anything.
//!
//! Ties: own events come before collisions at the same instant, lower ball index first.
//! Collisions at the very same instant (bit-equal times) are resolved as one group: pairs
//! that share a ball form one simultaneous impact, whose outcome does not depend on how the
//! balls are numbered (a mirror-symmetric rack stays symmetric).

use glam::{DVec2, DVec3};
use thiserror::Error;

use super::airborne::{self, Flight};
use super::ball_ball::{self, Kinematics};
use super::ball_cushion;
use super::cue::{Strike, StrikeError};
use super::event::{Event, EventKind};
use super::motion::{BallState, MotionModel, MotionState, Piece};
use super::params::{BallBallModel, Effects, Models, Params};
use super::roots::{TOUCH_ACCEL, TOUCH_SPEED};
use super::table::{Cushion, Table, TableKind};

/// A shot stops with an error past this many events: a safety net that no real shot nears
/// (a 15-ball break takes a few hundred).
pub const MAX_EVENTS: usize = 100_000;
/// Approach speed (m/s) under which a contact that is being pushed together (by friction
/// accelerations, not by speed) is held instead of bounced: bouncing would repeat forever
/// in ever shorter hops.
pub const HOLD_SPEED: f64 = 1e-3;
/// Gap between two balls (m) under which they count as touching: they take part in each
/// other's impacts. At the fastest legal speed the gap would close in under 1e-10 s.
pub const CONTACT_GAP: f64 = 1e-9;
/// A ball nearer to a colliding group than the group's fastest approach closes in
/// `NEAR_TIME` (s) takes part in its impact as if touching: a real impact lasts about
/// 0.2 ms (Hertzian contact), so a gap closing within a microsecond closes while the impact
/// is still going on. Resolved one pair at a time, such a gap would give a cascade.
pub const NEAR_TIME: f64 = 1e-6;
/// A pair pressed together by the cloth that meets again within `PERSIST_TIME` (s) of its
/// last impact, slower than `PERSIST_SPEED` (m/s) or than the `(1 − e)/2` of its last blow's
/// speed that a blow leaves each ball, is held rather than bounced (the persistence rule of
/// a sustained push): bounced, it would come back in ever shorter hops. A held set met
/// slower than `PERSIST_SPEED` answers as one body.
pub const PERSIST_TIME: f64 = 0.5;
/// The approach speed (m/s) of the persistence rule: see [`PERSIST_TIME`].
pub const PERSIST_SPEED: f64 = 0.05;
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
    offset: DVec2,
    radius: f64,
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

#[derive(Clone, Copy, Debug, PartialEq)]
enum OwnKind {
    Nothing,
    Transition,
    Rail(u8),
    Jaw(u8),
    Pocket(u8),
    /// An event of a ball in flight.
    Flight(Flight),
}

#[derive(Clone, Copy, Debug)]
struct Own {
    t: f64,
    kind: OwnKind,
}

const NO_OWN: Own = Own {
    t: f64::INFINITY,
    kind: OwnKind::Nothing,
};

/// Simulates shots, reusing its buffers so that steady-state simulation allocates nothing.
#[derive(Default)]
pub struct Simulator {
    table: Option<Table>,
    pieces: Vec<Piece>,
    own: Vec<Own>,
    pair: Vec<f64>,
    /// For each ball `i`, the earliest collision among its pairs `i < j`: the loop looks
    /// for the next event over these instead of over every pair.
    row: Vec<f64>,
    /// For each pair `i < j` (at `i·n + j`), when it last took part in an impact.
    last: Vec<f64>,
    /// For each pair `i < j`, whether its last impact left it held (moving as one).
    held: Vec<bool>,
    /// For each pair `i < j`, the fastest it approached in the last impact that bounced it.
    blow: Vec<f64>,
    /// For each ball, a box holding its current piece's whole path.
    boxes: Vec<(DVec2, DVec2)>,
    scratch: Scratch,
    outcome: Outcome,
}

/// Simulates one shot.
pub fn simulate(shot: &Shot) -> Result<Outcome, ShotError> {
    let mut sim = Simulator::default();
    sim.run(shot)?;
    Ok(sim.take())
}

thread_local! {
    static RUNS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many shots this thread has simulated so far. Changes nothing in any result; it lets
/// tests check that a client simulates each shot once.
pub fn simulations_on_this_thread() -> u64 {
    RUNS.with(|n| n.get())
}

struct Ctx<'a> {
    table: &'a Table,
    params: &'a Params,
    models: Models,
    effects: Effects,
    motion: MotionModel,
    contact: f64,
    limit: f64,
}

impl Simulator {
    /// A simulator with empty buffers; they grow to fit the shots it runs.
    pub fn new() -> Self {
        Self::default()
    }

    /// The outcome of the last run, handing over its buffers.
    pub fn take(&mut self) -> Outcome {
        std::mem::take(&mut self.outcome)
    }

    /// Simulates `shot`; the outcome stays valid until the next run.
    pub fn run(&mut self, shot: &Shot) -> Result<&Outcome, ShotError> {
        RUNS.with(|n| n.set(n.get().wrapping_add(1)));
        let build = || Table::for_shot(shot.table, shot.effects.pockets);
        let wanted = (shot.table, shot.effects.pockets);
        if self.table.as_ref().map(|t| (t.kind, t.has_pockets())) != Some(wanted) {
            self.table = Some(build());
        }
        let table = self.table.take().unwrap_or_else(build);
        let result = self.run_on(shot, &table);
        self.table = Some(table);
        result?;
        Ok(&self.outcome)
    }

    fn run_on(&mut self, shot: &Shot, table: &Table) -> Result<(), ShotError> {
        validate(shot, table)?;
        let ctx = Ctx {
            table,
            params: &shot.params,
            models: shot.models,
            effects: shot.effects,
            motion: MotionModel::new(&shot.params, &shot.effects),
            contact: ball_cushion::model_contact_distance(&shot.params, shot.models.cushion),
            limit: shot.horizon.unwrap_or(f64::INFINITY),
        };
        let n = shot.balls.len();
        let r = shot.params.ball_radius;
        let out = &mut self.outcome;
        out.events.clear();
        out.history.resize_with(n, Vec::new);
        out.history.iter_mut().for_each(Vec::clear);
        out.finals.clear();
        out.rest_time.clear();
        out.offset = table.half;
        out.work = Work::default();
        out.radius = r;
        self.pieces.clear();
        for (i, ball) in shot.balls.iter().enumerate() {
            let mut s = *ball;
            s.pos = table.to_engine(s.pos);
            if !s.motion.is_gone() {
                s.pocket = None;
                if let Some((struck, strike)) = shot.strike {
                    if struck == i {
                        let launch = strike.launch(&shot.params)?;
                        s.vel = launch.vel;
                        s.spin = launch.spin;
                        if ctx.effects.airborne && launch.vz < 0.0 {
                            // Driven into the slate: the ball bounces, and may fly.
                            s.vz = launch.vz;
                            s = airborne::off_slate(s, &shot.params);
                        }
                        out.events.push(Event {
                            t: 0.0,
                            kind: EventKind::Strike { ball: i as u16 },
                        });
                    }
                }
                s.classify(r);
            }
            let piece = Piece::new(0.0, s, &ctx.motion);
            self.pieces.push(piece);
            out.history[i].push(piece);
            let at_rest = s.motion == MotionState::Stationary || s.motion.is_gone();
            out.rest_time.push(at_rest.then_some(0.0));
        }
        self.boxes.clear();
        for p in &self.pieces {
            self.boxes.push(piece_box(p, ctx.limit));
        }
        self.own.clear();
        self.own.resize(n, NO_OWN);
        self.pair.clear();
        self.pair.resize(n * n, f64::INFINITY);
        self.row.clear();
        self.row.resize(n, f64::INFINITY);
        self.last.clear();
        self.last.resize(n * n, f64::NEG_INFINITY);
        self.held.clear();
        self.held.resize(n * n, false);
        self.blow.clear();
        self.blow.resize(n * n, 0.0);
        for i in 0..n {
            self.predict_own(i, 0.0, &ctx);
        }
        for i in 0..n {
            for j in i + 1..n {
                self.predict_pair(i, j, 0.0, &ctx);
            }
        }

        let mut now = 0.0;
        let mut stopped_by_horizon = false;
        // Steps of the loop: every step but a group impact in which nothing acts records an
        // event, so this also bounds a run of such silent steps.
        let mut steps = 0;
        loop {
            let (t, next) = self.earliest(n);
            if t > ctx.limit {
                stopped_by_horizon = ctx.limit.is_finite();
                break;
            }
            if !t.is_finite() {
                break;
            }
            steps += 1;
            if self.outcome.events.len() >= MAX_EVENTS || steps > 2 * MAX_EVENTS {
                return Err(ShotError::EventLimit);
            }
            now = t;
            match next {
                Next::Own(i) => self.resolve_own(i, t, &ctx),
                Next::Pair => self.resolve_group(t, n, &ctx),
            }
        }
        let moving = self
            .pieces
            .iter()
            .any(|p| !(p.start.motion == MotionState::Stationary || p.start.motion.is_gone()));
        let end = if stopped_by_horizon || (moving && ctx.limit.is_finite()) {
            ctx.limit
        } else {
            now
        };
        let out = &mut self.outcome;
        out.duration = end;
        for p in &self.pieces {
            let mut s = p.state_at(end.min(p.t_end), r);
            s.pos = table.to_scene(s.pos);
            out.finals.push(s);
        }
        Ok(())
    }

    fn earliest(&self, n: usize) -> (f64, Next) {
        let mut best = f64::INFINITY;
        let mut next = Next::Pair;
        for (i, own) in self.own.iter().enumerate() {
            if own.t < best {
                best = own.t;
                next = Next::Own(i);
            }
        }
        for &t in &self.row[..n] {
            if t < best {
                best = t;
                next = Next::Pair;
            }
        }
        (best, next)
    }

    /// Sets ball `i`'s next own event from `now`.
    fn predict_own(&mut self, i: usize, now: f64, ctx: &Ctx) {
        let piece = &self.pieces[i];
        if piece.start.motion == MotionState::Airborne {
            self.outcome.work.flight_checks += 1;
            let cushions = ctx.effects.cushions;
            let (t, flight) = airborne::next_event(piece, now, ctx.table, ctx.params, cushions);
            self.own[i] = Own {
                t,
                kind: OwnKind::Flight(flight),
            };
            return;
        }
        let mut best = Own {
            t: piece.t_end,
            kind: if piece.t_end.is_finite() {
                OwnKind::Transition
            } else {
                OwnKind::Nothing
            },
        };
        let until = piece.t_end.min(ctx.limit);
        if piece.start.motion.is_translating() {
            let mut consider = |t: Option<f64>, kind: OwnKind| {
                if let Some(t) = t {
                    if t < best.t || (t == best.t && best.kind == OwnKind::Transition) {
                        best = Own { t, kind };
                    }
                }
            };
            let work = &mut self.outcome.work;
            // The box holding the ball's whole path rules out most cushions and pockets.
            let (lo, hi) = self.boxes[i];
            let near = |center: DVec2, radius: f64| {
                (center.clamp(lo, hi) - center).length_squared() <= radius * radius
            };
            if ctx.effects.pockets {
                work.pocket_checks += ctx.table.pockets.len() as u64;
                for (k, pocket) in ctx.table.pockets.iter().enumerate() {
                    if near(pocket.center, pocket.radius) {
                        let t = ball_cushion::circle_time(
                            piece,
                            pocket.center,
                            pocket.radius,
                            now,
                            until,
                        );
                        consider(t, OwnKind::Pocket(k as u8));
                    }
                }
            }
            if ctx.effects.cushions {
                work.cushion_checks += (ctx.table.rails.len() + ctx.table.jaws.len()) as u64;
                for (k, rail) in ctx.table.rails.iter().enumerate() {
                    // The box corner deepest towards the rail.
                    let n = rail.normal;
                    let corner = DVec2::new(
                        if n.x > 0.0 { lo.x } else { hi.x },
                        if n.y > 0.0 { lo.y } else { hi.y },
                    );
                    if n.dot(corner - rail.a) <= ctx.contact {
                        let t = ball_cushion::rail_time(piece, rail, now, until, ctx.contact);
                        consider(t, OwnKind::Rail(k as u8));
                    }
                }
                for (k, jaw) in ctx.table.jaws.iter().enumerate() {
                    if near(jaw.center, jaw.radius + ctx.contact) {
                        let t = ball_cushion::jaw_time(piece, jaw, now, until, ctx.contact);
                        consider(t, OwnKind::Jaw(k as u8));
                    }
                }
            }
        }
        self.own[i] = best;
    }

    /// Sets the next collision of balls `i < j` from `now`.
    fn predict_pair(&mut self, i: usize, j: usize, now: f64, ctx: &Ctx) {
        let (a, b) = (&self.pieces[i], &self.pieces[j]);
        let n = self.own.len();
        let pocketed = |p: &Piece| p.start.motion.is_gone();
        let moving = |p: &Piece| p.start.motion.is_translating();
        let t = if pocketed(a) || pocketed(b) || !(moving(a) || moving(b)) {
            None
        } else {
            self.outcome.work.pair_checks += 1;
            let ((a_lo, a_hi), (b_lo, b_hi)) = (self.boxes[i], self.boxes[j]);
            let d = 2.0 * ctx.params.ball_radius;
            let apart = a_lo.x - d > b_hi.x
                || b_lo.x - d > a_hi.x
                || a_lo.y - d > b_hi.y
                || b_lo.y - d > a_hi.y;
            if apart {
                None
            } else {
                // Either ball's own next event re-predicts this pair anyway: look no further.
                let until = self.own[i].t.min(self.own[j].t).min(ctx.limit);
                let flying = |p: &Piece| p.start.motion == MotionState::Airborne;
                if flying(a) || flying(b) {
                    self.outcome.work.flight_checks += 1;
                    airborne::collision_time(a, b, now, until, ctx.params.ball_radius)
                } else {
                    ball_ball::collision_time(a, b, now, until, ctx.params.ball_radius)
                }
            }
        };
        let t = t.unwrap_or(f64::INFINITY);
        let old = std::mem::replace(&mut self.pair[i * n + j], t);
        if t <= self.row[i] {
            self.row[i] = t;
        } else if old == self.row[i] {
            let pairs = &self.pair[i * n + i + 1..(i + 1) * n];
            self.row[i] = pairs.iter().copied().fold(f64::INFINITY, f64::min);
        }
    }

    /// Ball `i` starts a new piece at `t` in state `s`: record it and re-predict.
    fn restart(&mut self, i: usize, t: f64, s: BallState, ctx: &Ctx) {
        self.start_piece(i, t, s, ctx);
        self.predict_own(i, t, ctx);
        self.predict_pairs_of(i, t, |_| false, ctx);
    }

    /// Records ball `i`'s new piece from `t` in state `s`, without predicting anything.
    fn start_piece(&mut self, i: usize, t: f64, s: BallState, ctx: &Ctx) {
        let piece = Piece::new(t, s, &ctx.motion);
        self.pieces[i] = piece;
        self.boxes[i] = piece_box(&piece, ctx.limit);
        self.outcome.history[i].push(piece);
        self.outcome.rest_time[i] = match s.motion {
            MotionState::Stationary | MotionState::Pocketed | MotionState::OffTable => Some(t),
            _ => None,
        };
    }

    /// Re-predicts every pair of ball `i` from `t`, except with the balls `done` names.
    fn predict_pairs_of(&mut self, i: usize, t: f64, done: impl Fn(usize) -> bool, ctx: &Ctx) {
        for j in (0..self.own.len()).filter(|&j| j != i && !done(j)) {
            self.predict_pair(i.min(j), i.max(j), t, ctx);
        }
    }

    fn resolve_own(&mut self, i: usize, t: f64, ctx: &Ctx) {
        let piece = self.pieces[i];
        let r = ctx.params.ball_radius;
        let ball = i as u16;
        let (s, kind) = match self.own[i].kind {
            OwnKind::Nothing => return,
            OwnKind::Transition => {
                let s = piece.state_after_end(r);
                let kind = EventKind::Transition {
                    ball,
                    from: piece.start.motion,
                    to: s.motion,
                };
                (s, kind)
            }
            OwnKind::Pocket(k) => {
                let mut s = piece.state_at(t, r);
                s.vel = DVec2::ZERO;
                s.spin = DVec3::ZERO;
                s.motion = MotionState::Pocketed;
                s.pocket = Some(k);
                (s, EventKind::BallPocket { ball, pocket: k })
            }
            OwnKind::Rail(k) => {
                let normal = ctx.table.rails[k as usize].normal;
                let s = self.bounce(&piece, t, normal, ctx);
                (
                    s,
                    EventKind::BallCushion {
                        ball,
                        cushion: Cushion::Rail(k),
                    },
                )
            }
            OwnKind::Flight(flight) => {
                airborne::resolve(&piece, t, flight, ball, ctx.table, ctx.params, &ctx.effects)
            }
            OwnKind::Jaw(k) => {
                let center = ctx.table.jaws[k as usize].center;
                let normal = (piece.pos_at(t) - center).normalize_or_zero();
                let s = self.bounce(&piece, t, normal, ctx);
                (
                    s,
                    EventKind::BallCushion {
                        ball,
                        cushion: Cushion::Jaw(k),
                    },
                )
            }
        };
        self.outcome.events.push(Event { t, kind });
        self.restart(i, t, s, ctx);
    }

    fn bounce(&self, piece: &Piece, t: f64, normal: DVec2, ctx: &Ctx) -> BallState {
        let r = ctx.params.ball_radius;
        let mut s = piece.state_at(t, r);
        let approach = -s.vel.dot(normal);
        if approach < HOLD_SPEED && piece.acc.dot(normal) < 0.0 {
            // Pressed against the cushion by friction: the cushion holds the ball, which
            // keeps only its motion along the cushion.
            s.vel -= normal * s.vel.dot(normal).min(0.0);
            s.spin = without_normal_slip(s.vel, s.spin, normal, r);
        } else {
            let (v, w) =
                ball_cushion::bounce(s.vel, s.spin, normal, ctx.models.cushion, ctx.params);
            s.vel = v;
            s.spin = w;
        }
        s.classify(r);
        s
    }

    /// Resolves every collision predicted for time `t`, together with every ball touching
    /// the colliding balls, as one impact of the touching group ([`group_impact`]).
    fn resolve_group(&mut self, t: f64, n: usize, ctx: &Ctx) {
        let r = ctx.params.ball_radius;
        let g = &mut self.scratch;
        g.balls.clear();
        let mut fastest: f64 = 0.0;
        for i in (0..n).filter(|&i| self.row[i] == t) {
            for j in i + 1..n {
                if self.pair[i * n + j] == t {
                    let (a, b) = (&self.pieces[i], &self.pieces[j]);
                    let normal = (b.pos_at(t) - a.pos_at(t)).normalize_or_zero();
                    fastest = fastest.max((a.vel_at(t) - b.vel_at(t)).dot(normal));
                    for b in [i, j] {
                        if !g.balls.contains(&b) {
                            g.balls.push(b);
                        }
                    }
                }
            }
        }
        let seeds = g.balls.len();
        // Balls in flight meet one pair at a time, only as predicted: a ball in the air is
        // never part of a touching group (its shadow may lie on one without touching it).
        let flying = |b: usize| self.pieces[b].start.motion == MotionState::Airborne;
        let in_flight = g.balls.iter().any(|&b| flying(b));
        // Grow the group by every ball touching one of its balls (or as near as the impact's
        // speed closes in `NEAR_TIME`), transitively. A ball whose path's box is out of reach
        // cannot touch (most balls, most of the time).
        let reach = 2.0 * r + CONTACT_GAP + NEAR_TIME * fastest;
        g.positions.clear();
        g.positions.resize(n, DVec2::INFINITY);
        for k in 0..seeds {
            let b = g.balls[k];
            g.positions[b] = self.pieces[b].pos_at(t);
        }
        let mut k = if in_flight { g.balls.len() } else { 0 };
        while k < g.balls.len() {
            let b = g.balls[k];
            let p = g.positions[b];
            for j in 0..n {
                let (lo, hi) = self.boxes[j];
                let near = p.x >= lo.x - reach
                    && p.x <= hi.x + reach
                    && p.y >= lo.y - reach
                    && p.y <= hi.y + reach;
                if !near
                    || j == b
                    || self.pieces[j].start.motion == MotionState::Pocketed
                    || flying(j)
                {
                    continue;
                }
                let q = self.pieces[j].pos_at(t);
                if (q - p).length_squared() <= reach * reach && !g.balls.contains(&j) {
                    g.positions[j] = q;
                    g.balls.push(j);
                }
            }
            k += 1;
        }
        g.seeds.clear();
        g.seeds.extend_from_slice(&g.balls[..seeds]);
        // Slots in ball order: the impact must not depend on how the group was found.
        g.balls.sort_unstable();
        g.states.clear();
        for &b in &g.balls {
            g.states.push(self.pieces[b].state_at(t, r));
        }
        g.walls.clear();
        if ctx.effects.cushions && !in_flight {
            for slot in 0..g.balls.len() {
                walls_touching(g, slot, ctx);
            }
        }
        g.contacts.clear();
        g.recent.clear();
        g.kept.clear();
        g.blow.clear();
        for a in 0..g.balls.len() {
            for b in a + 1..g.balls.len() {
                let d = g.states[b].pos - g.states[a].pos;
                let touching = if in_flight {
                    self.pair[g.balls[a] * n + g.balls[b]] == t
                } else {
                    d.length_squared() <= reach * reach
                };
                if touching {
                    g.contacts.push((a, b));
                    let last = self.last[g.balls[a] * n + g.balls[b]];
                    g.recent.push(t - last < PERSIST_TIME);
                    g.kept.push(self.held[g.balls[a] * n + g.balls[b]]);
                    g.blow.push(self.blow[g.balls[a] * n + g.balls[b]]);
                }
            }
        }
        g.start.clear();
        g.start.extend(g.states.iter().map(|s| (s.vel, s.spin)));
        if in_flight {
            flight_impact(g, ctx);
        } else {
            group_impact(g, ctx);
        }
        for (k, &(a, b)) in g.contacts.iter().enumerate() {
            self.held[g.balls[a] * n + g.balls[b]] = root(&g.parent, a) == root(&g.parent, b);
            if g.acted[k] {
                let (i, j) = (g.balls[a], g.balls[b]);
                self.last[i * n + j] = t;
                if g.blow[k] > 0.0 {
                    self.blow[i * n + j] = g.blow[k];
                }
                self.outcome.events.push(Event {
                    t,
                    kind: EventKind::BallBall {
                        a: i as u16,
                        b: j as u16,
                    },
                });
            }
        }
        for w in 0..g.walls.len() {
            if g.wall_acted[w] {
                let (slot, _, cushion) = g.walls[w];
                self.outcome.events.push(Event {
                    t,
                    kind: EventKind::BallCushion {
                        ball: g.balls[slot] as u16,
                        cushion,
                    },
                });
            }
        }
        // Every changed ball (and every colliding one) gets its new piece first, so that each
        // pair among them is predicted once, from both new pieces and both new own events.
        g.changed.clear();
        for k in 0..g.balls.len() {
            let s = g.states[k];
            if (s.vel, s.spin) != g.start[k] || g.seeds.contains(&g.balls[k]) {
                g.changed.push(k);
            }
        }
        let changed = std::mem::take(&mut self.scratch.changed);
        for &k in &changed {
            let mut s = self.scratch.states[k];
            s.classify(r);
            self.start_piece(self.scratch.balls[k], t, s, ctx);
        }
        for &k in &changed {
            self.predict_own(self.scratch.balls[k], t, ctx);
        }
        let balls = std::mem::take(&mut self.scratch.balls);
        for (m, &k) in changed.iter().enumerate() {
            let earlier = |j: usize| changed[..m].iter().any(|&c| balls[c] == j);
            self.predict_pairs_of(balls[k], t, earlier, ctx);
        }
        self.scratch.balls = balls;
        self.scratch.changed = changed;
    }
}

/// Buffers reused from one collision group to the next.
#[derive(Default)]
struct Scratch {
    /// The balls of the touching group (ball indices, in order), those among them whose
    /// collision was predicted, and their states during the impact (indexed by slot).
    balls: Vec<usize>,
    seeds: Vec<usize>,
    states: Vec<BallState>,
    /// Velocity and spin of each slot before the impact.
    start: Vec<(DVec2, DVec3)>,
    /// Every ball's position at the impact instant (pocketed balls at infinity).
    positions: Vec<DVec2>,
    /// The group's contacts (slots `a < b`), whether each took part, and their normals.
    contacts: Vec<(usize, usize)>,
    acted: Vec<bool>,
    normals: Vec<DVec2>,
    /// Cushions touching a ball of the group (slot, normal into the table, which), and
    /// whether each took part.
    walls: Vec<(usize, DVec2, Cushion)>,
    wall_acted: Vec<bool>,
    /// Whether each contact's pair took part in an impact less than `PERSIST_TIME` ago, and
    /// whether that impact left it held.
    recent: Vec<bool>,
    kept: Vec<bool>,
    /// Each contact's pair's fastest approach in its last bounce, on entry; during the
    /// impact, the fastest approach at which it is bounced now (0 if it is not).
    blow: Vec<f64>,
    /// Contacts (indices) taking part in the current round, and which of them are resolved.
    active: Vec<usize>,
    done: Vec<bool>,
    /// The contacts (slots) of the connected set being resolved, and their normals.
    component: Vec<(usize, usize)>,
    component_normals: Vec<DVec2>,
    /// The simultaneous impact's impulses, their last change, and the velocities during the
    /// iteration.
    lambda: Vec<f64>,
    delta: Vec<f64>,
    vel: Vec<DVec2>,
    /// Contacts per body in the impact, each body's mass (in balls), and each contact's
    /// bodies.
    degree: Vec<usize>,
    size: Vec<f64>,
    bodies: Vec<(usize, usize)>,
    /// Slots whose state changed; each slot's acceleration after the impact; union-find
    /// parents of held contacts.
    changed: Vec<usize>,
    acc: Vec<DVec2>,
    parent: Vec<usize>,
}

/// A box holding the whole path of a piece (up to the horizon `limit`).
fn piece_box(p: &Piece, limit: f64) -> (DVec2, DVec2) {
    let end = p.t_end.min(limit);
    if end.is_finite() || !p.start.motion.is_translating() {
        p.path_box(p.t0, end.max(p.t0))
    } else {
        (DVec2::NEG_INFINITY, DVec2::INFINITY)
    }
}

#[derive(Clone, Copy, Debug)]
enum Next {
    Own(usize),
    Pair,
}

/// Resolves the impact of a touching group: every contact of the group (within
/// `CONTACT_GAP`, or what the impact closes in `NEAR_TIME`) takes part, whether or not its
/// own collision was predicted.
///
/// The impact runs in rounds. Each round takes every contact approaching faster than
/// `HOLD_SPEED` and resolves it from the velocities the previous round left: a contact that
/// shares no body with another by the pairwise model (restitution, throw, spin transfer), a
/// connected set of them as one simultaneous impact ([`simultaneous_impact`]). A body is a
/// ball, or a held set when the group meets slower than `PERSIST_SPEED`. A line of
/// touching balls is so resolved as the wave a real cradle carries, one contact after the
/// other, and the far ball leaves. Within a round every contact is updated from the same
/// velocities, so the result does not depend on how the balls are numbered. What the rounds
/// leave is settled ([`settle`]). Each contact that took part gives one event.
fn group_impact(g: &mut Scratch, ctx: &Ctx) {
    g.acted.clear();
    g.acted.resize(g.contacts.len(), false);
    g.normals.clear();
    for &(a, b) in &g.contacts {
        g.normals
            .push((g.states[b].pos - g.states[a].pos).normalize_or_zero());
    }
    // A pair pressed together by the cloth that meets again soon after its last impact is a
    // sustained push: it is settled (held), not bounced.
    // Slot `n` is the cushions: one body that does not move.
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    if g.recent.contains(&true) {
        accelerations(g, ctx);
    }
    // Slower than a push's hop, or than what a blow leaves its pair (each ball keeps about
    // (1 − e)/2 of a blow's speed), it is the settling of that push or blow.
    let residual = (1.0 - restitution(ctx)) / 2.0;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let slow = PERSIST_SPEED.max(residual * g.blow[k]);
        g.recent[k] = g.recent[k]
            && approach(g, k) < slow
            && (g.acc[a] - g.acc[b]).dot(g.normals[k]) > TOUCH_ACCEL;
        g.blow[k] = 0.0;
    }
    g.wall_acted.clear();
    g.wall_acted.resize(g.walls.len(), false);
    // A held set met slower than a push moves as one body in the rounds too: a slow meeting
    // with it is one contact, not a wave through every contact of the set. A faster blow
    // releases it, and the wave runs through it as through any touching line.
    let fastest = (0..g.contacts.len()).fold(0.0f64, |m, k| m.max(approach(g, k)));
    let bodies = fastest <= PERSIST_SPEED && join_kept(g);
    let rounds = 4 * (g.contacts.len() + g.walls.len()) + 8;
    for _ in 0..rounds {
        g.active.clear();
        for k in 0..g.contacts.len() {
            let u = approach(g, k);
            if u > HOLD_SPEED && !g.recent[k] {
                g.active.push(k);
                g.acted[k] = true;
                g.blow[k] = g.blow[k].max(u);
            }
        }
        let walls_approach = g
            .walls
            .iter()
            .any(|&(slot, normal, _)| -g.states[slot].vel.dot(normal) > HOLD_SPEED);
        if g.active.is_empty() && !walls_approach {
            break;
        }
        g.done.clear();
        g.done.resize(g.active.len(), false);
        for first in 0..g.active.len() {
            if g.done[first] {
                continue;
            }
            g.done[first] = true;
            g.component.clear();
            g.component_normals.clear();
            g.component.push(g.contacts[g.active[first]]);
            g.component_normals.push(g.normals[g.active[first]]);
            let mut k = 0;
            while k < g.component.len() {
                // Contacts sharing a body (a ball, or a held set) are one simultaneous impact.
                let (a, b) = g.component[k];
                let (a, b) = (root(&g.parent, a), root(&g.parent, b));
                for m in 0..g.active.len() {
                    let contact = g.contacts[g.active[m]];
                    let (c, d) = (root(&g.parent, contact.0), root(&g.parent, contact.1));
                    if !g.done[m] && (c == a || c == b || d == a || d == b) {
                        g.done[m] = true;
                        g.component.push(contact);
                        g.component_normals.push(g.normals[g.active[m]]);
                    }
                }
                k += 1;
            }
            let (a, b) = g.component[0];
            // A lone contact between two single balls takes the pairwise model (with throw
            // and spin transfer); one with a held set, the simultaneous impact of bodies.
            let single = |m: usize| {
                !bodies
                    || (0..g.states.len())
                        .all(|o| o == m || root(&g.parent, o) != root(&g.parent, m))
            };
            if g.component.len() == 1 && single(a) && single(b) {
                collide_pair(&mut g.states, a, b, ctx);
            } else {
                simultaneous_impact(g, restitution(ctx));
            }
        }
        // A ball driven into a cushion bounces off it, unless one of its ball contacts
        // acts in this round (then the cushion waits for the next round).
        for w in 0..g.walls.len() {
            let (slot, normal, _) = g.walls[w];
            let s = &g.states[slot];
            let busy = g.active.iter().any(|&k| {
                let (a, b) = g.contacts[k];
                a == slot || b == slot
            });
            if -s.vel.dot(normal) > HOLD_SPEED && !busy {
                let (v, w_) =
                    ball_cushion::bounce(s.vel, s.spin, normal, ctx.models.cushion, ctx.params);
                g.states[slot].vel = v;
                g.states[slot].spin = w_;
                g.wall_acted[w] = true;
            }
        }
    }
    // Nothing to settle when every contact opens faster than a push could hold it and no
    // ball touches a cushion (the common case: two balls that bounced apart).
    let open = (0..g.contacts.len()).all(|k| approach(g, k) < -HOLD_SPEED);
    if !(open && g.walls.is_empty()) {
        settle(g, ctx);
    }
}

/// The ball–ball restitution of the collision model.
fn restitution(ctx: &Ctx) -> f64 {
    match ctx.models.ball_ball {
        BallBallModel::Ideal => 1.0,
        BallBallModel::Frictional => ctx.params.e_ball,
    }
}

/// The speed at which contact `k` of the group closes (negative: opening).
fn approach(g: &Scratch, k: usize) -> f64 {
    let (a, b) = g.contacts[k];
    (g.states[a].vel - g.states[b].vel).dot(g.normals[k])
}

/// Ends a group impact so that no contact of the group is left to collide again at the same
/// instant. A contact still approaching (slower than `HOLD_SPEED`, or after the last round)
/// takes a perfectly inelastic impact. A contact pressed together by the cloth (friction,
/// or a ball's own spin driving it on) that is not opening faster than `HOLD_SPEED` is
/// *held*: the balls it joins move on as one body, each with the group's average velocity
/// and spin, until something separates them. Without holding, the push would come back as
/// an endless stream of ever smaller bounces. Both steps keep momentum and never add energy
/// (the average minimises kinetic energy at fixed momentum).
fn settle(g: &mut Scratch, ctx: &Ctx) {
    /// Passes of inelastic impact and holding: holding can make a neighbour approach.
    const PASSES: usize = 8;
    // Held contacts stay held for the rest of the impact: balls moving as one no longer
    // press into each other, but must still share what a later pass gives one of them. A
    // contact held before that the rounds left moving as one is still held: a push on a
    // held set moves it as one body, without an event inside it.
    // Slot `n` is the cushions: one body that does not move.
    join_kept(g);
    for _ in 0..PASSES {
        // Every contact between different bodies takes part; the impact itself decides
        // which carry an impulse.
        g.component.clear();
        g.component_normals.clear();
        g.active.clear();
        let mut approaching = false;
        for k in 0..g.contacts.len() {
            let (a, b) = g.contacts[k];
            if root(&g.parent, a) != root(&g.parent, b) {
                approaching |= approach(g, k) > TOUCH_SPEED;
                g.component.push(g.contacts[k]);
                g.component_normals.push(g.normals[k]);
                g.active.push(k);
            }
        }
        let wall_body = g.states.len();
        for w in 0..g.walls.len() {
            let (slot, normal, _) = g.walls[w];
            approaching |= -g.states[slot].vel.dot(normal) > TOUCH_SPEED;
            g.component.push((wall_body, slot));
            g.component_normals.push(normal);
        }
        if approaching {
            simultaneous_impact(g, 0.0);
            for m in 0..g.component.len() {
                if g.lambda[m] > 0.0 {
                    if m < g.active.len() {
                        g.acted[g.active[m]] = true;
                    } else {
                        g.wall_acted[m - g.active.len()] = true;
                    }
                }
            }
        }
        let mut held = false;
        loop {
            held |= share_motion(g);
            if !join_pressed(g, ctx) {
                break;
            }
        }
        held |= hold_against_walls(g, ctx);
        if !approaching && !held {
            break;
        }
    }
}

/// Starts the held sets afresh (`Scratch::parent`) from the contacts held before this impact
/// whose balls still move alike; true if any set has more than one ball.
fn join_kept(g: &mut Scratch) -> bool {
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    let mut joined = false;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let (sa, sb) = (&g.states[a], &g.states[b]);
        if g.kept[k] && sa.vel == sb.vel && sa.spin == sb.spin {
            let (ra, rb) = (root(&g.parent, a), root(&g.parent, b));
            g.parent[ra.max(rb)] = ra.min(rb);
            joined = true;
        }
    }
    joined
}

/// Gives every ball of each held set the set's average velocity and spin; true if that
/// changed anything.
fn share_motion(g: &mut Scratch) -> bool {
    let n = g.states.len();
    // (The cushions' body, slot n, is never joined to a ball.)
    let mut changed = false;
    for top in 0..n {
        if g.parent[top] != top {
            continue;
        }
        let (mut vel, mut spin, mut count) = (DVec2::ZERO, DVec3::ZERO, 0.0);
        for m in 0..n {
            if root(&g.parent, m) == top {
                vel += g.states[m].vel;
                spin += g.states[m].spin;
                count += 1.0;
            }
        }
        if count > 1.0 {
            let (vel, spin) = (vel / count, spin / count);
            for m in 0..n {
                let s = &mut g.states[m];
                if root(&g.parent, m) == top && (s.vel != vel || s.spin != spin) {
                    s.vel = vel;
                    s.spin = spin;
                    changed = true;
                }
            }
        }
    }
    changed
}

/// Joins the held sets of every contact pressed together by the cloth and not opening faster
/// than `HOLD_SPEED`; true if any joined.
fn join_pressed(g: &mut Scratch, ctx: &Ctx) -> bool {
    accelerations(g, ctx);
    let mut joined = false;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let (ra, rb) = (root(&g.parent, a), root(&g.parent, b));
        let pressed = (g.acc[a] - g.acc[b]).dot(g.normals[k]) > TOUCH_ACCEL;
        if ra != rb && pressed && approach(g, k) > -HOLD_SPEED {
            g.parent[ra.max(rb)] = ra.min(rb);
            g.acted[k] = true;
            joined = true;
        }
    }
    joined
}

/// Records every cushion (rail or jaw) that the ball in `slot` touches.
fn walls_touching(g: &mut Scratch, slot: usize, ctx: &Ctx) {
    let p = g.states[slot].pos;
    let reach = ctx.contact + CONTACT_GAP;
    // Every cushion lies beyond the nose lines: a ball well inside them touches none.
    let inside = ctx.table.half - DVec2::splat(reach + ctx.params.ball_radius);
    if p.x.abs() < inside.x && p.y.abs() < inside.y {
        return;
    }
    for (k, rail) in ctx.table.rails.iter().enumerate() {
        let along = rail.b - rail.a;
        let s = along.dot(p - rail.a) / along.length_squared();
        if rail.normal.dot(p - rail.a) <= reach && (0.0..=1.0).contains(&s) {
            g.walls.push((slot, rail.normal, Cushion::Rail(k as u8)));
        }
    }
    for (k, jaw) in ctx.table.jaws.iter().enumerate() {
        let d = p - jaw.center;
        if d.length() <= jaw.radius + reach {
            g.walls
                .push((slot, d.normalize_or_zero(), Cushion::Jaw(k as u8)));
        }
    }
}

/// A held set pressed into a cushion by the cloth is held by it, as a single ball is
/// ([`Simulator::bounce`]): every ball of the set keeps only its motion along the cushion.
/// True if that changed anything.
fn hold_against_walls(g: &mut Scratch, ctx: &Ctx) -> bool {
    let r = ctx.params.ball_radius;
    let mut changed = false;
    for w in 0..g.walls.len() {
        accelerations(g, ctx);
        let (slot, normal, _) = g.walls[w];
        let s = g.states[slot];
        if s.vel.dot(normal) < HOLD_SPEED && g.acc[slot].dot(normal) < 0.0 {
            let top = root(&g.parent, slot);
            let mut vel = s.vel;
            vel -= normal * vel.dot(normal).min(0.0);
            let spin = without_normal_slip(vel, s.spin, normal, r);
            for m in 0..g.states.len() {
                let t = &mut g.states[m];
                if root(&g.parent, m) == top && (t.vel != vel || t.spin != spin) {
                    t.vel = vel;
                    t.spin = spin;
                    changed = true;
                    g.wall_acted[w] = true;
                }
            }
        }
    }
    changed
}

/// Each slot's acceleration on the cloth in its current state.
fn accelerations(g: &mut Scratch, ctx: &Ctx) {
    g.acc.clear();
    for s in &g.states {
        let mut c = *s;
        c.classify(ctx.params.ball_radius);
        g.acc.push(Piece::new(0.0, c, &ctx.motion).acc);
    }
}

fn root(parent: &[usize], mut k: usize) -> usize {
    while parent[k] != k {
        k = parent[k];
    }
    k
}

/// Several contacts at one instant as one frictionless impact with Poisson's restitution
/// `e`: the normal impulses `λ ≥ 0` of a perfectly inelastic impact are found first (every
/// contact ends not approaching, and a contact that ends separating carries no impulse: a
/// linear complementarity problem), then every impulse is scaled by `1 + e`. Scaling the
/// inelastic solution this way never adds energy for `e ≤ 1`, keeps momentum, and treats all
/// contacts alike. The complementarity problem is solved by projected Jacobi iteration, in
/// which every contact is updated from the same velocities, so the result does not depend on
/// the order of the contacts. A held set of balls (`Scratch::parent`) moves as one body of
/// their total mass.
fn simultaneous_impact(g: &mut Scratch, e: f64) {
    /// Sweeps of the iteration before giving up on further accuracy.
    const MAX_SWEEPS: usize = 10_000;
    let n = g.states.len();
    g.lambda.clear();
    g.delta.clear();
    g.vel.clear();
    g.vel.extend(g.states.iter().map(|s| s.vel));
    // Body n, the cushions, does not move: infinite mass.
    g.vel.push(DVec2::ZERO);
    g.size.clear();
    g.size.resize(n, 0.0);
    for m in 0..n {
        g.size[root(&g.parent, m)] += 1.0;
    }
    g.size.push(f64::INFINITY);
    let mut fastest: f64 = 0.0;
    g.degree.clear();
    g.degree.resize(n + 1, 0);
    g.bodies.clear();
    for (k, &(a, b)) in g.component.iter().enumerate() {
        let (a, b) = (root(&g.parent, a), root(&g.parent, b));
        g.bodies.push((a, b));
        g.lambda.push(0.0);
        g.delta.push(0.0);
        fastest = fastest.max(-(g.vel[b] - g.vel[a]).dot(g.component_normals[k]));
        g.degree[a] += 1;
        g.degree[b] += 1;
    }
    // Under-relaxation by the most contacts on one body keeps the iteration convergent.
    let omega = 1.0 / g.degree.iter().copied().max().unwrap_or(1).max(1) as f64;
    let tolerance = 1e-15 * fastest;
    for _ in 0..MAX_SWEEPS {
        let mut largest: f64 = 0.0;
        for (k, &(a, b)) in g.bodies.iter().enumerate() {
            // Separating speed, and how much each unit of impulse changes it.
            let u = (g.vel[b] - g.vel[a]).dot(g.component_normals[k]);
            let w = 1.0 / g.size[a] + 1.0 / g.size[b];
            let next = (g.lambda[k] - omega * u / w).max(0.0);
            g.delta[k] = next - g.lambda[k];
            largest = largest.max(g.delta[k].abs());
        }
        for (k, &(a, b)) in g.bodies.iter().enumerate() {
            let impulse = g.component_normals[k] * g.delta[k];
            g.vel[a] -= impulse / g.size[a];
            g.vel[b] += impulse / g.size[b];
            g.lambda[k] += g.delta[k];
        }
        if largest <= tolerance {
            break;
        }
    }
    // The impulses, scaled by 1 + e, on each body's own velocity.
    for m in 0..n {
        g.vel[m] = g.states[m].vel;
    }
    g.vel[n] = DVec2::ZERO;
    for (k, &(a, b)) in g.bodies.iter().enumerate() {
        let impulse = g.component_normals[k] * ((1.0 + e) * g.lambda[k]);
        g.vel[a] -= impulse / g.size[a];
        g.vel[b] += impulse / g.size[b];
    }
    // Members of a held set share one velocity already: they keep sharing it.
    for m in 0..n {
        g.states[m].vel = g.vel[root(&g.parent, m)];
    }
}

/// Collisions involving a ball in flight: the predicted pairs, one after the other (in
/// flight, contacts meet at one instant only by chance), with nothing held.
fn flight_impact(g: &mut Scratch, ctx: &Ctx) {
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    g.acted.clear();
    g.acted.resize(g.contacts.len(), true);
    g.blow.iter_mut().for_each(|b| *b = 0.0);
    g.wall_acted.clear();
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        collide_pair(&mut g.states, a, b, ctx);
    }
}

/// One contact approaching on its own, by the pairwise collision model.
fn collide_pair(states: &mut [BallState], a: usize, b: usize, ctx: &Ctx) {
    let (sa, sb) = (states[a], states[b]);
    if sa.motion == MotionState::Airborne || sb.motion == MotionState::Airborne {
        airborne::collide(states, a, b, restitution(ctx), ctx.params);
        return;
    }
    let (ka, kb) = ball_ball::collide(
        sa.pos,
        sb.pos,
        Kinematics {
            vel: sa.vel,
            spin: sa.spin,
        },
        Kinematics {
            vel: sb.vel,
            spin: sb.spin,
        },
        ctx.models.ball_ball,
        ctx.effects.ball_friction,
        ctx.params,
    );
    states[a].vel = ka.vel;
    states[a].spin = ka.spin;
    states[b].vel = kb.vel;
    states[b].spin = kb.spin;
}

/// The spin that leaves the ball's cloth slip with no component along `n`, changing only the
/// spin about the horizontal axis across `n`.
fn without_normal_slip(vel: DVec2, spin: DVec3, n: DVec2, r: f64) -> DVec3 {
    // slip·n = v·n − R·(ω·t) with t = (−n_y, n_x).
    let t = DVec2::new(-n.y, n.x);
    let current = spin.x * t.x + spin.y * t.y;
    let target = vel.dot(n) / r;
    let d = target - current;
    DVec3::new(spin.x + d * t.x, spin.y + d * t.y, spin.z)
}

/// Checks a shot without simulating it.
pub fn check(shot: &Shot) -> Result<(), ShotError> {
    validate(shot, &Table::for_shot(shot.table, shot.effects.pockets))
}

fn validate(shot: &Shot, table: &Table) -> Result<(), ShotError> {
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
    for i in (0..n).filter(|&i| on_table(i)) {
        // A ball in flight may be above the cushion noses' reach; its centre must still be
        // over the bed.
        let margin = if shot.balls[i].lift > 0.0 {
            0.0
        } else {
            contact
        };
        if !table.fits(table.to_engine(shot.balls[i].pos), margin) {
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
