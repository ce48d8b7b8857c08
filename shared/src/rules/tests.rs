//! One test per rule clause: each builds the exact table (balls + a strike played by the real
//! engine, or crafted shot facts where the engine cannot produce the situation) and checks
//! the verdict and its first reason word for word.

use glam::DVec2;

use super::*;
use crate::physics::{BallState, MotionState, Strike};

const R: f64 = 0.028575;
const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Pocket indices on the default table.
const BOTTOM_LEFT: u8 = 0;
const TOP_LEFT: u8 = 2;

/// A shot geometry: where the cue ball and the object ball(s) are, and the strike.
#[derive(Clone, Copy)]
struct Geometry {
    cue: [f64; 2],
    object: [f64; 2],
    dir: [f64; 2],
    speed: f64,
    tip: f64,
}

/// The object ball straight into the top-left corner; the draw keeps the cue ball out.
const POT: Geometry = Geometry {
    cue: [0.6, 1.94],
    object: [0.3, 2.24],
    dir: [-1.0, 1.0],
    speed: 2.0,
    tip: -0.3,
};
/// The same pot with follow: the cue ball goes in after it.
const POT_SCRATCH: Geometry = Geometry {
    speed: 3.0,
    tip: 0.45,
    ..POT
};
/// From the kitchen, the object ball into the bottom-left corner (for breaks).
const KITCHEN_POT: Geometry = Geometry {
    cue: [0.4, 0.4],
    object: [0.2, 0.2],
    dir: [-1.0, -1.0],
    speed: 2.0,
    tip: -0.3,
};
const KITCHEN_POT_SCRATCH: Geometry = Geometry {
    speed: 3.0,
    tip: 0.45,
    ..KITCHEN_POT
};
/// A full hit up the table: the object ball reaches the top rail, nothing falls.
const HIT: Geometry = Geometry {
    cue: [0.635, 1.0],
    object: [0.635, 1.2],
    dir: [0.0, 1.0],
    speed: 2.0,
    tip: -0.3,
};
/// A touch so soft that nothing reaches a cushion.
const SOFT: Geometry = Geometry {
    speed: 0.3,
    tip: 0.0,
    ..HIT
};
/// Aimed away from the object ball.
const MISS: Geometry = Geometry {
    dir: [1.0, 0.0],
    speed: 1.0,
    tip: 0.0,
    ..HIT
};
/// A half-ball cut: the object ball goes to the top rail, the cue ball into the top-left
/// corner.
const CUT_SCRATCH: Geometry = Geometry {
    cue: [0.4, 1.8],
    object: [0.4 + 2.0 * R * S2 + 1e-6, 2.14 + 2.0 * R * S2 + 1e-6],
    dir: [0.0, 1.0],
    speed: 3.0,
    tip: -0.2,
};
/// Centre spacing of touching balls (with the rack gap), along a diagonal.
const DIAGONAL: f64 = (2.0 * R + 1e-6) * S2;
/// A combination: the cue ball hits the object ball, which drives the ball at
/// [`COMBO_SECOND`] into the top-left corner.
const COMBO: Geometry = Geometry {
    cue: [0.6, 1.94],
    object: [0.3 + DIAGONAL, 2.24 - DIAGONAL],
    dir: [-1.0, 1.0],
    speed: 2.0,
    tip: 0.0,
};
const COMBO_SECOND: [f64; 2] = [0.3, 2.24];
/// A soft touch from the kitchen (a break that reaches no cushion).
const KITCHEN_SOFT: Geometry = Geometry {
    cue: [0.635, 0.5],
    object: [0.635, 0.7],
    dir: [0.0, 1.0],
    speed: 0.3,
    tip: 0.0,
};

impl Geometry {
    fn strike(&self) -> Strike {
        Strike {
            speed: self.speed,
            dir: DVec2::from_array(self.dir).normalize(),
            tip: DVec2::new(0.0, self.tip),
            elevation_deg: 0.0,
        }
    }
}

/// Places for balls that take no part in a shot (the lower right, clear of every geometry).
fn parking(k: usize) -> [f64; 2] {
    [0.95 + 0.1 * (k % 3) as f64, 0.3 + 0.15 * (k / 3) as f64]
}

/// A game of `variant` with only the given balls on the table, `balls_parked` parked, Player
/// A to shoot, no ball in hand, past the break.
fn table(variant: Variant, balls: &[(u8, [f64; 2])], parked: &[u8]) -> Game {
    table_with(variant, Settings::offline(), balls, parked)
}

fn table_with(
    variant: Variant,
    settings: Settings,
    balls: &[(u8, [f64; 2])],
    parked: &[u8],
) -> Game {
    let mut g = Game::new(variant, settings, 1);
    for b in g.balls.iter_mut() {
        *b = off_table();
    }
    for &(n, p) in balls {
        g.balls[usize::from(n)] = BallState::at_rest(DVec2::from_array(p));
    }
    for (k, &n) in parked.iter().enumerate() {
        g.balls[usize::from(n)] = BallState::at_rest(DVec2::from_array(parking(k)));
    }
    g.breaking = false;
    g.phase = shooting(None);
    g
}

fn shooting(in_hand: Option<InHand>) -> Phase {
    Phase::Shooting {
        in_hand,
        options: Vec::new(),
        push_out: false,
    }
}

/// The table for `geo` with `object` as the object ball.
fn setup(variant: Variant, geo: Geometry, object: u8, parked: &[u8]) -> Game {
    table(variant, &[(0, geo.cue), (object, geo.object)], parked)
}

fn shot(geo: Geometry, call: Option<u8>) -> Command {
    Command::Shot {
        strike: geo.strike(),
        call,
    }
}

fn shoot(g: &mut Game, geo: Geometry, call: Option<u8>) -> Verdict {
    let seat = g.to_move();
    g.apply(seat, &shot(geo, call))
        .unwrap_or_else(|e| panic!("shot refused: {e}"))
}

