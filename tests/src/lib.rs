//! What the integration tests share: an in-process server on 127.0.0.1 over real QUIC, a
//! scratch data directory, and a scripted player on the client core (network client and replica).

use std::future::Future;
use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context, Result};
use breakshot_client::bot::{run, BotConfig, Report};
use breakshot_client::net::{
    fetch_record, Client, ClientEvent, HostOptions, Reconnect, Session, SessionEvent,
};
use breakshot_client::play::{GameEvent, GameFlow, GameLink, Replica};
use breakshot_server::webcert::WebCerts;
use breakshot_server::{Config, Server, ServerError, Stats};
use breakshot_shared::physics::{BallState, Strike};
use breakshot_shared::protocol::{
    decode_payload, payload_len, AimAid, ClientMessage, Invite, Role, RoomCode, ServerMessage,
    WebLink, HEADER_LEN,
};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::Game;
use breakshot_shared::rules::{EightBallRules, Settings, Variant};
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

/// How long a test waits for a message before calling the server stuck. Generous: it only
/// turns a hang into a failure, it never measures speed.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// The seed of the test servers' randomness.
pub const SEED: u64 = 2026;

pub use breakshot_testkit::{scratch, TempDir};

/// A handshake spoken by hand (over a raw stream): the `Hello` for `identity` ...
pub fn hello_of(identity: &breakshot_shared::protocol::Identity) -> Result<ClientMessage> {
    Ok(ClientMessage::Hello {
        protocol: breakshot_shared::protocol::PROTOCOL_VERSION,
        physics: breakshot_shared::protocol::reference_hash()?,
        key: identity.public().0.to_vec(),
    })
}

/// ... and the `Prove` that answers the server's `Challenge` to it.
pub fn prove_of(
    identity: &breakshot_shared::protocol::Identity,
    answer: &ServerMessage,
) -> Result<ClientMessage> {
    let ServerMessage::Challenge { nonce } = answer else {
        bail!("expected a Challenge, got {answer:?}");
    };
    Ok(ClientMessage::Prove {
        signature: identity.sign(
            nonce,
            breakshot_shared::protocol::PROTOCOL_VERSION,
            breakshot_shared::protocol::reference_hash()?,
        ),
    })
}

pub mod postgres;
pub mod web;

/// The body of a test binary run again as a server process: prints the invite, then serves
/// `config` until the process is killed.
pub fn serve_until_killed(config: &Config) {
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    runtime.block_on(async {
        let server = Server::bind(config).expect("binding");
        println!("{}", server.invite());
        server.run(std::future::pending()).await.expect("serving");
    });
}

/// The invite a server process prints on `out` (the test harness may speak first on the
/// same line: the invite starts at its scheme), or None if none comes within [`PATIENCE`].
/// Read on a thread of its own, so a server that never prints it cannot hang the test.
pub fn printed_invite(out: std::process::ChildStdout) -> Option<Invite> {
    use std::io::{BufRead, BufReader};
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let invite = BufReader::new(out)
            .lines()
            .map_while(std::result::Result::ok)
            .find_map(|line| {
                let at = line.find("breakshot://")?;
                line[at..].trim().parse::<Invite>().ok()
            });
        let _ = tx.send(invite);
    });
    rx.recv_timeout(PATIENCE).ok().flatten()
}

/// A server running in this process.
pub struct TestServer {
    pub invite: Invite,
    pub addr: SocketAddr,
    pub restored: usize,
    /// The Noise public key of its WebSocket ([`Server::web_key`]).
    pub web_key: [u8; 32],
    /// Its web listener's TCP address, when `Config::web_dir` was set.
    pub web_addr: Option<SocketAddr>,
    /// The running server's live counters.
    pub stats: Arc<Stats>,
    /// The page's link to the server, when it serves the web client (`Config::web_dir`).
    pub web_link: Option<WebLink>,
    /// The running server's certificates for browsers (WebTransport).
    pub web_certs: WebCerts,
    stop: Option<oneshot::Sender<()>>,
    task: JoinHandle<Result<(), ServerError>>,
}

