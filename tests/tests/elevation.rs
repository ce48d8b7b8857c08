//! A shot with an elevated cue through a real server: the elevation crosses the wire, the
//! server and both players simulate the same jump to the last bit, and the stored record
//! keeps it. A strike with an elevation out of range is refused and changes nothing.

use breakshot_client::net::fetch_record;
use breakshot_server::verify::verify_dir;
use breakshot_shared::physics::{MotionState, Strike};
use breakshot_shared::protocol::{ClientMessage, ErrorCode, ServerMessage};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::Command;
use breakshot_tests::{break_shot, seated_pair, TestServer};

/// The cue elevation of the jump break (degrees).
const JUMP_DEG: f64 = 40.0;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_jump_shot_is_played_through_the_server_with_no_desync() -> anyhow::Result<()> {
    let (data, server) = TestServer::start_fresh("elevation").await?;
    let (mut a, mut b, room) = seated_pair(&server.invite).await?;
    let game = a.game().expect("a game after joining").clone();
    let ClientMessage::Shot { turn, strike, .. } = break_shot(&game) else {
        unreachable!()
    };

    // Out of range or not a number: refused, and the turn is still the break.
    for bad in [f64::NAN, -1.0, 90.5] {
        a.send(ClientMessage::Shot {
            turn,
            strike: Strike {
                elevation_deg: bad,
                ..strike
            },
            call: None,
        })
        .await?;
        match a.error().await? {
            ServerMessage::Error { code, message } => {
                assert_eq!(code, ErrorCode::Invalid, "{message}");
                assert!(message.contains("elevation"), "{message}");
            }
            other => unreachable!("{other:?}"),
        }
        assert_eq!(a.game().map(|g| g.turn()), Some(turn));
    }

    // The break with the cue elevated, a little below centre: the cue ball leaves the cloth.
    let jump = Strike {
        speed: 6.0,
        elevation_deg: JUMP_DEG,
        tip: glam::DVec2::new(0.0, -0.1),
        ..strike
    };
    a.send(ClientMessage::Shot {
        turn,
        strike: jump,
        call: None,
    })
    .await?;
    for p in [&mut a, &mut b] {
        loop {
            let msg = p.recv().await?;
            if let ServerMessage::ShotAccepted { command, .. } = &msg {
                // Everyone is told the strike as it was sent (its aim normalised), elevation
                // and all.
                let Command::Shot { strike, .. } = command else {
                    panic!("{command:?}")
                };
                assert_eq!(strike.validated(), jump.validated());
                assert_eq!(strike.elevation_deg, JUMP_DEG);
            }
            if matches!(msg, ServerMessage::ShotResolved { .. }) {
                break;
            }
            assert!(!matches!(msg, ServerMessage::Error { .. }), "{msg:?}");
        }
        // The player's own simulation of the jump matched the server's hash.
        assert_eq!(p.replica.desyncs(), 0);
        assert_eq!(p.replica.confirmed(), 1);
        // What the player shows is a jump: the cue ball flies.
        let shown = p.replica.playback().expect("the shot is being shown");
        let events: Vec<String> = shown
            .outcome()
            .events
            .iter()
            .take(8)
            .map(|e| e.kind.name())
            .collect();
        assert!(
            shown.outcome().history[0]
                .iter()
                .any(|piece| piece.start.motion == MotionState::Airborne),
            "the cue ball never left the cloth: {events:?}"
        );
    }

    // The stored record keeps the elevation and replays to the same hash.
    let fetched = fetch_record(&server.invite, &room).await?;
    server.stop().await?;
    let record = GameRecord::decode(&fetched.bytes)?;
    let Command::Shot { strike, .. } = &record.entries[0].command else {
        panic!("the first entry is not the break: {:?}", record.entries[0]);
    };
    assert_eq!(strike.elevation_deg, JUMP_DEG);
    record.replay()?;
    let checks = verify_dir(data.path())?;
    assert_eq!(checks.len(), 1);
    assert!(checks[0].result.is_ok(), "{:?}", checks[0].result);
    Ok(())
}
