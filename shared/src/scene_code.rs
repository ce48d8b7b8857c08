//! A position as a short text code, to pass to another player or to `breakshot-sim`: the
//! table and each ball's name and place, packed and written in URL-safe base64 after the
//! prefix `bs1.`. Places are kept to the micrometre, which is finer than any play needs and
//! keeps balls that touch in a scene from overlapping once decoded. A scene's own physics
//! (its parameters, models, effects and horizon where they differ from the table's
//! defaults) travel with it, so a shared position plays as it did; velocities, spins and
//! the strike are not part of a position.
//!
//! Layout (version 1): table name length (1 byte) and its name, ball count (1 byte), then
//! per ball its id's length (1 byte), the id, and x and y in micrometres (i32, little end);
//! then, only when the scene's physics differ from the table's defaults, their length
//! (u16, little end) and the differences as a JSON object in the scene format
//! (`{"physics": {...}, "models": {...}, "effects": {...}, "horizon": ...}`, each part only
//! when it differs).

use data_encoding::BASE64URL_NOPAD;

use crate::physics::TableKind;
use crate::scene::{Scene, SceneBall};

/// What every code starts with (its version).
pub const PREFIX: &str = "bs1.";

/// Micrometres per metre.
const UNIT: f64 = 1e6;

/// Why a text is not a position code.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CodeError {
    /// It does not start with [`PREFIX`].
    #[error("a position code starts with \"{PREFIX}\"")]
    Prefix,
    /// Its characters are not URL-safe base64.
    #[error("the position code is not valid base64: {0}")]
    Base64(String),
    /// It ends before the position does, or goes on after it.
    #[error("the position code is cut short or has bytes left over")]
    Length,
    /// It names no table of the simulator's.
    #[error("the position code names an unknown table \"{0}\"")]
    Table(String),
    /// A ball's name is not text.
    #[error("a ball's name in the position code is not text")]
    Name,
    /// The physics it carries are not a scene's.
    #[error("the position code's physics are not valid: {0}")]
    Physics(String),
    /// The scene cannot be written as a code (too many balls, a name too long, a place
    /// beyond ±2 km).
    #[error("the position cannot be written as a code: {0}")]
    TooBig(String),
}

/// The code of `scene`'s position: its table and its balls' names and places.
pub fn encode(scene: &Scene) -> Result<String, CodeError> {
    let mut bytes = Vec::new();
    let table = scene.table.name();
    bytes.push(table.len() as u8);
    bytes.extend_from_slice(table.as_bytes());
    let count = u8::try_from(scene.balls.len())
        .map_err(|_| CodeError::TooBig(format!("{} balls", scene.balls.len())))?;
    bytes.push(count);
    for b in &scene.balls {
        let len = u8::try_from(b.id.len())
            .map_err(|_| CodeError::TooBig(format!("the name \"{}\" is too long", b.id)))?;
        bytes.push(len);
        bytes.extend_from_slice(b.id.as_bytes());
        for x in b.pos {
            let um = (x * UNIT).round();
            if !(um.is_finite() && um.abs() <= f64::from(i32::MAX)) {
                return Err(CodeError::TooBig(format!("{} is placed at {x} m", b.id)));
            }
            bytes.extend_from_slice(&(um as i32).to_le_bytes());
        }
    }
    if let Some(physics) = own_physics(scene) {
        let len = u16::try_from(physics.len())
            .map_err(|_| CodeError::TooBig("its physics are too long".into()))?;
        bytes.extend_from_slice(&len.to_le_bytes());
        bytes.extend_from_slice(physics.as_bytes());
    }
    Ok(format!("{PREFIX}{}", BASE64URL_NOPAD.encode(&bytes)))
}

