//! Networking for clients and bots: connecting by invite with a pinned certificate, the
//! framed message stream, the local game mirror that predicts and checks every shot, and a
//! polling session for frame loops.

pub mod connection;
pub mod host;
pub mod link;
pub mod mirror;
pub mod pinned;
pub mod session;

pub use connection::{endpoint, Connection, NetError, Reader, Writer};
pub use host::{EmbeddedServer, Host, HostError, HostOptions};
pub use link::{NetLink, NoRoom};
pub use mirror::{Check, Mirror};
pub use session::{Session, SessionEvent};
