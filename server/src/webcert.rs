//! The certificate browsers are shown. A page trusts a self-signed server only through
//! WebTransport's `serverCertificateHashes`, which accepts an ECDSA certificate valid for at
//! most 14 days. So beside the long-lived identity ([`crate::tls::Identity`], which native
//! invites pin forever) the server keeps a short certificate for the `h3` ALPN: ECDSA P-256,
//! valid [`LIFETIME`] from [`BACKDATE`] before it was made, made again once less than
//! [`RENEW_BEFORE`] of it is left. The one it replaces is shown to no new connection but its
//! hash stays listed until it expires. Both live in the data directory, so a restart changes
//! no hash a link carries.
//!
//! The clock is injected ([`Clock`]), so a test can rotate without waiting days.

use std::fmt;
use std::fs;
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, RwLock};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use breakshot_shared::protocol::Fingerprint;
use rustls::crypto::CryptoProvider;
use rustls::pki_types::{CertificateDer, PrivateKeyDer, PrivatePkcs8KeyDer};
use rustls::sign::CertifiedKey;

use crate::tls::{fingerprint_of, CurrentCertificate, TlsError};

/// The short certificate being shown (DER).
pub const WEB_CERT_FILE: &str = "web-cert.der";
/// Its private key (PKCS#8 DER), mode 0600.
pub const WEB_KEY_FILE: &str = "web-key.der";
/// The certificate it replaced (DER), listed until it expires; absent when there is none.
pub const WEB_PREVIOUS_FILE: &str = "web-cert-previous.der";

const DAY: u64 = 24 * 3600;
/// How long a short certificate is valid: under the browsers' 14 days.
pub const LIFETIME: Duration = Duration::from_secs(13 * DAY);
/// How long before it was made a certificate's validity starts, for clients whose clock is
/// a little behind.
pub const BACKDATE: Duration = Duration::from_secs(3600);
/// A certificate with less than this left is replaced: a link printed just before still
/// works for as long.
pub const RENEW_BEFORE: Duration = Duration::from_secs(2 * DAY);
/// The most validity a browser accepts with `serverCertificateHashes`.
pub const BROWSER_MAX_VALIDITY: Duration = Duration::from_secs(14 * DAY);

/// Where the certificates get the time from.
pub trait Clock: Send + Sync {
    /// The current wall-clock time.
    fn now(&self) -> SystemTime;
}

/// The system's clock, the one in service.
#[derive(Debug, Default)]
pub struct SystemClock;

impl Clock for SystemClock {
    fn now(&self) -> SystemTime {
        SystemTime::now()
    }
}

/// Tests only: a clock that stands still until told to move.
#[derive(Debug)]
pub struct ManualClock(Mutex<SystemTime>);

impl ManualClock {
    /// A clock showing `at`.
    pub fn new(at: SystemTime) -> ManualClock {
        ManualClock(Mutex::new(at))
    }

    /// Moves the clock forward by `by`.
    pub fn advance(&self, by: Duration) {
        let mut now = self.0.lock().unwrap_or_else(|e| e.into_inner());
        *now += by;
    }
}

impl Clock for ManualClock {
    fn now(&self) -> SystemTime {
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A shared clock, as a [`crate::Config`] holds it.
#[derive(Clone)]
pub struct ClockRef(pub Arc<dyn Clock>);

impl Default for ClockRef {
    fn default() -> Self {
        ClockRef(Arc::new(SystemClock))
    }
}

impl fmt::Debug for ClockRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Clock")
    }
}

/// The certificate shown to new `h3` connections.
struct Current {
    key: Arc<CertifiedKey>,
    /// The key as kept in [`WEB_KEY_FILE`] (the signing key above cannot be read back).
    pkcs8: Vec<u8>,
    not_before: SystemTime,
    not_after: SystemTime,
    hash: Fingerprint,
}

/// The certificate that was replaced, kept for its hash.
struct Previous {
    cert: CertificateDer<'static>,
    not_after: SystemTime,
    hash: Fingerprint,
}