/// Asserts that the game ended with `winner` for `why`.
fn assert_won(v: &Verdict, winner: Seat, why: &str) {
    assert_eq!(v.over, Some((Some(winner), why.to_string())));
}

/// Asserts that `seat` is to break a new rack.
fn assert_breaks(g: &Game, seat: Seat) {
    assert_eq!((g.to_move(), g.breaker(), g.is_break()), (seat, seat, true));
}

fn in_hand(g: &Game) -> Option<InHand> {
    match g.phase() {
        Phase::Shooting { in_hand, .. } => *in_hand,
        other => panic!("not shooting: {other:?}"),
    }
}

fn options(g: &Game) -> Vec<Choice> {
    match g.phase() {
        Phase::Deciding { options } | Phase::Shooting { options, .. } => options.clone(),
        Phase::Over { .. } => Vec::new(),
    }
}

fn pocketed(g: &Game, ball: u8) -> bool {
    g.balls()[usize::from(ball)].motion == MotionState::Pocketed
}

const WPA: Variant = Variant::EightBall(EightBallRules::Wpa);
const BAR: Variant = Variant::EightBall(EightBallRules::Bar);

fn all_but(used: &[u8]) -> Vec<u8> {
    (1..=15).filter(|x| !used.contains(x)).collect()
}

/// One clause of the 8-ball rules played on the table.
struct Case {
    name: &'static str,
    variant: Variant,
    group_a: Option<Group>,
    geo: Geometry,
    object: u8,
    /// Other balls in play, at given places.
    extra: Vec<(u8, [f64; 2])>,
    parked: Vec<u8>,
    call: Option<u8>,
    first_reason: &'static str,
    foul: bool,
    next: Seat,
    winner: Option<Option<Seat>>,
    in_hand: Option<InHand>,
}

fn case(name: &'static str, geo: Geometry, object: u8, first_reason: &'static str) -> Case {
    Case {
        name,
        variant: WPA,
        group_a: Some(Group::Solids),
        geo,
        object,
        extra: Vec::new(),
        parked: all_but(&[object]),
        call: None,
        first_reason,
        foul: false,
        next: Seat::A,
        winner: None,
        in_hand: None,
    }
}

impl Case {
    fn foul(self) -> Case {
        Case {
            foul: true,
            next: Seat::B,
            in_hand: Some(InHand::Anywhere),
            ..self
        }
    }
    fn passes(self) -> Case {
        Case {
            next: Seat::B,
            ..self
        }
    }
    fn ends(self, winner: Seat) -> Case {
        Case {
            winner: Some(Some(winner)),
            ..self
        }
    }
    fn run(&self) -> (Game, Verdict) {
        let mut balls = vec![(0, self.geo.cue), (self.object, self.geo.object)];
        balls.extend(self.extra.iter().copied());
        let mut g = table(self.variant, &balls, &self.parked);
        g.group_a = self.group_a;
        let v = shoot(&mut g, self.geo, self.call);
        let name = self.name;
        assert_eq!(
            v.reasons.first().map(String::as_str),
            Some(self.first_reason),
            "{name}: {v:?}"
        );
        assert_eq!(v.foul, self.foul, "{name}: foul");
        match self.winner {
            Some(w) => {
                assert_eq!(v.over.as_ref().map(|o| o.0), Some(w), "{name}: winner");
                assert!(matches!(g.phase(), Phase::Over { .. }), "{name}");
            }
            None => {
                assert!(v.over.is_none(), "{name}: over {:?}", v.over);
                assert_eq!(v.next, self.next, "{name}: next");
                assert_eq!(g.to_move(), self.next, "{name}: to move");
                assert_eq!(in_hand(&g), self.in_hand, "{name}: in hand");
            }
        }
        (g, v)
    }
}

