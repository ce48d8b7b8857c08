//! The command line refuses bad input with a clear message before any window opens.

use std::process::{Command, Output};
use std::time::Duration;

use breakshot_testkit::TempDir;

mod common;

/// Runs `breakshot` with `args`; fails the test if it has not ended within a minute.
fn breakshot(args: &[&str]) -> Output {
    breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot")).args(args),
        None,
        Duration::from_secs(60),
    )
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs `breakshot` with `args`, checks that it refused them (exit code 2), and returns what
/// it said.
fn refused(args: &[&str]) -> String {
    let out = breakshot(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    err
}

/// Checks that `breakshot` refuses `args` saying `why`.
fn refused_saying(args: &[&str], why: &str) {
    let err = refused(args);
    assert!(err.contains(why), "{args:?}: {err}");
}

/// A file in a scratch folder of its own, removed with the folder when dropped, even if the
/// test fails.
struct TempFile {
    _dir: TempDir,
    path: String,
}

impl TempFile {
    fn path(&self) -> &str {
        &self.path
    }
}

fn temp_file(name: &str, contents: &[u8]) -> TempFile {
    let dir = breakshot_testkit::scratch("cli");
    let path = dir.path().join(name);
    std::fs::write(&path, contents).expect("file written");
    TempFile {
        path: path.to_str().expect("utf-8 path").to_owned(),
        _dir: dir,
    }
}

#[test]
fn a_missing_scene_file_is_named() {
    refused_saying(
        &["practice", "/nonexistent/scene.json"],
        "cannot read /nonexistent/scene.json",
    );
}

#[test]
fn an_invalid_scene_names_the_balls_at_fault() {
    let scene = r#"{"balls":[{"id":"cue","pos":[0.5,0.5]},{"id":"1","pos":[0.5,0.51]}]}"#;
    let path = temp_file("overlap.json", scene.as_bytes());
    refused_saying(&["practice", path.path()], "\"cue\" and \"1\" overlap");
}

#[test]
fn a_file_that_is_not_a_game_record_is_refused() {
    let path = temp_file("garbage.rec", b"\xff\xff\xff\xff not a record");
    refused_saying(&["replay", path.path()], "is not a game record");
}

#[test]
fn bad_options_are_refused() {
    for args in [
        &["practice", "--frames", "0"][..],
        &["practice", "--size", "12x"][..],
        &["local", "--mode", "snooker", "--reds", "7"][..],
        &["local", "--mode", "snooker", "--best-of", "2"][..],
        &["local", "--mode", "snooker", "--best-of", "37"][..],
        &["local", "--mode", "3cushion", "--race", "0"][..],
        // Options refused where they mean nothing.
        &["local", "--race", "5"][..],
        &["local", "--reds", "6"][..],
        &["host", "--mode", "9ball", "--best-of", "3"][..],
        &["local", "--mode", "snooker", "--race", "5"][..],
        &["vs-computer", "--mode", "9ball", "--rules", "bar"][..],
        &["host", "--mode", "3cushion", "--rules", "wpa"][..],
        &["practice", "--name", "ann"][..],
        &["join", "breakshot://127.0.0.1:4433/ROOM#ab", "--seed", "3"][..],
        &["replay", "x.rec", "--race", "3"][..],
        &["vs-computer", "--level", "0"][..],
        &["vs-computer", "--level", "6"][..],
        &["vs-computer", "--break", "nobody"][..],
        // The computer's level is an option of playing it.
        &["host", "--level", "2"][..],
    ] {
        let out = breakshot(args);
        assert_ne!(out.status.code(), Some(0), "{args:?} was accepted");
        assert!(!stderr(&out).is_empty(), "{args:?}: no message");
    }
}

#[test]
fn a_malformed_invite_is_refused_with_what_an_invite_looks_like() {
    let err = refused(&["join", "not-an-invite"]);
    assert!(err.contains("\"not-an-invite\" is not an invite"), "{err}");
    assert!(err.contains("breakshot://"), "{err}");
}

#[test]
fn an_invite_without_a_room_is_refused() {
    let server_only = format!("breakshot://127.0.0.1:4433#{}", "ab".repeat(32));
    refused_saying(&["join", &server_only], "no room");
}

#[test]
fn hosting_on_a_port_in_use_says_so_before_any_window_opens() {
    let taken = std::net::UdpSocket::bind("127.0.0.1:0").expect("a free port");
    let addr = taken.local_addr().expect("bound").to_string();
    let data = breakshot_testkit::scratch("cli-host");
    let err = refused(&[
        "host",
        "--bind",
        &addr,
        "--data",
        data.path().to_str().expect("utf-8"),
    ]);
    assert!(
        err.contains("could not start") && err.contains(&addr),
        "{err}"
    );
    assert_eq!(err.matches(&addr).count(), 1, "said once: {err}");
}

#[test]
fn a_short_fingerprint_is_named_once() {
    let err = refused(&["join", "breakshot://127.0.0.1:4433/ABCDEFGH#abcd"]);
    assert_eq!(
        err.matches("64 hexadecimal digits").count(),
        1,
        "said once: {err}"
    );
}

#[test]
fn an_address_that_cannot_be_in_an_invite_is_refused() {
    refused_saying(
        &["host", "--bind", "127.0.0.1:0", "--address", "my host:1"],
        "must be a host name or an IP address",
    );
}

#[test]
fn replay_from_a_server_needs_a_server_address_and_a_room_code() {
    refused_saying(
        &["replay", "--server", "not-a-server", "--game", "AAAAAAAA"],
        "is not a server address",
    );

    let server = format!("breakshot://127.0.0.1:4433#{}", "ab".repeat(32));
    refused_saying(
        &["replay", "--server", &server, "--game", "no!"],
        "is not a room code",
    );

    // --server without --game, or a file and a server at once, is a usage error.
    for args in [
        &["replay", "--server", &server][..],
        &[
            "replay", "game.rec", "--server", &server, "--game", "AAAAAAAA",
        ][..],
        &["replay"][..],
    ] {
        refused(args);
    }
}

#[test]
#[cfg(feature = "host")]
fn replay_of_a_game_the_server_does_not_have_is_refused() {
    let data = breakshot_testkit::scratch("cli-fetch");
    let server = common::loopback_server(data.path().to_path_buf());
    let invite = server.loopback_invite().to_string();
    refused_saying(
        &["replay", "--server", &invite, "--game", "zzzzzzzz"],
        "no game in room ZZZZZZZZ",
    );
}

#[test]
#[cfg(feature = "host")]
fn a_game_on_a_server_is_saved_to_a_record_file_that_replays() {
    use breakshot_shared::replay::GameRecord;

    let dir = breakshot_testkit::scratch("cli-save");
    let server = common::loopback_server(dir.path().join("server"));
    let invite = server.loopback_invite().to_string();
    let room = common::bots_game(&server);
    let save = |number: &str, file: &std::path::Path| {
        breakshot(&[
            "replay",
            "--server",
            &invite,
            "--game",
            room.as_str(),
            "--number",
            number,
            "--save",
            file.to_str().expect("utf-8 path"),
        ])
    };
    let file = dir.path().join("game.rec");
    let out = save("1", &file);
    // A game the room has not reached is refused, and says how many it has.
    let beyond = save("7", &dir.path().join("none.rec"));
    drop(server);
    assert_eq!(beyond.status.code(), Some(2), "{}", stderr(&beyond));
    assert!(stderr(&beyond).contains("no game 7"), "{}", stderr(&beyond));
    assert!(!dir.path().join("none.rec").exists());
    let bytes = std::fs::read(&file);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let record = GameRecord::decode(&bytes.expect("the saved file")).expect("a game record");
    record
        .replay()
        .expect("the saved game replays with every hash");
    assert!(
        stderr(&out).contains("breakshot replay"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_name_that_cannot_be_shown_is_refused_before_any_window_opens() {
    let data = breakshot_testkit::scratch("cli-name");
    let dir = data.path().to_str().expect("utf-8");
    let long = "x".repeat(25);
    let invite = format!("breakshot://127.0.0.1:9/ABCDEFGH#{}", "ab".repeat(32));
    for bad in ["   ", &long[..]] {
        refused_saying(
            &["join", &invite, "--data", dir, "--name", bad],
            "a name is 1 to 24 printable characters",
        );
    }
    assert!(
        !data.path().join("name").exists(),
        "a refused name is not kept"
    );
}

#[test]
fn a_record_of_another_format_version_is_named_once() {
    use breakshot_shared::replay::GameRecord;
    use breakshot_shared::rules::{Settings, Variant};
    let mut bytes = GameRecord::new(Variant::NineBall, Settings::offline(), 1).encode();
    // The format version is the record's first field, one byte while it is small.
    bytes[0] = 99;
    let path = temp_file("future.rec", &bytes);
    let err = refused(&["replay", path.path()]);
    assert!(err.contains("is not a game record"), "{err}");
    assert_eq!(
        err.matches("record format version 99").count(),
        1,
        "said once: {err}"
    );
}

/// What `breakshot SUB --help` prints.
fn help(sub: &str) -> String {
    let out = breakshot(&[sub, "--help"]);
    assert_eq!(out.status.code(), Some(0), "{sub} --help");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Each subcommand's `--help`: the options it takes and no other, each with a line of help.
#[test]
fn every_subcommand_lists_only_its_own_options_each_with_help() {
    let window = ["--screenshot", "--frames", "--size", "--data", "--view"];
    let cases: [(&str, &[&str]); 6] = [
        (
            "host",
            &[
                "--mode",
                "--rules",
                "--race",
                "--name",
                "--bind",
                "--address",
                "--aids",
                "--new",
                "--computer",
                "--level",
            ],
        ),
        ("join", &["--name"]),
        ("local", &["--mode", "--rules", "--race", "--seed"]),
        (
            "vs-computer",
            &[
                "--level", "--mode", "--rules", "--race", "--break", "--seed",
            ],
        ),
        ("practice", &["--mode", "--seed"]),
        ("replay", &["--server", "--game", "--number", "--save"]),
    ];
    // Each option of one subcommand is listed by no other.
    let all: std::collections::BTreeSet<&str> = cases
        .iter()
        .flat_map(|(_, own)| own.iter().copied())
        .collect();
    for (sub, own) in cases {
        let help = help(sub);
        // Option lines read `      --name <VALUE>   help text`.
        let options: Vec<(&str, &str)> = help
            .lines()
            .map(str::trim_start)
            .filter(|l| l.starts_with("--"))
            .map(|l| {
                let (name, rest) = l.split_once(' ').unwrap_or((l, ""));
                let rest = rest.trim_start();
                let text = match rest.strip_prefix('<') {
                    Some(value) => value.split_once('>').map_or("", |(_, t)| t),
                    None => rest,
                };
                (name, text.trim())
            })
            .collect();
        let listed: Vec<&str> = options.iter().map(|(name, _)| *name).collect();
        for &option in &all {
            assert_eq!(
                listed.contains(&option),
                own.contains(&option),
                "{sub} --help and {option}:\n{help}"
            );
        }
        for option in window {
            assert!(
                listed.contains(&option),
                "{sub} --help lacks {option}:\n{help}"
            );
        }
        for (name, text) in &options {
            assert!(
                text.split_whitespace().count() >= 3,
                "{sub}: {name} has no help line:\n{help}"
            );
        }
    }
    // The positional arguments say what they are.
    for (sub, arg, words) in [
        ("join", "<INVITE>", "invite"),
        ("practice", "[SCENE]", "scene file"),
        ("replay", "[FILE]", "record file"),
    ] {
        let help = help(sub);
        let line = help
            .lines()
            .skip_while(|l| l.trim() != "Arguments:")
            .find(|l| l.contains(arg))
            .unwrap_or_else(|| panic!("{sub} --help lacks {arg}:\n{help}"));
        assert!(line.to_lowercase().contains(words), "{sub}: {line}");
    }
}

#[test]
fn hosting_with_a_published_page_prints_a_link_to_it_naming_this_server() {
    let data = breakshot_testkit::scratch("cli-web-page");
    // No display: the window cannot open, but the invite and the link come first.
    let out = breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot"))
            .args(["--data", data.path().to_str().expect("utf-8")])
            .args(["host", "--bind", "127.0.0.1:0", "--name", "Hostess"])
            .args(["--web-page", "https://example.org/breakshot"])
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("BREAKSHOT_WEB"),
        None,
        Duration::from_secs(60),
    );
    let printed = String::from_utf8_lossy(&out.stdout);
    let mut lines = printed.lines();
    let invite: breakshot_shared::protocol::Invite = lines
        .next()
        .unwrap_or_default()
        .parse()
        .unwrap_or_else(|e| panic!("no invite first ({e}): {printed}\n{}", stderr(&out)));
    let line = lines.next().unwrap_or_default();
    let link: breakshot_shared::protocol::WebLink = line
        .parse()
        .unwrap_or_else(|e| panic!("no link second ({e}): {printed}"));
    assert_eq!(
        link.page.as_deref(),
        Some("https://example.org/breakshot/"),
        "{line}"
    );
    assert_eq!(link.server.as_ref(), Some(invite.first()), "{line}");
    assert_eq!(link.room, invite.room, "{line}");
    assert!(!link.cert.is_empty(), "the certificate hashes: {line}");

    // An address that is not a page's is refused before anything starts.
    refused_saying(&["host", "--web-page", "ftp://example.org/"], "https://");
}

#[test]
fn a_snooker_match_of_an_even_number_of_frames_or_snooker_options_in_another_game_are_refused_with_why(
) {
    refused_saying(
        &["local", "--mode", "snooker", "--best-of", "4"],
        "--best-of must be odd",
    );
    refused_saying(
        &["vs-computer", "--mode", "8ball", "--reds", "10"],
        "set a snooker match; they mean nothing with --mode 8ball",
    );
}
