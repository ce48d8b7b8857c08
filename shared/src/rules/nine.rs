//! 9-ball (World Standardized Rules).

use crate::physics::{BallState, MotionState};

use super::eight::BREAK_CUSHION_BALLS;
use super::facts::{ShotFacts, CUE};
use super::kitchen::kitchen_foul;
use super::{ball_name, pocket_name, rack, Choice, Game, InHand, Judged, Next, Pending, Seat};

const NINE: u8 = 9;
/// Consecutive fouls that lose the game.
pub(super) const FOULS_TO_LOSE: u8 = 3;

/// The lowest-numbered object ball on the table.
pub(super) fn lowest_ball(balls: &[BallState]) -> Option<u8> {
    (1..=NINE).find(|&b| {
        balls
            .get(usize::from(b))
            .is_some_and(|s| s.motion != MotionState::Pocketed)
    })
}

/// Counts a foul by `seat`; returns the end of the game on the third in a row.
pub(super) fn count_foul(game: &mut Game, seat: Seat, reasons: &mut Vec<String>) -> Option<Next> {
    let count = &mut game.fouls[seat.index()];
    *count = count.saturating_add(1);
    match *count {
        n if n >= FOULS_TO_LOSE => {
            let reason = format!(
                "{seat} loses: {FOULS_TO_LOSE} consecutive fouls; {} wins",
                seat.other()
            );
            reasons.insert(0, reason.clone());
            Some(Next::Over {
                winner: Some(seat.other()),
                reason,
            })
        }
        2 => {
            reasons.push(format!(
                "Warning: {seat} is on two consecutive fouls; a third loses the game"
            ));
            None
        }
        _ => None,
    }
}

/// Judges one 9-ball shot. `before` is the table before the shot; `game.balls` already holds
/// the balls at rest after it.
pub(super) fn judge(
    game: &mut Game,
    shooter: Seat,
    call: Option<u8>,
    facts: &ShotFacts,
    before: &[BallState],
    push_out: bool,
) -> Judged {
    let opponent = shooter.other();
    let breaking = game.breaking;
    let lowest = lowest_ball(before);
    let table = game.table();
    let mut fouls = Vec::new();
    if facts.scratched() {
        if facts.off_table.contains(&CUE) {
            fouls.push("Foul: the cue ball left the table".to_string());
        } else {
            fouls.push("Foul: scratch - the cue ball was pocketed".to_string());
        }
    }
    if let Some(reason) = kitchen_foul(game, facts) {
        fouls.push(reason);
    }
    // A push-out need not hit anything or reach a cushion.
    if !push_out {
        match (facts.first_contact, lowest) {
            (None, _) => fouls.push("Foul: the cue ball hit no ball".into()),
            (Some(b), Some(low)) if b != low => fouls.push(format!(
                "Foul: wrong ball first - hit {} before {}",
                ball_name(b),
                ball_name(low)
            )),
            _ => {}
        }
        let to_cushion = facts.object_balls_to_cushion.len();
        if breaking {
            if !facts.any_object_ball_pocketed() && to_cushion < BREAK_CUSHION_BALLS {
                fouls.push(format!(
                    "Foul: illegal break - no ball pocketed and only {to_cushion} object balls reached a cushion ({BREAK_CUSHION_BALLS} needed)"
                ));
            }
        } else if facts.no_cushion_after_contact() {
            fouls.push("Foul: no ball reached a cushion or a pocket after contact".into());
        }
    }
    for &b in facts.off_table.iter().filter(|&&b| b != CUE) {
        fouls.push(if b == NINE {
            "Foul: the 9 left the table".to_string()
        } else {
            format!("Foul: {} left the table (it stays off)", ball_name(b))
        });
    }
    let foul = !fouls.is_empty();
    let nine_down = facts.gone(NINE);

    if foul {
        let mut reasons = fouls;
        if nine_down {
            let spotted = rack::spot(&mut game.balls, usize::from(NINE), table);
            reasons.push(format!("The 9 is spotted {}", spotted.describe()));
        }
        if let Some(end) = count_foul(game, shooter, &mut reasons) {
            return Judged {
                reasons,
                foul: true,
                next: end,
            };
        }
        reasons.push(format!("{opponent} has ball in hand"));
        return Judged {
            reasons,
            foul: true,
            next: Next::Shoot {
                seat: opponent,
                in_hand: Some(InHand::Anywhere),
                // WPA 9-ball 2.4: no push-out after a foul on the break.
                options: Vec::new(),
            },
        };
    }
    game.fouls[shooter.index()] = 0;

    if push_out {
        let mut reasons = vec![format!("{shooter} pushed out")];
        if nine_down {
            let spotted = rack::spot(&mut game.balls, usize::from(NINE), table);
            reasons.push(format!(
                "The 9 is spotted {} (pocketed on a push-out)",
                spotted.describe()
            ));
        }
        reasons.push(format!(
            "{opponent} chooses to shoot from here or hand the table back"
        ));
        return Judged::offer(
            reasons,
            false,
            opponent,
            vec![Choice::AcceptTable, Choice::HandBack],
            Pending::PushOut { pusher: shooter },
        );
    }

    let counts = |p: u8| !game.settings.call_every_shot || breaking || call == Some(p);
    let mut reasons = Vec::new();
    if let Some(pocket) = facts.pocket_of(NINE) {
        if counts(pocket) {
            let reason = format!("{shooter} wins: the 9 fell on a legal shot");
            return Judged {
                reasons: vec![reason.clone()],
                foul: false,
                next: Next::Over {
                    winner: Some(shooter),
                    reason,
                },
            };
        }
        let spotted = rack::spot(&mut game.balls, usize::from(NINE), table);
        reasons.push(format!(
            "The 9 fell in the {}, not the called pocket, and is spotted {}",
            pocket_name(table, pocket),
            spotted.describe()
        ));
    }
    let scored = facts
        .pocketed
        .iter()
        .any(|&(b, p)| b != CUE && b != NINE && counts(p));
    let next_seat = if scored { shooter } else { opponent };
    reasons.push(if scored {
        format!("{shooter} pocketed a ball and continues")
    } else {
        format!("{opponent} to shoot")
    });
    Judged {
        reasons,
        foul: false,
        next: Next::Shoot {
            seat: next_seat,
            in_hand: None,
            // WPA 9-ball: the player who shoots after a legal break may push out.
            options: if breaking {
                vec![Choice::PushOut]
            } else {
                Vec::new()
            },
        },
    }
}
