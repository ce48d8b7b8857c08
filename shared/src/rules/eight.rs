//! 8-ball: World Standardized Rules, and the `bar` variant.

use crate::physics::{BallState, MotionState};

use super::facts::{ShotFacts, CUE};
use super::kitchen::kitchen_foul;
use super::{
    ball_name, pocket_name, Choice, EightBallRules, Game, Group, InHand, Judged, Next, Pending,
    Seat,
};

const EIGHT: u8 = 8;
/// Object balls that must reach a cushion in a break that pockets nothing.
pub(super) const BREAK_CUSHION_BALLS: usize = 4;

fn on_table(balls: &[BallState], ball: u8) -> bool {
    balls
        .get(usize::from(ball))
        .is_some_and(|b| b.motion != MotionState::Pocketed)
}

fn cleared(balls: &[BallState], group: Group) -> bool {
    group.balls().all(|b| !on_table(balls, b))
}

fn shooting_at_eight(balls: &[BallState], group: Option<Group>) -> bool {
    group.is_some_and(|g| cleared(balls, g))
}

/// `seat` has cleared its group and shoots at the 8.
pub(super) fn on_eight(game: &Game, seat: Seat) -> bool {
    shooting_at_eight(&game.balls, game.group_of(seat))
}

/// Balls `seat` may hit first.
pub(super) fn legal_first_balls(game: &Game, seat: Seat) -> Vec<u8> {
    let group = game.group_of(seat);
    (1..=15u8)
        .filter(|&b| on_table(&game.balls, b))
        .filter(|&b| legal_first(b, group, shooting_at_eight(&game.balls, group)))
        .collect()
}

fn legal_first(ball: u8, group: Option<Group>, at_eight: bool) -> bool {
    match group {
        _ if at_eight => ball == EIGHT,
        // Open table: anything but the 8.
        None => ball != EIGHT,
        Some(g) => Group::of(ball) == Some(g),
    }
}

/// What the shooter had to hit first, for the reason text.
fn target_name(group: Option<Group>, at_eight: bool) -> String {
    match group {
        _ if at_eight => "the 8".into(),
        None => "any ball but the 8".into(),
        Some(g) => g.one().into(),
    }
}

fn scratch_reason(facts: &ShotFacts) -> String {
    if facts.off_table.contains(&CUE) {
        "Foul: the cue ball left the table".into()
    } else {
        "Foul: scratch - the cue ball was pocketed".into()
    }
}

fn over(winner: Seat, reason: String, mut reasons: Vec<String>, foul: bool) -> Judged {
    reasons.insert(0, reason.clone());
    Judged {
        reasons,
        foul,
        next: Next::Over {
            winner: Some(winner),
            reason,
        },
    }
}

/// The fouls a break can commit besides being illegal: a scratch (the cue ball pocketed or
/// off the table) and object balls driven off the table (WPA 8-ball 3.3: a foul; they stay
/// off, as the 8-ball rule on spotting balls says, except the 8, which is judged with the
/// 8 on the break).
fn break_fouls(facts: &ShotFacts) -> Vec<String> {
    let mut fouls = Vec::new();
    if facts.scratched() {
        fouls.push(scratch_reason(facts));
    }
    for b in facts.object_balls_off_table() {
        fouls.push(if b == EIGHT {
            "Foul: the 8 left the table".to_string()
        } else {
            format!("Foul: {} left the table (it stays off)", ball_name(b))
        });
    }
    fouls
}

