//! Answers to `FetchRecord`: one of a room's stored games (the latest, or the one asked for by
//! its number), sent whole so that anyone who knows the room code can watch it again. Runs on
//! the writer thread, which owns the store.

use breakshot_shared::protocol::limits::MAX_SENT_RECORD;
use breakshot_shared::protocol::{ErrorCode, RoomCode, ServerMessage};

use crate::store::{Store, StoreError};

/// A stored game as the store gives it: (number, encoded record, finished).
pub type Found = Option<(u32, Vec<u8>, bool)>;

/// The message answering a request for game `game` of `room` (`None`: its latest).
pub fn answer(store: &Store, room: &RoomCode, game: Option<u32>) -> ServerMessage {
    let found = match game {
        None => store.latest(room),
        Some(number) => store.game(room, number),
    };
    if let Err(e) = &found {
        tracing::error!(%room, error = %e, "cannot read a stored record");
    }
    let played = match (&found, game) {
        // Only a miss needs the count, for its message.
        (Ok(None), Some(_)) => store.games_played(room).unwrap_or(None),
        _ => None,
    };
    reply(room, game, found, played)
}

/// The reply for what the store found for game `asked` of `room` (`played`: how many games
/// the room has, when the one asked for is not among them): the record, or why it is not sent.
pub fn reply(
    room: &RoomCode,
    asked: Option<u32>,
    found: Result<Found, StoreError>,
    played: Option<u32>,
) -> ServerMessage {
    let error = |code, message: String| ServerMessage::Error { code, message };
    match found {
        Ok(Some((game, record, finished))) if record.len() <= MAX_SENT_RECORD => {
            ServerMessage::Record {
                room: room.clone(),
                game,
                finished,
                record,
            }
        }
        Ok(Some((game, record, _))) => error(
            ErrorCode::TooLarge,
            format!(
                "game {game} of room {room} is recorded in {} bytes, more than the {MAX_SENT_RECORD} one message can carry",
                record.len()
            ),
        ),
        Ok(None) => match (asked, played) {
            (Some(game), Some(played)) => error(
                ErrorCode::NoSuchGame,
                format!(
                    "room {room} has no game {game}: its games are numbered 1 to {played}"
                ),
            ),
            _ => error(ErrorCode::NoSuchRoom, format!("no recorded game in room {room}")),
        },
        Err(_) => error(
            ErrorCode::ServerBusy,
            "the server cannot read its records now; try later".into(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use breakshot_shared::protocol::{decode_payload, encode_frame, HEADER_LEN};

    use super::*;

    fn room() -> RoomCode {
        RoomCode::parse("K7QX2M4B").unwrap()
    }

    #[test]
    fn the_largest_record_sent_fits_in_a_frame_and_a_larger_one_is_refused() {
        let largest = reply(
            &room(),
            None,
            Ok(Some((u32::MAX, vec![0xff; MAX_SENT_RECORD], true))),
            None,
        );
        assert!(
            matches!(largest, ServerMessage::Record { ref record, .. } if record.len() == MAX_SENT_RECORD)
        );
        let frame = encode_frame(&largest).unwrap();
        let back: ServerMessage = decode_payload(&frame[HEADER_LEN..]).unwrap();
        assert_eq!(back, largest);

        let larger = reply(
            &room(),
            Some(1),
            Ok(Some((1, vec![0; MAX_SENT_RECORD + 1], false))),
            None,
        );
        assert!(
            matches!(
                larger,
                ServerMessage::Error {
                    code: ErrorCode::TooLarge,
                    ..
                }
            ),
            "{larger:?}"
        );
    }

    #[test]
    fn a_room_without_games_is_no_such_room_and_a_missing_number_says_how_many_there_are() {
        for asked in [None, Some(1)] {
            let answer = reply(&room(), asked, Ok(None), None);
            assert!(matches!(
                answer,
                ServerMessage::Error {
                    code: ErrorCode::NoSuchRoom,
                    ..
                }
            ));
        }
        let answer = reply(&room(), Some(5), Ok(None), Some(2));
        match answer {
            ServerMessage::Error {
                code: ErrorCode::NoSuchGame,
                message,
            } => assert_eq!(
                message,
                "room K7QX2M4B has no game 5: its games are numbered 1 to 2"
            ),
            other => panic!("{other:?}"),
        }
    }
}
