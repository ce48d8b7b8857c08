//! Networking for the window, the bot and the tests: one player core without I/O
//! ([`PlayerCore`]: the handshake, the invite's addresses, entering a room, taking a seat
//! back, the one [`Seating`]) and its drivers: [`Client`] (quinn on tokio), [`Session`] (that
//! client on a thread of its own, for a frame loop) and [`Polled`] (any [`Transport`],
//! polled once a frame). Above them: the game screen's [`NetLink`], the remembered seats,
//! hosting, the computer seated in an online room, and fetching a stored game's record.

mod channel;
mod client;
#[cfg(feature = "host")]
mod embedded;
mod error;
mod player;
mod seated_computer;
// Without the embedded server, the helpers it shares with this module have no caller.
#[cfg_attr(not(feature = "host"), allow(dead_code))]
mod host;
mod net_link;
mod pinned;
mod polled;
mod records;
mod seat_player;
mod seats;
mod session;

pub use channel::{endpoint, Channel};
pub use client::{Client, ClientEvent};
#[cfg(feature = "host")]
pub use embedded::{EmbeddedServer, Host};
pub use error::NetError;
pub use host::{
    default_data_dir, names_wildcard, router_hint, HostError, HostOptions, ADDRESS_NOTE,
    DEFAULT_PORT,
};
pub use net_link::{NetLink, NoRoom};
pub use pinned::client_config;
pub use player::{Action, Entry, PlayerCore, PlayerEvent, Reconnect, Seating, ATTEMPT_LIMIT};
pub use polled::{MemoryServer, MemoryTransport, Polled, Transport, TransportEvent};
pub use records::{
    fetch_game, fetch_game_blocking, fetch_record, FetchError, FetchedRecord, FETCH_TIMEOUT,
};
pub use seat_player::RETRY_FOR;
pub(crate) use seat_player::{Entrance, PlayerResult, SeatPlayer};
pub use seated_computer::SeatedComputer;
pub use seats::{hosted_from, Remembered, SeatStore};
pub use session::{Session, SessionEvent};

pub(crate) use net_link::command_message;