fn judge_break(rules: EightBallRules, breaker: Seat, facts: &ShotFacts) -> Judged {
    let opponent = breaker.other();
    let scratched = facts.scratched();
    let fouls = break_fouls(facts);
    if facts.gone(EIGHT) {
        // The 8 is off the table until someone chooses to spot it.
        let eight_off = facts.off_table.contains(&EIGHT);
        return match rules {
            EightBallRules::Bar if eight_off => over(
                opponent,
                format!("{breaker} loses: drove the 8 off the table on the break (bar rules)"),
                fouls,
                true,
            ),
            EightBallRules::Bar if scratched => over(
                opponent,
                format!(
                    "{breaker} loses: scratched while pocketing the 8 on the break (bar rules)"
                ),
                fouls,
                true,
            ),
            EightBallRules::Bar => over(
                breaker,
                format!("{breaker} wins: the 8 fell on the break (bar rules)"),
                Vec::new(),
                false,
            ),
            // WPA 8-ball 3.3 (e): the breaker spots the 8 and continues, or re-breaks.
            EightBallRules::Wpa if fouls.is_empty() => Judged::offer(
                vec![format!(
                    "The 8 fell on the break: {breaker} chooses to spot it and continue, or to re-rack"
                )],
                false,
                breaker,
                vec![Choice::SpotEightAndContinue, Choice::Rerack],
                Pending::EightOnBreak { foul: false },
            ),
            // WPA 8-ball 3.3 (f): after a foul the opponent spots the 8 and takes the cue ball
            // in hand behind the head string, or re-racks and breaks. The 8 driven off the
            // table is a foul of its own (3.3) and is judged the same way.
            EightBallRules::Wpa => {
                let what = if eight_off {
                    "The 8 left the table on the break"
                } else {
                    "The 8 fell on the break with a foul"
                };
                let mut reasons = fouls;
                reasons.push(format!(
                    "{what}: {opponent} chooses to spot it and take ball in hand behind the head string, or to re-rack"
                ));
                Judged::offer(
                    reasons,
                    true,
                    opponent,
                    vec![Choice::SpotEightAndContinue, Choice::Rerack],
                    Pending::EightOnBreak { foul: true },
                )
            }
        };
    }
    // Balls that left the table count as driven to a rail (WPA 8.4).
    let to_cushion = facts.object_balls_to_cushion.len();
    let legal = facts.any_object_ball_pocketed() || to_cushion >= BREAK_CUSHION_BALLS;
    if !legal {
        let mut reasons = vec![format!(
            "Illegal break: no ball pocketed and only {to_cushion} object balls reached a cushion ({BREAK_CUSHION_BALLS} needed)"
        )];
        reasons.extend(fouls);
        reasons.push(format!(
            "{opponent} chooses to accept the table, re-rack and break, or have {breaker} break again"
        ));
        return Judged::offer(
            reasons,
            true,
            opponent,
            vec![
                Choice::AcceptTable,
                Choice::Rerack,
                Choice::OpponentRebreaks,
            ],
            Pending::IllegalBreak {
                offender: breaker,
                scratched,
            },
        );
    }
    if scratched {
        // WPA 8-ball: a scratch on a legal break gives the cue ball in hand behind the head
        // string.
        let mut reasons = fouls;
        reasons.push(format!(
            "{opponent} has the cue ball in hand behind the head string; the table is open"
        ));
        return Judged {
            reasons,
            foul: true,
            next: shoot(opponent, Some(InHand::Kitchen)),
        };
    }
    if !fouls.is_empty() {
        // WPA 3.3: an object ball off the table on the break; the incoming player accepts
        // the table in position or takes the cue ball in hand behind the head string.
        let mut reasons = fouls;
        reasons.push(format!(
            "{opponent} chooses to accept the table in position or take the cue ball in hand behind the head string; the table is open"
        ));
        return Judged::offer(
            reasons,
            true,
            opponent,
            vec![Choice::AcceptTable, Choice::CueBallInKitchen],
            Pending::JumpedOnBreak,
        );
    }
    if facts.any_object_ball_pocketed() {
        Judged {
            reasons: vec![format!(
                "Legal break: {breaker} pocketed a ball and continues; the table is open"
            )],
            foul: false,
            next: shoot(breaker, None),
        }
    } else {
        Judged {
            reasons: vec![format!(
                "Legal break: nothing pocketed; {opponent} shoots on an open table"
            )],
            foul: false,
            next: shoot(opponent, None),
        }
    }
}

fn shoot(seat: Seat, in_hand: Option<InHand>) -> Next {
    Next::Shoot {
        seat,
        in_hand,
        options: Vec::new(),
    }
}

