//! The clauses where the rules once differed from the WPA text, and the clauses about balls
//! that leave the table. Each assertion names its clause. The engine cannot yet lift a ball,
//! so departures are handed to [`ShotFacts::read`] with a simulated outcome, the way the
//! physics will report them.

use super::*;
use crate::physics::{ball_cushion, simulate, BallState, Params, Shot, TableKind};
use facts::Departure;

fn contact() -> f64 {
    ball_cushion::contact_distance(&Params::default())
}

fn length() -> f64 {
    rack::table_size(TableKind::NineFoot).1
}

/// Simulates `strike` from the current table of `g` and reads the facts, with `left`
/// reported as having left the table.
fn facts_with(g: &Game, strike: &Strike, left: &[Departure]) -> (Vec<BallState>, ShotFacts) {
    let outcome = simulate(&g.shot_for(strike)).expect("a valid shot");
    let facts = ShotFacts::read(&outcome, g.table(), left);
    (outcome.finals, facts)
}

/// Player A's shot `strike` from the current table of `g`, nothing called, judged with
/// `left` reported as having left the table.
fn judged_with(g: &mut Game, strike: &Strike, left: &[Departure]) -> Verdict {
    let (finals, facts) = facts_with(g, strike, left);
    g.judge_shot(Seat::A, None, finals, &facts, dummy_report())
}

fn gone(ball: u8, t: f64) -> Departure {
    Departure { ball, t }
}

// ---- the three deviations ----

#[test]
fn wpa_nine_ball_no_push_out_after_a_scratch_or_an_illegal_break() {
    // A scratch on the break.
    let mut g = breaking(setup(NINE, KITCHEN_POT_SCRATCH, 1, &[2, 3, 9]));
    let v = shoot(&mut g, KITCHEN_POT_SCRATCH, None);
    assert!(v.foul, "{v:?}");
    assert_eq!(
        (g.to_move(), in_hand(&g), options(&g)),
        (Seat::B, Some(InHand::Anywhere), Vec::new()),
        "WPA 9-ball 2.4: no push-out after a foul on the break (a scratch)"
    );
    // An illegal break: the 1 hit softly, nothing reaches a cushion.
    let mut g = breaking(setup(NINE, KITCHEN_SOFT, 1, &[2, 3, 9]));
    let v = shoot(&mut g, KITCHEN_SOFT, None);
    assert!(v.reasons[0].starts_with("Foul: illegal break"), "{v:?}");
    assert_eq!(
        options(&g),
        Vec::<Choice>::new(),
        "WPA 9-ball 2.3/2.4: an illegal break is a foul, and no push-out follows it"
    );
}

#[test]
fn wpa_kitchen_shot_at_a_ball_behind_the_head_string_is_a_foul() {
    // The break scratches; the incoming player places the cue ball in the kitchen and
    // shoots straight at a ball that is also behind the head string.
    let mut g = break_table(WPA, KITCHEN_POT_SCRATCH, 3);
    shoot(&mut g, KITCHEN_POT_SCRATCH, None);
    assert_eq!((g.to_move(), in_hand(&g)), (Seat::B, Some(InHand::Kitchen)));
    let target = g.balls()[1].pos;
    assert!(
        target.y < rack::head_string(g.table()),
        "the 1 is parked in the kitchen"
    );
    g.apply(
        Seat::B,
        &Command::PlaceCueBall {
            pos: [target.x, target.y - 0.15],
        },
    )
    .unwrap();
    let strike = Strike {
        speed: 1.5,
        dir: DVec2::Y,
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    };
    let v = g
        .apply(Seat::B, &Command::Shot { strike, call: None })
        .unwrap();
    assert_eq!(
        v.reasons[0],
        "Foul: from behind the head string, the cue ball hit the 1 behind it without first crossing it",
        "WPA 6.11 with 1.5: from the kitchen, a ball behind the head string may be hit first only after the cue ball crosses it"
    );
    assert!(v.foul);
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::A, Some(InHand::Anywhere))
    );
}

