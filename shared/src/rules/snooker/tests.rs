//! One test per snooker rule: each lays out a real position, plays the stroke with the
//! engine through `Game::apply`, and checks the verdict the rules give.

use glam::DVec2;

use super::frame::BallOn;
use super::table::*;
use super::*;
use crate::physics::{BallState, MotionState};
use crate::rules::{Command, Settings};

const R: f64 = 0.02625;

fn game() -> Game {
    Game::new(Variant::snooker(), Settings::offline(), 3)
}

/// A game with only `balls` on the table (the rest off), seat A to play on a red.
fn position(balls: &[(u8, [f64; 2])]) -> Game {
    let mut g = game();
    for b in g.balls.iter_mut() {
        *b = off_table();
    }
    for &(i, p) in balls {
        g.balls[usize::from(i)] = BallState::at_rest(DVec2::from_array(p));
    }
    g.phase = Phase::Shooting {
        in_hand: None,
        options: Vec::new(),
        push_out: false,
    };
    g
}

fn strike_at(g: &Game, target: [f64; 2], speed: f64) -> Command {
    let from = g.balls[0].pos;
    let dir = (DVec2::from_array(target) - from).normalize();
    Command::Shot {
        strike: Strike {
            speed,
            dir,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        },
        call: None,
    }
}

fn shot_dir(dir: [f64; 2], speed: f64, tip: [f64; 2]) -> Command {
    Command::Shot {
        strike: Strike {
            speed,
            dir: DVec2::from_array(dir).normalize(),
            tip: DVec2::from_array(tip),
            elevation_deg: 0.0,
        },
        call: None,
    }
}

fn scores(g: &Game) -> [u32; 2] {
    g.snooker().map_or([0, 0], |m| m.scores)
}

fn off(g: &Game, b: u8) -> bool {
    g.balls[usize::from(b)].motion == MotionState::Pocketed
}

/// A red straight into the top-left corner pocket from the cue ball, hit with stun.
const POT_FROM: [f64; 2] = [0.5, 3.069];
const POT_RED: [f64; 2] = [0.3, 3.269];

/// Whether a shot is due with the cue ball in hand in the D.
fn in_hand_in_the_d(g: &Game) -> bool {
    matches!(
        g.phase(),
        Phase::Shooting {
            in_hand: Some(InHand::D),
            ..
        }
    )
}

/// A soft stroke across the table from the cue ball at `[0.889, 1.0]`, clear of every ball
/// the tests put beside it: a foul and a miss.
fn miss() -> Command {
    shot_dir([1.0, 0.0], 0.3, [0.0, 0.0])
}

fn pot_red_game() -> Game {
    position(&[
        (CUE, POT_FROM),
        (1, POT_RED),
        (2, [1.2, 1.0]),
        (BLACK, spot(BLACK).to_array()),
    ])
}

fn pot_red() -> Command {
    shot_dir([-1.0, 1.0], 1.6, [0.0, -0.3])
}

#[test]
fn the_frame_is_racked_with_the_colours_on_their_spots_and_the_cue_ball_in_hand_in_the_d() {
    let g = game();
    assert_eq!(g.table(), crate::physics::TableKind::Snooker);
    assert_eq!(g.balls().len(), BALL_COUNT);
    for c in COLOURS {
        assert_eq!(g.balls()[usize::from(c)].pos, spot(c));
    }
    assert_eq!(frame::reds_left(g.balls()), 15);
    assert!(in_hand_in_the_d(&g));
    assert!(in_d(g.balls()[0].pos));
    let six = Game::new(
        Variant::Snooker {
            reds: 6,
            best_of: 1,
        },
        Settings::offline(),
        3,
    );
    assert_eq!(frame::reds_left(six.balls()), 6);
    // The racked balls touch nothing.
    for (i, b) in g
        .balls()
        .iter()
        .enumerate()
        .filter(|(_, b)| b.motion != MotionState::Pocketed)
    {
        assert!(is_free(g.balls(), i, b.pos), "ball {i} overlaps");
    }
}

#[test]
fn the_cue_ball_placed_outside_the_d_is_refused_and_nothing_changes() {
    let mut g = game();
    let before = g.clone();
    let outside = [0.889, 0.8];
    let err = g.apply(Seat::A, &Command::PlaceCueBall { pos: outside });
    assert_eq!(
        err,
        Err(RuleError::IllegalPlacement(
            "the cue ball must be placed in the D".into()
        ))
    );
    assert_eq!(g, before);
    let inside = [0.889 + 0.1, 0.7];
    assert!(g
        .apply(Seat::A, &Command::PlaceCueBall { pos: inside })
        .is_ok());
}

