//! A player who drops, as the other player meets it: a client process killed on its turn is
//! seen gone within seconds (QUIC keep-alive and idle timeout), its shot clock stops at the
//! moment it went silent, and it comes back to the time it had left; a server stopped and
//! started again gives the player to move what was left, not a full clock.
//!
//! The killed client is this test binary run again with [`CHILD`] set: it opens a room, prints
//! the room and its seat token, and waits until it is killed.

use std::io::Read;
use std::net::SocketAddr;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context as _, Result};
use breakshot_shared::protocol::limits::IDLE_TIMEOUT;
use breakshot_shared::protocol::{
    AimAid, ClientMessage, Invite, RoomCode, SeatToken, ServerMessage,
};
use breakshot_shared::rules::{Seat, Settings};
use breakshot_testkit::{read_line, Spawned};
use breakshot_tests::{eight_ball, scratch, Player, Reads, TestServer, PATIENCE};

/// Set (to an invite) in the client process the first test starts.
const CHILD: &str = "BREAKSHOT_DROPS_CLIENT";
/// The rooms' shot clock (s).
const CLOCK_S: u32 = 60;
const CLOCK_MS: u64 = CLOCK_S as u64 * 1000;

fn clocked() -> Settings {
    Settings {
        shot_clock: Some(CLOCK_S),
        ..Settings::offline()
    }
}

fn hex(token: &SeatToken) -> String {
    token.0.iter().map(|b| format!("{b:02x}")).collect()
}

fn token_of(hex: &str) -> Option<SeatToken> {
    let mut bytes = [0u8; 16];
    for (i, b) in bytes.iter_mut().enumerate() {
        *b = u8::from_str_radix(hex.get(2 * i..2 * i + 2)?, 16).ok()?;
    }
    Some(SeatToken(bytes))
}

/// The client process: creates a room with a shot clock as "ann", prints `ROOM TOKEN`, and
/// then only keeps its connection (and keep-alives) going. Does nothing in a normal run.
#[test]
fn client_process() {
    let Ok(invite) = std::env::var(CHILD) else {
        return;
    };
    let invite: Invite = invite.parse().expect("an invite");
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    runtime.block_on(async {
        let mut ann = Player::connect(&invite).await.expect("connecting");
        ann.send(ClientMessage::CreateRoom {
            variant: eight_ball(),
            mode: clocked(),
            aim_aid: AimAid::Full,
            name: "ann".into(),
        })
        .await
        .expect("sending");
        let room = match ann
            .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
            .await
            .expect("joined")
        {
            ServerMessage::Joined { snapshot, .. } => snapshot.room,
            _ => unreachable!(),
        };
        let token = ann.client.token().expect("a seat token");
        println!("{room} {}", hex(&token));
        // Read on, so the connection stays alive until the process is killed.
        while ann.recv().await.is_ok() {}
    });
}

/// Reads until the shot clock is told in a `TurnChanged` or a snapshot; returns its ms.
async fn clock_told(player: &mut Player) -> Result<u64> {
    loop {
        match player.recv().await? {
            ServerMessage::TurnChanged {
                shot_clock_ms: Some(ms),
                ..
            } => return Ok(ms),
            ServerMessage::Joined { snapshot, .. } if snapshot.shot_clock_ms.is_some() => {
                return Ok(snapshot.shot_clock_ms.unwrap_or_default())
            }
            ServerMessage::Error { .. } | ServerMessage::Reject { .. } => bail!("refused"),
            _ => {}
        }
    }
}

fn ms(d: Duration) -> u64 {
    u64::try_from(d.as_millis()).unwrap_or(u64::MAX)
}

