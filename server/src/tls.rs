//! The server's identity: a self-signed certificate made once and kept in the data
//! directory, so its SHA-256 fingerprint (what invites carry and clients pin) never changes.

use std::fs;
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use breakshot_shared::protocol::{limits, Fingerprint, ALPN, WEB_ALPN};
use rustls::pki_types::{CertificateDer, PrivateKeyDer, PrivatePkcs8KeyDer};
use rustls::server::{ClientHello, ResolvesServerCert};
use rustls::sign::CertifiedKey;
use sha2::{Digest, Sha256};
use thiserror::Error;

/// The certificate (DER) in the data directory; if it is lost, a new one is made and every
/// earlier invite stops working.
pub const CERT_FILE: &str = "cert.der";
/// The certificate's private key (PKCS#8 DER), mode 0600: whoever has it can impersonate the
/// server.
pub const KEY_FILE: &str = "key.der";
/// The secret behind QUIC stateless resets, kept so that a restarted server can tell the
/// clients of its previous run at once that their connections are gone (instead of leaving
/// them to wait for the idle timeout).
pub const RESET_KEY_FILE: &str = "reset.key";

/// Keep-alive so a thinking player's connection never idles out (the protocol's value).
pub const KEEP_ALIVE: Duration = limits::KEEP_ALIVE;
/// A peer silent this long is gone (the protocol's value).
pub const IDLE_TIMEOUT: Duration = limits::IDLE_TIMEOUT;