#[test]
fn a_red_potted_scores_one_and_the_striker_is_on_a_colour() {
    let mut g = pot_red_game();
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert!(off(&g, 1), "{:?}", v.reasons);
    assert_eq!(v.reasons[0], "Player A pots a red: 1 (break 1)");
    assert_eq!(scores(&g), [1, 0]);
    assert_eq!(g.to_move(), Seat::A);
    assert!(matches!(
        g.snooker().map(|m| m.ball_on(g.balls())),
        Some(BallOn::Colour(None))
    ));
    let Phase::Shooting { options, .. } = g.phase() else {
        panic!("shooting")
    };
    assert!(options.contains(&Choice::Nominate(BLACK)));
}

#[test]
fn nominating_a_ball_that_is_not_a_colour_is_refused_and_nothing_changes() {
    let mut g = pot_red_game();
    g.apply(Seat::A, &pot_red()).expect("shot");
    g.balls[3] = BallState::at_rest(DVec2::new(1.0, 2.0));
    let before = g.clone();
    let err = g.apply(Seat::A, &Command::Decide(Choice::Nominate(3)));
    assert_eq!(
        err,
        Err(RuleError::InvalidChoice(
            "a red is not a colour: nominate a colour".into()
        ))
    );
    assert_eq!(g, before);
    let err = g.apply(Seat::A, &Command::Decide(Choice::Nominate(40)));
    assert_eq!(
        err,
        Err(RuleError::InvalidChoice(
            "there is no ball 40 to nominate".into()
        ))
    );
}

#[test]
fn the_nominated_colour_potted_scores_its_value_and_is_re_spotted_while_reds_remain() {
    let mut g = position(&[(CUE, POT_FROM), (PINK, POT_RED), (2, [1.2, 1.0])]);
    g.snooker.as_mut().expect("snooker").on_colour = true;
    let v = g
        .apply(Seat::A, &Command::Decide(Choice::Nominate(PINK)))
        .expect("nominates");
    assert_eq!(v.reasons, vec!["Player A nominates the pink".to_string()]);
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert_eq!(v.reasons[0], "Player A pots the pink: 6 (break 6)");
    assert_eq!(v.reasons[1], "The pink is re-spotted on its spot");
    assert_eq!(g.balls()[usize::from(PINK)].pos, spot(PINK));
    assert_eq!(scores(&g), [6, 0]);
    assert!(matches!(
        g.snooker().map(|m| m.ball_on(g.balls())),
        Some(BallOn::Red)
    ));
}

#[test]
fn a_colour_goes_to_the_highest_free_spot_when_its_own_is_taken() {
    let mut g = position(&[(CUE, POT_FROM), (PINK, POT_RED), (2, spot(PINK).to_array())]);
    g.snooker.as_mut().expect("snooker").on_colour = true;
    g.apply(Seat::A, &Command::Decide(Choice::Nominate(PINK)))
        .expect("nominates");
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert_eq!(
        v.reasons[1],
        "The pink is re-spotted on the black's spot (its own is taken)"
    );
    assert_eq!(g.balls()[usize::from(PINK)].pos, spot(BLACK));
}

#[test]
fn with_every_spot_taken_a_colour_goes_as_near_its_own_spot_as_possible_towards_the_top() {
    let mut balls: Vec<BallState> = (0..BALL_COUNT).map(|_| off_table()).collect();
    for (k, c) in COLOURS.into_iter().enumerate() {
        balls[usize::from(1 + k as u8)] = BallState::at_rest(spot(c));
    }
    let how = respot(&mut balls, BLUE);
    assert_eq!(how, Respot::NearOwnSpot);
    let p = balls[usize::from(BLUE)].pos;
    assert_eq!(p.x, spot(BLUE).x);
    assert!(p.y > spot(BLUE).y && p.y - spot(BLUE).y < 2.0 * R + 1e-3);
}

#[test]
fn hitting_the_blue_first_when_on_a_red_is_a_foul_of_five() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.889, 1.6]), (1, [0.3, 3.0])]);
    let v = g
        .apply(Seat::A, &strike_at(&g, [0.889, 1.6], 1.5))
        .expect("shot");
    assert_eq!(
        v.reasons[0],
        "Foul and a miss: the blue was hit first, 5 to Player B"
    );
    assert!(v.foul);
    assert_eq!(scores(&g), [0, 5]);
    assert_eq!(
        g.phase(),
        &Phase::Deciding {
            options: vec![
                Choice::AcceptTable,
                Choice::OffenderPlaysAgain,
                Choice::ReplaceBalls
            ]
        }
    );
}

#[test]
fn a_foul_when_the_striker_needs_snookers_is_no_miss() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.889, 1.6]), (1, [0.3, 3.0])]);
    g.snooker.as_mut().expect("snooker").scores = [0, 60];
    let v = g
        .apply(Seat::A, &strike_at(&g, [0.889, 1.6], 1.5))
        .expect("shot");
    assert_eq!(v.reasons[0], "Foul: the blue was hit first, 5 to Player B");
    assert_eq!(
        g.phase(),
        &Phase::Deciding {
            options: vec![Choice::AcceptTable, Choice::OffenderPlaysAgain]
        }
    );
}

