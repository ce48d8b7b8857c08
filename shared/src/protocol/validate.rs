//! Checks on a message's own content, before any game state is consulted: finite numbers,
//! a normalised aim, speed and tip within the cue's limits, sane texts. Whether the command
//! is legal *now* is the room's and the rules' business.

use thiserror::Error;

use super::limits::{MAX_CHAT_CHARS, MAX_NAME_CHARS};
use super::messages::{ClientMessage, ErrorCode};
use crate::physics::{StrikeError, TableKind};
use crate::rules::snooker::{MAX_BEST_OF, RED_COUNTS};
use crate::rules::three_cushion::MAX_RACE;
use crate::rules::{Settings, Variant};

/// Pockets on a table with pockets.
pub const POCKETS: u8 = 6;

/// Why a client's message is invalid on its own, whatever the game's state (answered as
/// [`ErrorCode::Invalid`]).
#[derive(Debug, Error, PartialEq)]
pub enum InvalidMessage {
    /// The strike is not finite, or beyond the cue's limits (speed, tip, elevation).
    #[error("{0}")]
    Strike(#[from] StrikeError),
    /// A pocket index of [`POCKETS`] or more.
    #[error("pocket must be 0..{POCKETS}")]
    Pocket,
    /// A cue-ball placement that is not finite.
    #[error("cue ball position must be finite numbers")]
    Position,
    /// A player's name that is empty, too long or not printable.
    #[error("name must be 1 to {MAX_NAME_CHARS} printable characters")]
    Name,
    /// A chat line that is empty, too long or not printable.
    #[error("chat must be 1 to {MAX_CHAT_CHARS} printable characters")]
    Chat,
    /// A room code that is not well-formed.
    #[error("malformed room code")]
    Room,
    /// A new room whose table, race or shot clock is out of range.
    #[error("a room is played on a 7, 8 or 9-foot table (three-cushion: the carom table, a race of 1 to {MAX_RACE} points; snooker: the snooker table, 6, 10 or 15 reds, the best of an odd number of frames up to {MAX_BEST_OF}) with a shot clock of {MIN_SHOT_CLOCK} to {MAX_SHOT_CLOCK} s, if any")]
    Mode,
    /// Quick match for practice, which has no opponent.
    #[error("practice has no opponent to be matched with")]
    Practice,
    /// A game number of 0 (a room's games are numbered from 1).
    #[error("a room's games are numbered from 1")]
    GameNumber,
}

/// Shortest shot clock a room may have (seconds).
pub const MIN_SHOT_CLOCK: u32 = 10;
/// Longest shot clock a room may have (seconds).
pub const MAX_SHOT_CLOCK: u32 = 600;

impl InvalidMessage {
    /// The error code sent with the refusal: always [`ErrorCode::Invalid`].
    pub fn code(&self) -> ErrorCode {
        ErrorCode::Invalid
    }
}

/// Returns the message with its aim normalised, or why it is invalid.
pub fn validate(msg: ClientMessage) -> Result<ClientMessage, InvalidMessage> {
    match msg {
        ClientMessage::Shot { turn, strike, call } => {
            let strike = strike.validated()?;
            check_pocket(call)?;
            Ok(ClientMessage::Shot { turn, strike, call })
        }
        ClientMessage::Aim { turn, strike } => Ok(ClientMessage::Aim {
            turn,
            strike: strike.validated()?,
        }),
        ClientMessage::PlaceCueBall { pos, .. } if !pos.iter().all(|x| x.is_finite()) => {
            Err(InvalidMessage::Position)
        }
        ClientMessage::CallPocket { pocket, .. } if pocket >= POCKETS => {
            Err(InvalidMessage::Pocket)
        }
        ClientMessage::CreateRoom {
            variant, ref mode, ..
        }
        | ClientMessage::QuickMatch {
            variant, ref mode, ..
        } if !playable(variant, mode) => Err(InvalidMessage::Mode),
        ClientMessage::QuickMatch {
            variant: Variant::Practice,
            ..
        } => Err(InvalidMessage::Practice),
        ClientMessage::CreateRoom { ref name, .. }
        | ClientMessage::Join { ref name, .. }
        | ClientMessage::QuickMatch { ref name, .. }
            if !printable(name, MAX_NAME_CHARS) =>
        {
            Err(InvalidMessage::Name)
        }
        ClientMessage::Join { ref room, .. }
        | ClientMessage::Spectate { ref room }
        | ClientMessage::FetchRecord { ref room, .. }
            if !room.is_valid() =>
        {
            Err(InvalidMessage::Room)
        }
        ClientMessage::Chat { ref text } if !printable(text, MAX_CHAT_CHARS) => {
            Err(InvalidMessage::Chat)
        }
        ClientMessage::FetchRecord { game: Some(0), .. } => Err(InvalidMessage::GameNumber),
        other => Ok(other),
    }
}

fn check_pocket(call: Option<u8>) -> Result<(), InvalidMessage> {
    match call {
        Some(p) if p >= POCKETS => Err(InvalidMessage::Pocket),
        _ => Ok(()),
    }
}

/// A table the game is played on (pockets for pool, the carom table for three-cushion), a
/// race that ends, and a shot clock a person can play with.
fn playable(variant: Variant, mode: &Settings) -> bool {
    let clock_ok = mode
        .shot_clock
        .is_none_or(|s| (MIN_SHOT_CLOCK..=MAX_SHOT_CLOCK).contains(&s));
    let game_ok = match variant {
        Variant::ThreeCushion { race } => {
            mode.table == TableKind::Carom && (1..=MAX_RACE).contains(&race)
        }
        Variant::Snooker { reds, best_of } => {
            mode.table == TableKind::Snooker
                && RED_COUNTS.contains(&reds)
                && best_of % 2 == 1
                && best_of <= MAX_BEST_OF
        }
        _ => mode.table.has_pockets() && mode.table != TableKind::Snooker,
    };
    clock_ok && game_ok
}

/// Whether `name` may be a player's name: 1 to [`MAX_NAME_CHARS`] printable characters.
pub fn is_valid_name(name: &str) -> bool {
    printable(name, MAX_NAME_CHARS)
}

/// Non-blank, at most `max` characters, no control characters.
fn printable(text: &str, max: usize) -> bool {
    let n = text.chars().count();
    n > 0 && n <= max && !text.trim().is_empty() && !text.chars().any(char::is_control)
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::physics::Strike;

    fn shot(speed: f64, dir: DVec2, tip: DVec2) -> ClientMessage {
        elevated(0.0)(speed, dir, tip)
    }

    fn elevated(elevation_deg: f64) -> impl Fn(f64, DVec2, DVec2) -> ClientMessage {
        move |speed, dir, tip| ClientMessage::Shot {
            turn: 1,
            strike: Strike {
                speed,
                dir,
                tip,
                elevation_deg,
            },
            call: None,
        }
    }

    /// The aim-aid policies keep their wire (and stored) encoding as one byte, the one
    /// added last after the others, and a value past the last is refused when decoded.
    #[test]
    fn each_aim_aid_is_one_byte_and_a_value_past_the_last_is_refused() {
        use super::super::framing::{decode_payload, encode_frame, FrameError, HEADER_LEN};
        use super::super::messages::AimAid;
        let policies = [
            AimAid::Off,
            AimAid::FirstContact,
            AimAid::Full,
            AimAid::Advice,
        ];
        for (byte, policy) in policies.into_iter().enumerate() {
            let mut message = room(Variant::NineBall, Settings::online());
            if let ClientMessage::CreateRoom { aim_aid, .. } = &mut message {
                *aim_aid = policy;
            }
            let frame = encode_frame(&message).expect("encoded");
            let mut payload = frame[HEADER_LEN..].to_vec();
            // The name "ann" (its length, then three bytes) follows the policy's byte.
            let at = payload.len() - 5;
            assert_eq!(usize::from(payload[at]), byte, "{policy:?}");
            let back: ClientMessage = decode_payload(&payload).expect("decoded");
            assert_eq!(back, message);
            payload[at] = policies.len() as u8;
            let refused = decode_payload::<ClientMessage>(&payload);
            assert!(
                matches!(refused, Err(FrameError::Malformed(_))),
                "{refused:?}"
            );
        }
    }

    /// A room for "ann" with no aim aid.
    fn room(variant: Variant, mode: Settings) -> ClientMessage {
        ClientMessage::CreateRoom {
            variant,
            mode,
            aim_aid: super::super::messages::AimAid::Off,
            name: "ann".into(),
        }
    }

    #[test]
    fn an_elevated_shot_keeps_its_elevation() {
        for degrees in [0.0, 45.0, 90.0] {
            let Ok(ClientMessage::Shot { strike, .. }) =
                validate(elevated(degrees)(3.0, DVec2::Y, DVec2::ZERO))
            else {
                panic!("refused a cue elevated {degrees} degrees");
            };
            assert_eq!(strike.elevation_deg, degrees);
        }
    }

    #[test]
    fn a_good_shot_comes_back_with_a_unit_aim() {
        let Ok(ClientMessage::Shot { strike, .. }) =
            validate(shot(3.0, DVec2::new(3.0, 4.0), DVec2::ZERO))
        else {
            panic!("refused a good shot");
        };
        assert_eq!(strike.dir, DVec2::new(0.6, 0.8));
    }

    #[test]
    fn bad_numbers_are_refused() {
        let z = DVec2::ZERO;
        let y = DVec2::Y;
        for bad in [
            shot(f64::NAN, y, z),
            shot(-1.0, y, z),
            shot(15.1, y, z),
            shot(3.0, z, z),
            shot(3.0, DVec2::new(f64::INFINITY, 0.0), z),
            shot(3.0, y, DVec2::new(0.6, 0.0)),
            shot(3.0, y, DVec2::new(f64::NAN, 0.0)),
            elevated(f64::NAN)(3.0, y, z),
            elevated(-0.5)(3.0, y, z),
            elevated(90.5)(3.0, y, z),
            elevated(f64::INFINITY)(3.0, y, z),
            ClientMessage::PlaceCueBall {
                turn: 0,
                pos: [f64::NAN, 0.5],
            },
            ClientMessage::CallPocket { turn: 0, pocket: 6 },
            ClientMessage::Chat {
                text: "x".repeat(MAX_CHAT_CHARS + 1),
            },
            ClientMessage::Chat { text: "  ".into() },
            ClientMessage::Chat {
                text: "bell\u{7}".into(),
            },
            room(
                Variant::NineBall,
                Settings {
                    table: TableKind::Open,
                    ..Settings::offline()
                },
            ),
            room(
                Variant::NineBall,
                Settings {
                    table: TableKind::Carom,
                    ..Settings::offline()
                },
            ),
            room(
                Variant::ThreeCushion { race: 0 },
                Settings {
                    table: TableKind::Carom,
                    ..Settings::offline()
                },
            ),
            room(Variant::three_cushion(), Settings::offline()),
            room(Variant::snooker(), Settings::offline()),
            room(Variant::NineBall, snooker_table()),
            room(
                Variant::Snooker {
                    reds: 7,
                    best_of: 1,
                },
                snooker_table(),
            ),
            room(
                Variant::Snooker {
                    reds: 15,
                    best_of: 2,
                },
                snooker_table(),
            ),
            room(
                Variant::NineBall,
                Settings {
                    shot_clock: Some(0),
                    ..Settings::offline()
                },
            ),
        ] {
            assert!(validate(bad.clone()).is_err(), "accepted {bad:?}");
        }
    }

    fn snooker_table() -> Settings {
        Settings {
            table: TableKind::Snooker,
            ..Settings::online()
        }
    }

    #[test]
    fn snooker_rooms_of_6_10_and_15_reds_on_the_snooker_table_are_accepted() {
        for (reds, best_of) in [(15, 1), (10, 3), (6, 35)] {
            let msg = room(Variant::Snooker { reds, best_of }, snooker_table());
            assert_eq!(validate(msg.clone()), Ok(msg));
        }
    }

    #[test]
    fn a_three_cushion_room_on_the_carom_table_is_accepted() {
        let room = ClientMessage::CreateRoom {
            variant: Variant::three_cushion(),
            mode: Settings {
                table: TableKind::Carom,
                ..Settings::online()
            },
            aim_aid: super::super::messages::AimAid::Full,
            name: "ann".into(),
        };
        assert_eq!(validate(room.clone()), Ok(room));
    }
}
