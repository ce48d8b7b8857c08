//! What a shot sounds like, computed without an audio device: which sounds the shot's events
//! make and how loud (from the impact speeds at the event), and the sounds themselves,
//! synthesised as 16-bit mono PCM so the project ships no recordings.

use breakshot_shared::physics::{EventKind, Outcome};

/// Sample rate of the synthesised sounds (Hz).
pub(crate) const SAMPLE_RATE: u32 = 44_100;

/// The kinds of sound a shot makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sound {
    /// The cue tip on the cue ball.
    Strike,
    /// Two balls hitting.
    Click,
    /// A ball against a cushion or jaw.
    Thump,
    /// A ball falling into a pocket.
    Drop,
}

impl Sound {
    /// Every kind, once.
    pub const ALL: [Sound; 4] = [Sound::Strike, Sound::Click, Sound::Thump, Sound::Drop];

    /// The impact speed (m/s) that sounds at full volume.
    fn loud_speed(self) -> f64 {
        match self {
            Sound::Strike => 6.0,
            Sound::Click => 4.0,
            Sound::Thump => 3.0,
            Sound::Drop => 2.0,
        }
    }
}

/// One sound to play at shot time `t`, at `volume` in 0..=1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cue {
    /// When (s of shot time).
    pub t: f64,
    /// Which sound.
    pub sound: Sound,
    /// How loud, 0..=1, before the player's volume.
    pub volume: f32,
}

/// How long before an event the speeds are read (s): just before the impact changed them.
const BEFORE: f64 = 1e-6;
/// Quieter than this is not played.
const SILENT: f32 = 0.02;

/// The sounds of the shot's events with times in `(from, to]`, in time order.
pub(crate) fn cues(outcome: &Outcome, from: f64, to: f64) -> Vec<Cue> {
    let vel = |b: u16, t: f64| outcome.state_at(b as usize, (t - BEFORE).max(0.0)).vel;
    outcome
        .events
        .iter()
        .filter(|e| e.t > from && e.t <= to)
        .filter_map(|e| {
            let (sound, speed) = match e.kind {
                EventKind::Strike { ball } => (
                    Sound::Strike,
                    outcome.state_at(ball as usize, 0.0).vel.length(),
                ),
                EventKind::BallBall { a, b } => {
                    (Sound::Click, (vel(a, e.t) - vel(b, e.t)).length())
                }
                EventKind::BallCushion { ball, .. } => (Sound::Thump, vel(ball, e.t).length()),
                EventKind::BallPocket { ball, .. } => {
                    (Sound::Drop, vel(ball, e.t).length().max(0.5))
                }
                // A ball landing on the slate thumps like a soft cushion hit.
                EventKind::BallTable { ball } => {
                    let s = outcome.state_at(ball as usize, (e.t - BEFORE).max(0.0));
                    (Sound::Thump, s.vz.abs())
                }
                EventKind::Transition { .. } | EventKind::BallOffTable { .. } => return None,
            };
            let volume = (speed / sound.loud_speed()).clamp(0.0, 1.0).sqrt() as f32;
            (volume.is_finite() && volume >= SILENT).then_some(Cue {
                t: e.t,
                sound,
                volume,
            })
        })
        .collect()
}

/// A small deterministic noise source, so the sounds are the same on every machine.
struct Noise(u32);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        self.0 as f64 / u32::MAX as f64 * 2.0 - 1.0
    }
}

