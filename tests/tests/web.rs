//! The web listener over real sockets: the web client's files, and the game over a
//! Noise-encrypted WebSocket as docs/web.md describes it, with the hostile cases.

use std::net::SocketAddr;
use std::path::Path;
use std::sync::atomic::AtomicUsize;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use breakshot_server::Config;
use breakshot_shared::protocol::web::MAX_NOISE_MESSAGE;
use breakshot_shared::protocol::{ClientMessage, ServerMessage};
use breakshot_tests::web::{self, WebPlayer};
use breakshot_tests::{create_eight_ball, scratch, Player, Reads, TempDir, TestServer, PATIENCE};
use futures_util::SinkExt;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::Message;

/// The handshake time of these servers: short, so the slow cases end quickly.
const HANDSHAKE: Duration = Duration::from_secs(1);

/// Bytes that are not text, for a byte-exact check.
fn wasm_bytes() -> Vec<u8> {
    let mut bytes = b"\0asm\x01\0\0\0".to_vec();
    bytes.extend((0..70_000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8));
    bytes
}

/// A web directory beside a secret file, with a symbolic link pointing at the secret.
fn web_dir(root: &Path) -> std::path::PathBuf {
    let web = root.join("web");
    std::fs::create_dir_all(web.join("pkg")).unwrap();
    std::fs::write(
        web.join("index.html"),
        "<!doctype html><title>Breakshot</title>",
    )
    .unwrap();
    std::fs::write(web.join("pkg/breakshot.wasm"), wasm_bytes()).unwrap();
    std::fs::write(web.join("breakshot_net.js"), "export const x = 1;\n").unwrap();
    std::fs::write(web.join("style.css"), "body{}").unwrap();
    std::fs::write(root.join("secret.txt"), "SECRET").unwrap();
    std::os::unix::fs::symlink(root.join("secret.txt"), web.join("leak.txt")).unwrap();
    web
}

/// The configuration of a test server serving the [`web_dir`] in `folder`, its data beside it.
fn web_config(folder: &Path) -> Config {
    let mut config =
        TestServer::config(SocketAddr::from(([127, 0, 0, 1], 0)), &folder.join("data"));
    config.web_dir = Some(web_dir(folder));
    config
}

/// A server on a fresh scratch folder named after `name`, serving the folder's [`web_dir`]
/// with the short handshake time: the folder (keep it while the server runs), the server,
/// and its web listener's address.
async fn web_server(name: &str) -> Result<(TempDir, TestServer, SocketAddr)> {
    let folder = scratch(name);
    let mut config = web_config(folder.path());
    config.limits.handshake_timeout = HANDSHAKE;
    let server = TestServer::start_with(config).await?;
    let addr = server
        .web_addr
        .context("the server does not serve the web")?;
    Ok((folder, server, addr))
}

fn count(c: &AtomicUsize) -> usize {
    c.load(std::sync::atomic::Ordering::Relaxed)
}

