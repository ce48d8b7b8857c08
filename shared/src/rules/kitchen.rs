//! The cue ball in hand behind the head string ("the kitchen"), after the break: what the
//! shot from there may hit first (WPA 6.11) and the spot on request (WPA 1.5).

use super::facts::ShotFacts;
use super::{ball_name, capitalise, rack, Choice, Game, InHand, Phase};

impl Game {
    /// The shot being judged was played with the cue ball in hand behind the head string,
    /// and was not a break (WPA 6.11 judges where it went first).
    pub(super) fn shooting_from_kitchen(&self) -> bool {
        !self.breaking
            && matches!(
                self.phase,
                Phase::Shooting {
                    in_hand: Some(InHand::Kitchen),
                    ..
                }
            )
    }

    /// The legal balls of the player to move, if all of them lie behind the head string:
    /// then the one nearest it may be spotted on request (WPA 1.5).
    fn legal_balls_all_behind_head_string(&self) -> Option<Vec<u8>> {
        let head = rack::head_string(self.table());
        let legal = self.legal_first_balls();
        let behind = |&b: &u8| {
            self.balls
                .get(usize::from(b))
                .is_some_and(|s| s.pos.y < head)
        };
        (!legal.is_empty() && legal.iter().all(behind)).then_some(legal)
    }

    /// Adds [`Choice::SpotNearestBall`] to the options of a shot from behind the head string
    /// when every legal ball lies behind it too.
    pub(super) fn offer_spot_nearest_ball(&mut self) {
        let eligible =
            self.shooting_from_kitchen() && self.legal_balls_all_behind_head_string().is_some();
        if let Phase::Shooting { options, .. } = &mut self.phase {
            options.retain(|&c| c != Choice::SpotNearestBall);
            if eligible {
                options.push(Choice::SpotNearestBall);
            }
        }
    }

    /// Spots the legal ball nearest the head string (the lowest-numbered of equally near
    /// ones) and returns what happened.
    pub(super) fn spot_nearest_ball(&mut self) -> Option<String> {
        let legal = self.legal_balls_all_behind_head_string()?;
        let y = |b: u8| self.balls.get(usize::from(b)).map_or(f64::MIN, |s| s.pos.y);
        let nearest = legal
            .iter()
            .copied()
            .reduce(|best, b| if y(b) > y(best) { b } else { best })?;
        let kind = self.table();
        let spotted = rack::spot(&mut self.balls, usize::from(nearest), kind);
        self.offer_spot_nearest_ball();
        Some(format!(
            "{} is spotted {}",
            capitalise(&ball_name(nearest)),
            spotted.describe()
        ))
    }
}

/// WPA 6.11 (with 1.5): from the cue ball in hand behind the head string, the first ball hit
/// may lie behind the head string only if the cue ball crossed it first.
pub(super) fn kitchen_foul(game: &Game, facts: &ShotFacts) -> Option<String> {
    match facts.first_contact {
        Some(b) if game.shooting_from_kitchen() && facts.contact_behind_head_string => Some(format!(
            "Foul: from behind the head string, the cue ball hit {} behind it without first crossing it",
            ball_name(b)
        )),
        _ => None,
    }
}
