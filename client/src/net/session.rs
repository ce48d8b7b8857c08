//! The [`Client`] for a frame loop: the client runs on its own thread (with its own tokio
//! runtime); the game polls [`Session::try_recv`] once a frame and never blocks. Each event
//! comes with the core's [`Seating`] as it stood, so the seat is known here without being
//! worked out again.

use super::background::BackgroundThread;
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

use breakshot_shared::protocol::{ClientMessage, Invite, Role, RoomCode};
use breakshot_shared::rules::Seat;
use tokio::sync::mpsc::{unbounded_channel, UnboundedSender};
use tokio::sync::oneshot;

use super::client::{Client, ClientEvent};
use super::player::{Entry, Reconnect, Seating};
use super::port::{Port, SessionEvent};

/// How long a closing session waits for its close to be sent.
const CLOSE_GRACE: Duration = Duration::from_millis(500);

/// A polling adapter around a [`Client`] running on a thread of its own.
pub struct Session {
    requests: UnboundedSender<Request>,
    events: Receiver<(SessionEvent, Seating)>,
    /// The seat as it stood at the last event polled.
    seating: Seating,
    /// The connection's thread, stopped when this is dropped.
    _thread: BackgroundThread,
}

impl Session {
    /// Starts connecting to the server of `invite`; [`SessionEvent::Connected`] or
    /// [`SessionEvent::Closed`] follows.
    pub fn connect(invite: Invite) -> Session {
        let (requests, outgoing) = unbounded_channel::<Request>();
        let (events_tx, events) = mpsc::channel();
        let failed = events_tx.clone();
        let no_runtime = move |e: std::io::Error| {
            let _ = failed.send((SessionEvent::Closed(e.to_string()), Seating::default()));
        };
        let thread = BackgroundThread::spawn_with_runtime(
            "breakshot-session",
            no_runtime,
            move |runtime, stopped| {
                let (why, seating) = runtime.block_on(drive(invite, outgoing, &events_tx, stopped));
                let _ = events_tx.send((SessionEvent::Closed(why), seating));
            },
        )
        // As `std::thread::spawn` does: a process that cannot start a thread cannot go on.
        .expect("cannot start the network thread");
        Session {
            requests,
            events,
            seating: Seating::default(),
            _thread: thread,
        }
    }

    /// Queues a message for the server. Returns false if the session has ended.
    pub fn send(&self, msg: ClientMessage) -> bool {
        self.requests.send(Request::Send(msg)).is_ok()
    }

    /// Enters a room as `entry` says (the core carries out its fallbacks). Returns false if
    /// the session has ended.
    pub fn enter(&self, entry: Entry) -> bool {
        self.requests.send(Request::Enter(entry)).is_ok()
    }

    /// The next event, if one is waiting. Never blocks.
    pub fn try_recv(&mut self) -> Option<SessionEvent> {
        let (event, seating) = self.events.try_recv().ok()?;
        self.seating = seating;
        Some(event)
    }

    /// The next event, waiting at most `timeout` (for tools and tests, and for a caller that
    /// has nothing to do until the server answers).
    pub fn recv_timeout(&mut self, timeout: Duration) -> Option<SessionEvent> {
        let (event, seating) = self.events.recv_timeout(timeout).ok()?;
        self.seating = seating;
        Some(event)
    }

    /// The seat, as it stood at the last event polled.
    pub fn seating(&self) -> &Seating {
        &self.seating
    }

    /// Our role, once a room was joined.
    pub fn role(&self) -> Option<Role> {
        self.seating.role
    }

    /// Our seat, if we play.
    pub fn seat(&self) -> Option<Seat> {
        self.seating.seat()
    }

    /// The room joined, once joined.
    pub fn room(&self) -> Option<&RoomCode> {
        self.seating.room.as_ref()
    }
}

impl Port for Session {
    fn send(&mut self, msg: ClientMessage) -> bool {
        Session::send(self, msg)
    }

    fn enter(&mut self, entry: Entry) -> bool {
        Session::enter(self, entry)
    }

    fn try_recv(&mut self) -> Option<SessionEvent> {
        Session::try_recv(self)
    }

    fn seating(&self) -> &Seating {
        Session::seating(self)
    }
}

/// What the frame loop asks of the network thread.
enum Request {
    Send(ClientMessage),
    Enter(Entry),
}

/// Runs the client until the session is dropped or the connection ends for good; returns
/// why it ended.
async fn drive(
    invite: Invite,
    mut outgoing: tokio::sync::mpsc::UnboundedReceiver<Request>,
    events: &mpsc::Sender<(SessionEvent, Seating)>,
    mut stopped: oneshot::Receiver<()>,
) -> (String, Seating) {
    // Dropping the session while it connects must not wait for a timeout.
    let mut client = tokio::select! {
        c = Client::connect(invite, Reconnect::default()) => match c {
            Ok(c) => c,
            Err(e) => return (e.to_string(), Seating::default()),
        },
        _ = &mut stopped => return ("session closed".into(), Seating::default()),
    };
    let _ = events.send((SessionEvent::Connected, client.seating().clone()));
    loop {
        tokio::select! {
            event = client.recv() => {
                let event = match event {
                    Ok(ClientEvent::Message(msg)) => SessionEvent::Message(msg),
                    Ok(ClientEvent::SeatGone) => SessionEvent::SeatGone,
                    Ok(ClientEvent::Reconnecting(_)) => SessionEvent::Reconnecting,
                    Ok(ClientEvent::Reconnected) => SessionEvent::Connected,
                    Err(e) => return (e.to_string(), client.seating().clone()),
                };
                let _ = events.send((event, client.seating().clone()));
            }
            request = outgoing.recv() => match request {
                // A message that cannot be sent was lost with the connection; the next
                // `recv` finds out and reconnects.
                Some(Request::Send(msg)) => { let _ = client.send(&msg).await; }
                Some(Request::Enter(entry)) => client.enter(entry).await,
                None => break,
            },
            _ = &mut stopped => break,
        }
    }
    let seating = client.seating().clone();
    client.close(CLOSE_GRACE).await;
    ("session closed".into(), seating)
}
