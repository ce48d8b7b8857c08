//! Playing a shot's sounds: the cues `view::sound` finds for each frame, through macroquad's
//! audio when the client is built with the `sound` feature, silently otherwise. M mutes,
//! `[` and `]` turn the volume down and up (read, like every key, by `ui/input.rs`).

use breakshot_client::play::{InputFrame, Key};
use breakshot_client::view::sound::{Mixer, SoundTrack};
use breakshot_client::view::Playback;

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

    /// The mute and volume keys of this frame.
    pub fn keys(&mut self, input: &InputFrame) {
        let before = self.mixer;
        turn(&mut self.mixer, input);
        if self.mixer != before {
            super::report(&if self.mixer.muted {
                "sound muted".to_string()
            } else {
                format!("sound {:.0} %", 100.0 * self.mixer.volume)
            });
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

/// What the frame's mute and volume keys do to `mixer`.
fn turn(mixer: &mut Mixer, input: &InputFrame) {
    for key in &input.pressed {
        match key {
            Key::Mute => mixer.muted = !mixer.muted,
            Key::VolumeDown => mixer.nudge(-VOLUME_STEP),
            Key::VolumeUp => mixer.nudge(VOLUME_STEP),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn m_and_the_brackets_turn_the_sound_unless_a_line_is_being_typed() {
        let keys = InputFrame {
            pressed: vec![Key::Mute, Key::VolumeDown],
            typed: vec!['m', '['],
            ..InputFrame::default()
        };
        let mut mixer = Mixer::default();
        turn(&mut mixer, &keys.clone().while_typing());
        assert_eq!(
            mixer,
            Mixer::default(),
            "typed into the chat, not the sound"
        );
        turn(&mut mixer, &keys);
        assert!(mixer.muted);
        assert_ne!(mixer, Mixer::default());
    }
}
