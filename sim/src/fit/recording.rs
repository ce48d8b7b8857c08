//! Recorded shots: the format of the real-shot recordings (an array of
//! `{"id", "balls": {"1": {"t", "x", "y"}, ...}}`, positions centred on the table with `x`
//! along its length) read into the scene frame, in metres.

use std::collections::BTreeMap;

use anyhow::{bail, Context};
use breakshot_shared::physics::TableKind;
use glam::DVec2;
use serde::{Deserialize, Serialize};

/// The recordings' scale: a ball radius of 32.75 units stands for a 30.75 mm ball.
pub const UNITS_TO_METRES: f64 = 30.75 / 32.75;

/// How positions in a recordings file are given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// The real-shot recordings' own scaled units.
    Recording,
    /// Metres.
    Metres,
}

#[derive(Debug, Deserialize, Serialize)]
pub struct RawShot {
    pub id: serde_json::Value,
    pub balls: BTreeMap<String, RawTrack>,
}

#[derive(Debug, Deserialize, Serialize)]
pub struct RawTrack {
    pub t: Vec<f64>,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// One ball's recorded path, in the scene frame (metres, origin at a corner).
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub name: String,
    pub t: Vec<f64>,
    pub pos: Vec<DVec2>,
}

/// A recorded shot.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    pub id: String,
    pub balls: Vec<Track>,
    /// The ball that moves first: the one the cue struck.
    pub cue: usize,
}

impl Recording {
    /// Time of the last sample.
    pub fn end(&self) -> f64 {
        self.balls
            .iter()
            .filter_map(|b| b.t.last().copied())
            .fold(0.0, f64::max)
    }

    /// Latest time the cue can have struck: the cue ball's first sample after the start,
    /// where it has moved (the recordings start their clock a little before the strike).
    pub fn max_delay(&self) -> f64 {
        self.balls[self.cue]
            .t
            .get(1)
            .copied()
            .unwrap_or(0.0)
            .min(0.1)
    }

    /// Number of (ball, time) samples.
    pub fn samples(&self) -> usize {
        self.balls.iter().map(|b| b.t.len()).sum()
    }
}

/// Table-frame position of a recorded point: the recording's long axis `x` becomes the
/// scene's `y`, by a rotation (not a mirror, so side spin keeps its sense).
pub fn to_scene(x: f64, y: f64, scale: f64) -> DVec2 {
    let (w, l) = TableKind::Carom.size().unwrap_or((1.42, 2.84));
    DVec2::new(0.5 * w - y * scale, 0.5 * l + x * scale)
}

/// The inverse of [`to_scene`].
#[cfg(test)]
pub fn from_scene(p: DVec2, scale: f64) -> (f64, f64) {
    let (w, l) = TableKind::Carom.size().unwrap_or((1.42, 2.84));
    ((p.y - 0.5 * l) / scale, (0.5 * w - p.x) / scale)
}

/// Parses a recordings file.
pub fn parse(text: &str, units: Units) -> anyhow::Result<Vec<Recording>> {
    let raw: Vec<RawShot> = serde_json::from_str(text).context("reading the recordings")?;
    if raw.is_empty() {
        bail!("the recordings hold no shot");
    }
    let scale = match units {
        Units::Recording => UNITS_TO_METRES,
        Units::Metres => 1.0,
    };
    raw.into_iter()
        .enumerate()
        .map(|(k, shot)| {
            let id = match &shot.id {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            convert(id, shot, scale).with_context(|| format!("shot {k}"))
        })
        .collect()
}

fn convert(id: String, shot: RawShot, scale: f64) -> anyhow::Result<Recording> {
    if shot.balls.len() < 2 {
        bail!("a shot needs at least two balls");
    }
    let mut balls = Vec::with_capacity(shot.balls.len());
    for (name, track) in shot.balls {
        let n = track.t.len();
        if n == 0 || track.x.len() != n || track.y.len() != n {
            bail!("ball {name}: t, x and y must be non-empty and of the same length");
        }
        let finite = track.t.iter().chain(&track.x).chain(&track.y);
        if finite.into_iter().any(|v| !v.is_finite()) {
            bail!("ball {name}: every number must be finite");
        }
        if track.t.windows(2).any(|w| w[1] < w[0]) || track.t[0] < 0.0 {
            bail!("ball {name}: times must be non-negative and in order");
        }
        let pos = track
            .x
            .iter()
            .zip(&track.y)
            .map(|(&x, &y)| to_scene(x, y, scale))
            .collect();
        balls.push(Track {
            name,
            t: track.t,
            pos,
        });
    }
    // The cue ball moves first: it has the earliest second sample (a ball at rest
    // throughout has only its first and last).
    let cue = (0..balls.len())
        .min_by(|&a, &b| {
            let second = |i: usize| balls[i].t.get(1).copied().unwrap_or(f64::INFINITY);
            second(a).total_cmp(&second(b))
        })
        .unwrap_or(0);
    Ok(Recording { id, balls, cue })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_recordings_extents_are_the_carom_bed() {
        // ±1.48 × ±0.723 recording units are the centre limits of a 61.5 mm ball on a
        // 2.84 × 1.42 m bed.
        let corner = to_scene(1.48, 0.723, UNITS_TO_METRES);
        assert!((corner.y - (2.84 - 0.03075)).abs() < 1e-3, "{corner}");
        assert!((corner.x - 0.03075).abs() < 1e-3, "{corner}");
        let (x, y) = from_scene(corner, UNITS_TO_METRES);
        assert!((x - 1.48).abs() < 1e-12 && (y - 0.723).abs() < 1e-12);
    }

    #[test]
    fn the_first_ball_to_move_is_the_cue_ball() {
        let text = r#"[{"id": 7, "balls": {
            "1": {"t": [0, 9], "x": [0, 0], "y": [0, 0]},
            "2": {"t": [0, 0.02, 0.04], "x": [0.5, 0.6, 0.7], "y": [0, 0, 0]}}}]"#;
        let shots = parse(text, Units::Metres).expect("parses");
        assert_eq!(shots[0].id, "7");
        assert_eq!(shots[0].cue, 1);
        assert_eq!(shots[0].samples(), 5);
    }

    #[test]
    fn bad_recordings_are_refused() {
        for text in [
            "{}",
            "[]",
            r#"[{"id": 1, "balls": {"1": {"t": [0], "x": [0], "y": [0]}}}]"#,
            r#"[{"id": 1, "balls": {"1": {"t": [0, 1], "x": [0], "y": [0, 0]},
                                    "2": {"t": [0], "x": [0], "y": [0]}}}]"#,
            r#"[{"id": 1, "balls": {"1": {"t": [1, 0], "x": [0, 0], "y": [0, 0]},
                                    "2": {"t": [0], "x": [0], "y": [0]}}}]"#,
        ] {
            assert!(parse(text, Units::Metres).is_err(), "{text}");
        }
    }
}
