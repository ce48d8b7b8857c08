//! `breakshot-server verify`: re-simulating stored games catches any change.

use breakshot_server::store::Store;
use breakshot_server::verify::verify_dir;
use breakshot_shared::replay::GameRecord;
use breakshot_tests::{bot_games, TestServer};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn verify_passes_on_stored_games_and_fails_on_a_tampered_one() -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("verify").await?;
    let report = bot_games(&server, 2).await?;
    server.stop().await?;
    assert_eq!(report.games_completed, 2, "{:?}", report.errors);

    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 2);
    assert!(checks.iter().all(|c| c.result.is_ok()), "{checks:?}");

    // Change one recorded shot hash by one bit.
    let room = checks[0].room.clone();
    let store = Store::open(data.path())?;
    let mut record = GameRecord::decode(&store.record(&room, 1)?.expect("stored"))?;
    let (index, entry) = record
        .entries
        .iter_mut()
        .enumerate()
        .find(|(_, e)| e.hash.is_some())
        .expect("a shot");
    entry.hash = entry.hash.map(|h| h ^ 1);
    assert!(store.overwrite_record(&room, 1, &record.encode())?);

    let checks = verify_dir(data.path())?;
    let tampered = checks.iter().find(|c| c.room == room).expect("the game");
    let why = tampered
        .result
        .clone()
        .expect_err("a tampered game must fail");
    assert!(why.contains(&format!("entry {index}")), "{why}");
    assert_eq!(checks.iter().filter(|c| c.result.is_ok()).count(), 1);
    Ok(())
}
