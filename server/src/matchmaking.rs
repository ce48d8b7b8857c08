//! Quick match as pure state: one queue per variant and settings, players paired by rating
//! in a band that widens the longer they wait. The hub feeds it joins, leaves and `now`, and
//! opens a room for each pair it returns; it never reads a clock or a socket.
//!
//! Two players from the same source address (an IPv4 address, an IPv6 /64) are never
//! paired: one person cannot farm a rating by playing a second key of their own.

use std::net::IpAddr;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::PlayerKey;
use breakshot_shared::rules::{Settings, Variant};

use crate::output::ConnId;

/// How far apart two ratings may be when both players have only just joined ...
pub const BAND_START: f64 = 100.0;
/// ... how much further apart for every second the newer of the two has waited ...
pub const BAND_GROWTH_PER_S: f64 = 10.0;
/// ... and the furthest it goes (beyond it a player waits, until the queue times out).
pub const BAND_MAX: f64 = 800.0;

/// One player waiting.
#[derive(Clone, Debug)]
pub struct Waiting {
    /// Their connection.
    pub conn: ConnId,
    /// Who they are.
    pub key: PlayerKey,
    /// Their source address (per-address key).
    pub source: IpAddr,
    /// Their display name.
    pub name: String,
    /// Their rating now.
    pub rating: f64,
    /// When they joined the queue.
    pub since: Instant,
}

/// Two players to seat in a new room: `a` takes seat A (the one who waited longer).
#[derive(Clone, Debug)]
pub struct Match {
    /// The game they play.
    pub variant: Variant,
    /// Its settings.
    pub mode: Settings,
    /// Seat A's player.
    pub a: Waiting,
    /// Seat B's player.
    pub b: Waiting,
}

/// Why a join was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// This connection (or this player's key) is already queued.
    AlreadyQueued,
}

struct Queue {
    variant: Variant,
    mode: Settings,
    /// In the order they joined.
    players: Vec<Waiting>,
}

/// Every quick-match queue of one server.
pub struct Queues {
    queues: Vec<Queue>,
    timeout: Duration,
    /// Whether two players of one source address may be paired (load tests only).
    one_address: bool,
    /// When pairs were last looked for: the bands have widened a second later.
    checked: Option<Instant>,
}

/// The widest gap in rating a player who has waited `waited` accepts.
pub fn band(waited: Duration) -> f64 {
    (BAND_START + BAND_GROWTH_PER_S * waited.as_secs_f64()).min(BAND_MAX)
}

impl Queues {
    /// No one waiting; a player waits at most `timeout`; with `one_address`, players of one
    /// source address may be paired (for load tests from one machine only).
    pub fn new(timeout: Duration, one_address: bool) -> Queues {
        Queues {
            queues: Vec::new(),
            timeout,
            one_address,
            checked: None,
        }
    }

    /// Queues `who` for `variant` and `mode`; returns how many wait in that queue now.
    pub fn join(
        &mut self,
        variant: Variant,
        mode: Settings,
        who: Waiting,
    ) -> Result<usize, Refusal> {
        let taken = self
            .queues
            .iter()
            .flat_map(|q| &q.players)
            .any(|w| w.conn == who.conn || w.key == who.key);
        if taken {
            return Err(Refusal::AlreadyQueued);
        }
        let at = match self
            .queues
            .iter()
            .position(|q| q.variant == variant && q.mode == mode)
        {
            Some(at) => at,
            None => {
                self.queues.push(Queue {
                    variant,
                    mode,
                    players: Vec::new(),
                });
                self.queues.len() - 1
            }
        };
        let queue = &mut self.queues[at];
        queue.players.push(who);
        Ok(queue.players.len())
    }

    /// Takes `conn` out of its queue (it left, or disconnected); whether it was queued.
    pub fn leave(&mut self, conn: ConnId) -> bool {
        let mut found = false;
        for q in &mut self.queues {
            let before = q.players.len();
            q.players.retain(|w| w.conn != conn);
            found |= q.players.len() != before;
        }
        self.queues.retain(|q| !q.players.is_empty());
        found
    }

    /// Whether `conn` waits in a queue.
    pub fn is_queued(&self, conn: ConnId) -> bool {
        self.queues
            .iter()
            .any(|q| q.players.iter().any(|w| w.conn == conn))
    }

    /// Pairs every two players whose ratings are close enough for both, the longest waiting
    /// first, and takes them out of the queue.
    pub fn pairs(&mut self, now: Instant) -> Vec<Match> {
        self.checked = Some(now);
        let mut found = Vec::new();
        for q in &mut self.queues {
            let mut i = 0;
            while i < q.players.len() {
                let a = &q.players[i];
                let one_address = self.one_address;
                let partner = q.players.iter().enumerate().skip(i + 1).find(|(_, b)| {
                    let gap = (a.rating - b.rating).abs();
                    (one_address || b.source != a.source)
                        && gap <= band(now.saturating_duration_since(a.since))
                        && gap <= band(now.saturating_duration_since(b.since))
                });
                match partner.map(|(j, _)| j) {
                    Some(j) => {
                        let b = q.players.remove(j);
                        let a = q.players.remove(i);
                        found.push(Match {
                            variant: q.variant,
                            mode: q.mode,
                            a,
                            b,
                        });
                    }
                    None => i += 1,
                }
            }
        }
        self.queues.retain(|q| !q.players.is_empty());
        found
    }