/// What `scene` changes of its table's default physics, as a JSON object in the scene
/// format; None when it changes nothing.
fn own_physics(scene: &Scene) -> Option<String> {
    let defaults = table_scene(scene.table).ok()?;
    let value = |s: &Scene| serde_json::to_value(s).ok();
    let (mine, theirs) = (value(scene)?, value(&defaults)?);
    let mut own = serde_json::Map::new();
    if let (Some(serde_json::Value::Object(mine)), Some(serde_json::Value::Object(theirs))) =
        (mine.get("physics"), theirs.get("physics"))
    {
        let changed: serde_json::Map<_, _> = mine
            .iter()
            .filter(|(k, v)| theirs.get(*k) != Some(v))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        if !changed.is_empty() {
            own.insert("physics".into(), changed.into());
        }
    }
    for part in ["models", "effects", "horizon"] {
        if let Some(v) = mine.get(part).filter(|v| theirs.get(part) != Some(*v)) {
            own.insert(part.into(), v.clone());
        }
    }
    (!own.is_empty()).then(|| serde_json::Value::Object(own).to_string())
}

/// The scene of `table` with its defaults and no balls, as a scene file naming only its
/// table gets them.
fn table_scene(table: TableKind) -> Result<Scene, crate::scene::SceneError> {
    Scene::from_json(&format!("{{\"table\":\"{}\",\"balls\":[]}}", table.name()))
}

/// The scene a code gives: its table, the table's physics, the balls at rest, no strike.
/// Whether the position is one a table allows (balls apart and on the cloth) is for the
/// caller to check, as for any scene (`Game::practice`).
pub fn decode(code: &str) -> Result<Scene, CodeError> {
    let body = code.trim().strip_prefix(PREFIX).ok_or(CodeError::Prefix)?;
    let bytes = BASE64URL_NOPAD
        .decode(body.as_bytes())
        .map_err(|e| CodeError::Base64(e.to_string()))?;
    let mut r = Reader(&bytes);
    let table = r.text()?.ok_or(CodeError::Name)?;
    let table: TableKind = serde_json::from_value(serde_json::Value::String(table.clone()))
        .map_err(|_| CodeError::Table(table))?;
    let count = r.byte()?;
    let mut balls = Vec::with_capacity(usize::from(count));
    for _ in 0..count {
        let id = r.text()?.ok_or(CodeError::Name)?;
        let x = f64::from(r.i32()?) / UNIT;
        let y = f64::from(r.i32()?) / UNIT;
        balls.push(SceneBall {
            id,
            pos: [x, y],
            vel: [0.0; 2],
            spin: [0.0; 3],
        });
    }
    let mut scene = if r.0.is_empty() {
        table_scene(table).map_err(|e| CodeError::Table(e.to_string()))?
    } else {
        // The physics it carries, read as a scene file's would be (names and types checked).
        let len = usize::from(u16::from_le_bytes([r.byte()?, r.byte()?]));
        let text = String::from_utf8(r.take(len)?.to_vec()).map_err(|_| CodeError::Length)?;
        if !r.0.is_empty() {
            return Err(CodeError::Length);
        }
        let mut own: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(&text).map_err(|e| CodeError::Physics(e.to_string()))?;
        own.insert("table".into(), table.name().into());
        own.insert("balls".into(), serde_json::Value::Array(Vec::new()));
        Scene::from_json(&serde_json::Value::Object(own).to_string())
            .map_err(|e| CodeError::Physics(e.to_string()))?
    };
    scene.balls = balls;
    Ok(scene)
}

