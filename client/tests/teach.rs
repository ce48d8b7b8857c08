//! Practice that teaches, played in the window under a virtual display with `xdotool`:
//! shots taken back and played again. The window says what it did on standard error
//! (`BREAKSHOT_REPORT`: "report: ..." lines), which is what these tests read.
//!
//! Needs `xvfb-run` and `xdotool`; without them a test says why and passes.

use std::ffi::OsStr;
use std::path::Path;
use std::process::Command as Process;
use std::time::Duration;

use breakshot_shared::hash::{hash_hex, state_hash};
use breakshot_shared::rules::Game;
use breakshot_shared::scene::Scene;

mod common;

use common::screen::{assert_ran, reports};

const CUT: &str = include_str!("../scenes/cut-shot.json");

/// Runs `breakshot ARGS --screenshot OUT --frames FRAMES` at 1280x720 under a virtual
/// display while `xdotool` plays `keys` on its window (see [`common::screen::played`]), with
/// a fresh data directory; what the window reported, once it has run to its end. None if
/// xvfb-run or xdotool is missing (the reason is printed).
fn played(args: &[&OsStr], out: &Path, frames: u32, keys: &[&str]) -> Option<Vec<String>> {
    let data = breakshot_testkit::scratch("teach-data");
    played_with(args, out, frames, keys, data.path())
}

/// [`played`] with `data` as the window's data directory.
fn played_with(
    args: &[&OsStr],
    out: &Path,
    frames: u32,
    keys: &[&str],
    data: &Path,
) -> Option<Vec<String>> {
    let patience = Duration::from_secs(300);
    let run = common::screen::played(args, out, frames, keys, (1280, 720), data, patience)?;
    assert_ran(&run);
    Some(reports(&run))
}

/// [`played`] on the practice table of the scene `json`, written to `dir`, where the
/// screenshot goes too (`out.png`).
fn practised(dir: &Path, json: &str, frames: u32, keys: &[&str]) -> Option<Vec<String>> {
    let scene = dir.join("scene.json");
    std::fs::write(&scene, json).expect("scene written");
    let args = [OsStr::new("practice"), scene.as_os_str()];
    played(&args, &dir.join("out.png"), frames, keys)
}

/// Copies the screenshot `out` to where `BREAKSHOT_KEEP_SCREENSHOT` says, if it is set.
fn keep_screenshot(out: &Path) {
    if let Ok(keep) = std::env::var("BREAKSHOT_KEEP_SCREENSHOT") {
        std::fs::copy(out, keep).expect("screenshot kept");
    }
}

/// Where the first report starting with each of `starts` stands; the reports must hold
/// them all, each after the one before.
fn in_order<const N: usize>(said: &[String], starts: [&str; N]) -> [usize; N] {
    let mut from = 0;
    starts.map(|start| {
        let at = said[from..]
            .iter()
            .position(|l| l.starts_with(start))
            .map(|k| from + k)
            .unwrap_or_else(|| panic!("{start:?} after report {from} in {said:?}"));
        from = at + 1;
        at
    })
}

/// The hashes of the table at rest, in the order the window reported them.
fn tables(said: &[String]) -> Vec<&str> {
    said.iter()
        .filter_map(|l| l.strip_prefix("practice table "))
        .collect()
}

