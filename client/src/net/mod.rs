//! Networking for the window, the bot and the tests: one player core without I/O
//! ([`PlayerCore`]: the handshake, the invite's addresses, entering a room, taking a seat
//! back, the one [`Seating`]) and its drivers: [`Client`] (quinn on tokio), [`Session`] (that
//! client on a thread of its own, for a frame loop) and [`Polled`] (any [`Transport`],
//! polled once a frame). Above them: the game screen's [`NetLink`], the remembered seats,
//! hosting, the computer seated in an online room, and fetching a stored game's record.

#[cfg(not(target_arch = "wasm32"))]
mod background;
#[cfg(not(target_arch = "wasm32"))]
mod channel;
#[cfg(not(target_arch = "wasm32"))]
mod client;
#[cfg(all(feature = "host", not(target_arch = "wasm32")))]
mod embedded;
mod error;
mod player;
#[cfg(not(target_arch = "wasm32"))]
mod seated_computer;
// Without the embedded server, the helpers it shares with this module have no caller.
#[cfg_attr(any(not(feature = "host"), target_arch = "wasm32"), allow(dead_code))]
mod host;
mod keys;
mod net_link;
pub mod noise;
#[cfg(target_arch = "wasm32")]
pub mod page;
#[cfg(not(target_arch = "wasm32"))]
mod pinned;
mod polled;
mod port;
#[cfg(not(target_arch = "wasm32"))]
mod progress;
mod record_answer;
#[cfg(not(target_arch = "wasm32"))]
mod records;
#[cfg(not(target_arch = "wasm32"))]
mod seat_player;
mod seats;
#[cfg(not(target_arch = "wasm32"))]
mod session;
mod web_way;

#[cfg(not(target_arch = "wasm32"))]
pub use channel::{endpoint, shared_endpoint, Channel};
#[cfg(not(target_arch = "wasm32"))]
pub use client::{Client, ClientEvent};
#[cfg(all(feature = "host", not(target_arch = "wasm32")))]
pub use embedded::{EmbeddedServer, Host};
pub use error::NetError;
pub use host::{
    default_data_dir, names_wildcard, router_hint, web_bundle, HostError, HostOptions,
    ADDRESS_NOTE, DEFAULT_PORT, WEB_ENV,
};
pub use keys::{for_connection, fresh as fresh_identity, use_identity};
pub use net_link::{NetLink, NoRoom};
#[cfg(not(target_arch = "wasm32"))]
pub use pinned::client_config;
pub use player::{Action, Entry, PlayerCore, PlayerEvent, Reconnect, Seating, ATTEMPT_LIMIT};
pub use polled::{MemoryServer, MemoryTransport, Polled, Transport, TransportEvent};
pub use port::{PolledSession, Port, SessionEvent};
#[cfg(not(target_arch = "wasm32"))]
pub use progress::{stalled, Progress, Seen, Waiting};
pub use record_answer::{interpret_record, FetchError, FetchedRecord, FETCH_TIMEOUT};
#[cfg(not(target_arch = "wasm32"))]
pub use records::{fetch_game, fetch_game_blocking, fetch_record};
#[cfg(not(target_arch = "wasm32"))]
pub(crate) use seat_player::{Entrance, PlayerResult, SeatPlayer};
#[cfg(not(target_arch = "wasm32"))]
pub use seat_player::{ShotTimes, Tally, RETRY_FOR};
#[cfg(not(target_arch = "wasm32"))]
pub use seated_computer::SeatedComputer;
pub use seats::{hosted_from, Remembered, SeatStore};
#[cfg(not(target_arch = "wasm32"))]
pub use session::Session;
pub use web_way::{Using, WebWay};
