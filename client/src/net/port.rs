//! What a game screen's [`NetLink`](super::NetLink) talks through: a [`Port`] to one server.
//! Natively that is a [`Session`](super::Session), the client on a thread of its own; in the
//! browser it is a [`PolledSession`], the player core advanced on the frame's own turn.

use std::time::Duration;

use breakshot_shared::protocol::{ClientMessage, ServerMessage};

use super::player::{Entry, PlayerEvent, Seating};
use super::polled::{Polled, Transport};

/// What a session hears.
#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// The handshake succeeded.
    Connected,
    /// A message from the server.
    Message(ServerMessage),
    /// The seat remembered is gone (its token is stale, or its game ended while away).
    SeatGone,
    /// The connection of a seated player dropped; the session is connecting again to take
    /// the seat back (for as long as the server holds it).
    Reconnecting,
    /// The connection ended (or never started, or could not be restored), with the reason.
    Closed(String),
}

/// A connection to a server as a frame loop sees it: nothing blocks.
pub trait Port {
    /// Queues a message for the server. Returns false if the session has ended.
    fn send(&mut self, msg: ClientMessage) -> bool;
    /// Enters a room as `entry` says (the core carries out its fallbacks). Returns false if
    /// the session has ended.
    fn enter(&mut self, entry: Entry) -> bool;
    /// The next event, if one is waiting.
    fn try_recv(&mut self) -> Option<SessionEvent>;
    /// The seat, as it stood at the last event polled.
    fn seating(&self) -> &Seating;
}

/// A port chosen as the program runs (the lobby's, a `Session` natively or a
/// [`PolledSession`] in the page) is a port.
impl<P: Port + ?Sized> Port for Box<P> {
    fn send(&mut self, msg: ClientMessage) -> bool {
        (**self).send(msg)
    }

    fn enter(&mut self, entry: Entry) -> bool {
        (**self).enter(entry)
    }

    fn try_recv(&mut self) -> Option<SessionEvent> {
        (**self).try_recv()
    }

    fn seating(&self) -> &Seating {
        (**self).seating()
    }
}

/// A [`Port`] over the frame-polled driver: every [`Port::try_recv`] first advances the
/// core to the time `clock` tells.
pub struct PolledSession<T: Transport> {
    polled: Polled<T>,
    clock: fn() -> Duration,
    closed: bool,
}

impl<T: Transport> PolledSession<T> {
    /// A session over `polled`, on the time `clock` gives (the clock the core was made with).
    pub fn new(polled: Polled<T>, clock: fn() -> Duration) -> PolledSession<T> {
        PolledSession {
            polled,
            clock,
            closed: false,
        }
    }

    /// The driver under the session.
    pub fn polled(&self) -> &Polled<T> {
        &self.polled
    }
}

impl<T: Transport> Port for PolledSession<T> {
    fn send(&mut self, msg: ClientMessage) -> bool {
        // A message that cannot be sent was lost with the connection, as natively: the core
        // is reconnecting, or it has closed and says so.
        let _ = self.polled.send(&msg);
        !self.closed
    }

    fn enter(&mut self, entry: Entry) -> bool {
        self.polled.enter(entry);
        !self.closed
    }

    fn try_recv(&mut self) -> Option<SessionEvent> {
        self.polled.update((self.clock)());
        loop {
            let event = match self.polled.poll_event()? {
                PlayerEvent::Connected | PlayerEvent::Reconnected => SessionEvent::Connected,
                PlayerEvent::Message(msg) => SessionEvent::Message(msg),
                PlayerEvent::SeatGone => SessionEvent::SeatGone,
                PlayerEvent::Reconnecting(_) => SessionEvent::Reconnecting,
                PlayerEvent::Closed(e) => {
                    self.closed = true;
                    SessionEvent::Closed(e.to_string())
                }
                PlayerEvent::Seated(_) => continue,
            };
            return Some(event);
        }
    }

    fn seating(&self) -> &Seating {
        self.polled.seating()
    }
}
