//! The wire protocol between clients and the server: messages, framing, limits, invites and
//! the checks every message passes before the game sees it. Pure: no sockets, no clock.
//! docs/protocol.md is the reference for people.

pub mod framing;
pub mod identity;
pub mod ids;
pub mod invite;
pub mod limits;
pub mod lobby;
pub mod messages;
pub mod reference;
pub mod validate;
pub mod web;
pub mod web_link;

pub use framing::{decode_payload, encode_frame, payload_len, split_frame, FrameError, HEADER_LEN};
pub use identity::{Identity, IdentityError, PlayerKey};
pub use ids::{Fingerprint, RoomCode, SeatToken};
pub use invite::{Invite, InviteError, ServerAddress};
pub use lobby::{GameInPlay, RatedPlayer, WaitingRoom};
pub use messages::{
    command_of, AimAid, ClientMessage, ErrorCode, Role, Ruling, SeatView, ServerMessage, Snapshot,
};
pub use reference::{reference_hash, reference_shot, reference_shots, Mechanism, ReferenceShot};
pub use validate::{is_valid_name, validate, InvalidMessage};
pub use web_link::{WebLink, WebLinkError, WebTransportChoice};

/// Bumped whenever a message changes shape or meaning. A client with another version is
/// refused in the handshake with a reason. Version 2: a strike carries its cue elevation
/// (`Strike::elevation_deg`). Version 3: `FetchRecord` names the game wanted, so any game
/// of a room can be fetched, and records name their players and their physics. Version 4:
/// players are their keys: `Hello` carries an Ed25519 public key, proved by signing the
/// server's `Challenge` (`Prove`); public rooms, the lobby, quick match and ratings.
/// Version 5: the `Advice` aim-aid policy. Version 6: `Ratings`, the seats' ratings in a
/// rated room, told to whoever enters it. Version 7: `ShotResolved` carries the game after
/// the shot rather than its balls alone.
pub const PROTOCOL_VERSION: u32 = 7;

/// The protocol version a `Hello` payload claims, read from its first two fields alone: a
/// client of another version gets a readable refusal even when the rest of its `Hello` has
/// another shape. `None` if the payload is not a `Hello`.
pub fn claimed_version(payload: &[u8]) -> Option<u32> {
    let cfg = bincode::config::standard();
    let (variant, used): (u32, usize) = bincode::decode_from_slice(payload, cfg).ok()?;
    if variant != 0 {
        return None;
    }
    let (protocol, _): (u32, usize) = bincode::decode_from_slice(payload.get(used..)?, cfg).ok()?;
    Some(protocol)
}

/// The QUIC application protocol (ALPN) name.
pub const ALPN: &[u8] = b"breakshot/1";

/// The ALPN of WebTransport (HTTP/3), the browser's way onto the same UDP port. A
/// connection that negotiates it is shown the server's short-lived certificate, one that
/// negotiates [`ALPN`] the long-lived one its invites pin (docs/web.md). Its CONNECT goes
/// to [`web::WEBTRANSPORT_PATH`].
pub const WEB_ALPN: &[u8] = b"h3";
