//! A page's way to the server: WebTransport first, and the WebSocket when the page has no
//! WebTransport or it fails before opening (docs/web.md). Once WebTransport has failed, the
//! reconnections of the same page go straight to the WebSocket.

use breakshot_shared::protocol::{Fingerprint, ServerAddress};

use super::polled::{Transport, TransportEvent};

/// Which way is in use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Using {
    /// The first way (WebTransport).
    First,
    /// The fallback (the WebSocket, under Noise).
    Fallback,
}

/// A [`Transport`] that tries `first`, then `fallback`; either may be absent (a page without
/// WebTransport, a link that asks for one way only), not both.
pub struct WebWay<A: Transport, B: Transport> {
    first: Option<A>,
    fallback: Option<B>,
    using: Using,
    /// The first way failed to open once: not tried again.
    first_failed: bool,
    /// The first way opened on this connection (a later failure is a lost connection, not a
    /// reason to fall back).
    opened: bool,
    /// Where the connection being opened goes.
    target: Option<(ServerAddress, Fingerprint)>,
}

impl<A: Transport, B: Transport> WebWay<A, B> {
    /// Tries `first` and falls back to `fallback`.
    pub fn new(first: Option<A>, fallback: Option<B>) -> WebWay<A, B> {
        WebWay {
            using: if first.is_some() {
                Using::First
            } else {
                Using::Fallback
            },
            first,
            fallback,
            first_failed: false,
            opened: false,
            target: None,
        }
    }

    /// The way in use (or about to be).
    pub fn using(&self) -> Using {
        self.using
    }

    fn current(&mut self) -> Option<&mut dyn Transport> {
        match self.using {
            Using::First => self.first.as_mut().map(|t| t as &mut dyn Transport),
            Using::Fallback => self.fallback.as_mut().map(|t| t as &mut dyn Transport),
        }
    }
}

impl<A: Transport, B: Transport> Transport for WebWay<A, B> {
    fn open(&mut self, server: &ServerAddress, fingerprint: Fingerprint) {
        if let Some(t) = self.current() {
            t.close();
        }
        self.using = if self.first.is_some() && !(self.first_failed && self.fallback.is_some()) {
            Using::First
        } else {
            Using::Fallback
        };
        self.opened = false;
        self.target = Some((server.clone(), fingerprint));
        if let Some(t) = self.current() {
            t.open(server, fingerprint);
        }
    }

    fn send(&mut self, bytes: &[u8]) {
        if let Some(t) = self.current() {
            t.send(bytes);
        }
    }

    fn close(&mut self) {
        if let Some(t) = self.current() {
            t.close();
        }
        self.target = None;
    }

    fn poll(&mut self) -> Option<TransportEvent> {
        loop {
            let event = self.current()?.poll()?;
            match event {
                TransportEvent::Opened => {
                    self.opened = true;
                    return Some(TransportEvent::Opened);
                }
                TransportEvent::Failed(e)
                    if self.using == Using::First && !self.opened && self.fallback.is_some() =>
                {
                    tracing::info!(error = %e, "WebTransport failed; trying the WebSocket");
                    self.first_failed = true;
                    self.using = Using::Fallback;
                    if let (Some((server, fingerprint)), Some(t)) =
                        (self.target.clone(), self.fallback.as_mut())
                    {
                        t.open(&server, fingerprint);
                    }
                }
                other => return Some(other),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::net::{MemoryServer, MemoryTransport, NetError};

    fn address() -> ServerAddress {
        ServerAddress {
            host: "127.0.0.1".into(),
            port: 4433,
        }
    }

    fn ways() -> (
        WebWay<MemoryTransport, MemoryTransport>,
        MemoryServer,
        MemoryServer,
    ) {
        let (a, far_a) = MemoryTransport::pair();
        let (b, far_b) = MemoryTransport::pair();
        (WebWay::new(Some(a), Some(b)), far_a, far_b)
    }

    #[test]
    fn web_transport_is_tried_first_and_kept_when_it_opens() {
        let (mut way, wt, ws) = ways();
        way.open(&address(), Fingerprint([0; 32]));
        wt.accept();
        assert_eq!(way.poll(), Some(TransportEvent::Opened));
        way.send(b"abc");
        assert_eq!(wt.take_written(), b"abc");
        assert!(ws.opened().is_empty(), "the WebSocket is never opened");
        // A session that opened and then dropped is a lost connection, not a fallback.
        wt.fail(NetError::Lost("gone".into()));
        assert_eq!(
            way.poll(),
            Some(TransportEvent::Failed(NetError::Lost("gone".into())))
        );
        assert_eq!(way.using(), Using::First);
    }

    #[test]
    fn a_failed_web_transport_falls_back_to_the_web_socket_and_stays_there() {
        let (mut way, wt, ws) = ways();
        way.open(&address(), Fingerprint([0; 32]));
        wt.fail(NetError::Connect("no QUIC".into()));
        assert_eq!(
            way.poll(),
            None,
            "the failure is not reported: the fallback is tried"
        );
        assert_eq!(ws.opened(), vec![address()]);
        ws.accept();
        assert_eq!(way.poll(), Some(TransportEvent::Opened));
        way.send(b"xyz");
        assert_eq!(ws.take_written(), b"xyz");
        // Reconnecting goes straight to the WebSocket.
        way.open(&address(), Fingerprint([0; 32]));
        assert_eq!(wt.opened().len(), 1);
        assert_eq!(ws.opened().len(), 2);
    }

    #[test]
    fn without_a_fallback_the_failure_is_reported() {
        let (a, wt) = MemoryTransport::pair();
        let mut way: WebWay<MemoryTransport, MemoryTransport> = WebWay::new(Some(a), None);
        way.open(&address(), Fingerprint([0; 32]));
        wt.fail(NetError::Connect("no QUIC".into()));
        assert!(matches!(way.poll(), Some(TransportEvent::Failed(_))));
    }

    #[test]
    fn without_web_transport_the_web_socket_is_the_way() {
        let (b, ws) = MemoryTransport::pair();
        let mut way: WebWay<MemoryTransport, MemoryTransport> = WebWay::new(None, Some(b));
        way.open(&address(), Fingerprint([0; 32]));
        ws.accept();
        assert_eq!(way.poll(), Some(TransportEvent::Opened));
    }
}
