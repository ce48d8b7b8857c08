//! What the rules answer so that clients and bots need not re-derive it: whether a shot must
//! name a pocket, where the cue ball may go in hand, and the shot's trajectory.

use breakshot_shared::physics::Strike;
use breakshot_shared::rules::{
    is_off_table, rack, Command, EightBallRules, Game, InHand, RuleError, Seat, Settings, Variant,
};
use glam::DVec2;

fn break_strike(game: &Game) -> Strike {
    let cue = game.balls()[0].pos;
    let target = game.balls()[1].pos;
    Strike {
        speed: 9.0,
        dir: (target - cue).normalize(),
        tip: DVec2::ZERO,
        elevation_deg: 0.0,
    }
}

/// Plays shots until the game is past its break and a shot is due, or gives up.
fn past_the_break(mut game: Game) -> Game {
    let seat = game.to_move();
    let strike = break_strike(&game);
    game.apply(seat, &Command::Shot { strike, call: None })
        .expect("a legal break");
    game
}

#[test]
fn needs_call_agrees_with_the_check_in_every_variant() {
    let mut checked = 0;
    let called = Settings {
        call_every_shot: true,
        ..Settings::offline()
    };
    for (variant, settings, seed) in [
        (Variant::NineBall, called),
        (Variant::EightBall(EightBallRules::Wpa), called),
        (Variant::NineBall, Settings::offline()),
        (Variant::EightBall(EightBallRules::Wpa), Settings::offline()),
    ]
    .into_iter()
    .flat_map(|(v, s)| (0..20).map(move |seed| (v, s, seed)))
    {
        let game = Game::new(variant, settings, seed);
        assert!(!game.needs_call(), "{variant:?}: never on the break");
        let game = past_the_break(game);
        if !matches!(
            game.phase(),
            breakshot_shared::rules::Phase::Shooting { .. }
        ) {
            continue;
        }
        let strike = Strike {
            speed: 1.0,
            dir: DVec2::Y,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let seat = game.to_move();
        if game
            .check(
                seat,
                &Command::Shot {
                    strike,
                    call: Some(0),
                },
            )
            .is_err()
        {
            continue; // refused for another reason (the cue ball is in hand, say)
        }
        let refused = matches!(
            game.check(seat, &Command::Shot { strike, call: None }),
            Err(RuleError::InvalidShot(_))
        );
        assert_eq!(game.needs_call(), refused, "{variant:?} {settings:?}");
        if !game.is_break() {
            assert_eq!(game.needs_call(), settings.call_every_shot, "{variant:?}");
            checked += 1;
        }
    }
    assert!(checked >= 8, "too few games got past the break: {checked}");
}

#[test]
fn the_kitchen_is_behind_the_head_string_and_placement_agrees() {
    let game = Game::new(Variant::NineBall, Settings::offline(), 3);
    let (lo, hi) = game.in_hand_area(InHand::Kitchen);
    assert_eq!(lo, DVec2::ZERO);
    assert_eq!(hi.y, rack::head_string(game.table()));
    let x = 0.5 * hi.x;
    assert!(game.legal_cue_placement([x, hi.y - 0.1]).is_ok());
    assert!(game.legal_cue_placement([x, hi.y + 0.1]).is_err());
    let (_, all) = game.in_hand_area(InHand::Anywhere);
    assert_eq!((all.x, all.y), rack::table_size(game.table()));
    assert_eq!(game.params().ball_radius, rack::ball_radius());
}

#[test]
fn a_shot_s_verdict_carries_its_trajectory() {
    let mut game = Game::new(
        Variant::EightBall(EightBallRules::Wpa),
        Settings::offline(),
        5,
    );
    let strike = break_strike(&game);
    let seat = game.to_move();
    let verdict = game
        .apply(seat, &Command::Shot { strike, call: None })
        .expect("legal");
    let outcome = verdict.outcome.expect("a shot has a trajectory");
    assert_eq!(Some(outcome.hash()), verdict.shot.map(|s| s.hash));
    let fallen = outcome.finals.iter().filter(|b| is_off_table(b)).count();
    assert_eq!(
        fallen,
        game.balls().iter().filter(|b| is_off_table(b)).count(),
        "the rules table has the balls the trajectory pocketed"
    );
    let place = game.apply(Seat::A, &Command::Concede).expect("concede");
    assert!(place.outcome.is_none(), "only shots have trajectories");
}
