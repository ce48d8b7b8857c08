//! *Find a game*: a server's lobby. It lists the public rooms waiting for a player (join
//! with one click) and the games in play (watch with one click), a page at a time, and
//! offers a quick match. The server is the invite on the clipboard, else the one whose lobby
//! was opened last (remembered in the data directory).

use breakshot_client::memory;
use std::collections::VecDeque;

use breakshot_client::net::{Entry, NetLink, Port, SeatStore, Seating, Session, SessionEvent};
use breakshot_client::play::{InputFrame, Key};
use breakshot_client::view::{hud::variant_name, lobby_bar, lobby_row, Rect, LOBBY_BAR};
use breakshot_shared::protocol::{ClientMessage, GameInPlay, Invite, ServerMessage, WaitingRoom};
use breakshot_shared::rules::{EightBallRules, Settings, Variant};
use macroquad::prelude::*;

use super::draw::{self, Align};
use super::{Start, Step};

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
    session: Session,
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
    session: Session,
    /// Players waiting in the queue, as the server last said.
    waiting: u32,
    /// When the wait began (seconds, the window's clock).
    since: f64,
}

pub struct LobbyScreen {
    server: Option<Invite>,
    session: Option<Session>,
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

/// The server to show: the invite on the clipboard, else the one remembered.
fn server() -> Option<Invite> {
    let clipboard =
        macroquad::miniquad::window::clipboard_get().and_then(|t| t.trim().parse::<Invite>().ok());
    let remembered = || crate::ui::data_dir().and_then(|d| memory::last_server(&d));
    clipboard.or_else(remembered).map(|mut i| {
        i.room = None;
        i
    })
}

/// The player's name, as the menu's other games use it.
fn name() -> String {
    crate::ui::data_dir()
        .and_then(|d| memory::player_name(&d, None).ok())
        .unwrap_or_else(|| "player".to_owned())
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
        let server = server();
        let message = match &server {
            Some(_) => "Connecting...".to_owned(),
            None => "Copy a server's address (breakshot://...) and press Refresh".to_owned(),
        };
        let mut screen = LobbyScreen {
            server: None,
            session: None,
            queue: None,
            page: 0,
            pages: 1,
            waiting: Vec::new(),
            playing: Vec::new(),
            message,
            mouse: [-1.0, -1.0],
            asked: f64::NEG_INFINITY,
        };
        screen.connect(server);
        screen
    }

    fn connect(&mut self, server: Option<Invite>) {
        let Some(server) = server else { return };
        if let Some(data) = crate::ui::data_dir() {
            let _ = memory::remember_server(&data, &server);
        }
        self.session = Some(Session::connect(server.clone()));
        self.server = Some(server);
    }

    fn ask(&mut self) {
        let now = get_time();
        if now - self.asked < REFRESH {
            return;
        }
        if let Some(s) = &self.session {
            if s.send(ClientMessage::ListGames { page: self.page }) {
                self.asked = now;
            }
        }
    }

    /// The buttons: one per row (join or watch), then the bar at the bottom.
    fn layout(&self) -> Vec<(Click, &'static str, Rect)> {
        let (w, h) = (screen_width(), screen_height());
        let row_h = lobby_row(h);
        let button_w = (0.14 * w).max(90.0);
        let x = w - 0.06 * w - button_w;
        let mut out = Vec::new();
        let mut y = 0.2 * h;
        let join: fn(usize) -> Click = Click::Join;
        let lists = [
            (self.waiting.len(), join, "Join"),
            (self.playing.len(), Click::Watch, "Watch"),
        ];
        for (rows, click, label) in lists {
            for i in 0..rows {
                out.push((click(i), label, Rect::new(x, y, button_w, row_h * 0.9)));
                y += row_h;
            }
            // A row's gap after the waiting rooms, before the games to watch.
            y += row_h;
        }
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
        if let Some(session) = &mut self.session {
            while let Some(event) = session.try_recv() {
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
                        (self.page, self.pages) = (page, pages);
                        (self.waiting, self.playing) = (waiting, playing);
                        if self.waiting.is_empty() && self.playing.is_empty() {
                            self.message = "No public game right now: try a quick match".to_owned();
                        }
                    }
                    SessionEvent::Message(ServerMessage::Draining { message })
                    | SessionEvent::Message(ServerMessage::Error { message, .. }) => {
                        self.message = message;
                    }
                    SessionEvent::Closed(why) => {
                        self.message = format!("No connection: {why}");
                        self.session = None;
                        break;
                    }
                    _ => {}
                }
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
    fn poll_queue(&mut self) -> Option<Box<dyn breakshot_client::play::GameLink>> {
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
                    self.message = reason;
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
        let Some(server) = self.server.clone() else {
            if click == Click::Back {
                return Step::Open(Start::Menu);
            }
            self.connect(server());
            return Step::Stay;
        };
        match click {
            Click::Join(i) => {
                let Some(w) = self.waiting.get(i) else {
                    return Step::Stay;
                };
                let invite = Invite {
                    room: Some(w.room.clone()),
                    ..server
                };
                let seats = crate::ui::data_dir().map(|d| SeatStore::new(&d));
                match NetLink::join(invite, &name(), seats) {
                    Ok(link) => return Step::Open(Start::Network(Box::new(link))),
                    Err(e) => self.message = e.to_string(),
                }
            }
            Click::Watch(i) => {
                let Some(g) = self.playing.get(i) else {
                    return Step::Stay;
                };
                let session = Session::connect(server);
                session.enter(Entry::Spectate {
                    room: g.room.clone(),
                });
                return Step::Open(Start::Network(Box::new(NetLink::new(session))));
            }
            Click::QuickMatch => match self.queue.take() {
                // Leaving the queue; closing the connection would take the player out too.
                Some(queue) => {
                    queue.session.send(ClientMessage::LeaveQueue);
                    self.message = "You left the queue".into();
                }
                None => {
                    let session = Session::connect(server);
                    session.enter(Entry::QuickMatch(ClientMessage::QuickMatch {
                        variant: Variant::EightBall(EightBallRules::Wpa),
                        mode: Settings::online(),
                        name: name(),
                    }));
                    self.queue = Some(Queue {
                        session,
                        waiting: 0,
                        since: get_time(),
                    });
                }
            },
            Click::Refresh => {
                if self.session.is_none() {
                    self.connect(Some(server));
                } else {
                    self.ask();
                }
            }
            Click::Previous if self.page > 0 => {
                self.page -= 1;
                self.ask();
            }
            Click::Next if self.page + 1 < self.pages => {
                self.page += 1;
                self.ask();
            }
            Click::Previous | Click::Next => {}
            Click::Back => return Step::Open(Start::Menu),
        }
        Step::Stay
    }

    pub fn draw(&mut self) {
        let (w, h) = (screen_width(), screen_height());
        let title = "FIND A GAME";
        let size = 48.0f32.min(0.08 * h);
        draw::centred(title, 0.1 * h, size, WHITE);
        let row_h = lobby_row(h);
        let text_w = 0.7 * w;
        let line = |text: &str, y: f32, c: Color| {
            draw::label_in(
                text,
                Rect::new(0.06 * w, y, text_w, row_h * 0.9),
                22.0,
                Align::Left,
                c,
            );
        };
        let heading = Color::from_rgba(200, 220, 200, 255);
        line("Waiting for a player", 0.2 * h - row_h, heading);
        let mut y = 0.2 * h;
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
