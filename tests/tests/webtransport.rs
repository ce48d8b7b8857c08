//! WebTransport on the server's UDP port, as a browser reaches it: a real server, a real
//! WebTransport client pinning the short certificate's hash (as `serverCertificateHashes`
//! does), and native clients beside it still pinning the long-lived certificate.

use std::sync::atomic::Ordering::Relaxed;
use std::sync::Arc;
use std::time::{Duration, SystemTime};

use anyhow::{anyhow, bail, Context, Result};
use breakshot_server::webcert::{ClockRef, ManualClock};
use breakshot_shared::protocol::web::WEBTRANSPORT_PATH;
use breakshot_shared::protocol::{encode_frame, ClientMessage, Fingerprint, Invite, ServerMessage};
use breakshot_tests::{
    create_eight_ball, create_room, read_message, scratch, Player, Reads, TestServer, PATIENCE,
};
use web_transport_quinn::proto::ConnectError::WrongStatus;
use web_transport_quinn::quinn::rustls::pki_types::CertificateDer;
use web_transport_quinn::{
    ClientBuilder, ClientError, ConnectError, RecvStream, SendStream, Session,
};
use x509_parser::oid_registry::{OID_EC_P256, OID_KEY_TYPE_EC_PUBLIC_KEY};

/// A page's end of the game: the session and the one stream it opened.
struct Page {
    session: Session,
    send: SendStream,
    recv: RecvStream,
}

/// What a page would pass to `new WebTransport(...)`.
fn url(server: &TestServer, path: &str) -> Result<url::Url> {
    Ok(url::Url::parse(&format!(
        "https://127.0.0.1:{}{path}",
        server.addr.port()
    ))?)
}

/// Opens a WebTransport session to `path` trusting only `hashes`, as a page does.
async fn session(server: &TestServer, path: &str, hashes: &[Fingerprint]) -> Result<Session> {
    let client = ClientBuilder::new()
        .with_server_certificate_hashes(hashes.iter().map(|h| h.0.to_vec()).collect())?;
    let connect = client.connect(url(server, path)?);
    Ok(tokio::time::timeout(PATIENCE, connect)
        .await
        .map_err(|_| anyhow!("no WebTransport session in time"))??)
}

impl Page {
    async fn open(server: &TestServer, hashes: &[Fingerprint]) -> Result<Page> {
        let session = session(server, WEBTRANSPORT_PATH, hashes).await?;
        let (send, recv) = session.open_bi().await?;
        let mut page = Page {
            session,
            send,
            recv,
        };
        let me = breakshot_client::net::fresh_identity();
        page.send(&breakshot_tests::hello_of(&me)?).await?;
        let challenge = page.recv().await?;
        page.send(&breakshot_tests::prove_of(&me, &challenge)?)
            .await?;
        match page.recv().await? {
            ServerMessage::Welcome { .. } => Ok(page),
            other => bail!("expected Welcome, got {other:?}"),
        }
    }

    async fn send(&mut self, msg: &ClientMessage) -> Result<()> {
        self.send.write_all(&encode_frame(msg)?).await?;
        Ok(())
    }

    async fn recv(&mut self) -> Result<ServerMessage> {
        read_message(&mut self.recv).await
    }

    async fn until(&mut self, what: &str, want: impl Fn(&ServerMessage) -> bool) -> Result<()> {
        loop {
            let msg = self.recv().await?;
            if want(&msg) {
                return Ok(());
            }
            if let ServerMessage::Error { .. } | ServerMessage::Reject { .. } = msg {
                bail!("waiting for {what}, got {msg:?}");
            }
        }
    }
}

/// The certificate a connection was shown.
fn shown(conn: &web_transport_quinn::quinn::Connection) -> Result<CertificateDer<'static>> {
    let identity = conn.peer_identity().context("no certificate shown")?;
    let chain = identity
        .downcast::<Vec<CertificateDer<'static>>>()
        .map_err(|_| anyhow!("not a certificate chain"))?;
    chain.first().cloned().context("an empty chain")
}

