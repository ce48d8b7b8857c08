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
    /// The sum of the recorded durations, in nanoseconds (a Prometheus histogram's `_sum`).
    sum_nanos: AtomicU64,
}

impl Default for Histogram {
    fn default() -> Histogram {
        Histogram {
            counts: std::array::from_fn(|_| AtomicU64::new(0)),
            sum_nanos: AtomicU64::new(0),
        }
    }
}

fn bucket(d: Duration) -> usize {
    let micros = d.as_secs_f64() * 1e6;
    if micros <= 1.0 {
        return 0;
    }
    // libm rather than std: the bucket edges (shown in the metrics) are then the same on
    // every machine.
    let i = (libm::log2(micros) * PER_OCTAVE).ceil();
    (i as usize).min(BUCKETS - 1)
}

/// The upper edge of bucket `i`.
fn edge(i: usize) -> Duration {
    Duration::from_secs_f64(libm::exp2(i as f64 / PER_OCTAVE) * 1e-6)
}

impl Histogram {
    /// Counts one duration (one relaxed atomic add); one over about 34 s lands in the last bucket.
    pub fn record(&self, d: Duration) {
        self.counts[bucket(d)].fetch_add(1, Ordering::Relaxed);
        let nanos = u64::try_from(d.as_nanos()).unwrap_or(u64::MAX);
        self.sum_nanos.fetch_add(nanos, Ordering::Relaxed);
    }

    /// The sum of the recorded durations.
    pub fn sum(&self) -> Duration {
        Duration::from_nanos(self.sum_nanos.load(Ordering::Relaxed))
    }

    /// Cumulative counts at every `step`-th bucket edge, `(upper edge, durations at most
    /// that long)`, ending with the last bucket: the buckets of a Prometheus histogram
    /// (`step` 4 gives edges 2^(1/2), about 41 %, apart).
    pub fn cumulative(&self, step: usize) -> Vec<(Duration, u64)> {
        let step = step.max(1);
        let mut seen = 0;
        let mut out = Vec::with_capacity(BUCKETS / step + 1);
        for (i, c) in self.counts.iter().enumerate() {
            seen += c.load(Ordering::Relaxed);
            if i % step == step - 1 || i == BUCKETS - 1 {
                out.push((edge(i), seen));
            }
        }
        out
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

    #[test]
    fn cumulative_buckets_grow_to_the_count_and_the_sum_adds_up() {
        let h = Histogram::default();
        for ms in [1u64, 2, 3, 50] {
            h.record(Duration::from_millis(ms));
        }
        assert_eq!(h.sum(), Duration::from_millis(56));
        let buckets = h.cumulative(4);
        assert!(buckets
            .windows(2)
            .all(|w| w[0].0 < w[1].0 && w[0].1 <= w[1].1));
        assert_eq!(buckets.last().map(|b| b.1), Some(4));
        let under = |limit: Duration| {
            buckets
                .iter()
                .rev()
                .find(|(edge, _)| *edge <= limit)
                .map_or(0, |b| b.1)
        };
        assert_eq!(under(Duration::from_micros(900)), 0);
        assert_eq!(under(Duration::from_millis(40)), 3);
    }
}
