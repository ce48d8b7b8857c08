//! Every limit a server enforces, as one setting. The protocol's own limits (frame size,
//! name and chat length, chat rate) are constants both sides share
//! (`breakshot_shared::protocol::limits`); these are the server's resources and defences,
//! which an operator may tune. docs/operations.md explains each one.

use std::time::Duration;

use breakshot_shared::protocol::limits as protocol;
use breakshot_shared::rules::Variant;

/// The server's resources and defences; the defaults are those docs/operations.md lists.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Connections open at once, counting those still in their handshake. Beyond it new
    /// connection attempts are refused.
    pub max_connections: usize,
    /// Handshakes in progress at once before a client must first prove its address (a QUIC
    /// retry): a flood of attempts from spoofed or silent addresses then costs the server no
    /// state and no cryptography.
    pub max_handshakes: usize,
    /// The share of both totals above one source address may hold: at most
    /// `max_connections / address_share` connections and `max_handshakes / address_share`
    /// handshakes in progress (at least one of each). Beyond them its attempts are refused,
    /// so one address can never take the slots every other address needs.
    pub address_share: usize,
    /// How long a handshake may take before it is abandoned and its slots freed (a
    /// handshake that never finishes would otherwise hold them for the 30 s idle timeout).
    pub handshake_timeout: Duration,
    /// How long a connected client has to open its stream.
    pub open_timeout: Duration,
    /// How long the rest of a frame may take once its first byte has arrived: a client that
    /// sends half a frame and stalls is closed.
    pub frame_timeout: Duration,
    /// Messages queued for one client that it has not taken yet. A client that stops reading
    /// is disconnected when its queue passes this, so it cannot make the server hold an
    /// ever-growing backlog (its seat is held as for any dropped player).
    pub outbound_queue: usize,
    /// Messages of any kind one connection may send per second (a burst of as many is
    /// allowed); beyond it the connection is closed.
    pub messages_per_second: u32,
    /// Rooms on the server at once; `CreateRoom` beyond it gets `ServerBusy`.
    pub max_rooms: usize,
    /// Open rooms created from one source address; beyond it `CreateRoom` gets `ServerBusy`.
    pub rooms_per_address: usize,
    /// Room entries (create, join, rejoin, spectate) one source address may attempt in a
    /// burst ...
    pub entry_burst: u32,
    /// ... and the time it takes to earn one more. Excess attempts get `RateLimited`, which
    /// makes guessing room codes or seat tokens hopeless.
    pub entry_refill: Duration,
    /// How long a dropped player's seat is held before the game is forfeited.
    pub reconnect_window: Duration,
    /// Most commands one game of two players may hold; the last place goes to a concession
    /// of the player to move, which ends it. Real games take tens of commands; this bounds
    /// a game's record (and so what is stored, restored and verified for it).
    pub max_game_commands: usize,
    /// The same for a practice session, which one connection drives alone.
    pub max_practice_commands: usize,
    /// How long the seats of a finished game stay known after its room is gone (also
    /// across restarts): a player who comes back with their token in that time is told the
    /// result instead of `BadToken`.
    pub finished_retention: Duration,
    /// Whether quick match may pair two players of one source address. Off on a public
    /// server (a second key of one's own would be an easy opponent to farm a rating from);
    /// on for load tests from one machine.
    pub match_one_address: bool,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_connections: 4_096,
            max_handshakes: 256,
            address_share: 16,
            handshake_timeout: Duration::from_secs(5),
            open_timeout: Duration::from_secs(10),
            frame_timeout: Duration::from_secs(10),
            outbound_queue: 256,
            messages_per_second: protocol::MAX_MESSAGES_PER_SECOND,
            max_rooms: protocol::MAX_ROOMS,
            rooms_per_address: 32,
            entry_burst: 20,
            entry_refill: Duration::from_secs(1),
            reconnect_window: protocol::RECONNECT_WINDOW,
            max_game_commands: 900,
            max_practice_commands: 500,
            finished_retention: Duration::from_secs(3_600),
            match_one_address: false,
        }
    }
}

impl Limits {
    /// Most commands a game of `variant` may hold (at least two: a command and the
    /// concession that ends the game).
    pub fn max_commands(&self, variant: Variant) -> usize {
        let max = match variant {
            Variant::Practice => self.max_practice_commands,
            _ => self.max_game_commands,
        };
        max.max(2)
    }

    /// Connections one source address may hold (a share of `max_connections`).
    pub fn connections_per_address(&self) -> usize {
        (self.max_connections / self.address_share.max(1)).max(1)
    }

    /// Handshakes one source address may have in progress (a share of `max_handshakes`).
    pub fn handshakes_per_address(&self) -> usize {
        (self.max_handshakes / self.address_share.max(1)).max(1)
    }

    /// Limits for a load test run from one machine: every game comes from the same address,
    /// so the per-address limits are lifted. Never use this for a public server.
    pub fn single_address_load() -> Limits {
        Limits {
            max_connections: 16_384,
            // Thousands of bots connect at once from one address: none is asked to retry.
            max_handshakes: 16_384,
            address_share: 1,
            rooms_per_address: usize::MAX,
            entry_burst: u32::MAX,
            entry_refill: Duration::from_nanos(1),
            match_one_address: true,
            ..Limits::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use breakshot_shared::physics::Strike;
    use breakshot_shared::protocol::limits::{MAX_RECORD, MAX_SENT_RECORD};
    use breakshot_shared::replay::{GameRecord, RecordEntry};
    use breakshot_shared::rules::{Command, EightBallRules, Seat, Settings};
    use glam::DVec2;

    use super::*;

    /// The longest entry a client can cause: a shot with every number at full width, a
    /// called pocket and a hash.
    fn longest_entry() -> RecordEntry {
        RecordEntry {
            seat: Seat::B,
            command: Command::Shot {
                strike: Strike {
                    speed: -f64::MAX,
                    dir: DVec2::new(f64::MIN_POSITIVE, -f64::MAX),
                    tip: DVec2::new(-f64::MAX, f64::MAX),
                    elevation_deg: 0.0,
                },
                call: Some(u8::MAX),
            },
            hash: Some(u64::MAX),
            chain: u64::MAX,
        }
    }

    #[test]
    fn the_longest_game_the_limits_allow_is_loaded_verified_and_sent_whole() {
        let limits = Limits::default();
        for variant in [Variant::EightBall(EightBallRules::Wpa), Variant::Practice] {
            let mut record = GameRecord::new(variant, Settings::offline(), u64::MAX);
            record.entries.extend(std::iter::repeat_n(
                longest_entry(),
                limits.max_commands(variant),
            ));
            let bytes = record.encode();
            eprintln!(
                "{variant:?}: {} commands in {} bytes ({} per command)",
                record.entries.len(),
                bytes.len(),
                longest_entry().encode().len()
            );
            // Loaded by a restart and by `verify` (decoded within MAX_RECORD) ...
            assert!(bytes.len() <= MAX_RECORD);
            assert_eq!(GameRecord::decode(&bytes).unwrap(), record);
            // ... and sent whole to whoever asks for it to watch again.
            assert!(bytes.len() <= MAX_SENT_RECORD, "{} bytes", bytes.len());
        }
    }
}
