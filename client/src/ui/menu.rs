//! The menu the window opens on when no command is given.

use breakshot_client::play::{InputFrame, Key};
use breakshot_client::view::{menu_buttons, Rect};
use breakshot_shared::ai::Level;
use breakshot_shared::rules::{EightBallRules, Variant};
use macroquad::prelude::*;

use super::{draw, Start, Step};

mod drills;
#[cfg(not(target_arch = "wasm32"))]
mod replays;

#[derive(Clone, Copy, PartialEq, Eq)]
// A page offers only what a browser can do: no hosting, files or quitting.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
enum Item {
    Resume,
    Practice,
    Drills,
    Local,
    Computer,
    Host,
    Join,
    Replay,
    Quit,
    Lobby,
}

#[cfg(not(target_arch = "wasm32"))]
const ITEMS: [(Item, &str); 10] = [
    (Item::Resume, "Resume game"),
    (Item::Practice, "Practice"),
    (Item::Drills, "Drills"),
    (Item::Computer, "Play the computer"),
    (Item::Local, "Two players, one computer"),
    (Item::Lobby, "Find a game"),
    (Item::Host, "Host a game"),
    (Item::Join, "Join (invite on clipboard)"),
    (Item::Replay, "Watch a replay"),
    (Item::Quit, "Quit"),
];

#[cfg(target_arch = "wasm32")]
const ITEMS: [(Item, &str); 6] = [
    (Item::Join, "Join the game of the link"),
    (Item::Lobby, "Find a game"),
    (Item::Practice, "Practice"),
    (Item::Drills, "Drills"),
    (Item::Computer, "Play the computer"),
    (Item::Local, "Two players, one device"),
];

#[cfg(target_arch = "wasm32")]
use super::page_game::join_link as join;
#[cfg(not(target_arch = "wasm32"))]
use native::{host_default, join_from_clipboard as join, resume};

#[cfg(target_arch = "wasm32")]
fn host_default() -> Result<Box<dyn GameLink>, String> {
    Err("A page cannot host a game: run breakshot host on a computer".into())
}

#[cfg(target_arch = "wasm32")]
fn resume() -> Result<Box<dyn GameLink>, String> {
    join()
}

#[cfg(target_arch = "wasm32")]
use breakshot_client::play::GameLink;

/// What only the native window offers: hosting, resuming from the remembered seats and
/// joining from the clipboard.
#[cfg(not(target_arch = "wasm32"))]
mod native {
    use breakshot_client::memory::player_name;
    use breakshot_client::net::{hosted_from, HostOptions, NetLink, SeatStore};
    use breakshot_client::play::GameLink;
    use breakshot_shared::protocol::Invite;

    /// Hosts an 8-ball game with the defaults of `breakshot host`.
    pub(super) fn host_default() -> Result<Box<dyn GameLink>, String> {
        let data = crate::ui::data_dir()
            .ok_or("No user data directory (HOME is not set): run breakshot host --data DIR")?;
        let name = player_name(&data, None)?;
        let options = HostOptions {
            name,
            ..HostOptions::new(data)
        };
        #[cfg(feature = "host")]
        let hosted = breakshot_client::net::Host::start(&options)
            .map(|h| Box::new(h) as Box<dyn GameLink>)
            // With its causes: the error alone says only that the server could not start.
            .map_err(|e| format!("{:#}", anyhow::Error::new(e)));
        #[cfg(not(feature = "host"))]
        let hosted = {
            let _ = options;
            Err(breakshot_client::net::HostError::NotBuilt.to_string())
        };
        hosted
    }

    /// Goes back to the game whose seat this computer remembered last: hosts again when it was
    /// hosted here, else joins its invite with the remembered seat token.
    pub(super) fn resume() -> Result<Box<dyn GameLink>, String> {
        let data = crate::ui::data_dir().ok_or("No user data directory (HOME is not set)")?;
        let seats = SeatStore::new(&data);
        let Some(last) = seats.all().into_iter().next() else {
            return Err("No game to resume: host or join one first".into());
        };
        if hosted_from(&data, &last.invite.fingerprint) {
            return host_default();
        }
        let name = player_name(&data, None)?;
        let link = NetLink::join(last.invite, &name, Some(seats)).map_err(|e| e.to_string())?;
        Ok(Box::new(link))
    }

    /// Joins the game whose invite is on the clipboard.
    pub(super) fn join_from_clipboard() -> Result<Box<dyn GameLink>, String> {
        const HOW: &str = "copy the invite first, or run: breakshot join INVITE";
        let text = macroquad::miniquad::window::clipboard_get().unwrap_or_default();
        let invite: Invite = text
            .parse()
            .map_err(|e| format!("The clipboard holds no invite ({e}): {HOW}"))?;
        let data = crate::ui::data_dir();
        let name = match &data {
            Some(d) => player_name(d, None)?,
            None => "player".to_owned(),
        };
        let seats = data.map(|d| SeatStore::new(&d));
        NetLink::join(invite, &name, seats)
            .map(|link| Box::new(link) as Box<dyn GameLink>)
            .map_err(|e| e.to_string())
    }
}

pub struct MenuScreen {
    message: String,
    /// The page for watching a game again, when open.
    #[cfg(not(target_arch = "wasm32"))]
    replays: Option<Box<replays::ReplayPage>>,
    /// The page of drills, when open.
    drills: Option<drills::DrillsPage>,
    /// Where the mouse was at the last update (input is read in `ui/input.rs` only).
    mouse: [f32; 2],
}

