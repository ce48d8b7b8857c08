//! Fitting one shot's cue strike: the aim, cue speed and tip offset whose simulation best
//! matches a recording, by Nelder–Mead (argmin) from several starting tips.

use std::cell::RefCell;

use anyhow::{bail, Context};
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use breakshot_shared::physics::cue::{MAX_CUE_SPEED, MISCUE_LIMIT};
use breakshot_shared::physics::{
    ball_cushion, engine, BallState, Models, Outcome, Params, Shot, Simulator, Strike, TableKind,
};
use glam::DVec2;

use super::recording::Recording;

/// Cost of a strike the engine refuses or cannot finish (m): worse than any real fit.
const FAILED: f64 = 10.0;
/// Largest tip offset tried, a little inside the miscue limit.
const TIP_LIMIT: f64 = MISCUE_LIMIT - 0.01;
/// Starting tips [side, height] (units of R): centre, the four half-way points, diagonals.
const TIPS: [[f64; 2]; 9] = [
    [0.0, 0.0],
    [0.3, 0.0],
    [-0.3, 0.0],
    [0.0, 0.3],
    [0.0, -0.3],
    [0.25, 0.25],
    [-0.25, 0.25],
    [0.25, -0.25],
    [-0.25, -0.25],
];

/// A fitted strike and how well it matches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrikeFit {
    pub angle_deg: f64,
    pub speed: f64,
    pub tip: [f64; 2],
    /// When the cue struck, after the recording's first sample (s).
    pub delay: f64,
    pub rmse: f64,
}

impl StrikeFit {
    fn from_vector(x: &[f64], max_delay: f64, rmse: f64) -> StrikeFit {
        let (strike, _) = decode(x);
        StrikeFit {
            angle_deg: libm::atan2(strike.dir.y, strike.dir.x).to_degrees(),
            speed: strike.speed,
            tip: strike.tip.to_array(),
            delay: x[4].clamp(0.0, max_delay),
            rmse,
        }
    }

    /// The strike as an optimiser vector [angle (rad), speed, side, height, delay].
    pub fn vector(&self) -> Vec<f64> {
        vec![
            self.angle_deg.to_radians(),
            self.speed,
            self.tip[0],
            self.tip[1],
            self.delay,
        ]
    }

    pub fn strike(&self) -> Strike {
        decode(&self.vector()).0
    }
}

/// Optimiser vector to a valid strike, and how far outside the valid range it was (the
/// optimiser gets that as a penalty, so it comes back inside).
fn decode(x: &[f64]) -> (Strike, f64) {
    let speed = x[1].clamp(0.05, MAX_CUE_SPEED);
    let mut tip = DVec2::new(x[2], x[3]);
    let len = tip.length();
    let mut excess = (x[1] - speed).abs();
    if len > TIP_LIMIT {
        tip *= TIP_LIMIT / len;
        excess += len - TIP_LIMIT;
    }
    let dir = DVec2::new(libm::cos(x[0]), libm::sin(x[0]));
    (
        Strike {
            speed,
            dir,
            tip,
            elevation_deg: 0.0,
        },
        excess,
    )
}

/// The shot a recording starts from: its balls at their first recorded positions on the
/// carom table (nudged inside the cushions and apart where the recording's rounding puts
/// them a hair too close), simulated up to the last recorded time.
pub fn base_shot(rec: &Recording, params: &Params, models: Models) -> anyhow::Result<Shot> {
    let table = TableKind::Carom;
    let Some((w, l)) = table.size() else {
        bail!("the carom table has no size");
    };
    let contact = ball_cushion::model_contact_distance(params, models.cushion) + 1e-9;
    let mut pos: Vec<DVec2> = rec
        .balls
        .iter()
        .map(|b| {
            DVec2::new(
                b.pos[0].x.clamp(contact, w - contact),
                b.pos[0].y.clamp(contact, l - contact),
            )
        })
        .collect();
    let gap = 2.0 * params.ball_radius + 1e-9;
    for i in 0..pos.len() {
        for j in i + 1..pos.len() {
            let d = pos[j] - pos[i];
            let len = d.length();
            if len < gap {
                let push = d.normalize_or(DVec2::X) * (0.5 * (gap - len));
                pos[i] -= push;
                pos[j] += push;
            }
        }
    }
    let mut shot = Shot::new(table, pos.into_iter().map(BallState::at_rest).collect());
    shot.params = *params;
    shot.models = models;
    shot.horizon = Some(rec.end().max(0.1));
    engine::check(&shot).with_context(|| format!("shot {}: start position", rec.id))?;
    Ok(shot)
}