#[test]
fn hitting_no_ball_is_a_foul_of_four_and_the_offender_may_be_made_to_play_again() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (1, [0.3, 3.0])]);
    let v = g.apply(Seat::A, &miss()).expect("shot");
    assert_eq!(
        v.reasons[0],
        "Foul and a miss: the cue ball hit no ball, 4 to Player B"
    );
    assert_eq!(g.to_move(), Seat::B);
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::OffenderPlaysAgain))
        .expect("choice");
    assert_eq!(v.reasons[1], "Player A plays again");
    assert_eq!(g.to_move(), Seat::A);
    assert!(matches!(g.phase(), Phase::Shooting { .. }));
}

#[test]
fn an_in_off_is_a_foul_and_the_next_player_has_the_cue_ball_in_hand_in_the_d() {
    // The cue ball straight into the top-left corner, missing everything.
    let mut g = position(&[(CUE, POT_FROM), (1, [1.4, 1.0])]);
    let v = g
        .apply(Seat::A, &shot_dir([-1.0, 1.0], 1.2, [0.0, 0.0]))
        .expect("shot");
    assert!(off(&g, CUE));
    assert_eq!(
        v.reasons[0],
        "Foul and a miss: the cue ball hit no ball, 4 to Player B"
    );
    assert_eq!(v.reasons[1], "Also: in-off: the cue ball was potted");
    g.apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    assert!(in_hand_in_the_d(&g));
}

#[test]
fn potting_a_ball_not_on_is_a_foul_of_its_value() {
    let mut g = position(&[(CUE, POT_FROM), (PINK, POT_RED), (1, [1.2, 1.0])]);
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert!(
        v.reasons.contains(&"Also: the pink was potted".to_string()),
        "{:?}",
        v.reasons
    );
    assert!(v.reasons[0].ends_with("6 to Player B"));
    assert_eq!(g.balls()[usize::from(PINK)].pos, spot(PINK));
}

#[test]
fn a_foul_after_a_red_before_nominating_costs_seven() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (YELLOW, [0.889, 1.6]), (1, [0.3, 3.0])]);
    g.snooker.as_mut().expect("snooker").on_colour = true;
    // Hits no ball: a foul of the ball on's value, 7 as nothing was nominated.
    let v = g.apply(Seat::A, &miss()).expect("shot");
    assert_eq!(
        v.reasons[0],
        "Foul and a miss: the cue ball hit no ball before a colour was nominated, 7 to Player B"
    );
}

#[test]
fn two_reds_hit_at_once_are_fair_but_a_red_and_the_blue_at_once_are_a_foul_of_five() {
    let d = 0.03125;
    let place = |b: u8| {
        position(&[
            (CUE, [0.889, 1.0]),
            (1, [0.889 - d, 1.5]),
            (b, [0.889 + d, 1.5]),
        ])
    };
    let straight = shot_dir([0.0, 1.0], 1.0, [0.0, 0.0]);
    let mut g = place(2);
    let v = g.apply(Seat::A, &straight).expect("shot");
    assert!(!v.foul, "{:?}", v.reasons);
    let mut g = place(BLUE);
    let v = g.apply(Seat::A, &straight).expect("shot");
    assert_eq!(
        v.reasons[0],
        "Foul and a miss: a red and the blue were hit at once, 5 to Player B"
    );
}

#[test]
fn several_reds_potted_in_one_stroke_all_score() {
    // Two reds either side of the cue ball's line, hit at once (exactly: the table's frame
    // is centred, so the layout is an exact mirror image) and sent to the two top corners.
    // The search over the reds' distance finds where the engine pots both; the rules must
    // then count both.
    let d = 0.03125;
    let straight = shot_dir([0.0, 1.0], 3.0, [0.0, 0.0]);
    let mut found = false;
    for k in 0..40 {
        let y = 2.2 + 0.01 * f64::from(k);
        let mut g = position(&[
            (CUE, [0.889, y - 0.3]),
            (1, [0.889 - d, y]),
            (2, [0.889 + d, y]),
            (YELLOW, [1.5, 0.5]),
        ]);
        let v = g.apply(Seat::A, &straight).expect("shot");
        if !v.foul && off(&g, 1) && off(&g, 2) {
            assert_eq!(v.reasons[0], "Player A pots a red and a red: 2 (break 2)");
            assert_eq!(scores(&g), [2, 0]);
            found = true;
            break;
        }
    }
    assert!(found, "no layout had both reds potted");
}

