//! The computer player: only legal commands, pots simple shots at the top level under its
//! own noise, plays safe when nothing can be potted, and decides the same from the same seed.

use breakshot_shared::ai::{self, Kind, Level, Player, Thinking};
use breakshot_shared::physics::{BallState, Shot, TableKind};
use breakshot_shared::rules::{Command, EightBallRules, Game, Phase, Settings, Variant};
use glam::DVec2;

const R: f64 = 0.028575;

/// A practice game with the cue ball and ball 1 (and optionally more) at the given spots.
fn practice(layout: &[(usize, [f64; 2])]) -> Game {
    let mut game = Game::new(Variant::Practice, Settings::offline(), 1);
    let mut balls = vec![None; 16];
    for &(b, p) in layout {
        balls[b] = Some(p);
    }
    let seat = game.to_move();
    game.apply(seat, &Command::LoadLayout { balls })
        .expect("layout accepted");
    game
}

/// Out of `trials` decisions at level 5 (noise included), how many pot ball 1?
fn pots(layout: &[(usize, [f64; 2])], trials: u64) -> u64 {
    let mut made = 0;
    for seed in 0..trials {
        let mut game = practice(layout);
        let seat = game.to_move();
        let command = ai::decide(&game, Level::new(5), seed).expect("a move");
        assert!(matches!(command, Command::Shot { .. }), "{command:?}");
        let verdict = game.apply(seat, &command).expect("legal");
        let pocketed = verdict.shot.expect("a shot").pocketed;
        if pocketed.iter().any(|&(b, _)| b == 1) && !pocketed.iter().any(|&(b, _)| b == 0) {
            made += 1;
        }
    }
    made
}

#[test]
fn level_5_pots_a_straight_in_shot() {
    // Ball 1 on the long string half way to the foot rail, cue ball straight behind it
    // towards the top-left corner pocket.
    let made = pots(&[(0, [0.3, 1.2]), (1, [0.15, 1.9])], 10);
    assert!(made >= 9, "potted {made} of 10");
}

#[test]
fn level_5_pots_a_cut() {
    let made = pots(&[(0, [0.64, 1.5]), (1, [0.25, 2.2])], 10);
    assert!(made >= 8, "potted {made} of 10");
}

#[test]
fn level_5_pots_a_ball_frozen_to_a_rail() {
    // Ball 1 touching the left rail 0.6 m from the top-left corner pocket.
    let made = pots(&[(0, [0.3, 1.6]), (1, [R + 1e-6, 1.94])], 10);
    assert!(made >= 8, "potted {made} of 10");
}

#[test]
fn plays_safe_when_no_pot_exists() {
    // An open table has no pockets: nothing can be potted.
    let balls = vec![
        BallState::at_rest(DVec2::new(0.0, 0.0)),
        BallState::at_rest(DVec2::new(0.3, 0.8)),
    ];
    let shot = Shot::new(TableKind::Open, balls);
    let found = Thinking::suggest(&shot, 0, &[1], Level::new(5), 3)
        .finish()
        .expect("a suggestion");
    assert!(
        matches!(found.kind, Kind::Safety | Kind::Kick),
        "{:?}",
        found.kind
    );
    assert_eq!(found.p_success, 0.0);
    assert!(found.strike.validated().is_ok());
}

#[test]
fn the_same_seed_gives_the_same_decision() {
    let game = Game::new(Variant::NineBall, Settings::offline(), 9);
    let mut g = game.clone();
    // Play the break so that the decision is an ordinary shot.
    let seat = g.to_move();
    let brk = ai::decide(&g, Level::new(2), 1).expect("a break");
    g.apply(seat, &brk).expect("legal break");
    for level in [1, 4] {
        let a = ai::plan(&g, &Player::from(Level::new(level)), 77);
        let b = ai::plan(&g, &Player::from(Level::new(level)), 77);
        assert_eq!(a, b, "level {level}");
        assert_eq!(
            ai::decide(&g, Level::new(level), 5),
            ai::decide(&g, Level::new(level), 5)
        );
    }
}

