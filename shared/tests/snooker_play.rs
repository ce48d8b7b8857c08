//! Random snooker play: every command the rules accept keeps the scores moving only by
//! legal amounts (a fair stroke adds its pots to the striker, a foul 4 to 7 to the
//! opponent, nothing else changes a score), and every frame can be brought to an end.

use breakshot_shared::physics::{MotionState, Strike};
use breakshot_shared::rules::{Choice, Command, Game, Phase, Seat, Settings, Variant};
use glam::DVec2;
use proptest::prelude::*;

/// Strokes played per case: enough to reach fouls, free balls and colours, few enough to
/// stay fast in a debug build.
const STROKES: usize = 24;

fn scores(g: &Game) -> [u32; 2] {
    g.snooker().map_or([0, 0], |m| m.scores)
}

fn index(seat: Seat) -> usize {
    match seat {
        Seat::A => 0,
        Seat::B => 1,
    }
}

/// A legal place for the cue ball in hand: the first free point of a grid over the area.
fn place(g: &Game) -> Option<[f64; 2]> {
    let Phase::Shooting {
        in_hand: Some(area),
        ..
    } = g.phase()
    else {
        return None;
    };
    let (lo, hi) = g.in_hand_area(*area);
    (1..12)
        .flat_map(|i| (1..12).map(move |j| (i, j)))
        .find_map(|(i, j)| {
            let p = [
                lo.x + (hi.x - lo.x) * f64::from(i) / 12.0,
                lo.y + (hi.y - lo.y) * f64::from(j) / 12.0,
            ];
            g.legal_cue_placement(p).is_ok().then_some(p)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 10, ..ProptestConfig::default() })]

    #[test]
    fn scores_only_grow_by_legal_values_and_a_frame_always_ends(
        seed in any::<u64>(),
        reds in prop::sample::select(vec![6u8, 10, 15]),
        moves in prop::collection::vec((0.0..360.0f64, 0.3..5.0f64, 0usize..8), STROKES),
    ) {
        let mut g = Game::new(Variant::Snooker { reds, best_of: 1 }, Settings::offline(), seed);
        let mut strokes = 0;
        for (angle, speed, pick) in moves {
            if matches!(g.phase(), Phase::Over { .. }) {
                break;
            }
            let seat = g.to_move();
            let before = scores(&g);
            let cmd = match g.phase().clone() {
                Phase::Deciding { options } => Command::Decide(options[pick % options.len()]),
                Phase::Shooting { options, .. } => {
                    let cue_off = g.balls()[0].motion == MotionState::Pocketed;
                    if let (true, Some(pos)) = (cue_off || pick == 0, place(&g)) {
                        Command::PlaceCueBall { pos }
                    } else if !options.is_empty() && pick % 2 == 0 {
                        Command::Decide(options[pick % options.len()])
                    } else {
                        Command::Shot {
                            strike: Strike::at_angle(speed, angle, DVec2::ZERO),
                            call: None,
                        }
                    }
                }
                Phase::Over { .. } => break,
            };
            let verdict = g.apply(seat, &cmd);
            prop_assert!(verdict.is_ok(), "{cmd:?} refused: {verdict:?}");
            let Ok(verdict) = verdict else { break };
            strokes += usize::from(matches!(cmd, Command::Shot { .. }));
            let after = scores(&g);
            if matches!(g.phase(), Phase::Over { .. }) || verdict.over.is_some() {
                break;
            }
            let (me, them) = (index(seat), 1 - index(seat));
            prop_assert!(after[me] >= before[me] && after[them] >= before[them]);
            let gained = [after[me] - before[me], after[them] - before[them]];
            if verdict.foul {
                prop_assert_eq!(gained[0], 0, "{:?}", verdict.reasons);
                prop_assert!((4..=7).contains(&gained[1]), "{:?}", verdict.reasons);
            } else if matches!(cmd, Command::Shot { .. }) {
                prop_assert_eq!(gained[1], 0);
                // At most every red on the table, or one colour.
                prop_assert!(gained[0] <= u32::from(reds).max(7), "{:?}", verdict.reasons);
            } else {
                prop_assert_eq!(gained, [0, 0]);
            }
        }
        prop_assert!(strokes > 0, "no stroke was played");
        if !matches!(g.phase(), Phase::Over { .. }) {
            let seat = g.to_move();
            let v = g.apply(seat, &Command::Concede).expect("a frame can always be conceded");
            prop_assert!(v.over.is_some());
        }
        // Nominating is never refused with a panic, only with a reason.
        let _ = g.check(Seat::A, &Command::Decide(Choice::Nominate(255)));
    }
}
