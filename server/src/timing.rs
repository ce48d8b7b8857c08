//! The server's own time per command, from the moment its frame was read to the moment its
//! result was handed to the connections: queueing for the hub, the rules and the simulation,
//! and the durable store write. Kept as a histogram of atomic counters (cheap enough to
//! keep always), so a load test can tell the server's share of a round trip from the network
//! and the clients'.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Buckets per doubling of time: each bucket is 2^(1/8), about 9 %, wider than the last.
const PER_OCTAVE: f64 = 8.0;
/// Buckets from 1 µs up to 2^25 µs (about 34 s); longer times land in the last.
const BUCKETS: usize = 200;

/// Durations in buckets about 9 % wide, from 1 µs to about 34 s; safe to record from any
/// thread.
#[derive(Debug)]
pub struct Histogram {
    counts: [AtomicU64; BUCKETS],
}

impl Default for Histogram {
    fn default() -> Histogram {
        Histogram {
            counts: std::array::from_fn(|_| AtomicU64::new(0)),
        }
    }
}

fn bucket(d: Duration) -> usize {
    let micros = d.as_secs_f64() * 1e6;
    if micros <= 1.0 {
        return 0;
    }
    // Timing is not physics: std's log2 is fine here.
    let i = (micros.log2() * PER_OCTAVE).ceil();
    (i as usize).min(BUCKETS - 1)
}

/// The upper edge of bucket `i`.
fn edge(i: usize) -> Duration {
    Duration::from_secs_f64((i as f64 / PER_OCTAVE).exp2() * 1e-6)
}

impl Histogram {
    /// Counts one duration (one relaxed atomic add); one over about 34 s lands in the last bucket.
    pub fn record(&self, d: Duration) {
        self.counts[bucket(d)].fetch_add(1, Ordering::Relaxed);
    }

    /// How many durations were recorded.
    pub fn count(&self) -> u64 {
        self.counts.iter().map(|c| c.load(Ordering::Relaxed)).sum()
    }

    /// The time under which a fraction `q` of the recorded times fall (to within a bucket,
    /// rounded up), `None` if nothing was recorded.
    pub fn quantile(&self, q: f64) -> Option<Duration> {
        let counts: Vec<u64> = self
            .counts
            .iter()
            .map(|c| c.load(Ordering::Relaxed))
            .collect();
        let total: u64 = counts.iter().sum();
        if total == 0 {
            return None;
        }
        let rank = ((q.clamp(0.0, 1.0) * total as f64).ceil() as u64).max(1);
        let mut seen = 0;
        for (i, c) in counts.iter().enumerate() {
            seen += c;
            if seen >= rank {
                return Some(edge(i));
            }
        }
        Some(edge(BUCKETS - 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_within_a_bucket_of_the_truth() {
        let h = Histogram::default();
        assert_eq!(h.quantile(0.5), None);
        for ms in 1..=100u64 {
            h.record(Duration::from_millis(ms));
        }
        assert_eq!(h.count(), 100);
        let p50 = h.quantile(0.5).unwrap().as_secs_f64() * 1e3;
        let p99 = h.quantile(0.99).unwrap().as_secs_f64() * 1e3;
        assert!((50.0..=50.0 * 1.1).contains(&p50), "{p50}");
        assert!((99.0..=99.0 * 1.1).contains(&p99), "{p99}");
        h.record(Duration::from_secs(1_000));
        assert!(h.quantile(1.0).unwrap() >= Duration::from_secs(30));
    }
}
