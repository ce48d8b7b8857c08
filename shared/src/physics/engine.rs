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

//!
//! The shot and its outcome are defined in `shot.rs`, the impact of a touching group in
//! `group_impact.rs`; this module re-exports both modules' public items, which are part of
//! its interface.

use glam::{DVec2, DVec3};

use super::airborne::{self, Flight};
use super::ball_ball;
use super::ball_cushion;
use super::earliest::{self, Earliest};
use super::event::{Event, EventKind};
use super::extent::{self, ball, Balls, Extent, Mobility};
use super::group_impact::{self, refill, Scratch};
use super::motion::{BallState, MotionModel, MotionState, Piece};
use super::mouths::Mouth;
use super::roots;
use super::shot::{validate, Ctx};
use super::table::{Cushion, Table};

pub use super::group_impact::{CONTACT_GAP, HOLD_SPEED, NEAR_TIME, PERSIST_SPEED, PERSIST_TIME};
pub use super::shot::{
    check, kinetic_energy, mechanical_energy, Outcome, Shot, ShotError, Work, MAX_BALLS,
    MAX_EVENTS, OVERLAP_TOLERANCE,
};

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

/// Simulates shots, reusing its buffers so that steady-state simulation allocates nothing.
#[derive(Default)]
pub struct Simulator {
    table: Option<Table>,
    pieces: Vec<Piece>,
    /// For each ball, the time of its next own event, and which event it is.
    own_t: Vec<f64>,
    own: Vec<OwnKind>,
    /// The ball with the earliest own event.
    own_first: Earliest,
    /// For each pair `i < j`, its next collision, or while `solved` is false a lower bound on
    /// it: a pair is solved only when its bound is the earliest candidate (most never are:
    /// one of the balls changes first).
    pair: Vec<f64>,
    /// For each pair `i < j`, whether `pair` holds the exact collision time.
    solved: Vec<bool>,
    /// For each unsolved pair `i < j`, the time it was predicted from: solving it later
    /// from that same time gives the very bits an immediate solve would have.
    since: Vec<f64>,
    /// For each ball `i`, the earliest collision among its pairs `i < j`: the loop looks
    /// for the next event over these instead of over every pair.
    row: Vec<f64>,
    /// The ball whose row holds the earliest collision.
    row_first: Earliest,
    /// For each ball `i` whose `row[i]` is finite, a `j` whose pair holds it.
    arg: Vec<usize>,
    /// For each ball, the balls whose pair with it holds a time (is not infinite): a pass
    /// over its pairs writes only these and those within reach.
    links: Vec<Balls>,
    /// For each pair `i < j` (at `i·n + j`), when it last took part in an impact.
    last: Vec<f64>,
    /// For each pair `i < j`, whether its last impact left it held (moving as one).
    held: Vec<bool>,
    /// For each pair `i < j`, the fastest it approached in the last impact that bounced it.
    blow: Vec<f64>,
    /// For each ball, how its current piece moves and the box holding its whole path.
    extents: Vec<Extent>,
    /// The balls whose piece moves (on the cloth or in flight), and those not gone: a ball
    /// that moves may meet any ball still there, one that does not only those that move.
    moving: Balls,
    present: Balls,
    /// The table's pockets, each with its jaws.
    mouths: Vec<Mouth>,
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
            let table = build();
            self.mouths = Mouth::of(&table);
            self.table = Some(table);
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
        for mouth in &mut self.mouths {
            mouth.reach(ctx.contact.max(0.0));
        }
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
        self.extents.clear();
        (self.moving, self.present) = (0, 0);
        for i in 0..n {
            self.extents.push(Extent::of(&self.pieces[i], &ctx));
            self.note_mobility(i);
        }
        refill(&mut self.own_t, n, f64::INFINITY);
        refill(&mut self.own, n, OwnKind::Nothing);
        self.own_first = Earliest::of(&self.own_t);
        refill(&mut self.pair, n * n, f64::INFINITY);
        refill(&mut self.solved, n * n, true);
        refill(&mut self.since, n * n, 0.0);
        refill(&mut self.row, n, f64::INFINITY);
        self.row_first = Earliest::of(&self.row);
        refill(&mut self.arg, n, 0);
        refill(&mut self.links, n, 0);
        refill(&mut self.last, n * n, f64::NEG_INFINITY);
        refill(&mut self.held, n * n, false);
        refill(&mut self.blow, n * n, 0.0);
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
            let (t, next) = self.earliest(n, &ctx);
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