impl TestServer {
    /// Starts a server on a free loopback port.
    pub async fn start(data: &Path) -> Result<TestServer> {
        Self::start_at(SocketAddr::from(([127, 0, 0, 1], 0)), data).await
    }

    /// [`TestServer::start`] on a fresh [`scratch`] folder named after `name`, returned with
    /// the server: the folder is removed when dropped, so keep it while the server runs.
    pub async fn start_fresh(name: &str) -> Result<(TempDir, TestServer)> {
        let data = scratch(name);
        let server = Self::start(data.path()).await?;
        Ok((data, server))
    }

    /// Starts a server on `addr`. Its room codes, tokens and game seeds come from a fixed
    /// seed, so every run of a test plays the same games.
    pub async fn start_at(addr: SocketAddr, data: &Path) -> Result<TestServer> {
        Self::start_with(Self::config(addr, data)).await
    }

    /// The configuration [`TestServer::start_at`] uses, to change before
    /// [`TestServer::start_with`].
    pub fn config(addr: SocketAddr, data: &Path) -> Config {
        let mut config = Config::new(addr, data.to_path_buf());
        config.predictable_seed = Some(SEED);
        config
    }

    pub async fn start_with(config: Config) -> Result<TestServer> {
        // A port just released by a stopped server can take a moment to be free again.
        let mut tries = 0;
        let server = loop {
            match Server::bind(&config) {
                Err(ServerError::Bind { source, .. })
                    if source.kind() == std::io::ErrorKind::AddrInUse && tries < 100 =>
                {
                    tries += 1;
                    tokio::time::sleep(Duration::from_millis(50)).await;
                }
                other => break other?,
            }
        };
        let invite = server.invite();
        let addr = server.local_addr();
        let restored = server.restored();
        let web_key = server.web_key();
        let web_addr = server.web_addr();
        let stats = server.stats();
        let web_link = server.web_link(None);
        let web_certs = server.web_certs();
        let (stop, stopped) = oneshot::channel::<()>();
        let task = tokio::spawn(server.run(async {
            let _ = stopped.await;
        }));
        Ok(TestServer {
            invite,
            addr,
            restored,
            web_key,
            web_addr,
            stats,
            web_link,
            web_certs,
            stop: Some(stop),
            task,
        })
    }

    /// Waits up to `patience` for the server to stop by itself (a drain that finished);
    /// `Ok(false)` if it is still running then (it is stopped before returning).
    pub async fn stopped_by_itself(mut self, patience: Duration) -> Result<bool> {
        match tokio::time::timeout(patience, &mut self.task).await {
            Ok(ran) => {
                ran??;
                Ok(true)
            }
            Err(_) => {
                self.stop().await?;
                Ok(false)
            }
        }
    }

    /// Stops the server as Ctrl-C would and waits until it has finished.
    pub async fn stop(mut self) -> Result<()> {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        (&mut self.task).await??;
        Ok(())
    }
}

/// What reads the server's messages one at a time: a native [`Player`] or a page's
/// [`web::WebPlayer`].
pub trait Reads: Send {
    /// The next message, within [`PATIENCE`].
    fn recv(&mut self) -> impl Future<Output = Result<ServerMessage>> + Send;

    /// Reads messages until one satisfies `want`, and returns it; an error or a refusal on
    /// the way fails the wait, as does the connection's end.
    fn until(
        &mut self,
        what: &str,
        want: impl Fn(&ServerMessage) -> bool + Send,
    ) -> impl Future<Output = Result<ServerMessage>> + Send {
        async move {
            loop {
                let msg = self
                    .recv()
                    .await
                    .with_context(|| format!("waiting for {what}"))?;
                if want(&msg) {
                    return Ok(msg);
                }
                if let ServerMessage::Error { .. } | ServerMessage::Reject { .. } = msg {
                    bail!("waiting for {what}, got {msg:?}");
                }
            }
        }
    }
}

