//! Answers to `FetchRecord`: a room's latest stored game, sent whole so that anyone who knows
//! the room code can watch it again. Runs on the writer thread, which owns the store.

use breakshot_shared::protocol::limits::MAX_SENT_RECORD;
use breakshot_shared::protocol::{ErrorCode, RoomCode, ServerMessage};

use crate::store::{Store, StoreError};

/// The message answering a request for `room`'s record.
pub fn answer(store: &Store, room: &RoomCode) -> ServerMessage {
    let found = store.latest(room);
    if let Err(e) = &found {
        tracing::error!(%room, error = %e, "cannot read a stored record");
    }
    reply(room, found)
}

/// The reply for what the store found: the record, or why it is not sent.
pub fn reply(
    room: &RoomCode,
    found: Result<Option<(u32, Vec<u8>, bool)>, StoreError>,
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
        Ok(None) => error(ErrorCode::NoSuchRoom, format!("no recorded game in room {room}")),
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
            Ok(Some((u32::MAX, vec![0xff; MAX_SENT_RECORD], true))),
        );
        assert!(
            matches!(largest, ServerMessage::Record { ref record, .. } if record.len() == MAX_SENT_RECORD)
        );
        let frame = encode_frame(&largest).unwrap();
        let back: ServerMessage = decode_payload(&frame[HEADER_LEN..]).unwrap();
        assert_eq!(back, largest);

        let larger = reply(&room(), Ok(Some((1, vec![0; MAX_SENT_RECORD + 1], false))));
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
    fn a_room_without_games_is_no_such_room() {
        let answer = reply(&room(), Ok(None));
        assert!(matches!(
            answer,
            ServerMessage::Error {
                code: ErrorCode::NoSuchRoom,
                ..
            }
        ));
    }
}