/// Why the server's identity could not be loaded, made or used.
#[derive(Debug, Error)]
pub enum TlsError {
    /// A file of the identity in the data directory could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// The self-signed certificate could not be made.
    #[error("making the certificate: {0}")]
    Generate(#[from] rcgen::Error),
    /// rustls refused the certificate or key (a damaged `cert.der` or `key.der`, say).
    #[error("TLS: {0}")]
    Rustls(#[from] rustls::Error),
    /// The Noise key could not be made or used.
    #[error("Noise key: {0}")]
    Noise(String),
    /// quinn refused the TLS or transport configuration.
    #[error("QUIC TLS: {0}")]
    Quic(String),
}

/// The server's certificate and key, as kept in [`CERT_FILE`] and [`KEY_FILE`].
pub struct Identity {
    /// The self-signed certificate; its SHA-256 is the fingerprint.
    pub cert: CertificateDer<'static>,
    /// The certificate's private key (PKCS#8), as secret as the server itself.
    pub key: PrivatePkcs8KeyDer<'static>,
}

impl Identity {
    /// Loads the identity from `dir`, making and saving one on first start.
    pub fn load_or_create(dir: &Path) -> Result<Identity, TlsError> {
        let cert_path = dir.join(CERT_FILE);
        let key_path = dir.join(KEY_FILE);
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| TlsError::Io { path, source }
        };
        if cert_path.exists() && key_path.exists() {
            let cert = fs::read(&cert_path).map_err(io(&cert_path))?;
            let key = fs::read(&key_path).map_err(io(&key_path))?;
            return Ok(Identity {
                cert: CertificateDer::from(cert),
                key: PrivatePkcs8KeyDer::from(key),
            });
        }
        let made = rcgen::generate_simple_self_signed(vec![
            "breakshot".to_string(),
            "localhost".to_string(),
        ])?;
        let key = made.signing_key.serialize_der();
        // The key first, readable by the owner only; the certificate last, so a crash in
        // between leaves no certificate without its key.
        write_private(&key_path, &key).map_err(io(&key_path))?;
        fs::write(&cert_path, made.cert.der()).map_err(io(&cert_path))?;
        Ok(Identity {
            cert: made.cert.der().clone(),
            key: PrivatePkcs8KeyDer::from(key),
        })
    }

    /// SHA-256 of the certificate: what invites carry and clients pin.
    pub fn fingerprint(&self) -> Fingerprint {
        fingerprint_of(&self.cert)
    }

    /// The QUIC server configuration: ring only, TLS 1.3, ALPNs `breakshot/1` (shown this
    /// identity's certificate) and `h3` (shown `web`'s current short certificate, see
    /// [`ByAlpn`]), keep-alive and idle timeout as above.
    pub fn server_config(
        &self,
        web: Arc<dyn CurrentCertificate>,
    ) -> Result<quinn::ServerConfig, TlsError> {
        let provider = Arc::new(rustls::crypto::ring::default_provider());
        let native = CertifiedKey::from_der(
            vec![self.cert.clone()],
            PrivateKeyDer::Pkcs8(self.key.clone_key()),
            &provider,
        )?;
        let mut tls = rustls::ServerConfig::builder_with_provider(provider)
            .with_protocol_versions(&[&rustls::version::TLS13])?
            .with_no_client_auth()
            .with_cert_resolver(Arc::new(ByAlpn {
                native: Arc::new(native),
                web,
            }));
        tls.alpn_protocols = SERVER_ALPNS.iter().map(|a| a.to_vec()).collect();
        let crypto = quinn::crypto::rustls::QuicServerConfig::try_from(tls)
            .map_err(|e| TlsError::Quic(e.to_string()))?;
        let mut config = quinn::ServerConfig::with_crypto(Arc::new(crypto));
        let mut transport = quinn::TransportConfig::default();
        transport.keep_alive_interval(Some(KEEP_ALIVE));
        transport.max_idle_timeout(Some(
            quinn::IdleTimeout::try_from(IDLE_TIMEOUT)
                .map_err(|e| TlsError::Quic(e.to_string()))?,
        ));
        // What HTTP/3 needs (Chromium refuses a connection that offers fewer unidirectional
        // streams), since the ALPN is not known when these are sent; a native connection is
        // held to its one stream once it is ([`native_streams`]). Whatever a client leaves
        // unread on streams nobody accepts is bounded by the connection's receive window.
        transport.max_concurrent_bidi_streams(H3_BIDI_STREAMS.into());
        transport.max_concurrent_uni_streams(H3_UNI_STREAMS.into());
        transport.receive_window(CONNECTION_WINDOW.into());
        config.transport_config(Arc::new(transport));
        Ok(config)
    }
}

/// Bidirectional streams a client may have open: an `h3` client's CONNECT request and game
/// stream; a native client uses one.
const H3_BIDI_STREAMS: u32 = 2;
/// Unidirectional streams a client may open: an `h3` client's HTTP/3 control stream and its
/// two QPACK streams; a native client uses none.
const H3_UNI_STREAMS: u32 = 3;
/// The most bytes a client may have sent that the server has not read, over all its streams:
/// sixteen whole frames, far more than a game has in flight.
const CONNECTION_WINDOW: u32 = 16 * limits::MAX_FRAME as u32;

/// Grants a native connection (its ALPN now known) no stream beyond the one it opens: the
/// room HTTP/3 would have needed is never renewed.
pub fn native_streams(conn: &quinn::Connection) {
    conn.set_max_concurrent_bi_streams(1u32.into());
    conn.set_max_concurrent_uni_streams(0u32.into());
}

/// The ALPNs the server offers, in its order of preference (rustls picks the first of these
/// the client offers; [`ByAlpn`] must pick the same).
const SERVER_ALPNS: [&[u8]; 2] = [ALPN, WEB_ALPN];

/// Chooses the certificate by the ALPN the handshake will settle on: the long-lived one for
/// the native protocol (so every invite and remembered seat keeps working), the short one
/// for `h3`, which is all a browser can be made to trust.
#[derive(Debug)]
pub struct ByAlpn {
    native: Arc<CertifiedKey>,
    web: Arc<dyn CurrentCertificate>,
}

/// The certificate shown to browsers now (the short one, replaced before it ends:
/// `webcert::WebCerts`).
pub trait CurrentCertificate: std::fmt::Debug + Send + Sync {
    /// The certificate and key to show in a handshake starting now.
    fn current(&self) -> Arc<CertifiedKey>;
}

impl ResolvesServerCert for ByAlpn {
    fn resolve(&self, hello: ClientHello<'_>) -> Option<Arc<CertifiedKey>> {
        match chosen_alpn(hello.alpn().map(|offered| offered.collect())) {
            Some(WEB_ALPN) => Some(self.web.current()),
            // The native protocol, or none (the handshake then fails on the ALPN anyway).
            _ => Some(self.native.clone()),
        }
    }
}

/// The ALPN rustls will choose among what the client offered: the first of ours it offered.
fn chosen_alpn(offered: Option<Vec<&[u8]>>) -> Option<&'static [u8]> {
    let offered = offered?;
    SERVER_ALPNS
        .iter()
        .copied()
        .find(|ours| offered.contains(ours))
}

