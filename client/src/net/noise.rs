//! The WebSocket way in, encrypted: a [`Transport`] of whole messages (one WebSocket message
//! each) wrapped in the Noise handshake `NK` that docs/web.md describes, so that the game's
//! bytes are encrypted and the server is the one whose key the link names. Without I/O: it
//! is tested natively against a responder in memory.

use breakshot_shared::protocol::web::{
    MAX_NOISE_MESSAGE as MAX_MESSAGE, MAX_NOISE_PAYLOAD, NOISE_KEY_LEN, NOISE_PATTERN as PATTERN,
    NOISE_PROLOGUE as PROLOGUE,
};
use breakshot_shared::protocol::{Fingerprint, ServerAddress};
use snow::params::{CipherChoice, DHChoice, HashChoice, NoiseParams};
use snow::resolvers::{CryptoResolver, DefaultResolver};
use snow::types::{Cipher, Dh, Hash, Random};
use snow::{HandshakeState, TransportState};

use super::error::NetError;
use super::polled::{Transport, TransportEvent};

/// Fills `dest` with random bytes from the system, or in a browser from the page's
/// `crypto.getRandomValues`.
pub type FillRandom = fn(&mut [u8]) -> Result<(), String>;

/// Where the handshake stands.
enum State {
    /// Nothing open, or the connection is being opened.
    Idle,
    /// Message 1 sent; waiting for the server's message 2.
    Handshaking(Box<HandshakeState>),
    /// Both sides hold the session keys.
    Ready(Box<TransportState>),
}

/// A [`Transport`] of bytes over a `T` of whole messages, through Noise `NK` to the server
/// whose static key is `server_key`.
pub struct Noised<T: Transport> {
    inner: T,
    server_key: [u8; NOISE_KEY_LEN],
    random: FillRandom,
    state: State,
}

impl<T: Transport> Noised<T> {
    /// `inner` encrypted to the server with the static public key `server_key`.
    pub fn new(inner: T, server_key: [u8; NOISE_KEY_LEN], random: FillRandom) -> Noised<T> {
        Noised {
            inner,
            server_key,
            random,
            state: State::Idle,
        }
    }

    /// The message transport under the encryption.
    pub fn inner(&self) -> &T {
        &self.inner
    }

    /// Starts the handshake on an opened connection: builds the initiator, sends message 1.
    fn start(&mut self) -> Result<(), NetError> {
        let broken = |e: snow::Error| NetError::Connect(format!("encryption: {e}"));
        let params: NoiseParams = PATTERN.parse().map_err(broken)?;
        let resolver = Resolver {
            random: self.random,
        };
        let mut hs = snow::Builder::with_resolver(params, Box::new(resolver))
            .prologue(PROLOGUE)
            .map_err(broken)?
            .remote_public_key(&self.server_key)
            .map_err(broken)?
            .build_initiator()
            .map_err(broken)?;
        let mut msg = vec![0u8; MAX_MESSAGE];
        let n = hs.write_message(&[], &mut msg).map_err(broken)?;
        self.inner.send(&msg[..n]);
        self.state = State::Handshaking(Box::new(hs));
        Ok(())
    }

    /// Ends the connection because of `why`.
    fn fail(&mut self, why: NetError) -> Option<TransportEvent> {
        self.inner.close();
        self.state = State::Idle;
        Some(TransportEvent::Failed(why))
    }
}

impl<T: Transport> Transport for Noised<T> {
    fn open(&mut self, server: &ServerAddress, fingerprint: Fingerprint) {
        self.state = State::Idle;
        self.inner.open(server, fingerprint);
    }

    fn send(&mut self, bytes: &[u8]) {
        let State::Ready(session) = &mut self.state else {
            // Nothing is sent before the core hears `Opened`, which waits for the keys.
            return;
        };
        let mut msg = vec![0u8; MAX_MESSAGE];
        for piece in bytes.chunks(MAX_NOISE_PAYLOAD) {
            match session.write_message(piece, &mut msg) {
                Ok(n) => self.inner.send(&msg[..n]),
                Err(e) => {
                    tracing::error!(error = %e, "cannot encrypt a message");
                    self.inner.close();
                    self.state = State::Idle;
                    return;
                }
            }
        }
    }

