//! The computer's search in steps: however it is stepped, a [`Thinking`] search returns
//! exactly the command [`ai::decide`] returns for the same game, level and seed (compared bit
//! for bit), runs no more simulations per step than it was allowed, and reports a progress
//! that only goes forward and ends at 1.
//!
//! The positions are met in games the computer plays against itself from seeded racks in
//! every variant it plays: breaks, ordinary shots, balls in hand (placements), the choices
//! after a foul break, three-cushion strokes and practice layouts.
//!
//! A debug build is some twenty times slower than a release one, so there the test searches
//! a few dozen positions at the cheap levels; `.ci/run` runs it in release too, where it
//! searches over three hundred positions at every level.

use std::task::Poll;

use breakshot_shared::ai::{self, Decision, Level, Player, Schedule, Thinking};
use breakshot_shared::rules::{Command, EightBallRules, Game, Phase, Settings, Variant};

/// A command's exact bits: its encoding, in which every f64 is its IEEE bit pattern.
fn bits(command: &Option<Command>) -> Vec<u8> {
    bincode::serde::encode_to_vec(command, bincode::config::standard()).expect("encodable")
}

/// The positions before each of the first `moves` moves of a game the computer plays against
/// itself at level 1 (cheap, and it fouls often enough to give balls in hand).
fn positions_of(variant: Variant, settings: Settings, seed: u64, moves: usize) -> Vec<Game> {
    let mut game = Game::new(variant, settings, seed);
    let mut out = Vec::new();
    for n in 0..moves {
        if matches!(game.phase(), Phase::Over { .. }) {
            break;
        }
        out.push(game.clone());
        let seat = game.to_move();
        let command = ai::decide(&game, Level::new(1), seed * 1000 + n as u64).expect("a move");
        game.apply(seat, &command).expect("a legal move");
    }
    out
}

/// Practice layouts from a seeded source, one in three with the cue ball off the table (so
/// the computer must place it first).
fn practice_positions(count: u64) -> Vec<Game> {
    const R: f64 = 0.028575;
    let mut rng = ai::Rng::new(21);
    let mut out = Vec::new();
    for k in 0..count {
        let mut balls: Vec<Option<[f64; 2]>> = vec![None; 16];
        let mut placed: Vec<glam::DVec2> = Vec::new();
        for slot in balls.iter_mut().take(2 + (k % 6) as usize) {
            for _ in 0..100 {
                let p = glam::DVec2::new(0.05 + 1.17 * rng.unit(), 0.05 + 2.44 * rng.unit());
                if placed.iter().all(|q| (*q - p).length() > 2.5 * R) {
                    placed.push(p);
                    *slot = Some(p.to_array());
                    break;
                }
            }
        }
        if k % 3 == 0 {
            balls[0] = None;
        }
        let mut game = Game::new(Variant::Practice, Settings::offline(), k);
        let seat = game.to_move();
        game.apply(seat, &Command::LoadLayout { balls })
            .expect("layout accepted");
        out.push(game);
    }
    out
}

/// Every position of the test, named for a failure message.
fn positions(games: u64, moves: usize) -> Vec<(String, Game)> {
    let called = Settings {
        call_every_shot: true,
        ..Settings::offline()
    };
    let variants = [
        (
            "8-ball",
            Variant::EightBall(EightBallRules::Wpa),
            Settings::offline(),
        ),
        (
            "8-ball bar, called",
            Variant::EightBall(EightBallRules::Bar),
            called,
        ),
        ("9-ball", Variant::NineBall, Settings::offline()),
        (
            "three-cushion",
            Variant::three_cushion(),
            Settings::offline(),
        ),
    ];
    let mut out = Vec::new();
    for (name, variant, settings) in variants {
        for seed in 1..=games {
            for (n, game) in positions_of(variant, settings, seed, moves)
                .into_iter()
                .enumerate()
            {
                out.push((format!("{name}, rack {seed}, move {n}"), game));
            }
        }
    }
    for (k, game) in practice_positions(games * 4).into_iter().enumerate() {
        out.push((format!("practice layout {k}"), game));
    }
    out
}