/// Loads the stateless-reset secret from `dir`, or makes and keeps a new one (mode 0600).
/// A damaged file is replaced: a new secret only costs the resets of connections in flight.
pub fn reset_key(dir: &Path) -> Result<[u8; 32], TlsError> {
    kept_secret(&dir.join(RESET_KEY_FILE), None)
}

/// Loads the 32-byte secret at `path`, or makes and keeps a new one (mode 0600) when there is
/// none. A file of another length is replaced, or with `refuse_damaged` refused with that
/// reason (when a new secret would break what was given out with the old one).
pub(crate) fn kept_secret(path: &Path, refuse_damaged: Option<&str>) -> Result<[u8; 32], TlsError> {
    let io = |source| TlsError::Io {
        path: path.display().to_string(),
        source,
    };
    match fs::read(path) {
        Ok(bytes) => match (<[u8; 32]>::try_from(bytes.as_slice()), refuse_damaged) {
            (Ok(key), _) => return Ok(key),
            (Err(_), Some(why)) => return Err(io(std::io::Error::other(why))),
            (Err(_), None) => {}
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(io(e)),
    }
    let mut key = [0u8; 32];
    getrandom::fill(&mut key).map_err(|e| io(std::io::Error::other(e.to_string())))?;
    // A damaged file is removed first, so the new one is created with mode 0600 whatever
    // mode the old one had.
    let _ = fs::remove_file(path);
    write_private(path, &key).map_err(io)?;
    Ok(key)
}

/// Fails the test unless the file at `path` is readable by its owner only (mode 0600).
#[cfg(test)]
pub(crate) fn assert_private(path: &Path) {
    use std::os::unix::fs::PermissionsExt;
    let mode = fs::metadata(path).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o600, "{}", path.display());
}

/// SHA-256 of a certificate's DER bytes, the fingerprint clients compare with the invite's.
pub fn fingerprint_of(cert: &CertificateDer<'_>) -> Fingerprint {
    Fingerprint(Sha256::digest(cert.as_ref()).into())
}

/// Writes a new secret file readable by its owner only (mode 0600).
pub(crate) fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .mode(0o600)
        .open(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

#[cfg(test)]
mod tests {
    use std::os::unix::fs::PermissionsExt;

    use super::*;

    #[test]
    fn the_identity_is_made_once_and_kept_private() {
        let tmp = breakshot_testkit::scratch("tls");
        let dir = tmp.path().to_path_buf();
        let first = Identity::load_or_create(&dir).unwrap();
        let again = Identity::load_or_create(&dir).unwrap();
        assert_eq!(first.fingerprint(), again.fingerprint());
        crate::tls::assert_private(&dir.join(KEY_FILE));
    }

    #[test]
    fn the_alpn_chosen_is_the_first_of_ours_the_client_offers() {
        assert_eq!(chosen_alpn(Some(vec![b"h3"])), Some(WEB_ALPN));
        assert_eq!(chosen_alpn(Some(vec![ALPN])), Some(ALPN));
        assert_eq!(chosen_alpn(Some(vec![b"h3", ALPN])), Some(ALPN));
        assert_eq!(chosen_alpn(Some(vec![b"h2"])), None);
        assert_eq!(chosen_alpn(None), None);
    }

    #[test]
    fn the_reset_secret_is_made_once_and_kept_private() {
        let tmp = breakshot_testkit::scratch("reset");
        let dir = tmp.path().to_path_buf();
        let first = reset_key(&dir).unwrap();
        assert_eq!(reset_key(&dir).unwrap(), first);
        crate::tls::assert_private(&dir.join(RESET_KEY_FILE));
        // A damaged file is replaced rather than trusted.
        fs::write(dir.join(RESET_KEY_FILE), b"short").unwrap();
        fs::set_permissions(dir.join(RESET_KEY_FILE), fs::Permissions::from_mode(0o644)).unwrap();
        assert_ne!(reset_key(&dir).unwrap(), first);
        crate::tls::assert_private(&dir.join(RESET_KEY_FILE));
    }
}
