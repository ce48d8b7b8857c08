//! When the hub thread must next wake for a deadline (a shot clock, the end of a reconnect
//! window, a quick-match queue's band): the soonest of every room's. Finding it is a pass
//! over every room, and the hub handles thousands of messages a second among thousands of
//! rooms, so it looks again at most once per [`LOOK_EVERY`] and only after something may have
//! moved a deadline. A deadline set meanwhile is met that much late at most; deadlines here
//! are seconds long.

use std::time::{Duration, Instant};

/// How long a deadline found may be kept while the rooms change.
pub const LOOK_EVERY: Duration = Duration::from_millis(5);

/// The soonest deadline, as last found.
#[derive(Debug, Default)]
pub struct Soonest {
    /// The deadline found, and when it was looked for.
    found: Option<(Option<Instant>, Instant)>,
    /// Something happened since that may have moved a deadline.
    changed: bool,
}

impl Soonest {
    /// Something happened that may have moved a deadline (a message handled, a room back
    /// from its work, a tick).
    pub fn changed(&mut self) {
        self.changed = true;
    }

    /// The soonest deadline at `now`: the one found last, unless it is due, it may have moved
    /// and was found [`LOOK_EVERY`] ago or more, or none was ever found; then `look`'s.
    pub fn at(&mut self, now: Instant, look: impl FnOnce() -> Option<Instant>) -> Option<Instant> {
        let stale = match self.found {
            None => true,
            Some((due, looked)) => {
                due.is_some_and(|d| d <= now)
                    || (self.changed && now.saturating_duration_since(looked) >= LOOK_EVERY)
            }
        };
        if stale {
            self.found = Some((look(), now));
            self.changed = false;
        }
        self.found.and_then(|(due, _)| due)
    }

    /// How long the hub may sleep at `now` before it must look again, at most `cap`: until
    /// the deadline found, and, while a deadline may have moved, no longer than until the
    /// next look.
    pub fn wait(
        &mut self,
        now: Instant,
        cap: Duration,
        look: impl FnOnce() -> Option<Instant>,
    ) -> Duration {
        let due = self.at(now, look);
        let mut wait = due
            .map_or(cap, |d| d.saturating_duration_since(now))
            .min(cap);
        if self.changed {
            if let Some((_, looked)) = self.found {
                wait = wait.min((looked + LOOK_EVERY).saturating_duration_since(now));
            }
        }
        wait
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn a_deadline_found_is_kept_while_nothing_changes() {
        let t0 = Instant::now();
        let looks = Cell::new(0);
        let look = |d: Option<Instant>| {
            looks.set(looks.get() + 1);
            d
        };
        let mut s = Soonest::default();
        let far = t0 + Duration::from_secs(10);
        assert_eq!(s.at(t0, || look(Some(far))), Some(far));
        // However long after, nothing changed: no look, and the hub sleeps to the cap.
        let later = t0 + Duration::from_secs(1);
        assert_eq!(s.at(later, || look(None)), Some(far));
        assert_eq!(
            s.wait(later, Duration::from_millis(500), || look(None)),
            Duration::from_millis(500)
        );
        assert_eq!(looks.get(), 1);
    }

    #[test]
    fn a_changed_deadline_is_looked_for_again_after_the_look_is_old() {
        let t0 = Instant::now();
        let mut s = Soonest::default();
        let far = t0 + Duration::from_secs(10);
        let near = t0 + Duration::from_secs(2);
        assert_eq!(s.at(t0, || Some(far)), Some(far));
        s.changed();
        // Within LOOK_EVERY the old one stands, and the hub sleeps only until it is stale.
        let early = t0 + LOOK_EVERY / 2;
        assert_eq!(s.at(early, || Some(near)), Some(far));
        assert_eq!(
            s.wait(early, Duration::from_secs(1), || Some(near)),
            LOOK_EVERY / 2
        );
        // Past it the new one is found, and the hub may sleep until it (at most the cap).
        let later = t0 + LOOK_EVERY;
        assert_eq!(s.at(later, || Some(near)), Some(near));
        assert_eq!(
            s.wait(later, Duration::from_secs(1), || Some(far)),
            Duration::from_secs(1)
        );
    }

    #[test]
    fn a_deadline_that_passed_is_looked_for_again_at_once() {
        let t0 = Instant::now();
        let mut s = Soonest::default();
        let d = t0 + Duration::from_millis(1);
        assert_eq!(s.at(t0, || Some(d)), Some(d));
        let next = t0 + Duration::from_secs(3);
        assert_eq!(s.at(d, || Some(next)), Some(next));
        assert_eq!(s.at(d, || None), Some(next));
    }
}
