//! Web links: the address a player opens in a browser to reach a server (and a room) they can
//! trust, as docs/web.md describes it.
//!
//! `http://HOST:P/?room=ROOM&key=KEYHEX&cert=HASHHEX,HASHHEX`, and optionally
//! `server=HOST:P` (the game server, when the page comes from elsewhere), `watch=1`,
//! `replay=1` (the room's recorded game), `transport=ws|wt`, `name=NAME` (the player's name)
//! and, for tests, `computer=LEVEL`. The page itself reads only the query string, so a link
//! parses from the whole address or from its query string alone.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use super::ids::{Fingerprint, RoomCode};
use super::invite::ServerAddress;
use super::validate::is_valid_name;
use super::web::NOISE_KEY_LEN;
use crate::ai::Level;

/// Which ways in the page may use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WebTransportChoice {
    /// WebTransport when the page has it, else (or when it fails) the WebSocket.
    #[default]
    Any,
    /// Only the Noise-encrypted WebSocket (`transport=ws`).
    WebSocket,
    /// Only WebTransport (`transport=wt`).
    WebTransport,
}

/// A parsed web link.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WebLink {
    /// Everything before the `?` (`http://HOST:P/`): where the page is loaded from. `None` for
    /// a link parsed from its query string alone, which then displays as `?…`.
    pub page: Option<String>,
    /// The game server, when it is not the page's own host (`server=HOST:P`).
    pub server: Option<ServerAddress>,
    /// The room to join or watch; `None`: the page offers practice and the computer.
    pub room: Option<RoomCode>,
    /// The server's Noise static public key (X25519), which authenticates the WebSocket.
    pub key: [u8; NOISE_KEY_LEN],
    /// SHA-256 hashes of the server's current `h3` certificates, newest first; may be empty.
    pub cert: Vec<Fingerprint>,
    /// Watch instead of play (`watch=1`).
    pub watch: bool,
    /// Watch the room's recorded game from its start instead (`replay=1`).
    pub replay: bool,
    /// The ways in the page may try (`transport=`).
    pub transport: WebTransportChoice,
    /// Tests only: the page's own computer player takes its seat at this level.
    pub computer: Option<Level>,
    /// The player's name (`name=`), a valid name ([`is_valid_name`]).
    pub name: Option<String>,
}

