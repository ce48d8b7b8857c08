//! What the client's integration tests share: a server on loopback, and a game played on it.
#![cfg(feature = "host")]

use std::path::PathBuf;
use std::time::Duration;

use breakshot_client::bot::{run, BotConfig};
use breakshot_client::net::EmbeddedServer;
use breakshot_shared::protocol::RoomCode;

/// A server on a free loopback port, keeping its data in `data`.
pub fn loopback_server(data: PathBuf) -> EmbeddedServer {
    EmbeddedServer::start(breakshot_server::Config::new(
        std::net::SocketAddr::from(([127, 0, 0, 1], 0)),
        data,
    ))
    .expect("a server on loopback")
}

/// Two bots play one game on `server`: its room. Fails the test if the game has not ended
/// within two minutes or a bot met an error.
#[allow(dead_code)] // not every test file plays a bots game
pub fn bots_game(server: &EmbeddedServer) -> RoomCode {
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let bots = BotConfig::new(server.loopback_invite(), 1);
    let report = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(120), run(&bots)).await })
        .expect("the bots' game ended within two minutes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    report.games[0].room.clone().expect("the bots' room")
}
pub mod reported;
pub mod screen;
