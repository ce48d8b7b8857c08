//! Balls in flight: when they land, what they meet, and how the slate, the cushion nose and
//! other balls answer them.
//!
//! A ball in flight moves on a ballistic arc (see `motion.rs`), so everything it can meet is
//! the first root of a polynomial in time, found by the same root finder as every other
//! contact:
//!
//! - the cloth: its height above rest is a quadratic, and the piece ends when it reaches zero;
//! - another ball: the squared 3-D distance between the centres, `|Δr|² + Δz²`, is a quartic
//!   (a quadratic when both are in flight: gravity cancels in `Δz`), so a ball in flight can
//!   clear a ball on the cloth;
//! - a cushion nose, a horizontal edge at the cushion height along each rail: the squared
//!   distance from the centre to that edge is a quartic; a ball whose centre crosses the nose
//!   line without touching it has cleared the rail and leaves the table.
//!
//! The slate answers a ball moving down into it with restitution `e_table` and Coulomb
//! friction `mu_slide` at the contact point (capped at the impulse that ends the slip, so it
//! never adds energy); a rebound that would rise less than [`SETTLE_HEIGHT`] is not a flight:
//! the ball stays on the cloth and slides. Friction at the contact point leaves the angular
//! momentum about that point unchanged, which is what makes Coriolis' massé rule hold through
//! the bounces.
//!
//! Collisions in flight are frictionless: between balls, restitution `e_ball` along the 3-D
//! line of centres; with a cushion nose, restitution `e_cushion` along the line from the
//! nose edge to the centre. Spin is kept in both.

use glam::{DVec2, DVec3};

use super::ball_ball;
use super::event::EventKind;
use super::motion::{BallState, MotionState, Piece};
use super::octic::{self, Octic};
use super::params::{CushionModel, Params};
use super::roots::{first_contact, stays_apart, Poly, Touch, TOUCH_ACCEL, TOUCH_SPEED};
use super::shot::Ctx;
use super::table::{Cushion, Jaw, Rail, Table};

/// A rebound that would lift the ball less than this (m) ends the flight: the ball settles
/// onto the cloth and slides (pooltool's cut-off).
pub const SETTLE_HEIGHT: f64 = 0.005;

/// What ends a piece of flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flight {
    /// The ball reaches the cloth.
    Land,
    /// The ball touches the nose of rail `k`.
    Nose(u8),
    /// The ball's centre crosses the nose line of rail `k` above it: it leaves the table.
    Leave(u8),
    /// The ball touches the nose of jaw `k`.
    Jaw(u8),
    /// The ball's centre comes over the rounded cushion of jaw `k`: it leaves the table.
    OverJaw(u8),
}

/// The next event of a ball in flight after `now` (the landing, at the latest), and how many
/// cushion predictions it took.
pub fn next_event(
    piece: &Piece,
    now: f64,
    table: &Table,
    params: &Params,
    cushions: bool,
) -> (f64, Flight) {
    let mut best = (piece.t_end, Flight::Land);
    if !cushions {
        return best;
    }
    for (k, rail) in table.rails.iter().enumerate() {
        let until = best.0;
        if let Some(t) = nose_time(piece, rail, now, until, params) {
            best = (t, Flight::Nose(k as u8));
        }
        if let Some(t) = leave_time(piece, rail, now, best.0) {
            if t < best.0 {
                best = (t, Flight::Leave(k as u8));
            }
        }
    }
    for (k, jaw) in table.jaws.iter().enumerate() {
        if let Some(t) = jaw_time(piece, jaw, now, best.0, params) {
            best = (t, Flight::Jaw(k as u8));
        }
        if let Some(t) = over_jaw_time(piece, jaw, now, best.0) {
            if t < best.0 {
                best = (t, Flight::OverJaw(k as u8));
            }
        }
    }
    best
}