impl Reads for Player {
    fn recv(&mut self) -> impl Future<Output = Result<ServerMessage>> + Send {
        Player::recv(self)
    }
}

/// A scripted client: the client core's network client (with no reconnect, so a test
/// scripts every connection) and its replica of the game.
pub struct Player {
    /// The network client.
    pub client: Client,
    /// The copy of the game, fed every message received.
    pub replica: Replica,
}

impl Player {
    /// Connects and says hello, once.
    pub async fn connect(invite: &Invite) -> Result<Player> {
        Player::connect_with(invite, Reconnect::never()).await
    }

    /// Connects and says hello, reconnecting as `policy` says.
    pub async fn connect_with(invite: &Invite, policy: Reconnect) -> Result<Player> {
        let client = Client::connect(invite.clone(), policy).await?;
        Ok(Player {
            client,
            replica: Replica::default(),
        })
    }

    /// Sends a message.
    pub async fn send(&mut self, msg: ClientMessage) -> Result<()> {
        Ok(self.client.send(&msg).await?)
    }

    /// The next message (applied to the replica). The client's own reconnections (with a
    /// policy that reconnects) are passed over: the server's `Joined` follows them.
    pub async fn recv(&mut self) -> Result<ServerMessage> {
        let msg = loop {
            let event = tokio::time::timeout(PATIENCE, self.client.recv())
                .await
                .map_err(|_| anyhow!("no message from the server"))??;
            if let ClientEvent::Message(msg) = event {
                break msg;
            }
        };
        let me = match self.client.role() {
            Some(Role::Player(seat)) => Some(seat),
            _ => None,
        };
        self.replica.observe(&msg, me);
        Ok(msg)
    }

    /// The game as this player's replica holds it.
    pub fn game(&self) -> Option<&Game> {
        self.replica.game()
    }

    /// Closes the connection at once, as a pulled cable would.
    pub fn pull_cable(&self) {
        if let Some(quic) = self.client.quic() {
            quic.close(0u32.into(), b"cable pulled");
        }
    }

    /// Reads messages until the server's resolution of a shot arrives: its state hash and
    /// the table after the rules.
    pub async fn shot_resolved(&mut self) -> Result<(u64, Vec<BallState>)> {
        match self
            .until("ShotResolved", |m| {
                matches!(m, ServerMessage::ShotResolved { .. })
            })
            .await?
        {
            ServerMessage::ShotResolved { hash, game, .. } => Ok((hash, game.balls().to_vec())),
            other => bail!("expected ShotResolved, got {other:?}"),
        }
    }

    /// Asks to join `room` as `name` and reads messages until `Joined`.
    pub async fn join(&mut self, room: &RoomCode, name: &str) -> Result<ServerMessage> {
        self.send(ClientMessage::Join {
            room: room.clone(),
            name: name.into(),
        })
        .await?;
        self.until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
            .await
    }

    /// Reads messages until the turn passes (`TurnChanged`).
    pub async fn turn_changed(&mut self) -> Result<()> {
        self.until("TurnChanged", |m| {
            matches!(m, ServerMessage::TurnChanged { .. })
        })
        .await
        .map(drop)
    }

    /// Reads messages until the turn passes or the game ends (`TurnChanged`, `GameOver`).
    pub async fn turn_over(&mut self) -> Result<()> {
        self.until("TurnChanged", |m| {
            matches!(
                m,
                ServerMessage::TurnChanged { .. } | ServerMessage::GameOver { .. }
            )
        })
        .await
        .map(drop)
    }

    /// Reads messages until an error arrives, and returns it.
    pub async fn error(&mut self) -> Result<ServerMessage> {
        loop {
            let msg = self.recv().await?;
            if let ServerMessage::Error { .. } = msg {
                return Ok(msg);
            }
        }
    }
}

