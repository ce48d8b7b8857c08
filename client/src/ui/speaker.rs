//! Playing a shot's sounds: the cues `view::sound` finds for each frame, through macroquad's
//! audio when the client is built with the `sound` feature, silently otherwise. M mutes,
//! `[` and `]` turn the volume down and up.

use breakshot_client::view::sound::{Mixer, SoundTrack};
use breakshot_client::view::Playback;
use macroquad::prelude::{is_key_pressed, KeyCode};

/// Volume change per key press.
const VOLUME_STEP: f32 = 0.1;

pub struct Speaker {
    pub mixer: Mixer,
    track: SoundTrack,
    #[cfg(feature = "sound")]
    sounds: Vec<(
        breakshot_client::view::sound::Sound,
        macroquad::audio::Sound,
    )>,
}

impl Speaker {
    /// Synthesises the sounds and hands them to the audio back end (if built in).
    pub async fn new() -> Speaker {
        #[cfg(feature = "sound")]
        let sounds = {
            use breakshot_client::view::sound::{synthesise, wav, Sound};
            let mut sounds = Vec::new();
            for s in Sound::ALL {
                match macroquad::audio::load_sound_from_bytes(&wav(&synthesise(s))).await {
                    Ok(loaded) => sounds.push((s, loaded)),
                    Err(e) => tracing::warn!("sound {s:?} not loaded: {e}"),
                }
            }
            sounds
        };
        Speaker {
            mixer: Mixer::default(),
            track: SoundTrack::default(),
            #[cfg(feature = "sound")]
            sounds,
        }
    }

    /// The mute and volume keys.
    pub fn keys(&mut self) {
        if is_key_pressed(KeyCode::M) {
            self.mixer.muted = !self.mixer.muted;
        }
        if is_key_pressed(KeyCode::LeftBracket) {
            self.mixer.nudge(-VOLUME_STEP);
        }
        if is_key_pressed(KeyCode::RightBracket) {
            self.mixer.nudge(VOLUME_STEP);
        }
    }

    /// Plays the sounds of `shot` that became due since the last frame.
    pub fn hear(&mut self, shot: Option<&Playback>) {
        let Some(p) = shot else { return };
        let due = self.track.due(p.outcome(), p.time());
        #[cfg(feature = "sound")]
        for cue in &due {
            let volume = self.mixer.level(cue);
            let sound = self.sounds.iter().find(|(s, _)| *s == cue.sound);
            if let (Some((_, sound)), true) = (sound, volume > 0.0) {
                macroquad::audio::play_sound(
                    sound,
                    macroquad::audio::PlaySoundParams {
                        looped: false,
                        volume,
                    },
                );
            }
        }
        #[cfg(not(feature = "sound"))]
        let _ = due;
    }
}
