//! Breakshot's authoritative server: a pure core ([`hub::Hub`] routing connections to
//! [`room::Room`]s) driven by a thin QUIC layer, with every accepted command stored before
//! anyone sees its result.

#![warn(missing_docs, unreachable_pub)]

pub mod admin;
pub mod admission;
pub mod conn;
pub mod endings;
pub mod hub;
pub mod limits;
pub mod lobby;
pub mod matchmaking;
pub mod output;
pub mod pool;
pub mod quic;
pub mod ratelimit;
pub mod ratings;
pub mod records;
pub mod room;
pub mod rooms;
pub mod secret;
pub mod server;
pub mod source;
pub mod stats;
pub mod store;
pub mod timing;
pub mod tls;
pub mod verify;
pub mod web;
pub mod webcert;
pub mod webtransport;
pub mod work;
pub mod writer;

pub use limits::Limits;
pub use server::{run, Config, RoomHook, Server, ServerError, DEFAULT_DRAIN_TIMEOUT};
pub use stats::Stats;
