//! A random but legal player, for the property tests and the record tests.

#![allow(dead_code)]

use breakshot_shared::physics::{engine, simulate, MotionState, ShotError, Strike, Table};
use breakshot_shared::rules::rack::{ball_radius, head_string, table_size, SplitMix64};
use breakshot_shared::rules::{Choice, Command, Game, InHand, Phase, RuleError, Seat, Verdict};
use glam::DVec2;

/// A source of random numbers for the player (the rules' own SplitMix64, so a seed replays).
pub struct Dice(SplitMix64);

impl Dice {
    pub fn new(seed: u64) -> Dice {
        Dice(SplitMix64::new(seed))
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
    pub fn below(&mut self, n: usize) -> usize {
        self.0.below(n as u64) as usize
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.range(0.0, 1.0) < p
    }
}

/// How a played game ended.
#[derive(Debug, PartialEq)]
pub enum End {
    Over(Option<Seat>),
    Rerack,
    /// Still going after the shot budget.
    Unfinished,
    /// The engine left a table that its own validation refuses, so no shot can follow.
    Stuck(String),
}

/// What a game of random play did.
pub struct Played {
    pub end: End,
    pub shots: usize,
    /// Shots the engine could not finish (refused, nothing changed), replaced by another.
    pub refused: usize,
    /// Every applied command, with its seat and verdict.
    pub log: Vec<(Seat, Command, Verdict)>,
}

/// A random legal cue-ball position in `area`, if one is found.
pub fn place(game: &Game, area: InHand, dice: &mut Dice) -> Option<[f64; 2]> {
    let (w, l) = table_size(game.table());
    let margin = ball_radius() + 0.01;
    let top = match area {
        InHand::Kitchen => head_string(game.table()) - 0.001,
        InHand::Anywhere => l - margin,
        // Snooker: the D's bounding box; points outside the D are refused below.
        InHand::D => game.in_hand_area(area).1.y,
    };
    (0..100)
        .map(|_| [dice.range(margin, w - margin), dice.range(margin, top)])
        .find(|&p| game.legal_cue_placement(p).is_ok())
}

/// A random strike aimed at one of the balls the shooter may hit first (any ball in
/// practice), with a random cut, speed and tip.
pub fn random_strike(game: &Game, dice: &mut Dice) -> Strike {
    let balls = game.balls();
    let cue = balls[0].pos;
    let mut targets = game.legal_first_balls();
    if targets.is_empty() {
        targets = (1..balls.len() as u8)
            .filter(|&b| balls[usize::from(b)].motion != MotionState::Pocketed)
            .collect();
    }
    let speed_range = if game.is_break() {
        (6.0, 12.0)
    } else {
        (1.0, 6.0)
    };
    let speed = dice.range(speed_range.0, speed_range.1);
    let tip = DVec2::new(dice.range(-0.3, 0.3), dice.range(-0.3, 0.3));
    let dir = match targets.get(dice.below(targets.len().max(1))) {
        Some(&t) => {
            let to = balls[usize::from(t)].pos - cue;
            // Aim anywhere across the target ball: from a thin cut to a full hit.
            let spread = (2.0 * ball_radius() / to.length()).min(1.0) * 0.9;
            let side = DVec2::new(-to.y, to.x).normalize();
            to.normalize() + side * dice.range(-spread, spread)
        }
        None => DVec2::new(dice.range(-1.0, 1.0), dice.range(0.1, 1.0)),
    };
    Strike {
        speed,
        dir: dir.normalize(),
        tip,
        elevation_deg: 0.0,
    }
}

/// The command a random legal player gives now.
pub fn random_command(game: &Game, dice: &mut Dice) -> Command {
    let pockets = Table::new(game.table()).pockets.len() as u8;
    match game.phase() {
        Phase::Deciding { options } => Command::Decide(options[dice.below(options.len())]),
        Phase::Shooting {
            in_hand, options, ..
        } => {
            if options.contains(&Choice::PushOut) && dice.chance(0.3) {
                return Command::Decide(Choice::PushOut);
            }
            let cue_off = game.balls()[0].motion == MotionState::Pocketed;
            if let Some(area) = in_hand {
                let here_ok = !cue_off
                    && game
                        .legal_cue_placement(game.balls()[0].pos.to_array())
                        .is_ok();
                if !here_ok || dice.chance(0.5) {
                    if let Some(pos) = place(game, *area, dice) {
                        return Command::PlaceCueBall { pos };
                    }
                }
            }
            let strike = random_strike(game, dice);
            let shot = Command::Shot { strike, call: None };
            if let Err(RuleError::InvalidShot(_)) = game.check(game.to_move(), &shot) {
                // A call is required: call a random pocket.
                return Command::Shot {
                    strike,
                    call: Some(dice.below(usize::from(pockets)) as u8),
                };
            }
            shot
        }
        Phase::Over { .. } => Command::Concede,
    }
}

/// Checks what must hold after every command, apart from the table's geometry (see
/// [`check_table`]).
pub fn check_invariants(game: &Game, ball_count: usize) {
    let balls = game.balls();
    assert_eq!(balls.len(), ball_count, "ball count");
    for b in balls {
        assert!(
            matches!(
                b.motion,
                MotionState::Stationary | MotionState::Spinning | MotionState::Pocketed
            ),
            "a ball still moving between shots: {b:?}"
        );
    }
    match game.phase() {
        Phase::Deciding { options } => assert!(!options.is_empty(), "a choice with no options"),
        Phase::Shooting { in_hand, .. } => {
            if balls[0].motion == MotionState::Pocketed {
                assert!(in_hand.is_some(), "cue ball off the table and not in hand");
            }
        }
        Phase::Over { .. } => {}
    }
}

/// Checks the table with the engine's own validation (every ball on the cloth, none
/// overlapping), so that the next shot can be played. `before` is the game before `cmd`.
///
/// If the check fails only for balls exactly where the physics left them after a shot, the
/// fault is the engine's (its output fails its own validation) and the game cannot go on:
/// that is returned as an error. Any other failure is a rules fault and panics.
pub fn check_table(game: &Game, before: &Game, cmd: &Command) -> Result<(), String> {
    let probe = Strike {
        speed: 1.0,
        dir: DVec2::Y,
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    };
    let mut shot = game.shot_for(&probe);
    shot.strike = None;
    let Err(e) = engine::check(&shot) else {
        return Ok(());
    };
    let culprits = match e {
        ShotError::Overlap { a, b } => vec![a, b],
        ShotError::OffTable { ball } => vec![ball],
        _ => panic!("invalid table: {e}"),
    };
    if let Command::Shot { strike, .. } = cmd {
        let finals = simulate(&before.shot_for(strike))
            .expect("the shot was played")
            .finals;
        if culprits.iter().all(|&i| game.balls()[i] == finals[i]) {
            return Err(format!("the engine left a table it refuses: {e}"));
        }
    }
    panic!("the rules left an invalid table: {e}");
}

/// Plays random legal commands until the game ends, a re-rack, or `max_shots` shots.
pub fn play(game: &mut Game, dice: &mut Dice, max_shots: usize) -> Played {
    let ball_count = game.balls().len();
    let mut played = Played {
        end: End::Unfinished,
        shots: 0,
        refused: 0,
        log: Vec::new(),
    };
    let mut commands = 0;
    while played.shots < max_shots && commands < 20 * max_shots {
        commands += 1;
        let seat = game.to_move();
        let cmd = random_command(game, dice);
        let rack = game.rack_number();
        let is_shot = matches!(cmd, Command::Shot { .. });
        let before = game.clone();
        match game.apply(seat, &cmd) {
            Ok(verdict) => {
                check_invariants(game, ball_count);
                let table = check_table(game, &before, &cmd);
                if is_shot {
                    played.shots += 1;
                    assert!(verdict.shot.is_some());
                }
                let over = verdict.over.clone();
                played.log.push((seat, cmd, verdict));
                if let Err(why) = table {
                    played.end = End::Stuck(why);
                    return played;
                }
                if let Some((winner, _)) = over {
                    played.end = End::Over(winner);
                    return played;
                }
                if game.rack_number() != rack {
                    played.end = End::Rerack;
                    return played;
                }
            }
            Err(RuleError::InvalidShot(why)) if is_shot => {
                // The engine could not play the shot (its event limit); nothing may change.
                assert_eq!(*game, before, "a refused shot changed the game ({why})");
                played.refused += 1;
            }
            Err(e) => panic!("the random player's command was refused: {cmd:?}: {e}"),
        }
    }
    played
}
