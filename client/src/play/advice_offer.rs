//! Whether a game offers the computer's advice, and what a miss offers: it depends on who
//! decides the game and who else sees it, so one rule serves every kind of game.

/// What the computer's advice may do in a game.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdviceOffer {
    /// No advice: an online game, or a spectator's view.
    Refused,
    /// Advice on the table as it stands; after a miss, the comparison for the table it was
    /// played from, shown while the table stays with the player now to move (two players at
    /// one computer: the miss is not taken back, since the other player now plays).
    Beside,
    /// Advice on the table as it stands; after a miss, the shot is taken back first and the
    /// advice is for the table it was played from (against the computer: nobody else sees
    /// the game, so the table may go back).
    TakingBack,
}

impl AdviceOffer {
    /// The offer of a game decided at this computer (`offline`) or not, seen by a
    /// spectator (`watching`) or played, whose shots the player may take back
    /// (`takes_back`).
    pub fn of(offline: bool, watching: bool, takes_back: bool) -> AdviceOffer {
        match (offline && !watching, takes_back) {
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
        // A local game for two: advice, and a miss is advised on beside the table.
        assert_eq!(AdviceOffer::of(true, false, false), AdviceOffer::Beside);
        // Against the computer: a miss is taken back first.
        assert_eq!(AdviceOffer::of(true, false, true), AdviceOffer::TakingBack);
        // Online, played or watched, and a spectator anywhere: none.
        for (offline, watching, takes_back) in [
            (false, false, false),
            (false, true, false),
            (true, true, false),
            (true, true, true),
        ] {
            let offer = AdviceOffer::of(offline, watching, takes_back);
            assert_eq!(offer, AdviceOffer::Refused, "{offline} {watching}");
            assert!(!offer.allowed());
        }
        assert!(AdviceOffer::Beside.allowed() && AdviceOffer::TakingBack.allowed());
    }
}
