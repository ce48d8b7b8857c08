//! The same store tests for both backends: SQLite in a scratch folder, and PostgreSQL in a
//! throwaway cluster (skipped, with a message, where no PostgreSQL server is installed).

use breakshot_server::output::{RoomMeta, StoreOp, StoredSeat};
use breakshot_server::secret::TokenDigest;
use breakshot_server::store::{unix_now, Location, Store, StoreError, DB_FILE};
use breakshot_server::verify::verify_store;
use breakshot_shared::protocol::{AimAid, PlayerKey, RoomCode, ServerMessage};
use breakshot_shared::replay::{GameRecord, RecordEntry};
use breakshot_shared::rules::{Command, EightBallRules, Seat, Settings, Variant};
use breakshot_tests::postgres::Cluster;
use breakshot_tests::{bot_games, break_shot, scratch, seated_pair, Reads, TestServer};

fn meta(code: &str) -> RoomMeta {
    RoomMeta {
        code: RoomCode::parse(code).unwrap(),
        variant: Variant::EightBall(EightBallRules::Wpa),
        settings: Settings::offline(),
        aim_aid: AimAid::Off,
        seats: [
            Some(StoredSeat {
                name: "ann".into(),
                digest: TokenDigest([1; 32]),
            }),
            None,
        ],
    }
}

fn place(i: u32) -> RecordEntry {
    RecordEntry {
        seat: Seat::A,
        command: Command::PlaceCueBall {
            pos: [0.5, f64::from(i)],
        },
        hash: Some(u64::from(i)),
        chain: u64::from(i),
    }
}

/// Runs `check` on a fresh SQLite store.
fn on_sqlite(check: impl Fn(&dyn Fn() -> Store)) {
    let tmp = breakshot_testkit::scratch("store");
    check(&|| Store::open(tmp.path()).unwrap());
}

/// Runs `check` on a fresh PostgreSQL store, if a cluster can be started here.
fn on_postgres(test: &str, check: impl Fn(&dyn Fn() -> Store)) {
    let Some(cluster) = Cluster::start(test) else {
        return;
    };
    check(&|| Store::connect(&cluster.url).unwrap());
}

fn games_survive_reopening_and_finished_ones_are_not_reloaded(open: &dyn Fn() -> Store) {
    let record = GameRecord::new(
        Variant::EightBall(EightBallRules::Wpa),
        Settings::offline(),
        7,
    );
    let game = |code: &str| StoreOp::GameStarted {
        room: RoomCode::parse(code).unwrap(),
        number: 1,
        header: record.encode(),
    };
    let ended = StoreOp::GameEnded {
        room: RoomCode::parse("BBBBBBBB").unwrap(),
        number: 1,
        winner: Some(Seat::B),
        reason: "A conceded".into(),
    };
    let players = [PlayerKey([3; 32]), PlayerKey([4; 32])];
    {
        let mut store = open();
        let ops = [
            StoreOp::Room(meta("AAAAAAAA")),
            game("AAAAAAAA"),
            StoreOp::RatedRoom {
                room: RoomCode::parse("AAAAAAAA").unwrap(),
                players,
            },
            StoreOp::Room(meta("BBBBBBBB")),
            game("BBBBBBBB"),
            StoreOp::Room(meta("DDDDDDDD")),
            game("DDDDDDDD"),
            // Published while it waited, then listed again once its second player came.
            StoreOp::Listed {
                room: RoomCode::parse("DDDDDDDD").unwrap(),
                players: [Some(players[0]), None],
            },
            StoreOp::Listed {
                room: RoomCode::parse("DDDDDDDD").unwrap(),
                players: [Some(players[0]), Some(players[1])],
            },
        ];
        store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
        store.apply(&[&ended]).unwrap();
    }
    let store = open();
    let unfinished = store.unfinished().unwrap();
    assert_eq!(unfinished.len(), 2);
    assert_eq!(unfinished[0].meta.code.as_str(), "AAAAAAAA");
    assert_eq!(
        unfinished[0].listed, None,
        "a quick match's room is not published"
    );
    assert_eq!(
        unfinished[1].listed,
        Some([Some(players[0]), Some(players[1])]),
        "a published room comes back listed, with its players by seat as last stored"
    );
    assert_eq!(unfinished[0].record, Ok(record.clone()));
    assert_eq!(
        unfinished[0].meta.seats[0].as_ref().unwrap().digest,
        TokenDigest([1; 32])
    );
    assert_eq!(
        unfinished[0].rated,
        Some(players),
        "a quick-match room comes back rated, with its players by seat"
    );
    let all = store.all().unwrap();
    assert_eq!(
        all.iter()
            .map(|g| (g.meta.code.as_str(), g.finished, g.rated.is_some()))
            .collect::<Vec<_>>(),
        [
            ("AAAAAAAA", false, true),
            ("BBBBBBBB", true, false),
            ("DDDDDDDD", false, false)
        ]
    );
    let ended = store.ended_since(unix_now() - 60).unwrap();
    assert_eq!(ended.len(), 1);
    assert_eq!(ended[0].meta.code.as_str(), "BBBBBBBB");
    assert_eq!(ended[0].winner, Some(Seat::B));
    assert_eq!(ended[0].reason, "A conceded");
    assert!(store.ended_since(unix_now() + 60).unwrap().is_empty());
}