#[test]
fn three_shots_taken_back_give_the_table_before_them_to_the_bit_and_again_replays_one() {
    let dir = breakshot_testkit::scratch("teach-undo");
    // Each shot is played (Space) and its playback skipped (Space again); then U three
    // times, Y (redo the first shot), B (set it up again) and the same shot played again.
    let key = |k: &str| format!("key --window \"$wid\" {k}");
    let mut keys = vec!["sleep 1".to_string()];
    for k in [
        "space", "space", "space", "space", "space", "space", "u", "u", "u", "y", "b",
    ]
    .into_iter()
    .chain(["space", "space"])
    {
        // Slow frames (a loaded machine, a software display) still see each press.
        keys.extend([key(k), "sleep 0.4".to_string()]);
    }
    let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
    let Some(said) = practised(dir.path(), CUT, 900, &keys) else {
        return;
    };
    let shots = said
        .iter()
        .filter(|l| {
            // "practice shot N dir=… tip=… elevation=…"
            l.strip_prefix("practice shot ")
                .and_then(|rest| rest.split_whitespace().next())
                .is_some_and(|n| n.parse::<u32>().is_ok())
        })
        .count();
    let undone = said
        .iter()
        .filter(|l| *l == "practice shot taken back")
        .count();
    assert_eq!((shots, undone), (4, 3), "four shots, three undos: {said:?}");
    let seen = tables(&said);
    let start = Game::practice(&Scene::from_json(CUT).expect("a scene")).expect("a table");
    let first = hash_hex(state_hash(start.balls()));
    assert_eq!(
        seen.first(),
        Some(&first.as_str()),
        "the scene's table first"
    );
    // The tables at rest: after three shots, three undos give the first one back to the
    // bit; redo gives the one after the first shot, again the first, and the same strike
    // from it the same table as the first time.
    assert_eq!(seen.len(), 10, "{said:?}");
    let at = |i: usize| seen[i];
    assert_eq!(
        [at(4), at(5), at(6)],
        [at(2), at(1), at(0)],
        "undone: {said:?}"
    );
    assert_eq!([at(7), at(8), at(9)], [at(1), at(0), at(1)], "{said:?}");
    let distinct: std::collections::HashSet<_> = seen[..4].iter().collect();
    assert_eq!(distinct.len(), 4, "each shot moved balls: {said:?}");
}

#[test]
fn the_advice_shown_is_the_simulator_s_and_j_sets_the_cue_to_it() {
    use breakshot_client::play::{Advisor, Request};
    use breakshot_shared::ai::Level;
    let dir = breakshot_testkit::scratch("teach-advice");
    // I asks (level 3 by default); the search runs a few simulations a frame; once the
    // advice is shown, J sets the cue.
    let keys = [
        "sleep 1",
        "key --window \"$wid\" i",
        "await practice advice [0-9]",
        "key --window \"$wid\" j",
        "sleep 1",
    ];
    let Some(said) = practised(dir.path(), CUT, 1200, &keys) else {
        return;
    };
    let start = Game::practice(&Scene::from_json(CUT).expect("a scene")).expect("a table");
    let request = Request::for_table(&start, Level::new(3)).expect("a request");
    let mut advisor = Advisor::start(request).expect("an advisor");
    let want = advisor
        .step(usize::MAX)
        .expect("done")
        .clone()
        .expect("advice");
    let line = format!(
        "practice advice {} {} {} {} {}",
        want.strike.speed, want.strike.dir.x, want.strike.dir.y, want.p_success, want.trials
    );
    assert!(said.contains(&line), "{line} in {said:?}");
    let asked = said.iter().position(|l| *l == line);
    let set = said.iter().position(|l| l == "practice advice set");
    assert!(
        matches!((asked, set), (Some(a), Some(s)) if a < s),
        "advised, then set: {said:?}"
    );
    keep_screenshot(&dir.path().join("out.png"));
}

/// A shot that pockets nothing, then I: the shot is taken back, and the advice says the
/// chance the missed shot had beside the computer's own.
#[test]
fn after_a_miss_the_advice_says_what_the_shot_missed_was_worth() {
    let dir = breakshot_testkit::scratch("teach-miss");
    // The cue set to roll softly into the open cloth: it meets no ball.
    let mut soft: serde_json::Value = serde_json::from_str(CUT).expect("a scene");
    soft["strike"] = serde_json::json!({"ball": "cue", "speed": 0.8, "dir": [1.0, 0.0]});
    let keys = [
        "sleep 1",
        "key --window \"$wid\" space",
        "sleep 1",
        "key --window \"$wid\" space",
        "sleep 1",
        "key --window \"$wid\" i",
        "sleep 14",
    ];
    let Some(said) = practised(dir.path(), &soft.to_string(), 1500, &keys) else {
        return;
    };
    let [.., measured] = in_order(
        &said,
        [
            "practice missed",
            "practice shot taken back",
            "practice advice after a miss: that shot ",
        ],
    );
    let line = &said[measured];
    let trials = breakshot_client::play::PLAYED_TRIALS;
    assert!(line.ends_with(&format!(" of {trials}")), "{line}");
    keep_screenshot(&dir.path().join("out.png"));
}