#[test]
fn a_free_ball_is_given_when_snookered_after_a_foul() {
    // Player A taps the cue ball into nothing; it lies behind the pink, the one red beyond.
    let mut g = position(&[(CUE, [0.889, 2.5]), (PINK, [0.889, 2.6]), (1, [0.889, 3.2])]);
    let v = g
        .apply(Seat::A, &shot_dir([1.0, 0.0], 0.05, [0.0, 0.0]))
        .expect("shot");
    assert!(v.foul);
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    let v = nominate_free_ball(&mut g, &v, PINK);
    assert_eq!(
        v.reasons,
        vec!["Free ball: the pink is nominated".to_string()]
    );
    // Hitting the free ball first is fair.
    let v = g
        .apply(Seat::B, &strike_at(&g, [0.889, 2.6], 0.8))
        .expect("shot");
    assert!(!v.foul, "{:?}", v.reasons);
}

/// Checks that `v`, Player B's choice to play on, gave a free ball, and nominates `ball` as
/// it: the verdict of the nomination.
fn nominate_free_ball(g: &mut Game, v: &Verdict, ball: u8) -> Verdict {
    assert_eq!(
        v.reasons[1],
        "Free ball: Player B is snookered and may nominate any ball as the ball on"
    );
    g.apply(Seat::B, &Command::Decide(Choice::Nominate(ball)))
        .expect("the free ball is nominated")
}

/// Checks that Player B's nomination of `ball` (the `name`) as a free ball is refused as
/// there is none, and changes nothing.
fn free_ball_refused(g: &mut Game, ball: u8, name: &str) {
    let before = g.clone();
    let err = g.apply(Seat::B, &Command::Decide(Choice::Nominate(ball)));
    let why = format!(
        "no free ball: the cue ball is not snookered after a foul, and the {name} cannot be nominated"
    );
    assert_eq!(err, Err(RuleError::InvalidChoice(why)));
    assert_eq!(*g, before);
}

/// `balls` laid out, Player A taps the cue ball into nothing (a foul) and Player B plays on.
fn played_on_after_a_miss(balls: &[(u8, [f64; 2])]) -> Game {
    let mut g = position(balls);
    g.apply(Seat::A, &shot_dir([1.0, 0.0], 0.05, [0.0, 0.0]))
        .expect("shot");
    g.apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    g
}

#[test]
fn leaving_the_cue_ball_snookered_behind_the_free_ball_is_a_foul() {
    // As above, but Player B nudges the free ball along the line to the red: the cue ball
    // follows and stops with the pink between it and the only red.
    let mut g =
        played_on_after_a_miss(&[(CUE, [0.889, 2.5]), (PINK, [0.889, 2.6]), (1, [0.889, 3.2])]);
    g.apply(Seat::B, &Command::Decide(Choice::Nominate(PINK)))
        .expect("nominates");
    let before = scores(&g);
    let v = g
        .apply(Seat::B, &strike_at(&g, [0.889, 2.6], 0.3))
        .expect("shot");
    assert!(v.foul, "{:?}", v.reasons);
    assert!(
        v.reasons[0].contains("the cue ball was left snookered behind the free ball, the pink"),
        "{:?}",
        v.reasons
    );
    // The value of the ball on, a red: the least penalty, 4.
    assert_eq!(scores(&g)[0], before[0] + 4);
    // Without the pink in the way the red is in full view: the snooker is the free ball's.
    assert!(frame::snookered(&g.balls, &[1]));
    let mut without_pink = g.balls.clone();
    without_pink[usize::from(PINK)] = off_table();
    assert!(!frame::snookered(&without_pink, &[1]));
}

#[test]
fn a_free_ball_nomination_when_not_snookered_is_refused_and_nothing_changes() {
    let mut g =
        played_on_after_a_miss(&[(CUE, [0.889, 1.0]), (PINK, [0.3, 2.6]), (1, [0.889, 3.2])]);
    free_ball_refused(&mut g, PINK, "pink");
}

#[test]
fn snookered_means_no_ball_on_can_be_hit_at_both_extreme_edges() {
    let cue = DVec2::new(0.889, 1.0);
    let target = DVec2::new(0.889, 2.0);
    // A blocker half across the line hides one edge: snookered.
    let half_across = Obstacles::new(vec![DVec2::new(0.889 + 1.5 * R, 1.5)]);
    assert!(snookered_on(cue, target, &half_across));
    // Far enough aside, both edges are in view.
    let aside = Obstacles::new(vec![DVec2::new(0.889 + 4.1 * R, 1.5)]);
    assert!(!snookered_on(cue, target, &aside));
    // The same in a game: the red is on, the blue hides it.
    let g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.889, 1.5]), (1, [0.889, 2.0])]);
    assert!(frame::snookered(g.balls(), &[1]));
    let g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.3, 1.5]), (1, [0.889, 2.0])]);
    assert!(!frame::snookered(g.balls(), &[1]));
}