#[test]
fn eight_ball_clauses() {
    let on_eight = all_but(&[1, 2, 3, 4, 5, 6, 7, 8]);
    let cases = vec![
        case("own ball pocketed: the turn continues", POT, 3, "Player A pocketed a ball and continues"),
        Case {
            extra: vec![(11, COMBO_SECOND)],
            parked: all_but(&[3, 11]),
            ..case("only an opponent's ball pocketed: the turn passes", COMBO, 3, "Player B to shoot").passes()
        },
        Case {
            group_a: None,
            ..case(
                "open table: the first ball pocketed after the break assigns the group",
                POT,
                11,
                "Player A takes the stripes (the 11 pocketed first)",
            )
        },
        case("wrong ball first: the 8 before a solid", HIT, 8, "Foul: wrong ball first - hit the 8 before a solid").foul(),
        case("wrong ball first: a stripe before a solid", HIT, 12, "Foul: wrong ball first - hit the 12 before a solid").foul(),
        Case {
            group_a: None,
            ..case("open table: the 8 may not be hit first", HIT, 8, "Foul: wrong ball first - hit the 8 before any ball but the 8").foul()
        },
        case("no ball contacted", MISS, 3, "Foul: the cue ball hit no ball").foul(),
        case("nothing pocketed and no ball to a cushion after contact", SOFT, 3, "Foul: no ball reached a cushion or a pocket after contact").foul(),
        case("cue ball pocketed", POT_SCRATCH, 3, "Foul: scratch - the cue ball was pocketed").foul(),
        // A legal combination (own ball first) that drives the 8 in early.
        Case {
            extra: vec![(8, COMBO_SECOND)],
            parked: all_but(&[3, 8]),
            call: Some(TOP_LEFT),
            ..case("the 8 pocketed before the group is cleared loses", COMBO, 3, "Player A loses: pocketed the 8 before clearing the solids").ends(Seat::B)
        },
        Case {
            group_a: None,
            extra: vec![(8, COMBO_SECOND)],
            parked: all_but(&[11, 8]),
            call: Some(TOP_LEFT),
            ..case("the 8 pocketed on an open table loses", COMBO, 11, "Player A loses: pocketed the 8 on an open table").ends(Seat::B)
        },
        Case {
            foul: true,
            call: Some(TOP_LEFT),
            ..case("the 8 hit first and pocketed early loses", POT, 8, "Player A loses: pocketed the 8 before clearing the solids").ends(Seat::B)
        },
        Case {
            parked: on_eight.clone(),
            call: Some(TOP_LEFT),
            ..case("the 8 in the called pocket after clearing the group wins", POT, 8, "Player A wins: the 8 in the called top-left corner").ends(Seat::A)
        },
        Case {
            parked: on_eight.clone(),
            call: Some(BOTTOM_LEFT),
            ..case("the 8 in an uncalled pocket loses", POT, 8, "Player A loses: the 8 fell in the top-left corner, not the called bottom-left corner").ends(Seat::B)
        },
        Case {
            foul: true,
            parked: on_eight.clone(),
            call: Some(TOP_LEFT),
            ..case("the 8 pocketed with a foul loses", POT_SCRATCH, 8, "Player A loses: pocketed the 8 on a foul").ends(Seat::B)
        },
        // The one difference between the rule sets on a normal shot.
        Case {
            parked: on_eight.clone(),
            call: Some(BOTTOM_LEFT),
            ..case("WPA: a scratch while shooting at the 8 is only a foul", CUT_SCRATCH, 8, "Foul: scratch - the cue ball was pocketed").foul()
        },
        Case {
            foul: true,
            variant: BAR,
            parked: on_eight.clone(),
            call: Some(BOTTOM_LEFT),
            ..case("bar: a scratch while shooting at the 8 loses", CUT_SCRATCH, 8, "Player A loses: scratched while shooting at the 8 (bar rules)").ends(Seat::B)
        },
    ];
    for c in &cases {
        c.run();
    }
}

#[test]
fn eight_ball_fouls_leave_pocketed_balls_down_and_groups_unassigned() {
    let (g, _) = case(
        "scratch",
        POT_SCRATCH,
        3,
        "Foul: scratch - the cue ball was pocketed",
    )
    .foul()
    .run();
    assert!(pocketed(&g, 3));
    let (g, _) = Case {
        group_a: None,
        ..case(
            "open-table scratch",
            POT_SCRATCH,
            3,
            "Foul: scratch - the cue ball was pocketed",
        )
        .foul()
    }
    .run();
    assert_eq!(g.group_of(Seat::A), None);
    assert!(pocketed(&g, 3));
}

#[test]
fn eight_ball_groups_follow_the_first_legal_pot() {
    let (g, _) = Case {
        group_a: None,
        ..case(
            "",
            POT,
            11,
            "Player A takes the stripes (the 11 pocketed first)",
        )
    }
    .run();
    assert_eq!(g.group_of(Seat::A), Some(Group::Stripes));
    assert_eq!(g.group_of(Seat::B), Some(Group::Solids));
}

#[test]
fn eight_must_be_called() {
    let mut g = setup(WPA, POT, 8, &all_but(&[1, 2, 3, 4, 5, 6, 7, 8]));
    g.group_a = Some(Group::Solids);
    let cmd = shot(POT, None);
    assert_eq!(
        g.check(Seat::A, &cmd),
        Err(RuleError::InvalidShot("call a pocket for the 8".into()))
    );
    assert_eq!(
        g.apply(Seat::A, &cmd),
        Err(RuleError::InvalidShot("call a pocket for the 8".into()))
    );
    let bad_pocket = shot(POT, Some(6));
    assert!(matches!(
        g.check(Seat::A, &bad_pocket),
        Err(RuleError::InvalidShot(_))
    ));
}

#[test]
fn called_shots_setting_needs_the_ball_in_the_called_pocket() {
    let settings = Settings {
        call_every_shot: true,
        ..Settings::offline()
    };
    let mk = || {
        let mut g = table_with(
            WPA,
            settings,
            &[(0, POT.cue), (3, POT.object)],
            &all_but(&[3]),
        );
        g.group_a = Some(Group::Solids);
        g
    };
    let g = mk();
    let uncalled = shot(POT, None);
    assert_eq!(
        g.check(Seat::A, &uncalled),
        Err(RuleError::InvalidShot(
            "this game requires a called pocket on every shot".into()
        ))
    );
    let mut g = mk();
    let v = shoot(&mut g, POT, Some(BOTTOM_LEFT));
    assert_eq!(v.reasons, vec!["Player B to shoot".to_string()]);
    assert!(!v.foul);
    assert_eq!(g.to_move(), Seat::B);
    let mut g = mk();
    let v = shoot(&mut g, POT, Some(TOP_LEFT));
    assert_eq!(
        v.reasons,
        vec!["Player A pocketed a ball and continues".to_string()]
    );
}

/// A break-shot table: only the given balls, Player A breaking from the kitchen.
fn break_table(variant: Variant, geo: Geometry, object: u8) -> Game {
    breaking(setup(variant, geo, object, &all_but(&[object])))
}

/// `g` with Player A to break from the kitchen.
fn breaking(mut g: Game) -> Game {
    g.breaking = true;
    g.phase = shooting(Some(InHand::Kitchen));
    g
}

/// The two answers `chooser` has to the 8 falling on the break: spot it and shoot on (with
/// the cue ball `in_hand`), or re-rack and break.
fn spot_or_rerack(g: &Game, chooser: Seat, spotted_in_hand: Option<InHand>) {
    let mut spotted = g.clone();
    spotted
        .apply(chooser, &Command::Decide(Choice::SpotEightAndContinue))
        .unwrap();
    assert_eq!(spotted.balls()[8].pos, rack::foot_spot(spotted.table()));
    assert_eq!(
        (spotted.to_move(), in_hand(&spotted)),
        (chooser, spotted_in_hand)
    );
    let mut reracked = g.clone();
    reracked
        .apply(chooser, &Command::Decide(Choice::Rerack))
        .unwrap();
    assert_breaks(&reracked, chooser);
}

