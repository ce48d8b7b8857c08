//! Networking for clients and bots: connecting by invite with a pinned certificate, the
//! framed message stream, the local game mirror that predicts and checks every shot, a polling
//! session for frame loops, and fetching a stored game's record.

pub mod channel;
pub mod client;
pub mod computer;
#[cfg(feature = "host")]
mod embedded;
pub mod host;
pub mod link;
pub mod name;
pub mod pinned;
pub mod records;
pub mod seats;
pub mod session;

pub use channel::{endpoint, Channel, NetError, Reader, Writer};
pub use client::{Client, ClientEvent, Reconnect};
pub use computer::SeatedComputer;
#[cfg(feature = "host")]
pub use embedded::{EmbeddedServer, Host};
pub use host::{HostError, HostOptions};
pub use link::{NetLink, NoRoom};
pub use name::player_name;
pub use records::{fetch_record, fetch_record_blocking, FetchError, FetchedRecord};
pub use seats::{Remembered, SeatStore};
pub use session::{Session, SessionEvent};
