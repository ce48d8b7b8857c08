//! *Find a game*: a server's lobby. It lists the public rooms waiting for a player (join
//! with one click) and the games in play (watch with one click), a page at a time, and
//! offers a quick match. The same screen in the window and in the page: only where the
//! server comes from and how a connection to it is opened differ (`reach`).

use std::collections::VecDeque;

use breakshot_client::net::{Entry, NetLink, Port, Seating, SessionEvent};
use breakshot_client::play::{GameLink, InputFrame, Key};
use breakshot_client::view::{
    hud::variant_name, lobby_bar, lobby_line, lobby_row, lobby_rows, lobby_top, Rect, LOBBY_BAR,
};
use breakshot_shared::protocol::{ClientMessage, GameInPlay, ServerMessage, WaitingRoom};
use breakshot_shared::rules::{EightBallRules, Settings, Variant};
use macroquad::prelude::*;

use super::draw::{self, Align};
use super::{report, Start, Step};

// The window's clipboard and data directory, or the page's link.
#[cfg_attr(not(target_arch = "wasm32"), path = "lobby/native.rs")]
#[cfg_attr(target_arch = "wasm32", path = "lobby/page.rs")]
mod reach;

use reach::Server;

/// The least time between two pages asked for (the server limits them too).
const REFRESH: f64 = 1.0;

/// What a click on the screen does.
#[derive(Clone, Debug, PartialEq)]
enum Click {
    Join(usize),
    Watch(usize),
    QuickMatch,
    Refresh,
    Previous,
    Next,
    Back,
}

/// A session that found its match while this screen watched it: the events it read (the
/// connection and the room joined) are handed to the game screen first, as if unread.
struct Matched {
    session: Box<dyn Port>,
    unread: VecDeque<SessionEvent>,
}

impl Port for Matched {
    fn send(&mut self, msg: ClientMessage) -> bool {
        self.session.send(msg)
    }

    fn enter(&mut self, entry: Entry) -> bool {
        self.session.enter(entry)
    }

    fn try_recv(&mut self) -> Option<SessionEvent> {
        self.unread.pop_front().or_else(|| self.session.try_recv())
    }

    fn seating(&self) -> &Seating {
        self.session.seating()
    }
}

/// Waiting in the quick-match queue, on a connection of its own.
struct Queue {
    session: Box<dyn Port>,
    /// Players waiting in the queue, as the server last said.
    waiting: u32,
    /// When the wait began (seconds, the window's clock).
    since: f64,
}

pub struct LobbyScreen {
    server: Option<Server>,
    session: Option<Box<dyn Port>>,
    queue: Option<Queue>,
    page: u32,
    pages: u32,
    waiting: Vec<WaitingRoom>,
    playing: Vec<GameInPlay>,
    message: String,
    mouse: [f32; 2],
    /// When a page was last asked for (seconds, the window's clock).
    asked: f64,
}

/// A rating as shown beside a name.
fn rated(name: &str, rating: Option<i32>) -> String {
    match rating {
        Some(r) => format!("{name} ({r})"),
        None => name.to_owned(),
    }
}

/// One waiting room's line: the game, its rules, the host and how long it has waited.
pub fn waiting_line(w: &WaitingRoom) -> String {
    let clock = match w.mode.shot_clock {
        Some(s) => format!("{s} s a shot"),
        None => "no shot clock".into(),
    };
    let calls = if w.mode.call_every_shot {
        ", every shot called"
    } else {
        ""
    };
    format!(
        "{} · {clock}{calls} · {} · waiting {}:{:02}",
        variant_name(w.variant),
        rated(&w.host, w.rating),
        w.waited_s / 60,
        w.waited_s % 60
    )
}

/// One game in play's line: the game and both players.
pub fn playing_line(g: &GameInPlay) -> String {
    format!(
        "{} · {} v {}{}",
        variant_name(g.variant),
        rated(&g.names[0], g.ratings[0]),
        rated(&g.names[1], g.ratings[1]),
        if g.rated { " · rated" } else { "" }
    )
}

impl LobbyScreen {
    pub fn new() -> LobbyScreen {
        let mut screen = LobbyScreen {
            server: None,
            session: None,
            queue: None,
            page: 0,
            pages: 1,
            waiting: Vec::new(),
            playing: Vec::new(),
            message: String::new(),
            mouse: [-1.0, -1.0],
            asked: f64::NEG_INFINITY,
        };
        screen.connect();
        screen
    }

    /// Shows `message` on the status line (and tells whoever watches).
    fn say(&mut self, message: String) {
        report(&format!("lobby says {message}"));
        self.message = message;
    }