/// The samples of `sound` at full volume.
pub fn synthesise(sound: Sound) -> Vec<i16> {
    use std::f64::consts::TAU;
    let rate = SAMPLE_RATE as f64;
    let mut noise = Noise(0x9e37_79b9);
    // (length s, partials: (frequency Hz, amplitude, decay 1/s), noise amplitude, noise decay).
    let (length, partials, grit, grit_decay): (f64, &[(f64, f64, f64)], f64, f64) = match sound {
        // Phenolic balls: a bright, very short knock.
        Sound::Click => (
            0.06,
            &[
                (2650.0, 0.6, 90.0),
                (4100.0, 0.3, 140.0),
                (5900.0, 0.15, 200.0),
            ],
            0.25,
            400.0,
        ),
        // Rubber and wood: low and damped.
        Sound::Thump => (0.12, &[(130.0, 0.7, 35.0), (260.0, 0.25, 60.0)], 0.2, 150.0),
        // Leather tip: a dull tap with a little crack.
        Sound::Strike => (
            0.08,
            &[(900.0, 0.4, 70.0), (1800.0, 0.2, 120.0)],
            0.5,
            250.0,
        ),
        // Into the pocket: a hollow knock.
        Sound::Drop => (0.25, &[(320.0, 0.5, 18.0), (510.0, 0.3, 25.0)], 0.15, 40.0),
    };
    let n = (length * rate) as usize;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f64 / rate;
        // A 1 ms attack so no sound starts with a click of its own.
        let attack = (t / 0.001).min(1.0);
        let mut x = 0.0;
        for &(f, a, d) in partials {
            x += a * libm::sin(TAU * f * t) * libm::exp(-d * t);
        }
        x += grit * noise.next() * libm::exp(-grit_decay * t);
        out.push(
            (attack * x)
                .clamp(-1.0, 1.0)
                .mul_add(0.8 * i16::MAX as f64, 0.0) as i16,
        );
    }
    out
}

/// `samples` as a WAV file (16-bit mono), the form audio back ends load.
pub fn wav(samples: &[i16]) -> Vec<u8> {
    let data = (samples.len() * 2) as u32;
    let mut b = Vec::with_capacity(44 + data as usize);
    b.extend_from_slice(b"RIFF");
    b.extend_from_slice(&(36 + data).to_le_bytes());
    b.extend_from_slice(b"WAVEfmt ");
    b.extend_from_slice(&16u32.to_le_bytes());
    b.extend_from_slice(&1u16.to_le_bytes()); // PCM
    b.extend_from_slice(&1u16.to_le_bytes()); // mono
    b.extend_from_slice(&SAMPLE_RATE.to_le_bytes());
    b.extend_from_slice(&(SAMPLE_RATE * 2).to_le_bytes());
    b.extend_from_slice(&2u16.to_le_bytes());
    b.extend_from_slice(&16u16.to_le_bytes());
    b.extend_from_slice(b"data");
    b.extend_from_slice(&data.to_le_bytes());
    for s in samples {
        b.extend_from_slice(&s.to_le_bytes());
    }
    b
}

/// The player's sound settings: volume 0..=1 and mute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixer {
    /// 0..=1.
    pub volume: f32,
    /// Nothing is played.
    pub muted: bool,
}

impl Default for Mixer {
    fn default() -> Mixer {
        Mixer {
            volume: 0.7,
            muted: false,
        }
    }
}

impl Mixer {
    /// The volume to play `cue` at (0: not at all).
    pub fn level(&self, cue: &Cue) -> f32 {
        if self.muted {
            0.0
        } else {
            (self.volume * cue.volume).clamp(0.0, 1.0)
        }
    }

    /// Volume up or down by `step`, kept in 0..=1.
    pub fn nudge(&mut self, step: f32) {
        self.volume = (self.volume + step).clamp(0.0, 1.0);
    }
}

/// Sounds further behind the time shown than this (s of shot time) are dropped: after a skip
/// to the end of a shot, the table is not heard all at once.
const LATE: f64 = 0.25;

/// Follows a shot being shown and says which sounds are due each frame.
#[derive(Clone, Debug, Default)]
pub struct SoundTrack {
    /// The shot (its duration and event count tell shots apart) and the time heard up to.
    heard: Option<((u64, usize), f64)>,
}

