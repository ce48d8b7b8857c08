//! Thinking in steps: a search that advances by a bounded number of simulations per call, so
//! that a front end without threads (the browser) can think across frames and show how far
//! it has got.
//!
//! The search is written once, as ordinary code whose only suspension point is a simulation:
//! every trial shot first waits on the [`Meter`], which lets it through while the current
//! step has simulations left and otherwise suspends the whole search until the next step.
//! Rust's `async` turns that code into a state machine; a step polls it once with a waker
//! that does nothing, because nothing but the next step ever resumes it. Running to the end
//! ([`Thinking::finish`]) is the same poll with an unbounded allowance, so the one-call API
//! ([`super::decide`]) and the stepped one cannot give different answers.

use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::task::{Context, Poll, Waker};

/// Counts the simulations of one search and holds back those beyond the current step's
/// allowance. Cheap to clone: every clone counts into the same search.
#[derive(Clone, Debug, Default)]
pub(super) struct Meter(Arc<Counts>);

/// Atomics only so that a search may be sent to another thread; one thread uses it at a time.
#[derive(Debug, Default)]
struct Counts {
    /// Simulations run so far.
    done: AtomicUsize,
    /// Simulations the current step may still run.
    allowed: AtomicUsize,
    /// The search's latest estimate of its total (see [`Meter::expect`]).
    planned: AtomicUsize,
    /// Simulations expected after the part of the search now running (see
    /// [`Meter::expect_afterwards`]).
    afterwards: AtomicUsize,
}

impl Meter {
    /// Waits until one more simulation is allowed and counts it: call it before each one.
    pub(super) fn simulation(&self) -> Simulation<'_> {
        Simulation(&self.0)
    }

    /// Simulations run so far.
    pub(super) fn done(&self) -> usize {
        self.0.done.load(Ordering::Relaxed)
    }

    /// The part of the search now running expects about `more` simulations after those
    /// already run (and the parts after it what [`Meter::expect_afterwards`] said).
    pub(super) fn expect(&self, more: usize) {
        let afterwards = self.0.afterwards.load(Ordering::Relaxed);
        let total = self.done().saturating_add(more).saturating_add(afterwards);
        self.0.planned.store(total, Ordering::Relaxed);
    }

    /// The part of the search about to start will be followed by about `more` simulations.
    pub(super) fn expect_afterwards(&self, more: usize) {
        self.0.afterwards.store(more, Ordering::Relaxed);
    }

    fn allow(&self, simulations: usize) {
        self.0.allowed.store(simulations, Ordering::Relaxed);
    }

    fn planned(&self) -> usize {
        self.0.planned.load(Ordering::Relaxed)
    }
}

/// The wait for one simulation's turn ([`Meter::simulation`]).
#[must_use = "a simulation must wait for its turn"]
pub(super) struct Simulation<'a>(&'a Counts);

impl Future for Simulation<'_> {
    type Output = ();

    fn poll(self: Pin<&mut Self>, _: &mut Context<'_>) -> Poll<()> {
        let counts = self.0;
        let allowed = counts.allowed.load(Ordering::Relaxed);
        if allowed == 0 {
            // No waker is kept: the next step polls the search again.
            return Poll::Pending;
        }
        counts.allowed.store(allowed - 1, Ordering::Relaxed);
        counts.done.fetch_add(1, Ordering::Relaxed);
        Poll::Ready(())
    }
}

/// How far a search has got.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Simulations run so far.
    pub simulations: usize,
    /// The search's estimate of the simulations it will run in all, never below
    /// `simulations`; exact once it is finished. It is refined as the search learns how many
    /// candidates it has, so it may move either way.
    pub planned: usize,
    /// The search has its answer.
    pub finished: bool,
}

/// A search in progress, advanced by [`Thinking::step`]: made by [`Thinking::decide`],
/// [`Thinking::plan`] or [`Thinking::suggest`]. Its answer depends only on what it was asked,
/// never on how it is stepped.
pub struct Thinking<T> {
    search: Option<Pin<Box<dyn Future<Output = T> + Send>>>,
    answer: Option<T>,
    meter: Meter,
    /// The largest fraction reported, so that a progress bar never goes back.
    shown: f64,
}

impl<T> std::fmt::Debug for Thinking<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Thinking")
            .field("progress", &self.progress())
            .finish_non_exhaustive()
    }
}