fn a_game_is_appended_one_command_at_a_time_and_nothing_is_overwritten(open: &dyn Fn() -> Store) {
    let code = RoomCode::parse("CCCCCCCC").unwrap();
    let mut record = GameRecord::new(Variant::Practice, Settings::offline(), 3);
    {
        let mut store = open();
        let mut ops = vec![StoreOp::Room(meta("CCCCCCCC"))];
        ops.extend(StoreOp::whole_game(&code, 1, &record));
        store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
        for i in 0..30 {
            let entry = place(i);
            let op = StoreOp::Command {
                room: code.clone(),
                number: 1,
                index: i,
                entry: entry.encode(),
            };
            store.apply(&[&op]).unwrap();
            record.entries.push(entry);
        }
        // The same index twice is refused, and the whole batch with it.
        let next = StoreOp::Command {
            room: code.clone(),
            number: 1,
            index: 30,
            entry: place(30).encode(),
        };
        let again = StoreOp::Command {
            room: code.clone(),
            number: 1,
            index: 7,
            entry: place(99).encode(),
        };
        assert!(store.apply(&[&next, &again]).is_err());
    }
    let store = open();
    let stored = store.record(&code, 1).unwrap().unwrap();
    assert_eq!(GameRecord::decode(&stored).unwrap(), record);
    assert_eq!(store.unfinished().unwrap()[0].record, Ok(record.clone()));
    let (number, latest, finished) = store.latest(&code).unwrap().unwrap();
    assert_eq!((number, finished), (1, false));
    assert_eq!(GameRecord::decode(&latest).unwrap(), record);
    assert_eq!(
        store.latest(&RoomCode::parse("ZZZZZZZZ").unwrap()).unwrap(),
        None
    );
}

fn a_rematch_starts_a_new_game_and_an_overwritten_record_is_what_is_read(open: &dyn Fn() -> Store) {
    let code = RoomCode::parse("DDDDDDDD").unwrap();
    let mut first = GameRecord::new(Variant::Practice, Settings::offline(), 4);
    first.entries.extend((0..3).map(place));
    let second = GameRecord::new(Variant::Practice, Settings::offline(), 5);
    let mut store = open();
    let mut ops = vec![StoreOp::Room(meta("DDDDDDDD"))];
    ops.extend(StoreOp::whole_game(&code, 1, &first));
    ops.push(StoreOp::GameEnded {
        room: code.clone(),
        number: 1,
        winner: None,
        reason: "practice ended".into(),
    });
    ops.extend(StoreOp::whole_game(&code, 2, &second));
    store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
    let (number, latest, finished) = store.latest(&code).unwrap().unwrap();
    assert_eq!((number, finished), (2, false));
    assert_eq!(GameRecord::decode(&latest).unwrap(), second);
    let mut tampered = first.clone();
    tampered.entries[1].hash = Some(77);
    assert!(store
        .overwrite_record(&code, 1, &tampered.encode())
        .unwrap());
    let read = store.record(&code, 1).unwrap().unwrap();
    assert_eq!(GameRecord::decode(&read).unwrap(), tampered);
    assert!(!store
        .overwrite_record(&code, 9, &tampered.encode())
        .unwrap());
}