struct State {
    current: Current,
    previous: Option<Previous>,
}

struct Inner {
    dir: PathBuf,
    clock: Arc<dyn Clock>,
    provider: Arc<CryptoProvider>,
    state: RwLock<State>,
}

/// The short certificates, shared by the TLS configuration (which shows the current one),
/// the server (which refreshes them) and whoever publishes their hashes.
#[derive(Clone)]
pub struct WebCerts {
    inner: Arc<Inner>,
}

impl fmt::Debug for WebCerts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("WebCerts")
            .field("hashes", &self.hashes())
            .finish()
    }
}

impl WebCerts {
    /// Loads the short certificates kept in `dir`, making (and keeping) a new one if there is
    /// none, it is damaged, or it is due for replacement at the clock's time.
    pub fn load_or_create(dir: &Path, clock: ClockRef) -> Result<WebCerts, TlsError> {
        let provider = Arc::new(rustls::crypto::ring::default_provider());
        let now = clock.0.now();
        let loaded = load_current(dir, &provider)?;
        let previous = load_previous(dir)?;
        let (current, made) = match loaded {
            Some(current) => (current, false),
            None => (make(now, &provider)?, true),
        };
        let certs = WebCerts {
            inner: Arc::new(Inner {
                dir: dir.to_path_buf(),
                clock: clock.0,
                provider,
                state: RwLock::new(State { current, previous }),
            }),
        };
        if made {
            certs.persist(&certs.read())?;
        }
        certs.refresh()?;
        Ok(certs)
    }

    /// Replaces the current certificate if it is due (less than [`RENEW_BEFORE`] left, or
    /// not valid yet because the clock went back) and forgets a previous one that expired,
    /// keeping the result in the data directory. Returns whether anything changed. Cheap
    /// when nothing is due, so the server calls it often.
    pub fn refresh(&self) -> Result<bool, TlsError> {
        let now = self.inner.clock.now();
        let mut state = self.inner.state.write().unwrap_or_else(|e| e.into_inner());
        let due = now < state.current.not_before
            || state
                .current
                .not_after
                .duration_since(now)
                .unwrap_or_default()
                < RENEW_BEFORE;
        let expired = state.previous.as_ref().is_some_and(|p| p.not_after <= now);
        if !due && !expired {
            return Ok(false);
        }
        if due {
            let made = make(now, &self.inner.provider)?;
            let old = std::mem::replace(&mut state.current, made);
            let cert = old.key.cert.first().cloned();
            state.previous = cert.filter(|_| old.not_after > now).map(|cert| Previous {
                cert,
                not_after: old.not_after,
                hash: old.hash,
            });
            tracing::info!(hash = %state.current.hash, "new certificate for browsers");
        } else {
            state.previous = None;
        }
        // Served from memory at once, even if keeping it fails (the error says so).
        self.persist(&state)?;
        Ok(true)
    }

    /// SHA-256 of the certificates a page may be given, newest first: the current one, and the
    /// one it replaced until that expires.
    pub fn hashes(&self) -> Vec<Fingerprint> {
        let now = self.inner.clock.now();
        let state = self.read();
        let mut out = vec![state.current.hash];
        if let Some(p) = state.previous.as_ref().filter(|p| p.not_after > now) {
            out.push(p.hash);
        }
        out
    }

    /// The certificate and key a new `h3` connection is shown.
    pub fn current(&self) -> Arc<CertifiedKey> {
        self.read().current.key.clone()
    }

