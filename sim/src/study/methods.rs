//! The methods compared, and how a shot is timed under each.

use std::time::{Duration, Instant};

use anyhow::Context;
use breakshot_shared::physics::{Shot, Simulator};

use super::fixed_step::{self, FixedStep};
use super::metrics::median;
use super::trace::Trace;

/// The steps tried by the fixed-step methods (s), with their labels.
pub const STEPS: [(f64, &str); 5] = [
    (1.0 / 60.0, "1/60 s"),
    (1.0 / 240.0, "1/240 s"),
    (1e-3, "1 ms"),
    (1e-4, "0.1 ms"),
    (1e-5, "0.01 ms"),
];

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// The engine: exact event times, closed-form motion.
    Event,
    Fixed(FixedStep),
}

impl Method {
    /// The event-based engine, then plain fixed steps, then fixed steps with the
    /// time-of-impact correction, each from the coarsest step to the finest.
    pub fn all() -> Vec<Method> {
        let mut out = vec![Method::Event];
        for toi in [false, true] {
            out.extend(
                STEPS
                    .iter()
                    .map(|&(dt, _)| Method::Fixed(FixedStep { dt, toi })),
            );
        }
        out
    }

    pub fn family(&self) -> &'static str {
        match self {
            Method::Event => "event-based",
            Method::Fixed(FixedStep { toi: false, .. }) => "fixed step",
            Method::Fixed(FixedStep { toi: true, .. }) => "fixed step + TOI",
        }
    }

    pub fn step_label(&self) -> &'static str {
        match self {
            Method::Event => "exact",
            Method::Fixed(f) => STEPS
                .iter()
                .find(|(dt, _)| *dt == f.dt)
                .map_or("?", |(_, label)| label),
        }
    }

    pub fn label(&self) -> String {
        match self {
            Method::Event => "event-based".into(),
            _ => format!("{}, dt {}", self.family(), self.step_label()),
        }
    }

    pub fn dt(&self) -> Option<f64> {
        match self {
            Method::Event => None,
            Method::Fixed(f) => Some(f.dt),
        }
    }
}

/// One method's result on one shot.
#[derive(Clone, Debug)]
pub struct Timed {
    pub trace: Trace,
    /// Median time of one simulation of the shot (s).
    pub seconds: f64,
    pub steps: u64,
    pub deepest_overlap: f64,
    pub escaped: usize,
}

/// Repeats cheap runs until this much time has passed, to get a median.
const TIMING_BUDGET: Duration = Duration::from_millis(4);
const MAX_REPEATS: usize = 25;

/// The median time of `f` over a few runs (one run when a run is slow), and its last result.
pub fn time_median<T>(mut f: impl FnMut() -> T) -> (T, f64) {
    let start = Instant::now();
    let mut times = Vec::new();
    loop {
        let t0 = Instant::now();
        let out = std::hint::black_box(f());
        times.push(t0.elapsed().as_secs_f64());
        if start.elapsed() >= TIMING_BUDGET || times.len() >= MAX_REPEATS {
            return (out, median(&times));
        }
    }
}

/// Runs and times `shot` with `method`.
pub fn run(method: Method, shot: &Shot, sim: &mut Simulator) -> anyhow::Result<Timed> {
    match method {
        Method::Event => {
            let (ran, seconds) = time_median(|| sim.run(shot).map(|o| o.events.len()));
            ran.context("simulating the reference")?;
            let outcome = sim.run(shot).context("simulating the reference")?;
            Ok(Timed {
                trace: Trace::from_outcome(shot, outcome),
                seconds,
                steps: 0,
                deepest_overlap: 0.0,
                escaped: 0,
            })
        }
        Method::Fixed(f) => {
            let (run, seconds) = time_median(|| fixed_step::simulate(shot, f));
            let run = run.context("fixed-step simulation")?;
            Ok(Timed {
                trace: run.trace,
                seconds,
                steps: run.steps,
                deepest_overlap: run.deepest_overlap,
                escaped: run.escaped,
            })
        }
    }
}
