//! Several server instances on one PostgreSQL database (a throwaway cluster; skipped, with a
//! message, where no PostgreSQL server is installed). A room is owned by one instance at a
//! time: the others refuse its players and cannot write its games; when its owner stops, even
//! when killed with SIGKILL, its players' clients, given an invite that lists both instances,
//! come back through the other one by themselves, it rebuilds the room from the shot log, and
//! the game is finished there. A room that closes lets go, and its players learn the result
//! through any instance.
//!
//! The instance that is killed is this test binary run again with [`CHILD`] set: it serves
//! like `breakshot-server --store URL` until it is killed.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use breakshot_client::net::{fetch_record, Reconnect};
use breakshot_client::play::Chooser;
use breakshot_server::output::StoreOp;
use breakshot_server::store::{Location, Store, StoreError};
use breakshot_server::tls;
use breakshot_server::verify::verify_store;
use breakshot_server::Config;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, Invite, ServerAddress, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Game, Phase, Seat};
use breakshot_testkit::Spawned;
use breakshot_tests::postgres::Cluster;
use breakshot_tests::{
    printed_invite, scratch, seated_pair, seated_pair_with, serve_until_killed, Player, Reads,
    TestServer, PATIENCE, SEED,
};

/// Set (to `URL DATA`) in the instance process a test starts.
const CHILD: &str = "BREAKSHOT_INSTANCE_SERVER";
/// Moves a game may take before the test calls it stuck.
const MAX_MOVES: usize = 2000;

/// The instance process: serves on a free loopback port until killed. Does nothing in a
/// normal test run.
#[test]
fn instance_process() {
    let Ok(spec) = std::env::var(CHILD) else {
        return;
    };
    let (url, data) = spec.split_once(' ').expect("URL DATA");
    let mut config = Config::new(([127, 0, 0, 1], 0).into(), data.into());
    config.store = Location::Postgres(url.into());
    // The same games on every run, as the in-process test servers play.
    config.predictable_seed = Some(SEED);
    serve_until_killed(&config);
}

/// Starts an instance process on the cluster and returns it with its invite.
fn start_process(cluster: &Cluster, data: &Path) -> (Spawned, Invite) {
    let me = std::env::current_exe().expect("this test binary");
    let mut child = Spawned::start(
        Command::new(me)
            .args(["--exact", "instance_process", "--nocapture"])
            .env(CHILD, format!("{} {}", cluster.url, data.display()))
            .env("RUST_LOG", "warn")
            .stdout(Stdio::piped()),
    );
    let out = child.child().stdout.take().expect("stdout");
    let invite = printed_invite(out).expect("the instance printed no invite");
    (child, invite)
}

/// An in-process instance's configuration on the cluster, with randomness of its own
/// (`seed`), so two instances never make the same room codes.
fn instance_config(cluster: &Cluster, data: &Path, seed: u64, port: u16) -> Config {
    let mut config = TestServer::config(([127, 0, 0, 1], port).into(), data);
    config.store = Location::Postgres(cluster.url.clone());
    config.predictable_seed = Some(seed);
    config
}

/// Starts an in-process instance on `port` (0: any free one).
async fn start_instance(
    cluster: &Cluster,
    data: &Path,
    seed: u64,
    port: u16,
) -> Result<TestServer> {
    TestServer::start_with(instance_config(cluster, data, seed, port)).await
}

/// Plays one move, chosen by the computer player for whoever is to move, and waits until
/// both players have seen what it did. `false` once the game is over.
async fn play_move(chooser: &mut Chooser, a: &mut Player, b: &mut Player) -> Result<bool> {
    let game = a.game().context("a game")?.clone();
    if matches!(game.phase(), Phase::Over { .. }) {
        return Ok(false);
    }
    let mv = chooser.choose(&game).context("a move")?;
    let mover = if game.to_move() == Seat::A {
        &mut *a
    } else {
        &mut *b
    };
    mover.send(mv).await?;
    for p in [a, b] {
        p.until("the move's outcome", |m| {
            matches!(
                m,
                ServerMessage::TurnChanged { .. }
                    | ServerMessage::GameOver { .. }
                    | ServerMessage::PocketCalled { .. }
            )
        })
        .await?;
    }
    Ok(true)
}