    fn read(&self) -> std::sync::RwLockReadGuard<'_, State> {
        self.inner.state.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Writes the state to the data directory: the previous certificate first, then the new
    /// key, then the new certificate, each replaced whole (written aside, then renamed). A
    /// crash in between leaves a key that does not match its certificate, which the next
    /// start replaces.
    fn persist(&self, state: &State) -> Result<(), TlsError> {
        let dir = &self.inner.dir;
        match &state.previous {
            Some(p) => replace(&dir.join(WEB_PREVIOUS_FILE), p.cert.as_ref(), false)?,
            None => match fs::remove_file(dir.join(WEB_PREVIOUS_FILE)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(io_error(&dir.join(WEB_PREVIOUS_FILE), e))
                }
                _ => {}
            },
        }
        let Some(cert) = state.current.key.cert.first() else {
            return Err(TlsError::Rustls(rustls::Error::NoCertificatesPresented));
        };
        replace(&dir.join(WEB_KEY_FILE), &state.current.pkcs8, true)?;
        replace(&dir.join(WEB_CERT_FILE), cert.as_ref(), false)
    }
}

/// A new short certificate, valid from [`BACKDATE`] before `now` for [`LIFETIME`].
fn make(now: SystemTime, provider: &CryptoProvider) -> Result<Current, TlsError> {
    let start = whole_seconds(now.checked_sub(BACKDATE).unwrap_or(UNIX_EPOCH));
    let end = start + LIFETIME;
    let key = rcgen::KeyPair::generate_for(&rcgen::PKCS_ECDSA_P256_SHA256)?;
    let mut params =
        rcgen::CertificateParams::new(vec!["breakshot".to_string(), "localhost".to_string()])?;
    params.distinguished_name = rcgen::DistinguishedName::new();
    params
        .distinguished_name
        .push(rcgen::DnType::CommonName, "breakshot (browsers)");
    params.not_before = start.into();
    params.not_after = end.into();
    let cert = params.self_signed(&key)?;
    current_of(cert.der().clone(), key.serialize_der(), provider).ok_or(TlsError::Rustls(
        rustls::Error::General("a certificate just made does not load".into()),
    ))
}

/// A certificate and its key as the TLS configuration serves them, with their validity;
/// `None` if they are malformed, do not match, or could not be shown to a browser.
fn current_of(
    cert: CertificateDer<'static>,
    key: Vec<u8>,
    provider: &CryptoProvider,
) -> Option<Current> {
    let (not_before, not_after) = validity(&cert)?;
    if not_after.duration_since(not_before).ok()? > BROWSER_MAX_VALIDITY {
        return None;
    }
    let hash = fingerprint_of(&cert);
    let certified = CertifiedKey::from_der(
        vec![cert],
        PrivateKeyDer::Pkcs8(PrivatePkcs8KeyDer::from(key.clone())),
        provider,
    )
    .ok()?;
    // An unknown match is not good enough here: the key must be the certificate's.
    certified.keys_match().ok()?;
    Some(Current {
        key: Arc::new(certified),
        pkcs8: key,
        not_before,
        not_after,
        hash,
    })
}

/// The certificate's validity, from its DER.
pub fn validity(cert: &CertificateDer<'_>) -> Option<(SystemTime, SystemTime)> {
    let (_, parsed) = x509_parser::parse_x509_certificate(cert.as_ref()).ok()?;
    let at = |t: i64| Some(UNIX_EPOCH + Duration::from_secs(u64::try_from(t).ok()?));
    let v = parsed.validity();
    Some((at(v.not_before.timestamp())?, at(v.not_after.timestamp())?))
}

fn whole_seconds(t: SystemTime) -> SystemTime {
    UNIX_EPOCH + Duration::from_secs(t.duration_since(UNIX_EPOCH).unwrap_or_default().as_secs())
}

fn io_error(path: &Path, source: std::io::Error) -> TlsError {
    TlsError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Reads a file, `None` if it is not there.
fn read_if_there(path: &Path) -> Result<Option<Vec<u8>>, TlsError> {
    match fs::read(path) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io_error(path, e)),
    }
}

