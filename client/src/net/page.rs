//! The browser's side of the network: the page's plugin (`web/breakshot_net.js`) opens a
//! WebTransport stream or a WebSocket and queues what arrives; [`PageSocket`] polls it once a
//! frame as a [`Transport`]. Also the page's address, its randomness, its `localStorage` (the
//! name and the seats kept between visits) and a line of events for whoever watches the
//! page. Only in the browser build.

// The plugin's functions are imports of the WebAssembly module: calling a foreign function
// is `unsafe` in Rust, and these are the only ones the game calls (each takes plain numbers
// and pointers into the game's own memory, which the plugin reads or writes within the
// lengths given).
#![allow(unsafe_code)]

use breakshot_shared::protocol::{Fingerprint, ServerAddress, WebLink, WebLinkError};

use super::error::NetError;
use super::polled::{Transport, TransportEvent};

#[link(wasm_import_module = "env")]
extern "C" {
    fn bs_net_open(kind: u32, url: *const u8, url_len: usize, hashes: *const u8, len: usize)
        -> u32;
    fn bs_net_send(id: u32, ptr: *const u8, len: usize);
    fn bs_net_close(id: u32);
    fn bs_net_state(id: u32) -> u32;
    fn bs_net_next_len(id: u32) -> i32;
    fn bs_net_take(id: u32, ptr: *mut u8);
    fn bs_net_error(id: u32, ptr: *mut u8, cap: usize) -> usize;
    fn bs_has_web_transport() -> u32;
    fn bs_page(what: u32, ptr: *mut u8, cap: usize) -> usize;
    fn bs_random(ptr: *mut u8, len: usize);
    fn bs_report(ptr: *const u8, len: usize);
    fn bs_store_get(key: *const u8, key_len: usize, ptr: *mut u8, cap: usize) -> i32;
    fn bs_store_set(key: *const u8, key_len: usize, value: *const u8, len: usize);
    fn bs_store_remove(key: *const u8, key_len: usize);
}

/// The plugin's version, which its loader compares with its own.
#[no_mangle]
pub extern "C" fn breakshot_net_crate_version() -> u32 {
    1
}

const OPEN: u32 = 1;
const ENDED: u32 = 2;

/// A text the plugin writes into a buffer: asked again with the length it needs.
fn page_text(read: impl Fn(*mut u8, usize) -> usize) -> String {
    let mut buf = vec![0u8; 256];
    loop {
        let n = read(buf.as_mut_ptr(), buf.len());
        if n <= buf.len() {
            buf.truncate(n);
            return String::from_utf8_lossy(&buf).into_owned();
        }
        buf.resize(n, 0);
    }
}

/// The page's whole address (`location.href`).
pub fn page_url() -> String {
    page_text(|p, c| unsafe { bs_page(0, p, c) })
}

/// The page's `HOST:PORT` (`location.host`).
pub fn page_host() -> String {
    page_text(|p, c| unsafe { bs_page(1, p, c) })
}

/// Whether the page can open a WebTransport session (a secure context that has it).
pub fn has_web_transport() -> bool {
    unsafe { bs_has_web_transport() == 1 }
}

/// Fills `dest` from the page's `crypto.getRandomValues`.
pub fn fill_random(dest: &mut [u8]) -> Result<(), String> {
    // getRandomValues gives at most 65,536 bytes a call.
    for piece in dest.chunks_mut(65_536) {
        unsafe { bs_random(piece.as_mut_ptr(), piece.len()) };
    }
    Ok(())
}

/// Tells whoever watches the page (its status line, a test) that `line` happened.
pub fn report(line: &str) {
    unsafe { bs_report(line.as_ptr(), line.len()) };
}

/// The value the page keeps under `key` in its `localStorage`, if any (none where the
/// browser keeps nothing, as in some private windows).
pub fn stored(key: &str) -> Option<String> {
    let mut buf = vec![0u8; 256];
    loop {
        let n = unsafe { bs_store_get(key.as_ptr(), key.len(), buf.as_mut_ptr(), buf.len()) };
        let n = usize::try_from(n).ok()?;
        if n <= buf.len() {
            buf.truncate(n);
            return String::from_utf8(buf).ok();
        }
        buf.resize(n, 0);
    }
}