/// Reads a code's bytes from the front.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], CodeError> {
        if self.0.len() < n {
            return Err(CodeError::Length);
        }
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        Ok(head)
    }

    fn byte(&mut self) -> Result<u8, CodeError> {
        Ok(self.take(1)?[0])
    }

    fn i32(&mut self) -> Result<i32, CodeError> {
        let b = self.take(4)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// A length-prefixed name; None if it is not UTF-8.
    fn text(&mut self) -> Result<Option<String>, CodeError> {
        let n = usize::from(self.byte()?);
        Ok(String::from_utf8(self.take(n)?.to_vec()).ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules::{EightBallRules, Game, Variant};

    #[test]
    fn a_rack_s_code_gives_its_scene_back() {
        let game = Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), 3).expect("rack");
        let scene = game.scene();
        let code = encode(&scene).expect("a code");
        assert!(code.starts_with(PREFIX));
        assert!(code.len() < 260, "short: {} characters", code.len());
        let back = decode(&code).expect("decodes");
        assert_eq!(back.table, scene.table);
        assert_eq!(back.physics, scene.physics);
        assert_eq!(back.balls.len(), scene.balls.len());
        for (a, b) in back.balls.iter().zip(&scene.balls) {
            assert_eq!(a.id, b.id);
            for k in 0..2 {
                assert!((a.pos[k] - b.pos[k]).abs() <= 0.5e-6, "{a:?} vs {b:?}");
            }
        }
        // A decoded scene is a table the rules accept, and its code is the same again.
        Game::practice(&back).expect("a practice table");
        assert_eq!(encode(&back).expect("again"), code);
    }

    #[test]
    fn a_scene_s_own_physics_travel_with_its_code() {
        let scene = Scene::from_json(
            r#"{"table": "carom", "physics": {"mu_slide": 0.25, "e_cushion": 0.7},
                "models": {"cushion": "stronge"}, "effects": {"airborne": false},
                "balls": [{"id": "cue", "pos": [0.6, 1.0]}, {"id": "red", "pos": [0.7, 2.0]}]}"#,
        )
        .expect("a scene");
        let code = encode(&scene).expect("a code");
        let back = decode(&code).expect("decodes");
        assert_eq!(back.physics, scene.physics);
        assert_eq!(back.models, scene.models);
        assert_eq!(back.effects, scene.effects);
        assert_eq!(back.balls, scene.balls);
        // A scene with the table's defaults carries none: its code is as short as before.
        let plain = Scene {
            physics: table_scene(TableKind::Carom).expect("defaults").physics,
            models: table_scene(TableKind::Carom).expect("defaults").models,
            effects: table_scene(TableKind::Carom).expect("defaults").effects,
            ..scene.clone()
        };
        assert!(own_physics(&plain).is_none());
        assert!(encode(&plain).expect("a code").len() < code.len());
        // Physics that are not a scene's are refused with the reason.
        let mut bytes = BASE64URL_NOPAD
            .decode(&encode(&plain).expect("a code").as_bytes()[PREFIX.len()..])
            .expect("base64");
        let bad = br#"{"physics": {"no_such": 1}}"#;
        bytes.extend_from_slice(&(bad.len() as u16).to_le_bytes());
        bytes.extend_from_slice(bad);
        let bad = format!("{PREFIX}{}", BASE64URL_NOPAD.encode(&bytes));
        assert!(matches!(decode(&bad), Err(CodeError::Physics(why)) if why.contains("no_such")));
    }

    #[test]
    fn text_that_is_not_a_code_is_refused_with_a_reason() {
        assert_eq!(decode("hello"), Err(CodeError::Prefix));
        assert!(matches!(decode("bs1.!!!"), Err(CodeError::Base64(_))));
        let scene = Scene::from_json(r#"{"balls":[{"id":"cue","pos":[0.6,1.0]}]}"#).expect("ok");
        let code = encode(&scene).expect("a code");
        assert_eq!(decode(&code[..code.len() - 3]), Err(CodeError::Length));
        assert_eq!(decode(&format!("{code}AAAA")), Err(CodeError::Length));
        let mut bytes = vec![4];
        bytes.extend_from_slice(b"10ft");
        bytes.push(0);
        let unknown = format!("{PREFIX}{}", BASE64URL_NOPAD.encode(&bytes));
        assert_eq!(decode(&unknown), Err(CodeError::Table("10ft".into())));
    }
}
