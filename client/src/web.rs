//! The browser's start: the page's link (docs/web.md) chooses the first screen, and the game
//! reaches the server through the page's plugin, WebTransport first, else the WebSocket
//! under Noise. Whatever goes wrong is said on the page, never left as a blank canvas.

use breakshot_client::net::page;
use breakshot_client::net::{
    interpret_record, PlayerCore, PlayerEvent, Polled, Reconnect, FETCH_TIMEOUT,
};
use breakshot_client::play::ReplayViewer;
use breakshot_shared::protocol::{ClientMessage, ServerMessage, WebLink, WebLinkError};

use crate::ui::page_game::{join_link, way_to_server};
use crate::ui::{self, clock};

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

/// Fetches the record of the link's room from the server, saying so on the canvas while it
/// waits (at most [`FETCH_TIMEOUT`]).
async fn fetch_replay(link: &WebLink) -> Result<ReplayViewer, String> {
    let room = link
        .room
        .clone()
        .ok_or("This replay link names no game: ask for the game's link")?;
    let (invite, way) = way_to_server(link, Some(room.clone()))?;
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