/// Player A, cue ball hanging in the mouth of the bottom-left corner pocket, taps it a few
/// millimetres out along the baulk cushion (a foul and a miss) with `balls` on the table
/// too; it stays in the jaws, the left cushion's jaw in the way of every stroke up the
/// table. Player B plays on.
fn played_on_from_the_jaws(balls: &[(u8, [f64; 2])]) -> (Game, Verdict) {
    let mut layout = vec![(CUE, [0.008, 0.03])];
    layout.extend_from_slice(balls);
    let mut g = position(&layout);
    let v = g
        .apply(Seat::A, &shot_dir([1.0, 0.0], 0.03, [0.0, 0.0]))
        .expect("shot");
    assert!(v.foul, "{:?}", v.reasons);
    // Still in the mouth: nearer the left cushion's line than a ball on the cloth can be.
    let cue = g.balls[0].pos;
    assert!(cue.x < R * 0.9 && (cue.y - 0.03).abs() < 1e-12, "{cue}");
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    (g, v)
}

/// Where the cue ball rests after the tap of [`played_on_from_the_jaws`].
const IN_THE_JAWS: [f64; 2] = [0.014_283_068_445_710_145, 0.030_000_000_000_000_027];

#[test]
fn the_cue_ball_cannot_be_snookered_by_a_cushion_a_jaw_nearer_than_the_ball_not_on() {
    // WPBSA 2.16(e). The only red lies up the left cushion, the blue on the line between:
    // the blue hides the red, but the curved face of the jaw stands in the way first.
    let (mut g, v) = played_on_from_the_jaws(&[(1, [0.03, 1.5]), (BLUE, [0.03, 0.8])]);
    assert_eq!(g.balls[0].pos, DVec2::from_array(IN_THE_JAWS));
    assert!(
        !v.reasons.iter().any(|r| r.starts_with("Free ball")),
        "{:?}",
        v.reasons
    );
    free_ball_refused(&mut g, BLUE, "blue");
    // Out of the jaws, on the cloth by the cushion, the blue alone stands in the way: snookered.
    let mut on_the_cloth = g.balls.clone();
    on_the_cloth[0].pos.x = 0.03;
    assert!(frame::snookered(&on_the_cloth, &[1]));
}

#[test]
fn a_ball_not_on_nearer_than_the_jaw_snookers_the_cue_ball_in_the_jaws() {
    // WPBSA 2.16(e) the other way: the red lies up the table beyond the jaw, and the blue,
    // just clear of the cue ball, is met before the jaw on both strokes at its edges.
    let jaws = DVec2::from_array(IN_THE_JAWS);
    let at = |angle_deg: f64, dist: f64| {
        let a = angle_deg * (std::f64::consts::PI / 180.0);
        (jaws + DVec2::new(libm::cos(a), libm::sin(a)) * dist).to_array()
    };
    let (red, blue) = (at(85.0, 1.0), at(60.0, 2.0 * R + 0.001));
    let (mut g, v) = played_on_from_the_jaws(&[(1, red), (BLUE, blue)]);
    assert_eq!(g.balls[0].pos, jaws);
    nominate_free_ball(&mut g, &v, BLUE);
    // Without the blue the jaw alone is in the way: angled, not snookered.
    let mut angled = g.balls.clone();
    angled[usize::from(BLUE)] = off_table();
    assert!(!frame::snookered(&angled, &[1]));
}

/// Player A goes in-off into the top-left corner, missing everything, with `balls` on the
/// table too; Player B plays on with the cue ball in hand in the D.
fn played_on_after_an_in_off(balls: &[(u8, [f64; 2])]) -> (Game, Verdict) {
    let mut layout = vec![(CUE, POT_FROM)];
    layout.extend_from_slice(balls);
    let mut g = position(&layout);
    g.apply(Seat::A, &shot_dir([-1.0, 1.0], 1.2, [0.0, 0.0]))
        .expect("shot");
    assert!(off(&g, CUE));
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    assert!(in_hand_in_the_d(&g));
    (g, v)
}

#[test]
fn in_hand_the_cue_ball_is_snookered_if_obstructed_from_every_position_in_the_d() {
    // WPBSA 2.16(a). The only red by the top cushion, the pink half a metre in front of it:
    // from anywhere in the D some edge of the red is hidden.
    let (mut g, v) = played_on_after_an_in_off(&[(1, [0.889, 3.5]), (PINK, [0.889, 3.0])]);
    nominate_free_ball(&mut g, &v, PINK);
    // The D's two corners, its middle and a point on its arc: hidden from each.
    let mut balls = g.balls.clone();
    let c = d_centre();
    for p in [
        c + DVec2::new(-D_RADIUS + R, 0.0),
        c + DVec2::new(D_RADIUS - R, 0.0),
        c,
        c + DVec2::new(0.0, -D_RADIUS + R),
    ] {
        balls[0] = BallState::at_rest(p);
        assert!(frame::snookered(&balls, &[1]), "from {p}");
    }
}

