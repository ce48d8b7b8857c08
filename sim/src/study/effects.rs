//! The cost of each effect: the same shots simulated from the bare ideal model up to the
//! full model, one effect more at each rung; and the check that an effect switched off costs
//! nothing.

use std::time::Instant;

use anyhow::Context;
use breakshot_shared::physics::{
    BallBallModel, CushionModel, Effects, Models, Shot, Simulator, TableKind,
};
use glam::DVec2;

use super::methods::time_median;
use super::metrics::median;

/// Simulated time for every rung: the frictionless rungs never come to rest by themselves.
pub const HORIZON: f64 = 20.0;

/// One rung of the ladder: what is switched on.
#[derive(Clone, Copy, Debug)]
pub struct Rung {
    pub name: &'static str,
    pub models: Models,
    pub effects: Effects,
}

/// From nothing to everything, one effect more each time.
pub fn ladder() -> Vec<Rung> {
    let mut models = Models {
        ball_ball: BallBallModel::Ideal,
        cushion: CushionModel::Simple,
    };
    let mut effects = Effects::none();
    let mut rungs = vec![Rung {
        name: "ideal: no friction, no cushions, no pockets",
        models,
        effects,
    }];
    let mut add = |name, change: &dyn Fn(&mut Models, &mut Effects)| {
        change(&mut models, &mut effects);
        rungs.push(Rung {
            name,
            models,
            effects,
        });
    };
    add("+ cushions (mirror bounce)", &|_, e| e.cushions = true);
    add("+ pockets", &|_, e| e.pockets = true);
    add("+ sliding friction", &|_, e| e.slide_friction = true);
    add("+ rolling friction", &|_, e| e.roll_friction = true);
    add("+ spin friction", &|_, e| e.spin_friction = true);
    add("+ Han 2005 cushions", &|m, _| {
        m.cushion = CushionModel::Han2005
    });
    add("+ restitution e_ball", &|m, _| {
        m.ball_ball = BallBallModel::Frictional
    });
    add("+ ball-ball friction (full model)", &|_, e| {
        e.ball_friction = true
    });
    rungs
}

/// A rung's cost on the shots.
#[derive(Clone, Debug)]
pub struct RungCost {
    pub name: &'static str,
    /// Median over the shots of the median time per shot (s).
    pub median_shot: f64,
    /// Mean events per shot.
    pub mean_events: f64,
    /// Total time over total events (s).
    pub per_event: f64,
}

/// Times every rung on `shots`; `tick` is called once per simulated shot.
pub fn cost_of_effects(shots: &[Shot], mut tick: impl FnMut()) -> anyhow::Result<Vec<RungCost>> {
    let mut sim = Simulator::new();
    let mut out = Vec::new();
    for rung in ladder() {
        let mut times = Vec::new();
        let mut events = 0usize;
        for shot in shots {
            let shot = Shot {
                models: rung.models,
                effects: rung.effects,
                horizon: Some(HORIZON),
                ..shot.clone()
            };
            let (n, secs) = time_median(|| sim.run(&shot).map(|o| o.events.len()));
            events += n.with_context(|| format!("rung \"{}\"", rung.name))?;
            times.push(secs);
            tick();
        }
        out.push(RungCost {
            name: rung.name,
            median_shot: median(&times),
            mean_events: events as f64 / shots.len().max(1) as f64,
            per_event: times.iter().sum::<f64>() / events.max(1) as f64,
        });
    }
    Ok(out)
}

/// The same open-cloth shot on the open table and on a 9 ft table with cushions and pockets
/// off: same events, and (within noise) the same cost.
#[derive(Clone, Debug)]
pub struct DisabledCheck {
    pub events_open: usize,
    pub events_9ft: usize,
    /// The final positions agree (after moving the 9 ft shot back by its offset) to this (m).
    pub max_position_difference: f64,
    pub median_open: f64,
    pub median_9ft: f64,
    /// median_9ft / median_open, both measured interleaved in the same run.
    pub ratio: f64,
}

/// Runs per timed batch and batches per table in the disabled-effect check.
const BATCH: usize = 200;
const BATCHES: usize = 150;

pub fn disabled_effects_cost_nothing(open_shot: &Shot) -> anyhow::Result<DisabledCheck> {
    anyhow::ensure!(
        open_shot.table == TableKind::Open,
        "the check needs an open-cloth shot"
    );
    // Put the shot in the middle of a 9 ft table.
    let offset = DVec2::new(0.635, 0.8);
    let mut on_9ft = open_shot.clone();
    on_9ft.table = TableKind::NineFoot;
    on_9ft.effects.cushions = false;
    on_9ft.effects.pockets = false;
    for b in &mut on_9ft.balls {
        b.pos += offset;
    }
    let mut sim = Simulator::new();
    let open = sim.run(open_shot).context("open-cloth shot")?.clone();
    let table = sim
        .run(&on_9ft)
        .context("the shot on a 9 ft table")?
        .clone();
    let max_position_difference = open
        .finals
        .iter()
        .zip(&table.finals)
        .map(|(a, b)| (b.pos - offset - a.pos).length())
        .fold(0.0, f64::max);
    let mut times_open = Vec::with_capacity(BATCHES);
    let mut times_9ft = Vec::with_capacity(BATCHES);
    let batch = |shot: &Shot, sim: &mut Simulator| {
        let t0 = Instant::now();
        for _ in 0..BATCH {
            let _ = std::hint::black_box(sim.run(shot).map(|o| o.events.len()));
        }
        t0.elapsed().as_secs_f64() / BATCH as f64
    };
    for _ in 0..BATCHES {
        times_open.push(batch(open_shot, &mut sim));
        times_9ft.push(batch(&on_9ft, &mut sim));
    }
    let (median_open, median_9ft) = (median(&times_open), median(&times_9ft));
    Ok(DisabledCheck {
        events_open: open.events.len(),
        events_9ft: table.events.len(),
        max_position_difference,
        median_open,
        median_9ft,
        ratio: median_9ft / median_open,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rung_switches_on_one_more_thing_and_ends_at_the_full_model() {
        let rungs = ladder();
        let on = |r: &Rung| {
            let e = r.effects;
            [
                e.slide_friction,
                e.roll_friction,
                e.spin_friction,
                e.ball_friction,
                e.cushions,
                e.pockets,
            ]
            .iter()
            .filter(|x| **x)
            .count()
                + usize::from(r.models.cushion == CushionModel::Han2005)
                + usize::from(r.models.ball_ball == BallBallModel::Frictional)
        };
        for (k, r) in rungs.iter().enumerate() {
            assert_eq!(on(r), k, "{}", r.name);
        }
        let last = rungs.last().unwrap();
        assert_eq!(last.effects, Effects::default());
        assert_eq!(last.models, Models::default());
    }
}