/// How the players' clients reconnect in these tests: as the game's, with quicker retries.
fn reconnecting() -> Reconnect {
    Reconnect {
        first_for: PATIENCE,
        rejoin_for: PATIENCE,
        pause: Duration::from_millis(50),
        max_pause: Duration::from_millis(500),
    }
}

/// A loopback port nothing listens on now, for an instance started later whose address an
/// invite must already list.
fn free_port() -> u16 {
    let socket = std::net::UdpSocket::bind(("127.0.0.1", 0)).expect("a free UDP port");
    socket.local_addr().expect("its address").port()
}

/// Gives the instance in `to` the identity (certificate, key, reset key) of the one in
/// `from`, so one invite's fingerprint holds for both.
fn share_identity(from: &Path, to: &Path) {
    for file in [tls::CERT_FILE, tls::KEY_FILE, tls::RESET_KEY_FILE] {
        std::fs::copy(from.join(file), to.join(file)).expect("copying the identity");
    }
}

/// `invite` listing another instance on `port` after its own address.
fn also_at(invite: &Invite, port: u16) -> Invite {
    let mut both = invite.clone();
    both.servers.push(ServerAddress {
        host: "127.0.0.1".into(),
        port,
    });
    both
}

/// Waits until `player` is seated again after its connection was lost.
async fn seated_again(player: &mut Player) -> Result<Game> {
    match player
        .until("the seat back", |m| {
            matches!(m, ServerMessage::Joined { .. })
        })
        .await?
    {
        ServerMessage::Joined { snapshot, .. } => Ok(snapshot.game),
        other => bail!("expected Joined, got {other:?}"),
    }
}

/// Plays `a` and `b`'s game to its end.
async fn play_out(chooser: &mut Chooser, a: &mut Player, b: &mut Player) -> Result<()> {
    let mut moves = 0;
    while play_move(chooser, a, b).await? {
        moves += 1;
        anyhow::ensure!(moves < MAX_MOVES, "the game never ended");
    }
    assert!(matches!(
        a.game().context("a game")?.phase(),
        Phase::Over { .. }
    ));
    assert_eq!(a.game(), b.game());
    Ok(())
}

