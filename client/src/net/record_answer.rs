//! What a server's answer to `FetchRecord` means: the record of one of a room's games, or why
//! there is none. Shared by the native fetch (`records.rs`) and the browser's.

use std::time::Duration;

use breakshot_shared::protocol::{ErrorCode, RoomCode, ServerMessage};
use thiserror::Error;

use super::error::NetError;

/// How long connecting and fetching may take before the server counts as unreachable.
pub const FETCH_TIMEOUT: Duration = Duration::from_secs(15);

#[derive(Debug, Error)]
/// Why a game's record could not be fetched.
pub enum FetchError {
    #[error(transparent)]
    /// The connection failed.
    Net(#[from] NetError),
    #[error("the server has no game in room {0}")]
    /// The server has no game in that room.
    NoSuchGame(RoomCode),
    #[error("the server refused ({code:?}): {message}")]
    /// The server refused to send it.
    Refused {
        /// Why, as a code.
        code: ErrorCode,
        /// Why, in words.
        message: String,
    },
    #[error("the server answered with {0} instead of the record")]
    /// The server answered something else.
    Unexpected(String),
    #[error("no answer from {authority} within {} s: is the server running and its UDP port open?", FETCH_TIMEOUT.as_secs())]
    /// The server did not answer in time.
    Timeout {
        /// The server asked.
        authority: String,
    },
    #[error("cannot start the network: {0}")]
    /// No runtime to fetch with.
    Runtime(String),
}

/// One of a room's games as the server stores it.
#[derive(Clone, Debug, PartialEq)]
pub struct FetchedRecord {
    /// The room the game was played in.
    pub room: RoomCode,
    /// The game's number in its room, from 1.
    pub game: u32,
    /// The game is over (else it is still being played).
    pub finished: bool,
    /// An encoded [`breakshot_shared::replay::GameRecord`].
    pub bytes: Vec<u8>,
}

/// What the server's answer to `FetchRecord { room }` means.
pub fn interpret_record(
    room: &RoomCode,
    answer: ServerMessage,
) -> Result<FetchedRecord, FetchError> {
    match answer {
        ServerMessage::Record {
            room: got,
            game,
            finished,
            record,
        } if got == *room => Ok(FetchedRecord {
            room: got,
            game,
            finished,
            bytes: record,
        }),
        ServerMessage::Error {
            code: ErrorCode::NoSuchRoom,
            ..
        } => Err(FetchError::NoSuchGame(room.clone())),
        ServerMessage::Error { code, message } => Err(FetchError::Refused { code, message }),
        other => Err(FetchError::Unexpected(format!("{other:?}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room(code: &str) -> RoomCode {
        RoomCode::parse(code).unwrap()
    }

    #[test]
    fn only_the_record_of_the_room_asked_for_is_taken() {
        let record = |code: &str| ServerMessage::Record {
            room: room(code),
            game: 2,
            finished: true,
            record: vec![1, 2, 3],
        };
        let got = interpret_record(&room("AAAAAAAA"), record("AAAAAAAA")).unwrap();
        assert_eq!(
            (got.game, got.finished, got.bytes),
            (2, true, vec![1, 2, 3])
        );
        assert!(matches!(
            interpret_record(&room("AAAAAAAA"), record("BBBBBBBB")),
            Err(FetchError::Unexpected(_))
        ));
    }

    #[test]
    fn refusals_keep_their_meaning() {
        let error = |code| ServerMessage::Error {
            code,
            message: "why".into(),
        };
        assert!(matches!(
            interpret_record(&room("AAAAAAAA"), error(ErrorCode::NoSuchRoom)),
            Err(FetchError::NoSuchGame(r)) if r == room("AAAAAAAA")
        ));
        assert!(matches!(
            interpret_record(&room("AAAAAAAA"), error(ErrorCode::TooLarge)),
            Err(FetchError::Refused {
                code: ErrorCode::TooLarge,
                ..
            })
        ));
    }
}
