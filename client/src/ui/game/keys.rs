//! The keys the hint bar lists in a game, put together from the keys that game takes.

use breakshot_client::play::AdviceOffer;

/// Which keys a player's bar lists: the first of these that fits the game.
#[derive(Clone, Copy, PartialEq)]
enum Line {
    /// Shots may be taken back (against the computer): undo, redo, again and advice.
    TakesBack,
    /// Online in a room that allows advice: chat, and advice said to be the room's.
    RoomAdvice,
    /// Advice beside the table, which stays with the player to move (two at one computer).
    Beside,
    /// Online: chat.
    Chat,
    /// Offline, with nothing more.
    Plain,
}

/// What a player's hint bar lists: online (`chats`), with advice as `offer` says, shots
/// taken back or not (`takes_back`).
pub(super) fn player_keys(chats: bool, offer: AdviceOffer, takes_back: bool) -> String {
    let line = if takes_back {
        Line::TakesBack
    } else if chats && offer.allowed() {
        Line::RoomAdvice
    } else if offer == AdviceOffer::Beside {
        Line::Beside
    } else if chats {
        Line::Chat
    } else {
        Line::Plain
    };
    let online = matches!(line, Line::RoomAdvice | Line::Chat);
    // The lines with more keys to list say less of the others (the view in short, Space
    // without its skip; the room's advice without the elevation and the view), so that the
    // bar holds them.
    let view = match line {
        Line::RoomAdvice => None,
        Line::TakesBack | Line::Chat => Some("V: 3-D"),
        Line::Beside | Line::Plain => Some("V: 3-D view"),
    };
    let advice = match line {
        Line::RoomAdvice => Some("I advice  J play it (this room allows it)"),
        Line::TakesBack | Line::Beside => Some("I advice  J play it"),
        Line::Chat | Line::Plain => None,
    };
    bar(&[
        Some("Mouse: aim, drag back: shoot"),
        Some(if online {
            "Space: shoot"
        } else {
            "Space: shoot / skip"
        }),
        (line != Line::RoomAdvice).then_some("W/S: elevation"),
        view,
        Some("A G P L: aids"),
        (line == Line::TakesBack).then_some("U undo  Y redo  B again"),
        advice,
        online.then_some("T: chat"),
        Some("Esc: leave"),
    ])
}

/// What a watcher's hint bar lists, in a room whose players may ask for advice or not.
pub(super) fn watcher_keys(room_allows_advice: bool) -> String {
    bar(&[
        Some("Watching: both seats are taken"),
        room_allows_advice
            .then_some("the players may ask the computer's advice (this room allows it)"),
        Some("A G P: aids"),
        Some("T: chat"),
        Some("Esc: leave"),
    ])
}

/// The bar's line: the pieces given, apart.
fn bar(pieces: &[Option<&str>]) -> String {
    let shown: Vec<&str> = pieces.iter().flatten().copied().collect();
    shown.join("  |  ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The player's line as it was written out whole, one string for each kind of game.
    fn written_out(chats: bool, offer: AdviceOffer, takes_back: bool) -> &'static str {
        let keys = if chats && offer.allowed() {
            "Mouse: aim, drag back: shoot  |  Space: shoot  |  A G P L: aids  |  I advice  J play it (this room allows it)  |  T: chat  |  Esc: leave"
        } else if offer == AdviceOffer::Beside {
            "Mouse: aim, drag back: shoot  |  Space: shoot / skip  |  W/S: elevation  |  V: 3-D view  |  A G P L: aids  |  I advice  J play it  |  Esc: leave"
        } else if chats {
            "Mouse: aim, drag back: shoot  |  Space: shoot  |  W/S: elevation  |  V: 3-D  |  A G P L: aids  |  T: chat  |  Esc: leave"
        } else {
            "Mouse: aim, drag back: shoot  |  Space: shoot / skip  |  W/S: elevation  |  V: 3-D view  |  A G P L: aids  |  Esc: leave"
        };
        if takes_back {
            "Mouse: aim, drag back: shoot  |  Space: shoot / skip  |  W/S: elevation  |  V: 3-D  |  A G P L: aids  |  U undo  Y redo  B again  |  I advice  J play it  |  Esc: leave"
        } else {
            keys
        }
    }

    #[test]
    fn every_player_s_line_is_the_one_written_out_whole() {
        for chats in [false, true] {
            for offer in [
                AdviceOffer::Refused,
                AdviceOffer::Beside,
                AdviceOffer::TakingBack,
            ] {
                for takes_back in [false, true] {
                    assert_eq!(
                        player_keys(chats, offer, takes_back),
                        written_out(chats, offer, takes_back),
                        "chats {chats}, {offer:?}, takes back {takes_back}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_watcher_s_line_is_the_one_written_out_whole() {
        assert_eq!(
            watcher_keys(true),
            "Watching: both seats are taken  |  the players may ask the computer's advice (this room allows it)  |  A G P: aids  |  T: chat  |  Esc: leave"
        );
        assert_eq!(
            watcher_keys(false),
            "Watching: both seats are taken  |  A G P: aids  |  T: chat  |  Esc: leave"
        );
    }
}