    /// Takes out everyone who has waited the timeout by `now`, and returns them.
    pub fn expire(&mut self, now: Instant) -> Vec<Waiting> {
        let timeout = self.timeout;
        let mut out = Vec::new();
        for q in &mut self.queues {
            let (gone, kept): (Vec<_>, Vec<_>) = q
                .players
                .drain(..)
                .partition(|w| now.saturating_duration_since(w.since) >= timeout);
            q.players = kept;
            out.extend(gone);
        }
        self.queues.retain(|q| !q.players.is_empty());
        out
    }

    /// When something is next due: the band of a queue with two or more players widens
    /// every second after pairs were last looked for; a lone player only times out.
    pub fn next_deadline(&self) -> Option<Instant> {
        let timeouts = self
            .queues
            .iter()
            .flat_map(|q| &q.players)
            .map(|w| w.since + self.timeout);
        let widen = self
            .queues
            .iter()
            .any(|q| q.players.len() >= 2)
            .then_some(self.checked)
            .flatten()
            .map(|t| t + Duration::from_secs(1));
        timeouts.chain(widen).min()
    }

    /// Players waiting in each queue, for the operator's metrics.
    pub fn lengths(&self) -> Vec<(Variant, Settings, usize)> {
        self.queues
            .iter()
            .map(|q| (q.variant, q.mode, q.players.len()))
            .collect()
    }

    /// Players waiting in all queues.
    pub fn waiting(&self) -> usize {
        self.queues.iter().map(|q| q.players.len()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::rules::EightBallRules;

    fn who(conn: ConnId, rating: f64, source: u8, since: Instant) -> Waiting {
        Waiting {
            conn,
            key: PlayerKey([conn as u8; 32]),
            source: IpAddr::from([10, 0, 0, source]),
            name: format!("p{conn}"),
            rating,
            since,
        }
    }

    /// Empty queues whose players wait at most `longest`, the 8-ball game and settings to
    /// join them with, and the time they start at.
    fn eight_ball_queues(longest: Duration) -> (Queues, Variant, Settings, Instant) {
        let queues = Queues::new(longest, false);
        let (v, m) = (Variant::EightBall(EightBallRules::Wpa), Settings::online());
        (queues, v, m, Instant::now())
    }

    #[test]
    fn close_ratings_pair_at_once_far_ones_once_the_band_has_widened() {
        let (mut q, v, m, t0) = eight_ball_queues(Duration::from_secs(180));
        q.join(v, m, who(1, 1500.0, 1, t0)).unwrap();
        q.join(v, m, who(2, 1900.0, 2, t0)).unwrap();
        assert_eq!(q.join(v, m, who(3, 1550.0, 3, t0)), Ok(3));
        let first = q.pairs(t0);
        assert_eq!(first.len(), 1);
        assert_eq!((first[0].a.conn, first[0].b.conn), (1, 3));
        // 400 apart: the band reaches it after 30 s of waiting, not before.
        let t1 = t0 + Duration::from_secs(3);
        q.join(v, m, who(4, 2300.0, 4, t1)).unwrap();
        assert!(q.pairs(t0 + Duration::from_secs(29)).is_empty());
        let later = q.pairs(t0 + Duration::from_secs(33));
        assert_eq!(later.len(), 1, "the newer player's band is the limit");
        assert_eq!((later[0].a.conn, later[0].b.conn), (2, 4));
        assert_eq!(q.waiting(), 0);
    }

    #[test]
    fn other_settings_one_address_and_a_second_join_never_pair() {
        let (mut q, v, m, t0) = eight_ball_queues(Duration::from_secs(180));
        q.join(v, m, who(1, 1500.0, 1, t0)).unwrap();
        q.join(Variant::NineBall, m, who(2, 1500.0, 2, t0)).unwrap();
        // A second key from the first player's address: not their opponent.
        q.join(v, m, who(3, 1500.0, 1, t0)).unwrap();
        assert_eq!(
            q.join(v, m, who(1, 1500.0, 1, t0)),
            Err(Refusal::AlreadyQueued)
        );
        assert!(q.pairs(t0 + Duration::from_secs(100)).is_empty());
        assert_eq!(q.lengths().len(), 2);
    }

    #[test]
    fn leaving_and_waiting_too_long_take_a_player_out() {
        let (mut q, v, m, t0) = eight_ball_queues(Duration::from_secs(10));
        q.join(v, m, who(1, 1500.0, 1, t0)).unwrap();
        q.join(v, m, who(2, 1500.0, 1, t0 + Duration::from_secs(5)))
            .unwrap();
        assert!(q.pairs(t0).is_empty(), "one address");
        assert_eq!(q.next_deadline(), Some(t0 + Duration::from_secs(1)));
        assert!(q.leave(1));
        assert!(!q.leave(1));
        assert_eq!(
            q.next_deadline(),
            Some(t0 + Duration::from_secs(15)),
            "alone: only the timeout"
        );
        assert!(q.expire(t0 + Duration::from_secs(14)).is_empty());
        let gone = q.expire(t0 + Duration::from_secs(15));
        assert_eq!(gone.len(), 1);
        assert_eq!(q.waiting(), 0);
        assert_eq!(q.next_deadline(), None);
    }

    #[test]
    fn a_storm_of_joins_and_leaves_leaves_nothing_behind() {
        let (mut q, v, m, t0) = eight_ball_queues(Duration::from_secs(180));
        for n in 0..10_000u64 {
            let _ = q.join(v, m, who(n % 50, 1500.0, (n % 7) as u8, t0));
            if n % 3 == 0 {
                q.leave(n % 50);
            }
        }
        assert!(q.waiting() <= 50);
        for n in 0..50 {
            q.leave(n);
        }
        assert_eq!(q.waiting(), 0);
        assert!(q.lengths().is_empty());
    }
}
