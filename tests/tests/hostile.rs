//! Hostile clients against a real server while two bots play a normal game on it: bad
//! frames, messages in the wrong state, floods, handshakes that never finish and a client
//! that never reads. Each must cost only its own connection, the game must finish with
//! every hash agreeing, and the server's queues and connection counts must stay bounded.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use anyhow::{anyhow, bail, Context, Result};
use breakshot_client::bot::{run, BotConfig};
use breakshot_client::net::client_config;
use breakshot_server::{Limits, Stats};
use breakshot_shared::protocol::{
    encode_frame, reference_hash, ClientMessage, ErrorCode, Fingerprint, ServerMessage,
    PROTOCOL_VERSION,
};
use breakshot_tests::{
    break_shot, create_room, hello_of, prove_of, read_message, resident_bytes, scratch, Player,
    Reads, TestServer, PATIENCE,
};

/// Half-open handshakes the test server allows before it asks for retries.
const HANDSHAKES: usize = 64;
/// The test server's outgoing queue per client (small, so a non-reader fills it soon).
const QUEUE: usize = 16;
/// Connection attempts that never finish their handshake.
const HALF_OPEN: usize = 1_000;

fn hostile_limits() -> Limits {
    Limits {
        max_handshakes: HANDSHAKES,
        outbound_queue: QUEUE,
        frame_timeout: Duration::from_secs(1),
        ..Limits::default()
    }
}

/// A QUIC connection with the stream open and nothing sent: the test writes raw bytes.
struct Raw {
    _endpoint: quinn::Endpoint,
    conn: quinn::Connection,
    send: quinn::SendStream,
    recv: quinn::RecvStream,
}

impl Raw {
    /// Connects with a receive window of `window` bytes (what the client lets the server
    /// send before it reads).
    async fn connect(server: &TestServer, window: u32) -> Result<Raw> {
        let mut config = client_config(server.invite.fingerprint).map_err(|e| anyhow!(e))?;
        let mut transport = quinn::TransportConfig::default();
        transport.stream_receive_window(window.into());
        transport.receive_window(window.into());
        transport.keep_alive_interval(Some(Duration::from_secs(5)));
        config.transport_config(Arc::new(transport));
        let endpoint = quinn::Endpoint::client(SocketAddr::from(([127, 0, 0, 1], 0)))?;
        let conn = endpoint
            .connect_with(config, server.addr, "breakshot")?
            .await?;
        let (send, recv) = conn.open_bi().await?;
        Ok(Raw {
            _endpoint: endpoint,
            conn,
            send,
            recv,
        })
    }

    async fn write(&mut self, bytes: &[u8]) -> Result<()> {
        Ok(self.send.write_all(bytes).await?)
    }

    /// Says `Hello` as a fresh player and proves its key: the server's `Welcome` is on its way.
    async fn hello(&mut self) -> Result<()> {
        let me = breakshot_client::net::fresh_identity();
        self.write(&encode_frame(&hello_of(&me)?)?).await?;
        let challenge = self.read().await?;
        self.write(&encode_frame(&prove_of(&me, &challenge)?)?)
            .await
    }

    /// Reads one message from the server.
    async fn read(&mut self) -> Result<ServerMessage> {
        read_message(&mut self.recv).await
    }

    /// Waits for the server to close the connection and returns its reason.
    async fn closed(&self) -> Result<String> {
        let why = tokio::time::timeout(PATIENCE, self.conn.closed())
            .await
            .map_err(|_| anyhow!("the server never closed the connection"))?;
        match why {
            quinn::ConnectionError::ApplicationClosed(close) => {
                Ok(String::from_utf8_lossy(&close.reason).into_owned())
            }
            other => bail!("closed otherwise: {other}"),
        }
    }
}

/// Bytes from a fixed generator (xorshift), different for each `seed`.
fn noise(seed: u64, len: usize) -> Vec<u8> {
    let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect()
}

/// The address the half-open handshakes come from: not the players' 127.0.0.1 (all of
/// 127.0.0.0/8 is loopback on Linux).
const ABUSER: [u8; 4] = [127, 0, 0, 2];

