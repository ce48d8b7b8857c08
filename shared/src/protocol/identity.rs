//! A player's identity without a password: an Ed25519 key pair the client makes once and
//! keeps. `Hello` carries the public key; the server answers with a fresh random
//! `Challenge`, and the client's `Prove` signs it. On a server a player *is* their key; the
//! name they give is only shown beside it.
//!
//! What is signed ([`signed_message`]) covers the challenge and the connection's context
//! (the protocol version and physics the `Hello` claimed, and the key itself) under a
//! domain tag, so a signature is good for one connection's handshake only: the server
//! draws a new challenge for every connection and forgets it once answered, so a
//! signature seen on one connection proves nothing on another.

use ed25519_dalek::{Signature, Signer, SigningKey, Verifier, VerifyingKey};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Bytes of a public key on the wire.
pub const PUBLIC_KEY_LEN: usize = 32;
/// Bytes of a signature on the wire.
pub const SIGNATURE_LEN: usize = 64;
/// Bytes of a server's challenge.
pub const NONCE_LEN: usize = 32;
/// Bytes of the secret a key pair is made from (and kept as).
pub const SEED_LEN: usize = 32;

/// Keeps signatures of this handshake from meaning anything anywhere else.
const DOMAIN: &[u8] = b"breakshot hello proof\0";

/// A player as a server knows them: their Ed25519 public key.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PlayerKey(pub [u8; PUBLIC_KEY_LEN]);

impl PlayerKey {
    /// The key's bytes as the wire carries them, refused unless they are 32 bytes of a
    /// valid curve point.
    pub fn from_wire(bytes: &[u8]) -> Result<PlayerKey, IdentityError> {
        let bytes: [u8; PUBLIC_KEY_LEN] = bytes
            .try_into()
            .map_err(|_| IdentityError::KeyLength(bytes.len()))?;
        VerifyingKey::from_bytes(&bytes).map_err(|_| IdentityError::BadKey)?;
        Ok(PlayerKey(bytes))
    }

    /// The key in lowercase hex (64 characters), as the store and the operator see it.
    pub fn hex(&self) -> String {
        self.0.iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The key from [`PlayerKey::hex`]'s text.
    pub fn from_hex(text: &str) -> Option<PlayerKey> {
        if text.len() != 2 * PUBLIC_KEY_LEN || !text.is_ascii() {
            return None;
        }
        let mut bytes = [0u8; PUBLIC_KEY_LEN];
        for (i, b) in bytes.iter_mut().enumerate() {
            *b = u8::from_str_radix(&text[2 * i..2 * i + 2], 16).ok()?;
        }
        Some(PlayerKey(bytes))
    }

    /// The first 8 hex characters: enough to tell two players of one name apart on screen.
    pub fn short(&self) -> String {
        self.hex()[..8].to_owned()
    }

    /// Checks `signature` over the challenge `nonce` in the context `Hello` gave.
    pub fn verify(
        &self,
        nonce: &[u8; NONCE_LEN],
        protocol: u32,
        physics: u64,
        signature: &[u8],
    ) -> Result<(), IdentityError> {
        let signature: [u8; SIGNATURE_LEN] = signature
            .try_into()
            .map_err(|_| IdentityError::SignatureLength(signature.len()))?;
        let key = VerifyingKey::from_bytes(&self.0).map_err(|_| IdentityError::BadKey)?;
        let message = signed_message(self, nonce, protocol, physics);
        key.verify(&message, &Signature::from_bytes(&signature))
            .map_err(|_| IdentityError::Forged)
    }
}

impl std::fmt::Debug for PlayerKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PlayerKey({})", self.short())
    }
}

/// Why a key or a proof is refused.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum IdentityError {
    /// A public key must be exactly [`PUBLIC_KEY_LEN`] bytes.
    #[error("a player key is {PUBLIC_KEY_LEN} bytes, not {0}")]
    KeyLength(usize),
    /// The bytes are no Ed25519 public key.
    #[error("the player key is not a valid Ed25519 key")]
    BadKey,
    /// A signature must be exactly [`SIGNATURE_LEN`] bytes.
    #[error("a signature is {SIGNATURE_LEN} bytes, not {0}")]
    SignatureLength(usize),
    /// The signature does not prove the key over this connection's challenge.
    #[error("the signature does not prove the key over this connection's challenge")]
    Forged,
}

/// A player's key pair: the secret half stays on the player's machine.
#[derive(Clone)]
pub struct Identity {
    key: SigningKey,
}

