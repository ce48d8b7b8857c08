//! The reference shots: a fixed set of built-in shots whose results both sides compute at
//! start. Together they meet every mechanism of the physics (a rack broken into clusters,
//! balls frozen together, each cushion model, the jaws of a pocket, a ball in flight, the
//! carom table), and their combined hash is the build's **physics fingerprint**: a client
//! whose physics differs from the server's by a single bit in any of them is refused in the
//! handshake, before it could desynchronise a game, and every game record names the
//! fingerprint it was played with.
//!
//! The fingerprint is computed, never written down: a deliberate physics change moves it by
//! itself. The golden test (`shared/tests/golden.rs`) pins each shot's hash and the
//! fingerprint, so such a change is seen and reviewed there.

use std::sync::OnceLock;

use glam::DVec2;

use crate::physics::{
    simulate, BallState, CushionModel, EventKind, MotionState, Outcome, Params, Shot, ShotError,
    Strike, TableKind,
};

/// Which mechanism a reference shot is there for; [`ReferenceShot::meets`] checks that its
/// outcome really shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mechanism {
    /// A rack broken hard: many balls at once, cushions, every motion state.
    Break,
    /// Balls frozen together, struck as a group.
    FrozenGroup,
    /// A ball off the rails under one cushion model.
    Cushion(CushionModel),
    /// A ball into the rounded nose of a pocket's jaw.
    Jaw,
    /// An elevated strike that lifts the ball off the cloth.
    Flight,
    /// A ball in flight coming down on another ball (the contact, with its friction, in the
    /// air).
    FlightOntoBall,
    /// A ball in flight meeting a pocket jaw's nose.
    FlightJaw,
    /// Carom balls on the heated cloth of the carom table.
    Carom,
}

/// One shot of the set, by name.
#[derive(Clone, Debug)]
pub struct ReferenceShot {
    /// A stable name (the golden file lists the shots by it).
    pub name: &'static str,
    /// What the shot is there to exercise.
    pub mechanism: Mechanism,
    /// The shot.
    pub shot: Shot,
}

impl ReferenceShot {
    /// Whether `outcome` (this shot's) shows the mechanism the shot is there for.
    pub fn meets(&self, outcome: &Outcome) -> bool {
        let kinds = || outcome.events.iter().map(|e| &e.kind);
        match self.mechanism {
            Mechanism::Break => {
                kinds().any(|k| matches!(k, EventKind::BallCushion { .. }))
                    && kinds()
                        .filter(|k| matches!(k, EventKind::BallBall { .. }))
                        .count()
                        >= 8
            }
            Mechanism::FrozenGroup => {
                let last = u16::try_from(self.shot.balls.len() - 1).unwrap_or(u16::MAX);
                kinds()
                    .any(|k| matches!(k, EventKind::BallBall { a, b } if *a == last || *b == last))
            }
            Mechanism::Cushion(_) | Mechanism::Carom => kinds().any(|k| {
                matches!(
                    k,
                    EventKind::BallCushion {
                        cushion: crate::physics::Cushion::Rail(_),
                        ..
                    }
                )
            }),
            Mechanism::Jaw => kinds().any(|k| {
                matches!(
                    k,
                    EventKind::BallCushion {
                        cushion: crate::physics::Cushion::Jaw(_),
                        ..
                    }
                )
            }),
            // The ball leaves the cloth at the strike and lands on the slate.
            Mechanism::Flight => kinds().any(|k| matches!(k, EventKind::BallTable { .. })),
            Mechanism::FlightOntoBall => outcome.events.iter().any(|e| match e.kind {
                EventKind::BallBall { a, b } => {
                    in_flight(outcome, usize::from(a), e.t)
                        || in_flight(outcome, usize::from(b), e.t)
                }
                _ => false,
            }),
            Mechanism::FlightJaw => outcome.events.iter().any(|e| match e.kind {
                EventKind::BallCushion {
                    ball,
                    cushion: crate::physics::Cushion::Jaw(_),
                } => in_flight(outcome, usize::from(ball), e.t),
                _ => false,
            }),
        }
    }
}

/// Whether `ball` was in the air just before time `t` of `outcome`.
fn in_flight(outcome: &Outcome, ball: usize, t: f64) -> bool {
    outcome.state_at(ball, t - 1e-9).motion == MotionState::Airborne
}

