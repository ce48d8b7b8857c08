//! Positions of one's own: a practice table read from a scene file or a position code, and
//! written back as both, so a position can be kept, opened again and passed on.

use breakshot_shared::rules::Game;
use breakshot_shared::scene::Scene;
use breakshot_shared::scene_code;

/// The scene `text` holds: a position code (`bs1.…`) or a scene file's JSON. Err says why
/// it is neither.
pub fn read(text: &str) -> Result<Scene, String> {
    let text = text.trim();
    if text.starts_with(scene_code::PREFIX) {
        scene_code::decode(text).map_err(|e| e.to_string())
    } else {
        Scene::from_json(text).map_err(|e| e.to_string())
    }
}

/// The practice table `text` lays out, checked by the rules (balls apart, on the cloth):
/// the table to open, or the reason nothing changes.
pub fn open(text: &str) -> Result<(Scene, Game), String> {
    let scene = read(text)?;
    let game = Game::practice(&scene).map_err(|e| e.to_string())?;
    Ok((scene, game))
}

/// The table as it stands, as a scene file's JSON and as a code.
pub fn written(game: &Game) -> Result<(String, String), String> {
    let scene = game.scene();
    let code = scene_code::encode(&scene).map_err(|e| e.to_string())?;
    Ok((scene.to_json(), code))
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUT: &str = include_str!("../../scenes/cut-shot.json");

    #[test]
    fn a_table_written_and_opened_again_is_the_same_table() {
        let (_, game) = open(CUT).expect("a table");
        let (json, code) = written(&game).expect("written");
        let (_, from_file) = open(&json).expect("the file opens");
        let (_, from_code) = open(&code).expect("the code opens");
        assert_eq!(from_file.scene(), game.scene());
        assert_eq!(from_file.balls(), game.balls());
        assert_eq!(from_code.ball_ids(), game.ball_ids());
        for (a, b) in from_code.balls().iter().zip(game.balls()) {
            assert!((a.pos - b.pos).length() < 1e-6);
        }
    }

    #[test]
    fn bad_text_is_refused_with_a_reason() {
        for (text, says) in [
            ("bs1.***", "base64"),
            ("not json", "invalid scene"),
            (
                r#"{"balls":[{"id":"cue","pos":[0.6,1.0]},{"id":"1","pos":[0.61,1.0]}]}"#,
                "overlap",
            ),
            (
                r#"{"balls":[{"id":"cue","pos":[0.6,1.0]},{"id":"1","pos":[3.0,1.0]}]}"#,
                "playing surface",
            ),
        ] {
            let why = open(text).expect_err(text);
            assert!(why.contains(says), "{text}: {why}");
        }
    }
}
