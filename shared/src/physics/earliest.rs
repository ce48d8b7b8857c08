//! The earliest of a list of times, kept up to date as they change one at a time, so that the
//! event loop finds it without scanning the list at every step.

/// Which index holds the earliest of a list of times: the first (lowest) of equal times, and
/// none when no time is below infinity (a NaN is never the earliest). The answer is always
/// the one a scan from the first index would give.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Earliest {
    /// The index, or `usize::MAX` for none.
    first: usize,
}

impl Earliest {
    /// The earliest of `times`, by a scan.
    pub(super) fn of(times: &[f64]) -> Earliest {
        Earliest {
            first: first_min(times).map_or(usize::MAX, |(i, _)| i),
        }
    }

    /// The index of the earliest time and that time, if any is below infinity.
    #[inline]
    pub(super) fn get(self, times: &[f64]) -> Option<(usize, f64)> {
        times.get(self.first).map(|&t| (self.first, t))
    }

    /// Sets `times[i]` to `t`, keeping track of the earliest.
    #[inline]
    pub(super) fn set(&mut self, times: &mut [f64], i: usize, t: f64) {
        let f = self.first;
        let best = times.get(f).copied().unwrap_or(f64::INFINITY);
        times[i] = t;
        if t < best || (f != usize::MAX && t == best && i <= f) {
            // Earlier than the earliest, or equal to it at a lower index (or the earliest
            // itself, unchanged).
            self.first = i;
        } else if i == f {
            // The earliest went later (or became NaN): any other may now be first.
            *self = Earliest::of(times);
        }
    }
}

/// The first index of the least of `times` and that time, if any is below infinity (a NaN is
/// never the least): what a scan keeping the first strictly smaller time finds. The least is
/// found first, in two interleaved runs without branches, then the first index holding it
/// (every time equal to the least, a zero of either sign for a zero, was no smaller than it).
#[inline]
pub(super) fn first_min(times: &[f64]) -> Option<(usize, f64)> {
    let min = |best: f64, t: f64| if t < best { t } else { best };
    let (mut even, mut odd) = (f64::INFINITY, f64::INFINITY);
    let mut pairs = times.chunks_exact(2);
    for pair in &mut pairs {
        even = min(even, pair[0]);
        odd = min(odd, pair[1]);
    }
    let mut best = min(even, odd);
    if let [last] = pairs.remainder() {
        best = min(best, *last);
    }
    if best == f64::INFINITY {
        return None;
    }
    times.iter().position(|&t| t == best).map(|i| (i, times[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_min_agrees_with_a_scan() {
        let choices = [
            0.5,
            1.0,
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NAN,
            f64::NEG_INFINITY,
        ];
        let mut rng = crate::ai::Rng::new(0x2545_f491_4f6c_dd1du64);
        let mut next = || rng.next_u64();
        for _ in 0..20_000 {
            let n = (next() % 20) as usize;
            let times: Vec<f64> = (0..n).map(|_| choices[(next() % 7) as usize]).collect();
            let mut scan = None;
            let mut best = f64::INFINITY;
            for (i, &t) in times.iter().enumerate() {
                if t < best {
                    best = t;
                    scan = Some(i);
                }
            }
            let found = first_min(&times);
            assert_eq!(found.map(|(i, _)| i), scan, "{times:?}");
            if let Some((i, t)) = found {
                assert_eq!(t.to_bits(), times[i].to_bits());
            }
        }
    }

    #[test]
    fn always_agrees_with_a_scan() {
        let choices = [0.5, 1.0, 2.0, f64::INFINITY, f64::NAN];
        let mut rng = crate::ai::Rng::new(0x9e37_79b9_7f4a_7c15u64);
        let mut next = || rng.next_u64();
        let mut times = [f64::INFINITY; 6];
        let mut earliest = Earliest::of(&times);
        for _ in 0..20_000 {
            let i = (next() % 6) as usize;
            let t = choices[(next() % 5) as usize];
            earliest.set(&mut times, i, t);
            let scan = Earliest::of(&times);
            assert_eq!(earliest.first, scan.first, "{times:?}");
        }
    }
}