impl Identity {
    /// The key pair made from 32 secret random bytes (the client draws them once and keeps
    /// them: see `client::memory`).
    pub fn from_seed(seed: &[u8; SEED_LEN]) -> Identity {
        Identity {
            key: SigningKey::from_bytes(seed),
        }
    }

    /// The secret the pair is made from, to keep it between runs.
    pub fn seed(&self) -> [u8; SEED_LEN] {
        self.key.to_bytes()
    }

    /// The public half, as servers know the player.
    pub fn public(&self) -> PlayerKey {
        PlayerKey(self.key.verifying_key().to_bytes())
    }

    /// The signature that answers challenge `nonce` in the context of a `Hello` claiming
    /// `protocol` and `physics`.
    pub fn sign(&self, nonce: &[u8; NONCE_LEN], protocol: u32, physics: u64) -> Vec<u8> {
        let message = signed_message(&self.public(), nonce, protocol, physics);
        self.key.sign(&message).to_bytes().to_vec()
    }
}

impl std::fmt::Debug for Identity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Identity({})", self.public().short())
    }
}

/// The bytes a proof signs: the domain tag, the `Hello`'s protocol and physics, the key and
/// the server's challenge.
pub fn signed_message(
    key: &PlayerKey,
    nonce: &[u8; NONCE_LEN],
    protocol: u32,
    physics: u64,
) -> Vec<u8> {
    let mut m = Vec::with_capacity(DOMAIN.len() + 12 + PUBLIC_KEY_LEN + NONCE_LEN);
    m.extend_from_slice(DOMAIN);
    m.extend_from_slice(&protocol.to_le_bytes());
    m.extend_from_slice(&physics.to_le_bytes());
    m.extend_from_slice(&key.0);
    m.extend_from_slice(nonce);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ann() -> Identity {
        Identity::from_seed(&[7; SEED_LEN])
    }

    #[test]
    fn a_proof_verifies_only_for_its_challenge_and_context() {
        let id = ann();
        let key = id.public();
        let nonce = [1; NONCE_LEN];
        let sig = id.sign(&nonce, 4, 99);
        assert_eq!(key.verify(&nonce, 4, 99, &sig), Ok(()));
        assert_eq!(
            key.verify(&[2; NONCE_LEN], 4, 99, &sig),
            Err(IdentityError::Forged)
        );
        assert_eq!(key.verify(&nonce, 3, 99, &sig), Err(IdentityError::Forged));
        assert_eq!(key.verify(&nonce, 4, 98, &sig), Err(IdentityError::Forged));
        let other = Identity::from_seed(&[8; SEED_LEN]).public();
        assert_eq!(
            other.verify(&nonce, 4, 99, &sig),
            Err(IdentityError::Forged)
        );
        let mut flipped = sig.clone();
        flipped[10] ^= 1;
        assert_eq!(
            key.verify(&nonce, 4, 99, &flipped),
            Err(IdentityError::Forged)
        );
        assert_eq!(
            key.verify(&nonce, 4, 99, &sig[..63]),
            Err(IdentityError::SignatureLength(63))
        );
    }

    #[test]
    fn keys_of_the_wrong_length_or_off_the_curve_are_refused() {
        assert_eq!(
            PlayerKey::from_wire(&[0; 31]),
            Err(IdentityError::KeyLength(31))
        );
        assert_eq!(
            PlayerKey::from_wire(&[0; 33]),
            Err(IdentityError::KeyLength(33))
        );
        assert_eq!(PlayerKey::from_wire(&[]), Err(IdentityError::KeyLength(0)));
        let key = ann().public();
        assert_eq!(PlayerKey::from_wire(&key.0), Ok(key));
        // y = 2 has no x on the curve: not a point.
        let mut off = [0u8; 32];
        off[0] = 2;
        assert_eq!(PlayerKey::from_wire(&off), Err(IdentityError::BadKey));
    }

    #[test]
    fn a_key_survives_its_seed_and_its_hex() {
        let id = ann();
        assert_eq!(Identity::from_seed(&id.seed()).public(), id.public());
        let hex = id.public().hex();
        assert_eq!(hex.len(), 64);
        assert_eq!(PlayerKey::from_hex(&hex), Some(id.public()));
        assert_eq!(PlayerKey::from_hex("zz"), None);
        assert_eq!(PlayerKey::from_hex(&"é".repeat(32)), None);
    }
}