/// First time in (now, until] at which the ball touches the nose of `jaw`, a horizontal
/// circle of the jaw's radius `ρ` at the cushion height `h` about the jaw's axis, while
/// approaching it. With `q(τ)` the squared horizontal distance from the axis to the centre
/// (a quadratic: nothing slows a ball in flight) and `Δz(τ)` the centre's height above the
/// nose, the squared distance to the circle is `(√q − ρ)² + Δz²`; it is `R²` where
/// `A(τ) = q + ρ² + Δz² − R²` equals `2ρ·√q`, so contact is the first decreasing zero of the
/// octic `A² − 4ρ²·q`. That is also `(d² − R²)·((√q + ρ)² + Δz² − R²)`, with `d` the distance
/// to the circle, whose second factor stays positive until the first one has changed sign:
/// the first contact is the octic's. At `Δz = R − h` (a ball on the cloth) the contact lies at
/// the horizontal distance `ρ + R·cos θ` from the axis, the level jaw contact.
fn jaw_time(piece: &Piece, jaw: &Jaw, now: f64, until: f64, params: &Params) -> Option<f64> {
    let r = params.ball_radius;
    let rho = jaw.radius;
    let u0 = piece.pos_at(now) - jaw.center;
    let u1 = piece.vel_at(now);
    if stays_apart(u0, u1, DVec2::ZERO, until - now, rho + r) {
        return None;
    }
    let (lift, vz) = piece.height_at(now);
    let (e0, e1, e2) = (r + lift - params.cushion_height, vz, -0.5 * piece.gravity());
    let q = [u0.dot(u0), 2.0 * u0.dot(u1), u1.dot(u1)];
    let a: [f64; 5] = [
        q[0] + (rho * rho - r * r) + e0 * e0,
        q[1] + 2.0 * e0 * e1,
        q[2] + e1 * e1 + 2.0 * e0 * e2,
        2.0 * e1 * e2,
        e2 * e2,
    ];
    let mut poly: Octic = [0.0; 9];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in a.iter().enumerate() {
            poly[i + j] += x * y;
        }
    }
    for (k, x) in q.iter().enumerate() {
        poly[k] -= 4.0 * rho * rho * x;
    }
    // Near contact the octic is about 8ρ·R·√q times the gap d − R.
    let scale = 8.0 * rho * r * (rho + r);
    let touch = Touch {
        speed: scale * TOUCH_SPEED,
        accel: scale * TOUCH_ACCEL,
    };
    octic::first_contact(&poly, until - now, touch).map(|dt| now + dt)
}

/// First time in (now, until] at which the centre comes over the disc of `jaw` (the
/// rounded end of the cushion): a ball that does so without touching the nose first is
/// above the cushion by more than its radius, and leaves the table as over a rail.
fn over_jaw_time(piece: &Piece, jaw: &Jaw, now: f64, until: f64) -> Option<f64> {
    let u0 = piece.pos_at(now) - jaw.center;
    let u1 = piece.vel_at(now);
    let rho = jaw.radius;
    if stays_apart(u0, u1, DVec2::ZERO, until - now, rho) {
        return None;
    }
    let d = u0.length();
    let poly: Poly = [
        (d - rho) * (d + rho),
        2.0 * u0.dot(u1),
        u1.dot(u1),
        0.0,
        0.0,
    ];
    first_contact(&poly, until - now, Touch::squared(rho)).map(|dt| now + dt)
}

/// True when `p` lies between the rail's ends, seen along the rail.
fn along_rail(rail: &Rail, p: DVec2) -> bool {
    let along = rail.b - rail.a;
    let s = along.dot(p - rail.a);
    s >= 0.0 && s <= along.dot(along)
}

