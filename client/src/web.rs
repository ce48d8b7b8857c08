//! The browser's start: the page's link (docs/web.md) chooses the first screen, and the game
//! reaches the server through the page's plugin, WebTransport first, else the WebSocket
//! under Noise. Whatever goes wrong is said on the page, never left as a blank canvas.

use std::sync::OnceLock;

use breakshot_client::net::noise::Noised;
use breakshot_client::net::page::{self, PageSocket, Way};
use breakshot_client::net::{
    Entry, NetLink, PlayerCore, Polled, PolledSession, Port, Reconnect, WebWay,
};
use breakshot_client::play::{GameLink, PlayedByComputer};
use breakshot_shared::protocol::{
    Fingerprint, Invite, ServerAddress, WebLink, WebLinkError, WebTransportChoice,
};

use crate::ui::{self, clock};

/// The name a page's player goes by (a page has nowhere to remember one).
const PAGE_NAME: &str = "Guest";

/// The page's link, read once.
fn page_link() -> &'static Result<WebLink, WebLinkError> {
    static LINK: OnceLock<Result<WebLink, WebLinkError>> = OnceLock::new();
    LINK.get_or_init(|| page::page_url().parse())
}

/// Whether the page's link names a game to join.
pub fn link_has_room() -> bool {
    page_link().as_ref().is_ok_and(|l| l.room.is_some())
}

pub fn main() {
    let conf = macroquad::miniquad::conf::Conf {
        window_title: "Breakshot".to_string(),
        high_dpi: true,
        ..Default::default()
    };
    macroquad::Window::from_config(conf, async {
        let start = first_screen();
        let options = ui::Options {
            screenshot: None,
            frames: 0,
            seed: None,
            view: None,
            data: None,
        };
        page::report("started");
        if let Err(e) = ui::run(start, options).await {
            page::report(&format!("status {e:#}"));
        }
    });
}

/// The game of the link's room, else the menu (with why, when the link is broken).
fn first_screen() -> ui::Start {
    match page_link() {
        Ok(link) if link.room.is_some() => match join_link() {
            Ok(game) => return ui::Start::Network(game),
            Err(why) => page::report(&format!("status {why}")),
        },
        Ok(_) | Err(WebLinkError::MissingKey) => {}
        Err(e) => page::report(&format!(
            "status This link is damaged ({e}): ask for a new one"
        )),
    }
    ui::Start::Menu
}

/// Joins (or watches) the game of the link's room.
pub fn join_link() -> Result<Box<dyn GameLink>, String> {
    let link = page_link()
        .as_ref()
        .map_err(|e| format!("This link is damaged ({e}): ask for a new one"))?;
    let room = link
        .room
        .clone()
        .ok_or("This page's link names no game: ask the host for the game's link")?;
    let server = match &link.server {
        Some(server) => server.clone(),
        None => page::page_host()
            .parse::<ServerAddress>()
            .map_err(|e| format!("The page's address names no server: {e}"))?,
    };
    let first = (link.transport != WebTransportChoice::WebSocket && page::has_web_transport())
        .then(|| PageSocket::new(Way::WebTransport(link.cert.clone())));
    let fallback = (link.transport != WebTransportChoice::WebTransport)
        .then(|| Noised::new(PageSocket::new(Way::WebSocket), link.key, page::fill_random));
    if first.is_none() && fallback.is_none() {
        return Err(
            "This browser has no WebTransport here, and the link allows nothing else".into(),
        );
    }
    // The page trusts the server by the link's key and certificate hashes, never by the
    // native certificate's fingerprint, which it has no way to check.
    let invite = Invite {
        servers: vec![server],
        room: Some(room.clone()),
        fingerprint: Fingerprint([0; 32]),
    };
    let core = PlayerCore::new(invite.clone(), Reconnect::default(), clock::now());
    let session = PolledSession::new(Polled::new(core, WebWay::new(first, fallback)), clock::now);
    let game: NetLink<_> = if link.watch {
        let mut session = session;
        session.enter(Entry::Spectate { room });
        NetLink::new(session)
    } else {
        NetLink::joining(session, invite, PAGE_NAME, None).map_err(|e| e.to_string())?
    };
    Ok(match link.computer {
        Some(level) => Box::new(PlayedByComputer::new(game, level, ui::fresh_seed())),
        None => Box::new(game),
    })
}