impl MenuScreen {
    pub fn new() -> MenuScreen {
        MenuScreen::with_message(String::new())
    }

    /// The menu saying `message` (why the screen asked for could not be opened).
    pub fn with_message(message: String) -> MenuScreen {
        MenuScreen {
            message,
            #[cfg(not(target_arch = "wasm32"))]
            replays: None,
            drills: None,
            mouse: [-1.0, -1.0],
        }
    }

    /// Whether a line of text is being typed here (the replay page's invite): it takes the
    /// keys.
    pub fn typing(&self) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        return self.replays.as_ref().is_some_and(|p| p.typing());
        #[cfg(target_arch = "wasm32")]
        false
    }

    fn buttons() -> Vec<(Item, &'static str, Rect)> {
        // A page without a game in its link has nothing to join, and one without a usable
        // link no server whose games to find.
        #[cfg(target_arch = "wasm32")]
        let offered = |item: &&(Item, &str)| {
            let link = breakshot_client::net::page::link().as_ref();
            match item.0 {
                Item::Join => link.is_ok_and(|l| l.room.is_some()),
                Item::Lobby => link.is_ok(),
                _ => true,
            }
        };
        #[cfg(not(target_arch = "wasm32"))]
        let offered = |_: &&(Item, &str)| true;
        let items: Vec<&(Item, &str)> = ITEMS.iter().filter(offered).collect();
        let rects = menu_buttons(screen_width(), screen_height(), items.len());
        items
            .into_iter()
            .zip(rects)
            .map(|(&(item, name), r)| (item, name, r))
            .collect()
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        self.mouse = input.mouse;
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(page) = &mut self.replays {
            match page.update(input) {
                replays::PageStep::Stay => {}
                replays::PageStep::Back => self.replays = None,
                replays::PageStep::Watch(viewer) => return Step::Open(Start::Replay(viewer)),
            }
            return Step::Stay;
        }
        if let Some(page) = &mut self.drills {
            match page.update(input) {
                drills::PageStep::Stay => {}
                drills::PageStep::Back => self.drills = None,
                drills::PageStep::Play(drill) => return Step::Open(Start::Drill(drill)),
            }
            return Step::Stay;
        }
        if input.pressed.contains(&Key::Back) {
            return Step::Quit;
        }
        if !input.left_pressed {
            return Step::Stay;
        }
        let Some((item, _, _)) = Self::buttons()
            .into_iter()
            .find(|(_, _, r)| r.contains(input.mouse))
        else {
            return Step::Stay;
        };
        match item {
            Item::Practice => return Step::Open(Start::Practice(None)),
            Item::Drills => self.drills = Some(drills::DrillsPage::open()),
            Item::Local => {
                return Step::Open(Start::Local(Variant::EightBall(EightBallRules::Wpa)))
            }
            Item::Computer => {
                return Step::Open(Start::VsComputer {
                    variant: Variant::EightBall(EightBallRules::Wpa),
                    level: Level::new(3),
                    computer_breaks: false,
                })
            }
            Item::Resume => match resume() {
                Ok(link) => return Step::Open(Start::Network(link)),
                Err(e) => self.message = e,
            },
            Item::Host => match host_default() {
                Ok(host) => return Step::Open(Start::Network(host)),
                Err(e) => self.message = e,
            },
            Item::Join => match join() {
                Ok(link) => return Step::Open(Start::Network(link)),
                Err(e) => self.message = e,
            },
            // A game's invite and its number; a record file is dropped on the window.
            #[cfg(not(target_arch = "wasm32"))]
            Item::Replay => self.replays = Some(Box::new(replays::ReplayPage::open())),
            #[cfg(target_arch = "wasm32")]
            Item::Replay => {}
            Item::Quit => return Step::Quit,
            Item::Lobby => return Step::Open(Start::Lobby),
        }
        Step::Stay
    }

    pub fn draw(&mut self) {
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(page) = &self.replays {
            return page.draw(self.mouse);
        }
        if let Some(page) = &self.drills {
            return page.draw();
        }
        let (w, h) = (screen_width(), screen_height());
        let title = "BREAKSHOT";
        let title_size = 72.0f32.min(0.12 * h);
        let tw = draw::text_width(title, title_size);
        draw::label(title, 0.5 * (w - tw), 0.18 * h, title_size, WHITE);
        let buttons = Self::buttons();
        // One size for every label, the largest at which the longest fits its button.
        let fits = |size: f32| {
            buttons
                .iter()
                .all(|(_, name, r)| draw::text_width(name, size) <= r.w - 16.0)
        };
        let tallest = buttons
            .first()
            .map_or(28.0, |(_, _, r)| r.h / draw::text_scale());
        let mut size = 28.0f32.min(0.7 * tallest);
        while size > 10.0 && !fits(size) {
            size -= 1.0;
        }
        for (_, name, r) in buttons {
            draw::button_face(r, r.contains(self.mouse));
            let d = draw::text_width(name, size);
            draw::label(
                name,
                r.x + 0.5 * (r.w - d),
                r.y + 0.5 * r.h + 0.3 * size * draw::text_scale(),
                size,
                WHITE,
            );
        }
        if !self.message.is_empty() {
            let d = draw::text_width(&self.message, 22.0);
            draw::label(
                &self.message,
                (0.5 * (w - d)).max(8.0),
                0.99 * h - 4.0,
                22.0,
                YELLOW,
            );
        }
    }
}