fn sha256(cert: &CertificateDer<'_>) -> Fingerprint {
    breakshot_server::tls::fingerprint_of(cert)
}

/// A native client pins the invite's fingerprint: connecting at all proves it was shown the
/// long-lived certificate; the certificate's own hash is checked too.
async fn native_sees_the_long_lived_certificate(invite: &Invite) -> Result<Player> {
    let player = Player::connect(invite).await?;
    let conn = player.client.quic().context("not connected")?;
    assert_eq!(sha256(&shown(conn)?), invite.fingerprint);
    Ok(player)
}

#[tokio::test]
async fn a_page_says_hello_creates_a_room_and_a_native_player_joins_it() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web").await?;
    let hashes = server.web_certs.hashes();
    assert_eq!(hashes.len(), 1);
    let mut page = Page::open(&server, &hashes).await?;

    // The certificate shown is the short one, fit for serverCertificateHashes.
    let cert = shown(&page.session)?;
    assert_eq!(sha256(&cert), hashes[0]);
    assert_ne!(sha256(&cert), server.invite.fingerprint);
    let (_, parsed) = x509_parser::parse_x509_certificate(cert.as_ref())?;
    let key = &parsed.public_key().algorithm;
    assert_eq!(key.algorithm, OID_KEY_TYPE_EC_PUBLIC_KEY);
    assert_eq!(
        key.parameters.as_ref().and_then(|p| p.as_oid().ok()),
        Some(OID_EC_P256)
    );
    let validity = parsed.validity();
    let days = (validity.not_after.timestamp() - validity.not_before.timestamp()) as f64 / 86400.0;
    assert!(days <= 14.0, "valid {days} days");
    assert!(validity.is_valid(), "not valid now");

    page.send(&create_eight_ball("page")).await?;
    let room = loop {
        match page.recv().await? {
            ServerMessage::Joined { snapshot, .. } => break snapshot.room,
            ServerMessage::Error { .. } | ServerMessage::Reject { .. } => bail!("no room"),
            _ => {}
        }
    };
    let mut native = native_sees_the_long_lived_certificate(&server.invite).await?;
    native.join(&room, "native").await?;
    page.until(
        "PlayerJoined",
        |m| matches!(m, ServerMessage::PlayerJoined { name, .. } if name == "native"),
    )
    .await?;
    assert_eq!(server.stats.webtransport_sessions.load(Relaxed), 1);
    // Both ways in are one connection each to the gate and the hub.
    assert_eq!(server.stats.connections.load(Relaxed), 2);
    drop((page, native));
    server.stop().await
}

#[tokio::test]
async fn a_page_joins_a_room_a_native_player_made() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web").await?;
    let mut host = Player::connect(&server.invite).await?;
    let room = create_room(&mut host, "native").await?;
    let mut page = Page::open(&server, &server.web_certs.hashes()).await?;
    page.send(&ClientMessage::Join {
        room,
        name: "page".into(),
    })
    .await?;
    page.until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    host.until(
        "PlayerJoined",
        |m| matches!(m, ServerMessage::PlayerJoined { name, .. } if name == "page"),
    )
    .await?;
    drop((page, host));
    server.stop().await
}

#[tokio::test]
async fn another_path_is_refused_with_404() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web").await?;
    let refused = session(&server, "/elsewhere", &server.web_certs.hashes()).await;
    match refused {
        Err(e) => match e.downcast_ref::<ClientError>() {
            Some(ClientError::HttpError(ConnectError::ProtoError(WrongStatus(Some(status))))) => {
                assert_eq!(status.as_u16(), 404)
            }
            _ => bail!("refused, but not with 404: {e:#}"),
        },
        Ok(_) => bail!("a session on another path"),
    }
    // Counted once the server has let the page read its 404 and closed.
    let counted = async {
        while server.stats.webtransport_refused.load(Relaxed) == 0 {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    };
    tokio::time::timeout(PATIENCE, counted)
        .await
        .map_err(|_| anyhow!("the refusal was not counted"))?;
    assert_eq!(server.stats.webtransport_refused.load(Relaxed), 1);
    // The right path still works after a refusal.
    drop(Page::open(&server, &server.web_certs.hashes()).await?);
    server.stop().await
}