/// First time in (now, until] at which the ball touches the nose edge of `rail` while
/// approaching it.
fn nose_time(piece: &Piece, rail: &Rail, now: f64, until: f64, params: &Params) -> Option<f64> {
    let r = params.ball_radius;
    let p = piece.pos_at(now);
    let d0 = rail.normal.dot(p - rail.a);
    if d0 - r > piece.reach(now, until) {
        return None;
    }
    // Horizontal distance to the nose line, d(τ) = d0 + d1·τ + d2·τ², and height of the
    // centre above the nose, e(τ) = e0 + e1·τ + e2·τ².
    let d1 = rail.normal.dot(piece.vel_at(now));
    let d2 = 0.5 * rail.normal.dot(piece.acc);
    let (lift, vz) = piece.height_at(now);
    let e0 = r + lift - params.cushion_height;
    let e1 = vz;
    let e2 = -0.5 * piece.gravity();
    let poly: Poly = [
        (d0 * d0 + e0 * e0) - r * r,
        2.0 * (d0 * d1 + e0 * e1),
        d1 * d1 + 2.0 * d0 * d2 + e1 * e1 + 2.0 * e0 * e2,
        2.0 * (d1 * d2 + e1 * e2),
        d2 * d2 + e2 * e2,
    ];
    let t = now + first_contact(&poly, until - now, Touch::squared(r))?;
    let at = piece.pos_at(t);
    (rail.normal.dot(at - rail.a) >= 0.0 && along_rail(rail, at)).then_some(t)
}

/// First time in (now, until] at which the centre crosses the nose line of `rail` outwards,
/// between the rail's ends.
fn leave_time(piece: &Piece, rail: &Rail, now: f64, until: f64) -> Option<f64> {
    let p = piece.pos_at(now);
    let d0 = rail.normal.dot(p - rail.a);
    if d0 > piece.reach(now, until) {
        return None;
    }
    let poly: Poly = [
        d0,
        rail.normal.dot(piece.vel_at(now)),
        0.5 * rail.normal.dot(piece.acc),
        0.0,
        0.0,
    ];
    let t = now + first_contact(&poly, until - now, Touch::linear())?;
    along_rail(rail, piece.pos_at(t)).then_some(t)
}

/// Resolves the event `flight` of ball `ball` at time `t`: its new state and the event.
pub(super) fn resolve(
    piece: &Piece,
    t: f64,
    flight: Flight,
    ball: u16,
    ctx: &Ctx,
) -> (BallState, EventKind) {
    let (table, params) = (ctx.table, ctx.params);
    let r = params.ball_radius;
    // Every cushion model but the mirror one has friction at the nose.
    let friction = ctx.models.cushion != CushionModel::Simple;
    let mut s = piece.state_at(t, r);
    match flight {
        Flight::Land => {
            s.lift = 0.0;
            if ctx.effects.pockets {
                for (k, pocket) in table.pockets.iter().enumerate() {
                    if (s.pos - pocket.center).length() <= pocket.radius {
                        return (gone(s, MotionState::Pocketed, Some(k as u8)), {
                            EventKind::BallPocket {
                                ball,
                                pocket: k as u8,
                            }
                        });
                    }
                }
            }
            let h = table.half;
            if table.has_cushions() && (s.pos.x.abs() > h.x || s.pos.y.abs() > h.y) {
                // Landed beyond the cushion noses, not in a pocket.
                return (
                    gone(s, MotionState::OffTable, None),
                    EventKind::BallOffTable { ball },
                );
            }
            let s = off_slate(s, params);
            let kind = if s.motion == MotionState::Airborne {
                EventKind::BallTable { ball }
            } else {
                EventKind::Transition {
                    ball,
                    from: MotionState::Airborne,
                    to: s.motion,
                }
            };
            (s, kind)
        }
        Flight::Nose(k) => {
            let rail = &table.rails[k as usize];
            let d = rail.normal.dot(s.pos - rail.a);
            if d <= 0.0 {
                // Centred right above the nose edge: the ball is not on the bed's side of
                // it, and bouncing straight up and down on the edge would never end.
                return (
                    gone(s, MotionState::OffTable, None),
                    EventKind::BallOffTable { ball },
                );
            }
            let e = r + s.lift - params.cushion_height;
            let n = DVec3::new(rail.normal.x * d, rail.normal.y * d, e).normalize_or_zero();
            (
                off_edge(s, n, friction, params),
                EventKind::BallCushion {
                    ball,
                    cushion: Cushion::Rail(k),
                },
            )
        }
        Flight::Jaw(k) => {
            let jaw = &table.jaws[k as usize];
            let u = s.pos - jaw.center;
            let dist = u.length();
            if dist <= jaw.radius {
                // Centred over the cushion's rounded end: as above the nose of a rail.
                return (
                    gone(s, MotionState::OffTable, None),
                    EventKind::BallOffTable { ball },
                );
            }
            // From the nearest point of the nose circle to the centre.
            let d = u * ((dist - jaw.radius) / dist);
            let e = r + s.lift - params.cushion_height;
            let n = DVec3::new(d.x, d.y, e).normalize_or_zero();
            (
                off_edge(s, n, friction, params),
                EventKind::BallCushion {
                    ball,
                    cushion: Cushion::Jaw(k),
                },
            )
        }
        Flight::Leave(_) | Flight::OverJaw(_) => (
            gone(s, MotionState::OffTable, None),
            EventKind::BallOffTable { ball },
        ),
    }
}