/// Reads one frame of the wire format from a raw stream and decodes it; fails after
/// [`PATIENCE`]. For the tests that speak the protocol by hand, on any transport's stream.
pub async fn read_message(
    stream: &mut (impl tokio::io::AsyncRead + Unpin),
) -> Result<ServerMessage> {
    use tokio::io::AsyncReadExt;
    let read = async {
        let mut header = [0u8; HEADER_LEN];
        stream.read_exact(&mut header).await?;
        let mut payload = vec![0u8; payload_len(header)?];
        stream.read_exact(&mut payload).await?;
        anyhow::Ok(decode_payload(&payload)?)
    };
    tokio::time::timeout(PATIENCE, read)
        .await
        .map_err(|_| anyhow!("no message from the server"))?
}

/// The resident memory of this process in bytes (Linux), if it can be read.
pub fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}

pub fn eight_ball() -> Variant {
    Variant::EightBall(EightBallRules::Wpa)
}

/// Hosting as `ann` on a free port of 127.0.0.1 with its data in `data`, native players
/// only; the rest as [`HostOptions::new`] (8-ball, the online clock, every aid): the hosting
/// tests change only what they are about.
pub fn hosting_here(data: std::path::PathBuf) -> HostOptions {
    HostOptions {
        bind: ([127, 0, 0, 1], 0).into(),
        name: "ann".into(),
        web: None,
        ..HostOptions::new(data)
    }
}

/// The message that opens an 8-ball room with no clock and every aid, as `name`.
pub fn create_eight_ball(name: &str) -> ClientMessage {
    ClientMessage::CreateRoom {
        variant: eight_ball(),
        mode: Settings::offline(),
        aim_aid: AimAid::Full,
        name: name.into(),
    }
}

/// Creates an 8-ball room as `name` and returns its code.
pub async fn create_room(host: &mut Player, name: &str) -> Result<RoomCode> {
    host.send(create_eight_ball(name)).await?;
    match host
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    {
        ServerMessage::Joined { snapshot, .. } => Ok(snapshot.room),
        other => bail!("expected Joined, got {other:?}"),
    }
}

/// The bots' games of `config`, played to their end within `patience`: their report.
async fn played(config: &BotConfig, patience: Duration) -> Result<Report> {
    let games = config.games;
    tokio::time::timeout(patience, run(config))
        .await
        .map_err(|_| anyhow!("the bots' {games} game(s) did not finish within {patience:?}"))
}

/// `games` games between two bots through `server`, played to their end within
/// [`PATIENCE`]: the bots' report, unchecked (the server keeps running).
pub async fn bot_games(server: &TestServer, games: usize) -> Result<Report> {
    played(&BotConfig::new(server.invite.clone(), games), PATIENCE).await
}

/// One game between the bots of `config` through `server`, played to its end within
/// `patience`, then the server stopped: the bots' report, checked for what every such game
/// must give (no error, the one game completed, no desync, both players confirming every
/// shot they check: all of them, or the first and one in `config.check_every`), and the
/// game's record as the server stored it, checked finished.
pub async fn bot_game(
    server: TestServer,
    config: &BotConfig,
    patience: Duration,
) -> Result<(Report, GameRecord)> {
    let report = played(config, patience).await?;
    let room = report.games[0].room.clone().context("no room was opened")?;
    let fetched = fetch_record(&server.invite, &room).await?;
    server.stop().await?;
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert_eq!(report.tally.desyncs, 0);
    // Each player checks shots 1, 1 + N, 1 + 2N… of those it saw, the rest unchecked.
    let checked = report.tally.shots.div_ceil(config.check_every.max(1));
    assert_eq!(report.tally.confirmed, 2 * checked);
    assert_eq!(report.tally.unchecked, 2 * (report.tally.shots - checked));
    // Each shot's stages as the bots measured them: every shot accepted before its result
    // came back, and simulated by both players' replicas where they check it.
    let (shots, times) = (report.tally.shots as usize, &report.tally.times);
    assert_eq!(times.round_trip.len(), shots);
    assert_eq!(times.accepted.len(), shots);
    assert_eq!(times.received.len(), shots);
    // Each shot sent is timed on its way out (a refused one, sent again, twice).
    assert!(times.sent.len() >= shots, "{} shots sent", times.sent.len());
    let mut parts = times.received.iter().zip(&times.round_trip);
    assert!(parts.all(|(part, whole)| part <= whole));
    let mut pairs = times.accepted.iter().zip(&times.round_trip);
    assert!(pairs.all(|(a, r)| a <= r));
    assert_eq!(times.replica.len(), 2 * checked as usize);
    assert!(fetched.finished, "the stored game is not over");
    Ok((report, GameRecord::decode(&fetched.bytes)?))
}

