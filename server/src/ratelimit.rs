//! A token bucket: `burst` actions at once, then one per `refill`.

use std::time::{Duration, Instant};

/// One token bucket; the caller passes `now`, so it never reads a clock.
#[derive(Clone, Debug)]
pub struct Bucket {
    burst: u32,
    refill: Duration,
    tokens: u32,
    last: Instant,
}

impl Bucket {
    /// A full bucket: `burst` tokens, one more earned every `refill`, never more than `burst`.
    pub fn new(burst: u32, refill: Duration, now: Instant) -> Bucket {
        Bucket {
            burst,
            refill,
            tokens: burst,
            last: now,
        }
    }

    /// Takes one token if there is one.
    pub fn take(&mut self, now: Instant) -> bool {
        let earned =
            now.saturating_duration_since(self.last).as_nanos() / self.refill.as_nanos().max(1);
        if earned > 0 {
            let earned = u32::try_from(earned).unwrap_or(u32::MAX);
            self.tokens = self.tokens.saturating_add(earned).min(self.burst);
            // Keep the fraction of a refill already earned.
            self.last += self.refill * earned.min(self.burst);
            if self.tokens == self.burst {
                self.last = now;
            }
        }
        if self.tokens == 0 {
            return false;
        }
        self.tokens -= 1;
        true
    }

    /// Gives back a token taken for an action that turned out not to count.
    pub fn refund(&mut self) {
        self.tokens = (self.tokens + 1).min(self.burst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_burst_then_one_per_refill() {
        let t0 = Instant::now();
        let mut b = Bucket::new(3, Duration::from_secs(2), t0);
        assert!((0..3).all(|_| b.take(t0)));
        assert!(!b.take(t0));
        assert!(!b.take(t0 + Duration::from_secs(1)));
        assert!(b.take(t0 + Duration::from_secs(2)));
        assert!(!b.take(t0 + Duration::from_secs(3)));
        assert!((0..3).all(|_| b.take(t0 + Duration::from_secs(100))));
        assert!(!b.take(t0 + Duration::from_secs(100)));
    }
}