/// Root mean square distance (m) between the recorded and simulated positions of every
/// ball at every recorded time up to `until`, from the engine's exact motion at those times,
/// the strike coming `delay` seconds after the recording's start.
pub fn rmse(outcome: &Outcome, rec: &Recording, until: f64, delay: f64) -> f64 {
    let mut sum = 0.0;
    let mut count = 0usize;
    for (i, track) in rec.balls.iter().enumerate() {
        for (&t, &p) in track
            .t
            .iter()
            .zip(&track.pos)
            .take_while(|(&t, _)| t <= until)
        {
            sum += (outcome.state_at(i, t - delay).pos - p).length_squared();
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

/// One recording's cost function for argmin.
pub struct Problem<'a> {
    rec: &'a Recording,
    shot: Shot,
    sim: RefCell<Simulator>,
}

impl<'a> Problem<'a> {
    pub fn new(rec: &'a Recording, params: &Params, models: Models) -> anyhow::Result<Self> {
        Ok(Problem {
            rec,
            shot: base_shot(rec, params, models)?,
            sim: RefCell::new(Simulator::new()),
        })
    }

    /// RMSE of the strike vector `x` (with the out-of-range penalty).
    pub fn evaluate(&self, x: &[f64]) -> f64 {
        self.evaluate_until(x, f64::INFINITY)
    }

    /// RMSE of the strike vector `x` over the samples up to `until` (simulating no
    /// further), with the out-of-range penalty.
    pub fn evaluate_until(&self, x: &[f64], until: f64) -> f64 {
        let (strike, mut excess) = decode(x);
        let delay = x[4].clamp(0.0, self.rec.max_delay());
        // A second of delay out of range costs like 10 m of error.
        excess += 10.0 * (x[4] - delay).abs();
        let horizon = self.shot.horizon.map(|h| h.min(until.max(0.1)));
        let shot = Shot {
            strike: Some((self.rec.cue, strike)),
            horizon,
            ..self.shot.clone()
        };
        let mut sim = self.sim.borrow_mut();
        let cost = match sim.run(&shot) {
            Ok(outcome) => rmse(outcome, self.rec, until, delay),
            Err(_) => FAILED,
        };
        cost + excess
    }

    /// The simulated outcome of a fitted strike.
    pub fn outcome(&self, fit: &StrikeFit) -> anyhow::Result<Outcome> {
        let shot = Shot {
            strike: Some((self.rec.cue, fit.strike())),
            ..self.shot.clone()
        };
        breakshot_shared::physics::simulate(&shot).map_err(|e| anyhow::anyhow!("{e}"))
    }
}

/// A cost function for argmin.
struct Objective<'f>(&'f dyn Fn(&[f64]) -> f64);

impl CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Self::Param) -> Result<f64, argmin::core::Error> {
        Ok((self.0)(x))
    }
}

/// Nelder–Mead from `start` with a simplex of `step` along each axis; returns the best
/// point and its cost.
pub fn nelder_mead(
    cost: &dyn Fn(&[f64]) -> f64,
    start: &[f64],
    step: &[f64],
    iters: u64,
) -> (Vec<f64>, f64) {
    let problem = Objective(cost);
    let mut simplex = vec![start.to_vec()];
    for (k, s) in step.iter().enumerate() {
        let mut v = start.to_vec();
        v[k] += s;
        simplex.push(v);
    }
    let fallback = (start.to_vec(), f64::INFINITY);
    let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(1e-7) else {
        return fallback;
    };
    match Executor::new(problem, solver)
        .configure(|state| state.max_iters(iters))
        .run()
    {
        Ok(result) => {
            let state = result.state();
            match state.get_best_param() {
                Some(best) => (best.clone(), state.get_best_cost()),
                None => fallback,
            }
        }
        Err(_) => fallback,
    }
}

