//! `breakshot-sim suggest`: the computer player's strike for a scene (docs/scene.md).

use breakshot_shared::ai::{Level, Thinking};
use breakshot_shared::scene::Scene;

/// The suggestion for `scene` as the contract's JSON object, or a one-line reason the
/// request is not valid.
pub fn suggest(scene: &Scene, targets: &str, level: u8, seed: u64) -> Result<String, String> {
    if !(Level::MIN..=Level::MAX).contains(&level) {
        return Err(format!(
            "--level must be between {} and {}",
            Level::MIN,
            Level::MAX
        ));
    }
    let index = |id: &str| scene.balls.iter().position(|b| b.id == id);
    let cue = index("cue").ok_or("the scene has no ball with id \"cue\"")?;
    let mut wanted = Vec::new();
    for id in targets.split(',').map(str::trim) {
        let i = index(id).ok_or_else(|| format!("--targets: the scene has no ball \"{id}\""))?;
        if i == cue {
            return Err("--targets: the cue ball cannot be a target".into());
        }
        if !wanted.contains(&i) {
            wanted.push(i);
        }
    }
    let shot = scene.to_shot().map_err(|e| e.to_string())?;
    let found = Thinking::suggest(&shot, cue, &wanted, Level::new(level), seed).finish()?;
    let s = found.strike;
    let round = |x: f64| (x * 1e9).round() / 1e9;
    let json = serde_json::json!({
        "strike": {
            "ball": "cue",
            "speed": round(s.speed),
            "dir": [round(s.dir.x), round(s.dir.y)],
            "tip": [round(s.tip.x), round(s.tip.y)],
            "elevation_deg": 0.0,
        },
        "p_success": round(found.p_success),
    });
    Ok(json.to_string())
}
