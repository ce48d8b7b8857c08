//! The wire protocol between clients and the server: messages, framing, limits, invites and
//! the checks every message passes before the game sees it. Pure: no sockets, no clock.
//! docs/protocol.md is the reference for people.

pub mod framing;
pub mod ids;
pub mod invite;
pub mod limits;
pub mod messages;
pub mod reference;
pub mod validate;
pub mod web;
pub mod web_link;

pub use framing::{decode_payload, encode_frame, payload_len, split_frame, FrameError, HEADER_LEN};
pub use ids::{Fingerprint, RoomCode, SeatToken};
pub use invite::{Invite, InviteError, ServerAddress};
pub use messages::{
    command_of, AimAid, ClientMessage, ErrorCode, Role, Ruling, SeatView, ServerMessage, Snapshot,
};
pub use reference::{reference_hash, reference_shot, reference_shots, Mechanism, ReferenceShot};
pub use validate::{is_valid_name, validate, InvalidMessage};
pub use web_link::{WebLink, WebLinkError, WebTransportChoice};

/// Bumped whenever a message changes shape or meaning. A client with another version is
/// refused in the handshake with a reason. Version 2: a strike carries its cue elevation
/// (`Strike::elevation_deg`). Version 3: `FetchRecord` names the game wanted, so any game
/// of a room can be fetched, and records name their players and their physics.
pub const PROTOCOL_VERSION: u32 = 3;

/// The QUIC application protocol (ALPN) name.
pub const ALPN: &[u8] = b"breakshot/1";

/// The ALPN of WebTransport (HTTP/3), the browser's way onto the same UDP port. A
/// connection that negotiates it is shown the server's short-lived certificate, one that
/// negotiates [`ALPN`] the long-lived one its invites pin (docs/web.md). Its CONNECT goes
/// to [`web::WEBTRANSPORT_PATH`].
pub const WEB_ALPN: &[u8] = b"h3";