/// A first guess of the aim and cue speed from the cue ball's first recorded motion: its
/// direction over the first 15 cm (or 0.3 s), and its speed corrected for sliding friction.
pub fn first_guess(rec: &Recording, params: &Params) -> (f64, f64) {
    let track = &rec.balls[rec.cue];
    let p0 = track.pos[0];
    let k = (1..track.t.len())
        .find(|&k| (track.pos[k] - p0).length() >= 0.15 || track.t[k] >= 0.3)
        .unwrap_or(track.t.len() - 1);
    let d = track.pos[k] - p0;
    let t = track.t[k].max(1e-3);
    let angle = libm::atan2(d.y, d.x);
    let ball_speed = d.length() / t + 0.5 * params.mu_slide * params.gravity * t;
    // A centre hit gives the ball 1.54 times the cue's speed (docs/physics.md, cue strike).
    (angle, (ball_speed / 1.54).clamp(0.1, MAX_CUE_SPEED))
}

/// How much of the shot each stage of the search matches (s): a ball's path diverges
/// quickly once a bounce goes wrong, so the search first fits the start of the shot, where
/// aim and speed show, and then ever more of it, where the spin shows.
const STAGES: [f64; 4] = [0.8, 2.0, 5.0, f64::INFINITY];
/// Candidates carried from one stage to the next.
const KEEP: usize = 3;

/// Fits the strike of one recording. Without `warm`: a search from each starting tip and
/// aim over the first stage, the best few carried through the later stages, and a last
/// refinement over the whole shot. With `warm` (a previous fit): the refinement alone.
/// `iters` is the Nelder–Mead budget of one search.
pub fn fit(
    rec: &Recording,
    params: &Params,
    models: Models,
    warm: Option<&StrikeFit>,
    iters: u64,
) -> anyhow::Result<StrikeFit> {
    let problem = Problem::new(rec, params, models)?;
    let whole = |x: &[f64]| problem.evaluate(x);
    let max_delay = rec.max_delay();
    let fine = |x: &[f64]| {
        [
            0.004,
            0.03 * x[1].abs().max(0.1),
            0.04,
            0.04,
            0.1 * max_delay,
        ]
    };
    let mut best = match warm {
        Some(w) => {
            let x = w.vector();
            (x.clone(), problem.evaluate(&x))
        }
        None => {
            let (angle, speed) = first_guess(rec, params);
            let mut cands: Vec<(Vec<f64>, f64)> = Vec::new();
            let first = |x: &[f64]| problem.evaluate_until(x, STAGES[0]);
            let step = [0.02, 0.1 * speed, 0.1, 0.1, 0.3 * max_delay];
            for tip in TIPS {
                for da in [-0.03, 0.0, 0.03] {
                    let start = [angle + da, speed, tip[0], tip[1], 0.5 * max_delay];
                    cands.push(nelder_mead(&first, &start, &step, iters));
                }
            }
            for &until in &STAGES[1..] {
                cands.sort_by(|a, b| a.1.total_cmp(&b.1));
                cands.truncate(KEEP);
                let stage = |x: &[f64]| problem.evaluate_until(x, until);
                cands = cands
                    .iter()
                    .map(|(x, _)| nelder_mead(&stage, x, &fine(x), iters))
                    .collect();
            }
            cands
                .into_iter()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap_or((vec![angle, speed, 0.0, 0.0, 0.0], f64::INFINITY))
        }
    };
    let refined = nelder_mead(&whole, &best.0, &fine(&best.0), 2 * iters);
    if refined.1 < best.1 {
        best = refined;
    }
    let rmse = problem.evaluate(&best.0);
    Ok(StrikeFit::from_vector(&best.0, max_delay, rmse))
}
