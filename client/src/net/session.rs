//! A headless session for a frame loop: the network runs on its own thread (with its own
//! tokio runtime); the game polls [`Session::try_recv`] once a frame and never blocks. A
//! seated player whose connection drops is reconnected and takes the seat back with its
//! token.

use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::limits::RECONNECT_WINDOW;
use breakshot_shared::protocol::{ClientMessage, Invite, SeatToken, ServerMessage};
use tokio::sync::mpsc::{unbounded_channel, UnboundedSender};
use tokio::sync::oneshot;

use super::connection::{endpoint, Connection, NetError};
use super::mirror::{Check, Mirror};

#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// The handshake succeeded.
    Connected,
    Message(ServerMessage),
    /// What the local prediction of a shot showed.
    Check(Check),
    /// The connection of a seated player dropped; the session is connecting again to take
    /// the seat back (for as long as the server holds it).
    Reconnecting,
    /// The connection ended (or never started, or could not be restored), with the reason.
    Closed(String),
}

/// How a connection ended.
enum End {
    /// The session was dropped.
    Stopped,
    Lost(String),
}

/// How long a closing session waits for its close to be sent.
const CLOSE_GRACE: Duration = Duration::from_millis(500);

/// Pause between attempts to reach a server that went away.
const RETRY_PAUSE: Duration = Duration::from_millis(500);

/// Connects again after a drop, retrying for as long as the server holds a seat
/// ([`RECONNECT_WINDOW`]); a server that answers but refuses us is final.
async fn reopen(ep: &quinn::Endpoint, invite: &Invite) -> Result<Connection, NetError> {
    let since = Instant::now();
    loop {
        match Connection::open(ep, invite).await {
            Ok(c) => return Ok(c),
            Err(e @ NetError::Rejected(_)) => return Err(e),
            Err(e) if since.elapsed() > RECONNECT_WINDOW => return Err(e),
            Err(_) => tokio::time::sleep(RETRY_PAUSE).await,
        }
    }
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
                let ep = match endpoint() {
                    Ok(ep) => ep,
                    Err(e) => {
                        let _ = events_tx.send(SessionEvent::Closed(e.to_string()));
                        return;
                    }
                };
                // Set once a connection with a seat is lost: the seat to take back.
                let mut rejoin: Option<SeatToken> = None;
                loop {
                    let opening = async {
                        match rejoin {
                            None => Connection::open(&ep, &invite).await,
                            Some(_) => reopen(&ep, &invite).await,
                        }
                    };
                    // Dropping the session while it connects must not wait for a timeout.
                    let conn = tokio::select! {
                        c = opening => c,
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
                        let shared = shared.clone();
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
                                    Err(e) => return End::Lost(e.to_string()),
                                }
                            }
                        }
                    };
                    let writing = async {
                        if let Some(token) = rejoin {
                            if let Err(e) = writer.send(&ClientMessage::Rejoin { token }).await {
                                return End::Lost(e.to_string());
                            }
                        }
                        while let Some(msg) = outgoing.recv().await {
                            if let Err(e) = writer.send(&msg).await {
                                return End::Lost(e.to_string());
                            }
                        }
                        End::Stopped
                    };
                    let end = tokio::select! {
                        r = reading => r,
                        r = writing => r,
                        _ = &mut stopped => End::Stopped,
                    };
                    quic.close(0u32.into(), b"bye");
                    let reason = match end {
                        End::Stopped => {
                            // Let the close reach the server, so the opponent hears at once
                            // that we left rather than after the idle timeout.
                            let _ = tokio::time::timeout(CLOSE_GRACE, ep.wait_idle()).await;
                            "session closed".to_string()
                        }
                        End::Lost(reason) => match lock(&shared).token() {
                            // A seated player's connection dropped: take the seat back.
                            Some(token) => {
                                rejoin = Some(token);
                                let _ = events_tx.send(SessionEvent::Reconnecting);
                                continue;
                            }
                            None => reason,
                        },
                    };
                    let _ = events_tx.send(SessionEvent::Closed(reason));
                    return;
                }
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
