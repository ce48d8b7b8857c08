//! The rooms a hub holds, filed by their next deadline (a shot clock, the end of a reconnect
//! window), so the hub finds the soonest deadline and the rooms due without a pass over every
//! room. A room can only be changed through [`RoomMut`], which files it again when dropped,
//! so no change can leave the index behind.

use std::collections::{BTreeMap, BTreeSet};
use std::ops::{Deref, DerefMut};
use std::time::Instant;

use breakshot_shared::protocol::RoomCode;

use crate::room::Room;

/// The rooms, by code, with their deadlines and the rooms closed.
#[derive(Default)]
pub struct Rooms {
    map: BTreeMap<RoomCode, Room>,
    filing: Filing,
}

/// Each room's next deadline, by time, and the rooms closed (whose players have all gone,
/// dropped at the next tick).
#[derive(Default)]
struct Filing {
    due: BTreeSet<(Instant, RoomCode)>,
    filed: BTreeMap<RoomCode, Instant>,
    closed: BTreeSet<RoomCode>,
}

impl Filing {
    /// Files `room` under its deadline now, in place of where it was.
    fn file(&mut self, room: &Room) {
        let code = room.code();
        let deadline = room.next_deadline();
        if self.filed.get(code) != deadline.as_ref() {
            self.unfile_deadline(code);
            if let Some(at) = deadline {
                self.due.insert((at, code.clone()));
                self.filed.insert(code.clone(), at);
            }
        }
        if room.is_closed() {
            self.closed.insert(code.clone());
        } else {
            self.closed.remove(code);
        }
    }

    fn unfile_deadline(&mut self, code: &RoomCode) {
        if let Some(at) = self.filed.remove(code) {
            self.due.remove(&(at, code.clone()));
        }
    }

    fn unfile(&mut self, code: &RoomCode) {
        self.unfile_deadline(code);
        self.closed.remove(code);
    }
}

/// A room borrowed to be changed; it is filed again under its deadline when dropped.
pub struct RoomMut<'a> {
    room: &'a mut Room,
    filing: &'a mut Filing,
}

impl Deref for RoomMut<'_> {
    type Target = Room;
    fn deref(&self) -> &Room {
        self.room
    }
}

impl DerefMut for RoomMut<'_> {
    fn deref_mut(&mut self) -> &mut Room {
        self.room
    }
}

impl Drop for RoomMut<'_> {
    fn drop(&mut self) {
        self.filing.file(self.room);
    }
}

impl Rooms {
    /// Adds `room`, filed under its deadline (replacing a room of the same code).
    pub fn insert(&mut self, room: Room) {
        self.filing.file(&room);
        self.map.insert(room.code().clone(), room);
    }

    /// Takes the room `code` out, and out of the filing.
    pub fn remove(&mut self, code: &RoomCode) -> Option<Room> {
        self.filing.unfile(code);
        self.map.remove(code)
    }

    /// The room `code`, to look at.
    pub fn get(&self, code: &RoomCode) -> Option<&Room> {
        self.map.get(code)
    }