fn load_current(dir: &Path, provider: &CryptoProvider) -> Result<Option<Current>, TlsError> {
    let (Some(cert), Some(key)) = (
        read_if_there(&dir.join(WEB_CERT_FILE))?,
        read_if_there(&dir.join(WEB_KEY_FILE))?,
    ) else {
        return Ok(None);
    };
    let current = current_of(CertificateDer::from(cert), key, provider);
    if current.is_none() {
        tracing::warn!("the certificate for browsers is damaged; making a new one");
    }
    Ok(current)
}

fn load_previous(dir: &Path) -> Result<Option<Previous>, TlsError> {
    let Some(der) = read_if_there(&dir.join(WEB_PREVIOUS_FILE))? else {
        return Ok(None);
    };
    let cert = CertificateDer::from(der);
    Ok(validity(&cert).map(|(_, not_after)| Previous {
        hash: fingerprint_of(&cert),
        cert,
        not_after,
    }))
}

/// Replaces `path` whole with `bytes`: written beside it, flushed, then renamed over it.
fn replace(path: &Path, bytes: &[u8], private: bool) -> Result<(), TlsError> {
    let aside = path.with_extension("new");
    let _ = fs::remove_file(&aside);
    let write = || -> std::io::Result<()> {
        let mut f = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(if private { 0o600 } else { 0o644 })
            .open(&aside)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&aside, path)
    };
    write().map_err(|e| io_error(path, e))
}

impl CurrentCertificate for WebCerts {
    fn current(&self) -> Arc<CertifiedKey> {
        WebCerts::current(self)
    }
}

#[cfg(test)]
mod tests {

    use x509_parser::oid_registry::{
        OID_EC_P256, OID_KEY_TYPE_EC_PUBLIC_KEY, OID_SIG_ECDSA_WITH_SHA256,
    };

    use super::*;

    /// 2026-12-02, a fixed start for the hand-moved clock.
    const START: Duration = Duration::from_secs(1_796_169_600);

    #[test]
    fn a_server_configuration_is_made_with_the_short_certificate_beside_the_identity() {
        let tmp = breakshot_testkit::scratch("webcert-config");
        let identity = crate::tls::Identity::load_or_create(tmp.path()).unwrap();
        let web = WebCerts::load_or_create(tmp.path(), Default::default()).unwrap();
        assert!(identity.server_config(Arc::new(web)).is_ok());
    }

    fn clock() -> (Arc<ManualClock>, ClockRef) {
        let clock = Arc::new(ManualClock::new(UNIX_EPOCH + START));
        (clock.clone(), ClockRef(clock))
    }

