//! A file dropped on the window (or the page): a game record to watch, or a scene to
//! practise on. Which it is comes from its contents, not its name.

use breakshot_shared::scene::Scene;

use super::replay::ReplayViewer;

/// What a dropped file opens.
pub enum Dropped {
    /// A game record.
    Record(Box<ReplayViewer>),
    /// A scene file (docs/scene.md).
    Scene(Box<Scene>),
}

/// Reads a dropped file; `Err` says, for the player, why it opens nothing.
pub fn open_dropped(bytes: &[u8]) -> Result<Dropped, String> {
    let record = match ReplayViewer::decode(bytes) {
        Ok(viewer) => return Ok(Dropped::Record(Box::new(viewer))),
        Err(e) => e,
    };
    match std::str::from_utf8(bytes).map(Scene::from_json) {
        Ok(Ok(scene)) => Ok(Dropped::Scene(Box::new(scene))),
        // Text that starts as JSON was meant as a scene: say what is wrong with it.
        Ok(Err(e)) if bytes.trim_ascii_start().starts_with(b"{") => {
            Err(format!("The dropped scene is not valid: {e}"))
        }
        _ => Err(format!(
            "The dropped file is neither a game record ({record}) nor a scene"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::replay::GameRecord;
    use breakshot_shared::rules::{EightBallRules, Game, Settings, Variant};

    #[test]
    fn a_record_a_scene_and_anything_else() {
        let variant = Variant::EightBall(EightBallRules::Wpa);
        let record = GameRecord::new(variant, Settings::offline(), 5);
        assert!(matches!(
            open_dropped(&record.encode()),
            Ok(Dropped::Record(_))
        ));
        let scene = Game::new(variant, Settings::offline(), 3).scene().to_json();
        assert!(matches!(
            open_dropped(scene.as_bytes()),
            Ok(Dropped::Scene(_))
        ));
        let Err(why) = open_dropped(b"{\"table\": 12}") else {
            panic!("a broken scene opened")
        };
        assert!(why.contains("scene is not valid"), "{why}");
        let Err(why) = open_dropped(&[0xff, 0x00, 0x12]) else {
            panic!("noise opened")
        };
        assert!(why.contains("neither a game record"), "{why}");
    }
}
