//! Who may talk to whom: the client trusts only the pinned certificate, the server only
//! clients with its protocol version and physics. An invite listing several addresses is
//! tried in order.

use breakshot_client::net::{endpoint, Channel, Client, NetError, Reconnect};
use breakshot_shared::protocol::{Fingerprint, ServerAddress, PROTOCOL_VERSION};
use breakshot_tests::{scratch, TestServer};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_pinning_another_fingerprint_is_refused() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("fingerprint").await?;
    let mut invite = server.invite.clone();
    invite.fingerprint = Fingerprint([0x42; 32]);
    let result = Channel::open(&endpoint()?, &invite).await;
    match result {
        Err(e @ NetError::WrongFingerprint) => assert!(
            e.to_string().contains("ask the host for a fresh invite"),
            "{e}"
        ),
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("connected to a server whose certificate is not the pinned one"),
    }
    // The right fingerprint connects.
    Channel::open(&endpoint()?, &server.invite).await?;
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_with_another_protocol_version_is_rejected_with_a_reason() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("version").await?;
    let result = Channel::open_at(
        &endpoint()?,
        server.invite.first(),
        server.invite.fingerprint,
        PROTOCOL_VERSION + 1,
    )
    .await;
    match result {
        Err(NetError::Rejected(reason)) => {
            assert!(reason.contains("protocol version"), "{reason}");
            assert!(
                reason.contains(&(PROTOCOL_VERSION + 1).to_string()),
                "{reason}"
            );
        }
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("accepted protocol version {}", PROTOCOL_VERSION + 1),
    }
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_certificate_and_its_fingerprint_survive_a_restart() -> anyhow::Result<()> {
    let data = scratch("identity");
    let first = TestServer::start(data.path()).await?;
    let fingerprint = first.invite.fingerprint;
    first.stop().await?;
    let second = TestServer::start(data.path()).await?;
    assert_eq!(second.invite.fingerprint, fingerprint);
    second.stop().await
}

/// A UDP port that receives and never answers, as an instance that is down behind a
/// firewall looks to a client.
fn silent_address() -> (std::net::UdpSocket, ServerAddress) {
    let socket = std::net::UdpSocket::bind(("127.0.0.1", 0)).expect("a UDP port");
    let port = socket.local_addr().expect("its address").port();
    let address = ServerAddress {
        host: "127.0.0.1".into(),
        port,
    };
    (socket, address)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_invite_s_addresses_are_tried_in_order() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("addresses").await?;
    let (_silent, down) = silent_address();
    let mut invite = server.invite.clone();
    invite.servers.insert(0, down.clone());
    let client = Client::connect(invite.clone(), Reconnect::never()).await?;
    assert_eq!(
        client.address_index(),
        1,
        "the silent first address answered"
    );
    drop(client);
    // The live address first: it is the one taken.
    invite.servers.reverse();
    let client = Client::connect(invite, Reconnect::never()).await?;
    assert_eq!(client.address_index(), 0);
    drop(client);
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn when_no_address_lets_a_client_in_a_refusal_says_why() -> anyhow::Result<()> {
    let (_data, server) = TestServer::start_fresh("addresses-refused").await?;
    let (_silent, down) = silent_address();
    let mut invite = server.invite.clone();
    invite.fingerprint = Fingerprint([0x42; 32]);
    invite.servers.insert(0, down);
    // The server that answers is not the one pinned: that is what the player must hear,
    // not that the silent address timed out.
    match Client::connect(invite, Reconnect::never()).await {
        Err(NetError::WrongFingerprint) => {}
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("connected to a server whose certificate is not the pinned one"),
    }
    server.stop().await
}
