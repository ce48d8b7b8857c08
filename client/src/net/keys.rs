//! Which key a connection proves. The window proves the player's own, kept between runs
//! (`client::memory::identity`) and handed here once at start ([`use_identity`]); everything
//! else (the load bot's seats, the tests' players) proves a fresh key of its own for each
//! connection, so two seats of one process are two players. The browser's page keeps its
//! key in the page's storage, so a player stays the same player from visit to visit.

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

/// Where the page keeps its player's key (the secret seed, in hex) between visits.
#[cfg(target_arch = "wasm32")]
const PAGE_KEY: &str = "breakshot.key";

/// The key the page's connections prove: the one the page's storage keeps (made and kept on
/// the first visit; a damaged one is replaced).
#[cfg(target_arch = "wasm32")]
pub fn for_connection() -> Identity {
    CHOSEN
        .get_or_init(|| {
            let kept = super::page::stored(PAGE_KEY).and_then(|hex| seed_from_hex(&hex));
            let seed = kept.unwrap_or_else(|| {
                let seed = fresh_seed();
                super::page::store(PAGE_KEY, &seed_to_hex(&seed));
                seed
            });
            Identity::from_seed(&seed)
        })
        .clone()
}

/// A new key pair from the system's (or the page's) random generator.
pub fn fresh() -> Identity {
    Identity::from_seed(&fresh_seed())
}

fn fresh_seed() -> [u8; SEED_LEN] {
    let mut seed = [0u8; SEED_LEN];
    // Without randomness no key is secret; nothing sensible can go on.
    if let Err(e) = fill(&mut seed) {
        panic!("no random generator for a player key: {e}");
    }
    seed
}

/// A seed as the page keeps it: lower-case hex.
#[cfg(any(target_arch = "wasm32", test))]
fn seed_to_hex(seed: &[u8; SEED_LEN]) -> String {
    seed.iter().map(|b| format!("{b:02x}")).collect()
}

/// The seed a kept text holds, if it is one (exactly the hex of [`SEED_LEN`] bytes).
#[cfg(any(target_arch = "wasm32", test))]
fn seed_from_hex(text: &str) -> Option<[u8; SEED_LEN]> {
    let text = text.trim();
    if text.len() != 2 * SEED_LEN || !text.is_ascii() {
        return None;
    }
    let mut seed = [0u8; SEED_LEN];
    for (k, b) in seed.iter_mut().enumerate() {
        *b = u8::from_str_radix(&text[2 * k..2 * k + 2], 16).ok()?;
    }
    Some(seed)
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

    #[test]
    fn a_kept_seed_reads_back_and_a_damaged_one_is_no_seed() {
        let seed = fresh_seed();
        assert_eq!(seed_from_hex(&seed_to_hex(&seed)), Some(seed));
        let hex = seed_to_hex(&seed);
        for damaged in [
            &hex[1..],
            "zz",
            "",
            &format!("{hex}00"),
            &hex.replace(&hex[..2], "g0"),
        ] {
            assert_eq!(seed_from_hex(damaged), None, "{damaged}");
        }
    }
}
