//! The frame-polled driver of the [`PlayerCore`], for a front end without threads or an
//! async runtime (the browser): any [`Transport`] of byte frames, pumped once a frame with
//! the frame's time. [`MemoryTransport`] is one in memory, with the far end scripted by
//! hand ([`MemoryServer`]), for tests.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;
use std::time::Duration;

use breakshot_shared::protocol::{
    decode_payload, encode_frame, split_frame, ClientMessage, Fingerprint, ServerAddress,
    ServerMessage,
};

use super::error::NetError;
use super::player::{Action, Entry, PlayerCore, PlayerEvent, Seating};

/// What a transport reports.
#[derive(Clone, Debug, PartialEq)]
pub enum TransportEvent {
    /// The connection asked for is open.
    Opened,
    /// Bytes arrived (any split of the server's frames).
    Received(Vec<u8>),
    /// The connection asked for could not be opened, or the open one ended.
    Failed(NetError),
}

/// A way to reach a server with byte frames (WebTransport or WebSocket in a browser, QUIC
/// natively). One connection at a time; nothing blocks.
pub trait Transport {
    /// Starts opening a connection to `server`, trusting only the certificate with
    /// `fingerprint`, in place of any connection there was.
    fn open(&mut self, server: &ServerAddress, fingerprint: Fingerprint);
    /// Writes bytes on the open connection.
    fn send(&mut self, bytes: &[u8]);
    /// Closes the connection, or gives up the one being opened.
    fn close(&mut self);
    /// What happened since the last call, one report at a time.
    fn poll(&mut self) -> Option<TransportEvent>;
}

/// A [`PlayerCore`] over a [`Transport`], advanced by [`Polled::update`] once a frame.
pub struct Polled<T: Transport> {
    core: PlayerCore,
    transport: T,
}

impl<T: Transport> Polled<T> {
    /// Drives `core` over `transport`.
    pub fn new(core: PlayerCore, transport: T) -> Polled<T> {
        Polled { core, transport }
    }

    /// Hands the core what the transport reported and the time `now` (on the same clock
    /// the core was made with), and carries out what the core asks.
    pub fn update(&mut self, now: Duration) {
        self.flush();
        while let Some(report) = self.transport.poll() {
            match report {
                TransportEvent::Opened => self.core.opened(now),
                TransportEvent::Received(bytes) => self.core.received(&bytes, now),
                TransportEvent::Failed(e) => self.core.failed(e, now),
            }
            self.flush();
        }
        if self.core.timeout().is_some_and(|t| t <= now) {
            self.core.handle_timeout(now);
        }
        self.flush();
    }

    /// Enters a room as `entry` says.
    pub fn enter(&mut self, entry: Entry) {
        self.core.enter(entry);
        self.flush();
    }

    /// Sends a message (lost while reconnecting, as on a dropped connection).
    pub fn send(&mut self, msg: &ClientMessage) -> Result<(), NetError> {
        self.core.send(msg)?;
        self.flush();
        Ok(())
    }

    /// The next event, if one is waiting.
    pub fn poll_event(&mut self) -> Option<PlayerEvent> {
        self.core.poll_event()
    }

    /// The seat held, as the server last said.
    pub fn seating(&self) -> &Seating {
        self.core.seating()
    }

    /// The core under the driver.
    pub fn core(&self) -> &PlayerCore {
        &self.core
    }

    fn flush(&mut self) {
        while let Some(action) = self.core.poll_action() {
            match action {
                Action::Open {
                    server,
                    fingerprint,
                    ..
                } => self.transport.open(&server, fingerprint),
                Action::Close => self.transport.close(),
            }
        }
        while let Some(frame) = self.core.poll_transmit() {
            self.transport.send(&frame);
        }
    }
}

