//! Which key a connection proves. The window proves the player's own, kept between runs
//! (`client::memory::identity`) and handed here once at start ([`use_identity`]); everything
//! else (the load bot's seats, the tests' players) proves a fresh key of its own for each
//! connection, so two seats of one process are two players. The browser's page makes one
//! key per visit.

use std::sync::OnceLock;

use breakshot_shared::protocol::identity::SEED_LEN;
use breakshot_shared::protocol::Identity;

static CHOSEN: OnceLock<Identity> = OnceLock::new();

/// Makes every later connection of this process prove `identity` (the first call counts).
pub fn use_identity(identity: Identity) {
    let _ = CHOSEN.set(identity);
}

/// The key the next connection proves: the one chosen with [`use_identity`], else a fresh one.
#[cfg(not(target_arch = "wasm32"))]
pub fn for_connection() -> Identity {
    CHOSEN.get().cloned().unwrap_or_else(fresh)
}

/// The key the page's connections prove: one made for this visit of the page (the page does
/// not keep it: a reload is a new player, see docs/web.md).
#[cfg(target_arch = "wasm32")]
pub fn for_connection() -> Identity {
    CHOSEN.get_or_init(fresh).clone()
}

/// A new key pair from the system's (or the page's) random generator.
pub fn fresh() -> Identity {
    let mut seed = [0u8; SEED_LEN];
    // Without randomness no key is secret; nothing sensible can go on.
    if let Err(e) = fill(&mut seed) {
        panic!("no random generator for a player key: {e}");
    }
    Identity::from_seed(&seed)
}

#[cfg(not(target_arch = "wasm32"))]
fn fill(dest: &mut [u8]) -> Result<(), String> {
    getrandom::fill(dest).map_err(|e| e.to_string())
}

#[cfg(target_arch = "wasm32")]
fn fill(dest: &mut [u8]) -> Result<(), String> {
    super::page::fill_random(dest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresh_keys_differ() {
        assert_ne!(fresh().public(), fresh().public());
    }
}
