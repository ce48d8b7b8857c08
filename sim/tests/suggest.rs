//! `breakshot-sim suggest` as a black box: the contract's JSON object, and clear refusals.

use std::process::Command;
use std::time::Duration;

use serde_json::Value;

/// Runs `breakshot-sim suggest` on `scene` (given on standard input) with `args`; fails the
/// test if it does not finish within a minute.
fn suggest(scene: &str, args: &[&str]) -> (i32, String, String) {
    let out = breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot-sim"))
            .args(["suggest", "-"])
            .args(args),
        Some(scene.as_bytes()),
        Duration::from_secs(60),
    );
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const SCENE: &str = r#"{"table": "9ft", "balls": [
    {"id": "cue", "pos": [0.3, 1.2]},
    {"id": "1", "pos": [0.15, 1.9]},
    {"id": "2", "pos": [1.0, 0.6]}
]}"#;

#[test]
fn suggest_prints_the_contract_object() {
    let (code, out, err) = suggest(SCENE, &["--targets", "1", "--level", "5", "--seed", "4"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).expect("one JSON object");
    let strike = &v["strike"];
    assert_eq!(strike["ball"], "cue");
    assert!(strike["speed"].as_f64().expect("speed") > 0.0);
    let dir = strike["dir"].as_array().expect("dir");
    assert_eq!(dir.len(), 2);
    assert_eq!(strike["tip"].as_array().expect("tip").len(), 2);
    assert_eq!(strike["elevation_deg"].as_f64(), Some(0.0));
    let p = v["p_success"].as_f64().expect("p_success");
    assert!((0.0..=1.0).contains(&p));
    // A straight-in pot at the top level: it should be confident.
    assert!(p > 0.8, "p_success {p}");
    // The same seed gives the same answer.
    let (_, again, _) = suggest(SCENE, &["--targets", "1", "--level", "5", "--seed", "4"]);
    assert_eq!(out, again);
}

#[test]
fn suggest_refuses_unknown_targets_and_levels() {
    for args in [
        &["--targets", "7"][..],
        &["--targets", "cue"][..],
        &["--targets", "1", "--level", "9"][..],
    ] {
        let (code, out, err) = suggest(SCENE, args);
        assert_eq!(code, 2, "{args:?}: {out}");
        assert!(out.is_empty());
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    let (code, _, err) = suggest(
        r#"{"balls": [{"id": "1", "pos": [0.5, 0.5]}]}"#,
        &["--targets", "1"],
    );
    assert_eq!(code, 2);
    assert!(err.contains("cue"), "{err}");
}