/// A six-ball triangle on a 9-foot table, broken hard with a little side and follow, so the
/// shot exercises ball–ball and cushion collisions, pockets and every motion state.
pub fn reference_shot() -> Shot {
    let table = TableKind::NineFoot;
    let (width, length) = table.size().unwrap_or((1.27, 2.54));
    let r = Params::default().ball_radius;
    let row = 2.0 * r * 0.866_025_403_784_438_6 + 1e-4;
    let apex = DVec2::new(width / 2.0, length * 0.75);
    let mut balls = vec![BallState::at_rest(DVec2::new(
        width / 2.0 + 0.05,
        length * 0.25,
    ))];
    for i in 0..3u32 {
        for j in 0..=i {
            let x = apex.x + (f64::from(j) - f64::from(i) / 2.0) * (2.0 * r + 1e-4);
            balls.push(BallState::at_rest(DVec2::new(
                x,
                apex.y + f64::from(i) * row,
            )));
        }
    }
    let aim = apex - balls[0].pos;
    let strike = Strike {
        speed: 8.0,
        dir: aim / aim.length(),
        tip: DVec2::new(0.1, 0.2),
        elevation_deg: 0.0,
    };
    Shot::new(table, balls).struck(0, strike)
}

/// Three balls frozen in a line in front of the cue ball on a 9-foot table: the cue ball
/// drives into the group, resolved as a group impact.
fn frozen_group() -> Shot {
    let r = Params::default().ball_radius;
    let x = 0.635;
    let mut balls = vec![BallState::at_rest(DVec2::new(x, 0.6))];
    for k in 0..3 {
        balls.push(BallState::at_rest(DVec2::new(
            x,
            1.2 + f64::from(k) * 2.0 * r,
        )));
    }
    Shot::new(TableKind::NineFoot, balls).struck(0, Strike::at_angle(2.0, 90.0, DVec2::ZERO))
}

/// One ball with running english, two rails on an 8-foot table, under `model`.
fn off_the_rails(model: CushionModel) -> Shot {
    let mut shot = Shot::new(TableKind::EightFoot, at_rest(&[[0.3, 0.4]]));
    shot.models.cushion = model;
    shot.struck(0, Strike::at_angle(3.0, 63.0, DVec2::new(-0.3, 0.2)))
}

/// A ball sent along the bottom rail into the corner pocket's far jaw.
fn into_the_jaw() -> Shot {
    let r = Params::default().ball_radius;
    Shot::new(TableKind::NineFoot, at_rest(&[[0.6, r + 0.012]]))
        .struck(0, Strike::at_angle(1.5, 180.0, DVec2::ZERO))
}

/// A jump over a blocker on a 9-foot table: 4 m/s at 45° of cue elevation.
fn jump() -> Shot {
    let (cue, blocker) = ([0.635, 0.4], [0.635, 1.09]);
    Shot::new(TableKind::NineFoot, at_rest(&[cue, blocker])).struck(
        0,
        Strike::at_angle(4.0, 90.0, DVec2::new(0.0, -0.1)).elevated(45.0),
    )
}

/// A jump with side spin that comes down on a ball a little to its side.
fn jump_onto_ball() -> Shot {
    Shot::new(TableKind::NineFoot, at_rest(&[[0.635, 0.4], [0.65, 0.7]])).struck(
        0,
        Strike::at_angle(2.0, 90.0, DVec2::new(0.2, 0.1)).elevated(50.0),
    )
}

/// A jump towards a corner pocket that meets the nose of its jaw in the air.
fn jump_into_the_jaw() -> Shot {
    Shot::new(TableKind::NineFoot, at_rest(&[[0.3, 2.2]]))
        .struck(0, Strike::at_angle(2.0, 136.0, DVec2::ZERO).elevated(35.0))
}

/// Three carom balls, a three-cushion style shot with side spin.
fn carom() -> Shot {
    Shot::new(
        TableKind::Carom,
        at_rest(&[[0.4, 0.5], [0.9, 1.2], [0.3, 2.2]]),
    )
    .struck(0, Strike::at_angle(4.0, 55.0, DVec2::new(0.3, 0.1)))
}

/// Balls at rest on the cloth at `centres` (m, scene coordinates), the struck ball first.
fn at_rest(centres: &[[f64; 2]]) -> Vec<BallState> {
    centres
        .iter()
        .map(|&[x, y]| BallState::at_rest(DVec2::new(x, y)))
        .collect()
}

