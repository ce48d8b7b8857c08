//! The server's Noise static key (X25519) for the browser's WebSocket: made once, kept in the
//! data directory (`noise.key`, the 32-byte private key, mode 0600), so every web link stays
//! valid across restarts.

use std::path::Path;

use snow::params::DHChoice;
use snow::resolvers::{CryptoResolver, DefaultResolver};

use crate::tls::{kept_secret, TlsError};

/// The key's file in the data directory.
pub const NOISE_KEY_FILE: &str = "noise.key";

/// The server's static X25519 key pair.
#[derive(Clone)]
pub struct NoiseKey {
    /// The private key, as secret as the server itself.
    pub private: [u8; 32],
    /// The public key, as web links carry it (`key=`).
    pub public: [u8; 32],
}

impl std::fmt::Debug for NoiseKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "NoiseKey(public {:02x?})", self.public)
    }
}

impl NoiseKey {
    /// The pair of `private`.
    pub fn from_private(private: [u8; 32]) -> Result<NoiseKey, TlsError> {
        let mut dh = DefaultResolver
            .resolve_dh(&DHChoice::Curve25519)
            .ok_or_else(|| TlsError::Noise("no X25519 in this build".into()))?;
        dh.set(&private);
        let public = <[u8; 32]>::try_from(dh.pubkey())
            .map_err(|_| TlsError::Noise("an X25519 public key is 32 bytes".into()))?;
        Ok(NoiseKey { private, public })
    }

    /// Loads the key from `dir`, making and saving one on first start. A damaged file is an
    /// error rather than replaced: a new key would silently break every link given out.
    pub fn load_or_create(dir: &Path) -> Result<NoiseKey, TlsError> {
        let private = kept_secret(
            &dir.join(NOISE_KEY_FILE),
            Some(
                "not a 32-byte key; remove it to make a new one (web links given out stop working)",
            ),
        )?;
        NoiseKey::from_private(private)
    }
}

#[cfg(test)]
mod tests {
    use std::fs;

    use super::*;

    #[test]
    fn the_key_is_made_once_kept_private_and_never_silently_replaced() {
        let tmp = tempfile::tempdir().unwrap();
        let first = NoiseKey::load_or_create(tmp.path()).unwrap();
        let again = NoiseKey::load_or_create(tmp.path()).unwrap();
        assert_eq!(first.public, again.public);
        assert_ne!(first.public, first.private);
        crate::tls::assert_private(&tmp.path().join(NOISE_KEY_FILE));
        fs::write(tmp.path().join(NOISE_KEY_FILE), b"short").unwrap();
        assert!(NoiseKey::load_or_create(tmp.path()).is_err());
    }
}
