//! Every limit the server enforces, in one place so that the client, the server and the
//! documentation agree. docs/protocol.md explains each one.

use std::time::Duration;

/// Largest frame payload (bytes) either side accepts. Frames longer than this close the
/// connection before anything is allocated for them.
pub const MAX_FRAME: usize = 64 * 1024;
/// Longest player name (characters).
pub const MAX_NAME_CHARS: usize = 24;
/// Longest chat line (characters).
pub const MAX_CHAT_CHARS: usize = 200;
/// Chat lines a connection may send in a burst ...
pub const CHAT_BURST: u32 = 5;
/// ... and the time it takes to earn one more.
pub const CHAT_REFILL: Duration = Duration::from_secs(2);
/// Messages of any kind a connection may send per second before it is closed as abusive.
pub const MAX_MESSAGES_PER_SECOND: u32 = 50;
/// How long a seat is held for a player who dropped, before the game is forfeited.
pub const RECONNECT_WINDOW: Duration = Duration::from_secs(120);
/// Number of characters in a room code: 8 characters of 5 bits each, 40 bits, so guessing
/// a live room is hopeless at the rate-limited pace of room entries.
pub const ROOM_CODE_LEN: usize = 8;
/// Most rooms one server holds at once (each costs a few kilobytes).
pub const MAX_ROOMS: usize = 10_000;
/// Spectators allowed in one room.
pub const MAX_SPECTATORS: usize = 32;
/// Largest stored game record (bytes) a server will load or verify.
pub const MAX_RECORD: usize = 4 * 1024 * 1024;
/// Largest record (bytes) the server sends in one `Record` message: the rest of a frame is
/// room for the message's other fields (a few bytes). A game's record is about 2 KB.
pub const MAX_SENT_RECORD: usize = MAX_FRAME - 1024;
/// How often each side of a connection sends a QUIC keep-alive when it has nothing else to
/// send. With [`IDLE_TIMEOUT`] five times as long, four keep-alives in a row (and QUIC's own
/// retransmissions of them) must be lost before a live connection is taken for dead; each
/// costs a few dozen bytes, so a second is cheap.
pub const KEEP_ALIVE: Duration = Duration::from_secs(1);
/// A connection that hears nothing from its peer for this long is gone: a player whose
/// process was killed or whose network vanished is seen as away within this time (an orderly
/// close is seen at once). A false alarm from a longer network outage costs a reconnect, not
/// the game: the seat is held for [`RECONNECT_WINDOW`].
pub const IDLE_TIMEOUT: Duration = Duration::from_secs(5);
/// The least a returning player finds on the shot clock: the time left when they dropped
/// (or when the server stopped), but never less than this, enough to look at the table
/// again and play.
pub const MIN_CLOCK_ON_RETURN: Duration = Duration::from_secs(15);
/// Lobby and leaderboard pages a connection may ask for in a burst ...
pub const LOBBY_BURST: u32 = 5;
/// ... and the time it takes to earn one more.
pub const LOBBY_REFILL: Duration = Duration::from_secs(1);
/// How long a player waits in the quick-match queue before it gives up.
pub const QUEUE_TIMEOUT: Duration = Duration::from_secs(180);
/// Quick-match joins and leaves a connection may make in a burst ...
pub const QUEUE_BURST: u32 = 5;
/// ... and the time it takes to earn one more.
pub const QUEUE_REFILL: Duration = Duration::from_secs(2);