/// Every reference shot, in the order the fingerprint folds them.
pub fn reference_shots() -> Vec<ReferenceShot> {
    let shot = |name, mechanism, shot| ReferenceShot {
        name,
        mechanism,
        shot,
    };
    let cushion = |name, model| shot(name, Mechanism::Cushion(model), off_the_rails(model));
    vec![
        shot("break_9ft", Mechanism::Break, reference_shot()),
        shot("frozen_group", Mechanism::FrozenGroup, frozen_group()),
        cushion("cushion_han2005", CushionModel::Han2005),
        cushion("cushion_mathavan2010", CushionModel::Mathavan2010),
        cushion("cushion_stronge", CushionModel::Stronge),
        cushion("cushion_simple", CushionModel::Simple),
        shot("jaw", Mechanism::Jaw, into_the_jaw()),
        shot("jump", Mechanism::Flight, jump()),
        shot(
            "jump_onto_ball",
            Mechanism::FlightOntoBall,
            jump_onto_ball(),
        ),
        shot("jump_jaw", Mechanism::FlightJaw, jump_into_the_jaw()),
        shot("carom", Mechanism::Carom, carom()),
    ]
}

/// FNV-1a (64-bit) step over `bytes`, from `h`.
fn fold(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The physics fingerprint as this build computes it: every reference shot's name, event
/// count and state hash, folded in order. Computed once per process (it takes about a
/// millisecond), then remembered.
pub fn reference_hash() -> Result<u64, ShotError> {
    static FINGERPRINT: OnceLock<Result<u64, ShotError>> = OnceLock::new();
    FINGERPRINT
        .get_or_init(|| {
            let mut h = 0xcbf2_9ce4_8422_2325;
            for reference in reference_shots() {
                let outcome = simulate(&reference.shot)?;
                h = fold(h, reference.name.as_bytes());
                h = fold(h, &(outcome.events.len() as u64).to_le_bytes());
                h = fold(h, &outcome.hash().to_le_bytes());
            }
            Ok(h)
        })
        .clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_reference_shot_is_valid_and_meets_its_mechanism() {
        let shots = reference_shots();
        let missed: Vec<String> = shots
            .iter()
            .filter_map(|reference| {
                let outcome = simulate(&reference.shot).unwrap();
                (!reference.meets(&outcome)).then(|| {
                    format!(
                        "{} does not show {:?}: {:?}",
                        reference.name,
                        reference.mechanism,
                        outcome.events.iter().map(|e| &e.kind).collect::<Vec<_>>()
                    )
                })
            })
            .collect();
        assert!(missed.is_empty(), "{}", missed.join("\n"));
        for reference in &shots {
            let outcome = simulate(&reference.shot).unwrap();
            assert!(
                reference.meets(&outcome),
                "{} does not show {:?}: {:?}",
                reference.name,
                reference.mechanism,
                outcome.events.iter().map(|e| &e.kind).collect::<Vec<_>>()
            );
        }
        // Every cushion model has its shot.
        for model in [
            CushionModel::Han2005,
            CushionModel::Mathavan2010,
            CushionModel::Stronge,
            CushionModel::Simple,
        ] {
            assert!(shots
                .iter()
                .any(|s| s.mechanism == Mechanism::Cushion(model)));
        }
    }

    #[test]
    fn the_fingerprint_is_repeatable_and_moves_with_any_one_shot() {
        assert_eq!(reference_hash().unwrap(), reference_hash().unwrap());
        // Each shot's hash goes into it: a different result of any one shot gives another
        // fingerprint (checked by folding a changed hash in its place).
        let outcomes: Vec<(usize, u64)> = reference_shots()
            .iter()
            .map(|r| {
                let o = simulate(&r.shot).unwrap();
                (o.events.len(), o.hash())
            })
            .collect();
        let names: Vec<&str> = reference_shots().iter().map(|r| r.name).collect();
        let folded = |moved: Option<usize>| {
            let mut h = 0xcbf2_9ce4_8422_2325;
            for (i, (name, (events, hash))) in names.iter().zip(&outcomes).enumerate() {
                let hash = if moved == Some(i) { hash ^ 1 } else { *hash };
                h = fold(h, name.as_bytes());
                h = fold(h, &(*events as u64).to_le_bytes());
                h = fold(h, &hash.to_le_bytes());
            }
            h
        };
        assert_eq!(folded(None), reference_hash().unwrap());
        for (i, name) in names.iter().enumerate() {
            assert_ne!(folded(Some(i)), folded(None), "{name}");
        }
    }
}
