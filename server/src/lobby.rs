//! The lobby as pure state: the public rooms listed (waiting for a player, or in play to
//! watch), with what a list shows of them. The hub tells it when a room is listed, when its
//! second player comes and when it closes; it never reads a clock.

use std::collections::BTreeMap;
use std::time::Instant;

use breakshot_shared::protocol::lobby::{page_of, pages, GameInPlay, WaitingRoom};
use breakshot_shared::protocol::{PlayerKey, RoomCode, ServerMessage};
use breakshot_shared::rules::{Settings, Variant};

/// A listed room's player.
#[derive(Clone, Debug)]
pub struct Listed {
    /// Their display name.
    pub name: String,
    /// Who they are.
    pub key: Option<PlayerKey>,
}

/// One room in the lobby.
#[derive(Clone, Debug)]
pub struct Listing {
    /// The game it plays.
    pub variant: Variant,
    /// Its settings.
    pub mode: Settings,
    /// Seat A.
    pub host: Listed,
    /// Seat B, once taken: the room is then in play.
    pub guest: Option<Listed>,
    /// When it was listed.
    pub since: Instant,
    /// Whether its game counts for the ratings.
    pub rated: bool,
}

/// Every listed room.
#[derive(Default)]
pub struct Lobby {
    rooms: BTreeMap<RoomCode, Listing>,
}

impl Lobby {
    /// Lists `room`.
    pub fn list(&mut self, room: RoomCode, listing: Listing) {
        self.rooms.insert(room, listing);
    }

    /// Whether `room` is listed.
    pub fn is_listed(&self, room: &RoomCode) -> bool {
        self.rooms.contains_key(room)
    }

    /// `room`'s second seat was taken: it moves from waiting to in play. Returns the host's
    /// key when the room is listed.
    pub fn seated(&mut self, room: &RoomCode, guest: Listed) -> Option<Option<PlayerKey>> {
        let l = self.rooms.get_mut(room)?;
        l.guest = Some(guest);
        Some(l.host.key)
    }

    /// `room` closed.
    pub fn remove(&mut self, room: &RoomCode) {
        self.rooms.remove(room);
    }

    /// Rooms listed.
    pub fn len(&self) -> usize {
        self.rooms.len()
    }

    /// Whether no room is listed.
    pub fn is_empty(&self) -> bool {
        self.rooms.is_empty()
    }

    /// Page `page` (from 0) of both lists, the longest waiting first, with each player's
    /// rating from `rating`.
    pub fn page(
        &self,
        now: Instant,
        page: u32,
        rating: impl Fn(&PlayerKey) -> Option<i32>,
    ) -> ServerMessage {
        let rating_of = |p: &Listed| p.key.as_ref().and_then(&rating);
        let mut waiting: Vec<(Instant, WaitingRoom)> = Vec::new();
        let mut playing: Vec<(Instant, GameInPlay)> = Vec::new();
        for (code, l) in &self.rooms {
            match &l.guest {
                None => waiting.push((
                    l.since,
                    WaitingRoom {
                        room: code.clone(),
                        variant: l.variant,
                        mode: l.mode,
                        host: l.host.name.clone(),
                        rating: rating_of(&l.host),
                        waited_s: u32::try_from(now.saturating_duration_since(l.since).as_secs())
                            .unwrap_or(u32::MAX),
                    },
                )),
                Some(guest) => playing.push((
                    l.since,
                    GameInPlay {
                        room: code.clone(),
                        variant: l.variant,
                        names: [l.host.name.clone(), guest.name.clone()],
                        ratings: [rating_of(&l.host), rating_of(guest)],
                        rated: l.rated,
                    },
                )),
            }
        }
        waiting.sort_by_key(|(since, w)| (*since, w.room.to_string()));
        playing.sort_by_key(|(since, g)| (*since, g.room.to_string()));
        let waiting: Vec<WaitingRoom> = waiting.into_iter().map(|(_, w)| w).collect();
        let playing: Vec<GameInPlay> = playing.into_iter().map(|(_, g)| g).collect();
        ServerMessage::Games {
            page,
            pages: pages(waiting.len().max(playing.len())),
            waiting: page_of(&waiting, page),
            playing: page_of(&playing, page),
        }
    }
}
