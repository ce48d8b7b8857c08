//! Who gets a handshake: the connection and handshake counts, in total and per source
//! address, and the decision for each new connection attempt. One address may hold only a
//! share of the server's connections and of its handshakes in progress, so an address that
//! opens handshakes and never finishes them (a QUIC retry only makes it prove its address,
//! which any real host can) cannot fill the slots everyone else needs.
//!
//! [`Ledger`] is the pure bookkeeping; [`Gate`] shares it between the accept loop and the
//! connection tasks, and [`Ticket`] gives a slot back when its connection ends, however it
//! ends.

use std::collections::BTreeMap;
use std::net::IpAddr;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex, MutexGuard};

use crate::limits::Limits;
use crate::stats::Stats;

/// What to do with a connection attempt.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// Start its handshake.
    Admit,
    /// Ask it to prove its address first (a QUIC retry).
    Retry,
    /// Refuse it, for the reason given.
    Refuse(Refusal),
}

/// Why a connection attempt was refused, before any cryptography; each has its own counter in
/// [`Stats`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The server holds `max_connections`.
    Full,
    /// The address holds its share of the connections or of the handshakes in progress.
    AddressShare,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Counts {
    connections: usize,
    handshakes: usize,
}

/// Connections and handshakes in progress, in total and per source.
#[derive(Debug, Default)]
pub struct Ledger {
    total: Counts,
    sources: BTreeMap<IpAddr, Counts>,
}

impl Ledger {
    /// The decision for an attempt from `source`; `validated` says whether it has proven its
    /// address (answered a retry).
    pub fn decide(&self, limits: &Limits, source: IpAddr, validated: bool) -> Decision {
        if self.total.connections >= limits.max_connections {
            return Decision::Refuse(Refusal::Full);
        }
        let mine = self.sources.get(&source).copied().unwrap_or_default();
        if mine.connections >= limits.connections_per_address()
            || mine.handshakes >= limits.handshakes_per_address()
        {
            return Decision::Refuse(Refusal::AddressShare);
        }
        if self.total.handshakes >= limits.max_handshakes && !validated {
            return Decision::Retry;
        }
        Decision::Admit
    }

    /// An admitted attempt starts its handshake.
    pub fn opened(&mut self, source: IpAddr) {
        let mine = self.sources.entry(source).or_default();
        for c in [&mut self.total, mine] {
            c.connections += 1;
            c.handshakes += 1;
        }
    }

    /// Its handshake ended (connected or failed).
    pub fn handshake_over(&mut self, source: IpAddr) {
        self.total.handshakes = self.total.handshakes.saturating_sub(1);
        if let Some(mine) = self.sources.get_mut(&source) {
            mine.handshakes = mine.handshakes.saturating_sub(1);
        }
    }

    /// Its connection ended.
    pub fn closed(&mut self, source: IpAddr) {
        self.total.connections = self.total.connections.saturating_sub(1);
        if let Some(mine) = self.sources.get_mut(&source) {
            mine.connections = mine.connections.saturating_sub(1);
            if mine.connections == 0 {
                self.sources.remove(&source);
            }
        }
    }

    /// Connections open, counting those still in their handshake.
    pub fn connections(&self) -> usize {
        self.total.connections
    }

    /// Handshakes in progress: admitted, and neither connected nor failed yet.
    pub fn handshakes(&self) -> usize {
        self.total.handshakes
    }

    /// Addresses with a connection open (the map never holds more).
    pub fn sources(&self) -> usize {
        self.sources.len()
    }
}

/// The ledger shared by the accept loop and the connection tasks, mirrored into [`Stats`].
#[derive(Clone)]
pub struct Gate {
    ledger: Arc<Mutex<Ledger>>,
    stats: Arc<Stats>,
}

impl Gate {
    /// An empty ledger whose totals are mirrored into `stats` (`connections`, `handshaking`).
    pub fn new(stats: Arc<Stats>) -> Gate {
        Gate {
            ledger: Arc::default(),
            stats,
        }
    }

    fn lock(&self) -> MutexGuard<'_, Ledger> {
        // The ledger holds plain counts, valid even if a holder panicked.
        self.ledger.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn publish(&self, ledger: &Ledger) {
        self.stats
            .connections
            .store(ledger.connections(), Ordering::Relaxed);
        self.stats
            .handshaking
            .store(ledger.handshakes(), Ordering::Relaxed);
    }

    /// Decides on an attempt; an admitted one holds its slots until its ticket is dropped.
    pub fn admit(&self, limits: &Limits, source: IpAddr, validated: bool) -> Answer {
        let mut ledger = self.lock();
        match ledger.decide(limits, source, validated) {
            Decision::Admit => {
                ledger.opened(source);
                self.publish(&ledger);
                Answer::Admitted(Ticket {
                    gate: self.clone(),
                    source,
                    handshaking: true,
                })
            }
            Decision::Retry => Answer::Retry,
            Decision::Refuse(why) => Answer::Refused(why),
        }
    }
}

