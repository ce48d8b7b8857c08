//! Strangers meet through quick match on a real server, with no invite to a room: they are
//! paired, play a rated game through, and both ratings change as Glicko-2 says (the
//! `skillratings` crate's own numbers), then survive a restart on both store backends. The
//! lobby lists the game to watch while it is played.

use std::time::Duration;

use anyhow::{bail, Result};
use breakshot_client::bot::{run, BotConfig};
use breakshot_server::ratings::PlayerRating;
use breakshot_server::store::{Location, Store};
use breakshot_server::Limits;
use breakshot_shared::protocol::{
    ClientMessage, GameInPlay, RoomCode, SeatToken, ServerMessage, WaitingRoom,
};
use breakshot_tests::postgres::Cluster;
use breakshot_tests::{scratch, Player, Reads, TestServer, PATIENCE};
use skillratings::glicko2::{glicko2, Glicko2Config, Glicko2Rating};
use skillratings::Outcomes;

/// Both bots connect from 127.0.0.1: the test server lets one address be paired (a public
/// one does not; `server::matchmaking`'s tests hold that rule).
/// Ann's room, created and published in the lobby of `server`.
async fn published(server: &TestServer) -> Result<(Player, RoomCode)> {
    let mut host = Player::connect(&server.invite).await?;
    let room = breakshot_tests::create_room(&mut host, "ann").await?;
    host.send(ClientMessage::Publish).await?;
    host.until("the listing", |m| {
        matches!(m, ServerMessage::Published { .. })
    })
    .await?;
    Ok((host, room))
}

/// Checks that the lobby `p` is sent lists `room`, Ann's, and nothing else waiting.
async fn assert_waiting(p: &mut Player, room: &RoomCode) -> Result<()> {
    let (waiting, _) = lobby(p).await?;
    assert_eq!(waiting.len(), 1, "{waiting:?}");
    assert_eq!(&waiting[0].room, room);
    assert_eq!(waiting[0].host, "ann");
    Ok(())
}

/// The lobby's first page as `p` is sent it: the rooms waiting and the games in play.
async fn lobby(p: &mut Player) -> Result<(Vec<WaitingRoom>, Vec<GameInPlay>)> {
    p.send(ClientMessage::ListGames { page: 0 }).await?;
    match p
        .until("the lobby", |m| matches!(m, ServerMessage::Games { .. }))
        .await?
    {
        ServerMessage::Games {
            waiting, playing, ..
        } => Ok((waiting, playing)),
        other => bail!("expected the lobby, got {other:?}"),
    }
}

fn config_at(data: &std::path::Path, store: Option<Location>) -> breakshot_server::Config {
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data);
    config.limits = Limits {
        match_one_address: true,
        ..Limits::default()
    };
    if let Some(store) = store {
        config.store = store;
    }
    config
}

