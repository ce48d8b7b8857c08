//! The menu's page for watching a game again: the game's invite (its server and room), the
//! room's games by number once the server has said how many, and the one chosen fetched and
//! opened. The server tells how many games a room has by numbering its latest one, so no
//! more than the one `FetchRecord` is needed to list them.

use std::sync::mpsc::{channel, Receiver, TryRecvError};

use breakshot_client::net::{fetch_game_blocking, FetchedRecord, SeatStore};
use breakshot_client::play::{InputFrame, Key, ReplayViewer};
use breakshot_client::view::{replay_page, ReplayPageBoxes};
use breakshot_shared::protocol::{Invite, RoomCode};
use macroquad::prelude::*;

use super::super::draw::{self, Align};

/// What the page asks of the menu after a frame.
pub enum PageStep {
    Stay,
    /// Back to the menu's buttons.
    Back,
    /// Watch this game.
    Watch(Box<ReplayViewer>),
}

/// The room whose games are listed.
struct Listed {
    server: Invite,
    room: RoomCode,
    /// The latest game's number: the room has games 1 to `latest`.
    latest: u32,
    /// Whether the latest game is over (else it is still being played).
    finished: bool,
}

/// What a fetch under way is for.
enum Asked {
    /// The latest game, for how many there are.
    List(Invite, RoomCode),
    /// One game, to watch it.
    Game(u32),
}

pub struct ReplayPage {
    /// The invite as typed (or found on the clipboard or among the remembered games).
    text: String,
    listed: Option<Listed>,
    /// A fetch under way on its own thread, so the window keeps drawing.
    pending: Option<(Asked, Receiver<Result<FetchedRecord, String>>)>,
    message: String,
}

impl ReplayPage {
    /// The page, its invite line filled with the clipboard's invite if it names a room, else
    /// with the game this computer played last.
    pub fn open() -> ReplayPage {
        let clipboard = macroquad::miniquad::window::clipboard_get()
            .and_then(|t| t.trim().parse::<Invite>().ok())
            .filter(|i| i.room.is_some());
        let remembered = || {
            let data = crate::ui::data_dir()?;
            let last = SeatStore::new(&data).all().into_iter().next()?;
            Some(last.invite)
        };
        let text = clipboard
            .or_else(remembered)
            .map(|i| i.to_string())
            .unwrap_or_default();
        ReplayPage {
            text,
            listed: None,
            pending: None,
            message: "Type or paste a game's invite, then list its games".into(),
        }
    }

    /// The page takes the keys while it is open: the invite is typed here.
    pub fn typing(&self) -> bool {
        true
    }

    /// The games listed, first to last, with the button of each.
    fn buttons(&self) -> (ReplayPageBoxes, u32) {
        let count = self.listed.as_ref().map_or(0, |l| l.latest as usize);
        let boxes = replay_page(screen_width(), screen_height(), count);
        // As many as fit, the latest ones.
        let first = (count - boxes.games.len()) as u32 + 1;
        (boxes, first)
    }

    pub fn update(&mut self, input: &InputFrame) -> PageStep {
        if let Some(step) = self.poll() {
            return step;
        }
        for key in &input.pressed {
            match key {
                Key::Back => return PageStep::Back,
                Key::Erase => {
                    self.text.pop();
                }
                Key::Send => self.list(),
                // An invite copied from a chat or a mail goes in whole.
                Key::Paste => {
                    let pasted = macroquad::miniquad::window::clipboard_get().unwrap_or_default();
                    self.text.push_str(pasted.trim());
                }
                _ => {}
            }
        }
        self.text.extend(&input.typed);
        if !input.left_pressed {
            return PageStep::Stay;
        }
        let (boxes, first) = self.buttons();
        if boxes.back.contains(input.mouse) {
            return PageStep::Back;
        }
        if boxes.list.contains(input.mouse) {
            self.list();
        }
        if let Some(k) = boxes.games.iter().position(|r| r.contains(input.mouse)) {
            self.watch(first + k as u32);
        }
        PageStep::Stay
    }

    /// Asks the server of the invite typed for its room's latest game: its number says how
    /// many games there are.
    fn list(&mut self) {
        // What was typed or pasted, for whoever watches (the window's tests).
        super::super::report(&format!("replays list {}", self.text.trim()));
        let invite: Invite = match self.text.trim().parse() {
            Ok(i) => i,
            Err(e) => {
                self.message = format!("That is not an invite ({e})");
                return;
            }
        };
        let Some(room) = invite.room.clone() else {
            self.message = "This invite names no room: use the one the game was played with".into();
            return;
        };
        self.message = format!(
            "Asking {} for the games of room {room}...",
            invite.authority()
        );
        self.fetch(
            Asked::List(invite.clone(), room.clone()),
            invite,
            room,
            None,
        );
    }

