//! Trial shots on a private copy of the table, counted: the search's budget is a number of
//! simulations, never a time, so that a decision is the same on every machine. Each one
//! waits for its turn on the search's [`Meter`], which is what lets a search run in steps.

use glam::{DVec2, DVec3};

use super::thinking::Meter;
use crate::physics::{
    BallState, EventKind, MotionState, Outcome, Shot, Simulator, Strike, TableKind,
};

/// A simulator for trial shots from one table, counting what it runs on `meter`.
pub(super) struct Lab {
    sim: Simulator,
    shot: Shot,
    meter: Meter,
}

impl Lab {
    /// `shot` is the table as it lies (its strike, if any, is ignored).
    pub(super) fn new(shot: Shot, meter: &Meter) -> Lab {
        Lab {
            sim: Simulator::new(),
            shot: Shot {
                strike: None,
                ..shot
            },
            meter: meter.clone(),
        }
    }

    pub(super) fn table(&self) -> TableKind {
        self.shot.table
    }

    pub(super) fn balls(&self) -> &[BallState] {
        &self.shot.balls
    }

    /// The outcome of striking ball `cue` with `strike`, `None` if the engine refuses it.
    pub(super) async fn strike(&mut self, cue: usize, strike: Strike) -> Option<&Outcome> {
        self.meter.simulation().await;
        self.shot.strike = Some((cue, strike));
        let out = self.sim.run(&self.shot).ok();
        self.shot.strike = None;
        out
    }

    /// Does ball `ball`, sent off sliding at `speed` along `dir` with the rest at rest, end up
    /// in a pocket? The probe the search uses to find a pocket's window.
    pub(super) async fn rolls_in(&mut self, ball: usize, dir: DVec2, speed: f64) -> bool {
        let Some(start) = self.shot.balls.get(ball).copied() else {
            return false;
        };
        self.meter.simulation().await;
        let r = self.shot.params.ball_radius;
        let v = dir * speed;
        // Already rolling: an object ball leaves a collision sliding and rolls within a few
        // centimetres, so a rolling probe is the closer picture of its path.
        let spin = DVec3::new(-v.y / r, v.x / r, 0.0);
        self.shot.balls[ball] = BallState::moving(start.pos, v, spin, r);
        let fell = self
            .sim
            .run(&self.shot)
            .ok()
            .and_then(|o| o.finals.get(ball).copied())
            .is_some_and(|b| b.motion == MotionState::Pocketed);
        self.shot.balls[ball] = start;
        fell
    }
}

/// The first ball the cue ball `cue` hits in `out`, and that ball's direction as it leaves.
pub(super) fn first_hit(out: &Outcome, cue: usize) -> Option<(usize, DVec2)> {
    out.events.iter().find_map(|e| match e.kind {
        EventKind::BallBall { a, b } if usize::from(a) == cue || usize::from(b) == cue => {
            let other = if usize::from(a) == cue { b } else { a };
            let other = usize::from(other);
            let v = out.state_at(other, e.t).vel;
            Some((other, v.normalize_or_zero()))
        }
        _ => None,
    })
}
