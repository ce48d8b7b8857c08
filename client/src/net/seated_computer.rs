//! The computer seated in an online room: a [`SeatPlayer`] with the computer player's
//! chooser, on a thread of its own with its own runtime, taking the room's free seat through
//! the server like any other player. The server needs nothing new, and the search never runs
//! on the server's threads.

use super::background::BackgroundThread;
use std::time::Duration;

use breakshot_shared::ai::Level;
use breakshot_shared::protocol::Invite;
use tokio::sync::oneshot;

use super::host::HostError;
use super::seat_player::{Entrance, SeatPlayer, RETRY_FOR};
use crate::play::Chooser;

/// How long a stopped computer waits for a decision in progress before its thread ends.
const STOP_GRACE: Duration = Duration::from_secs(2);

/// The computer in the free seat of a room, playing game after game (it asks for a rematch
/// whenever a game ends) until dropped.
pub struct SeatedComputer {
    level: Level,
    /// The seat's thread, stopped when this is dropped.
    _thread: BackgroundThread,
}

impl SeatedComputer {
    /// Starts joining the room `invite` names, to play at `level` with decisions seeded
    /// from `seed`. `paced`: each move waits until the last shot has finished playing on
    /// the players' screens (and a moment more), as a player's would; else the computer
    /// moves as soon as it has chosen (for tests and load).
    pub fn join(
        invite: Invite,
        level: Level,
        seed: u64,
        paced: bool,
    ) -> Result<SeatedComputer, HostError> {
        let Some(room) = invite.room.clone() else {
            return Err(HostError::Room(format!("{invite} names no room")));
        };
        let no_runtime =
            |e: std::io::Error| tracing::error!(error = %e, "no runtime for the computer's seat");
        let thread = BackgroundThread::spawn_with_runtime(
            "computer-seat",
            no_runtime,
            move |runtime, stopped| {
                runtime.block_on(async move {
                    let (tx, rx) = oneshot::channel();
                    let _ = tx.send(room);
                    let chooser = Chooser::computer(level, seed);
                    let mut bot =
                        SeatPlayer::seated(invite, "computer".into(), chooser, RETRY_FOR).staying();
                    if paced {
                        bot = bot.pacing();
                    }
                    tokio::select! {
                        result = bot.play(Entrance::Join(rx)) => {
                            if let Some(e) = result.error {
                                tracing::warn!(error = %e, "the computer left its seat");
                            }
                        }
                        _ = stopped => {}
                    }
                });
                runtime.shutdown_timeout(STOP_GRACE);
            },
        )
        .map_err(|e| HostError::Runtime(e.to_string()))?;
        Ok(SeatedComputer {
            level,
            _thread: thread,
        })
    }

    /// How strong it plays.
    pub fn level(&self) -> Level {
        self.level
    }
}
