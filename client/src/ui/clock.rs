//! Frame pacing by wall-clock time.

use std::time::{Duration, Instant};

pub struct FrameClock {
    period: Duration,
    frame_start: Instant,
    last: Instant,
    /// How long the last frame slept to keep the pace.
    slept: Duration,
    /// How long the frame before this one worked: its time less its sleep.
    work: Duration,
}

impl FrameClock {
    pub fn new(fps: f64) -> FrameClock {
        let now = Instant::now();
        FrameClock {
            period: Duration::from_secs_f64(1.0 / fps),
            frame_start: now,
            last: now,
            slept: Duration::ZERO,
            work: Duration::ZERO,
        }
    }

    /// Seconds since the previous frame began; marks the start of this one.
    pub fn frame_time(&mut self) -> f64 {
        let now = Instant::now();
        let dt = now.duration_since(self.last);
        self.work = dt.saturating_sub(self.slept);
        self.slept = Duration::ZERO;
        let dt = dt.as_secs_f64();
        self.last = now;
        self.frame_start = now;
        dt
    }

    /// Sleeps out the rest of the frame's period.
    pub fn pace(&mut self) {
        let spent = self.frame_start.elapsed();
        if spent < self.period {
            let start = Instant::now();
            std::thread::sleep(self.period - spent);
            self.slept = start.elapsed();
        }
    }

    /// The time the previous frame took to update, draw and show (everything but the pacing
    /// sleep), in milliseconds.
    pub fn work_ms(&self) -> f64 {
        self.work.as_secs_f64() * 1000.0
    }
}
