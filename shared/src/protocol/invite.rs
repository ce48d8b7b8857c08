//! Invites: the text a player pastes to reach a server (and a room) they can trust.
//!
//! `breakshot://HOST:PORT/ROOM#FINGERPRINT`; the room is left out of a server's own address
//! (`breakshot://HOST:PORT#FINGERPRINT`). HOST may be a name, an IPv4 address, or an IPv6
//! address in brackets.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use super::ids::{Fingerprint, RoomCode};

pub const SCHEME: &str = "breakshot://";

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invite {
    pub host: String,
    pub port: u16,
    pub room: Option<RoomCode>,
    pub fingerprint: Fingerprint,
}

#[derive(Debug, Error, PartialEq, Eq)]
pub enum InviteError {
    #[error("an invite starts with {SCHEME}")]
    Scheme,
    #[error("an invite ends with #FINGERPRINT (the server certificate's SHA-256)")]
    MissingFingerprint,
    #[error("an invite names HOST:PORT")]
    Address,
    #[error(transparent)]
    Id(#[from] super::ids::IdError),
}

impl Invite {
    /// The same server with a room.
    pub fn with_room(&self, room: RoomCode) -> Invite {
        Invite {
            room: Some(room),
            ..self.clone()
        }
    }

    /// `HOST:PORT`, as a socket address string (brackets kept for IPv6).
    pub fn authority(&self) -> String {
        format!("{}:{}", self.host, self.port)
    }

    /// The host as it appears in a certificate (no brackets).
    pub fn server_name(&self) -> &str {
        self.host.trim_start_matches('[').trim_end_matches(']')
    }
}

impl FromStr for Invite {
    type Err = InviteError;

    fn from_str(s: &str) -> Result<Invite, InviteError> {
        let rest = s.trim().strip_prefix(SCHEME).ok_or(InviteError::Scheme)?;
        let (before, fp) = rest
            .split_once('#')
            .ok_or(InviteError::MissingFingerprint)?;
        let fingerprint = Fingerprint::parse(fp)?;
        let (authority, room) = match before.split_once('/') {
            Some((a, "")) => (a, None),
            Some((a, r)) => (a, Some(RoomCode::parse(r)?)),
            None => (before, None),
        };
        let (host, port) = authority.rsplit_once(':').ok_or(InviteError::Address)?;
        let port: u16 = port.parse().map_err(|_| InviteError::Address)?;
        let bracketed = host.starts_with('[') && host.ends_with(']');
        if host.is_empty() || (host.contains(':') && !bracketed) {
            return Err(InviteError::Address);
        }
        Ok(Invite {
            host: host.to_string(),
            port,
            room,
            fingerprint,
        })
    }
}

impl fmt::Display for Invite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{SCHEME}{}:{}", self.host, self.port)?;
        if let Some(room) = &self.room {
            write!(f, "/{room}")?;
        }
        write!(f, "#{}", self.fingerprint)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invites_round_trip() {
        let fp = "ab".repeat(32);
        for text in [
            format!("breakshot://127.0.0.1:4433/K7QX2M4B#{fp}"),
            format!("breakshot://example.org:9#{fp}"),
            format!("breakshot://[::1]:4433/K7QX2M4B#{fp}"),
        ] {
            let inv: Invite = text.parse().unwrap();
            assert_eq!(inv.to_string(), text);
        }
        let inv: Invite = format!("breakshot://[::1]:1#{fp}").parse().unwrap();
        assert_eq!(inv.server_name(), "::1");
    }

    #[test]
    fn broken_invites_say_what_is_wrong() {
        let fp = "ab".repeat(32);
        assert_eq!("http://x:1".parse::<Invite>(), Err(InviteError::Scheme));
        assert_eq!(
            "breakshot://x:1/K7QX2M4B".parse::<Invite>(),
            Err(InviteError::MissingFingerprint)
        );
        assert_eq!(
            format!("breakshot://x/K7QX2M4B#{fp}").parse::<Invite>(),
            Err(InviteError::Address)
        );
        assert!(format!("breakshot://x:1/BAD#{fp}")
            .parse::<Invite>()
            .is_err());
        assert!("breakshot://x:1#abc".parse::<Invite>().is_err());
    }
}
