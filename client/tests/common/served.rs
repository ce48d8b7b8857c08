//! A server on loopback, a game played on it, and waiting for what a client is told.
#![allow(dead_code)] // not every test file uses every part

use std::path::PathBuf;
use std::time::Duration;

use breakshot_client::bot::{run, BotConfig};
use breakshot_client::net::{Client, ClientEvent, EmbeddedServer, Reconnect};
use breakshot_shared::protocol::{
    AimAid, ClientMessage, Invite, RoomCode, ServerMessage, Snapshot,
};
use breakshot_shared::rules::{EightBallRules, Settings, Variant};

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
pub fn bots_game(server: &EmbeddedServer) -> RoomCode {
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let bots = BotConfig::new(server.loopback_invite(), 1);
    let report = runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(120), run(&bots)).await })
        .expect("the bots' game ended within two minutes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    report.games[0].room.clone().expect("the bots' room")
}

/// The next message `client` receives for which `want` holds.
pub async fn next(client: &mut Client, want: impl Fn(&ServerMessage) -> bool) -> ServerMessage {
    loop {
        if let ClientEvent::Message(m) = client.recv().await.expect("a message") {
            if want(&m) {
                return m;
            }
        }
    }
}

/// `f` run on `runtime`; fails the test if it takes more than a minute.
pub fn within<T>(
    runtime: &tokio::runtime::Runtime,
    what: &str,
    f: impl std::future::Future<Output = T>,
) -> T {
    runtime
        .block_on(async { tokio::time::timeout(Duration::from_secs(60), f).await })
        .unwrap_or_else(|_| panic!("{what} did not happen within a minute"))
}

/// A client of the server of `invite` that opened an online 8-ball room (WPA rules) as
/// `name`; the room as it was then.
pub async fn opened_room(invite: &Invite, name: &str) -> (Client, Box<Snapshot>) {
    seated(
        invite,
        ClientMessage::CreateRoom {
            variant: Variant::EightBall(EightBallRules::Wpa),
            mode: Settings::online(),
            aim_aid: AimAid::Full,
            name: name.into(),
        },
    )
    .await
}

/// A client of the server of `invite` seated in `room` as `name`; the room as it was then.
pub async fn joined_room(invite: &Invite, room: &RoomCode, name: &str) -> (Client, Box<Snapshot>) {
    let join = ClientMessage::Join {
        room: room.clone(),
        name: name.into(),
    };
    seated(invite, join).await
}

/// A client that sent `ask` and was given a seat.
async fn seated(invite: &Invite, ask: ClientMessage) -> (Client, Box<Snapshot>) {
    let mut client = Client::connect(invite.clone(), Reconnect::never())
        .await
        .expect("connected");
    client.send(&ask).await.expect("sent");
    let ServerMessage::Joined { snapshot, .. } =
        next(&mut client, |m| matches!(m, ServerMessage::Joined { .. })).await
    else {
        unreachable!("matched above")
    };
    (client, snapshot)
}
