//! Hosting a game from the game itself: the same server as `breakshot-server`, run on its
//! own thread inside this process, and a room on it that this computer plays in through
//! the same network path as the other player (QUIC on loopback, the certificate pinned by
//! its fingerprint).

use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr};
use std::path::PathBuf;

use breakshot_shared::ai::Level;
use breakshot_shared::protocol::{AimAid, Invite};
use breakshot_shared::rules::{EightBallRules, Settings, Variant};
use thiserror::Error;

/// The UDP port `breakshot host` listens on unless told otherwise (the one to open in a
/// firewall or forward on a router).
pub const DEFAULT_PORT: u16 = 4433;

/// What the host is told when no address the other player can dial was found.
pub const ADDRESS_NOTE: &str = "this computer has no network address the other player can \
     dial: start again with --address HOST (your LAN or public address)";

/// How to be reached from outside a home network, for a server on `port`: one line for the
/// invite panel and the terminal (the README says the same).
/// `web`: the web client is served too, on the same port number over TCP.
pub fn router_hint(port: u16, web: bool) -> String {
    let ports = if web {
        format!("UDP and TCP port {port}")
    } else {
        format!("UDP port {port}")
    };
    format!(
        "Over the internet: forward {ports} on your router to this computer and host with \
         --address YOUR_PUBLIC_IP"
    )
}

