//! Helpers shared by the physics tests: building shots on the open cloth.
#![allow(dead_code)]

use breakshot_shared::physics::{
    simulate, BallBallModel, BallState, MotionState, Outcome, Params, Piece, Shot, TableKind,
};
use glam::{DVec2, DVec3};

pub const R: f64 = 0.028575;
pub const G: f64 = 9.81;
pub const MU_S: f64 = 0.2;
pub const MU_R: f64 = 0.01;

pub fn ball(pos: [f64; 2], vel: [f64; 2], spin: [f64; 3]) -> BallState {
    BallState {
        pos: DVec2::from_array(pos),
        vel: DVec2::from_array(vel),
        spin: DVec3::from_array(spin),
        motion: MotionState::Stationary,
        pocket: None,
        lift: 0.0,
        vz: 0.0,
    }
}

pub fn open_shot(balls: Vec<BallState>) -> Shot {
    Shot::new(TableKind::Open, balls)
}

pub fn ideal(mut shot: Shot) -> Shot {
    shot.models.ball_ball = BallBallModel::Ideal;
    shot
}

pub fn run(shot: &Shot) -> Outcome {
    simulate(shot).expect("shot simulates")
}

/// The piece ball `i` started right after its `k`-th change (0 = initial).
pub fn piece(out: &Outcome, i: usize, k: usize) -> Piece {
    out.history[i][k]
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

pub fn deg(rad: f64) -> f64 {
    rad * 180.0 / std::f64::consts::PI
}

/// Angle between two vectors in degrees.
pub fn angle_between(a: DVec2, b: DVec2) -> f64 {
    deg(libm::acos(
        (a.dot(b) / (a.length() * b.length())).clamp(-1.0, 1.0),
    ))
}

/// The racks' generator (the rules' SplitMix64), with a range helper for test racks.
pub struct Rng(breakshot_shared::rules::rack::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(breakshot_shared::rules::rack::SplitMix64::new(seed))
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.unit()
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// A 15-ball triangle on a `table` (scene coordinates), apex on the foot spot, rows towards
/// the far end. Each ball is moved by up to `jitter` metres from its frozen position, on a
/// grid spaced `2R + 2·jitter`, so neighbours never overlap and gaps stay under `4·jitter`.
pub fn rack15(table: TableKind, jitter: f64, rng: &mut Rng) -> Vec<BallState> {
    let (w, l) = table.size().expect("pocket table");
    let spacing = 2.0 * R + 2.0 * jitter;
    let row_step = spacing * 3f64.sqrt() / 2.0;
    let (cx, fy) = (w / 2.0, 0.75 * l);
    let mut balls = Vec::new();
    for row in 0..5 {
        for k in 0..=row {
            let x = cx + (k as f64 - row as f64 / 2.0) * spacing;
            let y = fy + row as f64 * row_step;
            let (dx, dy) = if jitter > 0.0 {
                let a = rng.range(0.0, 2.0 * std::f64::consts::PI);
                let r = jitter * rng.unit().sqrt();
                (r * libm::cos(a), r * libm::sin(a))
            } else {
                (0.0, 0.0)
            };
            balls.push(ball([x + dx, y + dy], [0.0; 2], [0.0; 3]));
        }
    }
    balls
}

/// A break: the rack plus a cue ball from the head spot at `speed`, aimed at the apex with a
/// lateral offset of `offset` metres.
pub fn break_shot(table: TableKind, jitter: f64, speed: f64, offset: f64, rng: &mut Rng) -> Shot {
    let (w, l) = table.size().expect("pocket table");
    let mut balls = vec![ball([w / 2.0 + offset, 0.25 * l], [0.0, speed], [0.0; 3])];
    balls.extend(rack15(table, jitter, rng));
    Shot {
        table,
        ..open_shot(balls)
    }
}

/// Invariants every simulated shot must keep; returns the worst overlap seen at any event.
pub fn check_invariants(shot: &Shot, out: &Outcome) -> f64 {
    invariant_figures(shot, out).0
}

/// Checks the invariants and returns the worst overlap seen at any event (m) and the largest
/// relative change of kinetic energy across any event (negative: energy only fell).
pub fn invariant_figures(shot: &Shot, out: &Outcome) -> (f64, f64) {
    let p = &shot.params;
    let mut worst_overlap: f64 = 0.0;
    let mut worst_rise = f64::NEG_INFINITY;
    let mut last_t = 0.0;
    for e in &out.events {
        assert!(
            e.t.is_finite() && e.t >= last_t,
            "events out of order at {}",
            e.t
        );
        last_t = e.t;
        let states: Vec<BallState> = (0..out.history.len())
            .map(|i| out.state_at(i, e.t))
            .collect();
        for s in &states {
            assert!(
                s.pos.is_finite() && s.vel.is_finite() && s.spin.is_finite(),
                "NaN at {}",
                e.t
            );
        }
        for i in 0..states.len() {
            for j in i + 1..states.len() {
                if states[i].motion.is_gone() || states[j].motion.is_gone() {
                    continue;
                }
                // In 3-D: a ball in flight may pass above another.
                let dz = states[i].lift - states[j].lift;
                let d = (states[i].pos - states[j].pos).length();
                let d = if dz == 0.0 {
                    d
                } else {
                    (d * d + dz * dz).sqrt()
                };
                let gap = d - 2.0 * p.ball_radius;
                worst_overlap = worst_overlap.max(-gap);
            }
        }
        let (before, after) = energy_across(out, e.t, p);
        if before > 0.0 {
            worst_rise = worst_rise.max((after - before) / before);
        }
        assert!(
            after <= before * (1.0 + 1e-12) + 1e-15,
            "kinetic energy rose across {:?}: {before} -> {after}",
            e.kind
        );
    }
    (worst_overlap, worst_rise)
}

/// Mechanical energy (kinetic, and potential in flight) just before and just after time `t`.
pub fn energy_across(out: &Outcome, t: f64, p: &Params) -> (f64, f64) {
    let mut before = 0.0;
    let mut after = 0.0;
    for pieces in &out.history {
        let k_before = pieces.partition_point(|q| q.t0 < t).max(1) - 1;
        let k_after = pieces.partition_point(|q| q.t0 <= t).max(1) - 1;
        let at = |k: usize| {
            let q = &pieces[k];
            let s = q.state_at(t.min(q.t_end).max(q.t0), p.ball_radius);
            breakshot_shared::physics::mechanical_energy(&s, p)
        };
        before += at(k_before);
        after += at(k_after);
    }
    (before, after)
}
