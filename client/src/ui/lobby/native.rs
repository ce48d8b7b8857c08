//! Where the window's lobby finds its server and how it connects to it: the invite on the
//! clipboard, else the server whose lobby was opened last (remembered in the data
//! directory), reached by a [`Session`] on a thread of its own.

use breakshot_client::memory;
use breakshot_client::net::{Port, SeatStore, Session};
use breakshot_shared::protocol::{Invite, RoomCode};

/// A server whose lobby the window shows.
pub struct Server {
    /// Its invite, without a room.
    invite: Invite,
}

impl Server {
    /// The invite on the clipboard, else the server remembered (the one found is remembered
    /// for next time); or what to do to name one.
    pub fn find() -> Result<Server, String> {
        let clipboard = macroquad::miniquad::window::clipboard_get()
            .and_then(|t| t.trim().parse::<Invite>().ok());
        let remembered = || crate::ui::data_dir().and_then(|d| memory::last_server(&d));
        let mut invite = clipboard
            .or_else(remembered)
            .ok_or("Copy a server's address (breakshot://...) and press Refresh")?;
        invite.room = None;
        if let Some(data) = crate::ui::data_dir() {
            let _ = memory::remember_server(&data, &invite);
        }
        Ok(Server { invite })
    }

    /// A new connection to the server, in no room yet.
    pub fn connect(&self) -> Result<Box<dyn Port>, String> {
        Ok(Box::new(Session::connect(self.invite.clone())))
    }

    /// The invite of `room` on this server (under which a seat taken there is remembered).
    pub fn invite(&self, room: RoomCode) -> Invite {
        Invite {
            room: Some(room),
            ..self.invite.clone()
        }
    }

    /// The player's name, as the menu's other games use it.
    pub fn player_name(&self) -> String {
        crate::ui::data_dir()
            .and_then(|d| memory::player_name(&d, None).ok())
            .unwrap_or_else(|| "player".to_owned())
    }

    /// Where a seat taken is remembered: the data directory.
    pub fn seats(&self) -> Option<SeatStore> {
        crate::ui::data_dir().map(|d| SeatStore::new(&d))
    }
}
