//! The cost of each effect: the same shots simulated from the bare ideal model up to the
//! full model, one effect more at each rung; and the check that an effect switched off costs
//! nothing.

use std::time::Instant;

use anyhow::Context;
use breakshot_shared::physics::{
    BallBallModel, CushionModel, Effects, Models, Shot, Simulator, Table, TableKind,
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
    // The study's strikes are level, so flight never happens and its switch costs nothing:
    // it is on only to make the last rung the default model.
    add("+ ball-ball friction (full model)", &|_, e| {
        e.ball_friction = true;
        e.airborne = true;
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
    /// Median over the shots of time per event (s): a median, so that a shot slowed by
    /// another process does not move it.
    pub per_event: f64,
}

/// The ladder's costs, on the shots that every rung could simulate.
#[derive(Clone, Debug)]
pub struct EffectCosts {
    pub rungs: Vec<RungCost>,
    pub shots: usize,
    /// Shots left out because some rung could not simulate them, with the reason.
    pub left_out: Vec<String>,
}

/// Times every rung on `shots`; `tick` is called once per simulated shot.
pub fn cost_of_effects(shots: &[(String, Shot)], mut tick: impl FnMut()) -> EffectCosts {
    let mut sim = Simulator::new();
    let rungs = ladder();
    // measured[r][s]: (seconds, events) of shot s on rung r.
    let mut measured: Vec<Vec<Option<(f64, usize)>>> = Vec::new();
    let mut left_out = Vec::new();
    for rung in &rungs {
        let mut row = Vec::new();
        for (name, shot) in shots {
            let shot = Shot {
                models: rung.models,
                effects: rung.effects,
                horizon: Some(HORIZON),
                ..shot.clone()
            };
            let (n, secs) = time_median(|| sim.run(&shot).map(|o| o.events.len()));
            match n {
                Ok(n) => row.push(Some((secs, n))),
                Err(e) => {
                    left_out.push(format!("{name} on rung \"{}\": {e}", rung.name));
                    row.push(None);
                }
            }
            tick();
        }
        measured.push(row);
    }
    let usable: Vec<usize> = (0..shots.len())
        .filter(|&s| measured.iter().all(|row| row[s].is_some()))
        .collect();
    let rungs = rungs
        .iter()
        .zip(&measured)
        .map(|(rung, row)| {
            let picked: Vec<(f64, usize)> = usable.iter().filter_map(|&s| row[s]).collect();
            let times: Vec<f64> = picked.iter().map(|p| p.0).collect();
            let per_event: Vec<f64> = picked.iter().map(|p| p.0 / p.1.max(1) as f64).collect();
            let events: usize = picked.iter().map(|p| p.1).sum();
            RungCost {
                name: rung.name,
                median_shot: median(&times),
                mean_events: events as f64 / picked.len().max(1) as f64,
                per_event: median(&per_event),
            }
        })
        .collect();
    EffectCosts {
        rungs,
        shots: usable.len(),
        left_out,
    }
}

/// The same open-cloth shot on the open table and on a 9 ft table with cushions and pockets
/// off: same events, and (within noise) the same cost.
#[derive(Clone, Debug)]
pub struct DisabledCheck {
    pub events_open: usize,
    pub events_9ft: usize,
    /// Both runs gave bit-identical events.
    pub same_events: bool,
    /// Largest difference of a final position between the runs, after removing the table
    /// offset (m): the rounding of adding and removing the offset.
    pub position_difference: f64,
    pub median_open: f64,
    pub median_9ft: f64,
    /// median_9ft / median_open, both measured interleaved in the same run.
    pub ratio: f64,
}

/// Runs per timed batch and batches per table in the disabled-effect check.
const BATCH: usize = 20;
const BATCHES: usize = 150;

/// Snaps a coordinate to a multiple of 2⁻³⁰ m, so that adding and then removing the table
/// offset is exact and both runs see bit-identical engine coordinates.
fn snap(x: f64) -> f64 {
    let grid = (1u64 << 30) as f64;
    (x * grid).round() / grid
}

/// `shot` (on a 9 ft table) moved onto the open cloth, centred on the origin as the engine
/// centres the 9 ft table, and the same shot back on the 9 ft table with cushions and
/// pockets off.
pub fn open_and_9ft(shot: &Shot) -> (Shot, Shot) {
    let half = Table::new(TableKind::NineFoot).half;
    let mut open = shot.clone();
    open.table = TableKind::Open;
    for b in &mut open.balls {
        b.pos = DVec2::new(snap(b.pos.x - half.x), snap(b.pos.y - half.y));
    }
    let mut on_9ft = open.clone();
    on_9ft.table = TableKind::NineFoot;
    on_9ft.effects.cushions = false;
    on_9ft.effects.pockets = false;
    for b in &mut on_9ft.balls {
        b.pos += half;
    }
    (open, on_9ft)
}

/// Times a 9-ball break played on the open cloth against the same break on a 9 ft table with
/// cushions and pockets off, interleaved, each with its own simulator.
pub fn disabled_effects_cost_nothing(break_shot: &Shot) -> anyhow::Result<DisabledCheck> {
    anyhow::ensure!(
        break_shot.table == TableKind::NineFoot,
        "the check needs a shot on a 9 ft table"
    );
    let (open_shot, on_9ft) = open_and_9ft(break_shot);
    let half = Table::new(TableKind::NineFoot).half;
    let mut sim_open = Simulator::new();
    let mut sim_9ft = Simulator::new();
    let open = sim_open.run(&open_shot).context("open-cloth shot")?.clone();
    let table = sim_9ft
        .run(&on_9ft)
        .context("the shot on a 9 ft table")?
        .clone();
    let same_events = open.events == table.events;
    let position_difference = open
        .finals
        .iter()
        .zip(&table.finals)
        .map(|(a, b)| (b.pos - half - a.pos).length())
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
        times_open.push(batch(&open_shot, &mut sim_open));
        times_9ft.push(batch(&on_9ft, &mut sim_9ft));
    }
    let (median_open, median_9ft) = (median(&times_open), median(&times_9ft));
    Ok(DisabledCheck {
        events_open: open.events.len(),
        events_9ft: table.events.len(),
        same_events,
        position_difference,
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

    #[test]
    fn the_open_and_9ft_versions_of_a_shot_are_the_same_shot() {
        let shot =
            crate::study::workload::break_case(crate::study::workload::Category::Break9, 0).shot;
        let (open, on_9ft) = open_and_9ft(&shot);
        let a = breakshot_shared::physics::simulate(&open).unwrap();
        let b = breakshot_shared::physics::simulate(&on_9ft).unwrap();
        assert!(a.events.len() > 20, "a break, not a trivial shot");
        assert_eq!(a.events, b.events);
    }
}