#[test]
fn break_pocketing_a_ball_is_legal_and_assigns_no_group() {
    let mut g = break_table(WPA, KITCHEN_POT, 3);
    let v = shoot(&mut g, KITCHEN_POT, None);
    assert_eq!(
        v.reasons,
        vec!["Legal break: Player A pocketed a ball and continues; the table is open".to_string()]
    );
    assert!(!v.foul);
    assert_eq!(g.to_move(), Seat::A);
    assert_eq!(g.group_of(Seat::A), None);
    assert!(!g.is_break());
}

#[test]
fn break_must_be_taken_from_the_kitchen() {
    let mut g = break_table(WPA, KITCHEN_POT, 3);
    assert_eq!(
        g.legal_cue_placement([0.635, 0.64]),
        Err(RuleError::IllegalPlacement(
            "the cue ball must be behind the head string".into()
        ))
    );
    assert_eq!(g.legal_cue_placement([0.635, 0.6]), Ok(()));
    // A cue ball left outside the kitchen cannot break.
    g.balls[0] = BallState::at_rest(DVec2::new(0.635, 1.0));
    let cmd = shot(HIT, None);
    assert!(matches!(
        g.check(Seat::A, &cmd),
        Err(RuleError::IllegalPlacement(_))
    ));
}

#[test]
fn break_legality_counts_four_object_balls_to_a_cushion() {
    // The engine is not asked to drive exactly four balls to a rail: the count is what the
    // clause is about, so the facts are crafted.
    for (to_cushion, legal) in [(vec![1, 2, 3], false), (vec![1, 2, 3, 4], true)] {
        let mut g = Game::new(WPA, Settings::offline(), 5);
        let finals = g.balls.clone();
        let facts = ShotFacts {
            first_contact: Some(1),
            cushion_after_contact: true,
            object_balls_to_cushion: to_cushion.clone(),
            ..ShotFacts::default()
        };
        let v = g.judge_shot(Seat::A, None, finals, &facts, dummy_report());
        if legal {
            assert_eq!(
                v.reasons,
                vec!["Legal break: nothing pocketed; Player B shoots on an open table".to_string()]
            );
            assert_eq!(g.to_move(), Seat::B);
        } else {
            assert_eq!(v.reasons[0], "Illegal break: no ball pocketed and only 3 object balls reached a cushion (4 needed)");
            assert!(matches!(g.phase(), Phase::Deciding { .. }));
        }
    }
}

fn dummy_report() -> ShotReport {
    ShotReport {
        hash: 0,
        events: Vec::new(),
        pocketed: Vec::new(),
    }
}

#[test]
fn illegal_break_gives_the_opponent_three_choices() {
    let broken = || {
        let mut g = break_table(WPA, KITCHEN_SOFT, 3);
        let v = shoot(&mut g, KITCHEN_SOFT, None);
        assert_eq!(
            v.reasons[0],
            "Illegal break: no ball pocketed and only 0 object balls reached a cushion (4 needed)"
        );
        assert_eq!(g.to_move(), Seat::B);
        assert_eq!(
            options(&g),
            vec![
                Choice::AcceptTable,
                Choice::Rerack,
                Choice::OpponentRebreaks
            ]
        );
        // The offender cannot choose.
        assert_eq!(
            g.check(Seat::A, &Command::Decide(Choice::AcceptTable)),
            Err(RuleError::NotYourTurn)
        );
        g
    };
    let mut g = broken();
    let layout = g.balls.clone();
    g.apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .unwrap();
    assert_eq!(
        (g.to_move(), in_hand(&g), g.is_break()),
        (Seat::B, None, false)
    );
    assert_eq!(g.balls, layout);

    let mut g = broken();
    g.apply(Seat::B, &Command::Decide(Choice::Rerack)).unwrap();
    assert_breaks(&g, Seat::B);
    assert_eq!(
        g.balls
            .iter()
            .filter(|b| b.motion != MotionState::Pocketed)
            .count(),
        16
    );
    assert_eq!(in_hand(&g), Some(InHand::Kitchen));

    let mut g = broken();
    g.apply(Seat::B, &Command::Decide(Choice::OpponentRebreaks))
        .unwrap();
    assert_breaks(&g, Seat::A);
}

#[test]
fn scratch_on_a_legal_break_gives_ball_in_hand_behind_the_head_string() {
    let mut g = break_table(WPA, KITCHEN_POT_SCRATCH, 3);
    let v = shoot(&mut g, KITCHEN_POT_SCRATCH, None);
    assert_eq!(
        v.reasons,
        vec![
            "Foul: scratch - the cue ball was pocketed".to_string(),
            "Player B has the cue ball in hand behind the head string; the table is open"
                .to_string()
        ]
    );
    assert!(v.foul);
    assert_eq!((g.to_move(), in_hand(&g)), (Seat::B, Some(InHand::Kitchen)));
    assert!(pocketed(&g, 3) && g.group_of(Seat::B).is_none());
    // The cue ball must be placed, and only in the kitchen.
    let shot = shot(HIT, None);
    assert_eq!(
        g.check(Seat::B, &shot),
        Err(RuleError::WrongPhase("place the cue ball first".into()))
    );
    assert!(matches!(
        g.apply(Seat::B, &Command::PlaceCueBall { pos: [0.6, 1.0] }),
        Err(RuleError::IllegalPlacement(_))
    ));
    g.apply(Seat::B, &Command::PlaceCueBall { pos: [0.6, 0.3] })
        .unwrap();
    assert_eq!(g.balls()[0].pos, DVec2::new(0.6, 0.3));
    assert_eq!(g.check(Seat::B, &shot), Ok(()));
}

