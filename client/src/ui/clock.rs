//! Frame pacing by wall-clock time, and the window's one clock.

use std::time::Duration;

/// Time since the window's clock started. Natively a monotonic [`std::time::Instant`]; in the
/// browser, where `Instant` does not exist, the page's clock.
pub fn now() -> Duration {
    #[cfg(not(target_arch = "wasm32"))]
    {
        static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
        START.get_or_init(std::time::Instant::now).elapsed()
    }
    #[cfg(target_arch = "wasm32")]
    {
        static START: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
        let now = macroquad::miniquad::date::now();
        Duration::from_secs_f64((now - *START.get_or_init(|| now)).max(0.0))
    }
}

pub struct FrameClock {
    // The page paces its own frames.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    period: Duration,
    frame_start: Duration,
    last: Duration,
    /// How long the last frame slept to keep the pace.
    slept: Duration,
    /// How long the frame before this one worked: its time less its sleep.
    work: Duration,
}

impl FrameClock {
    pub fn new(fps: f64) -> FrameClock {
        let now = now();
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
        let now = now();
        let dt = now.saturating_sub(self.last);
        self.work = dt.saturating_sub(self.slept);
        self.slept = Duration::ZERO;
        self.last = now;
        self.frame_start = now;
        dt.as_secs_f64()
    }

    /// Sleeps out the rest of the frame's period. In the browser the page paces the frames
    /// (and nothing may sleep there).
    pub fn pace(&mut self) {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let spent = now().saturating_sub(self.frame_start);
            if spent < self.period {
                let start = now();
                std::thread::sleep(self.period - spent);
                self.slept = now().saturating_sub(start);
            }
        }
    }

    /// The time the previous frame took to update, draw and show (everything but the pacing
    /// sleep), in milliseconds.
    pub fn work_ms(&self) -> f64 {
        self.work.as_secs_f64() * 1000.0
    }
}

/// A seed for a new rack from the clock: every rack is different.
pub fn fresh_seed() -> u64 {
    // Seconds since 1970 from the system (or the page), in nanoseconds' worth of bits.
    (macroquad::miniquad::date::now() * 1e9) as u64
}