#[tokio::test(flavor = "multi_thread")]
async fn a_killed_client_is_seen_gone_in_seconds_and_finds_the_clock_as_it_left_it() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("drops-killed").await?;

    let me = std::env::current_exe()?;
    let mut child = Spawned::start(
        Command::new(me)
            .args([
                "--exact",
                "client_process",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD, server.invite.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::null()),
    );
    let stdout = child.child().stdout.take().context("stdout")?;
    // The test harness speaks first; the line wanted ends with "ROOM TOKEN". Every read is
    // bounded: a child that prints nothing fails the test.
    let (mut line, rest) = read_line(stdout, PATIENCE);
    let mut rest: Box<dyn Read + Send> = Box::new(rest);
    let mut lines = 1;
    let (room, token) = loop {
        let words: Vec<&str> = line.split_whitespace().collect();
        if let [.., room, token] = words[..] {
            if let (Ok(room), Some(token)) = (RoomCode::parse(room), token_of(token)) {
                break (room, token);
            }
        }
        if lines > 20 {
            bail!("the client printed no room and token");
        }
        let (next, more) = read_line(rest, PATIENCE);
        (line, rest, lines) = (next, Box::new(more), lines + 1);
    };

    // Ben sits down: the break's clock starts, ann (the killed process) to move.
    let mut ben = Player::connect(&server.invite).await?;
    let sat_down = Instant::now();
    ben.send(ClientMessage::Join {
        room: room.clone(),
        name: "ben".into(),
    })
    .await?;
    let first = clock_told(&mut ben).await?;
    let seated = Instant::now();
    assert_eq!(first, CLOCK_MS);

    tokio::time::sleep(Duration::from_secs(3)).await;
    child.child().kill()?;
    let killed = Instant::now();
    let left = ben
        .until("PlayerLeft", |m| {
            matches!(m, ServerMessage::PlayerLeft { .. })
        })
        .await?;
    let noticed = killed.elapsed();
    assert!(
        matches!(left, ServerMessage::PlayerLeft { seat: Seat::A, .. }),
        "{left:?}"
    );
    eprintln!("a killed client was seen gone after {noticed:?}");
    assert!(
        noticed < IDLE_TIMEOUT + Duration::from_secs(5),
        "seen gone only after {noticed:?}"
    );

    // Ann comes back later with her token: the clock runs on from where it stopped, the
    // moment she fell silent (her last keep-alive, at most a second before the kill), not
    // from when the server noticed.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let mut ann = Player::connect(&server.invite).await?;
    ann.send(ClientMessage::Rejoin { token }).await?;
    let resumed = clock_told(&mut ben).await?;
    let most = CLOCK_MS - ms(killed.duration_since(seated)) + 1_500;
    let least = CLOCK_MS - ms(killed.duration_since(sat_down)) - 500;
    eprintln!("the clock resumed at {resumed} ms (between {least} and {most})");
    assert!(
        (least..=most).contains(&resumed),
        "resumed at {resumed} ms, expected {least}..={most}"
    );
    let _ = child.wait(PATIENCE);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread")]
async fn a_restarted_server_gives_the_player_to_move_the_time_that_was_left() -> Result<()> {
    let data = scratch("drops-restart");
    let port = std::net::UdpSocket::bind("127.0.0.1:0")?
        .local_addr()?
        .port();
    let addr = SocketAddr::from(([127, 0, 0, 1], port));
    let server = TestServer::start_at(addr, data.path()).await?;

    let mut ann = Player::connect(&server.invite).await?;
    ann.send(ClientMessage::CreateRoom {
        variant: eight_ball(),
        mode: clocked(),
        aim_aid: AimAid::Full,
        name: "ann".into(),
    })
    .await?;
    let room = match ann
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    {
        ServerMessage::Joined { snapshot, .. } => snapshot.room,
        _ => unreachable!(),
    };
    let token_a = ann.client.token().context("ann's token")?;
    let mut ben = Player::connect(&server.invite).await?;
    let sat_down = Instant::now();
    ben.send(ClientMessage::Join {
        room,
        name: "ben".into(),
    })
    .await?;
    clock_told(&mut ben).await?;
    let seated = Instant::now();
    let token_b = ben.client.token().context("ben's token")?;

    // The server stops in an orderly way (as on SIGTERM) three seconds into ann's turn, and
    // stays down for three more.
    tokio::time::sleep(Duration::from_secs(3)).await;
    let stopping = Instant::now();
    server.stop().await?;
    let stopped = Instant::now();
    drop((ann, ben));
    tokio::time::sleep(Duration::from_secs(3)).await;

    let server = TestServer::start_at(addr, data.path()).await?;
    assert_eq!(server.restored, 1);
    let mut ann = Player::connect(&server.invite).await?;
    ann.send(ClientMessage::Rejoin { token: token_a }).await?;
    ann.until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    let mut ben = Player::connect(&server.invite).await?;
    ben.send(ClientMessage::Rejoin { token: token_b }).await?;
    let resumed = clock_told(&mut ann).await?;
    // What ran before the stop is gone; the time the server was down is not.
    let most = CLOCK_MS - ms(stopping.duration_since(seated));
    let least = CLOCK_MS - ms(stopped.duration_since(sat_down)) - 500;
    eprintln!("after the restart the clock runs from {resumed} ms (between {least} and {most})");
    assert!(
        (least..=most).contains(&resumed),
        "resumed at {resumed} ms, expected {least}..={most}"
    );
    server.stop().await
}