/// The answer of a cushion nose (a rail's edge or a jaw's circle) to a ball touching it in
/// flight, `n` the unit normal from the contact point to the centre: restitution
/// `e_cushion` along `n`, then, with `friction`, Coulomb friction `f_cushion` times the normal
/// impulse against the slip of the contact point, capped at the impulse that ends the slip
/// (`2/7·m·|s|` for a ball on a fixed edge), as the slate's.
fn off_edge(mut s: BallState, n: DVec3, friction: bool, params: &Params) -> BallState {
    let mut v = DVec3::new(s.vel.x, s.vel.y, s.vz);
    let approach = v.dot(n);
    // A ball bouncing on the edge from above, ever lower, would bounce without end (ever
    // shorter hops in a finite time): once the hops are lower than the cut-off they are
    // elastic, and the balance on the edge, which is unstable, ends in a few dozen hops at
    // most, with the ball falling to one side.
    let weak = n.z > 0.0 && approach * approach < 2.0 * params.gravity * SETTLE_HEIGHT;
    let restitution = if weak { 1.0 } else { params.e_cushion };
    if approach < 0.0 {
        v -= n * ((1.0 + restitution) * approach);
        if friction {
            // The contact point is at −R·n; its velocity, less its part along n.
            let r = params.ball_radius;
            let c = v + s.spin.cross(n * -r);
            let slip = c - n * c.dot(n);
            let speed = slip.length();
            if speed > 0.0 {
                let dv =
                    (params.f_cushion * (1.0 + restitution) * -approach).min(2.0 / 7.0 * speed);
                let dv = slip * (-dv / speed);
                v += dv;
                // Torque of the impulse m·Δv at −R·n: Δω = −(m·R/I)·n × Δv.
                s.spin -= n.cross(dv) * (2.5 / r);
            }
        }
    }
    (s.vel, s.vz) = (DVec2::new(v.x, v.y), v.z);
    after_impact(s, params)
}

/// A ball that fell into a pocket or left the table: it stays where it went, motionless.
fn gone(mut s: BallState, motion: MotionState, pocket: Option<u8>) -> BallState {
    s.vel = DVec2::ZERO;
    s.spin = DVec3::ZERO;
    s.lift = 0.0;
    s.vz = 0.0;
    s.motion = motion;
    s.pocket = pocket;
    s
}

/// The slate's answer to a ball on the cloth moving down into it (`vz < 0`): it bounces
/// with `e_table`, Coulomb friction at the contact point acts on its slip, and it flies if
/// the rebound would lift it at least [`SETTLE_HEIGHT`]; otherwise it stays on the cloth.
pub fn off_slate(mut s: BallState, params: &Params) -> BallState {
    let r = params.ball_radius;
    let m = params.ball_mass;
    let normal = -(1.0 + params.e_table) * m * s.vz.min(0.0);
    let u = s.slip(r);
    let slip = u.length();
    if slip > 0.0 && normal > 0.0 {
        // The most friction can do is end the slip, which takes 2/7·m·|u|.
        let f = (params.mu_slide * normal).min(2.0 / 7.0 * m * slip);
        let force = u * (-f / slip);
        s.vel += force / m;
        // Torque of the friction impulse at the contact point −R·ẑ.
        let k = r / params.inertia();
        s.spin.x += k * force.y;
        s.spin.y -= k * force.x;
    }
    s.lift = 0.0;
    s.vz = -params.e_table * s.vz.min(0.0);
    settle(s, params)
}

