//! Frame pacing by wall-clock time.

use std::time::{Duration, Instant};

pub struct FrameClock {
    period: Duration,
    frame_start: Instant,
    last: Instant,
}

impl FrameClock {
    pub fn new(fps: f64) -> FrameClock {
        let now = Instant::now();
        FrameClock {
            period: Duration::from_secs_f64(1.0 / fps),
            frame_start: now,
            last: now,
        }
    }

    /// Seconds since the previous frame began; marks the start of this one.
    pub fn frame_time(&mut self) -> f64 {
        let now = Instant::now();
        let dt = now.duration_since(self.last).as_secs_f64();
        self.last = now;
        self.frame_start = now;
        dt
    }

    /// Sleeps out the rest of the frame's period.
    pub fn pace(&self) {
        let spent = self.frame_start.elapsed();
        if spent < self.period {
            std::thread::sleep(self.period - spent);
        }
    }
}