impl SoundTrack {
    /// The cues between the last call and shot time `now` of `outcome` (since the start, for
    /// a new shot), except those more than 0.25 s (`LATE`) behind.
    pub fn due(&mut self, outcome: &Outcome, now: f64) -> Vec<Cue> {
        let mark = (outcome.duration.to_bits(), outcome.events.len());
        let from = match self.heard {
            Some((m, t)) if m == mark && t <= now => t,
            _ => -1.0,
        };
        self.heard = Some((mark, now));
        cues(outcome, from.max(now - LATE), now)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{simulate, BallState, Shot, Strike, TableKind};
    use glam::DVec2;

    fn into_the_corner(speed: f64) -> Outcome {
        // The cue ball drives ball 1 into the bottom-left corner pocket.
        let balls = vec![
            BallState::at_rest(DVec2::new(0.3, 0.3)),
            BallState::at_rest(DVec2::new(0.15, 0.15)),
        ];
        let shot = Shot::new(TableKind::NineFoot, balls)
            .struck(0, Strike::at_angle(speed, 225.0, DVec2::ZERO));
        simulate(&shot).expect("valid shot")
    }

    #[test]
    fn a_pot_sounds_strike_click_and_drop_in_order() {
        let o = into_the_corner(3.0);
        let all = cues(&o, -1.0, o.duration);
        let kinds: Vec<Sound> = all.iter().map(|c| c.sound).collect();
        assert_eq!(kinds.first(), Some(&Sound::Strike));
        let click = kinds
            .iter()
            .position(|&s| s == Sound::Click)
            .expect("a click");
        let drop = kinds
            .iter()
            .position(|&s| s == Sound::Drop)
            .expect("a drop");
        assert!(click < drop);
        assert!(all.windows(2).all(|w| w[0].t <= w[1].t));
        assert!(all.iter().all(|c| c.volume > 0.0 && c.volume <= 1.0));
    }

    #[test]
    fn harder_shots_are_louder() {
        let soft = cues(&into_the_corner(1.0), -1.0, f64::INFINITY);
        let hard = cues(&into_the_corner(4.0), -1.0, f64::INFINITY);
        let volume = |c: &[Cue], s: Sound| c.iter().find(|c| c.sound == s).map(|c| c.volume);
        for s in [Sound::Strike, Sound::Click] {
            let (a, b) = (
                volume(&soft, s).unwrap_or(0.0),
                volume(&hard, s).unwrap_or(0.0),
            );
            assert!(b > a && a > 0.0, "{s:?}: soft {a}, hard {b}");
        }
    }

    #[test]
    fn a_track_plays_each_sound_once_whatever_the_frame_rate() {
        let o = into_the_corner(3.0);
        let mut track = SoundTrack::default();
        let mut heard = Vec::new();
        let mut t = 0.0;
        while t < o.duration {
            heard.extend(track.due(&o, t));
            t += 1.0 / 60.0;
        }
        heard.extend(track.due(&o, o.duration));
        assert_eq!(heard, cues(&o, -1.0, o.duration));
        assert!(track.due(&o, o.duration).is_empty());
        // Skipping to the end of a new shot plays only its last moments.
        let mut skip = SoundTrack::default();
        let late = skip.due(&o, o.duration);
        assert!(late.iter().all(|c| c.t >= o.duration - LATE));
    }

    #[test]
    fn mute_and_volume_scale_every_sound() {
        let cue = Cue {
            t: 0.0,
            sound: Sound::Click,
            volume: 0.5,
        };
        let mut m = Mixer::default();
        m.nudge(1.0);
        assert_eq!(m.level(&cue), 0.5);
        m.nudge(-0.25);
        assert_eq!(m.level(&cue), 0.375);
        m.muted = true;
        assert_eq!(m.level(&cue), 0.0);
    }

    #[test]
    fn sounds_are_short_audible_and_fade_out() {
        for s in Sound::ALL {
            let pcm = synthesise(s);
            assert!(
                !pcm.is_empty() && pcm.len() < SAMPLE_RATE as usize / 2,
                "{s:?}"
            );
            let peak = pcm.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
            assert!(peak > 3000, "{s:?} is audible: {peak}");
            let tail = pcm[pcm.len() - 50..].iter().map(|x| x.unsigned_abs());
            assert!(tail.max().unwrap_or(0) < peak / 4, "{s:?} fades out");
            let file = wav(&pcm);
            assert_eq!(&file[..4], b"RIFF");
            assert_eq!(file.len(), 44 + 2 * pcm.len());
        }
    }
}