/// The state of a ball after an impact in flight or with a ball in flight: a ball on the
/// cloth pushed into it bounces off the slate; one that would rise less than
/// [`SETTLE_HEIGHT`] stays on the cloth.
pub fn after_impact(mut s: BallState, params: &Params) -> BallState {
    if s.lift <= 0.0 {
        s.lift = 0.0;
        if s.vz < 0.0 {
            return off_slate(s, params);
        }
    }
    settle(s, params)
}

/// Drops a vertical velocity too small to leave the cloth and classifies the ball.
fn settle(mut s: BallState, params: &Params) -> BallState {
    if s.lift == 0.0 && s.vz * s.vz < 2.0 * params.gravity * SETTLE_HEIGHT {
        s.vz = 0.0;
    }
    s.motion = MotionState::Sliding;
    s.classify(params.ball_radius);
    s
}

/// The first time in (now, until] at which the balls of pieces `a` and `b`, one of them at
/// least in flight, touch while approaching: the squared 3-D distance is a quartic.
pub fn collision_time(a: &Piece, b: &Piece, now: f64, until: f64, radius: f64) -> Option<f64> {
    let dr = b.pos_at(now) - a.pos_at(now);
    let dv = b.vel_at(now) - a.vel_at(now);
    if stays_apart(dr, dv, b.acc - a.acc, until - now, 2.0 * radius) {
        // Even their shadows on the cloth stay apart.
        return None;
    }
    let mut poly = ball_ball::contact_poly(a, b, now, radius);
    let (za, wa) = a.height_at(now);
    let (zb, wb) = b.height_at(now);
    // Δz(τ) = p + q·τ + s·τ².
    let p = zb - za;
    let q = wb - wa;
    let s = -0.5 * (b.gravity() - a.gravity());
    poly[0] += p * p;
    poly[1] += 2.0 * p * q;
    poly[2] += q * q + 2.0 * p * s;
    poly[3] += 2.0 * q * s;
    poly[4] += s * s;
    first_contact(&poly, until - now, Touch::squared(2.0 * radius)).map(|dt| now + dt)
}

/// A collision between touching balls `a` and `b` of which one at least is in flight:
/// restitution `e` along the 3-D line of centres, equal masses, then, with `friction`, the
/// same Coulomb friction at the contact as on the cloth (`ball_ball::friction_impulse`),
/// acting in 3-D: its vertical part goes to the balls, not to the cloth.
pub fn collide(
    states: &mut [BallState],
    a: usize,
    b: usize,
    e: f64,
    friction: bool,
    params: &Params,
) {
    let (sa, sb) = (states[a], states[b]);
    let d = sb.pos - sa.pos;
    let n = DVec3::new(d.x, d.y, sb.lift - sa.lift).normalize_or_zero();
    let va = DVec3::new(sa.vel.x, sa.vel.y, sa.vz);
    let vb = DVec3::new(sb.vel.x, sb.vel.y, sb.vz);
    let approach = (va - vb).dot(n);
    if approach <= 0.0 {
        return;
    }
    let j = n * (0.5 * (1.0 + e) * approach);
    let (mut va, mut vb) = (va - j, vb + j);
    let (mut wa, mut wb) = (sa.spin, sb.spin);
    if friction {
        let separation = e * approach;
        if let Some((dva, dw)) = ball_ball::friction_impulse(va, wa, vb, wb, n, separation, params)
        {
            va += dva;
            vb -= dva;
            wa += dw;
            wb += dw;
        }
    }
    for (k, v, w) in [(a, va, wa), (b, vb, wb)] {
        let mut s = states[k];
        (s.vel, s.vz, s.spin) = (DVec2::new(v.x, v.y), v.z, w);
        states[k] = after_impact(s, params);
    }
}
