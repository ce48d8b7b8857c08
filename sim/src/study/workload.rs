//! The shots of the study: single balls, two-ball hits, cushion shots and racked breaks.
//!
//! Every shot uses the ideal ball–ball model (`models.ball_ball = Ideal`: the normal
//! components are exchanged) so that the event-based engine and the fixed-step integrators
//! model the same physics; cloth friction, spin and cushions are the engine's full models.

use breakshot_shared::physics::{
    BallBallModel, BallState, Models, Params, Shot, Strike, TableKind,
};
use glam::DVec2;

/// A family of shots, reported together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Category {
    SingleNoSpin,
    SingleSpin,
    Stun,
    HalfBall,
    ThinCut,
    Cushion,
    Break8,
    Break9,
}

impl Category {
    pub const ALL: [Category; 8] = [
        Category::SingleNoSpin,
        Category::SingleSpin,
        Category::Stun,
        Category::HalfBall,
        Category::ThinCut,
        Category::Cushion,
        Category::Break8,
        Category::Break9,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::SingleNoSpin => "single ball, no spin",
            Category::SingleSpin => "single ball, spin",
            Category::Stun => "stun hit",
            Category::HalfBall => "half-ball hit",
            Category::ThinCut => "thin cut",
            Category::Cushion => "cushion shot",
            Category::Break8 => "8-ball break",
            Category::Break9 => "9-ball break",
        }
    }

    pub fn is_break(self) -> bool {
        matches!(self, Category::Break8 | Category::Break9)
    }
}

/// One shot of the workload.
#[derive(Clone, Debug)]
pub struct Case {
    pub category: Category,
    pub name: String,
    pub shot: Shot,
}

/// Racks per kind of break.
pub const RACKS: usize = 30;

/// The whole workload, in a fixed order.
pub fn workload() -> Vec<Case> {
    let mut cases = Vec::new();
    cases.extend(singles());
    cases.extend(two_ball_hits());
    cases.extend(cushion_shots());
    for k in 0..RACKS {
        cases.push(break_case(Category::Break8, k as u64));
    }
    for k in 0..RACKS {
        cases.push(break_case(Category::Break9, k as u64));
    }
    cases
}

fn models() -> Models {
    Models {
        ball_ball: BallBallModel::Ideal,
        ..Models::default()
    }
}

fn shot(table: TableKind, balls: Vec<BallState>, strike: (usize, Strike)) -> Shot {
    Shot {
        models: models(),
        ..Shot::new(table, balls).struck(strike.0, strike.1)
    }
}

fn at_rest(x: f64, y: f64) -> BallState {
    BallState::at_rest(DVec2::new(x, y))
}

/// Single balls on the open cloth: only the motion model and its transitions matter.
fn singles() -> Vec<Case> {
    let mut cases = Vec::new();
    for (k, (speed, angle)) in [
        (0.3, 90.0),
        (0.6, 30.0),
        (0.9, 135.0),
        (1.2, 200.0),
        (1.6, 290.0),
        (2.0, 10.0),
    ]
    .into_iter()
    .enumerate()
    {
        let strike = Strike::at_angle(speed, angle, DVec2::ZERO);
        cases.push(Case {
            category: Category::SingleNoSpin,
            name: format!("single-{k}: {speed} m/s at {angle} deg, centre"),
            shot: shot(TableKind::Open, vec![at_rest(0.0, 0.0)], (0, strike)),
        });
    }
    let spins = [
        (0.5, 90.0, [0.0, 0.4]),
        (1.0, 90.0, [0.0, -0.4]),
        (1.5, 45.0, [0.3, 0.0]),
        (1.2, 160.0, [-0.3, 0.2]),
        (2.0, 250.0, [0.2, -0.3]),
        (0.8, 0.0, [-0.25, -0.25]),
        (2.0, 315.0, [0.0, 0.45]),
        (1.8, 100.0, [0.4, -0.1]),
    ];
    for (k, (speed, angle, tip)) in spins.into_iter().enumerate() {
        let strike = Strike::at_angle(speed, angle, DVec2::from_array(tip));
        cases.push(Case {
            category: Category::SingleSpin,
            name: format!("spin-{k}: {speed} m/s at {angle} deg, tip {tip:?}"),
            shot: shot(TableKind::Open, vec![at_rest(0.0, 0.0)], (0, strike)),
        });
    }
    cases
}

