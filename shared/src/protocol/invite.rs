//! Invites: the text a player pastes to reach a server (and a room) they can trust.
//!
//! `breakshot://HOST:PORT/ROOM#FINGERPRINT`; the room is left out of a server's own address
//! (`breakshot://HOST:PORT#FINGERPRINT`). HOST may be a name, an IPv4 address, or an IPv6
//! address in brackets. Several addresses, separated by commas
//! (`breakshot://HOST1:PORT1,HOST2:PORT2/ROOM#FINGERPRINT`), name server instances that share
//! one database and one identity: a client tries them in order.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use super::ids::{Fingerprint, RoomCode};

/// What every invite starts with.
pub const SCHEME: &str = "breakshot://";

/// One address an invite names: a host and a UDP port.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ServerAddress {
    /// A name, an IPv4 address, or an IPv6 address in brackets.
    pub host: String,
    /// The UDP port the server listens on.
    pub port: u16,
}

/// A server (one or several instances of it) and, to join a game, a room on it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invite {
    /// The addresses to try, in order; never empty.
    pub servers: Vec<ServerAddress>,
    /// The room to join or watch; `None` in a server's own address.
    pub room: Option<RoomCode>,
    /// The certificate every listed instance presents.
    pub fingerprint: Fingerprint,
}

/// Why a text is not an invite.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum InviteError {
    /// The text does not start with [`SCHEME`].
    #[error("an invite starts with {SCHEME}")]
    Scheme,
    /// No `#` followed by the fingerprint.
    #[error("an invite ends with #FINGERPRINT (the server certificate's SHA-256)")]
    MissingFingerprint,
    /// A missing or malformed `HOST:PORT`, or no address at all.
    #[error("an invite names HOST:PORT (several separated by commas)")]
    Address,
    /// A malformed room code or fingerprint.
    #[error(transparent)]
    Id(#[from] super::ids::IdError),
}

impl ServerAddress {
    /// `HOST:PORT`, as a socket address string (brackets kept for IPv6).
    pub fn authority(&self) -> String {
        format!("{}:{}", self.host, self.port)
    }

    /// The host as it appears in a certificate (no brackets).
    pub fn server_name(&self) -> &str {
        self.host.trim_start_matches('[').trim_end_matches(']')
    }
}

impl FromStr for ServerAddress {
    type Err = InviteError;

    fn from_str(s: &str) -> Result<ServerAddress, InviteError> {
        let (host, port) = s.rsplit_once(':').ok_or(InviteError::Address)?;
        let port: u16 = port.parse().map_err(|_| InviteError::Address)?;
        let bracketed = host.starts_with('[') && host.ends_with(']');
        if host.is_empty() || (host.contains(':') && !bracketed) {
            return Err(InviteError::Address);
        }
        Ok(ServerAddress {
            host: host.to_string(),
            port,
        })
    }
}

impl fmt::Display for ServerAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.host, self.port)
    }
}

impl Invite {
    /// A server at one address, with no room.
    pub fn new(host: impl Into<String>, port: u16, fingerprint: Fingerprint) -> Invite {
        Invite {
            servers: vec![ServerAddress {
                host: host.into(),
                port,
            }],
            room: None,
            fingerprint,
        }
    }

    /// The same server with a room.
    pub fn with_room(&self, room: RoomCode) -> Invite {
        Invite {
            room: Some(room),
            ..self.clone()
        }
    }

    /// The same invite with the first address's host replaced (the name or address other
    /// computers dial, for a server bound to a wildcard address).
    pub fn with_host(mut self, host: impl Into<String>) -> Invite {
        self.servers[0].host = host.into();
        self
    }

    /// The first address, the one a client tries first.
    pub fn first(&self) -> &ServerAddress {
        &self.servers[0]
    }

    /// The first address as `HOST:PORT`, followed by how many others there are, for messages.
    pub fn authority(&self) -> String {
        match self.servers.len() {
            1 => self.first().authority(),
            n => format!("{} (and {} more)", self.first().authority(), n - 1),
        }
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
        let (authorities, room) = match before.split_once('/') {
            Some((a, "")) => (a, None),
            Some((a, r)) => (a, Some(RoomCode::parse(r)?)),
            None => (before, None),
        };
        let servers = authorities
            .split(',')
            .map(str::parse)
            .collect::<Result<Vec<ServerAddress>, _>>()?;
        Ok(Invite {
            servers,
            room,
            fingerprint,
        })
    }
}

impl fmt::Display for Invite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(SCHEME)?;
        for (i, server) in self.servers.iter().enumerate() {
            if i > 0 {
                f.write_str(",")?;
            }
            write!(f, "{server}")?;
        }
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
            format!("breakshot://a.example.org:4433,[::1]:4434,10.0.0.2:9/K7QX2M4B#{fp}"),
        ] {
            let inv: Invite = text.parse().unwrap();
            assert_eq!(inv.to_string(), text);
        }
        let inv: Invite = format!("breakshot://[::1]:1#{fp}").parse().unwrap();
        assert_eq!(inv.first().server_name(), "::1");
    }

    #[test]
    fn several_addresses_keep_their_order() {
        let fp = "ab".repeat(32);
        let inv: Invite = format!("breakshot://b.example.org:2,a.example.org:1/K7QX2M4B#{fp}")
            .parse()
            .unwrap();
        let names: Vec<String> = inv.servers.iter().map(ServerAddress::authority).collect();
        assert_eq!(names, ["b.example.org:2", "a.example.org:1"]);
        assert_eq!(inv.first().host, "b.example.org");
        assert_eq!(inv.authority(), "b.example.org:2 (and 1 more)");
    }

    #[test]
    fn broken_invites_say_what_is_wrong() {
        let fp = "ab".repeat(32);
        assert_eq!("http://x:1".parse::<Invite>(), Err(InviteError::Scheme));
        assert_eq!(
            "breakshot://x:1/K7QX2M4B".parse::<Invite>(),
            Err(InviteError::MissingFingerprint)
        );
        for authorities in ["x", "x:1,", ",x:1", "x:1,,y:2", "x:1,y", "::1:4433"] {
            assert_eq!(
                format!("breakshot://{authorities}/K7QX2M4B#{fp}").parse::<Invite>(),
                Err(InviteError::Address),
                "{authorities}"
            );
        }
        assert!(format!("breakshot://x:1/BAD#{fp}")
            .parse::<Invite>()
            .is_err());
        assert!("breakshot://x:1#abc".parse::<Invite>().is_err());
    }
}