#[test]
fn a_ball_in_hand_is_placed_once_then_played() {
    // The cue ball off the table in practice: the computer must place it, then shoot.
    let mut game = practice(&[(1, [0.4, 1.8]), (2, [0.9, 1.0])]);
    let seat = game.to_move();
    let first = ai::decide(&game, Level::new(3), 1).expect("a move");
    assert!(matches!(first, Command::PlaceCueBall { .. }), "{first:?}");
    game.apply(seat, &first).expect("legal placement");
    let second = ai::decide(&game, Level::new(3), 2).expect("a move");
    assert!(matches!(second, Command::Shot { .. }), "{second:?}");
}

/// Plays up to `commands` commands of a game with the computer in both seats, asserting the
/// rules accept every one.
fn only_legal(variant: Variant, settings: Settings, seed: u64, commands: usize) {
    let mut game = Game::new(variant, settings, seed);
    for n in 0..commands {
        if matches!(game.phase(), Phase::Over { .. }) {
            return;
        }
        let seat = game.to_move();
        let level = Level::new(1 + (n % 2) as u8);
        let command = ai::decide(&game, level, seed * 1000 + n as u64).expect("a move");
        if let Err(e) = game.apply(seat, &command) {
            panic!("{variant:?} seed {seed}, command {n}: {command:?} refused: {e}");
        }
    }
}

#[test]
fn never_makes_an_illegal_command() {
    let called = Settings {
        call_every_shot: true,
        ..Settings::offline()
    };
    for seed in 1..=2 {
        only_legal(
            Variant::EightBall(EightBallRules::Wpa),
            Settings::offline(),
            seed,
            14,
        );
        only_legal(Variant::EightBall(EightBallRules::Bar), called, seed, 14);
        only_legal(Variant::NineBall, Settings::offline(), seed, 14);
        only_legal(Variant::NineBall, called, seed, 10);
    }
    only_legal(Variant::Practice, Settings::offline(), 4, 8);
    only_legal(Variant::three_cushion(), Settings::offline(), 1, 6);
    only_legal(
        Variant::Snooker {
            reds: 6,
            best_of: 1,
        },
        Settings::offline(),
        1,
        8,
    );
}

/// In three-cushion the computer looks for caroms: from the starting position it finds
/// strokes that score, and under its own noise it scores with some of its decisions.
#[test]
fn three_cushion_is_played_for_points() {
    let game = Game::new(Variant::three_cushion(), Settings::offline(), 1);
    let player = Player::from(Level::new(4));
    let plan = ai::plan(&game, &player, 7).expect("a move");
    assert_eq!(plan.kind, Some(Kind::Carom));
    assert!(
        plan.p_success.is_some_and(|p| p > 0.0),
        "no stroke found that scores: {plan:?}"
    );
    let points = (0..6)
        .filter(|&seed| {
            let mut g = game.clone();
            let seat = g.to_move();
            let command = ai::decide(&g, Level::new(4), seed).expect("a move");
            let verdict = g.apply(seat, &command).expect("a legal stroke");
            verdict.next == seat && !verdict.foul
        })
        .count();
    assert!(points >= 1, "{points} points in 6 tries at level 4");
}

#[test]
fn never_makes_an_illegal_command_from_random_layouts() {
    // Random practice layouts, including a cue ball off the table.
    let mut rng = ai::Rng::new(12);
    for k in 0..6 {
        let mut balls: Vec<Option<[f64; 2]>> = vec![None; 16];
        let mut placed: Vec<DVec2> = Vec::new();
        for slot in balls.iter_mut().take(1 + 3 + k) {
            for _ in 0..100 {
                let p = DVec2::new(0.05 + 1.17 * rng.unit(), 0.05 + 2.44 * rng.unit());
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
        let mut game = Game::new(Variant::Practice, Settings::offline(), 1);
        let seat = game.to_move();
        game.apply(seat, &Command::LoadLayout { balls })
            .expect("layout accepted");
        for n in 0..3 {
            let command = ai::decide(&game, Level::new(2), n).expect("a move");
            game.apply(seat, &command)
                .unwrap_or_else(|e| panic!("layout {k}: {command:?} refused: {e}"));
        }
    }
}