#[test]
fn in_hand_the_cue_ball_is_not_snookered_if_some_position_in_the_d_gives_a_view() {
    // WPBSA 2.16(a). The pink nearer the D: it hides the red from the middle of the D (the
    // brown's spot among them) but not from its ends.
    let (g, v) = played_on_after_an_in_off(&[(1, [0.889, 3.5]), (PINK, [0.889, 2.5])]);
    assert!(
        !v.reasons.iter().any(|r| r.starts_with("Free ball")),
        "{:?}",
        v.reasons
    );
    let mut balls = g.balls.clone();
    balls[0] = BallState::at_rest(d_centre());
    assert!(frame::snookered(&balls, &[1]));
    balls[0] = BallState::at_rest(d_centre() + DVec2::new(D_RADIUS - R, 0.0));
    assert!(!frame::snookered(&balls, &[1]));
}

#[test]
fn after_a_foul_and_a_miss_the_balls_are_replaced_on_request() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.889, 1.6]), (1, [0.3, 3.0])]);
    let start = g.balls.clone();
    g.apply(Seat::A, &strike_at(&g, [0.889, 1.6], 1.5))
        .expect("shot");
    assert_ne!(g.balls, start);
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::ReplaceBalls))
        .expect("replace");
    assert_eq!(v.reasons[1], "The balls are replaced; Player A plays again");
    assert_eq!(g.balls, start);
    assert_eq!(g.to_move(), Seat::A);
}

#[test]
fn replacing_the_balls_when_no_miss_was_called_is_refused_and_nothing_changes() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.889, 1.6]), (1, [0.3, 3.0])]);
    g.snooker.as_mut().expect("snooker").scores = [0, 60];
    g.apply(Seat::A, &strike_at(&g, [0.889, 1.6], 1.5))
        .expect("shot");
    let before = g.clone();
    let err = g.apply(Seat::B, &Command::Decide(Choice::ReplaceBalls));
    assert_eq!(
        err,
        Err(RuleError::InvalidChoice(
            "the balls are replaced only after a foul and a miss".into()
        ))
    );
    assert_eq!(g, before);
}

#[test]
fn a_third_miss_from_a_clear_view_forfeits_the_frame_after_a_warning() {
    let mut g = position(&[(CUE, [0.889, 1.0]), (BLUE, [0.3, 1.6]), (1, [0.889, 2.0])]);
    // Each time Player A plays at the blue instead of the red in full view.
    let at_blue = strike_at(&g, [0.3, 1.6], 1.5);
    let v = g.apply(Seat::A, &at_blue).expect("first");
    assert!(v.reasons[0].starts_with("Foul and a miss"));
    g.apply(Seat::B, &Command::Decide(Choice::ReplaceBalls))
        .expect("replace");
    let v = g.apply(Seat::A, &at_blue).expect("second");
    assert_eq!(
        v.reasons.last().map(String::as_str),
        Some("Warning: another miss from here forfeits the frame for Player A")
    );
    g.apply(Seat::B, &Command::Decide(Choice::ReplaceBalls))
        .expect("replace");
    let v = g.apply(Seat::A, &at_blue).expect("third");
    assert!(v.reasons.contains(
        &"Player A missed a ball on 3 times in a row from a clear view: the frame goes to Player B"
            .to_string()
    ));
    assert_eq!(v.over, Some((Some(Seat::B), "Player B wins".to_string())));
}

#[test]
fn three_misses_from_the_jaws_with_the_ball_on_behind_the_jaw_are_no_clear_view_and_forfeit_nothing(
) {
    // The only red lies up the left cushion, nothing between; the cue ball rests in the
    // jaws of the corner, where the curved face stands in the path of a full-ball contact.
    let red = [0.03, 1.5];
    let mut g = position(&[(CUE, IN_THE_JAWS), (1, red)]);
    assert!(!frame::clear_view(&g.balls, &[1]));
    // Out of the jaws, on the cloth by the cushion, nothing is in the way.
    let mut on_the_cloth = g.balls.clone();
    on_the_cloth[0].pos.x = 0.03;
    assert!(frame::clear_view(&on_the_cloth, &[1]));
    let start = g.balls.clone();
    // Each time Player A plays out along the bottom cushion, hitting nothing.
    for stroke in 1..=3 {
        let v = g.apply(Seat::A, &miss()).expect("a stroke");
        assert!(
            v.reasons[0].starts_with("Foul and a miss"),
            "{:?}",
            v.reasons
        );
        assert!(
            !v.reasons.iter().any(|r| r.starts_with("Warning")),
            "stroke {stroke}: {:?}",
            v.reasons
        );
        assert_eq!(v.over, None, "stroke {stroke}");
        g.apply(Seat::B, &Command::Decide(Choice::ReplaceBalls))
            .expect("replace");
        assert_eq!(g.balls, start);
    }
}

