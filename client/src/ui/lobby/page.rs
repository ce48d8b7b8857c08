//! Where the page's lobby finds its server and how it connects to it: the server the page's
//! link names (the page's own host unless `server=` says otherwise), trusted by the link's
//! key and certificate hashes and reached by a [`PolledSession`](breakshot_client::net::PolledSession)
//! advanced on the frame's own turn.

use breakshot_client::net::{Port, SeatStore};
use breakshot_shared::protocol::{Invite, RoomCode, WebLink};

use crate::ui::page_game::{player_name, session, usable_link, way_to_server};

/// A server whose lobby the page shows.
pub struct Server {
    link: &'static WebLink,
    /// Its invite, without a room.
    invite: Invite,
}

impl Server {
    /// The server of the page's link; or why the page cannot reach one.
    pub fn find() -> Result<Server, String> {
        let link = usable_link()?;
        // Checked here once: a link that allows this browser no way in says so at once.
        let (invite, _) = way_to_server(link, None)?;
        Ok(Server { link, invite })
    }

    /// A new connection to the server, in no room yet.
    pub fn connect(&self) -> Result<Box<dyn Port>, String> {
        let (invite, way) = way_to_server(self.link, None)?;
        Ok(Box::new(session(&invite, way)))
    }

    /// The invite of `room` on this server (under which a seat taken there is remembered).
    pub fn invite(&self, room: RoomCode) -> Invite {
        Invite {
            room: Some(room),
            ..self.invite.clone()
        }
    }

    /// The player's name: the link's, else the one the page kept.
    pub fn player_name(&self) -> String {
        player_name(self.link)
    }

    /// Where a seat taken is remembered: the page's storage.
    pub fn seats(&self) -> Option<SeatStore> {
        Some(SeatStore::page())
    }
}