    /// Connects to the server found (the one already found, else looks for one).
    fn connect(&mut self) {
        let found = match self.server.take() {
            Some(server) => Ok(server),
            None => Server::find(),
        };
        let opened = found.and_then(|server| {
            let session = server.connect();
            self.server = Some(server);
            session
        });
        match opened {
            Ok(session) => {
                self.session = Some(session);
                self.say("Connecting...".to_owned());
            }
            Err(why) => self.say(why),
        }
    }

    fn ask(&mut self) {
        let now = get_time();
        if now - self.asked < REFRESH {
            return;
        }
        if let Some(s) = &mut self.session {
            if s.send(ClientMessage::ListGames { page: self.page }) {
                self.asked = now;
            }
        }
    }

    /// The buttons: one per row (join or watch), then the bar at the bottom.
    fn layout(&self) -> Vec<(Click, &'static str, Rect)> {
        let (w, h) = (screen_width(), screen_height());
        let (join, watch) = lobby_rows(w, h, self.waiting.len(), self.playing.len());
        let mut out: Vec<(Click, &'static str, Rect)> = Vec::new();
        out.extend(
            join.into_iter()
                .enumerate()
                .map(|(i, r)| (Click::Join(i), "Join", r)),
        );
        out.extend(
            watch
                .into_iter()
                .enumerate()
                .map(|(i, r)| (Click::Watch(i), "Watch", r)),
        );
        let quick = if self.queue.is_some() {
            "Cancel"
        } else {
            "Quick match"
        };
        let bar: [(Click, &'static str); LOBBY_BAR] = [
            (Click::QuickMatch, quick),
            (Click::Refresh, "Refresh"),
            (Click::Previous, "< Page"),
            (Click::Next, "Page >"),
            (Click::Back, "Back"),
        ];
        for ((click, name), r) in bar.into_iter().zip(lobby_bar(w, h)) {
            out.push((click, name, r));
        }
        out
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        self.mouse = input.mouse;
        let mut connected = false;
        while let Some(event) = self.session.as_mut().and_then(|s| s.try_recv()) {
            match event {
                SessionEvent::Connected => {
                    self.message = String::new();
                    connected = true;
                }
                SessionEvent::Message(ServerMessage::Games {
                    page,
                    pages,
                    waiting,
                    playing,
                }) => {
                    report(&format!(
                        "lobby page {} of {pages}: waiting={} playing={}",
                        page + 1,
                        waiting.len(),
                        playing.len()
                    ));
                    (self.page, self.pages) = (page, pages);
                    (self.waiting, self.playing) = (waiting, playing);
                    if self.waiting.is_empty() && self.playing.is_empty() {
                        self.message = "No public game right now: try a quick match".to_owned();
                    }
                }
                SessionEvent::Message(ServerMessage::Draining { message })
                | SessionEvent::Message(ServerMessage::Error { message, .. }) => {
                    self.say(message);
                }
                SessionEvent::Closed(why) => {
                    self.say(format!("No connection: {why}"));
                    self.session = None;
                }
                _ => {}
            }
        }
        if connected {
            self.asked = f64::NEG_INFINITY;
            self.ask();
        }
        if let Some(link) = self.poll_queue() {
            return Step::Open(Start::Network(link));
        }
        if input.pressed.contains(&Key::Back) {
            return Step::Open(Start::Menu);
        }
        if !input.left_pressed {
            return Step::Stay;
        }
        let Some((click, _, _)) = self
            .layout()
            .into_iter()
            .find(|(_, _, r)| r.contains(input.mouse))
        else {
            return Step::Stay;
        };
        self.clicked(click)
    }

    /// Follows the wait for a quick match; once a room is joined, the game's link.
    fn poll_queue(&mut self) -> Option<Box<dyn GameLink>> {
        let queue = self.queue.as_mut()?;
        let mut unread = VecDeque::new();
        while let Some(event) = queue.session.try_recv() {
            match event {
                SessionEvent::Message(ServerMessage::Queued { waiting, .. }) => {
                    queue.waiting = waiting;
                }
                SessionEvent::Message(ServerMessage::Joined { .. }) => {
                    unread.push_back(event);
                    let queue = self.queue.take()?;
                    let matched = Matched {
                        session: queue.session,
                        unread,
                    };
                    return Some(Box::new(NetLink::new(matched)));
                }
                SessionEvent::Message(ServerMessage::Unqueued { reason })
                | SessionEvent::Message(ServerMessage::Error {
                    message: reason, ..
                })
                | SessionEvent::Closed(reason) => {
                    self.say(reason);
                    self.queue = None;
                    return None;
                }
                SessionEvent::Connected => unread.push_back(event),
                _ => {}
            }
        }
        None
    }

    fn clicked(&mut self, click: Click) -> Step {
        if click == Click::Back {
            return Step::Open(Start::Menu);
        }
        let Some(server) = &self.server else {
            // No server yet: a click looks for one again (an invite may be on the clipboard
            // now).
            self.connect();
            return Step::Stay;
        };
        match click {
            Click::Join(i) => {
                let Some(w) = self.waiting.get(i) else {
                    return Step::Stay;
                };
                let invite = server.invite(w.room.clone());
                let joined = server.connect().and_then(|session| {
                    NetLink::joining(session, invite, &server.player_name(), server.seats())
                        .map_err(|e| e.to_string())
                });
                match joined {
                    Ok(link) => return Step::Open(Start::Network(Box::new(link))),
                    Err(e) => self.say(e),
                }
            }
            Click::Watch(i) => {
                let Some(g) = self.playing.get(i) else {
                    return Step::Stay;
                };
                let room = g.room.clone();
                match server.connect() {
                    Ok(mut session) => {
                        session.enter(Entry::Spectate { room });
                        return Step::Open(Start::Network(Box::new(NetLink::new(session))));
                    }
                    Err(e) => self.say(e),
                }
            }
            Click::QuickMatch => match self.queue.take() {
                // Leaving the queue; closing the connection would take the player out too.
                Some(mut queue) => {
                    queue.session.send(ClientMessage::LeaveQueue);
                    self.say("You left the queue".into());
                }
                None => {
                    let ask = ClientMessage::QuickMatch {
                        variant: Variant::EightBall(EightBallRules::Wpa),
                        mode: Settings::online(),
                        name: server.player_name(),
                    };
                    match server.connect() {
                        Ok(mut session) => {
                            session.enter(Entry::QuickMatch(ask));
                            report("lobby queued for a quick match");
                            self.queue = Some(Queue {
                                session,
                                waiting: 0,
                                since: get_time(),
                            });
                        }
                        Err(e) => self.say(e),
                    }
                }
            },
            Click::Refresh if self.session.is_none() => self.connect(),
            Click::Refresh => self.ask(),
            Click::Previous if self.page > 0 => {
                self.page -= 1;
                self.ask();
            }
            Click::Next if self.page + 1 < self.pages => {
                self.page += 1;
                self.ask();
            }
            Click::Previous | Click::Next | Click::Back => {}
        }
        Step::Stay
    }

    pub fn draw(&mut self) {
        let (w, h) = (screen_width(), screen_height());
        let title = "FIND A GAME";
        let size = 48.0f32.min(0.08 * h);
        draw::centred(title, 0.1 * h, size, WHITE);
        let row_h = lobby_row(h);
        let line = |text: &str, y: f32, c: Color| {
            draw::label_in(text, lobby_line(w, h, y), 22.0, Align::Left, c);
        };
        let heading = Color::from_rgba(200, 220, 200, 255);
        let mut y = lobby_top(h);
        line("Waiting for a player", y - row_h, heading);
        for room in &self.waiting {
            line(&waiting_line(room), y, WHITE);
            y += row_h;
        }
        line("Games in play", y, heading);
        y += row_h;
        for game in &self.playing {
            line(&playing_line(game), y, WHITE);
            y += row_h;
        }
        for (_, name, r) in self.layout() {
            let fill = if r.contains(self.mouse) {
                Color::from_rgba(40, 130, 90, 255)
            } else {
                Color::from_rgba(24, 104, 74, 255)
            };
            draw_rectangle(r.x, r.y, r.w, r.h, fill);
            draw::label_in(name, r, 24.0, Align::Centre, WHITE);
        }
        let status = if let Some(q) = &self.queue {
            let waited = (get_time() - q.since).max(0.0) as u32;
            format!(
                "Looking for an 8-ball opponent of your level: {} waiting, {}:{:02}",
                q.waiting,
                waited / 60,
                waited % 60
            )
        } else if self.message.is_empty() {
            format!("Page {} of {}", self.page + 1, self.pages)
        } else {
            self.message.clone()
        };
        line(&status, h - 3.0 * row_h, heading);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::protocol::RoomCode;

    #[test]
    fn a_line_names_the_game_its_rules_the_host_and_the_wait() {
        let w = WaitingRoom {
            room: RoomCode::parse("K7QX2M4B").unwrap(),
            variant: Variant::NineBall,
            mode: Settings::online(),
            host: "ann".into(),
            rating: Some(1620),
            waited_s: 75,
        };
        let text = waiting_line(&w);
        assert!(text.starts_with("9-ball · "), "{text}");
        assert!(text.contains("ann (1620)"), "{text}");
        assert!(text.ends_with("waiting 1:15"), "{text}");
        let g = GameInPlay {
            room: w.room.clone(),
            variant: Variant::NineBall,
            names: ["ann".into(), "bob".into()],
            ratings: [Some(1620), None],
            rated: true,
        };
        assert_eq!(playing_line(&g), "9-ball · ann (1620) v bob · rated");
    }
}
