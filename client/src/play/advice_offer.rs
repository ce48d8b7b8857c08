//! Whether a game offers the computer's advice, and what a miss offers: it depends on who
//! decides the game and who else sees it, so one rule serves every kind of game.

use breakshot_shared::protocol::AimAid;

/// What the computer's advice may do in a game.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdviceOffer {
    /// No advice: an online room that does not allow it, or a spectator's view.
    Refused,
    /// Advice on the table as it stands; after a miss, the comparison for the table it was
    /// played from, shown while the table stays with the player now to move (two players at
    /// one computer, or an online room that allows advice: the miss is not taken back, since
    /// the other player now plays).
    Beside,
    /// Advice on the table as it stands; after a miss, the shot is taken back first and the
    /// advice is for the table it was played from (against the computer: nobody else sees
    /// the game, so the table may go back).
    TakingBack,
}

impl AdviceOffer {
    /// The offer of a game decided at this computer (`offline`) or in a room whose policy
    /// is `room`, seen by a spectator (`watching`) or played, whose shots the player may
    /// take back (`takes_back`).
    pub fn of(offline: bool, room: AimAid, watching: bool, takes_back: bool) -> AdviceOffer {
        let allowed = offline || room == AimAid::Advice;
        match (allowed && !watching, takes_back) {
            (false, _) => AdviceOffer::Refused,
            (true, false) => AdviceOffer::Beside,
            (true, true) => AdviceOffer::TakingBack,
        }
    }

    /// Whether advice may be asked at all.
    pub fn allowed(self) -> bool {
        self != AdviceOffer::Refused
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advice_is_offered_at_this_computer_and_refused_online_and_to_spectators() {
        // At this computer the room's policy is not asked (it is Full there).
        for room in [AimAid::Off, AimAid::Full] {
            // A local game for two: advice, and a miss is advised on beside the table.
            assert_eq!(
                AdviceOffer::of(true, room, false, false),
                AdviceOffer::Beside
            );
            // Against the computer: a miss is taken back first.
            assert_eq!(
                AdviceOffer::of(true, room, false, true),
                AdviceOffer::TakingBack
            );
        }
        // Online in a room that allows it: beside the table, as for two at one computer.
        assert_eq!(
            AdviceOffer::of(false, AimAid::Advice, false, false),
            AdviceOffer::Beside
        );
        // Online in any other room, and a spectator anywhere: none.
        for (offline, room, watching, takes_back) in [
            (false, AimAid::Off, false, false),
            (false, AimAid::FirstContact, false, false),
            (false, AimAid::Full, false, false),
            (false, AimAid::Advice, true, false),
            (true, AimAid::Full, true, false),
            (true, AimAid::Full, true, true),
        ] {
            let offer = AdviceOffer::of(offline, room, watching, takes_back);
            assert_eq!(offer, AdviceOffer::Refused, "{offline} {room:?} {watching}");
            assert!(!offer.allowed());
        }
        assert!(AdviceOffer::Beside.allowed() && AdviceOffer::TakingBack.allowed());
    }
}