/// Why a text is not a web link.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum WebLinkError {
    /// No `key=` parameter.
    #[error("a web link carries key= (the server's key, 64 hexadecimal digits)")]
    MissingKey,
    /// A parameter that is not valid for its name (the name is given).
    #[error("the link's {0}= is not valid")]
    Bad(&'static str),
    /// The same parameter twice.
    #[error("the link has {0}= twice")]
    Repeated(&'static str),
    /// A `%` not followed by two hexadecimal digits, or an escape that is not UTF-8.
    #[error("the link has a bad %-escape")]
    Escape,
}

/// The parameters a link may carry, in the order [`WebLink`] displays them.
const NAMES: [&str; 9] = [
    "server",
    "room",
    "key",
    "cert",
    "watch",
    "replay",
    "transport",
    "computer",
    "name",
];

impl WebLink {
    /// A link to the server with key `key`, at the page's own host, no room.
    pub fn new(key: [u8; NOISE_KEY_LEN]) -> WebLink {
        WebLink {
            page: None,
            server: None,
            room: None,
            key,
            cert: Vec::new(),
            watch: false,
            replay: false,
            transport: WebTransportChoice::Any,
            computer: None,
            name: None,
        }
    }

    /// The address of a page served by a server's own web listener: `http://HOST:PORT/`
    /// (an IPv6 host in brackets, as given).
    pub fn page_url(host: &str, port: u16) -> String {
        format!("http://{host}:{port}/")
    }

    /// The address of a published copy of the web bundle (a static site, as `--web-page`
    /// gives it), kept with a final `/` so the link's query follows it; or why it is not one.
    pub fn published_page(text: &str) -> Result<String, String> {
        let rest = text
            .strip_prefix("https://")
            .or_else(|| text.strip_prefix("http://"))
            .ok_or("the page's address starts with https:// (or http://)")?;
        if rest.is_empty() || rest.contains(['?', '#', ' ']) {
            return Err("the page's address is a plain URL without ? or #".into());
        }
        Ok(if text.ends_with('/') {
            text.to_owned()
        } else {
            format!("{text}/")
        })
    }

    /// The same link with a room.
    pub fn with_room(&self, room: RoomCode) -> WebLink {
        WebLink {
            room: Some(room),
            ..self.clone()
        }
    }

    /// The query string (without its `?`).
    pub fn query(&self) -> String {
        let mut parts: Vec<(&str, String)> = Vec::new();
        if let Some(server) = &self.server {
            parts.push(("server", server.to_string()));
        }
        if let Some(room) = &self.room {
            parts.push(("room", room.to_string()));
        }
        parts.push(("key", Fingerprint(self.key).to_string()));
        if !self.cert.is_empty() {
            let hashes: Vec<String> = self.cert.iter().map(Fingerprint::to_string).collect();
            parts.push(("cert", hashes.join(",")));
        }
        if self.watch {
            parts.push(("watch", "1".into()));
        }
        if self.replay {
            parts.push(("replay", "1".into()));
        }
        match self.transport {
            WebTransportChoice::Any => {}
            WebTransportChoice::WebSocket => parts.push(("transport", "ws".into())),
            WebTransportChoice::WebTransport => parts.push(("transport", "wt".into())),
        }
        if let Some(level) = self.computer {
            parts.push(("computer", level.number().to_string()));
        }
        if let Some(name) = &self.name {
            parts.push(("name", name.clone()));
        }
        parts
            .iter()
            .map(|(name, value)| format!("{name}={}", escape(value)))
            .collect::<Vec<_>>()
            .join("&")
    }

    /// Parses a query string (a leading `?` is allowed). Unknown parameters are ignored, so
    /// an older page still opens a newer link.
    pub fn from_query(query: &str) -> Result<WebLink, WebLinkError> {
        let query = query.trim();
        let query = query.strip_prefix('?').unwrap_or(query);
        let query = query.split_once('#').map_or(query, |(q, _)| q);
        let mut values: [Option<String>; NAMES.len()] = Default::default();
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (name, value) = pair.split_once('=').unwrap_or((pair, ""));
            let name = unescape(name)?;
            let Some(i) = NAMES.iter().position(|n| *n == name) else {
                continue;
            };
            if values[i].is_some() {
                return Err(WebLinkError::Repeated(NAMES[i]));
            }
            values[i] = Some(unescape(value)?);
        }
        let [server, room, key, cert, watch, replay, transport, computer, name] = values;
        let key = key.ok_or(WebLinkError::MissingKey)?;
        Ok(WebLink {
            page: None,
            server: server
                .map(|s| s.parse().map_err(|_| WebLinkError::Bad("server")))
                .transpose()?,
            room: room
                .map(|r| RoomCode::parse(&r).map_err(|_| WebLinkError::Bad("room")))
                .transpose()?,
            key: Fingerprint::parse(&key)
                .map_err(|_| WebLinkError::Bad("key"))?
                .0,
            cert: match cert.as_deref() {
                None | Some("") => Vec::new(),
                Some(list) => list
                    .split(',')
                    .map(|h| Fingerprint::parse(h).map_err(|_| WebLinkError::Bad("cert")))
                    .collect::<Result<_, _>>()?,
            },
            watch: flag(watch.as_deref(), "watch")?,
            replay: flag(replay.as_deref(), "replay")?,
            transport: match transport.as_deref() {
                None => WebTransportChoice::Any,
                Some("ws") => WebTransportChoice::WebSocket,
                Some("wt") => WebTransportChoice::WebTransport,
                Some(_) => return Err(WebLinkError::Bad("transport")),
            },
            computer: computer
                .map(|c| match c.parse::<u8>() {
                    Ok(n) if (Level::MIN..=Level::MAX).contains(&n) => Ok(Level::new(n)),
                    _ => Err(WebLinkError::Bad("computer")),
                })
                .transpose()?,
            name: name
                .map(|n| {
                    let n = n.trim();
                    is_valid_name(n)
                        .then(|| n.to_owned())
                        .ok_or(WebLinkError::Bad("name"))
                })
                .transpose()?,
        })
    }
}