#[derive(Debug, Error)]
/// Why hosting failed.
pub enum HostError {
    /// The server could not start.
    #[cfg(feature = "host")]
    #[error("the game server could not start")]
    Server(#[from] breakshot_server::ServerError),
    /// This build has no embedded server.
    #[cfg(not(feature = "host"))]
    #[error("this build cannot host games (it was built without the `host` feature): run breakshot-server and join its invite")]
    NotBuilt,
    #[error("the game server could not start: {0}")]
    /// No runtime for the server's thread.
    Runtime(String),
    #[error("could not open a room on the game server: {0}")]
    /// The room could not be opened.
    Room(String),
    #[error("the invite's address must be a host name or an IP address, not {0:?}")]
    /// The address given for the invite is not one.
    Address(String),
}

/// What to host.
#[derive(Clone, Debug)]
pub struct HostOptions {
    /// The UDP address the server listens on.
    pub bind: SocketAddr,
    /// The server's data directory (certificate and game store).
    pub data: PathBuf,
    /// The game played.
    pub variant: Variant,
    /// The room's settings.
    pub settings: Settings,
    /// The aiming aids the room allows.
    pub aim_aid: AimAid,
    /// The address written into the invite instead of the bound one: what the other player
    /// dials to reach this computer.
    pub address: Option<String>,
    /// Go back to this computer's unfinished game on this server, if there is one, rather
    /// than open a new room.
    pub resume: bool,
    /// The host player's name.
    pub name: String,
    /// The computer plays the other seat at this level (a friend with the invite watches).
    /// A game against the computer is not resumed: it always opens a new room.
    pub computer: Option<Level>,
    /// The web client's bundle (`web/build.sh OUT_DIR`), served on the same port number over
    /// TCP so that a friend can play from a browser; `None`: native players only.
    pub web: Option<PathBuf>,
    /// The address where the same bundle is published (a static HTTPS site): the link then
    /// opens that page and names this server (`server=HOST:PORT`), reached over WebTransport.
    pub web_page: Option<String>,
}

impl HostOptions {
    /// An 8-ball game (WPA rules, the online shot clock, every aid allowed) served on
    /// [`DEFAULT_PORT`] of every interface, with its data in `data`.
    pub fn new(data: PathBuf) -> HostOptions {
        HostOptions {
            bind: SocketAddr::from(([0, 0, 0, 0], DEFAULT_PORT)),
            data,
            variant: Variant::EightBall(EightBallRules::Wpa),
            settings: Settings::online(),
            aim_aid: AimAid::Full,
            address: None,
            resume: true,
            name: "host".into(),
            computer: None,
            web: web_bundle(),
            web_page: None,
        }
    }
}

/// The environment variable that names the web client's bundle (what `web/build.sh` built).
pub const WEB_ENV: &str = "BREAKSHOT_WEB";

/// The web client's bundle, if one is built: `$BREAKSHOT_WEB`, else `web` beside the
/// program's folder (`target/web` for `target/release/breakshot`: `bash web/build.sh
/// target/web`), else `web` in the program's folder (a packaged game). A folder counts only
/// with its `index.html`.
pub fn web_bundle() -> Option<PathBuf> {
    let built = |dir: PathBuf| dir.join("index.html").is_file().then_some(dir);
    if let Some(dir) = std::env::var_os(WEB_ENV) {
        return built(PathBuf::from(dir));
    }
    let exe = std::env::current_exe().ok()?;
    let folder = exe.parent()?;
    folder
        .parent()
        .and_then(|up| built(up.join("web")))
        .or_else(|| built(folder.join("web")))
}

/// True when `invite` names a wildcard address (0.0.0.0 or ::), which the other player
/// cannot dial: the host has to give their LAN or public address instead.
pub fn names_wildcard(invite: &Invite) -> bool {
    invite
        .first()
        .server_name()
        .parse::<IpAddr>()
        .is_ok_and(|ip| ip.is_unspecified())
}

/// The address another computer on the same network dials to reach this one: the first
/// IPv4 address in a private range (a home or office LAN), else any other routable IPv4,
/// else a routable IPv6 address. Loopback, link-local and wildcard addresses never.
pub(crate) fn lan_address(candidates: &[IpAddr]) -> Option<IpAddr> {
    let dialable = |ip: &IpAddr| match ip {
        IpAddr::V4(v4) => !(v4.is_loopback() || v4.is_link_local() || v4.is_unspecified()),
        IpAddr::V6(v6) => {
            // fe80::/10 is link-local: it needs a zone id nobody puts in an invite.
            !(v6.is_loopback() || v6.is_unspecified() || (v6.segments()[0] & 0xffc0) == 0xfe80)
        }
    };
    let dialable: Vec<IpAddr> = candidates.iter().copied().filter(dialable).collect();
    let private = |ip: &&IpAddr| matches!(ip, IpAddr::V4(v4) if v4.is_private());
    dialable
        .iter()
        .find(private)
        .or_else(|| dialable.iter().find(|ip| ip.is_ipv4()))
        .or_else(|| dialable.first())
        .copied()
}

/// This computer's addresses on the interfaces that are up.
#[cfg(all(feature = "host", not(target_arch = "wasm32")))]
pub(super) fn interface_addresses() -> Vec<IpAddr> {
    match if_addrs::get_if_addrs() {
        Ok(interfaces) => interfaces.iter().map(|i| i.ip()).collect(),
        Err(e) => {
            tracing::warn!(error = %e, "cannot list the network interfaces");
            Vec::new()
        }
    }
}

/// The environment variable that names the data directory (what `--data` gives).
pub(crate) const DATA_ENV: &str = "BREAKSHOT_DATA";

/// The default data directory: `$BREAKSHOT_DATA` if set, else `breakshot` in the user's
/// data directory (`$XDG_DATA_HOME`, else `~/.local/share` on Linux and other Unix systems,
/// `~/Library/Application Support` on macOS, `%APPDATA%` on Windows).
pub fn default_data_dir() -> Option<PathBuf> {
    let var = |name: &str| {
        std::env::var_os(name)
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
    };
    if let Some(dir) = var(DATA_ENV) {
        return Some(dir);
    }
    let base = if cfg!(windows) {
        var("APPDATA")
    } else if cfg!(target_os = "macos") {
        var("HOME").map(|h| h.join("Library").join("Application Support"))
    } else {
        var("XDG_DATA_HOME").or_else(|| var("HOME").map(|h| h.join(".local").join("share")))
    };
    base.map(|b| b.join("breakshot"))
}

/// Where this computer reaches a server bound to `bound`: the loopback address of the same
/// family when the server listens on every interface, else the bound address itself.
pub(crate) fn loopback_for(bound: SocketAddr) -> SocketAddr {
    let ip = match bound.ip() {
        IpAddr::V4(ip) if ip.is_unspecified() => IpAddr::V4(Ipv4Addr::LOCALHOST),
        IpAddr::V6(ip) if ip.is_unspecified() => IpAddr::V6(Ipv6Addr::LOCALHOST),
        ip => ip,
    };
    SocketAddr::new(ip, bound.port())
}

/// The host part of an invite for an address the host gives: a name or an IP address (an
/// IPv6 address is put in brackets).
pub(crate) fn invite_host(address: &str) -> Result<String, HostError> {
    let a = address.trim();
    if let Ok(ip) = a
        .trim_start_matches('[')
        .trim_end_matches(']')
        .parse::<IpAddr>()
    {
        return Ok(host_text(ip));
    }
    let name_char = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '.';
    if a.is_empty() || !a.chars().all(name_char) {
        return Err(HostError::Address(address.to_string()));
    }
    Ok(a.to_string())
}

/// `ip` as an invite writes it (IPv6 in brackets).
pub(super) fn host_text(ip: IpAddr) -> String {
    match ip {
        IpAddr::V6(ip) => format!("[{ip}]"),
        ip => ip.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wildcard_bind_is_dialled_on_loopback() {
        let v4: SocketAddr = "0.0.0.0:4433".parse().unwrap();
        assert_eq!(loopback_for(v4), "127.0.0.1:4433".parse().unwrap());
        let v6: SocketAddr = "[::]:9".parse().unwrap();
        assert_eq!(loopback_for(v6), "[::1]:9".parse().unwrap());
        let lan: SocketAddr = "192.168.1.20:4433".parse().unwrap();
        assert_eq!(loopback_for(lan), lan);
    }

    #[test]
    fn only_a_wildcard_address_needs_replacing_in_an_invite() {
        let fp = "ab".repeat(32);
        let invite = |host: &str| -> Invite {
            format!("breakshot://{host}:4433/K7QX2M4B#{fp}")
                .parse()
                .unwrap()
        };
        assert!(names_wildcard(&invite("0.0.0.0")));
        assert!(names_wildcard(&invite("[::]")));
        for host in ["127.0.0.1", "192.168.1.20", "[::1]", "pool.example.org"] {
            assert!(!names_wildcard(&invite(host)), "{host}");
        }
    }

    #[test]
    fn the_lan_address_is_a_private_ipv4_one_and_never_unroutable() {
        let ips =
            |list: &[&str]| -> Vec<IpAddr> { list.iter().map(|s| s.parse().unwrap()).collect() };
        let pick = |list: &[&str]| lan_address(&ips(list)).map(|ip| ip.to_string());
        assert_eq!(
            pick(&[
                "127.0.0.1",
                "::1",
                "fe80::1",
                "169.254.3.4",
                "203.0.113.9",
                "192.168.1.20"
            ]),
            Some("192.168.1.20".into())
        );
        assert_eq!(
            pick(&["127.0.0.1", "203.0.113.9"]),
            Some("203.0.113.9".into())
        );
        assert_eq!(pick(&["::1", "2001:db8::7"]), Some("2001:db8::7".into()));
        assert_eq!(
            pick(&["127.0.0.1", "::1", "0.0.0.0", "fe80::2", "169.254.1.1"]),
            None
        );
        assert_eq!(pick(&[]), None);
    }

    #[test]
    fn a_given_address_becomes_the_invite_s_host() {
        assert_eq!(invite_host("pool.example.org").unwrap(), "pool.example.org");
        assert_eq!(invite_host("192.168.1.20").unwrap(), "192.168.1.20");
        assert_eq!(invite_host("2001:db8::7").unwrap(), "[2001:db8::7]");
        assert_eq!(invite_host("[2001:db8::7]").unwrap(), "[2001:db8::7]");
        for bad in ["", "host:4433", "a/b", "x#y", "two words"] {
            assert!(invite_host(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn the_data_directory_is_in_the_user_s_data_directory() {
        if let Some(dir) = default_data_dir() {
            assert!(dir.is_absolute());
            assert!(dir.ends_with("breakshot"));
        }
    }
}
