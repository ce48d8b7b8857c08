//! The [`Client`] for a frame loop: the client runs on its own thread (with its own tokio
//! runtime); the game polls [`Session::try_recv`] once a frame and never blocks.

use std::sync::mpsc::{self, Receiver};
use std::thread::JoinHandle;
use std::time::Duration;

use breakshot_shared::protocol::{ClientMessage, Invite, Role, RoomCode, ServerMessage};
use breakshot_shared::rules::Seat;
use tokio::sync::mpsc::{unbounded_channel, UnboundedSender};
use tokio::sync::oneshot;

use super::client::{Client, ClientEvent, Reconnect};

/// What a session hears.
#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// The handshake succeeded.
    Connected,
    /// A message from the server.
    Message(ServerMessage),
    /// The connection of a seated player dropped; the session is connecting again to take
    /// the seat back (for as long as the server holds it).
    Reconnecting,
    /// The connection ended (or never started, or could not be restored), with the reason.
    Closed(String),
}

/// How long a closing session waits for its close to be sent.
const CLOSE_GRACE: Duration = Duration::from_millis(500);

/// A polling adapter around a [`Client`] running on a thread of its own.
pub struct Session {
    requests: UnboundedSender<ClientMessage>,
    events: Receiver<SessionEvent>,
    /// The role and room of the last `Joined` polled.
    joined: Option<(Role, RoomCode)>,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl Session {
    /// Starts connecting to the server of `invite`; [`SessionEvent::Connected`] or
    /// [`SessionEvent::Closed`] follows.
    pub fn connect(invite: Invite) -> Session {
        let (requests, outgoing) = unbounded_channel::<ClientMessage>();
        let (events_tx, events) = mpsc::channel();
        let (stop, stopped) = oneshot::channel::<()>();
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
            let why = runtime.block_on(drive(invite, outgoing, &events_tx, stopped));
            let _ = events_tx.send(SessionEvent::Closed(why));
        });
        Session {
            requests,
            events,
            joined: None,
            stop: Some(stop),
            thread: Some(thread),
        }
    }

    /// Queues a message for the server. Returns false if the session has ended.
    pub fn send(&self, msg: ClientMessage) -> bool {
        self.requests.send(msg).is_ok()
    }

    /// The next event, if one is waiting. Never blocks.
    pub fn try_recv(&mut self) -> Option<SessionEvent> {
        let event = self.events.try_recv().ok()?;
        self.note(&event);
        Some(event)
    }

    /// The next event, waiting at most `timeout` (for tools and tests, not frame loops).
    pub fn recv_timeout(&mut self, timeout: Duration) -> Option<SessionEvent> {
        let event = self.events.recv_timeout(timeout).ok()?;
        self.note(&event);
        Some(event)
    }

    fn note(&mut self, event: &SessionEvent) {
        if let SessionEvent::Message(ServerMessage::Joined { role, snapshot, .. }) = event {
            self.joined = Some((*role, snapshot.room.clone()));
        }
    }

    /// Our role, once a room was joined.
    pub fn role(&self) -> Option<Role> {
        self.joined.as_ref().map(|j| j.0)
    }

    /// Our seat, if we play.
    pub fn seat(&self) -> Option<Seat> {
        match self.role() {
            Some(Role::Player(seat)) => Some(seat),
            _ => None,
        }
    }

    /// The room joined, once joined.
    pub fn room(&self) -> Option<&RoomCode> {
        self.joined.as_ref().map(|j| &j.1)
    }
}

/// Runs the client until the session is dropped or the connection ends for good; returns
/// why it ended.
async fn drive(
    invite: Invite,
    mut outgoing: tokio::sync::mpsc::UnboundedReceiver<ClientMessage>,
    events: &mpsc::Sender<SessionEvent>,
    mut stopped: oneshot::Receiver<()>,
) -> String {
    // Dropping the session while it connects must not wait for a timeout.
    let mut client = tokio::select! {
        c = Client::connect(invite, Reconnect::default()) => match c {
            Ok(c) => c,
            Err(e) => return e.to_string(),
        },
        _ = &mut stopped => return "session closed".into(),
    };
    let _ = events.send(SessionEvent::Connected);
    loop {
        tokio::select! {
            event = client.recv() => match event {
                Ok(ClientEvent::Message(msg)) => {
                    let _ = events.send(SessionEvent::Message(msg));
                }
                Ok(ClientEvent::Reconnecting(_)) => {
                    let _ = events.send(SessionEvent::Reconnecting);
                }
                Ok(ClientEvent::Reconnected) => {
                    let _ = events.send(SessionEvent::Connected);
                }
                Err(e) => return e.to_string(),
            },
            msg = outgoing.recv() => match msg {
                // A message that cannot be sent was lost with the connection; the next
                // `recv` finds out and reconnects.
                Some(msg) => { let _ = client.send(&msg).await; }
                None => break,
            },
            _ = &mut stopped => break,
        }
    }
    client.close(CLOSE_GRACE).await;
    "session closed".into()
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