/// The break as the cue is first set (too soft: a foul), its playback skipped; then I,
/// and time for the advice's search.
const BREAK_THEN_ADVICE: [&str; 7] = [
    "sleep 1.5",
    "key --window \"$wid\" space",
    "sleep 1",
    "key --window \"$wid\" space",
    "sleep 2",
    "key --window \"$wid\" i",
    "sleep 14",
];

/// Against the computer: a soft break is a foul, a miss; I takes it back and the advice
/// says what that break was worth beside the computer's own.
#[test]
fn against_the_computer_a_missed_shot_is_taken_back_and_advised_on() {
    let dir = breakshot_testkit::scratch("teach-vs-miss");
    let out = dir.path().join("out.png");
    let args = [
        OsStr::new("vs-computer"),
        OsStr::new("--level"),
        OsStr::new("1"),
    ];
    let Some(said) = played(&args, &out, 1500, &BREAK_THEN_ADVICE) else {
        return;
    };
    in_order(
        &said,
        [
            "game missed",
            "message Taken back: ",
            "message Advice: That shot: ",
        ],
    );
    keep_screenshot(&out);
}

/// In a local game for two a soft break is a miss too, but the table has passed to the
/// other player: I compares the break with the computer's own without taking it back, and
/// the turn and the table stay as the miss left them.
#[test]
fn in_a_local_game_for_two_a_miss_is_advised_on_beside_the_table() {
    let dir = breakshot_testkit::scratch("teach-local-miss");
    let out = dir.path().join("out.png");
    let Some(said) = played(&[OsStr::new("local")], &out, 1500, &BREAK_THEN_ADVICE) else {
        return;
    };
    let [missed, beside, _] = in_order(
        &said,
        [
            "game missed ",
            "game advice beside ",
            "message Advice: That shot: ",
        ],
    );
    // "turn=N table=HASH" at the miss and once the advice is shown: the same.
    let state = |at: usize, prefix: &str| said[at].strip_prefix(prefix).map(str::to_owned);
    assert_eq!(
        state(missed, "game missed "),
        state(beside, "game advice beside "),
        "{said:?}"
    );
    assert!(
        !said.iter().any(|l| l.starts_with("message Taken back")),
        "nothing taken back: {said:?}"
    );
    keep_screenshot(&out);
}

/// Online, I is refused in a room hosted with the usual aids, and gives the computer's
/// advice in one hosted with `--aids advice`: the room's policy decides, for every player.
#[cfg(feature = "host")]
#[test]
fn online_the_advice_is_given_only_where_the_room_allows_it() {
    let dir = breakshot_testkit::scratch("teach-online");
    let out = dir.path().join("out.png");
    for (aids, says) in [
        ("full", "message No advice: this room does not allow"),
        ("advice", "message Advice: "),
    ] {
        let data = dir.path().join(aids);
        let args = [
            "host",
            "--computer",
            "--bind",
            "127.0.0.1:0",
            "--aids",
            aids,
            "--data",
        ]
        .map(OsStr::new)
        .into_iter()
        .chain([data.as_os_str()])
        .collect::<Vec<_>>();
        let keys = ["sleep 2", "key --window \"$wid\" i", "sleep 12"];
        let Some(said) = played(&args, &out, 1200, &keys) else {
            return;
        };
        assert!(said.iter().any(|l| l.starts_with(says)), "{aids}: {said:?}");
    }
    keep_screenshot(&out);
}

