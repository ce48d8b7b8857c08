//! What a browser and the server agree on beyond the frames (docs/web.md): the paths on the
//! server's HTTP and WebTransport side, and the Noise handshake that encrypts the WebSocket.

/// The HTTP path of the WebSocket that carries the game (`ws://HOST:P/ws`).
pub const WS_PATH: &str = "/ws";

/// The WebTransport CONNECT path (over HTTP/3, ALPN `h3`).
pub const WEBTRANSPORT_PATH: &str = "/breakshot";

/// The HTTP path that answers the current `h3` certificate hashes, hex, one a line, newest
/// first.
pub const CERTIFICATE_HASH_PATH: &str = "/certificate.sha256";

/// The Noise protocol of the WebSocket: the page knows the server's static key (`NK`).
pub const NOISE_PATTERN: &str = "Noise_NK_25519_ChaChaPoly_BLAKE2s";

/// The Noise prologue: both sides mix it in, so a handshake made for anything else fails.
pub const NOISE_PROLOGUE: &[u8] = b"breakshot-ws/1";

/// The largest Noise message, so the largest WebSocket message, in bytes (tag included).
pub const MAX_NOISE_MESSAGE: usize = 65_535;

/// The authentication tag every Noise transport message ends with.
pub const NOISE_TAG_LEN: usize = 16;

/// The most bytes of the stream one transport message carries.
pub const MAX_NOISE_PAYLOAD: usize = MAX_NOISE_MESSAGE - NOISE_TAG_LEN;

/// The length of an X25519 key (the server's static public key in a link).
pub const NOISE_KEY_LEN: usize = 32;