    /// The next event: the earliest own event or collision (own events first at the same
    /// instant), solving the pairs whose lower bound is the earliest candidate until the
    /// earliest is exact. Both earliests are kept up to date as times change ([`Earliest`]),
    /// so nothing is scanned here.
    fn earliest(&mut self, n: usize, ctx: &Ctx) -> (f64, Next) {
        let (own_best, own_next) = match self.own_first.get(&self.own_t) {
            Some((i, t)) => (t, Next::Own(i)),
            None => (f64::INFINITY, Next::Pair),
        };
        loop {
            let (first, best) = match self.row_first.get(&self.row) {
                Some((first, best)) if best < own_best => (first, best),
                _ => return (own_best, own_next),
            };
            let k = first * n + self.arg[first];
            debug_assert_eq!(self.pair[k], best);
            if !self.solved[k] {
                // The usual case: the earliest is one pair's bound.
                self.solve_pair(first, self.arg[first], ctx);
                continue;
            }
            // Exact; any other pair at the same time must be exact too.
            if !self.solve_pairs_at(best, first, n, ctx) {
                return (best, Next::Pair);
            }
        }
    }

    /// Solves every unsolved pair whose bound is `t`, in the rows from `first` on (no row
    /// before it holds `t`); false when there was none.
    fn solve_pairs_at(&mut self, t: f64, first: usize, n: usize, ctx: &Ctx) -> bool {
        let mut any = false;
        for i in first..n {
            if self.row[i] != t {
                continue;
            }
            // Only the row's links hold a time: the balls `j > i` of `links[i]` (shifted
            // twice, as `i + 1` may be 128, past a shift's range). The same line walks them in
            // `resolve_group`; made a function, even one always inlined, the 8-ball break took
            // 2,100 more instructions (0.5 %).
            for j in extent::members(self.links[i] >> i >> 1).map(|j| i + 1 + j) {
                let k = i * n + j;
                if self.pair[k] == t && !self.solved[k] {
                    self.solve_pair(i, j, ctx);
                    any = true;
                }
            }
        }
        any
    }

    /// Replaces the bound of the unsolved pair `i < j` by its exact collision time.
    fn solve_pair(&mut self, i: usize, j: usize, ctx: &Ctx) {
        let n = self.row.len();
        let k = i * n + j;
        let bound = self.pair[k];
        self.solved[k] = true;
        // Only a pair on the cloth is left unsolved (`deferred_collision`), with a bound from
        // `ball_ball::earliest_contact` on the same pieces, time and horizon.
        let (a, b) = (&self.pieces[i], &self.pieces[j]);
        let until = self.horizon(i, j, ctx);
        let exact = ball_ball::collision_time(a, b, self.since[k], until, ctx.params.ball_radius)
            .unwrap_or(f64::INFINITY);
        debug_assert!(exact >= bound, "pair {i}-{j}: bound {bound} above {exact}");
        self.set_pair(i, j, exact);
    }

