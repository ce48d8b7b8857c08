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

use super::ball_ball::{self, Kinematics};
use super::ball_cushion;
use super::cue::{Strike, StrikeError};
use super::event::{Event, EventKind};
use super::motion::{BallState, MotionModel, MotionState, Piece};
use super::params::{BallBallModel, Effects, Models, Params};
use super::table::{Cushion, Table, TableKind};

/// A shot stops with an error past this many events: a safety net that no real shot nears
/// (a 15-ball break takes a few hundred).
pub const MAX_EVENTS: usize = 100_000;
/// Approach speed (m/s) under which a contact that is being pushed together (by friction
/// accelerations, not by speed) is held instead of bounced: bouncing would repeat forever
/// in ever shorter hops.
pub const HOLD_SPEED: f64 = 1e-3;
/// Overlap between two balls (m) that a shot may start with: rounding, not a real overlap.
pub const OVERLAP_TOLERANCE: f64 = 1e-9;
/// Most balls a shot may have (a pool rack has 16, snooker 22).
pub const MAX_BALLS: usize = 128;

/// Everything that defines a shot.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    pub table: TableKind,
    pub params: Params,
    pub models: Models,
    pub effects: Effects,
    /// Stop at this time even if balls still move.
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
    #[error("{0}")]
    Params(String),
    #[error("ball {ball}: {field} must be finite numbers")]
    NotFinite { ball: usize, field: &'static str },
    #[error("balls {a} and {b} overlap")]
    Overlap { a: usize, b: usize },
    #[error("ball {ball} is not on the playing surface")]
    OffTable { ball: usize },
    #[error("horizon is required when slide_friction, roll_friction or spin_friction is off")]
    HorizonRequired,
    #[error("horizon must be a positive finite number of seconds")]
    Horizon,
    #[error("strike.ball names no ball on the table")]
    StrikeBall,
    #[error("{0}")]
    Strike(#[from] StrikeError),
    #[error("a shot has at most {MAX_BALLS} balls")]
    TooManyBalls,
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
}

/// Kinetic energy of one ball.
pub fn kinetic_energy(s: &BallState, params: &Params) -> f64 {
    0.5 * params.ball_mass * s.vel.length_squared()
        + 0.5 * params.inertia() * s.spin.length_squared()
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
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum OwnKind {
    Nothing,
    Transition,
    Rail(u8),
    Jaw(u8),
    Pocket(u8),
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
    pub fn new() -> Self {
        Self::default()
    }

    /// The outcome of the last run, handing over its buffers.
    pub fn take(&mut self) -> Outcome {
        std::mem::take(&mut self.outcome)
    }

    /// Simulates `shot`; the outcome stays valid until the next run.
    pub fn run(&mut self, shot: &Shot) -> Result<&Outcome, ShotError> {
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
            contact: ball_cushion::contact_distance(&shot.params),
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
            if s.motion != MotionState::Pocketed {
                s.pocket = None;
                if let Some((struck, strike)) = shot.strike {
                    if struck == i {
                        let (v, w) = strike.ball_motion(&shot.params)?;
                        s.vel = v;
                        s.spin = w;
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
            let at_rest = matches!(s.motion, MotionState::Stationary | MotionState::Pocketed);
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
        loop {
            let (t, next) = self.earliest(n);
            if t > ctx.limit {
                stopped_by_horizon = ctx.limit.is_finite();
                break;
            }
            if !t.is_finite() {
                break;
            }
            if self.outcome.events.len() >= MAX_EVENTS {
                return Err(ShotError::EventLimit);
            }
            now = t;
            match next {
                Next::Own(i) => self.resolve_own(i, t, &ctx),
                Next::Pair => self.resolve_group(t, n, &ctx),
            }
        }
        let moving = self.pieces.iter().any(|p| {
            !matches!(
                p.start.motion,
                MotionState::Stationary | MotionState::Pocketed
            )
        });
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
        for i in 0..n {
            for &t in &self.pair[i * n + i + 1..(i + 1) * n] {
                if t < best {
                    best = t;
                    next = Next::Pair;
                }
            }
        }
        (best, next)
    }

    /// Sets ball `i`'s next own event from `now`.
    fn predict_own(&mut self, i: usize, now: f64, ctx: &Ctx) {
        let piece = &self.pieces[i];
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
        let pocketed = |p: &Piece| p.start.motion == MotionState::Pocketed;
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
                ball_ball::collision_time(a, b, now, until, ctx.params.ball_radius)
            }
        };
        self.pair[i * n + j] = t.unwrap_or(f64::INFINITY);
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
            MotionState::Stationary | MotionState::Pocketed => Some(t),
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

    /// Resolves every collision predicted for time `t`, as one group.
    fn resolve_group(&mut self, t: f64, n: usize, ctx: &Ctx) {
        let r = ctx.params.ball_radius;
        let g = &mut self.scratch;
        g.pairs.clear();
        g.balls.clear();
        for i in 0..n {
            for j in i + 1..n {
                if self.pair[i * n + j] == t {
                    g.pairs.push((i, j));
                    for b in [i, j] {
                        if !g.balls.contains(&b) {
                            g.balls.push(b);
                        }
                    }
                }
            }
        }
        // Work on the involved balls' states at t, indexed by slot.
        g.states.clear();
        for &b in &g.balls {
            g.states.push(self.pieces[b].state_at(t, r));
        }
        for k in 0..g.pairs.len() {
            let (i, j) = g.pairs[k];
            let slot = |b: usize| g.balls.iter().position(|&x| x == b).unwrap_or(0);
            g.pairs[k] = (slot(i), slot(j));
        }
        // Resolve each connected set of collisions on its own.
        g.done.clear();
        g.done.resize(g.pairs.len(), false);
        for start in 0..g.pairs.len() {
            if g.done[start] {
                continue;
            }
            g.done[start] = true;
            g.component.clear();
            g.component.push(g.pairs[start]);
            let mut k = 0;
            while k < g.component.len() {
                let (a, b) = g.component[k];
                for m in 0..g.pairs.len() {
                    let (c, d) = g.pairs[m];
                    if !g.done[m] && (c == a || c == b || d == a || d == b) {
                        g.done[m] = true;
                        g.component.push((c, d));
                    }
                }
                k += 1;
            }
            resolve_component(g, ctx);
        }
        for &(a, b) in &g.pairs {
            let (i, j) = (g.balls[a], g.balls[b]);
            self.outcome.events.push(Event {
                t,
                kind: EventKind::BallBall {
                    a: i.min(j) as u16,
                    b: i.max(j) as u16,
                },
            });
        }
        // Every involved ball gets its new piece first, so that each pair among them is
        // predicted once, from both new pieces and both new own events.
        let involved = self.scratch.balls.len();
        for k in 0..involved {
            let mut s = self.scratch.states[k];
            s.classify(r);
            self.start_piece(self.scratch.balls[k], t, s, ctx);
        }
        for k in 0..involved {
            self.predict_own(self.scratch.balls[k], t, ctx);
        }
        for k in 0..involved {
            let ball = self.scratch.balls[k];
            let earlier = std::mem::take(&mut self.scratch.balls);
            self.predict_pairs_of(ball, t, |j| earlier[..k].contains(&j), ctx);
            self.scratch.balls = earlier;
        }
    }
}

/// Buffers reused from one collision group to the next.
#[derive(Default)]
struct Scratch {
    /// Colliding pairs (ball indices, then slots into `balls`).
    pairs: Vec<(usize, usize)>,
    /// The balls involved, and their states at the collision instant.
    balls: Vec<usize>,
    states: Vec<BallState>,
    done: Vec<bool>,
    /// The pairs (slots) of the connected set being resolved.
    component: Vec<(usize, usize)>,
    /// The simultaneous impact's contact normals, impulses, their last change, and the
    /// velocities during the iteration and before it.
    normals: Vec<DVec2>,
    lambda: Vec<f64>,
    delta: Vec<f64>,
    vel: Vec<DVec2>,
    before: Vec<DVec2>,
    /// Contacts per ball in the impact.
    degree: Vec<usize>,
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

/// Resolves collisions that share balls at one instant. One collision is resolved by its
/// model; several are one simultaneous impact ([`simultaneous_impact`]), which does not
/// depend on how the balls are numbered, so a mirror-symmetric rack stays symmetric.
fn resolve_component(g: &mut Scratch, ctx: &Ctx) {
    if g.component.len() == 1 {
        let (a, b) = g.component[0];
        collide_pair(&mut g.states, a, b, ctx);
        return;
    }
    g.before.clear();
    g.before.extend(g.states.iter().map(|s| s.vel));
    simultaneous_impact(g, ctx);
    // A contact the impact left exactly as it was (a push, not an approach) would be found
    // again at this instant: its balls move on together.
    for k in 0..g.component.len() {
        let (a, b) = g.component[k];
        if g.states[a].vel == g.before[a] && g.states[b].vel == g.before[b] {
            merge(&mut g.states, a, b);
        }
    }
}

/// Several contacts at one instant as one frictionless impact with Poisson's restitution:
/// the normal impulses `λ ≥ 0` of a perfectly inelastic impact are found first (every
/// contact ends not approaching, and a contact that ends separating carries no impulse: a
/// linear complementarity problem), then every impulse is scaled by `1 + e`. Scaling the
/// inelastic solution this way never adds energy for `e ≤ 1`, keeps momentum, and treats all
/// contacts alike. The complementarity problem is solved by projected Jacobi iteration, in
/// which every contact is updated from the same velocities, so the result does not depend on
/// the order of the contacts. Contacts approaching slower than `HOLD_SPEED` all round are
/// perfectly inelastic, as single ones are.
fn simultaneous_impact(g: &mut Scratch, ctx: &Ctx) {
    /// Sweeps of the iteration before giving up on further accuracy.
    const MAX_SWEEPS: usize = 10_000;
    let contacts = &g.component;
    g.normals.clear();
    g.lambda.clear();
    g.delta.clear();
    g.vel.clear();
    g.vel.extend(g.states.iter().map(|s| s.vel));
    let mut fastest: f64 = 0.0;
    g.degree.clear();
    g.degree.resize(g.states.len(), 0);
    for &(a, b) in contacts {
        let n = (g.states[b].pos - g.states[a].pos).normalize_or_zero();
        g.normals.push(n);
        g.lambda.push(0.0);
        g.delta.push(0.0);
        fastest = fastest.max(-(g.vel[b] - g.vel[a]).dot(n));
        g.degree[a] += 1;
        g.degree[b] += 1;
    }
    // Under-relaxation by the most contacts on one ball keeps the iteration convergent.
    let omega = 1.0 / g.degree.iter().copied().max().unwrap_or(1).max(1) as f64;
    let tolerance = 1e-15 * fastest;
    for _ in 0..MAX_SWEEPS {
        let mut largest: f64 = 0.0;
        for (k, &(a, b)) in contacts.iter().enumerate() {
            // Separating speed; each unit of impulse changes it by 2 (equal masses).
            let u = (g.vel[b] - g.vel[a]).dot(g.normals[k]);
            let next = (g.lambda[k] - omega * 0.5 * u).max(0.0);
            g.delta[k] = next - g.lambda[k];
            largest = largest.max(g.delta[k].abs());
        }
        for (k, &(a, b)) in contacts.iter().enumerate() {
            let impulse = g.normals[k] * g.delta[k];
            g.vel[a] -= impulse;
            g.vel[b] += impulse;
            g.lambda[k] += g.delta[k];
        }
        if largest <= tolerance {
            break;
        }
    }
    let e = match ctx.models.ball_ball {
        _ if fastest < HOLD_SPEED => 0.0,
        BallBallModel::Ideal => 1.0,
        BallBallModel::Frictional => ctx.params.e_ball,
    };
    for (k, &(a, b)) in contacts.iter().enumerate() {
        let impulse = g.normals[k] * ((1.0 + e) * g.lambda[k]);
        g.states[a].vel -= impulse;
        g.states[b].vel += impulse;
    }
}

fn collide_pair(states: &mut [BallState], a: usize, b: usize, ctx: &Ctx) {
    let r = ctx.params.ball_radius;
    let (sa, sb) = (states[a], states[b]);
    let n = (sb.pos - sa.pos).normalize_or_zero();
    let approach = (sa.vel - sb.vel).dot(n);
    let accel = |s: &BallState| {
        let mut c = *s;
        c.classify(r);
        Piece::new(0.0, c, &ctx.motion).acc
    };
    let pushing = (accel(&sa) - accel(&sb)).dot(n) > 0.0;
    if approach < HOLD_SPEED && pushing {
        merge(states, a, b);
        return;
    }
    if approach < HOLD_SPEED {
        // Too slow to bounce: perfectly inelastic along the line of centres. Without this a
        // frozen cluster would trade ever smaller bounces forever (inelastic collapse).
        let common = 0.5 * (sa.vel.dot(n) + sb.vel.dot(n));
        states[a].vel += n * (common - sa.vel.dot(n));
        states[b].vel += n * (common - sb.vel.dot(n));
    } else {
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
    if states[a].vel == sa.vel && states[b].vel == sb.vel {
        // Nothing changed (a contact within rounding of at rest): make sure the pair cannot
        // be found touching-and-approaching again at this instant.
        merge(states, a, b);
    }
}

/// Two touching balls pushed together by friction (a sustained contact) move on as one:
/// both take the average velocity and spin. Momentum is kept, energy can only drop (it is
/// convex), and with identical motion they can no longer press into each other.
fn merge(states: &mut [BallState], a: usize, b: usize) {
    let vel = 0.5 * (states[a].vel + states[b].vel);
    let spin = 0.5 * (states[a].spin + states[b].spin);
    for k in [a, b] {
        states[k].vel = vel;
        states[k].spin = spin;
    }
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
    }
    if let Some((i, strike)) = shot.strike {
        if i >= shot.balls.len() || shot.balls[i].motion == MotionState::Pocketed {
            return Err(ShotError::StrikeBall);
        }
        strike.validated()?;
    }
    let r = shot.params.ball_radius;
    let contact = ball_cushion::contact_distance(&shot.params);
    let on_table = |i: usize| shot.balls[i].motion != MotionState::Pocketed;
    let n = shot.balls.len();
    for i in (0..n).filter(|&i| on_table(i)) {
        if !table.fits(table.to_engine(shot.balls[i].pos), contact) {
            return Err(ShotError::OffTable { ball: i });
        }
    }
    // Touching is allowed, and so is the overlap rounding leaves between balls the engine
    // itself brought to rest touching; more is not.
    let min_dist = 2.0 * r - OVERLAP_TOLERANCE;
    for i in (0..n).filter(|&i| on_table(i)) {
        for j in (i + 1..n).filter(|&j| on_table(j)) {
            // Scene coordinates: the same distance as in the engine's, to rounding.
            if (shot.balls[j].pos - shot.balls[i].pos).length() < min_dist {
                return Err(ShotError::Overlap { a: i, b: j });
            }
        }
    }
    Ok(())
}