/// Checks every stored game and returns how many there are.
async fn verified(cluster: &Cluster) -> Result<usize> {
    let location = Location::Postgres(cluster.url.clone());
    let checks = tokio::task::spawn_blocking(move || verify_store(&location)).await??;
    for c in &checks {
        assert!(c.result.is_ok(), "verify failed: {c:?}");
    }
    Ok(checks.len())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_instances_never_both_accept_commands_for_one_room() -> Result<()> {
    let Some(cluster) = Cluster::start("two_instances_never_both_accept_commands") else {
        return Ok(());
    };
    let (data_a, data_b) = (scratch("instance-a"), scratch("instance-b"));
    let first = start_instance(&cluster, data_a.path(), SEED, 0).await?;
    // The players' invite lists the second instance after the first, before it is up.
    let port_b = free_port();
    let invite = also_at(&first.invite, port_b);
    let (mut a, mut b, room) = seated_pair_with(&invite, reconnecting()).await?;
    let tokens = [a.client.token(), b.client.token()].map(|t| t.expect("a seat token"));
    let mut chooser = Chooser::new(5);
    play_move(&mut chooser, &mut a, &mut b).await?;

    share_identity(data_a.path(), data_b.path());
    let second = start_instance(&cluster, data_b.path(), SEED + 1, port_b).await?;
    assert_eq!(second.invite.fingerprint, first.invite.fingerprint);
    assert_eq!(
        second.restored, 0,
        "the second instance took a live room at start"
    );
    // A player coming back through the other instance is refused while the owner lives...
    let mut stray = Player::connect(&second.invite).await?;
    stray
        .send(ClientMessage::Rejoin { token: tokens[0] })
        .await?;
    let refused = stray.error().await?;
    assert!(
        matches!(
            refused,
            ServerMessage::Error {
                code: ErrorCode::ServerBusy,
                ..
            }
        ),
        "{refused:?}"
    );
    // ... and nothing else connected to the database can write the room's games.
    let url = cluster.url.clone();
    let code = room.clone();
    let written = tokio::task::spawn_blocking(move || -> Result<(), StoreError> {
        let mut other = Store::connect(&url)?;
        other.apply(&[&StoreOp::Command {
            room: code,
            number: 1,
            index: 1000,
            entry: vec![0],
        }])
    })
    .await?;
    assert!(
        matches!(written, Err(StoreError::OwnedElsewhere(ref r)) if *r == room.to_string()),
        "{written:?}"
    );
    // The owner plays on.
    play_move(&mut chooser, &mut a, &mut b).await?;
    let before = a.game().context("a game")?.clone();
    drop(stray);
    // The game so far can be watched again through either instance: it replays, every hash
    // checked, to the table the players see.
    for instance in [&first, &second] {
        let fetched = fetch_record(&instance.invite, &room).await?;
        assert!(!fetched.finished);
        let record = GameRecord::decode(&fetched.bytes)?;
        assert_eq!(record.replay()?, before, "through {}", instance.invite);
    }

    // The owner stops (as an instance is drained: SIGTERM). Its players' clients find the
    // room on the invite's next address, which takes it over from the shot log.
    first.stop().await?;
    for p in [&mut a, &mut b] {
        assert_eq!(seated_again(p).await?, before);
        assert_eq!(
            p.client.address_index(),
            1,
            "not through the second address"
        );
    }
    assert!(play_move(&mut chooser, &mut a, &mut b).await?);
    assert!(a.game().context("a game")?.turn() > before.turn());
    assert_eq!(a.replica.desyncs() + b.replica.desyncs(), 0);
    drop((a, b));
    second.stop().await?;
    assert_eq!(verified(&cluster).await?, 1);
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_told_its_game_is_played_elsewhere_asks_the_next_address() -> Result<()> {
    let Some(cluster) = Cluster::start("a_client_told_its_game_is_played_elsewhere") else {
        return Ok(());
    };
    let (data_a, data_b) = (scratch("elsewhere-a"), scratch("elsewhere-b"));
    let owner = start_instance(&cluster, data_a.path(), SEED, 0).await?;
    let (mut a, mut b, room) = seated_pair(&owner.invite).await?;
    let mut chooser = Chooser::new(3);
    play_move(&mut chooser, &mut a, &mut b).await?;
    let seen = b.game().context("a game")?.clone();
    let token = b.client.token().context("a seat token")?;
    share_identity(data_a.path(), data_b.path());
    let other = start_instance(&cluster, data_b.path(), SEED + 1, 0).await?;

    // Bob comes back with an invite that lists the other instance first: it answers that
    // the game is played elsewhere, and the client asks the next address, the owner.
    let mut invite = also_at(&other.invite, owner.addr.port());
    invite.room = Some(room);
    drop(b);
    let mut back = Player::connect_with(&invite, reconnecting()).await?;
    assert_eq!(back.client.address_index(), 0);
    back.send(ClientMessage::Rejoin { token }).await?;
    assert_eq!(seated_again(&mut back).await?, seen);
    assert_eq!(back.client.address_index(), 1, "not through the owner");
    assert!(play_move(&mut chooser, &mut a, &mut back).await?);
    drop((a, back));
    other.stop().await?;
    owner.stop().await?;
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_game_on_a_killed_instance_is_finished_through_another() -> Result<()> {
    let Some(cluster) = Cluster::start("a_game_on_a_killed_instance") else {
        return Ok(());
    };
    let (data_a, data_b) = (scratch("killed-a"), scratch("killed-b"));
    let (mut process, invite) = start_process(&cluster, data_a.path());
    let port_b = free_port();
    let invite = also_at(&invite, port_b);
    let (mut a, mut b, _room) = seated_pair_with(&invite, reconnecting()).await?;
    let mut chooser = Chooser::new(11);
    for _ in 0..4 {
        anyhow::ensure!(
            play_move(&mut chooser, &mut a, &mut b).await?,
            "the game ended before the instance could be killed"
        );
    }
    let seen = a.game().context("a game")?.clone();
    share_identity(data_a.path(), data_b.path());
    let other = start_instance(&cluster, data_b.path(), SEED + 1, port_b).await?;
    assert_eq!(other.restored, 0);

    // SIGKILL, mid-game. A client hears nothing from a dead server until its connection
    // idles out; the test does not wait for that, and drops the connections itself.
    process.child().kill()?;
    process.wait(PATIENCE);
    for p in [&mut a, &mut b] {
        p.pull_cable();
    }
    for p in [&mut a, &mut b] {
        assert_eq!(
            seated_again(p).await?,
            seen,
            "the room was rebuilt as the players last saw it"
        );
        assert_eq!(
            p.client.address_index(),
            1,
            "not through the second address"
        );
    }
    play_out(&mut chooser, &mut a, &mut b).await?;
    assert_eq!(a.replica.desyncs() + b.replica.desyncs(), 0);
    drop((a, b));
    other.stop().await?;
    assert_eq!(verified(&cluster).await?, 1);
    Ok(())
}

/// Advisory locks held in the cluster: one per room an instance owns.
async fn advisory_locks(cluster: &Cluster) -> Result<i64> {
    let url = cluster.url.clone();
    tokio::task::spawn_blocking(move || -> Result<i64> {
        let mut db = ::postgres::Client::connect(&url, ::postgres::NoTls)?;
        let row = db.query_one(
            "SELECT COUNT(*) FROM pg_locks WHERE locktype = 'advisory'",
            &[],
        )?;
        Ok(row.get(0))
    })
    .await?
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_room_that_closes_lets_go_of_its_lock_and_any_instance_tells_the_result() -> Result<()> {
    let Some(cluster) = Cluster::start("a_room_that_closes_lets_go") else {
        return Ok(());
    };
    let data = scratch("closing");
    let mut config = instance_config(&cluster, data.path(), SEED, 0);
    // A room stays open for its players' return (a rematch) this long after they leave.
    config.limits.reconnect_window = Duration::from_millis(200);
    let server = TestServer::start_with(config).await?;
    let (mut a, mut b, _room) = seated_pair(&server.invite).await?;
    let tokens = [a.client.token(), b.client.token()].map(|t| t.expect("a seat token"));
    assert_eq!(advisory_locks(&cluster).await?, 1, "the new room is owned");
    // Another instance, up while the game is played (so it has not read its end at start).
    let data_b = scratch("closing-b");
    let other = start_instance(&cluster, data_b.path(), SEED + 1, 0).await?;
    a.send(ClientMessage::Concede).await?;
    for p in [&mut a, &mut b] {
        p.until("the game's end", |m| {
            matches!(m, ServerMessage::GameOver { .. })
        })
        .await?;
    }
    drop((a, b));
    let deadline = Instant::now() + PATIENCE;
    while advisory_locks(&cluster).await? != 0 {
        anyhow::ensure!(
            Instant::now() < deadline,
            "the closed room's lock was never let go"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    // A player coming back through the other instance learns how the game ended.
    let mut late = Player::connect(&other.invite).await?;
    late.send(ClientMessage::Rejoin { token: tokens[1] })
        .await?;
    let told = late.recv().await?;
    assert!(
        matches!(
            told,
            ServerMessage::GameFinished {
                seat: Seat::B,
                winner: Some(Seat::B),
                ..
            }
        ),
        "{told:?}"
    );
    drop(late);
    other.stop().await?;
    server.stop().await
}