#[test]
fn eight_on_the_break_wpa_breaker_chooses_bar_wins() {
    let mut g = break_table(WPA, KITCHEN_POT, 8);
    let v = shoot(&mut g, KITCHEN_POT, None);
    assert_eq!(
        v.reasons,
        vec![
            "The 8 fell on the break: Player A chooses to spot it and continue, or to re-rack"
                .to_string()
        ]
    );
    assert_eq!(g.to_move(), Seat::A);
    assert_eq!(
        options(&g),
        vec![Choice::SpotEightAndContinue, Choice::Rerack]
    );
    spot_or_rerack(&g, Seat::A, None);

    // Bar rules: the 8 on the break wins.
    let mut g = break_table(BAR, KITCHEN_POT, 8);
    let v = shoot(&mut g, KITCHEN_POT, None);
    assert_won(
        &v,
        Seat::A,
        "Player A wins: the 8 fell on the break (bar rules)",
    );
}

#[test]
fn eight_on_the_break_with_a_scratch_wpa_opponent_chooses_bar_loses() {
    let mut g = break_table(WPA, KITCHEN_POT_SCRATCH, 8);
    let v = shoot(&mut g, KITCHEN_POT_SCRATCH, None);
    assert_eq!(
        v.reasons,
        vec![
            "Foul: scratch - the cue ball was pocketed".to_string(),
            "The 8 fell on the break with a foul: Player B chooses to spot it and take ball in hand behind the head string, or to re-rack".to_string()
        ]
    );
    assert_eq!(g.to_move(), Seat::B);
    spot_or_rerack(&g, Seat::B, Some(InHand::Kitchen));

    let mut g = break_table(BAR, KITCHEN_POT_SCRATCH, 8);
    let v = shoot(&mut g, KITCHEN_POT_SCRATCH, None);
    assert_won(
        &v,
        Seat::B,
        "Player A loses: scratched while pocketing the 8 on the break (bar rules)",
    );
}

#[test]
fn ball_in_hand_after_a_foul_goes_anywhere_free() {
    let (mut g, _) = case("", MISS, 3, "Foul: the cue ball hit no ball")
        .foul()
        .run();
    let object = HIT.object;
    let overlapping = [object[0] + R, object[1]];
    let into_the_cushion = [0.01, 1.0];
    for pos in [overlapping, [f64::NAN, 1.0], into_the_cushion] {
        assert!(
            matches!(
                g.apply(Seat::B, &Command::PlaceCueBall { pos }),
                Err(RuleError::IllegalPlacement(_))
            ),
            "{pos:?}"
        );
    }
    assert_eq!(
        g.apply(Seat::A, &Command::PlaceCueBall { pos: [0.635, 1.8] }),
        Err(RuleError::NotYourTurn)
    );
    g.apply(Seat::B, &Command::PlaceCueBall { pos: [0.635, 1.8] })
        .unwrap();
    assert_eq!(g.balls()[0].pos, DVec2::new(0.635, 1.8));
}

#[test]
fn stalemate_offered_by_both_reracks_with_the_same_breaker() {
    let mut g = Game::new(WPA, Settings::offline(), 9);
    let first_rack = g.balls.clone();
    let mut tmp = g.clone();
    // An offer lapses once a shot is played.
    tmp.apply(Seat::A, &Command::ProposeStalemate).unwrap();
    assert!(tmp.stalemate_offered(Seat::A));
    tmp.apply(
        Seat::A,
        &Command::Shot {
            strike: Strike {
                speed: 8.0,
                dir: DVec2::Y,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
            call: None,
        },
    )
    .unwrap();
    assert!(!tmp.stalemate_offered(Seat::A));

    g.group_a = Some(Group::Solids);
    g.breaking = false;
    g.to_move = Seat::B;
    let v = g.apply(Seat::A, &Command::ProposeStalemate).unwrap();
    assert_eq!(v.reasons, vec!["Player A offers a stalemate".to_string()]);
    assert_eq!(
        g.apply(Seat::A, &Command::ProposeStalemate),
        Err(RuleError::WrongPhase(
            "you have already offered a stalemate".into()
        ))
    );
    let v = g.apply(Seat::B, &Command::ProposeStalemate).unwrap();
    assert_eq!(
        v.reasons,
        vec!["Stalemate agreed by both players: re-rack, Player A breaks again".to_string()]
    );
    assert_eq!(
        (g.to_move(), g.breaker(), g.is_break(), g.group_of(Seat::A)),
        (Seat::A, Seat::A, true, None)
    );
    assert_eq!(g.balls.len(), 16);
    assert_ne!(g.balls, first_rack, "a re-rack is a new rack");
    assert_eq!(g.rack_number(), 1);
    assert_eq!(in_hand(&g), Some(InHand::Kitchen));
}

#[test]
fn shot_clock_expiry_is_a_foul() {
    let mut g = table_with(
        WPA,
        Settings::online(),
        &[(0, HIT.cue), (3, HIT.object)],
        &all_but(&[3]),
    );
    assert_eq!(g.settings().shot_clock, Some(60));
    assert_eq!(
        g.apply(Seat::B, &Command::TimeExpired),
        Err(RuleError::NotYourTurn)
    );
    let v = g.apply(Seat::A, &Command::TimeExpired).unwrap();
    assert_eq!(
        v.reasons,
        vec![
            "Foul: Player A ran out of time".to_string(),
            "Player B has ball in hand".to_string()
        ]
    );
    assert!(v.foul);
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere))
    );

    let mut offline = Game::new(WPA, Settings::offline(), 1);
    assert_eq!(
        offline.apply(Seat::A, &Command::TimeExpired),
        Err(RuleError::NotAllowed("this game has no shot clock".into()))
    );
}