    fn close(&mut self) {
        self.state = State::Idle;
        self.inner.close();
    }

    fn poll(&mut self) -> Option<TransportEvent> {
        loop {
            let event = self.inner.poll()?;
            match (event, &mut self.state) {
                (TransportEvent::Opened, _) => {
                    if let Err(e) = self.start() {
                        return self.fail(e);
                    }
                }
                (TransportEvent::Received(msg), State::Handshaking(hs)) => {
                    let mut payload = vec![0u8; MAX_MESSAGE];
                    // Only the holder of the key the link names can answer message 1.
                    if hs.read_message(&msg, &mut payload).is_err() || !hs.is_handshake_finished() {
                        return self.fail(NetError::WrongKey);
                    }
                    let State::Handshaking(hs) = std::mem::replace(&mut self.state, State::Idle)
                    else {
                        unreachable!("matched above")
                    };
                    match hs.into_transport_mode() {
                        Ok(session) => {
                            self.state = State::Ready(Box::new(session));
                            return Some(TransportEvent::Opened);
                        }
                        Err(e) => return self.fail(NetError::Connect(format!("encryption: {e}"))),
                    }
                }
                (TransportEvent::Received(msg), State::Ready(session)) => {
                    let mut payload = vec![0u8; msg.len()];
                    match session.read_message(&msg, &mut payload) {
                        Ok(n) => {
                            payload.truncate(n);
                            return Some(TransportEvent::Received(payload));
                        }
                        Err(_) => {
                            return self.fail(NetError::Lost(
                                "a message from the server failed to decrypt".into(),
                            ))
                        }
                    }
                }
                // Bytes before the connection was asked for belong to no connection.
                (TransportEvent::Received(_), State::Idle) => {}
                (TransportEvent::Failed(e), _) => {
                    self.state = State::Idle;
                    return Some(TransportEvent::Failed(e));
                }
            }
        }
    }
}

/// The default primitives, with randomness from [`FillRandom`]: the browser build has no
/// system randomness of its own.
struct Resolver {
    random: FillRandom,
}

struct Rng(FillRandom);

impl Random for Rng {
    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), snow::Error> {
        (self.0)(dest).map_err(|_| snow::Error::Rng)
    }
}

impl CryptoResolver for Resolver {
    fn resolve_rng(&self) -> Option<Box<dyn Random>> {
        Some(Box::new(Rng(self.random)))
    }

    fn resolve_dh(&self, choice: &DHChoice) -> Option<Box<dyn Dh>> {
        DefaultResolver.resolve_dh(choice)
    }

    fn resolve_hash(&self, choice: &HashChoice) -> Option<Box<dyn Hash>> {
        DefaultResolver.resolve_hash(choice)
    }

    fn resolve_cipher(&self, choice: &CipherChoice) -> Option<Box<dyn Cipher>> {
        DefaultResolver.resolve_cipher(choice)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::net::{MemoryServer, MemoryTransport};

    fn os_random(dest: &mut [u8]) -> Result<(), String> {
        getrandom::fill(dest).map_err(|e| e.to_string())
    }

    fn builder() -> snow::Builder<'static> {
        snow::Builder::with_resolver(
            PATTERN.parse().unwrap(),
            Box::new(Resolver { random: os_random }),
        )
    }

    /// A responder in memory, as the server runs it.
    struct Responder {
        hs: Option<HandshakeState>,
        session: Option<TransportState>,
    }

    impl Responder {
        fn new(private: &[u8]) -> Responder {
            let hs = builder()
                .prologue(PROLOGUE)
                .unwrap()
                .local_private_key(private)
                .unwrap()
                .build_responder()
                .unwrap();
            Responder {
                hs: Some(hs),
                session: None,
            }
        }

        /// Answers message 1.
        fn answer(&mut self, msg1: &[u8]) -> Vec<u8> {
            let mut hs = self.hs.take().unwrap();
            let mut buf = vec![0u8; MAX_MESSAGE];
            hs.read_message(msg1, &mut buf).unwrap();
            let n = hs.write_message(&[], &mut buf).unwrap();
            self.session = Some(hs.into_transport_mode().unwrap());
            buf.truncate(n);
            buf
        }

        fn seal(&mut self, plain: &[u8]) -> Vec<u8> {
            self.transport(|session, buf| session.write_message(plain, buf))
        }