fn the_latest_shot_clock_of_a_game_is_kept_and_a_running_one_loses_the_time_since(
    open: &dyn Fn() -> Store,
) {
    let code = RoomCode::parse("DDDDDDDD").unwrap();
    let record = GameRecord::new(Variant::Practice, Settings::offline(), 5);
    let clock = |turn, left_ms, running| StoreOp::Clock {
        room: code.clone(),
        number: 1,
        turn,
        left_ms,
        running,
    };
    {
        let mut store = open();
        let mut ops = vec![StoreOp::Room(meta("DDDDDDDD"))];
        ops.extend(StoreOp::whole_game(&code, 1, &record));
        ops.push(clock(0, 30_000, true));
        store.apply(&ops.iter().collect::<Vec<_>>()).unwrap();
        store.apply(&[&clock(1, 40_000, true)]).unwrap();
        store.apply(&[&clock(1, 12_500, false)]).unwrap();
    }
    let store = open();
    let games = store.unfinished().unwrap();
    let stored = games[0].clock.expect("a stored clock");
    assert_eq!(
        (stored.turn, stored.left_ms, stored.running),
        (1, 12_500, false)
    );
    // A stopped clock keeps its time however late it is read; a running one does not.
    let later = stored.at_ms + 3_000;
    assert_eq!(
        stored.left_at(later).left,
        std::time::Duration::from_millis(12_500)
    );
    let running = breakshot_server::store::StoredClock {
        running: true,
        ..stored
    };
    assert_eq!(
        running.left_at(later).left,
        std::time::Duration::from_millis(9_500)
    );
    assert_eq!(
        running.left_at(later + 60_000).left,
        std::time::Duration::ZERO
    );
}

#[test]
fn sqlite_shot_clocks() {
    on_sqlite(the_latest_shot_clock_of_a_game_is_kept_and_a_running_one_loses_the_time_since);
}

#[test]
fn postgres_shot_clocks() {
    on_postgres(
        "postgres_shot_clocks",
        the_latest_shot_clock_of_a_game_is_kept_and_a_running_one_loses_the_time_since,
    );
}

#[test]
fn sqlite_games_survive_reopening_and_finished_ones_are_not_reloaded() {
    on_sqlite(games_survive_reopening_and_finished_ones_are_not_reloaded);
}

#[test]
fn postgres_games_survive_reopening_and_finished_ones_are_not_reloaded() {
    on_postgres(
        "postgres_games_survive_reopening",
        games_survive_reopening_and_finished_ones_are_not_reloaded,
    );
}

#[test]
fn sqlite_a_game_is_appended_one_command_at_a_time() {
    on_sqlite(a_game_is_appended_one_command_at_a_time_and_nothing_is_overwritten);
}

#[test]
fn postgres_a_game_is_appended_one_command_at_a_time() {
    on_postgres(
        "postgres_a_game_is_appended",
        a_game_is_appended_one_command_at_a_time_and_nothing_is_overwritten,
    );
}

#[test]
fn sqlite_rematches_and_overwritten_records() {
    on_sqlite(a_rematch_starts_a_new_game_and_an_overwritten_record_is_what_is_read);
}

#[test]
fn postgres_rematches_and_overwritten_records() {
    on_postgres(
        "postgres_rematches",
        a_rematch_starts_a_new_game_and_an_overwritten_record_is_what_is_read,
    );
}