/// Judges one 8-ball shot. `before` is the table before the shot; `game.balls` already holds
/// the balls at rest after it.
pub(super) fn judge(
    game: &mut Game,
    rules: EightBallRules,
    shooter: Seat,
    call: Option<u8>,
    facts: &ShotFacts,
    before: &[BallState],
) -> Judged {
    if game.breaking {
        return judge_break(rules, shooter, facts);
    }
    let opponent = shooter.other();
    let group = game.group_of(shooter);
    let at_eight = shooting_at_eight(before, group);
    let table = game.table();

    let mut fouls = Vec::new();
    if facts.scratched() {
        fouls.push(scratch_reason(facts));
    }
    if let Some(reason) = kitchen_foul(game, facts) {
        fouls.push(reason);
    }
    match facts.first_contact {
        None => fouls.push("Foul: the cue ball hit no ball".into()),
        Some(b) if !legal_first(b, group, at_eight) => fouls.push(format!(
            "Foul: wrong ball first - hit {} before {}",
            ball_name(b),
            target_name(group, at_eight)
        )),
        Some(_) => {}
    }
    if facts.no_cushion_after_contact() {
        fouls.push("Foul: no ball reached a cushion or a pocket after contact".into());
    }
    for &b in facts.off_table.iter().filter(|&&b| b != CUE && b != EIGHT) {
        fouls.push(format!(
            "Foul: {} left the table (it stays off)",
            ball_name(b)
        ));
    }
    let foul = !fouls.is_empty();

    if facts.off_table.contains(&EIGHT) {
        return over(
            opponent,
            format!("{shooter} loses: drove the 8 off the table"),
            fouls,
            foul,
        );
    }
    if let Some(pocket) = facts.pocket_of(EIGHT) {
        let lost = if !at_eight {
            Some(match group {
                None => "pocketed the 8 on an open table".to_string(),
                Some(g) => format!("pocketed the 8 before clearing the {g:?}").to_lowercase(),
            })
        } else if foul {
            Some("pocketed the 8 on a foul".to_string())
        } else if call != Some(pocket) {
            Some(match call {
                Some(c) => format!(
                    "the 8 fell in the {}, not the called {}",
                    pocket_name(table, pocket),
                    pocket_name(table, c)
                ),
                None => "the 8 fell in an uncalled pocket".to_string(),
            })
        } else {
            None
        };
        return match lost {
            Some(why) => over(opponent, format!("{shooter} loses: {why}"), fouls, foul),
            None => over(
                shooter,
                format!(
                    "{shooter} wins: the 8 in the called {}",
                    pocket_name(table, pocket)
                ),
                Vec::new(),
                false,
            ),
        };
    }
    if at_eight && facts.scratched() && rules == EightBallRules::Bar {
        return over(
            opponent,
            format!("{shooter} loses: scratched while shooting at the 8 (bar rules)"),
            fouls,
            true,
        );
    }
    if foul {
        fouls.push(format!("{opponent} has ball in hand"));
        return Judged {
            reasons: fouls,
            foul: true,
            next: shoot(opponent, Some(InHand::Anywhere)),
        };
    }

    // A legal shot. With called shots only balls in the called pocket count for the shooter.
    let counts = |p: u8| !game.settings.call_every_shot || call == Some(p);
    let mut reasons = Vec::new();
    let mut group = group;
    if group.is_none() {
        let first = facts
            .pocketed
            .iter()
            .find(|&&(b, p)| Group::of(b).is_some() && counts(p));
        if let Some(&(b, _)) = first {
            let g = Group::of(b).unwrap_or(Group::Solids);
            game.group_a = Some(if shooter == Seat::A { g } else { g.other() });
            group = Some(g);
            reasons.push(format!(
                "{shooter} takes the {} ({} pocketed first)",
                format!("{g:?}").to_lowercase(),
                ball_name(b)
            ));
        }
    }
    let scored = group.is_some_and(|g| {
        facts
            .pocketed
            .iter()
            .any(|&(b, p)| Group::of(b) == Some(g) && counts(p))
    });
    if scored {
        reasons.push(format!("{shooter} pocketed a ball and continues"));
        Judged {
            reasons,
            foul: false,
            next: shoot(shooter, None),
        }
    } else {
        reasons.push(format!("{opponent} to shoot"));
        Judged {
            reasons,
            foul: false,
            next: shoot(opponent, None),
        }
    }
}