#[tokio::test]
async fn a_page_with_a_wrong_hash_is_not_connected() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web").await?;
    // The long-lived certificate's hash is not the one h3 is shown; nor is a made-up one.
    for wrong in [server.invite.fingerprint, Fingerprint([7; 32])] {
        let e = match session(&server, WEBTRANSPORT_PATH, &[wrong]).await {
            Err(e) => e,
            Ok(_) => bail!("connected with a wrong hash"),
        };
        assert!(
            matches!(
                e.downcast_ref::<ClientError>(),
                Some(ClientError::Connection(_))
            ),
            "{e:#}"
        );
    }
    server.stop().await
}

#[tokio::test]
async fn a_rotation_serves_a_new_certificate_lists_the_old_and_leaves_native_pins_alone(
) -> Result<()> {
    let data = scratch("web");
    let time = Arc::new(ManualClock::new(SystemTime::now()));
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.clock = ClockRef(time.clone());
    let server = TestServer::start_with(config).await?;
    let old = server.web_certs.hashes();
    drop(native_sees_the_long_lived_certificate(&server.invite).await?);

    // Eleven days on, the certificate has less than two days left: the server's own check
    // would replace it within a minute; the test does not wait for that.
    time.advance(Duration::from_secs(11 * 86400));
    assert!(server.web_certs.refresh()?);
    let new = server.web_certs.hashes();
    assert_eq!(new.len(), 2);
    assert_ne!(new[0], old[0]);
    assert_eq!(new[1], old[0], "the old hash stays listed");

    // New sessions are shown the new certificate; a page knowing only the old hash no
    // longer connects, one with the list does.
    let page = Page::open(&server, &new).await?;
    assert_eq!(sha256(&shown(&page.session)?), new[0]);
    assert!(session(&server, WEBTRANSPORT_PATH, &old).await.is_err());
    drop(page);
    drop(native_sees_the_long_lived_certificate(&server.invite).await?);

    // Two days later the old one has expired and is no longer listed.
    time.advance(Duration::from_secs(2 * 86400));
    assert_eq!(server.web_certs.hashes(), vec![new[0]]);
    server.stop().await
}

#[tokio::test]
async fn a_restart_keeps_the_hashes_a_link_carries() -> Result<()> {
    let (data, server) = TestServer::start_fresh("web").await?;
    let hashes = server.web_certs.hashes();
    let invite = server.invite.clone();
    server.stop().await?;

    let server = TestServer::start(data.path()).await?;
    assert_eq!(server.web_certs.hashes(), hashes);
    assert_eq!(server.invite.fingerprint, invite.fingerprint);
    drop(Page::open(&server, &hashes).await?);
    server.stop().await
}

#[tokio::test]
async fn a_session_that_opens_no_stream_is_closed_after_the_open_timeout() -> Result<()> {
    let data = scratch("web");
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.limits.open_timeout = Duration::from_millis(300);
    let server = TestServer::start_with(config).await?;
    let idle = session(&server, WEBTRANSPORT_PATH, &server.web_certs.hashes()).await?;
    let closed = tokio::time::timeout(PATIENCE, idle.closed())
        .await
        .map_err(|_| anyhow!("a session without a stream is still open"))?;
    assert!(closed.to_string().contains("no stream"), "{closed}");
    server.stop().await
}

#[tokio::test]
async fn a_session_counts_against_the_connection_limit_like_a_native_connection() -> Result<()> {
    let data = scratch("web");
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.limits.max_connections = 1;
    let server = TestServer::start_with(config).await?;
    let native = Player::connect(&server.invite).await?;
    assert!(
        session(&server, WEBTRANSPORT_PATH, &server.web_certs.hashes())
            .await
            .is_err(),
        "a session beyond the limit"
    );
    assert_eq!(server.stats.refused.load(Relaxed), 1);
    drop(native);
    server.stop().await
}

