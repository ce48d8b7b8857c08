//! Golden hashes: a fixed set of shots whose event count and state hash are committed in
//! `tests/golden/hashes.txt`. Any change of a single bit in any result fails this test, in
//! debug and in release builds alike.
//!
//! The shots are listed in `tests/golden/shots.rs`, which the WebAssembly build of them
//! (`web/golden`) shares, so the browser's bits are checked against this same file.
//!
//! The handshake's reference shots (one per mechanism) and the physics fingerprint made of
//! them are among the entries, so a physics change that moves the fingerprint shows here.
//!
//! After a deliberate change to the physics, regenerate the file and review what changed:
//!
//! ```sh
//! BREAKSHOT_BLESS=1 cargo test -p breakshot-shared --test golden
//! ```

#[path = "golden/shots.rs"]
mod shots;

use std::collections::BTreeMap;
use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn read_expected() -> BTreeMap<String, (usize, String)> {
    let text = std::fs::read_to_string(dir().join("hashes.txt")).unwrap_or_default();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let parts: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(parts.len(), 3, "bad line in hashes.txt: {l}");
            (
                parts[0].to_string(),
                (parts[1].parse().expect("event count"), parts[2].to_string()),
            )
        })
        .collect()
}

#[test]
fn golden_hashes_hold() {
    let results = shots::results();
    let mut actual = BTreeMap::new();
    for (name, result) in &results {
        match result {
            Ok(got) => {
                actual.insert(name.clone(), got.clone());
            }
            Err(why) => panic!("golden shot {name} failed: {why}"),
        }
    }
    let expected = read_expected();
    let mut changes = Vec::new();
    for (name, got) in &actual {
        match expected.get(name) {
            Some(want) if want == got => {}
            Some(want) => changes.push(format!(
                "{name}: {} events {} -> {} events {}",
                want.0, want.1, got.0, got.1
            )),
            None => changes.push(format!("{name}: new, {} events {}", got.0, got.1)),
        }
    }
    for name in expected.keys().filter(|n| !actual.contains_key(*n)) {
        changes.push(format!("{name}: removed"));
    }
    if std::env::var_os("BREAKSHOT_BLESS").is_some() {
        let mut text = String::from(
            "# name events hash — regenerate with BREAKSHOT_BLESS=1 (see golden.rs)\n",
        );
        text.push_str(&shots::to_text(&results));
        std::fs::write(dir().join("hashes.txt"), text).expect("write hashes.txt");
        for c in &changes {
            println!("changed: {c}");
        }
        return;
    }
    assert!(
        changes.is_empty(),
        "golden hashes changed:\n{}",
        changes.join("\n")
    );
}
