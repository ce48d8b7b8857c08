//! `breakshot-sim fit` as a black box: the contract's outputs from a small recording made
//! here, and a clear failure on a file that is not recordings.

use std::process::{Command, Output};
use std::time::Duration;

/// Runs the simulator, failing the test if it has not finished within `limit`.
fn sim(args: &[&str], limit: Duration) -> Output {
    breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot-sim")).args(args),
        None,
        limit,
    )
}

/// One shot in the recordings' format, in metres: the cue ball rolls 0.3 m along the
/// table's long axis in 0.2 s; the other ball stays put.
fn recording() -> String {
    let t: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.02).collect();
    let x: Vec<f64> = t.iter().map(|t| 1.6 * t - 0.5 * t * t).collect();
    let y = vec![0.0; t.len()];
    format!(
        r#"[{{"id": 42, "balls": {{
            "1": {{"t": {t:?}, "x": {x:?}, "y": {y:?}}},
            "2": {{"t": [0, 0.2], "x": [0.8, 0.8], "y": [0.3, 0.3]}}}}}}]"#
    )
}

#[test]
fn fit_writes_the_contract_outputs() {
    let dir = breakshot_testkit::scratch("fit-outputs");
    let rec = dir.path().join("rec.json");
    std::fs::write(&rec, recording()).expect("recording written");
    let out = dir.path().join("out");
    let (rec_s, out_s) = (rec.to_string_lossy(), out.to_string_lossy());
    let args = [
        "fit",
        &rec_s,
        "--out",
        &out_s,
        "--units",
        "m",
        "--strikes-only",
        "--iters",
        "10",
    ];
    let o = sim(&args, Duration::from_secs(300));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("fit.csv")).expect("fit.csv");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let id = header.iter().position(|c| *c == "id").expect("id column");
    let rmse = header
        .iter()
        .position(|c| *c == "rmse_m")
        .expect("rmse_m column");
    let row: Vec<&str> = lines.next().expect("one row").split(',').collect();
    assert_eq!(row[id], "42");
    let rmse: f64 = row[rmse].parse().expect("a number");
    // A straight roll is easy to match: well under the 2 cm the ball moves per sample.
    assert!((0.0..0.02).contains(&rmse), "RMSE {rmse}");
    for file in ["fit.md", "paths.png", "rmse.png"] {
        assert!(out.join(file).is_file(), "{file} written");
    }
}

#[test]
fn fit_refuses_what_is_not_recordings() {
    let dir = breakshot_testkit::scratch("fit-bad");
    let rec = dir.path().join("rec.json");
    std::fs::write(&rec, r#"{"balls": []}"#).expect("file written");
    let out = dir.path().join("out");
    let (rec_s, out_s) = (rec.to_string_lossy(), out.to_string_lossy());
    let o = sim(&["fit", &rec_s, "--out", &out_s], Duration::from_secs(60));
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("recordings") && !err.contains("panicked"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
    let o = sim(
        &["fit", &rec_s, "--out", &out_s, "--units", "furlongs"],
        Duration::from_secs(60),
    );
    assert_eq!(o.status.code(), Some(2));
}
