//! `breakshot-sim fit` as a black box: the contract's outputs from a small recording made
//! here, and a clear failure on a file that is not recordings.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the simulator, failing the test if it has not finished within `limit`.
fn sim(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_breakshot-sim"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("breakshot-sim starts");
    let start = Instant::now();
    loop {
        if child
            .try_wait()
            .expect("waiting for breakshot-sim")
            .is_some()
        {
            return child.wait_with_output().expect("breakshot-sim output");
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("breakshot-sim {args:?} did not finish within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A folder of its own under the build's temporary directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
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
    let dir = Scratch::new("fit-outputs");
    let rec = dir.0.join("rec.json");
    std::fs::write(&rec, recording()).expect("recording written");
    let out = dir.0.join("out");
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
    let dir = Scratch::new("fit-bad");
    let rec = dir.0.join("rec.json");
    std::fs::write(&rec, r#"{"balls": []}"#).expect("file written");
    let out = dir.0.join("out");
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