#[test]
fn postgres_a_newer_schema_is_refused_and_migrating_twice_changes_nothing() {
    let Some(cluster) = Cluster::start("postgres_schema") else {
        return;
    };
    drop(Store::connect(&cluster.url).unwrap());
    drop(Store::connect(&cluster.url).unwrap());
    let mut db = ::postgres::Client::connect(&cluster.url, ::postgres::NoTls).unwrap();
    let versions: i64 = db
        .query_one("SELECT COUNT(*) FROM breakshot_schema", &[])
        .unwrap()
        .get(0);
    // One row per migration, each applied once.
    let migrations = std::fs::read_dir(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../server/migrations/postgres"
    ))
    .unwrap()
    .count();
    assert_eq!(versions, i64::try_from(migrations).unwrap());
    db.execute("INSERT INTO breakshot_schema (version) VALUES (99)", &[])
        .unwrap();
    assert!(matches!(
        Store::connect(&cluster.url),
        Err(StoreError::Schema { found: 99, .. })
    ));
}

#[test]
fn a_store_location_is_a_postgres_url_or_nothing() {
    assert_eq!(
        Location::parse("postgres://u@db.example.org/breakshot").unwrap(),
        Location::Postgres("postgres://u@db.example.org/breakshot".into())
    );
    assert!(Location::parse("postgresql:///games").is_ok());
    assert!(matches!(
        Location::parse("sqlite:games.db"),
        Err(StoreError::Location(_))
    ));
}

/// A server keeps its games in PostgreSQL: they are all there for `verify` (which catches a
/// changed hash), nothing is written to the data directory's SQLite, and a game left
/// unfinished comes back when the server starts again.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_on_postgres_keeps_every_game_there_and_verify_checks_them() -> anyhow::Result<()>
{
    let Some(cluster) = Cluster::start("a_server_on_postgres") else {
        return Ok(());
    };
    let location = Location::Postgres(cluster.url.clone());
    let data = scratch("pg-server");
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.store = location.clone();
    let server = TestServer::start_with(config.clone()).await?;
    let report = bot_games(&server, 2).await?;
    assert_eq!(report.games_completed, 2, "{:?}", report.errors);
    assert_eq!(report.tally.desyncs, 0);
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;
    a.send(break_shot(a.game().expect("a game"))).await?;
    for p in [&mut a, &mut b] {
        p.until("the result", |m| {
            matches!(m, ServerMessage::ShotResolved { .. })
        })
        .await?;
    }
    server.stop().await?;
    assert!(!data.path().join(DB_FILE).exists());

    let checks = blocking({
        let location = location.clone();
        move || verify_store(&location)
    })
    .await?;
    assert_eq!(checks.len(), 3, "{checks:?}");
    assert!(checks.iter().all(|c| c.result.is_ok()), "{checks:?}");
    assert_eq!(checks.iter().filter(|c| !c.finished).count(), 1);

    // The unfinished game is brought back from the database, every hash checked.
    let server = TestServer::start_with(config).await?;
    assert_eq!(server.restored, 1);
    server.stop().await?;

    // One changed bit in a recorded hash, and verify names the game.
    let tampered = room.clone();
    let checks = blocking(move || {
        let store = Store::at(&location)?;
        let mut record =
            GameRecord::decode(&store.record(&tampered, 1)?.expect("stored")).expect("a record");
        let shot = record.entries.iter_mut().find(|e| e.hash.is_some());
        let shot = shot.expect("a shot");
        shot.hash = shot.hash.map(|h| h ^ 1);
        store.overwrite_record(&tampered, 1, &record.encode())?;
        verify_store(&location)
    })
    .await?;
    let failed: Vec<_> = checks.iter().filter(|c| c.result.is_err()).collect();
    assert_eq!(failed.len(), 1, "{checks:?}");
    assert_eq!(failed[0].room, room);
    Ok(())
}

/// The PostgreSQL driver blocks on a runtime of its own: it runs off the test's runtime.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, StoreError> + Send + 'static,
) -> anyhow::Result<T> {
    Ok(tokio::task::spawn_blocking(f).await??)
}