    /// Sets ball `i`'s next own event from `now`.
    fn predict_own(&mut self, i: usize, now: f64, ctx: &Ctx) {
        let piece = &self.pieces[i];
        if piece.start.motion == MotionState::Airborne {
            self.outcome.work.flight_checks += 1;
            let cushions = ctx.effects.cushions;
            let (t, flight) = airborne::next_event(piece, now, ctx.table, ctx.params, cushions);
            self.set_own(i, t, OwnKind::Flight(flight));
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
            // Of equal times, the candidate first in the order pockets, rails, jaws wins
            // (and any of them over the transition), whatever order they are tried in. One
            // whose lower bound (a closed form, see `roots::contact_bound`) is already later
            // than the best so far cannot be taken, and is not solved.
            let rails_from = ctx.table.pockets.len();
            let jaws_from = rails_from + ctx.table.rails.len();
            let rank = |kind: OwnKind| match kind {
                OwnKind::Pocket(k) => k as usize,
                OwnKind::Rail(k) => rails_from + k as usize,
                OwnKind::Jaw(k) => jaws_from + k as usize,
                _ => usize::MAX,
            };
            let consider = |best: &mut Own, t: Option<f64>, kind: OwnKind| {
                if let Some(t) = t {
                    if t < best.t || (t == best.t && rank(kind) < rank(best.kind)) {
                        *best = Own { t, kind };
                    }
                }
            };
            let can_beat =
                |best: &Own, bound: Option<f64>| bound.is_some_and(|b| now + b <= best.t);
            let (p, v, acc) = (piece.pos_at(now), piece.vel_at(now), piece.acc);
            let reach = until - now;
            let work = &mut self.outcome.work;
            // The box holding the ball's whole path rules out most cushions and pockets.
            let Extent { lo, hi, .. } = self.extents[i];
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
                        let line = ball_cushion::rail_line(piece, rail, now, ctx.contact);
                        let [c0, c1, c2] = line;
                        if can_beat(&best, roots::line_bound(c0, c1, c2, reach)) {
                            let t = ball_cushion::rail_time(piece, rail, now, until, line);
                            consider(&mut best, t, OwnKind::Rail(k as u8));
                        }
                    }
                }
            }
            // Rails first: a ball that reaches one (most fast balls) can meet a pocket or a
            // jaw only on its path up to there, a far smaller box than its whole path's.
            let (lo, hi) = if best.t < until {
                let (l, h) = piece.path_box(now, best.t);
                // Nor do this ball's pairs look past its own event, which is at the latest
                // here: their box tests need only its path up to there.
                self.extents[i].narrow(l, h, 2.0 * ctx.params.ball_radius);
                let margin = DVec2::splat(NARROW_MARGIN);
                (lo.max(l - margin), hi.min(h + margin))
            } else {
                (lo, hi)
            };
            let near = |center: DVec2, radius: f64| {
                (center.clamp(lo, hi) - center).length_squared() <= radius * radius
            };
            if ctx.effects.pockets {
                work.pocket_checks += ctx.table.pockets.len() as u64;
            }
            // A pocket and its jaws are looked at only when the path comes near their mouth.
            for mouth in &self.mouths {
                if !mouth.near(lo, hi) {
                    continue;
                }
                if let (Some(k), true) = (mouth.pocket, ctx.effects.pockets) {
                    let pocket = &ctx.table.pockets[k as usize];
                    if near(pocket.center, pocket.radius)
                        && can_beat(
                            &best,
                            roots::contact_bound(p - pocket.center, v, acc, pocket.radius, reach),
                        )
                    {
                        let t = ball_cushion::circle_time(
                            piece,
                            pocket.center,
                            pocket.radius,
                            now,
                            until,
                        );
                        consider(&mut best, t, OwnKind::Pocket(k));
                    }
                }
                if !ctx.effects.cushions {
                    continue;
                }
                for &k in &mouth.jaws {
                    let jaw = &ctx.table.jaws[k as usize];
                    let radius = jaw.radius + ctx.contact;
                    if near(jaw.center, radius)
                        && can_beat(
                            &best,
                            roots::contact_bound(p - jaw.center, v, acc, radius, reach),
                        )
                    {
                        let t = ball_cushion::jaw_time(piece, jaw, now, until, ctx.contact);
                        consider(&mut best, t, OwnKind::Jaw(k));
                    }
                }
            }
        }
        self.set_own(i, best.t, best.kind);
    }

    fn set_own(&mut self, i: usize, t: f64, kind: OwnKind) {
        self.own_first.set(&mut self.own_t, i, t);
        self.own[i] = kind;
    }

    /// Sets the next collision of balls `i < j` from `now`.
    #[inline]
    fn predict_pair(&mut self, i: usize, j: usize, now: f64, ctx: &Ctx) {
        let (a, b) = (&self.extents[i], &self.extents[j]);
        let t = if !a.may_meet(b) {
            f64::INFINITY
        } else {
            self.outcome.work.pair_checks += 1;
            if a.apart(b) {
                f64::INFINITY
            } else {
                self.deferred_collision(i, j, now, ctx)
            }
        };
        self.set_pair(i, j, t);
    }

    /// The next collision of balls `i < j` after `now`, or a lower bound on it marked
    /// unsolved, to be solved (from `now`) only if it becomes the earliest candidate. Any
    /// other value written to the pair later (a new prediction) marks it again.
    fn deferred_collision(&mut self, i: usize, j: usize, now: f64, ctx: &Ctx) -> f64 {
        let n = self.row.len();
        let k = i * n + j;
        let flying = Mobility::Flying;
        let until = self.horizon(i, j, ctx);
        let (a, b) = (&self.pieces[i], &self.pieces[j]);
        if self.extents[i].mobility == flying || self.extents[j].mobility == flying {
            // Solved at once: a ball in flight meets few others, and only as predicted.
            self.solved[k] = true;
            self.outcome.work.flight_checks += 1;
            let t = airborne::collision_time(a, b, now, until, ctx.params.ball_radius);
            return t.unwrap_or(f64::INFINITY);
        }
        match ball_ball::earliest_contact(a, b, now, until, ctx.params.ball_radius) {
            None => {
                self.solved[k] = true;
                f64::INFINITY
            }
            Some(bound) => {
                self.solved[k] = false;
                self.since[k] = now;
                bound
            }
        }
    }

    /// How far a prediction of the pair `i`, `j` looks: either ball's own next event
    /// re-predicts the pair anyway, so no further.
    #[inline(always)]
    fn horizon(&self, i: usize, j: usize, ctx: &Ctx) -> f64 {
        self.own_t[i].min(self.own_t[j]).min(ctx.limit)
    }

    /// Records `t` as the next collision of balls `i < j`, keeping `row[i]` the earliest of
    /// its row.
    #[inline(always)]
    fn set_pair(&mut self, i: usize, j: usize, t: f64) {
        let n = self.row.len();
        let old = std::mem::replace(&mut self.pair[i * n + j], t);
        if t == old {
            // Most pairs stay out of reach: nothing to update.
            return;
        }
        if (old == f64::INFINITY) != (t == f64::INFINITY) {
            self.links[i] ^= ball(j);
            self.links[j] ^= ball(i);
        }
        if t <= self.row[i] {
            self.row_first.set(&mut self.row, i, t);
            self.arg[i] = j;
        } else if old == self.row[i] {
            let (arg, best) = earliest::first_min(&self.pair[i * n + i + 1..(i + 1) * n])
                .map_or((0, f64::INFINITY), |(m, p)| (i + 1 + m, p));
            self.row_first.set(&mut self.row, i, best);
            self.arg[i] = arg;
        }
    }

    /// Ball `i` starts a new piece at `t` in state `s`: record it and re-predict.
    fn restart(&mut self, i: usize, t: f64, s: BallState, ctx: &Ctx) {
        self.start_piece(i, t, s, ctx);
        self.predict_own(i, t, ctx);
        self.predict_pairs_of(i, t, 0, ctx);
    }

    /// Records ball `i`'s new piece from `t` in state `s`, without predicting anything.
    fn start_piece(&mut self, i: usize, t: f64, s: BallState, ctx: &Ctx) {
        let piece = Piece::new(t, s, &ctx.motion);
        self.pieces[i] = piece;
        self.extents[i] = Extent::of(&piece, ctx);
        self.note_mobility(i);
        self.outcome.history[i].push(piece);
        self.outcome.rest_time[i] = match s.motion {
            MotionState::Stationary | MotionState::Pocketed | MotionState::OffTable => Some(t),
            _ => None,
        };
    }

    /// Records ball `i`'s mobility in the sets of balls that move and that are present.
    fn note_mobility(&mut self, i: usize) {
        let mobility = self.extents[i].mobility;
        let moves = matches!(mobility, Mobility::Cloth | Mobility::Flying);
        let here = mobility != Mobility::Gone;
        self.moving = self.moving & !ball(i) | Balls::from(moves) << i;
        self.present = self.present & !ball(i) | Balls::from(here) << i;
    }

    /// Re-predicts every pair of ball `i` from `t`, except with the balls in `done`.
    fn predict_pairs_of(&mut self, i: usize, t: f64, done: Balls, ctx: &Ctx) {
        // The pass over every other ball: most are dismissed by their boxes alone, and a pair
        // dismissed now that held no time before needs no writing.
        let meet = match self.extents[i].mobility {
            Mobility::Gone => 0,
            Mobility::Still => self.moving,
            Mobility::Cloth | Mobility::Flying => self.present,
        } & !ball(i);
        let near = extent::within_reach(&self.extents, i) & meet;
        let others = !done;
        self.outcome.work.pair_checks += u64::from(extent::count(meet & others));
        for j in extent::members((near | self.links[i]) & others) {
            let (lo, hi) = (i.min(j), i.max(j));
            let time = if near & ball(j) != 0 {
                self.deferred_collision(lo, hi, t, ctx)
            } else {
                f64::INFINITY
            };
            self.set_pair(lo, hi, time);
        }
    }

    fn resolve_own(&mut self, i: usize, t: f64, ctx: &Ctx) {
        let piece = &self.pieces[i];
        let r = ctx.params.ball_radius;
        let ball = i as u16;
        let (s, kind) = match self.own[i] {
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
                let s = self.bounce(piece, t, normal, ctx);
                (
                    s,
                    EventKind::BallCushion {
                        ball,
                        cushion: Cushion::Rail(k),
                    },
                )
            }
            OwnKind::Flight(flight) => airborne::resolve(piece, t, flight, ball, ctx),
            OwnKind::Jaw(k) => {
                let center = ctx.table.jaws[k as usize].center;
                let normal = (piece.pos_at(t) - center).normalize_or_zero();
                let s = self.bounce(piece, t, normal, ctx);
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
            s.spin = group_impact::without_normal_slip(s.vel, s.spin, normal, r);
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
            // A pair holding `t` holds a time: it is among the row's links (walked as in
            // `solve_pairs_at`).
            for j in extent::members(self.links[i] >> i >> 1).map(|j| i + 1 + j) {
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
        let flying = |piece: &Piece| piece.start.motion == MotionState::Airborne;
        let in_flight = g.balls.iter().any(|&b| flying(&self.pieces[b]));
        // Grow the group by every ball touching one of its balls (or as near as the impact's
        // speed closes in `NEAR_TIME`), transitively. A ball whose path's box is out of reach
        // cannot touch (most balls, most of the time).
        let reach = 2.0 * r + CONTACT_GAP + NEAR_TIME * fastest;
        // Only the group's balls' positions are read, each written when it joins.
        if g.positions.len() < n {
            g.positions.resize(n, DVec2::INFINITY);
        }
        let (pieces, extents) = (&self.pieces, &self.extents);
        let mut grouped: Balls = 0;
        for k in 0..seeds {
            let b = g.balls[k];
            g.positions[b] = pieces[b].pos_at(t);
            grouped |= ball(b);
        }
        let mut k = if in_flight { g.balls.len() } else { 0 };
        while k < g.balls.len() {
            let p = g.positions[g.balls[k]];
            for (j, (extent, piece)) in extents.iter().zip(pieces).enumerate() {
                let Extent { lo, hi, .. } = *extent;
                let near = p.x >= lo.x - reach
                    && p.x <= hi.x + reach
                    && p.y >= lo.y - reach
                    && p.y <= hi.y + reach;
                if !near
                    || grouped & ball(j) != 0
                    || piece.start.motion == MotionState::Pocketed
                    || flying(piece)
                {
                    continue;
                }
                let q = piece.pos_at(t);
                if (q - p).length_squared() <= reach * reach {
                    g.positions[j] = q;
                    g.balls.push(j);
                    grouped |= ball(j);
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
                group_impact::walls_touching(g, slot, ctx);
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
            group_impact::flight_impact(g, ctx);
        } else {
            group_impact::group_impact(g, ctx);
        }
        for (k, &(a, b)) in g.contacts.iter().enumerate() {
            self.held[g.balls[a] * n + g.balls[b]] =
                group_impact::root(&g.parent, a) == group_impact::root(&g.parent, b);
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
        let mut earlier = 0;
        for &k in &changed {
            self.predict_pairs_of(balls[k], t, earlier, ctx);
            earlier |= ball(balls[k]);
        }
        self.scratch.balls = balls;
        self.scratch.changed = changed;
    }
}

/// How far (m) a box narrowed to a ball's path up to an earlier time is widened: a contact
/// the root solver finds is nearer than this to the exact one (the rounding of positions of
/// a few metres is some 1e-15 m).
const NARROW_MARGIN: f64 = 1e-9;

#[derive(Clone, Copy, Debug)]
enum Next {
    Own(usize),
    Pair,
}
