//! What the lobby shows: public rooms waiting for a player, games in play to watch, and the
//! leaderboard, each a page of a list the server keeps. A room is private (reached by its
//! invite, as before) unless its host lists it with [`super::ClientMessage::Publish`];
//! quick-match rooms are listed for watching.

use serde::{Deserialize, Serialize};

use super::ids::RoomCode;
use crate::rules::{Settings, Variant};

/// A public room waiting for its second player.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WaitingRoom {
    /// The room to join.
    pub room: RoomCode,
    /// The game it plays.
    pub variant: Variant,
    /// Its rules' settings (calls, shot clock, table).
    pub mode: Settings,
    /// The host's display name.
    pub host: String,
    /// The host's rating (Glicko-2, rounded), if they have played a rated game here.
    pub rating: Option<i32>,
    /// Seconds the room has waited since it was listed.
    pub waited_s: u32,
}

/// A listed game with both players, open to spectators.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GameInPlay {
    /// The room to watch.
    pub room: RoomCode,
    /// The game it plays.
    pub variant: Variant,
    /// Seats A and B's display names.
    pub names: [String; 2],
    /// Their ratings, where they have one.
    pub ratings: [Option<i32>; 2],
    /// Whether the game counts for the ratings (a quick match).
    pub rated: bool,
}

/// One line of the leaderboard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RatedPlayer {
    /// The place on the board, from 1.
    pub rank: u32,
    /// The name last played under.
    pub name: String,
    /// The first 8 hex characters of the player's key (two players may share a name).
    pub key: String,
    /// The Glicko-2 rating, rounded.
    pub rating: i32,
    /// The rating's deviation, rounded: how unsure it still is.
    pub deviation: i32,
    /// Rated games played.
    pub games: u32,
}

/// Entries on one page of any lobby list.
pub const PAGE_SIZE: usize = 20;

/// The number of pages a list of `len` entries makes (at least 1, an empty page).
pub fn pages(len: usize) -> u32 {
    len.div_ceil(PAGE_SIZE).max(1) as u32
}

/// The entries of `page` (from 0) of `all`; empty past the end.
pub fn page_of<T: Clone>(all: &[T], page: u32) -> Vec<T> {
    let start = (page as usize).saturating_mul(PAGE_SIZE);
    all.iter().skip(start).take(PAGE_SIZE).cloned().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_cut_a_list_and_a_page_past_the_end_is_empty() {
        let all: Vec<u32> = (0..45).collect();
        assert_eq!(pages(all.len()), 3);
        assert_eq!(pages(0), 1);
        assert_eq!(page_of(&all, 0).len(), PAGE_SIZE);
        assert_eq!(page_of(&all, 2), vec![40, 41, 42, 43, 44]);
        assert!(page_of(&all, 3).is_empty());
        assert!(page_of(&all, u32::MAX).is_empty());
    }
}