/// The aim from `cue` that passes the object ball's centre at `offset` (the impact
/// parameter: 0 full ball, R half ball, 2R no contact), on the left when positive.
pub fn aim(cue: DVec2, object: DVec2, offset: f64) -> DVec2 {
    let d = object - cue;
    let dist = d.length();
    let turn = libm::asin(offset / dist);
    let (s, c) = (libm::sin(turn), libm::cos(turn));
    DVec2::new(d.x * c - d.y * s, d.x * s + d.y * c) / dist
}

/// Cue ball and one object ball on a 9 ft table: stun, half-ball and thin cut hits.
fn two_ball_hits() -> Vec<Case> {
    let table = TableKind::NineFoot;
    let r = Params::default().ball_radius;
    let mut cases = Vec::new();
    let layouts = [
        // (cue, object, stick speed)
        ([0.635, 0.6], [0.635, 1.1], 2.0),
        ([0.4, 0.5], [0.5, 1.3], 3.0),
        ([0.9, 0.7], [0.7, 1.5], 4.0),
        ([0.635, 0.4], [0.6, 1.9], 5.0),
        ([0.3, 1.0], [0.8, 1.2], 2.5),
        ([1.0, 1.8], [0.6, 1.2], 3.5),
    ];
    for (k, (cue, obj, speed)) in layouts.into_iter().enumerate() {
        let (cue, obj) = (DVec2::from_array(cue), DVec2::from_array(obj));
        let balls = vec![BallState::at_rest(cue), BallState::at_rest(obj)];
        // Stun: a low hit so that the cue ball still slides without roll when it arrives.
        let tip = DVec2::new(0.0, -0.15 - 0.05 * (k % 3) as f64);
        let strike = Strike {
            speed,
            dir: aim(cue, obj, 0.0),
            tip,
            elevation_deg: 0.0,
        };
        cases.push(Case {
            category: Category::Stun,
            name: format!("stun-{k}: {speed} m/s, full ball"),
            shot: shot(table, balls.clone(), (0, strike)),
        });
        // Half-ball: rolling from the start (natural roll at b = 0.4).
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let strike = Strike {
            speed,
            dir: aim(cue, obj, side * r),
            tip: DVec2::new(0.0, 0.4),
            elevation_deg: 0.0,
        };
        cases.push(Case {
            category: Category::HalfBall,
            name: format!("half-{k}: {speed} m/s, half ball"),
            shot: shot(table, balls.clone(), (0, strike)),
        });
        // Thin cut: the cue ball grazes the object ball (impact parameter 1.90R to 1.99R).
        let offset = (1.90 + 0.018 * k as f64) * r;
        let strike = Strike {
            speed: speed + 1.0,
            dir: aim(cue, obj, side * offset),
            tip: DVec2::new(0.0, 0.2),
            elevation_deg: 0.0,
        };
        cases.push(Case {
            category: Category::ThinCut,
            name: format!(
                "thin-{k}: {} m/s, impact at {:.3} R",
                speed + 1.0,
                offset / r
            ),
            shot: shot(table, balls, (0, strike)),
        });
    }
    cases
}

/// A single ball driven around a 9 ft table off several rails.
fn cushion_shots() -> Vec<Case> {
    let shots = [
        ([0.3, 0.5], 3.0, 60.0, [0.0, 0.0]),
        ([0.635, 0.8], 4.0, 80.0, [0.3, 0.0]),
        ([1.0, 0.4], 5.0, 120.0, [-0.3, 0.2]),
        ([0.5, 2.0], 6.0, 250.0, [0.0, -0.3]),
        ([0.9, 1.5], 2.5, 20.0, [0.2, 0.2]),
        ([0.2, 1.27], 7.0, 33.0, [0.0, 0.3]),
        ([1.1, 2.3], 4.5, 200.0, [-0.35, 0.0]),
        ([0.635, 1.27], 3.0, 0.0, [0.0, 0.0]),
    ];
    shots
        .into_iter()
        .enumerate()
        .map(|(k, (pos, speed, angle, tip))| {
            let strike = Strike::at_angle(speed, angle, DVec2::from_array(tip));
            Case {
                category: Category::Cushion,
                name: format!("cushion-{k}: {speed} m/s at {angle} deg, tip {tip:?}"),
                shot: shot(
                    TableKind::NineFoot,
                    vec![BallState::at_rest(DVec2::from_array(pos))],
                    (0, strike),
                ),
            }
        })
        .collect()
}

/// The racks' generator: the rules' SplitMix64, so that racks are the same on every run.
pub use breakshot_shared::rules::rack::SplitMix64 as Rng;

/// Uniform in [-1, 1).
fn symmetric(rng: &mut Rng) -> f64 {
    2.0 * rng.unit() - 1.0
}