#[test]
fn wpa_kitchen_shot_that_crosses_the_head_string_first_may_hit_a_ball_behind_it() {
    let cue = [0.3, 0.45];
    let strike = Strike {
        speed: 3.0,
        dir: DVec2::new(0.15, 1.0).normalize(),
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    };
    // Where the cue ball comes back down the table past y = 0.3, after the foot rail: the
    // object ball goes there (the way up is far from it).
    let alone = table(WPA, &[(0, cue)], &[]);
    let outcome = simulate(&alone.shot_for(&strike)).unwrap();
    let back = (1..)
        .map(|k| outcome.state_at(0, f64::from(k) * 1e-3))
        .scan(false, |crossed, s| {
            *crossed |= s.pos.y > rack::head_string(TableKind::NineFoot);
            Some((*crossed, s))
        })
        .take(20_000)
        .find(|(crossed, s)| *crossed && s.vel.y < 0.0 && s.pos.y <= 0.3)
        .map(|(_, s)| s.pos)
        .expect("the cue ball comes back into the kitchen");
    let mut g = table(WPA, &[(0, cue), (3, back.to_array())], &[]);
    g.phase = shooting(Some(InHand::Kitchen));
    let v = g
        .apply(Seat::A, &Command::Shot { strike, call: None })
        .unwrap();
    let first = v.shot.as_ref().and_then(|r| {
        r.events.iter().find_map(|e| match e.kind {
            crate::physics::EventKind::BallBall { a: 0, b } => Some(b),
            _ => None,
        })
    });
    assert_eq!(first, Some(3), "the cue ball hits the 3 first: {v:?}");
    assert!(
        !v.reasons.iter().any(|r| r.contains("head string")),
        "WPA 6.11: a cue ball that crossed the head string may come back and hit a ball behind it: {v:?}"
    );
}

#[test]
fn wpa_spot_on_request_when_every_legal_ball_is_behind_the_head_string() {
    // A legal break that scratches, leaving the only legal balls (the 3 and the 11) in the
    // kitchen: the incoming player may have the one nearest the head string spotted.
    let mut g = breaking(table(
        WPA,
        &[
            (0, [0.635, 0.3]),
            (3, [0.4, 0.55]),
            (11, [0.9, 0.35]),
            (8, [0.635, 2.0]),
        ],
        &[],
    ));
    let mut finals = g.balls.clone();
    finals[0] = off_table();
    let facts = ShotFacts {
        first_contact: Some(8),
        cushion_after_contact: true,
        object_balls_to_cushion: vec![3, 11, 8, 12],
        pocketed: vec![(0, 0)],
        ..ShotFacts::default()
    };
    g.judge_shot(Seat::A, None, finals, &facts, dummy_report());
    assert_eq!(in_hand(&g), Some(InHand::Kitchen));
    assert_eq!(
        options(&g),
        vec![Choice::SpotNearestBall],
        "WPA 1.5: every legal ball is behind the head string, so the nearest may be spotted"
    );
    let v = g
        .apply(Seat::B, &Command::Decide(Choice::SpotNearestBall))
        .unwrap();
    assert_eq!(
        v.reasons,
        vec![
            "Player B chooses to have the ball nearest the head string spotted".to_string(),
            "The 3 is spotted on the foot spot".to_string()
        ],
        "WPA 1.5: the legal ball nearest the head string is spotted (1.4)"
    );
    assert_eq!(g.balls()[3].pos, rack::foot_spot(g.table()));
    assert_eq!(
        (g.to_move(), in_hand(&g), options(&g)),
        (Seat::B, Some(InHand::Kitchen), Vec::new()),
        "WPA 1.5: with a legal ball past the head string there is nothing more to spot"
    );
}

