//! Helpers shared by the physics tests: building shots on the open cloth.
#![allow(dead_code)]

use breakshot_shared::physics::{
    simulate, BallBallModel, BallState, Effects, Models, MotionState, Outcome, Params, Piece, Shot,
    TableKind,
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
    }
}

pub fn open_shot(balls: Vec<BallState>) -> Shot {
    Shot {
        table: TableKind::Open,
        params: Params::default(),
        models: Models::default(),
        effects: Effects::default(),
        horizon: None,
        balls,
        strike: None,
    }
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
