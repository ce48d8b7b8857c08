//! The `breakshot-server` command as an operator uses it.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use breakshot_server::output::{RoomMeta, StoreOp};
use breakshot_server::store::Store;
use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{AimAid, Invite, RoomCode};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{Command as Cmd, EightBallRules, Game, Settings, Variant};
use glam::DVec2;

const BIN: &str = env!("CARGO_BIN_EXE_breakshot-server");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("breakshot-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Stores one game of two real shots, with `tamper` flipping a bit of the second hash.
fn store_game(dir: &Path, tamper: bool) {
    let variant = Variant::EightBall(EightBallRules::Wpa);
    let settings = Settings::offline();
    let mut game = Game::new(variant, settings, 42);
    let mut record = GameRecord::new(variant, settings, 42);
    for speed in [9.0, 3.0] {
        let seat = game.to_move();
        let cue = game.balls()[0].pos;
        let command = Cmd::Shot {
            strike: Strike {
                speed,
                dir: nearest_ball(&game) - cue,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
            call: None,
        };
        let Ok(verdict) = game.apply(seat, &command) else {
            // After the break the rules may want the cue ball placed first: one shot is
            // enough then.
            break;
        };
        record.push(seat, command, verdict.shot.map(|s| s.hash));
    }
    if tamper {
        let last = record.entries.last_mut().unwrap();
        last.hash = last.hash.map(|h| h ^ 1);
    }
    let code = RoomCode::parse("K7QX2M4B").unwrap();
    let ops = [StoreOp::Room(RoomMeta {
        code: code.clone(),
        variant,
        settings,
        aim_aid: AimAid::Off,
        seats: [None, None],
    })]
    .into_iter()
    .chain(StoreOp::whole_game(&code, 1, &record))
    .collect::<Vec<_>>();
    Store::open(dir)
        .unwrap()
        .apply(&ops.iter().collect::<Vec<_>>())
        .unwrap();
}

/// The position of the object ball nearest the cue ball.
fn nearest_ball(game: &Game) -> DVec2 {
    let cue = game.balls()[0].pos;
    game.balls()[1..]
        .iter()
        .map(|b| b.pos)
        .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
        .unwrap()
}

#[test]
fn verify_reports_each_game_and_fails_on_a_tampered_one() {
    let dir = scratch("verify");
    store_game(&dir, false);
    let out = Command::new(BIN)
        .args(["verify", "--data"])
        .arg(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("verified K7QX2M4B game 1"), "{text}");
    assert!(text.contains("1 games: 1 verified, 0 failed"), "{text}");

    store_game(&dir, true);
    let out = Command::new(BIN)
        .args(["verify", "--data"])
        .arg(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("FAILED   K7QX2M4B game 1"), "{text}");
    assert!(text.contains("state hash differs"), "{text}");

    let out = Command::new(BIN)
        .args(["verify", "--data"])
        .arg(dir.join("nothing"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_server_prints_its_invite_first_and_stops_cleanly_on_ctrl_c() {
    let dir = scratch("serve");
    let mut child = Command::new(BIN)
        .args(["--bind", "127.0.0.1:0", "--data"])
        .arg(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let invite: Invite = line.trim().parse().unwrap();
    assert_eq!(invite.host, "127.0.0.1");
    assert_ne!(invite.port, 0);
    assert!(invite.room.is_none());

    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    assert!(child.wait().unwrap().success());
    std::fs::remove_dir_all(&dir).unwrap();
}