#[test]
fn wpa_a_ball_frozen_to_a_rail_pressed_into_it_is_not_driven_to_it() {
    // The 3 frozen to the foot rail, hit softly straight into it with draw.
    let frozen = [0.635, length() - contact()];
    let cue = [0.635, frozen[1] - 0.3];
    let strike = Strike {
        speed: 0.5,
        dir: DVec2::Y,
        tip: DVec2::new(0.0, -0.3),
        elevation_deg: 0.0,
    };
    let mk = |object: [f64; 2]| {
        let mut g = table(WPA, &[(0, cue), (3, object)], &all_but(&[3]));
        g.group_a = Some(Group::Solids);
        g
    };
    let g = mk(frozen);
    let (_, facts) = facts_with(&g, &strike, &[]);
    assert_eq!(facts.first_contact, Some(3));
    assert!(
        facts.object_balls_to_cushion.is_empty() && !facts.cushion_after_contact,
        "WPA 8.4: a frozen ball pressed into its rail is not driven to it (nor counted toward a break's four): {facts:?}"
    );
    let mut g = mk(frozen);
    let v = g
        .apply(Seat::A, &Command::Shot { strike, call: None })
        .unwrap();
    assert_eq!(
        v.reasons[0], "Foul: no ball reached a cushion or a pocket after contact",
        "WPA 6.3 with 8.4: no ball was driven to a rail"
    );
    // The same shot with the 3 a centimetre off the rail drives it there: no foul.
    let mut g = mk([frozen[0], frozen[1] - 0.01]);
    let v = g
        .apply(Seat::A, &Command::Shot { strike, call: None })
        .unwrap();
    assert!(
        !v.foul,
        "WPA 8.4: a ball not touching the rail and then touching it is driven to it: {v:?}"
    );
}

// ---- balls that leave the table ----

/// A table past the break: Player A on the solids, hitting the 3 up the table.
fn eight_ball_hit() -> Game {
    let mut g = table(WPA, &[(0, HIT.cue), (3, HIT.object)], &all_but(&[3]));
    g.group_a = Some(Group::Solids);
    g
}

#[test]
fn wpa_jumped_object_ball_is_a_foul_and_stays_off() {
    let mut g = eight_ball_hit();
    let v = judged_with(&mut g, &HIT.strike(), &[gone(12, 0.5)]);
    assert_eq!(
        v.reasons[0], "Foul: the 12 left the table (it stays off)",
        "WPA 6.5, 8-ball: a ball driven off the table is a foul; only the 8 is ever spotted"
    );
    assert!(v.foul && pocketed(&g, 12) && g.balls()[12].pocket.is_none());
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere)),
        "WPA 8-ball: ball in hand after a foul"
    );

    let mut g = table(NINE, &[(0, HIT.cue), (2, HIT.object)], &[5, 9]);
    let v = judged_with(&mut g, &HIT.strike(), &[gone(5, 0.5)]);
    assert_eq!(
        v.reasons[0], "Foul: the 5 left the table (it stays off)",
        "WPA 6.5, 9-ball: a ball driven off the table is a foul; only the 9 is ever spotted"
    );
    assert!(pocketed(&g, 5));
}

#[test]
fn wpa_nine_jumped_off_the_table_is_spotted() {
    let mut g = table(NINE, &[(0, HIT.cue), (2, HIT.object)], &[9]);
    let v = judged_with(&mut g, &HIT.strike(), &[gone(9, 0.5)]);
    assert_eq!(
        v.reasons,
        vec![
            "Foul: the 9 left the table".to_string(),
            "The 9 is spotted on the foot spot".to_string(),
            "Player B has ball in hand".to_string()
        ],
        "WPA 9-ball: the 9 driven off the table is a foul and is spotted (1.4)"
    );
    assert_eq!(g.balls()[9], BallState::at_rest(rack::foot_spot(g.table())));
}

#[test]
fn wpa_eight_jumped_off_the_table_loses_except_on_the_break() {
    let mut g = eight_ball_hit();
    let v = judged_with(&mut g, &HIT.strike(), &[gone(8, 0.5)]);
    assert_eq!(
        v.over,
        Some((
            Some(Seat::B),
            "Player A loses: drove the 8 off the table".into()
        )),
        "WPA 8-ball: driving the 8 off the table loses the rack"
    );
}

