//! Entering a room, and the one record of the seat held.

use breakshot_shared::protocol::{
    ClientMessage, ErrorCode, Role, RoomCode, SeatToken, ServerMessage,
};
use breakshot_shared::rules::Seat;

/// How a player enters a room, with what to do when the server says no.
#[derive(Clone, Debug, PartialEq)]
pub enum Entry {
    /// Opens a room: a [`ClientMessage::CreateRoom`].
    Create(ClientMessage),
    /// Asks for the free seat of `room`; when both seats are taken, watches instead if
    /// `watch_if_full`.
    Join {
        /// The room.
        room: RoomCode,
        /// The player's name.
        name: String,
        /// Watch a full room rather than be refused.
        watch_if_full: bool,
    },
    /// Waits for a quick match (a [`ClientMessage::QuickMatch`]): answered by `Queued`, then
    /// `Joined` once paired.
    QuickMatch(ClientMessage),
    /// Watches `room`.
    Spectate {
        /// The room.
        room: RoomCode,
    },
    /// Takes back the seat `token` holds; when the server no longer knows it (or its room),
    /// enters as `otherwise` says, if anything.
    Rejoin {
        /// The seat's token.
        token: SeatToken,
        /// The entry to fall back to.
        otherwise: Option<Box<Entry>>,
    },
}

impl Entry {
    /// The message that asks for this entry.
    pub(super) fn message(&self) -> ClientMessage {
        match self {
            Entry::Create(msg) | Entry::QuickMatch(msg) => msg.clone(),
            Entry::Join { room, name, .. } => ClientMessage::Join {
                room: room.clone(),
                name: name.clone(),
            },
            Entry::Spectate { room } => ClientMessage::Spectate { room: room.clone() },
            Entry::Rejoin { token, .. } => ClientMessage::Rejoin { token: *token },
        }
    }

    /// The entry to try when the server refuses this one with `code`, and whether the seat
    /// remembered is gone; None when the refusal stands.
    pub(super) fn fallback(self, code: ErrorCode) -> Option<(Entry, bool)> {
        match (self, code) {
            (
                Entry::Rejoin {
                    otherwise: Some(next),
                    ..
                },
                ErrorCode::BadToken | ErrorCode::NoSuchRoom,
            ) => Some((*next, true)),
            (
                Entry::Join {
                    room,
                    watch_if_full: true,
                    ..
                },
                ErrorCode::RoomFull,
            ) => Some((Entry::Spectate { room }, false)),
            _ => None,
        }
    }
}

/// The seat a player holds, as the server last said: the one record of it, kept by the
/// core and read by everyone else.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Seating {
    /// Our role in the room joined last.
    pub role: Option<Role>,
    /// The room joined last.
    pub room: Option<RoomCode>,
    /// The token that takes the seat back, once seated.
    pub token: Option<SeatToken>,
}

impl Seating {
    /// Our seat, if we play.
    pub fn seat(&self) -> Option<Seat> {
        match self.role {
            Some(Role::Player(seat)) => Some(seat),
            _ => None,
        }
    }

    /// True when we watch the room rather than play in it.
    pub fn watching(&self) -> bool {
        self.role == Some(Role::Spectator)
    }

    /// Notes what `msg` says of the seat; returns the seating when it changed (a `Joined`).
    pub(super) fn observe(&mut self, msg: &ServerMessage) -> Option<Seating> {
        let ServerMessage::Joined {
            role,
            token,
            snapshot,
        } = msg
        else {
            return None;
        };
        self.role = Some(*role);
        if token.is_some() {
            self.token = *token;
        }
        self.room = Some(snapshot.room.clone());
        Some(self.clone())
    }
}