/// Waits (bounded) until `check` holds.
async fn eventually(what: &str, check: impl Fn() -> bool) {
    let give_up = tokio::time::Instant::now() + PATIENCE;
    while !check() {
        assert!(tokio::time::Instant::now() < give_up, "never: {what}");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

#[tokio::test]
async fn a_page_creates_a_room_over_the_websocket_and_a_native_player_joins_it() -> Result<()> {
    let (_data, server, addr) = web_server("web-play").await?;
    // One port number for both ways in.
    assert_eq!(addr.port(), server.addr.port());

    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    page.send(&create_eight_ball("page")).await?;
    let ServerMessage::Joined {
        snapshot, token, ..
    } = page
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    else {
        unreachable!()
    };
    assert!(token.is_some());
    let mut native = Player::connect(&server.invite).await?;
    native.join(&snapshot.room, "native").await?;
    let joined = page
        .until("PlayerJoined", |m| {
            matches!(m, ServerMessage::PlayerJoined { .. })
        })
        .await?;
    assert!(matches!(joined, ServerMessage::PlayerJoined { name, .. } if name == "native"));

    // A second page joins as a spectator, through the same hub.
    let mut watcher = WebPlayer::hello(addr, &server.web_key).await?;
    watcher
        .send(&ClientMessage::Spectate {
            room: snapshot.room.clone(),
        })
        .await?;
    watcher
        .until("Joined", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?;
    assert_eq!(count(&server.stats.web_sockets), 2);
    server.stop().await
}

/// Checks the server closed a hostile WebSocket without the hub seeing it: `failures`
/// counted so far, and no game connection ever started.
async fn refused_before_the_hub(server: &TestServer, failures: usize) -> Result<()> {
    eventually("the failure counted", || {
        count(&server.stats.web_sockets_failed) == failures
    })
    .await;
    assert_eq!(
        count(&server.stats.web_sockets),
        0,
        "the hub saw a connection"
    );
    Ok(())
}

#[tokio::test]
async fn bad_handshakes_close_the_socket_before_the_hub_sees_anything() -> Result<()> {
    let (_data, server, addr) = web_server("web-handshake").await?;

    // The wrong server key: the server cannot read message 1.
    let mut ws = web::open(addr).await?;
    let mut hs = web::initiator(&[7u8; 32])?;
    let mut out = vec![0u8; MAX_NOISE_MESSAGE];
    let len = hs.write_message(&[], &mut out)?;
    ws.send(Message::binary(out[..len].to_vec())).await?;
    assert!(web::next(&mut ws).await?.is_none(), "answered a wrong key");
    refused_before_the_hub(&server, 1).await?;

    // A text message.
    let mut ws = web::open(addr).await?;
    ws.send(Message::text("hello")).await?;
    assert!(web::next(&mut ws).await?.is_none());
    refused_before_the_hub(&server, 2).await?;

    // A message over 65,535 bytes.
    let mut ws = web::open(addr).await?;
    let _ = ws
        .send(Message::binary(vec![0u8; MAX_NOISE_MESSAGE + 1]))
        .await;
    assert!(web::next(&mut ws).await?.is_none());
    refused_before_the_hub(&server, 3).await?;

    // Message 1 with a payload.
    let mut ws = web::open(addr).await?;
    let mut hs = web::initiator(&server.web_key)?;
    let len = hs.write_message(b"hi", &mut out)?;
    ws.send(Message::binary(out[..len].to_vec())).await?;
    assert!(web::next(&mut ws).await?.is_none());
    refused_before_the_hub(&server, 4).await?;

    // Nothing at all: closed once the handshake time is up.
    let mut ws = web::open(addr).await?;
    let started = tokio::time::Instant::now();
    assert!(web::next(&mut ws).await?.is_none());
    assert!(started.elapsed() < HANDSHAKE * 5, "{:?}", started.elapsed());
    refused_before_the_hub(&server, 5).await?;

    // The handshake slots were all given back, and a good page still gets in.
    eventually("no handshake left", || {
        count(&server.stats.handshaking) == 0
    })
    .await;
    WebPlayer::hello(addr, &server.web_key).await?;
    server.stop().await
}

#[tokio::test]
async fn bad_messages_after_the_handshake_close_the_socket() -> Result<()> {
    let (_data, server, addr) = web_server("web-after").await?;

    // Garbage that is no Noise message of this session.
    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    page.ws.send(Message::binary(vec![0x5a; 100])).await?;
    assert!(
        web::next(&mut page.ws).await?.is_none(),
        "garbage was accepted"
    );

    // A text message.
    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    page.ws.send(Message::text("{}")).await?;
    assert!(web::next(&mut page.ws).await?.is_none());

    // Too large a message.
    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    let _ = page.ws.send(Message::binary(vec![1u8; 100_000])).await;
    assert!(web::next(&mut page.ws).await?.is_none());

    // A well-encrypted stream that is not frames: the connection's own defences close it.
    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    page.send_bytes(&[0xff; 64]).await?;
    if let Ok(msg) = page.recv().await {
        bail!("answered garbage frames with {msg:?}");
    }

    // Every one of them was a game connection, and each has ended.
    assert_eq!(count(&server.stats.web_sockets), 4);
    eventually("all connections gone", || {
        count(&server.stats.connections) == 0
    })
    .await;
    server.stop().await
}

#[tokio::test]
async fn files_are_served_byte_exact_with_their_types() -> Result<()> {
    let (_data, server, addr) = web_server("web-files").await?;

    let index = web::get(addr, "/?room=K7QX2M4B&key=00").await?;
    assert_eq!(index.status, 200);
    assert_eq!(
        index.header("content-type"),
        Some("text/html; charset=utf-8")
    );
    assert_eq!(index.body, b"<!doctype html><title>Breakshot</title>");

    let wasm = web::get(addr, "/pkg/breakshot.wasm").await?;
    assert_eq!(wasm.status, 200);
    assert_eq!(wasm.header("content-type"), Some("application/wasm"));
    assert_eq!(
        wasm.header("content-length"),
        Some(wasm_bytes().len().to_string().as_str())
    );
    assert!(
        wasm.body == wasm_bytes(),
        "the wasm file changed on the way"
    );

    for (path, kind) in [
        ("/breakshot_net.js", "text/javascript; charset=utf-8"),
        ("/style.css", "text/css; charset=utf-8"),
    ] {
        let r = web::get(addr, path).await?;
        assert_eq!(
            (r.status, r.header("content-type")),
            (200, Some(kind)),
            "{path}"
        );
    }

    let head = web::request(
        addr,
        format!("HEAD /pkg/breakshot.wasm HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes(),
    )
    .await?;
    assert_eq!(head.status, 200);
    assert_eq!(
        head.header("content-length"),
        Some(wasm_bytes().len().to_string().as_str())
    );
    assert!(head.body.is_empty());

    // Refusals that name, in a header, what would be accepted.
    let other_version = "GET /ws HTTP/1.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
                         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\
                         Sec-WebSocket-Version: 8\r\n\r\n";
    for (what, request, status, header, accepted) in [
        (
            "a POST",
            "POST / HTTP/1.1\r\nContent-Length: 2\r\n\r\nhi",
            405,
            "allow",
            "GET, HEAD",
        ),
        (
            "a WebSocket of another version",
            other_version,
            426,
            "sec-websocket-version",
            "13",
        ),
    ] {
        let refused = web::request(addr, request.as_bytes()).await?;
        assert_eq!(
            (refused.status, refused.header(header)),
            (status, Some(accepted)),
            "{what}"
        );
    }

    let missing = web::get(addr, "/nope.js").await?;
    assert_eq!(missing.status, 404);
    assert!(missing.body.len() < 100);

    let with_body = web::request(addr, b"GET / HTTP/1.1\r\nContent-Length: 4\r\n\r\nbody").await?;
    assert_eq!(with_body.status, 413);

    let plain_ws = web::get(addr, "/ws").await?;
    assert_eq!(plain_ws.status, 400);
    assert!(count(&server.stats.web_requests) >= 9);
    server.stop().await
}

#[tokio::test]
async fn no_path_leaves_the_web_directory() -> Result<()> {
    let (_data, server, addr) = web_server("web-escape").await?;
    for path in [
        "/../secret.txt",
        "/%2e%2e/secret.txt",
        "/..%2fsecret.txt",
        "/pkg/..%2f..%2fsecret.txt",
        "/pkg/%2E%2E/%2E%2E/secret.txt",
        "/%5c..%5csecret.txt",
        "/secret.txt%00.html",
        "/leak.txt",
        "//secret.txt",
    ] {
        let r = web::get(addr, path).await?;
        assert!(matches!(r.status, 400 | 404), "{path}: {}", r.status);
        assert!(
            !String::from_utf8_lossy(&r.body).contains("SECRET"),
            "{path} leaked"
        );
    }
    // An absolute form or a target that is not a path.
    for target in ["http://evil.example/secret.txt", "*", "secret.txt"] {
        let r = web::get(addr, target).await?;
        assert_eq!(r.status, 400, "{target}");
    }
    server.stop().await
}

#[tokio::test]
async fn request_heads_are_bounded_in_size_and_time() -> Result<()> {
    let (_data, server, addr) = web_server("web-heads").await?;

    let mut big = format!("GET / HTTP/1.1\r\nHost: {addr}\r\nX-Fill: ").into_bytes();
    big.extend(std::iter::repeat_n(b'a', 9 * 1024));
    big.extend(b"\r\n\r\n");
    assert_eq!(web::request(addr, &big).await?.status, 431);

    let bad = web::request(addr, b"\x16\x03\x01 not http\r\n\r\n").await?;
    assert_eq!(bad.status, 400);

    // A head that never ends: the connection is closed once the handshake time is up.
    let mut slow = TcpStream::connect(addr).await?;
    slow.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n").await?;
    let started = tokio::time::Instant::now();
    assert!(
        web::closed_within(&mut slow, HANDSHAKE * 5).await,
        "a slow head kept its connection"
    );
    assert!(started.elapsed() >= HANDSHAKE / 2);
    server.stop().await
}

#[tokio::test]
async fn tcp_connections_pass_the_same_gate() -> Result<()> {
    let data = scratch("web-gate");
    let mut config = web_config(data.path());
    config.limits.max_connections = 3;
    config.limits.address_share = 1;
    let server = TestServer::start_with(config).await?;
    let addr = server.web_addr.expect("serving the web");
    let mut held = Vec::new();
    for _ in 0..3 {
        held.push(TcpStream::connect(addr).await?);
    }
    eventually("three connections", || {
        count(&server.stats.connections) == 3
    })
    .await;
    let mut refused = TcpStream::connect(addr).await?;
    assert!(web::closed_within(&mut refused, PATIENCE).await);
    assert_eq!(count(&server.stats.refused), 1);
    drop(held);
    eventually("slots given back", || count(&server.stats.connections) == 0).await;
    assert_eq!(web::get(addr, "/").await?.status, 200);
    server.stop().await
}

#[tokio::test]
async fn a_server_without_web_has_no_tcp_listener() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("web-none").await?;
    assert!(server.web_addr.is_none());
    let tried = tokio::time::timeout(PATIENCE, TcpStream::connect(server.addr)).await?;
    assert!(tried.is_err(), "something listens on TCP {}", server.addr);
    server.stop().await
}

#[tokio::test]
async fn a_quiet_page_stays_and_a_vanished_one_is_dropped_after_the_idle_timeout() -> Result<()> {
    use breakshot_shared::protocol::limits::IDLE_TIMEOUT;
    let (_data, server, addr) = web_server("web-idle").await?;
    let mut page = WebPlayer::hello(addr, &server.web_key).await?;
    // A page that says nothing but whose browser answers the server's pings stays.
    let quiet = tokio::time::timeout(IDLE_TIMEOUT + Duration::from_secs(2), page.recv()).await;
    assert!(quiet.is_err(), "the quiet page got {quiet:?}");
    assert_eq!(count(&server.stats.connections), 1);
    // One that answers nothing any more (a closed laptop) is taken for gone.
    let started = tokio::time::Instant::now();
    eventually("the silent page dropped", || {
        count(&server.stats.connections) == 0
    })
    .await;
    assert!(
        started.elapsed() >= IDLE_TIMEOUT / 2,
        "{:?}",
        started.elapsed()
    );
    drop(page);
    server.stop().await
}

#[tokio::test]
async fn the_web_link_names_the_listener_the_key_and_the_room() -> Result<()> {
    use breakshot_server::Server;
    use breakshot_shared::protocol::{RoomCode, WebLink};
    let data = scratch("web-link");
    let mut config = TestServer::config(
        SocketAddr::from(([127, 0, 0, 1], 0)),
        &data.path().join("data"),
    );
    assert!(Server::bind(&config)?.web_link(None).is_none());
    config.web_dir = Some(web_dir(data.path()));
    let server = Server::bind(&config)?;
    let port = server.local_addr().port();
    assert_eq!(server.web_addr().map(|a| a.port()), Some(port));
    let room = RoomCode::parse("K7QX2M4B")?;
    let link = server
        .web_link(Some(room.clone()))
        .expect("serving the web");
    let text = link.to_string();
    let key: String = server
        .web_key()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    // The browsers' certificate hashes follow, newest first.
    let hashes: Vec<String> = server
        .web_cert_hashes()
        .iter()
        .map(|h| h.to_string())
        .collect();
    assert!(!hashes.is_empty());
    assert_eq!(
        text,
        format!(
            "http://127.0.0.1:{port}/?room=K7QX2M4B&key={key}&cert={}",
            hashes.join(",")
        )
    );
    let back: WebLink = text.parse()?;
    assert_eq!((back.room, back.key), (Some(room), server.web_key()));
    Ok(())
}
