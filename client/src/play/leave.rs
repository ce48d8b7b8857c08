//! Leaving an online game: Esc asks first, because leaving keeps the seat only for the
//! reconnect window; conceding is a separate, explicit choice.

use std::time::Duration;

use breakshot_shared::rules::Seat;

use super::controls::Key;
use crate::view::hud::Connection;

/// What a key does while the player is asked whether to leave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeaveAnswer {
    /// Back to the game (Esc again).
    Stay,
    /// Leave for the menu; the seat is kept for the reconnect window (Enter or Space).
    Leave,
    /// Give up the game (C).
    Concede,
}

/// Does Esc ask before leaving? Only for a player holding a seat in an online game still in
/// play (leaving keeps the seat only for the reconnect window); a spectator, a game at this
/// computer or a game that is over goes straight back to the menu.
pub fn asks_first(seat: Option<Seat>, connection: &Connection, over: bool) -> bool {
    seat.is_some() && *connection != Connection::Offline && !over
}

/// The answer a key gives to the question, if it answers it.
pub fn answer(key: Key) -> Option<LeaveAnswer> {
    match key {
        Key::Back => Some(LeaveAnswer::Stay),
        Key::Shoot => Some(LeaveAnswer::Leave),
        Key::Concede => Some(LeaveAnswer::Concede),
        _ => None,
    }
}

/// The question, one line each: what leaving does and how to come back, with `window` the
/// time the server keeps the seat.
pub fn question(window: Duration) -> [String; 4] {
    let minutes = window.as_secs().div_ceil(60);
    [
        "Leave the game?".into(),
        format!(
            "Your seat is kept for {minutes} minute{}: run the same breakshot join (or host) \
             command, or Resume game in the menu, to come back. After that you forfeit.",
            if minutes == 1 { "" } else { "s" }
        ),
        "Enter: leave    C: concede the game    Esc: keep playing".into(),
        String::new(),
    ]
}

#[cfg(test)]
mod tests {

    #[test]
    fn esc_asks_first_only_for_a_seat_held_online_in_a_game_in_play() {
        let online = Connection::Connected;
        assert!(asks_first(Some(Seat::A), &online, false));
        assert!(!asks_first(None, &online, false), "a spectator just goes");
        assert!(
            !asks_first(Some(Seat::A), &Connection::Offline, false),
            "one computer"
        );
        assert!(
            !asks_first(Some(Seat::B), &online, true),
            "the game is over"
        );
    }

    use super::*;

    #[test]
    fn esc_stays_enter_leaves_and_only_c_concedes() {
        assert_eq!(answer(Key::Back), Some(LeaveAnswer::Stay));
        assert_eq!(answer(Key::Shoot), Some(LeaveAnswer::Leave));
        assert_eq!(answer(Key::Concede), Some(LeaveAnswer::Concede));
        for other in [Key::AimLine, Key::Rerack, Key::Debug, Key::Next] {
            assert_eq!(answer(other), None, "{other:?}");
        }
    }

    #[test]
    fn the_question_says_how_long_the_seat_is_kept() {
        let q = question(Duration::from_secs(120));
        assert!(q[1].contains("kept for 2 minutes"), "{}", q[1]);
        assert!(q[2].contains("C: concede"));
    }
}