#[test]
fn playing_away_from_a_touching_ball_on_is_no_foul_but_pushing_it_is() {
    let red = [0.889, 1.5];
    let touching = [0.889, 1.5 - 2.0 * R];
    let mut g = position(&[(CUE, touching), (1, red), (BLUE, [0.3, 3.0])]);
    let v = g
        .apply(Seat::A, &shot_dir([0.0, -1.0], 0.5, [0.0, 0.0]))
        .expect("away");
    assert!(!v.foul, "{:?}", v.reasons);
    let mut g = position(&[(CUE, touching), (1, red), (BLUE, [0.3, 3.0])]);
    let v = g
        .apply(Seat::A, &shot_dir([0.0, 1.0], 0.5, [0.0, 0.0]))
        .expect("push");
    assert!(v.foul);
    assert!(
        v.reasons
            .iter()
            .any(|r| r.contains("push stroke: the cue ball was touching a red")),
        "{:?}",
        v.reasons
    );
}

/// The last black in front of the top-left pocket.
fn last_black(scores: [u32; 2]) -> Game {
    let mut g = position(&[(CUE, POT_FROM), (BLACK, POT_RED)]);
    g.snooker.as_mut().expect("snooker").scores = scores;
    g
}

#[test]
fn the_last_black_potted_ends_the_frame_for_the_higher_score() {
    let mut g = last_black([30, 33]);
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert_eq!(v.reasons[0], "Player A pots the black: 7 (break 7)");
    assert!(v
        .reasons
        .contains(&"Player A wins the frame 37-33".to_string()));
    assert_eq!(v.over, Some((Some(Seat::A), "Player A wins".to_string())));
}

#[test]
fn scores_tied_after_the_last_black_re_spot_the_black_and_the_next_score_decides() {
    let mut g = last_black([30, 37]);
    let v = g.apply(Seat::A, &pot_red()).expect("shot");
    assert!(v.over.is_none());
    assert!(v
        .reasons
        .iter()
        .any(|r| r.starts_with("Scores level at 37: the black is re-spotted")));
    assert_eq!(g.balls()[usize::from(BLACK)].pos, spot(BLACK));
    assert!(in_hand_in_the_d(&g));
    // The player drawn misses everything: the foul decides the frame.
    let seat = g.to_move();
    g.apply(seat, &Command::PlaceCueBall { pos: [0.889, 0.6] })
        .expect("placed");
    let v = g
        .apply(seat, &shot_dir([1.0, 0.0], 0.2, [0.0, 0.0]))
        .expect("shot");
    assert!(v.foul);
    assert_eq!(v.over.map(|(w, _)| w), Some(Some(seat.other())));
}

#[test]
fn a_foul_with_only_the_black_left_ends_the_frame_when_the_scores_differ() {
    let mut g = last_black([30, 20]);
    let v = g
        .apply(Seat::A, &shot_dir([1.0, 0.0], 0.2, [0.0, 0.0]))
        .expect("shot");
    assert!(v.foul);
    assert_eq!(v.over, Some((Some(Seat::A), "Player A wins".to_string())));
    assert!(v
        .reasons
        .contains(&"Player A wins the frame 30-27".to_string()));
}

#[test]
fn a_conceded_frame_goes_to_the_opponent_and_the_match_goes_on_to_its_frames() {
    let mut g = Game::new(
        Variant::Snooker {
            reds: 6,
            best_of: 3,
        },
        Settings::offline(),
        9,
    );
    let v = g.apply(Seat::A, &Command::Concede).expect("concede");
    assert_eq!(v.reasons[0], "Player A concedes the frame");
    assert!(v.over.is_none());
    assert_eq!(g.snooker().map(|m| m.frames), Some([0, 1]));
    // The other player breaks off the next frame, from the D, with the reds racked again.
    assert_eq!(g.to_move(), Seat::B);
    assert_eq!(frame::reds_left(g.balls()), 6);
    let v = g.apply(Seat::B, &Command::Concede).expect("concede");
    assert!(v.over.is_none());
    let v = g.apply(Seat::A, &Command::Concede).expect("concede");
    assert_eq!(
        v.over,
        Some((Some(Seat::B), "Player B wins the match 2-1".to_string()))
    );
}

#[test]
fn a_snooker_record_replays_and_verifies() {
    let mut g = game();
    let mut record = crate::replay::GameRecord::of(&g);
    let place = Command::PlaceCueBall { pos: [1.05, 0.70] };
    let v = g.apply(Seat::A, &place).expect("placed");
    record.push(Seat::A, place, v.shot.map(|s| s.hash));
    let break_off = strike_at(&g, [0.9944 + 1.5 * R, 2.912], 4.5);
    let v = g.apply(Seat::A, &break_off).expect("break-off");
    record.push(Seat::A, break_off, v.shot.map(|s| s.hash));
    let decoded = crate::replay::GameRecord::decode(&record.encode()).expect("decodes");
    assert_eq!(decoded.replay().expect("replays"), g);
}

