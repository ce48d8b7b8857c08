//! The command line refuses bad input with a clear message before any window opens.

use std::process::{Command, Output};

fn breakshot(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_breakshot"))
        .args(args)
        .output()
        .expect("breakshot runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn temp_file(name: &str, contents: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("breakshot-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("file written");
    path
}

#[test]
fn a_missing_scene_file_is_named() {
    let out = breakshot(&["practice", "/nonexistent/scene.json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cannot read /nonexistent/scene.json"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn an_invalid_scene_names_the_balls_at_fault() {
    let scene = r#"{"balls":[{"id":"cue","pos":[0.5,0.5]},{"id":"1","pos":[0.5,0.51]}]}"#;
    let path = temp_file("overlap.json", scene.as_bytes());
    let out = breakshot(&["practice", path.to_str().expect("utf-8 path")]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("\"cue\" and \"1\" overlap"), "{err}");
}

#[test]
fn a_file_that_is_not_a_game_record_is_refused() {
    let path = temp_file("garbage.rec", b"\xff\xff\xff\xff not a record");
    let out = breakshot(&["replay", path.to_str().expect("utf-8 path")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("is not a game record"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_options_are_refused() {
    for args in [
        &["practice", "--frames", "0"][..],
        &["practice", "--size", "12x"][..],
        &["local", "--mode", "snooker"][..],
    ] {
        let out = breakshot(args);
        assert_ne!(out.status.code(), Some(0), "{args:?} was accepted");
        assert!(!stderr(&out).is_empty(), "{args:?}: no message");
    }
}

#[test]
fn network_commands_say_when_they_are_not_in_the_build() {
    for args in [&["host"][..], &["join", "some-invite"][..]] {
        let out = breakshot(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains("not available"), "{}", stderr(&out));
    }
}
