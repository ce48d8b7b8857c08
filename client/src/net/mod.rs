//! Networking for clients and bots: connecting by invite with a pinned certificate, the
//! framed message stream, the local game mirror that predicts and checks every shot, a polling
//! session for frame loops, and fetching a stored game's record.

mod channel;
mod client;
mod computer;
#[cfg(feature = "host")]
mod embedded;
// Without the embedded server, the helpers it shares with this module have no caller.
#[cfg_attr(not(feature = "host"), allow(dead_code))]
mod host;
mod link;
mod pinned;
mod records;
mod seats;
mod session;

pub use channel::{endpoint, Channel, NetError, Reader, Writer, ATTEMPT_LIMIT};
pub use client::{Client, ClientEvent, Reconnect};
pub use computer::SeatedComputer;
#[cfg(feature = "host")]
pub use embedded::{EmbeddedServer, Host};
pub use host::{
    default_data_dir, names_wildcard, router_hint, HostError, HostOptions, ADDRESS_NOTE,
    DEFAULT_PORT,
};
pub use link::{NetLink, NoRoom};
pub use pinned::client_config;
pub use records::{
    fetch_game, fetch_game_blocking, fetch_record, fetch_record_blocking, FetchError,
    FetchedRecord, FETCH_TIMEOUT,
};
pub use seats::{hosted_from, Remembered, SeatStore};
pub use session::{Session, SessionEvent};

pub(crate) use link::command_message;