/// Starts `n` connections through a relay that passes the client's packets to the server
/// from [`ABUSER`] and drops every answer but a QUIC retry, so each attempt proves its
/// address (as any real host can) and none ever finishes its handshake. Returns what keeps
/// them alive (dropping it lets the client side give up).
async fn half_open(server: SocketAddr, fingerprint: Fingerprint, n: usize) -> Result<impl Drop> {
    let front = Arc::new(tokio::net::UdpSocket::bind("127.0.0.1:0").await?);
    let back = Arc::new(tokio::net::UdpSocket::bind(SocketAddr::from((ABUSER, 0))).await?);
    let relay_addr = front.local_addr()?;
    let client = Arc::new(std::sync::Mutex::new(None::<SocketAddr>));
    let outward = {
        let (front, back, client) = (front.clone(), back.clone(), client.clone());
        async move {
            let mut buf = vec![0u8; 65_536];
            while let Ok((len, from)) = front.recv_from(&mut buf).await {
                *client.lock().unwrap_or_else(|e| e.into_inner()) = Some(from);
                let _ = back.send_to(&buf[..len], server).await;
            }
        }
    };
    let inward = async move {
        let mut buf = vec![0u8; 65_536];
        while let Ok((len, _)) = back.recv_from(&mut buf).await {
            // A long-header packet of type Retry (QUIC v1: 0b1x11_xxxx).
            let retry = len > 0 && buf[0] & 0xb0 == 0xb0;
            let to = *client.lock().unwrap_or_else(|e| e.into_inner());
            if let (true, Some(to)) = (retry, to) {
                let _ = front.send_to(&buf[..len], to).await;
            }
        }
    };
    let relay = tokio::spawn(async move {
        tokio::join!(outward, inward);
    });
    let endpoint = quinn::Endpoint::client(SocketAddr::from(([127, 0, 0, 1], 0)))?;
    let config = client_config(fingerprint).map_err(|e| anyhow!(e))?;
    let mut pending = Vec::with_capacity(n);
    for i in 0..n {
        pending.push(endpoint.connect_with(config.clone(), relay_addr, "breakshot")?);
        if i % 50 == 49 {
            // Let the relay keep up, so few first packets are lost in the socket buffers.
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    }
    struct Flood {
        relay: tokio::task::JoinHandle<()>,
        _pending: Vec<quinn::Connecting>,
        endpoint: quinn::Endpoint,
    }
    impl Drop for Flood {
        fn drop(&mut self) {
            self.relay.abort();
            self.endpoint.close(0u32.into(), b"done");
        }
    }
    Ok(Flood {
        relay,
        _pending: pending,
        endpoint,
    })
}

fn count(c: &std::sync::atomic::AtomicUsize) -> usize {
    Stats::get(c)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hostile_clients_cost_only_their_own_connections() -> Result<()> {
    let data = scratch("hostile");
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.limits = hostile_limits();
    let server = TestServer::start_with(config).await?;
    let stats = server.stats.clone();
    let rss_before = resident_bytes();

    // Handshakes that never finish, all from one address: it holds at most its share of
    // the handshakes; the rest are refused.
    let flood = half_open(server.addr, server.invite.fingerprint, HALF_OPEN).await?;
    let deadline = tokio::time::Instant::now() + PATIENCE;
    let seen = || count(&stats.handshaking) + count(&stats.retried) + count(&stats.refused_address);
    while seen() < HALF_OPEN {
        if tokio::time::Instant::now() > deadline {
            bail!(
                "the server saw only {} of the handshakes: {stats:?}",
                seen()
            );
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let share = hostile_limits().handshakes_per_address();
    assert!(count(&stats.handshaking) <= share, "{stats:?}");
    eprintln!(
        "{HALF_OPEN} silent handshakes from one address: {} held, {} refused",
        count(&stats.handshaking),
        count(&stats.refused_address)
    );

    // A normal game, played while everything below goes on. Its clients pass the retry.
    let bots = {
        let invite = server.invite.clone();
        tokio::spawn(async move { run(&BotConfig::new(invite, 1)).await })
    };

    // An oversized length prefix, before anything else.
    let mut big = Raw::connect(&server, 1 << 20).await?;
    big.write(&[0xff, 0xff, 0xff, 0xff]).await?;
    let why = big.closed().await?;
    assert!(why.contains("exceeds"), "{why}");

    // Hostile handshakes: a key of the wrong length, a forged signature, a proof replayed
    // from another connection. Each is refused with its reason and closed.
    let mut short = Raw::connect(&server, 1 << 20).await?;
    let mut hello = hello_of(&breakshot_client::net::fresh_identity())?;
    if let ClientMessage::Hello { key, .. } = &mut hello {
        key.truncate(31);
    }
    short.write(&encode_frame(&hello)?).await?;
    assert!(
        matches!(short.read().await?, ServerMessage::Reject { reason } if reason.contains("32 bytes, not 31"))
    );
    assert!(short.closed().await?.contains("not 31"));

    let ann = breakshot_client::net::fresh_identity();
    let mut forger = Raw::connect(&server, 1 << 20).await?;
    forger.write(&encode_frame(&hello_of(&ann)?)?).await?;
    let challenge = forger.read().await?;
    let forged = prove_of(&breakshot_client::net::fresh_identity(), &challenge)?;
    forger.write(&encode_frame(&forged)?).await?;
    assert!(matches!(forger.read().await?, ServerMessage::Reject { .. }));
    assert!(forger.closed().await?.contains("does not prove the key"));

    let mut honest = Raw::connect(&server, 1 << 20).await?;
    honest.write(&encode_frame(&hello_of(&ann)?)?).await?;
    let proof = prove_of(&ann, &honest.read().await?)?;
    honest.write(&encode_frame(&proof)?).await?;
    assert!(matches!(
        honest.read().await?,
        ServerMessage::Welcome { .. }
    ));
    let mut replayer = Raw::connect(&server, 1 << 20).await?;
    replayer.write(&encode_frame(&hello_of(&ann)?)?).await?;
    assert!(matches!(
        replayer.read().await?,
        ServerMessage::Challenge { .. }
    ));
    replayer.write(&encode_frame(&proof)?).await?;
    assert!(matches!(
        replayer.read().await?,
        ServerMessage::Reject { .. }
    ));
    assert!(replayer.closed().await?.contains("does not prove the key"));
    drop(honest);

    // A client of version 3, whose Hello has no key: told why in words, not cut off.
    #[derive(serde::Serialize)]
    enum OldClientMessage {
        Hello { protocol: u32, physics: u64 },
    }
    let mut old = Raw::connect(&server, 1 << 20).await?;
    let v3 = OldClientMessage::Hello {
        protocol: 3,
        physics: reference_hash()?,
    };
    old.write(&encode_frame(&v3)?).await?;
    assert!(matches!(old.read().await?, ServerMessage::Reject { reason }
        if reason.contains(&format!("protocol version 3 is not supported; this server speaks version {PROTOCOL_VERSION}"))));

    // A truncated frame: a length, part of the payload, then the end of the stream.
    let mut cut = Raw::connect(&server, 1 << 20).await?;
    cut.hello().await?;
    cut.write(&[0, 0, 0, 100, 1, 2, 3]).await?;
    cut.send.finish()?;
    assert_eq!(cut.closed().await?, "truncated frame");

    // A truncated frame whose sender stalls: closed when the frame takes too long.
    let mut stall = Raw::connect(&server, 1 << 20).await?;
    stall.hello().await?;
    stall.write(&[0, 0, 0, 100, 1, 2, 3]).await?;
    assert_eq!(stall.closed().await?, "a frame took too long to arrive");

    // Random bytes, with and without a greeting first: every one is closed.
    for seed in 0..20 {
        let mut r = Raw::connect(&server, 1 << 20).await?;
        if seed % 2 == 1 {
            r.hello().await?;
        }
        r.write(&noise(seed, 1 + (seed as usize * 397) % 3000))
            .await?;
        r.send.finish()?;
        r.closed().await.with_context(|| format!("noise {seed}"))?;
    }

    // A valid frame before Hello.
    let mut early = Raw::connect(&server, 1 << 20).await?;
    early.write(&encode_frame(&ClientMessage::Concede)?).await?;
    assert_eq!(early.closed().await?, "the first message must be Hello");

    // Valid frames in the wrong state: a shot before joining, a second join.
    let mut host = Player::connect(&server.invite).await?;
    let room = create_room(&mut host, "host").await?;
    let mut guest = Player::connect(&server.invite).await?;
    let game = host.game().expect("snapshot").clone();
    guest.send(break_shot(&game)).await?;
    assert!(matches!(
        guest.error().await?,
        ServerMessage::Error {
            code: ErrorCode::Unexpected,
            ..
        }
    ));
    for _ in 0..2 {
        guest
            .send(ClientMessage::Join {
                room: room.clone(),
                name: "guest".into(),
            })
            .await?;
    }
    guest
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    assert!(matches!(
        guest.error().await?,
        ServerMessage::Error {
            code: ErrorCode::Unexpected,
            ..
        }
    ));

    // A flood: far more messages than the per-second limit allows, then disconnected.
    let mut flooder = Player::connect(&server.invite).await?;
    let frame = encode_frame(&ClientMessage::Concede)?;
    let burst: Vec<u8> = frame.repeat(3_000);
    let _ = flooder.client.send_raw(&burst).await;
    let why =
        tokio::time::timeout(PATIENCE, flooder.client.quic().expect("connected").closed()).await?;
    assert!(why.to_string().contains("too many messages"), "{why}");

    // A client that never reads: its window is a few hundred bytes, so everything it is sent
    // beyond that waits in its queue until the queue is full and it is dropped.
    let mut deaf = Raw::connect(&server, 256).await?;
    deaf.hello().await?;
    for _ in 0..45 {
        deaf.write(&encode_frame(&ClientMessage::Concede)?).await?;
    }
    assert_eq!(deaf.closed().await?, "not reading: outgoing queue full");

    // The game went on and finished with every hash agreeing.
    let report = tokio::time::timeout(PATIENCE, bots)
        .await
        .map_err(|_| anyhow!("the game beside the hostile clients never finished"))??;
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert_eq!(report.tally.desyncs, 0);
    assert_eq!(report.tally.confirmed, 2 * report.tally.shots);
    eprintln!(
        "the game beside them: {} shots, p50 {:.1} ms, p99 {:.1} ms",
        report.tally.shots,
        report.percentile_ms(0.5),
        report.percentile_ms(0.99)
    );

    // Bounded: handshakes held, queues, and every abuser counted once.
    assert!(count(&stats.handshaking) <= share);
    assert!(count(&stats.connections) <= Limits::default().max_connections);
    assert_eq!(count(&stats.flooding), 1);
    // The client that never reads is dropped for it; the flooder, which does not read its
    // replies either, may be dropped for the same reason before its flood is noticed.
    let too_slow = count(&stats.too_slow);
    assert!(
        (1..=2).contains(&too_slow),
        "{too_slow} clients dropped for not reading"
    );
    // The hub never had more waiting than one burst per connection.
    let peak = count(&stats.hub_queue_peak);
    assert!(peak <= 60 * 64, "hub queue peaked at {peak}");
    if let (Some(before), Some(after)) = (rss_before, resident_bytes()) {
        eprintln!(
            "resident memory of the test process: {} KiB before, {} KiB after; hub queue peak {peak}",
            before / 1024,
            after / 1024
        );
    }
    drop(flood);
    server.stop().await
}

/// The flood of the hardening report: with `--max-connections 300`, 400 handshakes from one
/// address that never finish used to hold every slot for 29 s. Now that address holds only
/// its share, and a player from another address gets in and plays every time.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn half_open_handshakes_from_one_address_never_lock_out_another() -> Result<()> {
    let limits = Limits {
        max_connections: 300,
        ..Limits::default()
    };
    games_beside_floods(limits, 400, 4).await
}

/// The other flood of the report, at the default limits: about 4,300 handshakes from one
/// address got other addresses refused for at least 5 s. A measurement more than a check
/// (run it in release for the figures in docs/operations.md):
/// `cargo test --release -p breakshot-tests --test hostile -- --ignored --nocapture`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "a measurement: run it by hand, in release"]
async fn a_default_server_lets_players_in_beside_a_4300_handshake_flood() -> Result<()> {
    games_beside_floods(Limits::default(), 4_300, 4).await
}

/// Plays `games` bot games from 127.0.0.1, each while a fresh flood of `flood` half-open
/// handshakes from [`ABUSER`] is at its height; every game must get in and finish, and the
/// flood's slots must be given back afterwards.
async fn games_beside_floods(limits: Limits, flood: usize, games: usize) -> Result<()> {
    let data = scratch("lockout");
    let mut config = TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), data.path());
    config.limits = limits.clone();
    let server = TestServer::start_with(config).await?;
    let stats = server.stats.clone();
    let before = resident_bytes();

    let started = std::time::Instant::now();
    let mut peak = 0;
    for game in 0..games {
        // A fresh flood before each game, so it is at its height while the players connect.
        let sent = half_open(server.addr, server.invite.fingerprint, flood).await?;
        let deadline = tokio::time::Instant::now() + PATIENCE;
        while count(&stats.handshaking) < limits.handshakes_per_address() {
            if tokio::time::Instant::now() > deadline {
                bail!("the flood never reached the server: {stats:?}");
            }
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        let mut bots = BotConfig::new(server.invite.clone(), 1);
        bots.seed = 100 + game as u64;
        let report = tokio::time::timeout(PATIENCE, run(&bots))
            .await
            .map_err(|_| anyhow!("game {game} did not finish"))?;
        assert!(report.errors.is_empty(), "game {game}: {:?}", report.errors);
        assert_eq!(report.games_completed, 1, "game {game}");
        assert_eq!(report.tally.desyncs, 0);
        assert!(count(&stats.handshaking) <= limits.handshakes_per_address() + 2);
        peak = peak.max(resident_bytes().unwrap_or(0));
        drop(sent);
    }
    assert!(count(&stats.refused_address) > 0, "{stats:?}");
    eprintln!(
        "{games} games played beside {flood}-handshake floods (max_connections {}) in {:.1} s; \
         {} attempts refused to the flooding address; this process's memory {} MB before, \
         {} MB at most",
        limits.max_connections,
        started.elapsed().as_secs_f64(),
        count(&stats.refused_address),
        before.unwrap_or(0) >> 20,
        peak >> 20,
    );
    // Abandoned handshakes give their slots back within the handshake timeout.
    let deadline = tokio::time::Instant::now() + limits.handshake_timeout + PATIENCE;
    while count(&stats.handshaking) > 0 || count(&stats.connections) > 0 {
        if tokio::time::Instant::now() > deadline {
            bail!("slots were never given back: {stats:?}");
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    server.stop().await
}