/// Runs `thinking` in steps of `step` simulations to its answer, checking the steps and the
/// progress on the way.
fn stepped<T: Clone + PartialEq + std::fmt::Debug>(
    mut thinking: Thinking<T>,
    step: usize,
    context: &str,
) -> T {
    let mut last = thinking.progress();
    let mut fraction = thinking.fraction();
    assert_eq!(
        (last.simulations, fraction),
        (0, 0.0),
        "{context}: a fresh search"
    );
    loop {
        let poll = thinking.step(step).map(Clone::clone);
        let now = thinking.progress();
        let ran = now.simulations - last.simulations;
        assert!(
            ran <= step,
            "{context}: {ran} simulations in a step of {step}"
        );
        assert!(now.planned >= now.simulations, "{context}: {now:?}");
        assert!(
            thinking.fraction() >= fraction && thinking.fraction() <= 1.0,
            "{context}: the fraction went from {fraction} to {}",
            thinking.fraction()
        );
        fraction = thinking.fraction();
        match poll {
            Poll::Ready(answer) => {
                assert!(now.finished && fraction == 1.0, "{context}: {now:?}");
                assert_eq!(now.planned, now.simulations, "{context}: finished");
                // Asked again, a finished search gives the same answer and runs nothing.
                let again = thinking.step(step).map(Clone::clone);
                assert_eq!(again, Poll::Ready(answer.clone()), "{context}");
                assert_eq!(thinking.progress(), now, "{context}");
                return answer;
            }
            Poll::Pending => {
                assert!(!now.finished && fraction < 1.0, "{context}: {now:?}");
                // A step that was allowed simulations and is not finished used all of them.
                assert_eq!(ran, step, "{context}: a step stopped early");
            }
        }
        last = now;
    }
}

/// How much the test searches: (racks per variant, moves per rack, levels in turn, the
/// fewest positions). See the module's comment.
fn extent() -> (u64, usize, &'static [u8], usize) {
    if cfg!(debug_assertions) {
        (1, 8, &[1, 2], 30)
    } else {
        (6, 12, &[1, 2, 3, 4, 5], 300)
    }
}

#[test]
fn the_stepped_search_returns_exactly_what_decide_returns() {
    let (racks, moves, levels, fewest) = extent();
    let positions = positions(racks, moves);
    assert!(
        positions.len() >= fewest,
        "only {} positions",
        positions.len()
    );
    for (k, (name, game)) in positions.iter().enumerate() {
        let level = Level::new(levels[k % levels.len()]);
        let seed = 0xD0 + k as u64;
        let expected = bits(&ai::decide(game, level, seed));
        for step in [1, 7, 1 << 30] {
            let context = format!("{name}, level {}, steps of {step}", level.number());
            let answer = stepped(Thinking::decide(game, level, seed), step, &context);
            assert_eq!(bits(&answer), expected, "{context}: another command");
        }
    }
}

/// A decision's exact bits: the command's, the chance's, and what it cost.
fn decision_bits(decision: &Option<Decision>) -> Option<(Vec<u8>, Option<u64>, String, usize)> {
    decision.as_ref().map(|d| {
        (
            bits(&Some(d.command.clone())),
            d.p_success.map(f64::to_bits),
            format!("{:?}", d.kind),
            d.simulations,
        )
    })
}

/// The look-ahead (a search inside each trial) is where stepping is most intricate, and the
/// levels that use it are the slowest: a player with level 1's breadth and a small schedule
/// that looks ahead checks it at any build's speed.
#[test]
fn a_stepped_plan_with_look_ahead_returns_exactly_what_plan_returns() {
    let player = Player {
        schedule: Schedule {
            samples: [1, 2, 3],
            keep: [4, 2],
            look_ahead: true,
        },
        ..Player::from(Level::new(1))
    };
    let games = [
        positions_of(
            Variant::EightBall(EightBallRules::Wpa),
            Settings::offline(),
            4,
            5,
        ),
        positions_of(Variant::NineBall, Settings::offline(), 5, 5),
    ];
    // The same player without the look-ahead, to show that the look-ahead ran.
    let flat = Player {
        schedule: Schedule {
            look_ahead: false,
            ..player.schedule
        },
        ..player
    };
    let cost = |d: &Option<Decision>| d.as_ref().map(|d| d.simulations);
    let mut looked_ahead = 0;
    for (k, game) in games.iter().flatten().enumerate() {
        let expected = ai::plan(game, &player, k as u64);
        looked_ahead += usize::from(cost(&expected) > cost(&ai::plan(game, &flat, k as u64)));
        for step in [1, 7, 1 << 30] {
            let context = format!("position {k}, steps of {step}");
            let answer = stepped(Thinking::plan(game, &player, k as u64), step, &context);
            assert_eq!(
                decision_bits(&answer),
                decision_bits(&expected),
                "{context}"
            );
        }
    }
    assert!(
        looked_ahead >= 3,
        "only {looked_ahead} searches looked ahead"
    );
}