/// What the crate says two new players' ratings become when one beats the other.
fn expected() -> (Glicko2Rating, Glicko2Rating) {
    glicko2(
        &Glicko2Rating::new(),
        &Glicko2Rating::new(),
        &Outcomes::WIN,
        &Glicko2Config::new(),
    )
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// Plays one quick match with two bots, checks the game and the ratings stored, restarts
/// the server on the same store and checks the leaderboard it serves.
async fn quick_match_rates_and_remembers(
    data: &std::path::Path,
    store: Option<Location>,
) -> Result<()> {
    let server = TestServer::start_with(config_at(data, store.clone())).await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    config.quick_match = true;
    let report = tokio::time::timeout(PATIENCE, run(&config))
        .await
        .map_err(|_| anyhow::anyhow!("the quick match never finished"))?;
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.games_completed, 1);
    assert_eq!(report.tally.desyncs, 0);
    assert_eq!(report.tally.confirmed, 2 * report.tally.shots);
    let game = &report.games[0];
    eprintln!(
        "quick match over after {} shots: {}",
        report.tally.shots, game.reason
    );
    server.stop().await?;

    // Both ratings, as stored, are the crate's numbers for a win and a loss.
    let location = store.unwrap_or_else(|| Location::Sqlite(data.to_path_buf()));
    // The PostgreSQL driver blocks on a runtime of its own: read on a plain thread.
    let stored = {
        let location = location.clone();
        tokio::task::spawn_blocking(move || Store::at(&location)?.ratings()).await??
    };
    assert_eq!(stored.len(), 2, "{stored:?}");
    let (win, loss) = expected();
    let mut ratings: Vec<&PlayerRating> = stored.iter().map(|(_, r)| r).collect();
    ratings.sort_by(|a, b| b.rating.total_cmp(&a.rating));
    for (got, want) in ratings.iter().zip([win, loss]) {
        assert!(close(got.rating, want.rating), "{got:?} vs {want:?}");
        assert!(close(got.deviation, want.deviation), "{got:?} vs {want:?}");
        assert!(
            close(got.volatility, want.volatility),
            "{got:?} vs {want:?}"
        );
        assert_eq!(got.games, 1);
    }
    assert!(ratings[0].rating > 1500.0 && ratings[1].rating < 1500.0);

    // A new server on the same store serves them on its leaderboard.
    let server = TestServer::start_with(config_at(data, Some(location))).await?;
    let mut p = Player::connect(&server.invite).await?;
    p.send(ClientMessage::Leaderboard { page: 0 }).await?;
    match p.recv().await? {
        ServerMessage::Leaders { players, pages, .. } => {
            assert_eq!(pages, 1);
            assert_eq!(players.len(), 2);
            assert_eq!(players[0].rating, win.rating.round() as i32);
            assert_eq!(players[1].rating, loss.rating.round() as i32);
            assert_eq!(players[0].rank, 1);
        }
        other => bail!("expected the leaderboard, got {other:?}"),
    }
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn strangers_meet_through_quick_match_and_their_ratings_survive_a_restart() -> Result<()> {
    let data = scratch("quick-match");
    quick_match_rates_and_remembers(data.path(), None).await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn on_postgres_the_ratings_survive_a_restart_too() -> Result<()> {
    let Some(cluster) = Cluster::start("quick_match_postgres") else {
        return Ok(());
    };
    let data = scratch("quick-match-pg");
    quick_match_rates_and_remembers(data.path(), Some(Location::Postgres(cluster.url.clone())))
        .await
}

/// Asks for a quick match of 8-ball.
fn quick(name: &str) -> ClientMessage {
    ClientMessage::QuickMatch {
        variant: breakshot_tests::eight_ball(),
        mode: breakshot_shared::rules::Settings::online(),
        name: name.into(),
    }
}

/// Reads until this player is seated, and returns the seat's token.
async fn seated(p: &mut Player) -> Result<SeatToken> {
    match p
        .until("seated", |m| matches!(m, ServerMessage::Joined { .. }))
        .await?
    {
        ServerMessage::Joined { token: Some(t), .. } => Ok(t),
        other => bail!("expected a seat, got {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_rated_game_the_server_restarted_in_is_rated_when_it_ends() -> Result<()> {
    let data = scratch("quick-match-restart");
    let server = TestServer::start_with(config_at(data.path(), None)).await?;
    let mut ann = Player::connect(&server.invite).await?;
    ann.send(quick("ann")).await?;
    ann.until("queued", |m| matches!(m, ServerMessage::Queued { .. }))
        .await?;
    let mut bob = Player::connect(&server.invite).await?;
    bob.send(quick("bob")).await?;
    let (token_a, token_b) = (seated(&mut ann).await?, seated(&mut bob).await?);
    server.stop().await?;

    // The same data, a new server: both come back to their seats and bob concedes.
    let server = TestServer::start_with(config_at(data.path(), None)).await?;
    let mut rated = Vec::new();
    let mut players = Vec::new();
    for token in [token_a, token_b] {
        let mut p = Player::connect(&server.invite).await?;
        p.send(ClientMessage::Rejoin { token }).await?;
        p.until("back in the seat", |m| {
            matches!(m, ServerMessage::Joined { .. })
        })
        .await?;
        players.push(p);
    }
    // Listed again as a rated game to watch.
    let mut finder = Player::connect(&server.invite).await?;
    let (_, playing) = lobby(&mut finder).await?;
    assert_eq!(playing.len(), 1, "{playing:?}");
    assert!(playing[0].rated);
    assert_eq!(playing[0].names, ["ann".to_string(), "bob".to_string()]);
    players[1].send(ClientMessage::Concede).await?;
    for _ in 0..2 {
        let told = players[0]
            .until("the ratings", |m| matches!(m, ServerMessage::Rated { .. }))
            .await?;
        if let ServerMessage::Rated { before, after, .. } = told {
            rated.push((before, after));
        }
    }
    let (win, loss) = expected();
    let shown = |r: f64| r.round() as i32;
    assert_eq!(
        rated,
        [(1500, shown(win.rating)), (1500, shown(loss.rating))],
        "seat A won, seat B lost: Glicko-2's numbers for two new players"
    );
    server.stop().await?;
    let stored = Store::open(data.path())?.ratings()?;
    assert_eq!(stored.len(), 2, "both ratings stored: {stored:?}");
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_published_room_is_listed_again_by_a_server_restarted_on_its_data() -> Result<()> {
    let data = scratch("lobby-restart");
    let server = TestServer::start_with(config_at(data.path(), None)).await?;
    let (_host, room) = published(&server).await?;
    server.stop().await?;
    let server = TestServer::start_with(config_at(data.path(), None)).await?;
    let mut finder = Player::connect(&server.invite).await?;
    assert_waiting(&mut finder, &room).await?;
    // And a stranger joins it from there.
    finder.join(&room, "bob").await?;
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_published_room_is_in_the_lobby_and_a_queued_player_can_leave() -> Result<()> {
    let (_data, server) = TestServer::start_fresh("lobby").await?;
    let (_host, room) = published(&server).await?;
    let mut finder = Player::connect(&server.invite).await?;
    assert_waiting(&mut finder, &room).await?;
    // A player who queues and leaves is out of the queue; one who drops is too.
    finder
        .send(ClientMessage::QuickMatch {
            variant: breakshot_tests::eight_ball(),
            mode: breakshot_shared::rules::Settings::online(),
            name: "bob".into(),
        })
        .await?;
    finder
        .until("queued", |m| {
            matches!(m, ServerMessage::Queued { waiting: 1, .. })
        })
        .await?;
    finder.send(ClientMessage::LeaveQueue).await?;
    finder
        .until("out of the queue", |m| {
            matches!(m, ServerMessage::Unqueued { .. })
        })
        .await?;

    // A storm of lobby pages and queue joins and leaves: refused beyond their budgets, with
    // nothing left queued and the connection still served.
    let storm = |n: usize| match n % 3 {
        0 => ClientMessage::ListGames { page: 0 },
        1 => ClientMessage::QuickMatch {
            variant: breakshot_tests::eight_ball(),
            mode: breakshot_shared::rules::Settings::online(),
            name: "eve".into(),
        },
        _ => ClientMessage::LeaveQueue,
    };
    for n in 0..30 {
        finder.send(storm(n)).await?;
    }
    let mut limited = 0;
    for _ in 0..30 {
        if let ServerMessage::Error {
            code: breakshot_shared::protocol::ErrorCode::RateLimited,
            ..
        } = finder.recv().await?
        {
            limited += 1;
        }
    }
    assert!(limited >= 10, "only {limited} of 30 refused");
    finder.send(ClientMessage::LeaveQueue).await?;
    let deadline = tokio::time::Instant::now() + PATIENCE;
    loop {
        let queued: usize = server
            .stats
            .queued
            .lock()
            .unwrap()
            .iter()
            .map(|q| q.1)
            .sum();
        if queued == 0 {
            break;
        }
        if tokio::time::Instant::now() > deadline {
            bail!("{queued} still queued after the storm");
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    server.stop().await
}
