//! A room's command lent out of the hub, so that the expensive part of a command (a shot's
//! simulation in `Game::apply`) runs beside other rooms instead of on the hub's thread.
//! The room travels with its work and comes back with the result; while it is away the hub
//! holds every event for it, so one room still sees its events one at a time, in order.

use std::fmt;
use std::time::Instant;

use breakshot_shared::protocol::{ClientMessage, RoomCode};

use crate::output::RoomOutput;
use crate::room::{Room, Who};

/// One message for one room, with the room itself.
pub struct RoomWork {
    room: Box<Room>,
    who: Who,
    msg: ClientMessage,
    /// When the message was read, for the server's time per command.
    pub read: Instant,
}

/// A room back from its work, to hand to [`crate::hub::Hub::returned`].
pub struct Returned(pub(crate) Box<Room>);

impl RoomWork {
    pub(crate) fn new(room: Box<Room>, who: Who, msg: ClientMessage, read: Instant) -> RoomWork {
        RoomWork {
            room,
            who,
            msg,
            read,
        }
    }

    /// The code of the room out on this work (for the tests' hook, and the log if it panics).
    pub fn room(&self) -> &RoomCode {
        self.room.code()
    }

    /// Runs the message through the room (pure; may take as long as a shot's simulation).
    /// The outputs go to the store and the connections before the room goes back to the
    /// hub, so the room's next outputs always follow these.
    pub fn run(self, now: Instant) -> (Vec<RoomOutput>, Returned) {
        let mut room = self.room;
        let out = room.handle(now, self.who, self.msg);
        (out, Returned(room))
    }
}

impl fmt::Debug for RoomWork {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RoomWork")
            .field("room", self.room.code())
            .field("who", &self.who)
            .field("msg", &self.msg)
            .finish()
    }
}

impl fmt::Debug for Returned {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("Returned").field(self.0.code()).finish()
    }
}
