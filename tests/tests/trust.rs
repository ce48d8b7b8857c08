//! Who may talk to whom: the client trusts only the pinned certificate, the server only
//! clients with its protocol version and physics.

use breakshot_client::net::{endpoint, Channel, NetError};
use breakshot_shared::protocol::{Fingerprint, PROTOCOL_VERSION};
use breakshot_tests::{scratch, TestServer};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_pinning_another_fingerprint_is_refused() -> anyhow::Result<()> {
    let data = scratch("fingerprint");
    let server = TestServer::start(data.path()).await?;
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
    let data = scratch("version");
    let server = TestServer::start(data.path()).await?;
    let result = Channel::open_as(&endpoint()?, &server.invite, PROTOCOL_VERSION + 1).await;
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
