//! Position codes at the simulator's command line: `breakshot-sim code` writes one, and a
//! code stands wherever a scene file does (here `suggest`, as the game's advice quotes it).

use std::process::{Command, Output};
use std::time::Duration;

use breakshot_shared::ai::{Level, Thinking};
use breakshot_shared::rules::{EightBallRules, Game, Variant};
use breakshot_shared::scene::Scene;
use breakshot_shared::scene_code;

fn sim(args: &[&str], stdin: Option<&str>) -> Output {
    breakshot_testkit::run(
        Command::new(env!("CARGO_BIN_EXE_breakshot-sim")).args(args),
        stdin.map(str::as_bytes),
        Duration::from_secs(120),
    )
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).trim().to_owned(),
        String::from_utf8_lossy(&out.stderr).trim().to_owned(),
    )
}

#[test]
fn a_rack_s_code_is_printed_read_back_and_suggested_on_like_its_scene_file() {
    let game = Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 5).expect("rack");
    let scene = game.scene();
    let json = scene.to_json();
    let out = sim(&["code", "-"], Some(&json));
    let (code, err) = text(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(code, scene_code::encode(&scene).expect("a code"));
    // The code given for the scene prints the scene back.
    let out = sim(&["code", &code], None);
    let (back, err) = text(&out);
    assert!(out.status.success(), "{err}");
    let back = Scene::from_json(&back).expect("a scene");
    assert_eq!(back.balls.len(), scene.balls.len());
    // suggest on the code says what the search says of the scene the code stands for.
    let ids: Vec<&str> = back.balls.iter().skip(1).map(|b| b.id.as_str()).collect();
    let targets = ids.join(",");
    let out = sim(
        &[
            "suggest",
            &code,
            "--targets",
            &targets,
            "--level",
            "1",
            "--seed",
            "9",
        ],
        None,
    );
    let (said, err) = text(&out);
    assert!(out.status.success(), "{err}");
    let v: serde_json::Value = serde_json::from_str(&said).expect("JSON");
    let shot = back.to_shot().expect("a shot");
    let index: Vec<usize> = (1..back.balls.len()).collect();
    let want = Thinking::suggest(&shot, 0, &index, Level::new(1), 9)
        .finish()
        .expect("a suggestion");
    let speed = v["strike"]["speed"].as_f64().expect("speed");
    assert!(
        (speed - want.strike.speed).abs() < 1e-8,
        "{said} vs {want:?}"
    );
    let p = v["p_success"].as_f64().expect("p");
    assert!((p - want.p_success).abs() < 1e-8, "{said} vs {want:?}");
}

#[test]
fn a_code_that_does_not_decode_is_refused_with_a_reason() {
    for (bad, says) in [("bs1.@@@", "base64"), ("bs1.AzlmdAcDY3Vl", "cut short")] {
        let out = sim(&["code", bad], None);
        let (said, err) = text(&out);
        assert!(!out.status.success(), "{bad}: {said}");
        assert!(said.is_empty(), "nothing printed: {said}");
        assert!(err.contains(says), "{bad}: {err}");
    }
}
