//! Players' Glicko-2 ratings, computed by the `skillratings` crate, updated when a rated game
//! (a quick match) ends: the winner's result is a win, the loser's a loss (a concession or a
//! forfeit is a loss like any other); a game nobody won changes nothing. Pure: the hub keeps
//! the ratings and hands each change to the store.

use std::collections::BTreeMap;

use breakshot_shared::protocol::lobby::{page_of, pages, RatedPlayer};
use breakshot_shared::protocol::PlayerKey;
use skillratings::glicko2::{glicko2, Glicko2Config, Glicko2Rating};
use skillratings::Outcomes;

/// One player's rating as kept.
#[derive(Clone, Debug, PartialEq)]
pub struct PlayerRating {
    /// The name last played under.
    pub name: String,
    /// The Glicko-2 rating.
    pub rating: f64,
    /// Its deviation.
    pub deviation: f64,
    /// Its volatility.
    pub volatility: f64,
    /// Rated games played.
    pub games: u32,
}

impl PlayerRating {
    /// A player's rating before any rated game (the crate's 1500, 350, 0.06).
    pub fn new(name: &str) -> PlayerRating {
        let start = Glicko2Rating::new();
        PlayerRating {
            name: name.to_owned(),
            rating: start.rating,
            deviation: start.deviation,
            volatility: start.volatility,
            games: 0,
        }
    }

    fn glicko(&self) -> Glicko2Rating {
        Glicko2Rating {
            rating: self.rating,
            deviation: self.deviation,
            volatility: self.volatility,
        }
    }

    fn after(&self, name: &str, new: Glicko2Rating) -> PlayerRating {
        PlayerRating {
            name: name.to_owned(),
            rating: new.rating,
            deviation: new.deviation,
            volatility: new.volatility,
            games: self.games.saturating_add(1),
        }
    }

    /// The rating as shown: rounded.
    pub fn shown(&self) -> i32 {
        self.rating.round() as i32
    }
}

/// Every rating this server knows.
#[derive(Default)]
pub struct Ratings {
    players: BTreeMap<PlayerKey, PlayerRating>,
}

impl Ratings {
    /// The ratings as the store kept them.
    pub fn from_stored(stored: impl IntoIterator<Item = (PlayerKey, PlayerRating)>) -> Ratings {
        Ratings {
            players: stored.into_iter().collect(),
        }
    }

    /// `key`'s rating, if they have played a rated game.
    pub fn get(&self, key: &PlayerKey) -> Option<&PlayerRating> {
        self.players.get(key)
    }

    /// `key`'s rating for pairing: theirs, or the starting one.
    pub fn or_start(&self, key: &PlayerKey) -> f64 {
        self.get(key)
            .map_or_else(|| Glicko2Rating::new().rating, |r| r.rating)
    }

    /// `key`'s rating as shown (rounded): theirs, or the starting one.
    pub fn shown_or_start(&self, key: &PlayerKey) -> i32 {
        self.or_start(key).round() as i32
    }

    /// Rates a game `winner` (playing as `winner_name`) won against `loser`; returns both
    /// players' ratings before and after, winner first, to store and to tell.
    pub fn rate(
        &mut self,
        winner: (PlayerKey, &str),
        loser: (PlayerKey, &str),
    ) -> [(PlayerKey, PlayerRating, PlayerRating); 2] {
        let w = self
            .players
            .get(&winner.0)
            .cloned()
            .unwrap_or_else(|| PlayerRating::new(winner.1));
        let l = self
            .players
            .get(&loser.0)
            .cloned()
            .unwrap_or_else(|| PlayerRating::new(loser.1));
        let (nw, nl) = glicko2(
            &w.glicko(),
            &l.glicko(),
            &Outcomes::WIN,
            &Glicko2Config::new(),
        );
        let (w2, l2) = (w.after(winner.1, nw), l.after(loser.1, nl));
        self.players.insert(winner.0, w2.clone());
        self.players.insert(loser.0, l2.clone());
        [(winner.0, w, w2), (loser.0, l, l2)]
    }

    /// A page (from 0) of the leaderboard, best first (ties by key), and the pages in all.
    pub fn leaderboard(&self, page: u32) -> (u32, Vec<RatedPlayer>) {
        let mut all: Vec<(&PlayerKey, &PlayerRating)> = self.players.iter().collect();
        all.sort_by(|a, b| b.1.rating.total_cmp(&a.1.rating).then(a.0.cmp(b.0)));
        let lines: Vec<RatedPlayer> = all
            .iter()
            .enumerate()
            .map(|(i, (key, r))| RatedPlayer {
                rank: i as u32 + 1,
                name: r.name.clone(),
                key: key.short(),
                rating: r.shown(),
                deviation: r.deviation.round() as i32,
                games: r.games,
            })
            .collect();
        (pages(lines.len()), page_of(&lines, page))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_win_moves_both_ratings_as_the_crate_s_own_example() {
        let mut r = Ratings::default();
        let (ann, bob) = (PlayerKey([1; 32]), PlayerKey([2; 32]));
        let [(_, w0, w1), (_, l0, l1)] = r.rate((ann, "ann"), (bob, "bob"));
        assert_eq!((w0.rating, l0.rating), (1500.0, 1500.0));
        // The crate's documented example: 1500/350/0.06 against the same, a win.
        assert_eq!(w1.rating.round(), 1662.0);
        assert_eq!(w1.deviation.round(), 290.0);
        assert_eq!(l1.rating.round(), 1338.0);
        assert_eq!((w1.games, l1.games), (1, 1));
        let (pages, board) = r.leaderboard(0);
        assert_eq!(pages, 1);
        assert_eq!(board[0].name, "ann");
        assert_eq!(board[0].rating, 1662);
        assert_eq!(board[1].rank, 2);
        assert!(r.leaderboard(1).1.is_empty());
    }
}
