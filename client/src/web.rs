//! The browser's start: the page's link (docs/web.md) chooses the first screen, and the game
//! reaches the server through the page's plugin, WebTransport first, else the WebSocket
//! under Noise. Whatever goes wrong is said on the page, never left as a blank canvas.

use std::sync::OnceLock;

use breakshot_client::net::noise::Noised;
use breakshot_client::net::page::{self, PageSocket, Way as PageWay};
use breakshot_client::net::{
    interpret_record, Entry, NetLink, PlayerCore, PlayerEvent, Polled, PolledSession, Port,
    Reconnect, WebWay, FETCH_TIMEOUT,
};
use breakshot_client::play::{GameLink, PlayedByComputer, ReplayViewer};
use breakshot_shared::protocol::{
    ClientMessage, Fingerprint, Invite, RoomCode, ServerAddress, ServerMessage, WebLink,
    WebLinkError, WebTransportChoice,
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
        // First, so that a reason told below stays on the status line.
        page::report("started");
        let start = match page_link() {
            Ok(link) if link.replay => match fetch_replay(link).await {
                Ok(viewer) => ui::Start::Replay(Box::new(viewer)),
                Err(why) => {
                    page::report(&format!("status {why}"));
                    ui::Start::Menu
                }
            },
            _ => first_screen(),
        };
        let options = ui::Options {
            screenshot: None,
            frames: 0,
            seed: None,
            view: None,
            data: None,
        };
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

/// The link, read, or why it cannot be used.
fn usable_link() -> Result<&'static WebLink, String> {
    page_link()
        .as_ref()
        .map_err(|e| format!("This link is damaged ({e}): ask for a new one"))
}

/// The page's way to the game server of `link`: the invite the player core dials and the
/// transports to try.
type Way = WebWay<PageSocket, Noised<PageSocket>>;

fn way_to_server(link: &WebLink, room: RoomCode) -> Result<(Invite, Way), String> {
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
        room: Some(room),
        fingerprint: Fingerprint([0; 32]),
    };
    Ok((invite, WebWay::new(first, fallback)))
}

/// Joins (or watches) the game of the link's room.
pub fn join_link() -> Result<Box<dyn GameLink>, String> {
    let link = usable_link()?;
    let room = link
        .room
        .clone()
        .ok_or("This page's link names no game: ask the host for the game's link")?;
    let (invite, way) = way_to_server(link, room.clone())?;
    let core = PlayerCore::new(
        invite.clone(),
        Reconnect::default(),
        breakshot_client::net::for_connection(),
        clock::now(),
    );
    let session = PolledSession::new(Polled::new(core, way), clock::now);
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

/// Fetches the record of the link's room from the server, saying so on the canvas while it
/// waits (at most [`FETCH_TIMEOUT`]).
async fn fetch_replay(link: &WebLink) -> Result<ReplayViewer, String> {
    let room = link
        .room
        .clone()
        .ok_or("This replay link names no game: ask for the game's link")?;
    let (invite, way) = way_to_server(link, room.clone())?;
    let mut polled = Polled::new(
        PlayerCore::new(
            invite,
            Reconnect::never(),
            breakshot_client::net::for_connection(),
            clock::now(),
        ),
        way,
    );
    let deadline = clock::now() + FETCH_TIMEOUT;
    loop {
        polled.update(clock::now());
        while let Some(event) = polled.poll_event() {
            match event {
                PlayerEvent::Connected => {
                    let ask = ClientMessage::FetchRecord {
                        room: room.clone(),
                        game: None,
                    };
                    polled.send(&ask).map_err(|e| e.to_string())?;
                }
                PlayerEvent::Message(
                    msg @ (ServerMessage::Record { .. } | ServerMessage::Error { .. }),
                ) => {
                    let fetched = interpret_record(&room, msg).map_err(|e| e.to_string())?;
                    return ReplayViewer::decode(&fetched.bytes)
                        .map_err(|e| format!("The server sent an unreadable record: {e}"));
                }
                PlayerEvent::Closed(e) => return Err(format!("Cannot fetch the game: {e}")),
                _ => {}
            }
        }
        if clock::now() > deadline {
            return Err(format!(
                "No answer from the server within {} s",
                FETCH_TIMEOUT.as_secs()
            ));
        }
        macroquad::prelude::clear_background(macroquad::prelude::BLACK);
        let text = format!("Fetching the game of room {room}...");
        macroquad::prelude::draw_text(&text, 20.0, 40.0, 28.0, macroquad::prelude::WHITE);
        macroquad::prelude::next_frame().await;
    }
}