    /// The room `code` to change; filed again when the borrow ends.
    pub fn get_mut(&mut self, code: &RoomCode) -> Option<RoomMut<'_>> {
        let room = self.map.get_mut(code)?;
        Some(RoomMut {
            room,
            filing: &mut self.filing,
        })
    }

    /// Whether a room of this code is here.
    pub fn contains_key(&self, code: &RoomCode) -> bool {
        self.map.contains_key(code)
    }

    /// How many rooms are here.
    pub fn len(&self) -> usize {
        self.map.len()
    }

    /// Whether no room is here.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }

    /// Every room, in the order of their codes.
    pub fn values(&self) -> impl Iterator<Item = &Room> {
        self.map.values()
    }

    /// The soonest deadline of any room.
    pub fn next_deadline(&self) -> Option<Instant> {
        let soonest = self.filing.due.first().map(|(at, _)| *at);
        debug_assert_eq!(
            soonest,
            self.map.values().filter_map(Room::next_deadline).min(),
            "the filing agrees with every room's own deadline"
        );
        soonest
    }

    /// The rooms whose deadline is due by `now`, soonest first.
    pub fn due(&self, now: Instant) -> Vec<RoomCode> {
        self.filing
            .due
            .iter()
            .take_while(|(at, _)| *at <= now)
            .map(|(_, code)| code.clone())
            .collect()
    }

    /// The rooms closed, to be dropped.
    pub fn closed(&self) -> Vec<RoomCode> {
        debug_assert!(
            self.map
                .values()
                .all(|r| r.is_closed() == self.filing.closed.contains(r.code())),
            "the filing knows every closed room"
        );
        self.filing.closed.iter().cloned().collect()
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use breakshot_shared::protocol::limits::ROOM_CODE_LEN;
    use breakshot_shared::protocol::{AimAid, SeatToken};
    use breakshot_shared::rules::{Settings, Variant};

    use super::*;
    use crate::room::RoomRules;

    const WINDOW: Duration = Duration::from_secs(30);

    /// A 9-ball room of code `n` whose creator is connection `n`.
    fn room(now: Instant, n: u8) -> Room {
        let rules = RoomRules {
            variant: Variant::NineBall,
            settings: Settings::online(),
            aim_aid: AimAid::Full,
            reconnect_window: WINDOW,
            max_commands: 1000,
        };
        let code = RoomCode::from_random([n; ROOM_CODE_LEN]);
        let token = SeatToken([n; 16]);
        Room::create(now, code, rules, 7, u64::from(n), format!("p{n}"), token).0
    }

    fn code(n: u8) -> RoomCode {
        RoomCode::from_random([n; ROOM_CODE_LEN])
    }

    #[test]
    fn a_change_through_the_borrow_files_the_room_under_its_new_deadline() {
        let t0 = Instant::now();
        let mut rooms = Rooms::default();
        rooms.insert(room(t0, 1));
        rooms.insert(room(t0, 2));
        assert_eq!(rooms.next_deadline(), None);
        // Room 2's player drops at t0 + 1 s, room 1's at t0 + 2 s: each seat is held for the
        // reconnect window from then.
        for (n, at) in [(2, 1), (1, 2)] {
            let at = t0 + Duration::from_secs(at);
            let _ = rooms
                .get_mut(&code(n))
                .unwrap()
                .disconnect(at, at, u64::from(n));
        }
        let first = t0 + Duration::from_secs(1) + WINDOW;
        assert_eq!(rooms.next_deadline(), Some(first));
        assert_eq!(rooms.due(first - Duration::from_millis(1)), Vec::new());
        assert_eq!(rooms.due(first), vec![code(2)]);
        assert_eq!(rooms.due(first + WINDOW), vec![code(2), code(1)]);
        // Its deadline passed, the room forfeits the seat and is filed under none.
        let _ = rooms.get_mut(&code(2)).unwrap().tick(first);
        assert_eq!(rooms.next_deadline(), Some(first + Duration::from_secs(1)));
        assert_eq!(rooms.due(first), Vec::new());
    }

    #[test]
    fn a_room_taken_out_leaves_the_filing() {
        let t0 = Instant::now();
        let mut rooms = Rooms::default();
        rooms.insert(room(t0, 3));
        let _ = rooms.get_mut(&code(3)).unwrap().disconnect(t0, t0, 3);
        assert!(rooms.next_deadline().is_some());
        let out = rooms.remove(&code(3)).expect("the room");
        assert_eq!(rooms.next_deadline(), None);
        assert!(rooms.due(t0 + 2 * WINDOW).is_empty());
        // Back in (as a room comes back from its work), it is filed again.
        rooms.insert(out);
        assert_eq!(rooms.due(t0 + WINDOW), vec![code(3)]);
    }

    #[test]
    fn a_room_whose_seats_are_gone_is_listed_closed() {
        let t0 = Instant::now();
        let mut rooms = Rooms::default();
        rooms.insert(room(t0, 4));
        rooms.insert(room(t0, 5));
        let _ = rooms.get_mut(&code(4)).unwrap().disconnect(t0, t0, 4);
        // The window runs out with nobody back: the seat is forfeited and nobody is left.
        let _ = rooms.get_mut(&code(4)).unwrap().tick(t0 + WINDOW);
        assert_eq!(rooms.get(&code(4)).map(Room::is_closed), Some(true));
        assert_eq!(rooms.closed(), vec![code(4)]);
        rooms.remove(&code(4));
        assert!(rooms.closed().is_empty());
        assert_eq!(rooms.len(), 1);
    }
}
