//! Room codes, seat tokens and certificate fingerprints.

use std::fmt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::limits::ROOM_CODE_LEN;

/// Letters used in room codes: no 0/O, 1/I/L, so a code read aloud is typed right.
pub const ROOM_ALPHABET: &[u8; 32] = b"23456789ABCDEFGHJKMNPQRSTUVWXYZ_";

/// A short code naming a room, e.g. `K7QX2M4B`: 8 characters of 5 bits, 40 bits.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct RoomCode(String);

/// Why a room code or a fingerprint typed or pasted by a person was refused.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum IdError {
    #[error(
        "a room code is {ROOM_CODE_LEN} characters from {}",
        String::from_utf8_lossy(ROOM_ALPHABET)
    )]
    /// Not [`ROOM_CODE_LEN`] characters from [`ROOM_ALPHABET`].
    RoomCode,
    /// Not 64 hexadecimal digits.
    #[error("a fingerprint is 64 hexadecimal digits (SHA-256)")]
    Fingerprint,
}

impl RoomCode {
    /// Parses a code typed by a person (case-insensitive).
    pub fn parse(s: &str) -> Result<RoomCode, IdError> {
        let up = s.trim().to_ascii_uppercase();
        if up.len() == ROOM_CODE_LEN && up.bytes().all(|b| ROOM_ALPHABET.contains(&b)) {
            Ok(RoomCode(up))
        } else {
            Err(IdError::RoomCode)
        }
    }

    /// A code from random bytes (one byte per character).
    pub fn from_random(bytes: [u8; ROOM_CODE_LEN]) -> RoomCode {
        let s = bytes
            .iter()
            .map(|b| ROOM_ALPHABET[usize::from(b % 32)] as char)
            .collect();
        RoomCode(s)
    }

    /// Whether this is a well-formed code (a decoded message may carry anything).
    pub fn is_valid(&self) -> bool {
        RoomCode::parse(&self.0).is_ok_and(|c| c.0 == self.0)
    }

    /// The code in upper case, as shown to players.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for RoomCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl fmt::Debug for RoomCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "RoomCode({})", self.0)
    }
}

/// A secret that proves a connection holds a seat: 128 random bits, given once to the
/// player who took the seat. Its `Debug` never shows the bits, so it cannot leak into logs.
#[derive(Clone, Copy, Serialize, Deserialize)]
pub struct SeatToken(pub [u8; 16]);

impl SeatToken {
    /// Compares in constant time: how long a wrong guess takes says nothing about how much
    /// of it was right.
    pub fn matches(&self, other: &SeatToken) -> bool {
        let diff = self
            .0
            .iter()
            .zip(other.0.iter())
            .fold(0u8, |acc, (a, b)| acc | (a ^ b));
        std::hint::black_box(diff) == 0
    }
}

impl PartialEq for SeatToken {
    fn eq(&self, other: &SeatToken) -> bool {
        self.matches(other)
    }
}

impl Eq for SeatToken {}

impl fmt::Debug for SeatToken {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SeatToken(<secret>)")
    }
}

/// The SHA-256 digest of a server's certificate (DER), shown as 64 lowercase hex digits.
#[derive(Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fingerprint(pub [u8; 32]);

impl Fingerprint {
    /// Parses 64 hexadecimal digits (either case; surrounding white space is ignored).
    pub fn parse(s: &str) -> Result<Fingerprint, IdError> {
        let s = s.trim();
        if s.len() != 64 || !s.is_ascii() {
            return Err(IdError::Fingerprint);
        }
        let mut out = [0u8; 32];
        for (i, byte) in out.iter_mut().enumerate() {
            *byte =
                u8::from_str_radix(&s[2 * i..2 * i + 2], 16).map_err(|_| IdError::Fingerprint)?;
        }
        Ok(Fingerprint(out))
    }
}

impl fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.iter().try_for_each(|b| write!(f, "{b:02x}"))
    }
}

impl fmt::Debug for Fingerprint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Fingerprint({self})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_codes_parse_case_insensitively_and_refuse_ambiguous_letters() {
        assert_eq!(RoomCode::parse("k7qx2m4b").unwrap().as_str(), "K7QX2M4B");
        assert!(RoomCode::parse("K7QX2M4O").is_err());
        assert!(RoomCode::parse("K7QX2M4").is_err());
        assert!(RoomCode::from_random([0, 1, 2, 3, 200, 255, 31, 32]).is_valid());
        assert!(!RoomCode("k7qx2m4b".into()).is_valid());
    }

    #[test]
    fn room_codes_carry_at_least_40_bits() {
        let bits_per_char = ROOM_ALPHABET.len().ilog2() as usize;
        assert_eq!(1 << bits_per_char, ROOM_ALPHABET.len());
        assert!(bits_per_char * ROOM_CODE_LEN >= 40);
        // Every character of the code uses all 5 bits of its byte: 32 values give 32 codes.
        let distinct: std::collections::BTreeSet<String> = (0..32u8)
            .map(|b| RoomCode::from_random([b; ROOM_CODE_LEN]).0)
            .collect();
        assert_eq!(distinct.len(), 32);
    }

    #[test]
    fn tokens_match_only_themselves_and_never_print() {
        let a = SeatToken([7; 16]);
        let mut b = a;
        assert!(a.matches(&b));
        b.0[15] ^= 1;
        assert!(!a.matches(&b));
        assert!(!format!("{a:?}").contains('7'));
    }

    #[test]
    fn fingerprints_round_trip_through_hex() {
        let f = Fingerprint([0xab; 32]);
        assert_eq!(Fingerprint::parse(&f.to_string()), Ok(f));
        assert!(Fingerprint::parse("abc").is_err());
        assert!(Fingerprint::parse(&"zz".repeat(32)).is_err());
    }
}
