//! `breakshot-sim fit` as a black box: the contract's outputs from a small recording made
//! here, and a clear failure on a file that is not recordings.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

use breakshot_testkit::TempDir;

/// Runs the simulator, failing the test if it has not finished within `limit`.
fn sim(args: &[&str], limit: Duration) -> Output {
    breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot-sim")).args(args),
        None,
        limit,
    )
}

/// A scratch folder `name` holding `rec.json` with `text`. Returns the folder (removed when
/// dropped), that file's path as an argument, and an output folder `out` in it.
fn scratch_with(name: &str, text: &str) -> (TempDir, String, PathBuf) {
    let dir = breakshot_testkit::scratch(name);
    let rec = dir.path().join("rec.json");
    std::fs::write(&rec, text).expect("recording written");
    let out = dir.path().join("out");
    (dir, rec.to_string_lossy().into_owned(), out)
}

/// Asserts that the fit failed with exit code `code`, saying what was wrong (its error
/// names `names`) without a panic, and wrote nothing to `out`.
fn assert_refused(o: &Output, code: i32, names: &str, out: &Path) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert!(err.contains(names) && !err.contains("panicked"), "{err}");
    assert!(!out.exists(), "nothing written");
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
    let (_dir, rec_s, out) = scratch_with("fit-outputs", &recording());
    let out_s = out.to_string_lossy();
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
    let (_dir, rec_s, out) = scratch_with("fit-bad", r#"{"balls": []}"#);
    let out_s = out.to_string_lossy();
    let o = sim(&["fit", &rec_s, "--out", &out_s], Duration::from_secs(60));
    assert_refused(&o, 1, "recordings", &out);
    let o = sim(
        &["fit", &rec_s, "--out", &out_s, "--units", "furlongs"],
        Duration::from_secs(60),
    );
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn fit_starts_from_the_parameters_named_and_writes_its_own() {
    let (dir, rec_s, _) = scratch_with("fit-start", &recording());
    let fit = |out: &str, extra: &[&str]| {
        let out = dir.path().join(out);
        let out_s = out.to_string_lossy().into_owned();
        let mut args = vec!["fit", &rec_s, "--out", &out_s, "--units", "m"];
        args.extend_from_slice(extra);
        (sim(&args, Duration::from_secs(300)), out)
    };
    // `defaults` starts from the carom table's own parameters, and the fit writes the
    // parameters it ends with as a physics file, which `--start` reads back.
    let (o, out) = fit(
        "defaults",
        &["--strikes-only", "--iters", "10", "--start", "defaults"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("fit.md")).expect("fit.md");
    assert!(md.contains("the carom table's defaults"), "{md}");
    let physics = out.join("physics.json");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&physics).expect("physics.json"))
            .expect("JSON");
    assert_eq!(written["ball_radius"], 0.03075, "the carom ball: {written}");
    let physics_s = physics.to_string_lossy().into_owned();
    let (o, out) = fit(
        "file",
        &["--strikes-only", "--iters", "10", "--start", &physics_s],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("physics.json")).expect("read"))
            .expect("JSON");
    assert_eq!(again, written, "strikes only: the parameters are kept");
    // A bad start is a usage error that says what is wrong, and nothing is written.
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, r#"{"mu_slide": "slow"}"#).expect("written");
    let bad_s = bad.to_string_lossy().into_owned();
    for arg in ["carom", bad_s.as_str()] {
        let (o, out) = fit("bad", &["--strikes-only", "--start", arg]);
        assert_refused(&o, 2, "--start", &out);
    }
    // So is a loss it does not know.
    let (o, out) = fit("bad", &["--loss", "median"]);
    assert_refused(&o, 2, "--loss median", &out);
}

#[test]
fn folds_need_two_and_the_shared_fit() {
    let (_dir, rec_s, out) = scratch_with("fit-folds", &recording());
    let out_s = out.to_string_lossy();
    for extra in [
        &["--folds", "1"][..],
        &["--folds", "2", "--strikes-only"][..],
    ] {
        let mut args = vec!["fit", &rec_s, "--out", &out_s, "--units", "m"];
        args.extend_from_slice(extra);
        let o = sim(&args, Duration::from_secs(60));
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("--folds"));
    }
    // One shot cannot be dealt into two folds: a clear failure, not a panic.
    let o = sim(
        &[
            "fit", &rec_s, "--out", &out_s, "--units", "m", "--folds", "2",
        ],
        Duration::from_secs(60),
    );
    assert_refused(&o, 1, "--folds 2", &out);
}
