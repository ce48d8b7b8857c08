//! Fetching a game's record from a server by its room code, to watch it again: one short
//! connection (pinned certificate, handshake), one `FetchRecord`, one answer.

use std::time::Duration;

use breakshot_shared::protocol::{ClientMessage, Invite, RoomCode};

use super::client::{Client, ClientEvent};
use super::player::Reconnect;
use super::record_answer::{interpret_record, FetchError, FetchedRecord, FETCH_TIMEOUT};

/// Fetches the record of `room`'s latest game from the server `server` names (its room, if
/// any, is ignored). Gives up after [`FETCH_TIMEOUT`].
pub async fn fetch_record(server: &Invite, room: &RoomCode) -> Result<FetchedRecord, FetchError> {
    fetch_game(server, room, None).await
}

/// Fetches the record of game `game` of `room` (numbered from 1; `None`: the latest), as
/// [`fetch_record`] does. A number the room has not reached is refused with
/// [`ErrorCode::NoSuchGame`](breakshot_shared::protocol::ErrorCode::NoSuchGame), whose message says how many games it has.
pub async fn fetch_game(
    server: &Invite,
    room: &RoomCode,
    game: Option<u32>,
) -> Result<FetchedRecord, FetchError> {
    let fetched = tokio::time::timeout(FETCH_TIMEOUT, fetch_on(server, room, game)).await;
    fetched.map_err(|_| FetchError::Timeout {
        authority: server.authority(),
    })?
}

/// [`fetch_game`] for code outside an async runtime (it makes a small one).
pub fn fetch_game_blocking(
    server: &Invite,
    room: &RoomCode,
    game: Option<u32>,
) -> Result<FetchedRecord, FetchError> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| FetchError::Runtime(e.to_string()))?;
    runtime.block_on(fetch_game(server, room, game))
}

async fn fetch_on(
    server: &Invite,
    room: &RoomCode,
    game: Option<u32>,
) -> Result<FetchedRecord, FetchError> {
    let mut client = Client::connect(server.clone(), Reconnect::never()).await?;
    client
        .send(&ClientMessage::FetchRecord {
            room: room.clone(),
            game,
        })
        .await?;
    let answer = loop {
        if let ClientEvent::Message(msg) = client.recv().await? {
            break msg;
        }
    };
    client.close(Duration::ZERO).await;
    interpret_record(room, answer)
}
