//! Opening a connection: the invite's addresses tried in order (each but the last given
//! [`ATTEMPT_LIMIT`]), pass after pass with growing pauses, for as long as allowed. A server
//! that answers and refuses is final.

use std::time::Duration;

use super::{NetError, Reconnect, ATTEMPT_LIMIT};

/// Why a connection is being opened.
pub(super) enum Purpose {
    /// The first connection.
    First,
    /// To take the seat back after the connection dropped (why it dropped).
    Rejoin(String),
}

/// What to do after an attempt failed.
pub(super) enum Then {
    /// Try the next address now.
    Next,
    /// Wait for the pause before the next pass ([`Opening::timeout`]).
    Wait,
    /// Give up, with the reason that says most.
    GiveUp(NetError),
    /// No attempt was in progress: nothing to do.
    Nothing,
}

/// One opening in progress.
pub(super) struct Opening {
    purpose: Purpose,
    /// When the opening began, and how long it may go on.
    since: Duration,
    patience: Duration,
    /// The address each pass starts from, and how many of this pass have failed.
    start: usize,
    tried: usize,
    /// An attempt is in progress, and its transport is open (our handshake is under way).
    attempting: bool,
    open: bool,
    /// When the attempt in progress is given up (None: the last address of a pass, which
    /// is given the transport's own time).
    deadline: Option<Duration>,
    /// When the next pass begins, while pausing between passes.
    resume_at: Option<Duration>,
    pause: Duration,
    max_pause: Duration,
    /// The reason that says most of this pass's failures.
    failure: Option<NetError>,
}

impl Opening {
    pub(super) fn new(
        purpose: Purpose,
        start: usize,
        now: Duration,
        patience: Duration,
        policy: Reconnect,
    ) -> Opening {
        Opening {
            purpose,
            since: now,
            patience,
            start,
            tried: 0,
            attempting: false,
            open: false,
            deadline: None,
            resume_at: None,
            pause: policy.pause,
            max_pause: policy.max_pause,
            failure: None,
        }
    }

    pub(super) fn purpose(&self) -> &Purpose {
        &self.purpose
    }

    /// Waits `pause` before the first attempt.
    pub(super) fn pause_for(&mut self, pause: Duration, now: Duration) {
        self.resume_at = Some(now + pause);
    }

    /// True while the first attempt waits for a pause.
    pub(super) fn pauses_first(&self) -> bool {
        self.resume_at.is_some()
    }

    /// Starts the next attempt of the pass; returns its address's index among `n`.
    pub(super) fn start_attempt(&mut self, now: Duration, n: usize) -> usize {
        self.resume_at = None;
        self.attempting = true;
        self.open = false;
        self.deadline = (self.tried + 1 < n).then(|| now + ATTEMPT_LIMIT);
        self.attempt_at(n)
    }

    /// The address of the attempt in progress (or the next one).
    pub(super) fn attempt_at(&self, n: usize) -> usize {
        (self.start + self.tried) % n.max(1)
    }

    /// The transport of the attempt in progress is open; false if no attempt waited for it.
    pub(super) fn open(&mut self) -> bool {
        let fresh = self.attempting && !self.open;
        self.open |= fresh;
        fresh
    }

    /// True while our handshake is under way on an open transport.
    pub(super) fn is_open(&self) -> bool {
        self.attempting && self.open
    }

    /// When something is due: the attempt's deadline, or the end of the pause.
    pub(super) fn timeout(&self) -> Option<Duration> {
        if self.attempting {
            self.deadline
        } else {
            self.resume_at
        }
    }

    pub(super) fn attempt_overdue(&self, now: Duration) -> bool {
        self.attempting && self.deadline.is_some_and(|d| now >= d)
    }

    pub(super) fn pause_over(&self, now: Duration) -> bool {
        !self.attempting && self.resume_at.is_some_and(|r| now >= r)
    }

    /// The attempt in progress failed with `error`, at `now`, of `n` addresses.
    pub(super) fn failed(&mut self, error: NetError, now: Duration, n: usize) -> Then {
        if !self.attempting {
            return Then::Nothing;
        }
        self.attempting = false;
        self.open = false;
        self.deadline = None;
        // A refusal says more than a failure to connect elsewhere.
        match &self.failure {
            Some(f) if f.is_refusal() && !error.is_refusal() => {}
            _ => self.failure = Some(error),
        }
        self.tried += 1;
        if self.tried < n {
            return Then::Next;
        }
        self.tried = 0;
        let failure = self
            .failure
            .take()
            .unwrap_or_else(|| NetError::Connect("no address answered".into()));
        if failure.is_refusal() || now.saturating_sub(self.since) + self.pause > self.patience {
            return Then::GiveUp(failure);
        }
        self.resume_at = Some(now + self.pause);
        self.pause = (self.pause * 2).min(self.max_pause);
        Then::Wait
    }
}