/// Nominal gap between neighbouring balls of a rack (m).
pub const RACK_GAP: f64 = 1e-4;

/// The rack's ball centres: a triangle of 15 (8-ball) or a diamond of 9 (9-ball), apex on
/// the foot spot (w/2, 3l/4), pointing at the head end. Neighbours sit `2R + RACK_GAP` apart
/// and each ball is moved at random by up to a quarter of the gap, so no two touch.
pub fn rack(category: Category, table: TableKind, radius: f64, rng: &mut Rng) -> Vec<DVec2> {
    let (w, l) = table.size().unwrap_or((1.27, 2.54));
    let apex = DVec2::new(0.5 * w, 0.75 * l);
    let d = 2.0 * radius + RACK_GAP;
    let row_step = d * 3f64.sqrt() / 2.0;
    let rows: &[usize] = match category {
        Category::Break9 => &[1, 2, 3, 2, 1],
        _ => &[1, 2, 3, 4, 5],
    };
    let mut out = Vec::new();
    for (row, &count) in rows.iter().enumerate() {
        for k in 0..count {
            let x = apex.x + (k as f64 - 0.5 * (count as f64 - 1.0)) * d;
            let y = apex.y + row as f64 * row_step;
            let jitter = DVec2::new(symmetric(rng), symmetric(rng)) * (0.25 * RACK_GAP);
            out.push(DVec2::new(x, y) + jitter);
        }
    }
    out
}

/// Rack number `k` of a kind of break: 8-ball on a 7 ft table, 9-ball on a 9 ft table; the
/// cue ball behind the head string, struck hard at the apex ball (ball speed about
/// 12 m/s, as in the reference break).
pub fn break_case(category: Category, k: u64) -> Case {
    let table = match category {
        Category::Break9 => TableKind::NineFoot,
        _ => TableKind::SevenFoot,
    };
    let radius = Params::default().ball_radius;
    let mut rng = Rng::new(0xB8EA_0000 + k * 7919 + category as u64);
    let (w, l) = table.size().unwrap_or((1.27, 2.54));
    let cue = DVec2::new(0.5 * w + 0.08 * symmetric(&mut rng), 0.25 * l);
    let rack = rack(category, table, radius, &mut rng);
    let apex = rack[0];
    let mut balls = vec![BallState::at_rest(cue)];
    balls.extend(rack.into_iter().map(BallState::at_rest));
    // Aim at the apex ball, off by up to a tenth of a ball radius.
    let dir = aim(cue, apex, 0.1 * radius * symmetric(&mut rng));
    let strike = Strike {
        speed: 8.0,
        dir,
        tip: DVec2::new(0.0, 0.1 * symmetric(&mut rng)),
        elevation_deg: 0.0,
    };
    Case {
        category,
        name: format!(
            "{}-{k}",
            if category == Category::Break9 {
                "break9"
            } else {
                "break8"
            }
        ),
        shot: shot(table, balls, (0, strike)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::engine::check;

    #[test]
    fn every_shot_of_the_workload_is_valid() {
        let cases = workload();
        for category in [Category::Break8, Category::Break9] {
            let count = cases.iter().filter(|c| c.category == category).count();
            assert!(count >= 20, "{count} breaks of {category:?}");
        }
        for c in &cases {
            assert_eq!(check(&c.shot), Ok(()), "{}", c.name);
        }
    }

    #[test]
    fn racks_have_small_gaps_and_no_contacts() {
        let r = Params::default().ball_radius;
        for category in [Category::Break8, Category::Break9] {
            let balls = rack(category, TableKind::NineFoot, r, &mut Rng::new(3));
            assert_eq!(
                balls.len(),
                if category == Category::Break8 { 15 } else { 9 }
            );
            let closest = balls
                .iter()
                .enumerate()
                .flat_map(|(i, a)| balls[i + 1..].iter().map(move |b| (*b - *a).length()))
                .fold(f64::INFINITY, f64::min);
            assert!(
                closest > 2.0 * r && closest < 2.0 * r + 2.0 * RACK_GAP,
                "{closest}"
            );
        }
    }

    #[test]
    fn aim_passes_the_object_ball_at_the_offset() {
        let (cue, obj) = (DVec2::new(0.1, 0.2), DVec2::new(0.7, 1.3));
        let dir = aim(cue, obj, 0.02);
        let d = obj - cue;
        // Distance of the object centre from the aim line, signed (left positive).
        let miss = dir.perp_dot(d);
        assert!((miss.abs() - 0.02).abs() < 1e-12, "{miss}");
    }
}