/// Two players seated in a new 8-ball room: (host in seat A, guest in seat B, room).
pub async fn seated_pair(invite: &Invite) -> Result<(Player, Player, RoomCode)> {
    seated_pair_with(invite, Reconnect::never()).await
}

/// [`seated_pair`] with players that reconnect as `policy` says.
pub async fn seated_pair_with(
    invite: &Invite,
    policy: Reconnect,
) -> Result<(Player, Player, RoomCode)> {
    let mut a = Player::connect_with(invite, policy).await?;
    let room = create_room(&mut a, "alice").await?;
    let mut b = Player::connect_with(invite, policy).await?;
    b.join(&room, "bob").await?;
    a.until("PlayerJoined", |m| {
        matches!(m, ServerMessage::PlayerJoined { .. })
    })
    .await?;
    Ok((a, b, room))
}

/// A legal, hard break: the cue ball straight at the nearest ball.
pub fn break_shot(game: &Game) -> ClientMessage {
    let balls = game.balls();
    let cue = balls[0].pos;
    let target = balls[1..]
        .iter()
        .map(|b| b.pos)
        .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
        .unwrap_or(cue);
    ClientMessage::Shot {
        turn: game.turn(),
        strike: Strike {
            speed: 9.0,
            dir: (target - cue).normalize_or(glam::DVec2::Y),
            tip: glam::DVec2::ZERO,
            elevation_deg: 0.0,
        },
        call: None,
    }
}

/// Polls a session the way a frame loop does (`try_recv`, then a few milliseconds of
/// "drawing") until an event `want` accepts; fails on a closed session or after [`PATIENCE`].
pub fn poll_until(
    session: &mut Session,
    what: &str,
    want: impl Fn(&SessionEvent) -> bool,
) -> SessionEvent {
    poll_frames(
        what,
        || session.try_recv(),
        |event| {
            if want(event) {
                return true;
            }
            if let SessionEvent::Closed(why) = event {
                panic!("closed while waiting for {what}: {why}");
            }
            false
        },
    )
}

/// Polls a game link the way a game screen does, handing every event to the screen's
/// `flow`, until an event `want` accepts; fails after [`PATIENCE`].
pub fn poll_link_until(
    link: &mut dyn GameLink,
    flow: &mut GameFlow,
    what: &str,
    want: impl Fn(&GameEvent) -> bool,
) -> GameEvent {
    let next = || link.poll().inspect(|event| flow.handle(event.clone()));
    poll_frames(what, next, want)
}

/// The frame loop of [`poll_until`] and [`poll_link_until`]: takes every event `next` has
/// ready, then "draws" for a few milliseconds, until `want` accepts one; fails after
/// [`PATIENCE`].
fn poll_frames<E>(what: &str, mut next: impl FnMut() -> Option<E>, want: impl Fn(&E) -> bool) -> E {
    let start = Instant::now();
    loop {
        while let Some(event) = next() {
            if want(&event) {
                return event;
            }
        }
        assert!(start.elapsed() < PATIENCE, "no {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}