#[test]
fn out_of_time_on_a_choice_takes_the_first_option() {
    let mut g = break_table(WPA, KITCHEN_SOFT, 3);
    g.settings = Settings::online();
    shoot(&mut g, KITCHEN_SOFT, None);
    assert_eq!(g.to_move(), Seat::B);
    let v = g.apply(Seat::B, &Command::TimeExpired).unwrap();
    assert_eq!(
        v.reasons,
        vec![
            "Player B ran out of time; the first option is taken".to_string(),
            "Player B chooses to accept the table".to_string()
        ]
    );
    assert!(!v.foul);
    assert_eq!(
        (g.to_move(), in_hand(&g), g.is_break()),
        (Seat::B, None, false)
    );
}

#[test]
fn out_of_time_before_the_break_gives_the_break_away() {
    let mut g = Game::new(NINE, Settings::online(), 3);
    let v = g.apply(Seat::A, &Command::TimeExpired).unwrap();
    assert_eq!(
        v.reasons,
        vec![
            "Foul: Player A ran out of time".to_string(),
            "Player B breaks".to_string()
        ]
    );
    assert_eq!(
        (g.to_move(), g.breaker(), g.is_break(), in_hand(&g)),
        (Seat::B, Seat::B, true, Some(InHand::Kitchen))
    );
}

#[test]
fn conceding_ends_the_game_and_nothing_is_accepted_after() {
    let mut g = Game::new(WPA, Settings::offline(), 1);
    let v = g.apply(Seat::B, &Command::Concede).unwrap();
    assert_won(&v, Seat::A, "Player B conceded; Player A wins");
    assert_eq!(
        g.apply(Seat::A, &Command::Concede),
        Err(RuleError::GameOver)
    );
}

#[test]
fn commands_out_of_turn_or_phase_change_nothing() {
    let mut g = Game::new(WPA, Settings::offline(), 1);
    let before = g.clone();
    let shot = shot(HIT, None);
    assert_eq!(g.apply(Seat::B, &shot), Err(RuleError::NotYourTurn));
    assert!(matches!(
        g.apply(Seat::A, &Command::Decide(Choice::Rerack)),
        Err(RuleError::InvalidChoice(_))
    ));
    assert!(matches!(
        g.apply(Seat::A, &Command::PlaceBall { ball: 3, pos: None }),
        Err(RuleError::NotAllowed(_))
    ));
    let bad = Command::Shot {
        strike: Strike {
            speed: f64::NAN,
            ..HIT.strike()
        },
        call: None,
    };
    assert!(matches!(
        g.apply(Seat::A, &bad),
        Err(RuleError::InvalidShot(_))
    ));
    assert_eq!(g, before);
}

// ---- 9-ball ----

const NINE: Variant = Variant::NineBall;

#[test]
fn nine_ball_break_must_hit_the_one_first() {
    let mut g = breaking(setup(NINE, KITCHEN_POT, 2, &[1, 3, 9]));
    let v = shoot(&mut g, KITCHEN_POT, None);
    assert_eq!(
        v.reasons[0],
        "Foul: wrong ball first - hit the 2 before the 1"
    );
    assert!(v.foul);
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere))
    );
    assert_eq!(
        options(&g),
        Vec::<Choice>::new(),
        "WPA 9-ball 2.4: a push-out is allowed only after a break without a foul"
    );
}

#[test]
fn nine_ball_push_out_after_the_break() {
    let broken = || {
        let mut g = breaking(setup(NINE, KITCHEN_POT, 1, &[2, 3, 9]));
        let v = shoot(&mut g, KITCHEN_POT, None);
        assert_eq!(
            v.reasons,
            vec!["Player A pocketed a ball and continues".to_string()]
        );
        assert_eq!(options(&g), vec![Choice::PushOut]);
        g
    };
    let mut g = broken();
    g.apply(Seat::A, &Command::Decide(Choice::PushOut)).unwrap();
    assert!(matches!(g.phase(), Phase::Shooting { push_out: true, .. }));
    // Hitting nothing is no foul on a push-out.
    let v = g.apply(Seat::A, &shot(MISS, None)).unwrap();
    assert_eq!(
        v.reasons,
        vec![
            "Player A pushed out".to_string(),
            "Player B chooses to shoot from here or hand the table back".to_string()
        ]
    );
    assert!(!v.foul);
    assert_eq!(
        (g.to_move(), options(&g)),
        (Seat::B, vec![Choice::AcceptTable, Choice::HandBack])
    );
    let mut back = g.clone();
    back.apply(Seat::B, &Command::Decide(Choice::HandBack))
        .unwrap();
    assert_eq!((back.to_move(), in_hand(&back)), (Seat::A, None));
    g.apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .unwrap();
    assert_eq!(g.to_move(), Seat::B);
    assert!(
        options(&g).is_empty(),
        "the push-out is only for the shot after the break"
    );

    // Not declaring a push-out: the same shot is a foul and the option lapses.
    let mut g = broken();
    let v = g.apply(Seat::A, &shot(MISS, None)).unwrap();
    assert_eq!(v.reasons[0], "Foul: the cue ball hit no ball");
    assert!(options(&g).is_empty());
    assert_eq!(
        g.apply(Seat::B, &Command::Decide(Choice::PushOut)),
        Err(RuleError::InvalidChoice("you cannot push out now".into()))
    );
}

#[test]
fn nine_ball_lowest_ball_first() {
    let mut g = setup(NINE, HIT, 3, &[2, 9]);
    assert_eq!(g.legal_first_balls(), vec![2]);
    let v = shoot(&mut g, HIT, None);
    assert_eq!(
        v.reasons[0],
        "Foul: wrong ball first - hit the 3 before the 2"
    );
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere))
    );
    assert_eq!(g.consecutive_fouls(Seat::A), 1);
}

