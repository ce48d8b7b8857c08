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
use super::params::{Effects, Params};
use super::roots::{first_contact, stays_apart, Poly, Touch};
use super::table::{Cushion, Rail, Table};

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
    best
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
pub fn resolve(
    piece: &Piece,
    t: f64,
    flight: Flight,
    ball: u16,
    table: &Table,
    params: &Params,
    effects: &Effects,
) -> (BallState, EventKind) {
    let r = params.ball_radius;
    let mut s = piece.state_at(t, r);
    match flight {
        Flight::Land => {
            s.lift = 0.0;
            if effects.pockets {
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
            let mut v = DVec3::new(s.vel.x, s.vel.y, s.vz);
            let approach = v.dot(n);
            // A ball bouncing on the edge from above, ever lower, would bounce without end
            // (ever shorter hops in a finite time): once the hops are lower than the cut-off
            // they are elastic, and the balance on the edge, which is unstable, ends in a few
            // dozen hops at most, with the ball falling to one side.
            let weak = e > 0.0 && approach * approach < 2.0 * params.gravity * SETTLE_HEIGHT;
            let restitution = if weak { 1.0 } else { params.e_cushion };
            if approach < 0.0 {
                v -= n * ((1.0 + restitution) * approach);
            }
            (s.vel, s.vz) = (DVec2::new(v.x, v.y), v.z);
            (
                after_impact(s, params),
                EventKind::BallCushion {
                    ball,
                    cushion: Cushion::Rail(k),
                },
            )
        }
        Flight::Leave(_) => (
            gone(s, MotionState::OffTable, None),
            EventKind::BallOffTable { ball },
        ),
    }
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
/// frictionless, restitution `e` along the 3-D line of centres, equal masses.
pub fn collide(states: &mut [BallState], a: usize, b: usize, e: f64, params: &Params) {
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
    for (k, v) in [(a, va - j), (b, vb + j)] {
        let mut s = states[k];
        (s.vel, s.vz) = (DVec2::new(v.x, v.y), v.z);
        states[k] = after_impact(s, params);
    }
}