#[test]
fn the_computer_nominates_a_colour_before_playing_at_it() {
    let mut g = pot_red_game();
    g.apply(Seat::A, &pot_red()).expect("shot");
    assert!(g.snooker().is_some_and(|m| m.on_colour));
    let cmd = crate::ai::decide(&g, crate::ai::Level::new(1), 5).expect("a move");
    assert!(
        matches!(cmd, Command::Decide(Choice::Nominate(c)) if is_colour(c)),
        "{cmd:?}"
    );
    g.apply(Seat::A, &cmd).expect("the nomination is legal");
    let cmd = crate::ai::decide(&g, crate::ai::Level::new(1), 5).expect("a move");
    assert!(matches!(cmd, Command::Shot { .. }), "{cmd:?}");
}

fn jump(speed: f64, elevation_deg: f64) -> Command {
    Command::Shot {
        strike: Strike {
            speed,
            dir: DVec2::new(0.0, 1.0),
            tip: DVec2::ZERO,
            elevation_deg,
        },
        call: None,
    }
}

#[test]
fn a_cue_ball_that_flies_over_a_ball_before_its_first_contact_is_a_jump_shot() {
    // A red 12 cm up the table from the cue ball, another far beyond on the same line.
    let layout = [(CUE, [0.889, 1.0]), (1, [0.889, 1.12]), (2, [0.889, 2.2])];
    // Struck down hard at 40°, the cue ball clears the near red.
    let mut g = position(&layout);
    let v = g.apply(Seat::A, &jump(3.0, 40.0)).expect("shot");
    assert!(v.foul, "{:?}", v.reasons);
    assert_eq!(
        v.reasons[0],
        "Foul: jump shot: the cue ball jumped over a red, 4 to Player B"
    );
    // At 20° it hops but meets the near red: a fair stroke that scores nothing.
    let mut g = position(&layout);
    let v = g.apply(Seat::A, &jump(3.0, 20.0)).expect("shot");
    assert!(!v.foul, "{:?}", v.reasons);
}

#[test]
fn a_cue_ball_jumped_off_the_table_is_a_foul_and_the_next_player_has_it_in_hand() {
    // Struck up at 45° from half a metre off the top cushion, the cue ball flies over it.
    let mut g = position(&[(CUE, [0.889, 3.0]), (1, [0.889, 1.12])]);
    let v = g.apply(Seat::A, &jump(4.0, 45.0)).expect("shot");
    assert!(off(&g, CUE));
    assert_eq!(
        v.reasons[..2],
        [
            "Foul and a miss: the cue ball hit no ball, 4 to Player B".to_string(),
            "Also: the cue ball left the table".to_string()
        ]
    );
    g.apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .expect("plays on");
    assert!(in_hand_in_the_d(&g));
}

#[test]
fn in_hand_the_search_of_the_d_misses_no_view_a_fine_grid_finds() {
    // WPBSA 2.16(a), the search checked against a grid of the D: on tables with one or two
    // reds, each screened by colours put in front of it, wherever the search calls the cue
    // ball snookered, no point of the grid has a red in view.
    let mut rng = crate::rules::rack::SplitMix64::new(11);
    let mut called = [0, 0];
    for _ in 0..40 {
        let mut balls = vec![off_table(); BALL_COUNT];
        let mut on = Vec::new();
        for red in 1..=1 + rng.below(2) as u8 {
            let p = DVec2::new(0.1 + 1.578 * rng.unit(), 2.0 + 1.4 * rng.unit());
            if is_free(&balls, usize::from(red), p) {
                balls[usize::from(red)] = BallState::at_rest(p);
                on.push(red);
            }
        }
        for colour in COLOURS.into_iter().take(1 + rng.below(6) as usize) {
            let Some(&red) = on.get(rng.below(on.len() as u64) as usize) else {
                break;
            };
            let towards_d = (d_centre() - balls[usize::from(red)].pos).normalize();
            let p = balls[usize::from(red)].pos
                + towards_d * (2.0 * R + 0.002 + 0.6 * rng.unit())
                + DVec2::new(-towards_d.y, towards_d.x) * (0.1 * (rng.unit() - 0.5));
            if is_free(&balls, usize::from(colour), p) {
                balls[usize::from(colour)] = BallState::at_rest(p);
            }
        }
        let snookered = frame::snookered(&balls, &on);
        called[usize::from(snookered)] += 1;
        if !snookered {
            continue;
        }
        let c = d_centre();
        let step = 0.005;
        for i in -60..=60 {
            for j in -60..=0 {
                let p = c + DVec2::new(f64::from(i), f64::from(j)) * step;
                if !in_d(p) || !is_free(&balls, usize::from(CUE), p) {
                    continue;
                }
                balls[0] = BallState::at_rest(p);
                assert!(frame::snookered(&balls, &on), "a view from {p}");
            }
        }
        balls[0] = off_table();
    }
    // Both answers come up.
    assert!(called[0] > 5 && called[1] > 5, "{called:?}");
}
