//! Live counters of a running server, cheap enough to keep always: what an operator (or a
//! test) reads to see that queues and connection counts stay bounded.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::timing::Histogram;

/// Live counters of a running server, shared by its threads ([`crate::Server::stats`]).
#[derive(Debug, Default)]
pub struct Stats {
    /// Connections open, counting those still in their handshake.
    pub connections: AtomicUsize,
    /// Connections still in their handshake.
    pub handshaking: AtomicUsize,
    /// Events waiting for the hub thread.
    pub hub_queue: AtomicUsize,
    /// The most events that have waited for the hub at once.
    pub hub_queue_peak: AtomicUsize,
    /// Rooms open (updated by the hub thread).
    pub rooms: AtomicUsize,
    /// Connection attempts refused at the connection limit.
    pub refused: AtomicUsize,
    /// Connection attempts refused because their address held its share.
    pub refused_address: AtomicUsize,
    /// Connection attempts asked to prove their address first.
    pub retried: AtomicUsize,
    /// Connections closed because they sent faster than the message limit.
    pub flooding: AtomicUsize,
    /// Connections closed because they did not read what they were sent.
    pub too_slow: AtomicUsize,
    /// The server's own time per applied command: from reading its frame to handing its
    /// (stored) result to the connections.
    pub command_time: Histogram,
    /// Time per durable store write (one group commit of every operation waiting).
    pub store_write_time: Histogram,
    /// The stages of a command's time, so that a slow tail is found where it is. From a
    /// message's first byte on its stream to the message decoded (the rest of its frame
    /// arriving, and the connection's turn on the runtime).
    pub read_time: Histogram,
    /// From a message's frame read to the hub thread taking it up (the hub's queue).
    pub hub_wait: Histogram,
    /// The hub thread's time on one message, with the rules and simulation of a room it
    /// runs itself.
    pub hub_time: Histogram,
    /// From a room lent out with a message to a worker thread starting on it.
    pub worker_wait: Histogram,
    /// A worker's time on one room's message: the rules and the simulation.
    pub worker_time: Histogram,
    /// From results handed to the writer thread to the writer taking them up (it may be
    /// committing earlier ones meanwhile).
    pub writer_wait: Histogram,
    /// From a message handed to its connection to its frame written on the stream (the
    /// connection's turn on the runtime, and QUIC's flow control for a slow reader).
    pub send_wait: Histogram,
    /// Rooms whose second seat nobody has taken yet (updated by the hub about once a second).
    pub rooms_waiting: AtomicUsize,
    /// Rooms with both players seated and the game not over (likewise).
    pub rooms_playing: AtomicUsize,
    /// Rooms whose game is over, kept for a rematch (likewise).
    pub rooms_over: AtomicUsize,
    /// Rooms refused because the server is draining.
    pub refused_draining: AtomicUsize,
    /// Whole HTTP request heads read on the web listener (for files, errors and WebSocket
    /// upgrades alike; a malformed or oversized head is not counted).
    pub web_requests: AtomicUsize,
    /// WebSockets whose Noise handshake succeeded, so that became game connections.
    pub web_sockets: AtomicUsize,
    /// WebSockets closed before the hub saw them: a failed or late Noise handshake, a text
    /// or oversized message.
    pub web_sockets_failed: AtomicUsize,
    /// WebTransport sessions that opened their stream, so that became game connections.
    pub webtransport_sessions: AtomicUsize,
    /// `h3` connections that did not become game connections: a failed HTTP/3 exchange,
    /// another path, or no stream in the open time.
    pub webtransport_refused: AtomicUsize,
    /// Players waiting for a quick match, by game (`eight_ball`, `nine_ball`,
    /// `three_cushion`, `snooker`), updated by the hub about once a second.
    pub queued: std::sync::Mutex<Vec<(&'static str, usize)>>,
    /// Rooms listed in the lobby (likewise).
    pub rooms_listed: AtomicUsize,
    /// Desyncs clients reported (`ReportDesync`), since the server started.
    pub desyncs_reported: AtomicUsize,
    /// Set to drain: no new rooms; the server stops once the last game has ended.
    draining: AtomicBool,
}

impl Stats {
    /// Reads one counter: a recent value, not synchronised with the others.
    pub fn get(counter: &AtomicUsize) -> usize {
        counter.load(Ordering::Relaxed)
    }

    /// Starts draining (idempotent): the hub opens no new room, readiness turns false, and
    /// the server stops once no room is left (or its drain time is up).
    pub fn start_drain(&self) {
        self.draining.store(true, Ordering::Relaxed);
    }

    /// Whether the server is draining.
    pub fn is_draining(&self) -> bool {
        self.draining.load(Ordering::Relaxed)
    }
}