#[test]
fn a_ball_dragged_then_kept_opens_again_as_the_same_table() {
    use breakshot_client::play::position;
    use breakshot_client::view::{Frame, Layout};
    let dir = breakshot_testkit::scratch("teach-position");
    let (scene, out) = (dir.path().join("scene.json"), dir.path().join("out.png"));
    let data = dir.path().join("data");
    std::fs::write(&scene, CUT).expect("scene written");
    let start = Game::practice(&Scene::from_json(CUT).expect("a scene")).expect("a table");
    let layout = Layout::new(1280.0, 720.0, Frame::new(start.table(), start.balls()));
    // The 8 (ball 2 of the scene) is dragged to a free spot; then O keeps the position.
    let [fx, fy] = layout.to_screen(start.balls()[2].pos).map(f32::round);
    let to = glam::DVec2::new(0.9, 0.9);
    let [tx, ty] = layout.to_screen(to).map(f32::round);
    let keys = [
        "sleep 1".to_string(),
        "key --window \"$wid\" f".into(),
        format!("mousemove --window \"$wid\" {fx} {fy}"),
        "mousedown 1".into(),
        format!("mousemove --window \"$wid\" {tx} {ty}"),
        "sleep 0.3".into(),
        "mouseup 1".into(),
        "key --window \"$wid\" o".into(),
    ];
    let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
    let Some(said) = played_with(
        &[OsStr::new("practice"), scene.as_os_str()],
        &out,
        600,
        &keys,
        &data,
    ) else {
        return;
    };
    assert!(said.iter().any(|l| l == "practice ball placed"), "{said:?}");
    let saved = said
        .iter()
        .find_map(|l| l.strip_prefix("practice saved "))
        .expect("the position kept");
    let (path, code) = saved.rsplit_once(' ').expect("path and code");
    let text = std::fs::read_to_string(path).expect("the scene file");
    assert!(path.starts_with(data.to_str().expect("a path")), "{path}");
    let (_, kept) = position::open(&text).expect("the kept file opens");
    let (_, coded) = position::open(code).expect("the code opens");
    // The 8 is where it was dropped (to the pixel), every other ball where it was.
    let scale = layout.scale;
    assert!(
        (kept.balls()[2].pos - to).length() <= 1.5 / scale,
        "{:?}",
        kept.balls()[2]
    );
    for i in (0..start.balls().len()).filter(|&i| i != 2) {
        assert_eq!(kept.balls()[i], start.balls()[i], "ball {i}");
    }
    assert_eq!(kept.ball_ids(), start.ball_ids());
    for (a, b) in coded.balls().iter().zip(kept.balls()) {
        assert!(
            (a.pos - b.pos).length() < 1e-6,
            "the code is the same table"
        );
    }
}

#[test]
fn a_code_that_does_not_decode_is_refused_before_any_window_opens() {
    for (code, says) in [("bs1.@@@", "base64"), ("bs1.AzlmdAcDY3Vl", "cut short")] {
        let out = breakshot_testkit::run(
            Process::new(env!("CARGO_BIN_EXE_breakshot")).args(["practice", code]),
            None,
            Duration::from_secs(60),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(says), "{code}: {err}");
    }
}