/// Chromium closes a connection whose handshake offers fewer than three unidirectional
/// streams ("new unidirectional limit 0 decreases the current limit: 3"), and the offer is
/// made before the ALPN is known: every connection is offered them from the start, a native
/// one too (which is then given no more).
#[tokio::test]
async fn the_handshake_offers_the_streams_http3_needs() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web").await?;
    let native = Player::connect(&server.invite).await?;
    let conn = native.client.quic().context("not connected")?;
    for n in 0..3 {
        tokio::time::timeout(Duration::from_secs(5), conn.open_uni())
            .await
            .map_err(|_| anyhow!("stream {n}: no credit from the handshake"))??;
    }
    drop(native);
    server.stop().await
}

/// `GET /certificate.sha256` on the server's TCP port: status line, headers and body.
async fn published_hashes(server: &TestServer) -> Result<(String, Vec<String>)> {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let exchange = async {
        let mut tcp = tokio::net::TcpStream::connect(server.addr).await?;
        tcp.write_all(b"GET /certificate.sha256 HTTP/1.1\r\nHost: test\r\n\r\n")
            .await?;
        let mut answer = String::new();
        tcp.read_to_string(&mut answer).await?;
        anyhow::Ok(answer)
    };
    let answer = tokio::time::timeout(PATIENCE, exchange)
        .await
        .map_err(|_| anyhow!("no answer from the web listener"))??;
    let (head, body) = answer.split_once("\r\n\r\n").context("no end of head")?;
    Ok((
        head.to_ascii_lowercase(),
        body.lines().map(str::to_string).collect(),
    ))
}

#[tokio::test]
async fn the_web_listener_publishes_the_hashes_newest_first() -> Result<()> {
    let data = scratch("web");
    let site = scratch("web-site");
    std::fs::write(site.path().join("index.html"), "<!doctype html>")?;
    let time = Arc::new(ManualClock::new(SystemTime::now()));
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.clock = ClockRef(time.clone());
    config.web_dir = Some(site.path().to_path_buf());
    let server = TestServer::start_with(config).await?;

    let (head, body) = published_hashes(&server).await?;
    assert!(head.starts_with("http/1.1 200"), "{head}");
    assert!(head.contains("\r\ncontent-type: text/plain"), "{head}");
    assert!(head.contains("\r\ncache-control: no-store"), "{head}");
    let hex = |hashes: Vec<Fingerprint>| hashes.iter().map(|h| h.to_string()).collect::<Vec<_>>();
    assert_eq!(body, hex(server.web_certs.hashes()));
    assert_eq!(body.len(), 1);

    time.advance(Duration::from_secs(12 * 86400));
    assert!(server.web_certs.refresh()?);
    let (_, body) = published_hashes(&server).await?;
    assert_eq!(body.len(), 2);
    assert_eq!(body, hex(server.web_certs.hashes()));
    // What the page fetched is what it connects with.
    let listed: Vec<Fingerprint> = body
        .iter()
        .map(|h| Fingerprint::parse(h))
        .collect::<Result<_, _>>()?;
    drop(Page::open(&server, &listed).await?);
    server.stop().await
}

#[tokio::test]
async fn the_running_server_replaces_the_certificate_by_itself() -> Result<()> {
    let data = scratch("web");
    let time = Arc::new(ManualClock::new(SystemTime::now()));
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.clock = ClockRef(time.clone());
    config.web_cert_check = Duration::from_millis(50);
    let server = TestServer::start_with(config).await?;
    let first = server.web_certs.hashes();
    time.advance(Duration::from_secs(12 * 86400));
    let replaced = async {
        while server.web_certs.hashes().len() < 2 {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    };
    tokio::time::timeout(PATIENCE, replaced)
        .await
        .map_err(|_| anyhow!("the server did not replace its certificate"))?;
    let now = server.web_certs.hashes();
    assert_eq!(now[1], first[0]);
    assert_eq!(
        sha256(&shown(&Page::open(&server, &now[..1]).await?.session)?),
        now[0]
    );
    server.stop().await
}