#[test]
fn wpa_eight_jumped_on_the_break_opponent_spots_it_or_reracks() {
    let broken = |variant| {
        let mut g = break_table(variant, KITCHEN_POT, 3);
        g.balls[8] = BallState::at_rest(DVec2::new(0.9, 1.8));
        let v = judged_with(&mut g, &KITCHEN_POT.strike(), &[gone(8, 0.5)]);
        (g, v)
    };
    let (g, v) = broken(WPA);
    assert_eq!(
        v.reasons,
        vec![
            "Foul: the 8 left the table".to_string(),
            "The 8 left the table on the break: Player B chooses to spot it and take ball in hand behind the head string, or to re-rack".to_string()
        ],
        "WPA 8-ball 3.3: an object ball off the table on the break is a foul; the 8 is spotted or the balls re-racked"
    );
    assert_eq!(
        (g.to_move(), options(&g)),
        (Seat::B, vec![Choice::SpotEightAndContinue, Choice::Rerack])
    );
    let mut spotted = g.clone();
    let v = spotted
        .apply(Seat::B, &Command::Decide(Choice::SpotEightAndContinue))
        .unwrap();
    assert_eq!(v.reasons[1], "The 8 is spotted on the foot spot");
    assert_eq!(
        (spotted.to_move(), in_hand(&spotted)),
        (Seat::B, Some(InHand::Kitchen)),
        "WPA 8-ball 3.3 (f): the 8 spotted after a break foul, ball in hand behind the head string"
    );

    let (g, v) = broken(BAR);
    assert_eq!(
        v.over,
        Some((
            Some(Seat::B),
            "Player A loses: drove the 8 off the table on the break (bar rules)".into()
        )),
        "bar rules: the 8 off the table loses, on the break too"
    );
    assert!(matches!(g.phase(), Phase::Over { .. }));
}

#[test]
fn wpa_object_ball_jumped_on_a_legal_break_accept_in_position_or_kitchen() {
    let broken = || {
        let mut g = break_table(WPA, KITCHEN_POT, 3);
        let v = judged_with(&mut g, &KITCHEN_POT.strike(), &[gone(12, 0.5)]);
        (g, v)
    };
    let (g, v) = broken();
    assert_eq!(
        v.reasons,
        vec![
            "Foul: the 12 left the table (it stays off)".to_string(),
            "Player B chooses to accept the table in position or take the cue ball in hand behind the head string; the table is open".to_string()
        ],
        "WPA 8-ball 3.3: an object ball off the table on the break is a foul"
    );
    assert_eq!(
        options(&g),
        vec![Choice::AcceptTable, Choice::CueBallInKitchen],
        "WPA 8-ball 3.3: the incoming player accepts the table in position or takes the cue ball behind the head string"
    );
    let mut accepted = g.clone();
    accepted
        .apply(Seat::B, &Command::Decide(Choice::AcceptTable))
        .unwrap();
    assert_eq!((accepted.to_move(), in_hand(&accepted)), (Seat::B, None));
    let mut kitchen = g;
    kitchen
        .apply(Seat::B, &Command::Decide(Choice::CueBallInKitchen))
        .unwrap();
    assert_eq!(
        (kitchen.to_move(), in_hand(&kitchen)),
        (Seat::B, Some(InHand::Kitchen))
    );
}

#[test]
fn wpa_cue_ball_off_the_table_gives_ball_in_hand() {
    let mut g = eight_ball_hit();
    let v = judged_with(&mut g, &HIT.strike(), &[gone(0, 0.5)]);
    assert_eq!(v.reasons[0], "Foul: the cue ball left the table");
    assert!(pocketed(&g, 0));
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere)),
        "WPA 6.1: the cue ball off the table is a foul; ball in hand anywhere"
    );

    let mut g = break_table(WPA, KITCHEN_POT, 3);
    let v = judged_with(&mut g, &KITCHEN_POT.strike(), &[gone(0, 0.5)]);
    assert_eq!(v.reasons[0], "Foul: the cue ball left the table");
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Kitchen)),
        "WPA 8-ball 3.3 and scratch on a legal break: the cue ball off the table on a legal break gives ball in hand behind the head string"
    );

    let mut g = table(NINE, &[(0, HIT.cue), (2, HIT.object)], &[9]);
    judged_with(&mut g, &HIT.strike(), &[gone(0, 0.5)]);
    assert_eq!(
        (g.to_move(), in_hand(&g)),
        (Seat::B, Some(InHand::Anywhere)),
        "WPA 9-ball: after any foul, ball in hand anywhere"
    );
}

