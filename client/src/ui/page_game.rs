//! The game a page's link names (docs/web.md): joining it or watching it, the player's name,
//! and the way to its server, WebTransport first, else the WebSocket under Noise. The page's
//! start and its menu both open it from here, and the lobby its connections to the server.

use breakshot_client::net::noise::Noised;
use breakshot_client::net::page::{self, PageSocket, Way as PageWay};
use breakshot_client::net::{
    Entry, NetLink, PlayerCore, Polled, PolledSession, Port, Reconnect, SeatStore, WebWay,
};
use breakshot_client::play::{GameLink, PlayedByComputer};
use breakshot_shared::protocol::{
    is_valid_name, Fingerprint, Invite, RoomCode, ServerAddress, WebLink, WebTransportChoice,
};

use super::clock;

/// The name a page's player goes by when no link has named them yet.
const PAGE_NAME: &str = "Guest";
/// Where the page keeps the name last given (`name=` in a link) for the next visit.
const NAME_KEY: &str = "breakshot.name";

/// The player's name: the link's `name=` (kept for next time), else the name kept from an
/// earlier visit, else [`PAGE_NAME`].
pub(crate) fn player_name(link: &WebLink) -> String {
    if let Some(name) = &link.name {
        page::store(NAME_KEY, name);
        return name.clone();
    }
    page::stored(NAME_KEY)
        .map(|n| n.trim().to_owned())
        .filter(|n| is_valid_name(n))
        .unwrap_or_else(|| PAGE_NAME.to_owned())
}

/// The link, read, or why it cannot be used.
pub(crate) fn usable_link() -> Result<&'static WebLink, String> {
    page::link()
        .as_ref()
        .map_err(|e| format!("This link is damaged ({e}): ask for a new one"))
}

/// The page's way to the game server of `link`: WebTransport, the WebSocket, or both.
pub(crate) type Way = WebWay<PageSocket, Noised<PageSocket>>;

/// The invite the player core dials to reach the game server of `link` (and `room`, if
/// given), and the transports to try.
pub(crate) fn way_to_server(
    link: &WebLink,
    room: Option<RoomCode>,
) -> Result<(Invite, Way), String> {
    let server = match &link.server {
        Some(server) => server.clone(),
        None => page::page_host()
            .parse::<ServerAddress>()
            .map_err(|e| format!("The page's address names no server: {e}"))?,
    };
    let first = (link.transport != WebTransportChoice::WebSocket && page::has_web_transport())
        .then(|| PageSocket::new(PageWay::WebTransport(link.cert.clone())));
    let fallback = (link.transport != WebTransportChoice::WebTransport).then(|| {
        Noised::new(
            PageSocket::new(PageWay::WebSocket),
            link.key,
            page::fill_random,
        )
    });
    if first.is_none() && fallback.is_none() {
        return Err(
            "This browser has no WebTransport here, and the link allows nothing else".into(),
        );
    }
    // The page trusts the server by the link's key and certificate hashes, never by the
    // native certificate's fingerprint, which it has no way to check.
    let invite = Invite {
        servers: vec![server],
        room,
        fingerprint: Fingerprint([0; 32]),
    };
    Ok((invite, WebWay::new(first, fallback)))
}

/// A session to the server of `invite` over `way`, connecting at once (and again when the
/// connection drops), advanced each time the frame loop polls it.
pub(crate) fn session(invite: &Invite, way: Way) -> PolledSession<Way> {
    let core = PlayerCore::new(
        invite.clone(),
        Reconnect::default(),
        breakshot_client::net::for_connection(),
        clock::now(),
    );
    PolledSession::new(Polled::new(core, way), clock::now)
}

/// Joins (or watches) the game of the link's room.
pub(crate) fn join_link() -> Result<Box<dyn GameLink>, String> {
    let link = usable_link()?;
    let room = link
        .room
        .clone()
        .ok_or("This page's link names no game: ask the host for the game's link")?;
    let (invite, way) = way_to_server(link, Some(room.clone()))?;
    let session = session(&invite, way);
    let game: NetLink<_> = if link.watch {
        let mut session = session;
        session.enter(Entry::Spectate { room });
        NetLink::new(session)
    } else {
        // The seat taken is kept in the page's storage: a reload takes it back.
        let name = player_name(link);
        page::report(&format!("joining as {name}"));
        NetLink::joining(session, invite, &name, Some(SeatStore::page()))
            .map_err(|e| e.to_string())?
    };
    Ok(match link.computer {
        Some(level) => Box::new(PlayedByComputer::new(game, level, clock::fresh_seed())),
        None => Box::new(game),
    })
}