/// Both ends of a [`MemoryTransport`].
#[derive(Default)]
struct Wire {
    /// Every address a connection was asked to, in order.
    opened: Vec<ServerAddress>,
    /// Connections closed (or attempts given up) by the client.
    closes: usize,
    /// Bytes the client wrote, not read by the server yet.
    written: Vec<u8>,
    /// The same bytes as the client's writes, one per write (for a transport of messages).
    messages: Vec<Vec<u8>>,
    /// Reports waiting for the client.
    reports: VecDeque<TransportEvent>,
}

/// A [`Transport`] in memory: what the client writes waits for its [`MemoryServer`], and
/// what the server says waits for the client's next poll.
pub struct MemoryTransport {
    wire: Rc<RefCell<Wire>>,
}

/// The far end of a [`MemoryTransport`], scripted by a test.
pub struct MemoryServer {
    wire: Rc<RefCell<Wire>>,
}

impl MemoryTransport {
    /// A transport and the server end that scripts it.
    pub fn pair() -> (MemoryTransport, MemoryServer) {
        let wire = Rc::new(RefCell::new(Wire::default()));
        (
            MemoryTransport { wire: wire.clone() },
            MemoryServer { wire },
        )
    }
}

impl Transport for MemoryTransport {
    fn open(&mut self, server: &ServerAddress, _fingerprint: Fingerprint) {
        let mut wire = self.wire.borrow_mut();
        wire.opened.push(server.clone());
        wire.written.clear();
        wire.messages.clear();
    }

    fn send(&mut self, bytes: &[u8]) {
        let mut wire = self.wire.borrow_mut();
        wire.written.extend_from_slice(bytes);
        wire.messages.push(bytes.to_vec());
    }

    fn close(&mut self) {
        let mut wire = self.wire.borrow_mut();
        wire.closes += 1;
        wire.reports.clear();
    }

    fn poll(&mut self) -> Option<TransportEvent> {
        self.wire.borrow_mut().reports.pop_front()
    }
}

impl MemoryServer {
    /// The addresses the client asked to connect to, in order.
    pub fn opened(&self) -> Vec<ServerAddress> {
        self.wire.borrow().opened.clone()
    }

    /// How many times the client closed a connection.
    pub fn closes(&self) -> usize {
        self.wire.borrow().closes
    }

    /// Accepts the connection being opened.
    pub fn accept(&self) {
        self.report(TransportEvent::Opened);
    }

    /// Fails the connection being opened, or ends the open one.
    pub fn fail(&self, error: NetError) {
        self.report(TransportEvent::Failed(error));
    }

    /// Says `msg` to the client.
    pub fn say(&self, msg: &ServerMessage) {
        let frame = encode_frame(msg).expect("a server message fits a frame");
        self.report(TransportEvent::Received(frame));
    }

    /// Hands the client `bytes` as they are (a message of a message transport, or any
    /// piece of the byte stream).
    pub fn deliver(&self, bytes: Vec<u8>) {
        self.report(TransportEvent::Received(bytes));
    }

    /// The client's writes since the last call, one per write, taken from the wire.
    pub fn take_messages(&self) -> Vec<Vec<u8>> {
        let mut wire = self.wire.borrow_mut();
        wire.written.clear();
        std::mem::take(&mut wire.messages)
    }

    /// The bytes the client wrote since the last call, taken from the wire.
    pub fn take_written(&self) -> Vec<u8> {
        self.take_messages().concat()
    }

    /// The messages the client wrote since the last call.
    pub fn heard(&self) -> Vec<ClientMessage> {
        let mut wire = self.wire.borrow_mut();
        let mut heard = Vec::new();
        let mut used = 0;
        while let Ok(Some((payload, n))) = split_frame(&wire.written[used..]) {
            if let Ok(msg) = decode_payload(payload) {
                heard.push(msg);
            }
            used += n;
        }
        wire.written.drain(..used);
        wire.messages.clear();
        heard
    }

    fn report(&self, event: TransportEvent) {
        self.wire.borrow_mut().reports.push_back(event);
    }
}