#[test]
fn a_drill_scores_a_made_and_a_missed_attempt_and_remembers_them() {
    use breakshot_client::view::{Frame, Layout};
    let dir = breakshot_testkit::scratch("teach-drill");
    let (drill, out) = (dir.path().join("drill.json"), dir.path().join("out.png"));
    let data = dir.path().join("data");
    // The shipped straight-in drill, with the strike that makes it as the first aim.
    let shipped: serde_json::Value =
        serde_json::from_str(include_str!("../drills/straight-in.json")).expect("a drill");
    let mut with_aim = shipped.clone();
    with_aim["scene"]["strike"] =
        serde_json::json!({"ball": "cue", "speed": 2.5, "dir": [-0.640184, 0.768221]});
    std::fs::write(&drill, with_aim.to_string()).expect("drill written");
    // The second attempt is on the ladder's second rung. Its aim is set by a tap on the
    // table at 174° from the cue ball, and its power by a click on the bar at 2.5 m/s: off
    // the left rail, leaving the 1 and the cue ball on the table at every whole degree from
    // 166° to 182° at 2.2, 2.5 and 2.8 m/s (`breakshot-sim run`). Pixels, not the time a key
    // is held: a window slowed by a loaded machine turned a held key 36° instead of 50°,
    // which pots the 1.
    let rung = serde_json::json!({
        "table": shipped["scene"]["table"],
        "balls": shipped["ladder"][0]["balls"],
    });
    let second =
        Game::practice(&Scene::from_json(&rung.to_string()).expect("a scene")).expect("a table");
    let layout = Layout::new(1280.0, 720.0, Frame::new(second.table(), second.balls()));
    let cue = second.balls()[0].pos;
    let angle = 174f64.to_radians();
    let [ax, ay] = layout
        .to_screen(cue + 0.3 * glam::DVec2::new(libm::cos(angle), libm::sin(angle)))
        .map(f32::round);
    // The bar runs from no power at its foot to the full speed at its head.
    let mut full = breakshot_client::play::Aim::default();
    full.set_power(1.0);
    let bar = layout.power_bar;
    let (px, py) = (
        (bar.x + 0.5 * bar.w).round(),
        (bar.y + bar.h * (1.0 - 2.5 / full.speed()) as f32).round(),
    );
    let key = |k: &str| format!("key --window \"$wid\" {k}");
    let click = |x: f32, y: f32| format!("mousemove --window \"$wid\" {x} {y} click 1");
    let keys = [
        "sleep 1".to_string(),
        key("space"),
        key("space"),
        // Twice, a second apart: a click while the first shot still plays is not taken.
        "sleep 1".into(),
        click(ax, ay),
        click(px, py),
        "sleep 1".into(),
        click(ax, ay),
        click(px, py),
        "sleep 0.5".into(),
        key("space"),
        key("space"),
    ];
    let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
    let args = [OsStr::new("practice"), drill.as_os_str()];
    let Some(said) = played_with(&args, &out, 900, &keys, &data) else {
        return;
    };
    // The second attempt went where the tap aimed.
    let second_dir = said
        .iter()
        .find_map(|l| l.strip_prefix("practice shot 2 dir="))
        .and_then(|l| l.split_once(' '))
        .and_then(|(d, _)| d.split_once(','))
        .map(|(x, y)| [x, y].map(|v| v.parse::<f64>().expect("a number")))
        .unwrap_or_else(|| panic!("no second shot: {said:?}"));
    let aimed = libm::atan2(second_dir[1], second_dir[0]).to_degrees();
    assert!((aimed - 174.0).abs() < 1.0, "aimed at {aimed}°: {said:?}");
    let drills: Vec<&String> = said.iter().filter(|l| l.starts_with("drill ")).collect();
    assert_eq!(
        drills,
        // The straight-in drill is a ladder: made, up a rung; missed, down again.
        [
            "drill made: 1 of 1; best streak 1",
            "drill rung 2 of 3",
            "drill missed: 1 of 2; best streak 1",
            "drill rung 1 of 3"
        ],
        "{said:?}"
    );
    let kept = std::fs::read_to_string(data.join("drill-straight-in")).expect("the score kept");
    assert_eq!(kept.trim(), "1 2 1");
}

/// The menu's *Drills* lists the shipped drills; the three-cushion one opens on the carom
/// table, I sets its example on the cue, and the example, played, scores the attempt.
#[test]
fn the_menu_s_drills_open_a_drill_whose_example_makes_it() {
    use breakshot_client::view::menu_buttons;
    let dir = breakshot_testkit::scratch("teach-menu-drill");
    let (out, data) = (dir.path().join("out.png"), dir.path().join("data"));
    let shipped = breakshot_client::play::drill::Drill::shipped();
    let corner = shipped
        .iter()
        .position(|d| d.first().scene.table == breakshot_shared::physics::TableKind::Carom)
        .expect("a three-cushion drill ships");
    // The menu's third button is *Drills*; the page lists the drills, then *Back*.
    let click = |r: breakshot_client::view::Rect| {
        let [x, y] = r.center();
        format!("mousemove --window \"$wid\" {x} {y} click 1")
    };
    let keys = [
        "sleep 1".to_string(),
        click(menu_buttons(1280.0, 720.0, 10)[2]),
        "sleep 0.5".into(),
        click(menu_buttons(1280.0, 720.0, shipped.len() + 1)[corner]),
        "sleep 1".into(),
        "key --window \"$wid\" i".into(),
        "key --window \"$wid\" space".into(),
        "sleep 1".into(),
        "key --window \"$wid\" space".into(),
    ];
    let keys: Vec<&str> = keys.iter().map(String::as_str).collect();
    let Some(said) = played_with(&[], &out, 700, &keys, &data) else {
        return;
    };
    let name = &shipped[corner].name;
    for line in [
        "screen practice".to_owned(),
        format!("practice drill {name}"),
        "practice drill example set".to_owned(),
        "drill made: 1 of 1; best streak 1".to_owned(),
    ] {
        assert!(said.contains(&line), "{line:?} not in {said:?}");
    }
}