/// A parameter that is `1` or `0` (absent: `0`).
fn flag(value: Option<&str>, name: &'static str) -> Result<bool, WebLinkError> {
    match value {
        None | Some("0") => Ok(false),
        Some("1") => Ok(true),
        Some(_) => Err(WebLinkError::Bad(name)),
    }
}

impl FromStr for WebLink {
    type Err = WebLinkError;

    /// A whole address (`http://…` or `https://…`, the part before `?` kept as
    /// [`WebLink::page`]) or a query string alone.
    fn from_str(s: &str) -> Result<WebLink, WebLinkError> {
        let s = s.trim();
        let lower = s.get(..8).unwrap_or(s).to_ascii_lowercase();
        if !(lower.starts_with("http://") || lower.starts_with("https://")) {
            return WebLink::from_query(s);
        }
        let s = s.split_once('#').map_or(s, |(a, _)| a);
        let (page, query) = s.split_once('?').unwrap_or((s, ""));
        Ok(WebLink {
            page: Some(page.to_string()),
            ..WebLink::from_query(query)?
        })
    }
}

impl fmt::Display for WebLink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}?{}", self.page.as_deref().unwrap_or(""), self.query())
    }
}

/// Percent-escapes everything but unreserved characters and those a host:port needs.
fn escape(value: &str) -> String {
    let mut out = String::with_capacity(value.len());
    for b in value.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~:[],".contains(&b) {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// Undoes [`escape`] (and any other %-escape; `+` is a space, as in a form).
fn unescape(value: &str) -> Result<String, WebLinkError> {
    let bytes = value.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' => {
                let hex = bytes.get(i + 1..i + 3).ok_or(WebLinkError::Escape)?;
                let hex = std::str::from_utf8(hex).map_err(|_| WebLinkError::Escape)?;
                out.push(u8::from_str_radix(hex, 16).map_err(|_| WebLinkError::Escape)?);
                i += 3;
            }
            b'+' => {
                out.push(b' ');
                i += 1;
            }
            b => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).map_err(|_| WebLinkError::Escape)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> String {
        "0f".repeat(32)
    }

    /// `text` as a web link; a test of a valid link fails with the reason it was refused.
    fn parsed(text: &str) -> WebLink {
        text.parse()
            .unwrap_or_else(|e| panic!("{text} is refused: {e}"))
    }

    #[test]
    fn links_round_trip() {
        let k = key();
        let h1 = "ab".repeat(32);
        let h2 = "cd".repeat(32);
        for text in [
            format!("http://192.168.1.20:4433/?room=K7QX2M4B&key={k}&cert={h1},{h2}"),
            format!("http://192.168.1.20:4433/?key={k}"),
            format!("http://[::1]:4433/?room=K7QX2M4B&key={k}&cert={h1}"),
            format!("https://example.org/play/?server=game.example.org:4433&room=K7QX2M4B&key={k}&watch=1&transport=wt"),
            format!("http://h:1/?server=[::1]:9&key={k}&transport=ws&computer=3"),
            format!("http://h:1/?room=K7QX2M4B&key={k}&replay=1"),
            format!("http://h:1/?room=K7QX2M4B&key={k}&name=Ann%20Lee"),
            format!("?room=K7QX2M4B&key={k}"),
        ] {
            assert_eq!(parsed(&text).to_string(), text, "{text}");
        }
    }

    #[test]
    fn a_full_link_and_its_query_say_the_same() {
        let k = key();
        let full = parsed(&format!(
            "http://10.0.0.2:4433/?room=k7qx2m4b&key={k}&cert="
        ));
        assert_eq!(full.page.as_deref(), Some("http://10.0.0.2:4433/"));
        assert_eq!(full.room.as_ref().map(RoomCode::as_str), Some("K7QX2M4B"));
        assert_eq!(full.key, [0x0f; 32]);
        assert!(full.cert.is_empty());
        assert!(!full.watch);
        assert_eq!(full.transport, WebTransportChoice::Any);
        let query = WebLink::from_query(&full.query()).unwrap();
        assert_eq!(
            query,
            WebLink {
                page: None,
                ..full.clone()
            }
        );
        // The page's own `location.search` starts with `?`; a fragment is not the query's.
        let search = WebLink::from_query(&format!("?{}#x", full.query())).unwrap();
        assert_eq!(search, query);
    }

    #[test]
    fn escapes_are_decoded_and_unknown_parameters_ignored() {
        let k = key();
        let link = parsed(&format!(
            "?roo%6D=K7QX2M4B&key={k}&utm=%20x&server=%5B%3A%3A1%5D%3A7"
        ));
        assert_eq!(link.room.unwrap().as_str(), "K7QX2M4B");
        assert_eq!(link.server.unwrap().authority(), "[::1]:7");
    }

    #[test]
    fn bad_links_are_refused_with_a_reason() {
        let k = key();
        let h = "ab".repeat(32);
        for (text, want) in [
            ("?room=K7QX2M4B".to_string(), WebLinkError::MissingKey),
            ("http://h:1/".to_string(), WebLinkError::MissingKey),
            ("".to_string(), WebLinkError::MissingKey),
            (
                format!("?key={}", "0f".repeat(31)),
                WebLinkError::Bad("key"),
            ),
            (format!("?key={k}zz"), WebLinkError::Bad("key")),
            (format!("?key={k}&room=nope"), WebLinkError::Bad("room")),
            (format!("?key={k}&cert={h},"), WebLinkError::Bad("cert")),
            (format!("?key={k}&cert=12"), WebLinkError::Bad("cert")),
            (format!("?key={k}&watch=yes"), WebLinkError::Bad("watch")),
            (format!("?key={k}&replay=2"), WebLinkError::Bad("replay")),
            (
                format!("?key={k}&transport=tcp"),
                WebLinkError::Bad("transport"),
            ),
            (
                format!("?key={k}&computer=0"),
                WebLinkError::Bad("computer"),
            ),
            (
                format!("?key={k}&computer=6"),
                WebLinkError::Bad("computer"),
            ),
            (
                format!("?key={k}&server=nohost"),
                WebLinkError::Bad("server"),
            ),
            (
                format!("?key={k}&server=::1:4"),
                WebLinkError::Bad("server"),
            ),
            (format!("?key={k}&name="), WebLinkError::Bad("name")),
            (format!("?key={k}&name=%07"), WebLinkError::Bad("name")),
            (
                format!("?key={k}&name={}", "n".repeat(25)),
                WebLinkError::Bad("name"),
            ),
            (format!("?key={k}&key={k}"), WebLinkError::Repeated("key")),
            (format!("?key={k}&room=%4"), WebLinkError::Escape),
            (format!("?key={k}&room=%zz"), WebLinkError::Escape),
            (format!("?key={k}&room=%ff"), WebLinkError::Escape),
            (format!("?key={k}&room=%C3%"), WebLinkError::Escape),
        ] {
            assert_eq!(text.parse::<WebLink>(), Err(want), "{text}");
        }
    }

    #[test]
    fn a_published_page_is_a_plain_address_ending_in_a_slash() {
        assert_eq!(
            WebLink::published_page("https://example.org/play").as_deref(),
            Ok("https://example.org/play/")
        );
        assert_eq!(
            WebLink::published_page("https://example.org/").as_deref(),
            Ok("https://example.org/")
        );
        for bad in [
            "ftp://x/",
            "https://",
            "https://x/?a=1",
            "https://x/#y",
            "x.org",
        ] {
            assert!(WebLink::published_page(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn odd_bytes_never_panic() {
        for text in [
            "?%",
            "?=&&=",
            "?key=é",
            "http://",
            "HTTPS://x?key=%%",
            "?\u{0}",
        ] {
            let _ = text.parse::<WebLink>();
        }
    }
}