/// Keeps `value` under `key` in the page's `localStorage` (nothing where it cannot).
pub fn store(key: &str, value: &str) {
    unsafe { bs_store_set(key.as_ptr(), key.len(), value.as_ptr(), value.len()) };
}

/// Forgets `key` in the page's `localStorage`.
pub fn unstore(key: &str) {
    unsafe { bs_store_remove(key.as_ptr(), key.len()) };
}

/// Which way a [`PageSocket`] goes.
#[derive(Clone, Debug, PartialEq)]
pub enum Way {
    /// WebTransport to `https://HOST:PORT/breakshot`, trusting these certificate hashes.
    WebTransport(Vec<Fingerprint>),
    /// A WebSocket to `ws://HOST:PORT/ws` (to be wrapped in Noise: see `noise`).
    WebSocket,
}

/// One connection of the page's plugin, polled as a [`Transport`].
pub struct PageSocket {
    way: Way,
    id: Option<u32>,
    opened: bool,
}

impl PageSocket {
    /// A socket that goes `way` when opened.
    pub fn new(way: Way) -> PageSocket {
        PageSocket {
            way,
            id: None,
            opened: false,
        }
    }

    fn url(&self, server: &ServerAddress) -> String {
        match self.way {
            Way::WebTransport(_) => format!("https://{}/breakshot", server.authority()),
            Way::WebSocket => format!("ws://{}/ws", server.authority()),
        }
    }
}

impl Transport for PageSocket {
    fn open(&mut self, server: &ServerAddress, _fingerprint: Fingerprint) {
        self.close();
        let url = self.url(server);
        let (kind, hashes) = match &self.way {
            Way::WebTransport(hashes) => (
                0,
                hashes
                    .iter()
                    .map(|h| h.to_string())
                    .collect::<Vec<_>>()
                    .join(","),
            ),
            Way::WebSocket => (1, String::new()),
        };
        let id =
            unsafe { bs_net_open(kind, url.as_ptr(), url.len(), hashes.as_ptr(), hashes.len()) };
        self.id = Some(id);
        self.opened = false;
    }

    fn send(&mut self, bytes: &[u8]) {
        if let Some(id) = self.id {
            unsafe { bs_net_send(id, bytes.as_ptr(), bytes.len()) };
        }
    }

    fn close(&mut self) {
        if let Some(id) = self.id.take() {
            unsafe { bs_net_close(id) };
        }
    }

    fn poll(&mut self) -> Option<TransportEvent> {
        let id = self.id?;
        let state = unsafe { bs_net_state(id) };
        if !self.opened && state == OPEN {
            self.opened = true;
            return Some(TransportEvent::Opened);
        }
        let len = unsafe { bs_net_next_len(id) };
        if len >= 0 {
            let mut piece = vec![0u8; len as usize];
            unsafe { bs_net_take(id, piece.as_mut_ptr()) };
            return Some(TransportEvent::Received(piece));
        }
        if state == ENDED {
            let why = page_text(|p, c| unsafe { bs_net_error(id, p, c) });
            self.close();
            return Some(TransportEvent::Failed(if self.opened {
                NetError::Lost(why)
            } else {
                NetError::Connect(why)
            }));
        }
        None
    }
}

/// A socket given up closes its connection: the plugin would otherwise keep it open (the
/// browser answers the server's pings by itself), and the server a player who has left.
impl Drop for PageSocket {
    fn drop(&mut self) {
        self.close();
    }
}

/// The page's link (docs/web.md), read and parsed once.
pub fn link() -> &'static Result<WebLink, WebLinkError> {
    static LINK: std::sync::OnceLock<Result<WebLink, WebLinkError>> = std::sync::OnceLock::new();
    LINK.get_or_init(|| page_url().parse())
}
