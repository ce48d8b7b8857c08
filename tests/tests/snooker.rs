//! Snooker through a real server: a whole frame between two bots, every client's copy of
//! each stroke matching the server's, the record replaying to the same scores, and the
//! frame ended by the rules (the last black, a forfeit after three misses), not conceded.

use std::time::Duration;

use breakshot_client::bot::BotConfig;
use breakshot_server::verify::verify_dir;
use breakshot_shared::physics::TableKind;
use breakshot_shared::rules::snooker::frame::{MAX_PENALTY, MIN_PENALTY};
use breakshot_shared::rules::{Command, Game, Phase, Variant};
use breakshot_tests::{bot_game, TestServer};

/// A frame of 15 reds between two bots takes a few hundred strokes: more than one
/// game's usual patience.
const FRAME_PATIENCE: Duration = Duration::from_secs(240);

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_bots_play_a_whole_frame_of_snooker_through_the_server_without_a_desync(
) -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("snooker-frame").await?;
    let mut config = BotConfig::new(server.invite.clone(), 1);
    let variant = Variant::snooker();
    config.variant = variant;
    let (report, record) = bot_game(server, &config, FRAME_PATIENCE).await?;

    // The record is a frame on the snooker table; replayed by the rules, the scores only
    // grow, a fair stroke by the striker's pots, a foul by 4 to 7 to the other player.
    assert_eq!(record.variant, variant);
    let mut game = Game::new(record.variant, record.settings, record.seed);
    assert_eq!(game.table(), TableKind::Snooker);
    let (mut strokes, mut fouls) = (0, 0);
    for e in &record.entries {
        assert_ne!(e.command, Command::Concede, "{}", report.games[0].reason);
        let before = game.snooker().expect("a snooker game").scores;
        let verdict = game.apply(e.seat, &e.command)?;
        let after = game.snooker().expect("a snooker game").scores;
        let gained = [after[0] - before[0], after[1] - before[1]];
        let (own, other) = (gained[e.seat.index()], gained[e.seat.other().index()]);
        if let Command::Shot { .. } = &e.command {
            strokes += 1;
            assert_eq!(verdict.shot.map(|s| s.hash), e.hash);
            if verdict.foul {
                fouls += 1;
                assert_eq!(own, 0, "{:?}", verdict.reasons);
                assert!(
                    (MIN_PENALTY..=MAX_PENALTY).contains(&other),
                    "{:?}",
                    verdict.reasons
                );
            } else {
                assert_eq!(other, 0, "{:?}", verdict.reasons);
            }
        } else {
            assert_eq!(gained, [0, 0], "{:?}: {:?}", e.command, verdict.reasons);
        }
    }
    let Phase::Over { winner, reason } = game.phase() else {
        panic!("the record does not end the frame: {:?}", game.phase());
    };
    assert!(winner.is_some(), "{reason}");
    assert_eq!(strokes, report.tally.shots);
    let m = game.snooker().expect("a snooker game");
    eprintln!(
        "snooker frame over after {strokes} strokes ({fouls} fouls), {}-{}: {reason}",
        m.scores[0], m.scores[1]
    );

    // The stored record replays to the same hashes.
    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 1);
    assert!(checks[0].result.is_ok(), "{:?}", checks[0].result);
    assert!(checks[0].finished);
    Ok(())
}
