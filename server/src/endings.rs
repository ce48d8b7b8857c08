//! Seats of games that are over, kept for a while after their room is gone so that a player
//! who was away when the game ended (their opponent took the last shot, or the server
//! restarted) is told the result when they come back with their token, instead of being
//! told the token is unknown.

use std::collections::BTreeMap;
use std::time::Instant;

use breakshot_shared::protocol::{RoomCode, ServerMessage};
use breakshot_shared::rules::Seat;

use crate::secret::TokenDigest;

/// How one game ended, as told to a returning player.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ending {
    /// The room's code.
    pub room: RoomCode,
    /// The game's number in its room, from 1.
    pub game: u32,
    /// `None` if nobody won (also for a game abandoned before anyone could win).
    pub winner: Option<Seat>,
    /// The readable reason, as `GameOver` gave it ("abandoned" for a game that never ended).
    pub reason: String,
}

#[derive(Debug)]
struct Kept {
    ending: Ending,
    seat: Seat,
    until: Instant,
}

/// Finished seats by the digest of their token, each until its own expiry.
#[derive(Debug, Default)]
pub struct Endings {
    seats: BTreeMap<TokenDigest, Kept>,
}

impl Endings {
    /// Keeps `seats` of the ended game until `until`.
    pub fn keep(
        &mut self,
        ending: &Ending,
        seats: impl IntoIterator<Item = (Seat, TokenDigest)>,
        until: Instant,
    ) {
        for (seat, digest) in seats {
            self.seats.insert(
                digest,
                Kept {
                    ending: ending.clone(),
                    seat,
                    until,
                },
            );
        }
    }

    /// The answer for a returning player holding the token with `digest`, if its game is
    /// over and still kept.
    pub fn answer(&self, now: Instant, digest: &TokenDigest) -> Option<ServerMessage> {
        let kept = self.seats.get(digest).filter(|k| k.until > now)?;
        Some(ServerMessage::GameFinished {
            room: kept.ending.room.clone(),
            game: kept.ending.game,
            seat: kept.seat,
            winner: kept.ending.winner,
            reason: kept.ending.reason.clone(),
        })
    }

    /// Forgets the seats whose time is up.
    pub fn expire(&mut self, now: Instant) {
        self.seats.retain(|_, k| k.until > now);
    }

    /// Seats kept, counting any whose time is up but that [`Endings::expire`] has not dropped yet.
    pub fn len(&self) -> usize {
        self.seats.len()
    }

    /// Whether no seat is kept.
    pub fn is_empty(&self) -> bool {
        self.seats.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn a_finished_seat_is_answered_with_its_result_until_it_expires() {
        let now = Instant::now();
        let mut endings = Endings::default();
        let ending = Ending {
            room: RoomCode::parse("K7QX2M4B").unwrap(),
            game: 2,
            winner: Some(Seat::B),
            reason: "A conceded; B wins".into(),
        };
        let a = TokenDigest([1; 32]);
        let b = TokenDigest([2; 32]);
        endings.keep(
            &ending,
            [(Seat::A, a), (Seat::B, b)],
            now + Duration::from_secs(60),
        );
        assert!(matches!(
            endings.answer(now, &a),
            Some(ServerMessage::GameFinished {
                seat: Seat::A,
                winner: Some(Seat::B),
                game: 2,
                ..
            })
        ));
        assert!(endings.answer(now, &TokenDigest([3; 32])).is_none());
        let later = now + Duration::from_secs(61);
        assert!(endings.answer(later, &b).is_none());
        endings.expire(later);
        assert!(endings.is_empty());
    }
}