#[test]
fn nine_ball_nine_on_any_legal_shot_wins() {
    // A combination: the cue ball hits the 2 (the lowest), the 2 drives the 9 in.
    let d = (2.0 * R + 1e-6) * S2;
    let geo = Geometry {
        speed: 2.0,
        tip: 0.0,
        ..POT
    };
    let mut g = table(
        NINE,
        &[(0, geo.cue), (2, [0.3 + d, 2.24 - d]), (9, geo.object)],
        &[3],
    );
    let v = shoot(&mut g, geo, None);
    assert_won(&v, Seat::A, "Player A wins: the 9 fell on a legal shot");
}

#[test]
fn nine_ball_nine_pocketed_on_a_foul_is_spotted() {
    // The 9 is hit first (a foul: the 2 is lowest) and falls: it comes back on the foot spot.
    let mut g = setup(NINE, POT, 9, &[2]);
    let v = shoot(&mut g, POT, None);
    assert_eq!(
        v.reasons,
        vec![
            "Foul: wrong ball first - hit the 9 before the 2".to_string(),
            "The 9 is spotted on the foot spot".to_string(),
            "Player B has ball in hand".to_string()
        ]
    );
    assert!(v.over.is_none());
    assert_eq!(g.balls()[9], BallState::at_rest(rack::foot_spot(g.table())));
}

#[test]
fn nine_ball_three_consecutive_fouls_lose() {
    let mut g = setup(NINE, MISS, 2, &[9]);
    let miss = shot(MISS, None);
    let mut last = None;
    for (k, seat) in [Seat::A, Seat::B, Seat::A, Seat::B, Seat::A]
        .into_iter()
        .enumerate()
    {
        // Ball in hand: put the cue ball back where the miss starts.
        if k > 0 {
            g.apply(seat, &Command::PlaceCueBall { pos: MISS.cue })
                .unwrap();
        }
        let v = g.apply(seat, &miss).unwrap();
        assert!(v.foul);
        if k == 2 {
            assert!(
                v.reasons.contains(
                    &"Warning: Player A is on two consecutive fouls; a third loses the game"
                        .to_string()
                ),
                "{v:?}"
            );
        }
        last = Some(v);
    }
    let v = last.unwrap();
    assert_won(
        &v,
        Seat::B,
        "Player A loses: 3 consecutive fouls; Player B wins",
    );
}

#[test]
fn nine_ball_a_legal_shot_clears_the_foul_count() {
    let mut g = setup(NINE, HIT, 2, &[9]);
    g.fouls = [2, 0];
    let v = shoot(&mut g, HIT, None);
    assert!(!v.foul, "{v:?}");
    assert_eq!(g.consecutive_fouls(Seat::A), 0);
}

#[test]
fn nine_ball_time_expired_counts_as_a_foul() {
    let mut g = table_with(
        NINE,
        Settings::online(),
        &[(0, HIT.cue), (2, HIT.object)],
        &[9],
    );
    g.fouls = [2, 0];
    let v = g.apply(Seat::A, &Command::TimeExpired).unwrap();
    assert_won(
        &v,
        Seat::B,
        "Player A loses: 3 consecutive fouls; Player B wins",
    );
}

// ---- practice ----

#[test]
fn practice_has_no_turns_and_no_fouls() {
    let mut g = setup(Variant::Practice, POT_SCRATCH, 3, &[]);
    let v = shoot(&mut g, POT_SCRATCH, None);
    assert!(!v.foul);
    assert_eq!(
        v.reasons,
        vec![
            "The 3 fell in the top-left corner".to_string(),
            "The cue ball fell in the top-left corner".to_string()
        ]
    );
    // Either seat may act; the cue ball goes anywhere free.
    g.apply(Seat::B, &Command::PlaceCueBall { pos: [0.635, 2.0] })
        .unwrap();
    let v = g.apply(Seat::B, &shot(MISS, None)).unwrap();
    assert!(!v.foul && v.over.is_none());
    assert_eq!(
        g.apply(Seat::A, &Command::ProposeStalemate),
        Err(RuleError::NotAllowed(
            "there is no stalemate in practice".into()
        ))
    );
    assert!(matches!(
        g.apply(Seat::A, &Command::TimeExpired),
        Err(RuleError::NotAllowed(_))
    ));
}

#[test]
fn practice_places_any_ball_freely() {
    let mut g = Game::new(Variant::Practice, Settings::offline(), 1);
    assert!(!g.is_break());
    g.apply(
        Seat::A,
        &Command::PlaceBall {
            ball: 5,
            pos: Some([0.3, 0.3]),
        },
    )
    .unwrap();
    assert_eq!(g.balls()[5], BallState::at_rest(DVec2::new(0.3, 0.3)));
    let overlapping = Command::PlaceBall {
        ball: 6,
        pos: Some([0.3 + R, 0.3]),
    };
    let no_such_ball = Command::PlaceBall {
        ball: 16,
        pos: None,
    };
    for cmd in [overlapping, no_such_ball] {
        assert!(
            matches!(g.apply(Seat::A, &cmd), Err(RuleError::IllegalPlacement(_))),
            "{cmd:?}"
        );
    }
    g.apply(Seat::A, &Command::PlaceBall { ball: 5, pos: None })
        .unwrap();
    assert!(pocketed(&g, 5));
}