/// The gate's answer to an attempt.
pub enum Answer {
    /// Start its handshake; the ticket holds its slots.
    Admitted(Ticket),
    /// Send it a QUIC retry: it must prove its address first.
    Retry,
    /// Refuse it, for this reason.
    Refused(Refusal),
}

/// One admitted connection's slots: its handshake's until [`Ticket::handshake_over`], its
/// connection's until dropped.
pub struct Ticket {
    gate: Gate,
    source: IpAddr,
    handshaking: bool,
}

impl Ticket {
    /// The handshake is over (whether or not it succeeded).
    pub fn handshake_over(&mut self) {
        if std::mem::take(&mut self.handshaking) {
            let mut ledger = self.gate.lock();
            ledger.handshake_over(self.source);
            self.gate.publish(&ledger);
        }
    }
}

impl Drop for Ticket {
    fn drop(&mut self) {
        self.handshake_over();
        let mut ledger = self.gate.lock();
        ledger.closed(self.source);
        self.gate.publish(&ledger);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> Limits {
        Limits {
            max_connections: 64,
            max_handshakes: 32,
            address_share: 8,
            ..Limits::default()
        }
    }

    fn ip(last: u8) -> IpAddr {
        IpAddr::from([192, 0, 2, last])
    }

    /// A connection from `source`, which must be admitted, opened (still in its handshake).
    fn open(ledger: &mut Ledger, limits: &Limits, source: IpAddr) {
        assert_eq!(
            ledger.decide(limits, source, false),
            Decision::Admit,
            "{source}"
        );
        ledger.opened(source);
    }

    #[test]
    fn one_address_gets_only_its_share_of_handshakes_and_others_still_get_in() {
        let (limits, mut ledger) = (limits(), Ledger::default());
        let share = limits.handshakes_per_address();
        assert_eq!(share, 4);
        for _ in 0..share {
            open(&mut ledger, &limits, ip(1));
        }
        assert_eq!(
            ledger.decide(&limits, ip(1), true),
            Decision::Refuse(Refusal::AddressShare)
        );
        assert_eq!(ledger.decide(&limits, ip(2), false), Decision::Admit);
        // A finished handshake frees its handshake slot, not its connection slot.
        ledger.handshake_over(ip(1));
        assert_eq!(ledger.decide(&limits, ip(1), false), Decision::Admit);
    }

    #[test]
    fn one_address_gets_only_its_share_of_connections() {
        let (limits, mut ledger) = (limits(), Ledger::default());
        for _ in 0..limits.connections_per_address() {
            open(&mut ledger, &limits, ip(1));
            ledger.handshake_over(ip(1));
        }
        assert_eq!(
            ledger.decide(&limits, ip(1), false),
            Decision::Refuse(Refusal::AddressShare)
        );
        ledger.closed(ip(1));
        assert_eq!(ledger.decide(&limits, ip(1), false), Decision::Admit);
    }

    #[test]
    fn the_totals_still_bind_many_addresses() {
        let (limits, mut ledger) = (limits(), Ledger::default());
        for i in 0..limits.max_handshakes {
            open(&mut ledger, &limits, ip(u8::try_from(i).unwrap()));
        }
        // Handshakes are at their total: unproven addresses are asked to prove themselves.
        assert_eq!(ledger.decide(&limits, ip(200), false), Decision::Retry);
        assert_eq!(ledger.decide(&limits, ip(200), true), Decision::Admit);
        for i in 0..limits.max_handshakes {
            ledger.handshake_over(ip(u8::try_from(i).unwrap()));
        }
        for i in limits.max_handshakes..limits.max_connections {
            let source = ip(u8::try_from(i).unwrap());
            ledger.opened(source);
            ledger.handshake_over(source);
        }
        assert_eq!(
            ledger.decide(&limits, ip(250), true),
            Decision::Refuse(Refusal::Full)
        );
        assert_eq!(ledger.sources(), limits.max_connections);
        for i in 0..limits.max_connections {
            ledger.closed(ip(u8::try_from(i).unwrap()));
        }
        assert_eq!(ledger.sources(), 0);
        assert_eq!(ledger.connections(), 0);
    }

    #[test]
    fn a_ticket_gives_its_slots_back_however_its_connection_ends() {
        let stats = Arc::new(Stats::default());
        let gate = Gate::new(stats.clone());
        let limits = limits();
        let admit = || match gate.admit(&limits, ip(1), false) {
            Answer::Admitted(ticket) => ticket,
            _ => panic!("not admitted"),
        };
        let mut connected = admit();
        let failed = admit();
        assert_eq!(Stats::get(&stats.handshaking), 2);
        connected.handshake_over();
        assert_eq!(Stats::get(&stats.handshaking), 1);
        assert_eq!(Stats::get(&stats.connections), 2);
        drop(failed);
        drop(connected);
        assert_eq!(Stats::get(&stats.handshaking), 0);
        assert_eq!(Stats::get(&stats.connections), 0);
        assert_eq!(gate.lock().sources(), 0);
    }
}