#[test]
fn wpa_balls_off_the_table_count_as_driven_to_a_rail() {
    // A break so soft that nothing reaches a cushion, but four balls leave the table.
    let mut g = break_table(WPA, KITCHEN_SOFT, 3);
    let left: Vec<Departure> = [1, 2, 4, 5].iter().map(|&b| gone(b, 2.0)).collect();
    let (finals, facts) = facts_with(&g, &KITCHEN_SOFT.strike(), &left);
    assert_eq!(
        facts.object_balls_to_cushion,
        vec![1, 2, 4, 5],
        "WPA 8.4: a ball driven off the table was driven to a rail"
    );
    let v = g.judge_shot(Seat::A, None, finals, &facts, dummy_report());
    assert!(
        !v.reasons[0].starts_with("Illegal break"),
        "WPA 8-ball 3.3 with 8.4: four balls off the table make the break legal: {v:?}"
    );
    assert_eq!(
        options(&g),
        vec![Choice::AcceptTable, Choice::CueBallInKitchen]
    );

    // After the first contact, a departure is a rail after contact; before it, it is not.
    let g = eight_ball_hit();
    let (_, soft) = facts_with(&g, &SOFT.strike(), &[]);
    assert!(soft.no_cushion_after_contact());
    let (_, late) = facts_with(&g, &SOFT.strike(), &[gone(5, 5.0)]);
    assert!(
        late.cushion_after_contact,
        "WPA 8.4: a ball off the table after the contact was driven to a rail"
    );
    let (_, early) = facts_with(&g, &SOFT.strike(), &[gone(5, 0.01)]);
    assert!(
        !early.cushion_after_contact,
        "a departure before the first contact is not a rail after contact"
    );
}

#[test]
fn a_level_shot_reports_no_departure_and_a_jump_over_the_rail_reports_one() {
    let g = eight_ball_hit();
    let outcome = simulate(&g.shot_for(&HIT.strike())).unwrap();
    assert!(facts::departures(&outcome).is_empty());
    assert_eq!(
        ShotFacts::from_outcome(&outcome, g.table()),
        ShotFacts::read(&outcome, g.table(), &[])
    );
    // The cue ball jumped over the foot rail by a steep, hard stroke: the physics says it
    // left, and the rules read it as gone (WPA 8.5, driven off the table).
    let (_, length) = TableKind::NineFoot.size().expect("pocket table");
    let jump = Strike::at_angle(4.0, 90.0, DVec2::ZERO).elevated(45.0);
    let cue = BallState::at_rest(DVec2::new(0.635, length - 0.3));
    let shot = Shot::new(TableKind::NineFoot, vec![cue]).struck(0, jump);
    let outcome = simulate(&shot).unwrap();
    let left = facts::departures(&outcome);
    assert_eq!(
        left.len(),
        1,
        "the jumped cue ball left the table (WPA 8.5): {left:?}"
    );
    assert_eq!(left[0].ball, 0);
    assert!(ShotFacts::from_outcome(&outcome, TableKind::NineFoot).scratched());
}

#[test]
fn spotting_always_finds_a_place() {
    let kind = TableKind::NineFoot;
    let foot = rack::foot_spot(kind);
    let d = 2.0 * rack::ball_radius() + rack::RACK_GAP;
    let (_, l) = rack::table_size(kind);
    // Balls all along the long string, from the head rail to the foot rail.
    let string: Vec<BallState> = (0..)
        .map(|k| contact() + d * f64::from(k))
        .take_while(|&y| y <= l - contact())
        .map(|y| BallState::at_rest(DVec2::new(foot.x, y)))
        .collect();
    let full_behind: Vec<BallState> = std::iter::once(off_table())
        .chain(
            string
                .iter()
                .copied()
                .filter(|b| b.pos.y >= foot.y - 0.5 * d),
        )
        .collect();
    let mut balls = full_behind;
    assert_eq!(
        rack::spot(&mut balls, 0, kind),
        rack::Spotted::InFrontOfFootSpot,
        "WPA 1.4: with the string behind the foot spot full, the ball goes in front of it"
    );
    assert_eq!(balls[0].pos.x, foot.x);
    assert!(balls[0].pos.y < foot.y);
    assert!(rack::is_free(&balls, 0, balls[0].pos, kind));

    let mut balls: Vec<BallState> = std::iter::once(off_table()).chain(string).collect();
    assert_eq!(
        rack::spot(&mut balls, 0, kind),
        rack::Spotted::NearFootSpot,
        "with the whole string full, spotting still finds a place"
    );
    assert_ne!(balls[0].pos.x, foot.x);
    assert!(rack::is_free(&balls, 0, balls[0].pos, kind));
    assert!((balls[0].pos - foot).length() < 3.0 * d);
}