/// Setting up a position works on every table a practice can be on: a ball moved to a free
/// spot, refused on another ball or off the cloth, taken off, put back, then played.
#[test]
fn practice_places_balls_on_the_carom_and_the_snooker_table_too() {
    for variant in [Variant::three_cushion(), Variant::snooker()] {
        let mut g = Game::practice_rack(variant, 1).expect("a practice table");
        let last = (g.balls().len() - 1) as u8;
        let cue = g.cue_ball() as u8;
        let object = if last == cue { 0 } else { last };
        let spot = [0.5, 1.0];
        let place = |ball, pos| Command::PlaceBall { ball, pos };
        g.apply(Seat::A, &place(object, Some(spot)))
            .unwrap_or_else(|e| panic!("{variant:?}: {e}"));
        assert_eq!(
            g.balls()[usize::from(object)],
            BallState::at_rest(DVec2::from(spot))
        );
        let r = g.params().ball_radius;
        for bad in [Some([0.5 + r, 1.0]), Some([-0.2, 1.0])] {
            let before = g.balls().to_vec();
            assert!(
                matches!(
                    g.apply(Seat::A, &place(cue, bad)),
                    Err(RuleError::IllegalPlacement(_))
                ),
                "{variant:?}: {bad:?}"
            );
            assert_eq!(g.balls(), before.as_slice(), "a refusal changes nothing");
        }
        g.apply(Seat::A, &place(object, None)).expect("taken off");
        assert!(pocketed(&g, object));
        g.apply(Seat::A, &place(object, Some(spot)))
            .expect("put back");
        // The cue ball played towards the ball placed (on the snooker table a baulk colour
        // may be in the way: any contact will do).
        let cue_pos = g.balls()[usize::from(cue)].pos;
        let strike = Strike {
            speed: 2.0,
            dir: (DVec2::from(spot) - cue_pos).normalize(),
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let v = g
            .apply(Seat::A, &Command::Shot { strike, call: None })
            .unwrap_or_else(|e| panic!("{variant:?}: {e}"));
        assert!(v.outcome.is_some(), "{variant:?}: the shot was simulated");
        assert_ne!(
            g.balls()[usize::from(cue)].pos,
            cue_pos,
            "{variant:?}: the cue ball moved"
        );
    }
}

#[test]
fn practice_loads_a_scene() {
    let scene = crate::scene::Scene::from_json(
        r#"{"table": "9ft", "balls": [
            {"id": "cue", "pos": [0.635, 0.6]},
            {"id": "1", "pos": [0.635, 1.9]},
            {"id": "8", "pos": [0.3, 2.0]}
        ]}"#,
    )
    .unwrap();
    let layout = layout_from_scene(&scene).unwrap();
    let mut g = Game::new(Variant::Practice, Settings::offline(), 1);
    g.apply(Seat::A, &Command::LoadLayout { balls: layout })
        .unwrap();
    let on: Vec<usize> = (0..16).filter(|&i| !pocketed(&g, i as u8)).collect();
    assert_eq!(on, vec![0, 1, 8]);
    assert_eq!(g.balls()[8].pos, DVec2::new(0.3, 2.0));

    let odd = crate::scene::Scene::from_json(r#"{"balls": [{"id": "ghost", "pos": [0.5, 0.5]}]}"#)
        .unwrap();
    assert_eq!(
        layout_from_scene(&odd),
        Err(RuleError::IllegalPlacement(
            "scene ball \"ghost\" is not a pool ball (use \"cue\" and \"1\" to \"15\")".into()
        ))
    );
    let wrong_len = Command::LoadLayout {
        balls: vec![None; 3],
    };
    let overlap = Command::LoadLayout {
        balls: (0..16).map(|_| Some([0.5, 0.5])).collect(),
    };
    for cmd in [wrong_len, overlap] {
        assert!(
            matches!(g.apply(Seat::A, &cmd), Err(RuleError::IllegalPlacement(_))),
            "{cmd:?}"
        );
    }
}

#[test]
fn turn_counts_every_applied_command() {
    let mut g = Game::new(Variant::Practice, Settings::offline(), 1);
    assert_eq!(g.turn(), 0);
    g.apply(Seat::A, &Command::PlaceCueBall { pos: [0.635, 0.3] })
        .unwrap();
    let _ = g.apply(
        Seat::A,
        &Command::PlaceCueBall {
            pos: [f64::NAN, 0.3],
        },
    );
    assert_eq!(g.turn(), 1);
}

mod wpa;

#[test]
fn a_preview_is_the_judgement_the_shot_gets_and_changes_nothing() {
    // 9-ball, the 3 on, the 5 hit first: the preview warns of the very foul the shot gets.
    let g = setup(Variant::NineBall, HIT, 5, &[3]);
    let before = g.clone();
    let preview = g
        .preview(Seat::A, &HIT.strike(), None)
        .expect("a legal stroke");
    assert_eq!(g, before);
    assert!(preview.foul);
    assert_eq!(
        preview.reasons[0],
        "Foul: wrong ball first - hit the 5 before the 3"
    );
    assert!(preview.outcome.is_some(), "the trajectory comes with it");
    let mut played = g.clone();
    let verdict = shoot(&mut played, HIT, None);
    assert_eq!(
        (verdict.foul, &verdict.reasons, verdict.shot.map(|s| s.hash)),
        (preview.foul, &preview.reasons, preview.shot.map(|s| s.hash))
    );
    // A shot the rules refuse is refused by the preview too.
    let wrong_seat = g.preview(Seat::B, &HIT.strike(), None);
    assert_eq!(wrong_seat.map(|v| v.foul), Err(RuleError::NotYourTurn));
}

#[test]
fn a_three_cushion_miss_previews_as_no_foul() {
    let g = Game::new(Variant::three_cushion(), Settings::offline(), 1);
    // Straight along the long axis, away from both object balls.
    let away = Strike::at_angle(0.5, 270.0, DVec2::ZERO);
    let preview = g.preview(Seat::A, &away, None).expect("a legal stroke");
    assert!(!preview.foul, "{:?}", preview.reasons);
}
