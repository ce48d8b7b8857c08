//! The browser's start: the page's link (docs/web.md) chooses the first screen, and the game
//! reaches the server through the page's plugin, WebTransport first, else the WebSocket
//! under Noise. Whatever goes wrong is said on the page, never left as a blank canvas.

use breakshot_client::net::noise::Noised;
use breakshot_client::net::page::{self, PageSocket, Way as PageWay};
use breakshot_client::net::{
    interpret_record, Entry, NetLink, PlayerCore, PlayerEvent, Polled, PolledSession, Port,
    Reconnect, SeatStore, WebWay, FETCH_TIMEOUT,
};
use breakshot_client::play::{GameLink, PlayedByComputer, ReplayViewer};
use breakshot_shared::protocol::{
    is_valid_name, ClientMessage, Fingerprint, Invite, RoomCode, ServerAddress, ServerMessage,
    WebLink, WebLinkError, WebTransportChoice,
};

use crate::ui::{self, clock};

/// The name a page's player goes by when no link has named them yet.
const PAGE_NAME: &str = "Guest";
/// Where the page keeps the name last given (`name=` in a link) for the next visit.
const NAME_KEY: &str = "breakshot.name";

/// The player's name: the link's `name=` (kept for next time), else the name kept from an
/// earlier visit, else [`PAGE_NAME`].
fn player_name(link: &WebLink) -> String {
    if let Some(name) = &link.name {
        page::store(NAME_KEY, name);
        return name.clone();
    }
    page::stored(NAME_KEY)
        .map(|n| n.trim().to_owned())
        .filter(|n| is_valid_name(n))
        .unwrap_or_else(|| PAGE_NAME.to_owned())
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
        let start = match page::link() {
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
    match page::link() {
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
    page::link()
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
    let core = PlayerCore::new(invite.clone(), Reconnect::default(), clock::now());
    let session = PolledSession::new(Polled::new(core, way), clock::now);
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
        PlayerCore::new(invite, Reconnect::never(), clock::now()),
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