    /// Fetches game `number` of the room listed, to watch it.
    fn watch(&mut self, number: u32) {
        let Some(l) = &self.listed else { return };
        let (server, room) = (l.server.clone(), l.room.clone());
        self.message = format!("Fetching game {number} of room {room}...");
        self.fetch(Asked::Game(number), server, room, Some(number));
    }

    fn fetch(&mut self, asked: Asked, server: Invite, room: RoomCode, number: Option<u32>) {
        if self.pending.is_some() {
            return;
        }
        let (tell, answer) = channel();
        let spawned = std::thread::Builder::new()
            .name("fetch-record".into())
            .spawn(move || {
                let fetched =
                    fetch_game_blocking(&server, &room, number).map_err(|e| e.to_string());
                let _ = tell.send(fetched);
            });
        match spawned {
            Ok(_) => self.pending = Some((asked, answer)),
            Err(e) => self.message = format!("Cannot fetch: {e}"),
        }
    }

    /// The fetch's answer, once it has come.
    fn poll(&mut self) -> Option<PageStep> {
        let (asked, answer) = self.pending.as_ref()?;
        let got = match answer.try_recv() {
            Ok(got) => got,
            Err(TryRecvError::Empty) => return None,
            Err(TryRecvError::Disconnected) => Err("the fetch stopped".to_owned()),
        };
        let asked = match asked {
            Asked::List(server, room) => Asked::List(server.clone(), room.clone()),
            Asked::Game(n) => Asked::Game(*n),
        };
        self.pending = None;
        match (asked, got) {
            (_, Err(why)) => self.message = format!("Cannot fetch: {why}"),
            (Asked::List(server, room), Ok(latest)) => {
                self.message = format!(
                    "Room {room} has {} game{}: choose one",
                    latest.game,
                    if latest.game == 1 { "" } else { "s" }
                );
                self.listed = Some(Listed {
                    server,
                    room,
                    latest: latest.game,
                    finished: latest.finished,
                });
            }
            (Asked::Game(n), Ok(fetched)) => match ReplayViewer::decode(&fetched.bytes) {
                Ok(viewer) => return Some(PageStep::Watch(Box::new(viewer))),
                Err(e) => self.message = format!("Game {n} came as an unreadable record: {e}"),
            },
        }
        Some(PageStep::Stay)
    }

    pub fn draw(&self, mouse: [f32; 2]) {
        let (w, h) = (screen_width(), screen_height());
        let title = "Watch a replay";
        let size = 40.0f32.min(0.08 * h);
        draw::centred(title, 0.16 * h, size, WHITE);
        let (boxes, first) = self.buttons();
        // The invite line, with a caret: it is where typing goes.
        let f = boxes.field;
        draw_rectangle(f.x, f.y, f.w, f.h, Color::from_rgba(10, 30, 24, 255));
        draw_rectangle_lines(f.x, f.y, f.w, f.h, 2.0, LIGHTGRAY);
        let inside = breakshot_client::view::Rect::new(f.x + 8.0, f.y, f.w - 16.0, f.h);
        // The end of a long invite (its room and fingerprint) is the part being typed.
        let shown = fit_end(&format!("{}_", self.text), inside.w, 18.0);
        draw::label_in(&shown, inside, 18.0, Align::Left, WHITE);
        let button = |r: breakshot_client::view::Rect, name: &str| {
            draw::button_face(r, r.contains(mouse));
            let inside = breakshot_client::view::Rect::new(r.x + 6.0, r.y, r.w - 12.0, r.h);
            draw::label_in(name, inside, 20.0, Align::Centre, WHITE);
        };
        button(boxes.list, "List the room's games");
        button(boxes.back, "Back (Esc)");
        let latest = self.listed.as_ref().map(|l| (l.latest, l.finished));
        for (k, r) in boxes.games.iter().enumerate() {
            let n = first + k as u32;
            let name = match latest {
                Some((last, false)) if last == n => format!("Game {n} (live)"),
                _ => format!("Game {n}"),
            };
            button(*r, &name);
        }
        let line = breakshot_client::view::Rect::new(16.0, 0.93 * h, w - 32.0, 0.06 * h);
        draw::label_in(&self.message, line, 20.0, Align::Centre, YELLOW);
    }
}

/// The end of `text` that fits `w` pixels at `size`.
fn fit_end(text: &str, w: f32, size: f32) -> String {
    let chars: Vec<char> = text.chars().collect();
    (0..chars.len())
        .map(|start| chars[start..].iter().collect::<String>())
        .find(|t| draw::text_width(t, size) <= w)
        .unwrap_or_default()
}