impl<T> Thinking<T> {
    /// A search made by `start` from the meter it must count its simulations on.
    pub(super) fn start<S>(start: impl FnOnce(Meter) -> S) -> Thinking<T>
    where
        S: Future<Output = T> + Send + 'static,
    {
        let meter = Meter::default();
        Thinking {
            search: Some(Box::pin(start(meter.clone()))),
            answer: None,
            meter,
            shown: 0.0,
        }
    }

    /// Runs at most `simulations` more simulations (0 only does the bookkeeping up to the
    /// next one) and returns the answer once the search is finished, on this call and every
    /// later one.
    pub fn step(&mut self, simulations: usize) -> Poll<&T> {
        if let Some(search) = self.search.as_mut() {
            self.meter.allow(simulations);
            if let Poll::Ready(answer) = search
                .as_mut()
                .poll(&mut Context::from_waker(Waker::noop()))
            {
                self.answer = Some(answer);
                // The search's state is no longer needed: free it now, not when dropped.
                self.search = None;
            }
            self.meter.allow(0);
        }
        let fraction = self.progress().fraction();
        self.shown = self.shown.max(fraction);
        match &self.answer {
            Some(answer) => Poll::Ready(answer),
            None => Poll::Pending,
        }
    }

    /// Runs the search to its end and returns its answer.
    pub fn finish(mut self) -> T {
        loop {
            if self.step(usize::MAX).is_ready() {
                if let Some(answer) = self.answer.take() {
                    return answer;
                }
            }
        }
    }

    /// Simulations run and planned.
    pub fn progress(&self) -> Progress {
        let simulations = self.meter.done();
        let finished = self.answer.is_some();
        Progress {
            simulations,
            planned: if finished {
                simulations
            } else {
                self.meter.planned().max(simulations)
            },
            finished,
        }
    }

    /// The share of the work done, 0 to 1, for a progress bar: it never decreases from one
    /// step to the next and is 1 exactly when the search is finished.
    pub fn fraction(&self) -> f64 {
        if self.answer.is_some() {
            1.0
        } else {
            self.shown
        }
    }
}

impl Progress {
    /// Simulations run over simulations planned: 0 to 1, and 1 only when finished.
    pub fn fraction(&self) -> f64 {
        if self.finished {
            1.0
        } else if self.planned == 0 {
            0.0
        } else {
            // Below 1 while any work may remain, however good the estimate was.
            (self.simulations as f64 / self.planned as f64).min(0.99)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A search of `n` simulations that expects them all from the start.
    fn counting(n: usize) -> Thinking<usize> {
        Thinking::start(move |meter| async move {
            meter.expect(n);
            for _ in 0..n {
                meter.simulation().await;
            }
            meter.done()
        })
    }

    #[test]
    fn a_step_runs_at_most_its_allowance_and_the_answer_stays() {
        let mut thinking = counting(10);
        assert!(thinking.step(3).is_pending());
        assert_eq!(thinking.progress().simulations, 3);
        assert!(thinking.step(0).is_pending(), "no simulation allowed");
        assert_eq!(thinking.progress().simulations, 3);
        assert!(thinking.step(6).is_pending());
        assert_eq!(thinking.fraction(), 0.9);
        assert_eq!(thinking.step(5), Poll::Ready(&10), "one left to run");
        assert_eq!(thinking.step(5), Poll::Ready(&10), "and it stays");
        let progress = thinking.progress();
        assert_eq!((progress.simulations, progress.planned), (10, 10));
        assert!(progress.finished && thinking.fraction() == 1.0);
    }

    #[test]
    fn the_fraction_never_goes_back_when_the_estimate_grows() {
        let mut thinking = Thinking::start(|meter| async move {
            meter.expect(4);
            for k in 0..8 {
                if k == 3 {
                    // Halfway through the first estimate, the search finds it has more to do.
                    meter.expect(100);
                }
                meter.simulation().await;
            }
        });
        assert!(thinking.step(2).is_pending());
        assert_eq!(thinking.fraction(), 0.5);
        assert!(thinking.step(1).is_pending());
        assert_eq!(
            thinking.fraction(),
            0.5,
            "3 of 103 is less than shown before"
        );
        assert!(thinking.progress().fraction() < 0.5);
        assert!(thinking.step(100).is_ready());
        assert_eq!(thinking.fraction(), 1.0);
    }

    #[test]
    fn finish_runs_to_the_end_and_a_search_can_be_sent() {
        fn sendable<T: Send>(t: T) -> T {
            t
        }
        assert_eq!(sendable(counting(1000)).finish(), 1000);
    }
}
