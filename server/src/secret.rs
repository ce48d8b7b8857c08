//! Seat tokens and randomness. The server keeps only a digest of each token (in memory and
//! on disk), so neither a log nor a stolen database hands out seats.

use breakshot_shared::protocol::SeatToken;
use breakshot_shared::rules::rack::SplitMix64;
use sha2::{Digest, Sha256};

/// SHA-256 of a seat token.
#[derive(
    Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug, serde::Serialize, serde::Deserialize,
)]
pub struct TokenDigest(pub [u8; 32]);

impl TokenDigest {
    /// The digest kept in place of `token`, which is never stored or logged.
    pub fn of(token: &SeatToken) -> TokenDigest {
        TokenDigest(Sha256::digest(token.0).into())
    }

    /// Constant-time comparison.
    pub fn matches(&self, other: &TokenDigest) -> bool {
        let diff = self
            .0
            .iter()
            .zip(other.0.iter())
            .fold(0u8, |acc, (a, b)| acc | (a ^ b));
        std::hint::black_box(diff) == 0
    }
}

/// Where random bytes come from: the operating system in the server, a fixed sequence in
/// tests so that room codes and seeds are reproducible.
pub trait Entropy: Send {
    /// Fills all of `buf` with random bytes (they become room codes, seat tokens and seeds).
    fn fill(&mut self, buf: &mut [u8]);
}

/// The operating system's generator.
pub struct OsEntropy;

impl Entropy for OsEntropy {
    fn fill(&mut self, buf: &mut [u8]) {
        // The OS generator failing is not something a game server can work around; the
        // bytes would otherwise be predictable tokens.
        if let Err(e) = getrandom::fill(buf) {
            panic!("the operating system's random generator failed: {e}");
        }
    }
}

/// A deterministic stream for tests: the rules' SplitMix64 from a seed.
pub struct TestEntropy(SplitMix64);

impl TestEntropy {
    /// The same bytes for the same `seed` on every run and platform.
    pub fn new(seed: u64) -> TestEntropy {
        TestEntropy(SplitMix64::new(seed))
    }
}

impl Entropy for TestEntropy {
    fn fill(&mut self, buf: &mut [u8]) {
        for chunk in buf.chunks_mut(8) {
            let z = self.0.next_u64();
            chunk.copy_from_slice(&z.to_le_bytes()[..chunk.len()]);
        }
    }
}

/// A fresh 128-bit seat token; only the player who takes the seat is sent it.
pub fn new_token(rng: &mut dyn Entropy) -> SeatToken {
    let mut t = [0u8; 16];
    rng.fill(&mut t);
    SeatToken(t)
}

/// A fresh game seed: it draws the racks, and is recorded, so a replay needs no randomness.
pub fn new_seed(rng: &mut dyn Entropy) -> u64 {
    let mut b = [0u8; 8];
    rng.fill(&mut b);
    u64::from_le_bytes(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digests_match_their_token_only() {
        let mut rng = TestEntropy::new(1);
        let a = new_token(&mut rng);
        let b = new_token(&mut rng);
        assert!(TokenDigest::of(&a).matches(&TokenDigest::of(&a)));
        assert!(!TokenDigest::of(&a).matches(&TokenDigest::of(&b)));
    }
}
