//! Choosing among candidates by playing each one many times under the player's own
//! execution noise: successive halving, so the promising ones get the samples.

use super::candidates::Candidate;
use super::noise::{mix, Noise, Rng};
use crate::physics::Strike;

/// What one trial of a candidate led to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Played {
    /// How good the result is for the shooter, 0 (lost) to 1 (won).
    pub value: f64,
    /// The shot did what it was meant to (a pot that keeps the turn, or a win).
    pub success: bool,
}

impl Played {
    /// A strike that could not be played: worth nothing, and no success.
    pub(super) const REFUSED: Played = Played {
        value: 0.0,
        success: false,
    };
}

/// Plays a strike as delivered and judges the result.
pub(super) trait Judge {
    /// `deep`: look one shot further where the shooter keeps the table.
    fn play(&mut self, strike: &Strike, call: Option<u8>, deep: bool) -> Played;
    /// Simulations run so far.
    fn runs(&self) -> usize;
}

/// How many trials each round gives its candidates, and how many go on to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// Cumulative samples per candidate after each round.
    pub samples: [usize; 3],
    /// Candidates kept after each of the first two rounds.
    pub keep: [usize; 2],
    /// The last round looks one shot further.
    pub look_ahead: bool,
}

/// The chosen candidate and what its trials showed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Choice {
    pub candidate: Candidate,
    /// Mean value over its trials.
    pub value: f64,
    /// Share of its trials that succeeded.
    pub p_success: f64,
    pub trials: usize,
}

#[derive(Clone, Copy)]
struct Tally {
    index: usize,
    sum: f64,
    successes: usize,
    n: usize,
}

impl Tally {
    fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }
}

/// The best of `candidates` for a player with `noise`. Trial `k` of every candidate uses the
/// same noise draws (common random numbers), so candidates are compared on equal luck.
pub(super) fn choose<J: Judge>(
    judge: &mut J,
    candidates: &[Candidate],
    noise: Noise,
    schedule: &Schedule,
    seed: u64,
) -> Option<Choice> {
    let mut alive: Vec<Tally> = (0..candidates.len())
        .map(|index| Tally {
            index,
            sum: 0.0,
            successes: 0,
            n: 0,
        })
        .collect();
    for round in 0..3 {
        let deep = round == 2 && schedule.look_ahead;
        if deep {
            // The look-ahead changes what a trial is worth: start the finalists afresh.
            for t in alive.iter_mut() {
                *t = Tally {
                    index: t.index,
                    sum: 0.0,
                    successes: 0,
                    n: 0,
                };
            }
        }
        let target = schedule.samples[round];
        for t in alive.iter_mut() {
            let c = &candidates[t.index];
            while t.n < target {
                let mut rng = Rng::new(mix(seed, t.n as u64 + 1));
                let strike = noise.perturb(&c.strike, &mut rng);
                let played = judge.play(&strike, c.call, deep);
                t.sum += played.value;
                t.successes += usize::from(played.success);
                t.n += 1;
            }
        }
        // Stable order: best mean first, then the earlier candidate.
        alive.sort_by(|a, b| b.mean().total_cmp(&a.mean()).then(a.index.cmp(&b.index)));
        if round < 2 {
            alive.truncate(schedule.keep[round].max(1));
        }
    }
    alive.first().map(|t| Choice {
        candidate: candidates[t.index],
        value: t.mean(),
        p_success: if t.n == 0 {
            0.0
        } else {
            t.successes as f64 / t.n as f64
        },
        trials: t.n,
    })
}
