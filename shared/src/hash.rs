//! The state hash: a fingerprint of every ball's exact bits, the same on every machine.

use crate::physics::{BallState, MotionState};

/// FNV-1a (64-bit) over every ball's position, velocity, spin, motion state and pocket (and
/// height and vertical velocity of a ball in flight), in ball order. `-0.0` is folded into `0.0` so that equal numbers hash equal.
pub fn state_hash(balls: &[BallState]) -> u64 {
    let mut h = Fnv::new();
    h.write(&(balls.len() as u64).to_le_bytes());
    for b in balls {
        for x in [
            b.pos.x, b.pos.y, b.vel.x, b.vel.y, b.spin.x, b.spin.y, b.spin.z,
        ] {
            let x = if x == 0.0 { 0.0 } else { x };
            h.write(&x.to_bits().to_le_bytes());
        }
        let state = match b.motion {
            MotionState::Stationary => 0u8,
            MotionState::Spinning => 1,
            MotionState::Sliding => 2,
            MotionState::Rolling => 3,
            MotionState::Pocketed => 4,
            MotionState::Airborne => 5,
            MotionState::OffTable => 6,
        };
        h.write(&[state, b.pocket.map_or(255, |p| p)]);
        if b.motion == MotionState::Airborne {
            // Only a ball in flight has a height and a vertical velocity.
            for x in [b.lift, b.vz] {
                let x = if x == 0.0 { 0.0 } else { x };
                h.write(&x.to_bits().to_le_bytes());
            }
        }
    }
    h.finish()
}

/// One link of a chain of hashes: FNV-1a (64-bit) over the previous link and `bytes`, so
/// each link depends on everything before it (a game record's entries are chained so).
pub fn chain_hash(prev: u64, bytes: &[u8]) -> u64 {
    let mut h = Fnv::new();
    h.write(&prev.to_le_bytes());
    h.write(bytes);
    h.finish()
}

/// Formats a hash the way results and records show it: 16 hex digits.
pub fn hash_hex(h: u64) -> String {
    format!("{h:016x}")
}

struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn finish(&self) -> u64 {
        self.0
    }
}
