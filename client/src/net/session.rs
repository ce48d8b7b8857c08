//! A headless session for a frame loop: the network runs on its own thread (with its own
//! tokio runtime); the game polls [`Session::try_recv`] once a frame and never blocks.

use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

use breakshot_shared::protocol::{ClientMessage, Invite, ServerMessage};
use tokio::sync::mpsc::{unbounded_channel, UnboundedSender};
use tokio::sync::oneshot;

use super::connection::{endpoint, Connection};
use super::mirror::{Check, Mirror};

#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// The handshake succeeded.
    Connected,
    Message(ServerMessage),
    /// What the local prediction of a shot showed.
    Check(Check),
    /// The connection ended (or never started), with the reason.
    Closed(String),
}

pub struct Session {
    requests: UnboundedSender<ClientMessage>,
    events: Receiver<SessionEvent>,
    mirror: Arc<Mutex<Mirror>>,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl Session {
    /// Starts connecting to the server of `invite`; [`SessionEvent::Connected`] or
    /// [`SessionEvent::Closed`] follows.
    pub fn connect(invite: Invite) -> Session {
        let (requests, mut outgoing) = unbounded_channel::<ClientMessage>();
        let (events_tx, events) = mpsc::channel();
        let (stop, mut stopped) = oneshot::channel::<()>();
        let mirror = Arc::new(Mutex::new(Mirror::default()));
        let shared = mirror.clone();
        let thread = std::thread::spawn(move || {
            let runtime = match tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
            {
                Ok(r) => r,
                Err(e) => {
                    let _ = events_tx.send(SessionEvent::Closed(e.to_string()));
                    return;
                }
            };
            runtime.block_on(async move {
                let connecting = async {
                    match endpoint() {
                        Ok(ep) => Connection::open(&ep, &invite).await,
                        Err(e) => Err(e),
                    }
                };
                // Dropping the session while it connects must not wait for a timeout.
                let conn = tokio::select! {
                    c = connecting => c,
                    _ = &mut stopped => return,
                };
                let (quic, mut writer, mut reader) = match conn {
                    Ok(c) => c.split(),
                    Err(e) => {
                        let _ = events_tx.send(SessionEvent::Closed(e.to_string()));
                        return;
                    }
                };
                let _ = events_tx.send(SessionEvent::Connected);
                let reading = {
                    let events_tx = events_tx.clone();
                    async move {
                        loop {
                            match reader.recv().await {
                                Ok(msg) => {
                                    let check = lock(&shared).observe(&msg);
                                    let _ = events_tx.send(SessionEvent::Message(msg));
                                    if let Some(c) = check {
                                        let _ = events_tx.send(SessionEvent::Check(c));
                                    }
                                }
                                Err(e) => return e.to_string(),
                            }
                        }
                    }
                };
                let writing = async {
                    while let Some(msg) = outgoing.recv().await {
                        if let Err(e) = writer.send(&msg).await {
                            return e.to_string();
                        }
                    }
                    "session closed".to_string()
                };
                let reason = tokio::select! {
                    r = reading => r,
                    r = writing => r,
                    _ = &mut stopped => "session closed".to_string(),
                };
                quic.close(0u32.into(), b"bye");
                let _ = events_tx.send(SessionEvent::Closed(reason));
            });
        });
        Session {
            requests,
            events,
            mirror,
            stop: Some(stop),
            thread: Some(thread),
        }
    }

    /// Queues a message for the server. Returns false if the session has ended.
    pub fn send(&self, msg: ClientMessage) -> bool {
        self.requests.send(msg).is_ok()
    }

    /// The next event, if one is waiting. Never blocks.
    pub fn try_recv(&self) -> Option<SessionEvent> {
        self.events.try_recv().ok()
    }

    /// The next event, waiting at most `timeout` (for tools and tests, not frame loops).
    pub fn recv_timeout(&self, timeout: Duration) -> Option<SessionEvent> {
        self.events.recv_timeout(timeout).ok()
    }

    /// Reads the local copy of the game (role, token, predictions, desync count).
    pub fn mirror(&self) -> MutexGuard<'_, Mirror> {
        lock(&self.mirror)
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn lock(m: &Mutex<Mirror>) -> MutexGuard<'_, Mirror> {
    // A panic elsewhere while holding the lock leaves the mirror as it was; keep using it.
    m.lock().unwrap_or_else(|e| e.into_inner())
}