        fn open(&mut self, msg: &[u8]) -> Vec<u8> {
            self.transport(|session, buf| session.read_message(msg, buf))
        }

        /// Runs one transport-mode step into a fresh buffer, cut to what it wrote.
        fn transport(
            &mut self,
            step: impl FnOnce(&mut TransportState, &mut [u8]) -> Result<usize, snow::Error>,
        ) -> Vec<u8> {
            let mut buf = vec![0u8; MAX_MESSAGE];
            let n = step(self.session.as_mut().unwrap(), &mut buf).unwrap();
            buf.truncate(n);
            buf
        }
    }

    fn keypair() -> snow::Keypair {
        builder().generate_keypair().unwrap()
    }

    fn address() -> ServerAddress {
        ServerAddress {
            host: "127.0.0.1".into(),
            port: 4433,
        }
    }

    /// A connection to `server` opened on a memory wire, its first message written but not
    /// answered yet; with the far end.
    fn opening(server: &snow::Keypair) -> (Noised<MemoryTransport>, MemoryServer) {
        let key: [u8; 32] = server.public.clone().try_into().unwrap();
        let (wire, far) = MemoryTransport::pair();
        let mut noised = Noised::new(wire, key, os_random);
        noised.open(&address(), Fingerprint([0; 32]));
        far.accept();
        assert_eq!(noised.poll(), None, "the keys are not agreed yet");
        (noised, far)
    }

    /// A connection whose handshake is done, with the far end and the server's side of it.
    fn opened() -> (Noised<MemoryTransport>, MemoryServer, Responder) {
        let server = keypair();
        let (mut noised, far) = opening(&server);
        let mut responder = Responder::new(&server.private);
        far.deliver(responder.answer(&far.take_written()));
        assert_eq!(noised.poll(), Some(TransportEvent::Opened));
        (noised, far, responder)
    }

    #[test]
    fn the_handshake_opens_and_bytes_cross_encrypted_both_ways() {
        let (mut noised, far, mut responder) = opened();
        noised.send(b"hello, server");
        let sealed = far.take_written();
        assert!(
            !sealed.windows(5).any(|w| w == b"hello"),
            "sent in the clear"
        );
        assert_eq!(responder.open(&sealed), b"hello, server");

        far.deliver(responder.seal(b"hello, page"));
        assert_eq!(
            noised.poll(),
            Some(TransportEvent::Received(b"hello, page".to_vec()))
        );
    }

    #[test]
    fn a_server_without_the_links_key_is_refused() {
        let (server, impostor) = (keypair(), keypair());
        let (mut noised, far) = opening(&server);
        let msg1 = far.take_written();
        // The impostor cannot read message 1, so it answers with a handshake of its own.
        let mut other = builder()
            .prologue(PROLOGUE)
            .unwrap()
            .remote_public_key(&impostor.public)
            .unwrap()
            .build_initiator()
            .unwrap();
        let mut fake = vec![0u8; MAX_MESSAGE];
        let n = other.write_message(&[], &mut fake).unwrap();
        assert!(!msg1.is_empty());
        far.deliver(fake[..n].to_vec());
        assert_eq!(
            noised.poll(),
            Some(TransportEvent::Failed(NetError::WrongKey))
        );
        assert_eq!(far.closes(), 1, "the socket is closed");
    }

    #[test]
    fn a_tampered_message_ends_the_connection() {
        let (mut noised, far, mut responder) = opened();
        let mut sealed = responder.seal(b"a frame");
        sealed[0] ^= 1;
        far.deliver(sealed);
        assert!(matches!(
            noised.poll(),
            Some(TransportEvent::Failed(NetError::Lost(_)))
        ));
    }

    #[test]
    fn a_long_write_is_cut_into_messages_that_fit() {
        let (mut noised, far, mut responder) = opened();
        let long: Vec<u8> = (0..200_000u32).map(|i| i as u8).collect();
        noised.send(&long);
        let messages = far.take_messages();
        assert_eq!(messages.len(), 4);
        assert!(messages.iter().all(|m| m.len() <= MAX_MESSAGE));
        let got: Vec<u8> = messages.iter().flat_map(|m| responder.open(m)).collect();
        assert_eq!(got, long);
    }
}
