//! Choosing among candidates by playing each one many times under the player's own
//! execution noise: successive halving, so the promising ones get the samples.

use super::candidates::Candidate;
use super::noise::{mix, Noise, Rng};
use super::thinking::Meter;
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
    async fn play(&mut self, strike: &Strike, call: Option<u8>, deep: bool) -> Played;
    /// What the judge's simulations are counted on.
    fn meter(&self) -> &Meter;
    /// Simulations a look-ahead is expected to cost before any has been played: only for the
    /// progress estimate.
    fn look_ahead_guess(&self) -> usize;
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

/// Trials left from the start of `round` with `alive` candidates in it, and how many of them
/// look one shot further.
pub(super) fn trials_left(schedule: &Schedule, round: usize, mut alive: usize) -> (usize, usize) {
    let (mut plain, mut deep) = (0, 0);
    for r in round..3 {
        let is_deep = r == 2 && schedule.look_ahead;
        let before = if r == 0 || is_deep {
            0
        } else {
            schedule.samples[r - 1]
        };
        let trials = alive * schedule.samples[r].saturating_sub(before);
        if is_deep {
            deep += trials;
        } else {
            plain += trials;
        }
        if r < 2 {
            alive = alive.min(schedule.keep[r].max(1));
        }
    }
    (plain, deep)
}

/// The best of `candidates` for a player with `noise`. Trial `k` of every candidate uses the
/// same noise draws (common random numbers), so candidates are compared on equal luck.
pub(super) async fn choose<J: Judge>(
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
    // What a trial with the look-ahead costs, as measured so far: (trials, simulations).
    let mut deep_cost = (0usize, 0usize);
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
        let (mut plain, mut deeper) = trials_left(schedule, round, alive.len());
        for t in alive.iter_mut() {
            let c = &candidates[t.index];
            while t.n < target {
                let per_deep = match deep_cost {
                    (0, _) => 1 + judge.look_ahead_guess(),
                    (n, sims) => sims.div_ceil(n),
                };
                judge.meter().expect(plain + deeper * per_deep);
                let before = judge.meter().done();
                let mut rng = Rng::new(mix(seed, t.n as u64 + 1));
                let strike = noise.perturb(&c.strike, &mut rng);
                let played = judge.play(&strike, c.call, deep).await;
                t.sum += played.value;
                t.successes += usize::from(played.success);
                t.n += 1;
                if deep {
                    deeper = deeper.saturating_sub(1);
                    deep_cost.0 += 1;
                    deep_cost.1 += judge.meter().done() - before;
                } else {
                    plain = plain.saturating_sub(1);
                }
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