    fn der(certs: &WebCerts) -> CertificateDer<'static> {
        certs.current().cert[0].clone()
    }

    #[test]
    fn a_certificate_is_what_browsers_accept() {
        let tmp = breakshot_testkit::scratch("webcert");
        let (_, clock) = clock();
        let certs = WebCerts::load_or_create(tmp.path(), clock).unwrap();
        let der = der(&certs);
        let (_, cert) = x509_parser::parse_x509_certificate(der.as_ref()).unwrap();
        let key = cert.public_key();
        assert_eq!(key.algorithm.algorithm, OID_KEY_TYPE_EC_PUBLIC_KEY);
        let curve = key.algorithm.parameters.as_ref().unwrap().as_oid().unwrap();
        assert_eq!(curve, OID_EC_P256);
        assert_eq!(
            cert.signature_algorithm.algorithm,
            OID_SIG_ECDSA_WITH_SHA256
        );
        let v = cert.validity();
        let span = v.not_after.timestamp() - v.not_before.timestamp();
        assert_eq!(span, 13 * DAY as i64);
        assert!(span < 14 * DAY as i64);
        let start = START.as_secs() as i64;
        assert_eq!(v.not_before.timestamp(), start - 3600);
        assert_eq!(certs.hashes(), vec![fingerprint_of(&der)]);
    }

    #[test]
    fn a_certificate_is_replaced_two_days_before_it_ends_and_listed_until_it_does() {
        let tmp = breakshot_testkit::scratch("webcert");
        let (time, clock) = clock();
        let certs = WebCerts::load_or_create(tmp.path(), clock).unwrap();
        let first = certs.hashes()[0];
        // Made an hour into its validity: eleven days less an hour until two days are left.
        time.advance(Duration::from_secs(11 * DAY - 3600 - 1));
        assert!(!certs.refresh().unwrap());
        assert_eq!(certs.hashes(), vec![first]);
        time.advance(Duration::from_secs(2));
        assert!(certs.refresh().unwrap());
        let hashes = certs.hashes();
        assert_eq!(hashes.len(), 2);
        assert_ne!(hashes[0], first);
        assert_eq!(hashes[1], first);
        assert_eq!(fingerprint_of(&der(&certs)), hashes[0]);
        // Listed until it expires, not a second longer.
        time.advance(Duration::from_secs(2 * DAY - 2));
        assert_eq!(certs.hashes().len(), 2);
        time.advance(Duration::from_secs(1));
        assert_eq!(certs.hashes(), vec![hashes[0]]);
        assert!(certs.refresh().unwrap());
        assert!(!tmp.path().join(WEB_PREVIOUS_FILE).exists());
        assert!(!certs.refresh().unwrap());
    }

    #[test]
    fn a_restart_keeps_the_hashes_and_the_key_is_private() {
        let tmp = breakshot_testkit::scratch("webcert");
        let (time, clock) = clock();
        let certs = WebCerts::load_or_create(tmp.path(), clock.clone()).unwrap();
        time.advance(Duration::from_secs(12 * DAY));
        assert!(certs.refresh().unwrap());
        let hashes = certs.hashes();
        let again = WebCerts::load_or_create(tmp.path(), clock.clone()).unwrap();
        assert_eq!(again.hashes(), hashes);
        crate::tls::assert_private(&tmp.path().join(WEB_KEY_FILE));
        // A start long after both ended makes a new one and lists nothing old.
        time.advance(Duration::from_secs(30 * DAY));
        let late = WebCerts::load_or_create(tmp.path(), clock).unwrap();
        assert_eq!(late.hashes().len(), 1);
        assert!(!hashes.contains(&late.hashes()[0]));
    }

    #[test]
    fn a_damaged_or_mismatched_certificate_is_replaced() {
        let tmp = breakshot_testkit::scratch("webcert");
        let (_, clock) = clock();
        let first = WebCerts::load_or_create(tmp.path(), clock.clone()).unwrap();
        let other = breakshot_testkit::scratch("webcert-other");
        WebCerts::load_or_create(other.path(), clock.clone()).unwrap();
        // Another certificate's key: the pair no longer matches.
        fs::copy(
            other.path().join(WEB_KEY_FILE),
            tmp.path().join(WEB_KEY_FILE),
        )
        .unwrap();
        let again = WebCerts::load_or_create(tmp.path(), clock.clone()).unwrap();
        assert_ne!(again.hashes()[0], first.hashes()[0]);
        fs::write(tmp.path().join(WEB_CERT_FILE), b"not a certificate").unwrap();
        let third = WebCerts::load_or_create(tmp.path(), clock.clone()).unwrap();
        assert_ne!(third.hashes()[0], again.hashes()[0]);
        assert_eq!(
            WebCerts::load_or_create(tmp.path(), clock)
                .unwrap()
                .hashes(),
            third.hashes()
        );
    }

    #[test]
    fn a_clock_set_back_before_the_certificate_gets_a_new_one() {
        let tmp = breakshot_testkit::scratch("webcert");
        let (time, clock) = clock();
        WebCerts::load_or_create(tmp.path(), clock).unwrap();
        let earlier = ManualClock::new(time.now() - Duration::from_secs(2 * 3600));
        let certs = WebCerts::load_or_create(tmp.path(), ClockRef(Arc::new(earlier))).unwrap();
        let (not_before, _) = validity(&der(&certs)).unwrap();
        assert!(not_before <= time.now() - Duration::from_secs(2 * 3600));
    }
}
