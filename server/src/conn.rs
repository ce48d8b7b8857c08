//! One client connection: reads frames into the hub, writes what the hub sends. It only
//! moves bytes; every decision is the hub's, except the defences that must act before a
//! message reaches the hub: the frame size, the time a frame may take, the message rate
//! (so no connection can fill the hub's queue) and the outgoing queue's length.

use std::net::IpAddr;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{SendError, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::{
    decode_payload, encode_frame, payload_len, ClientMessage, RoomCode, SeatToken, ServerMessage,
    HEADER_LEN,
};
use tokio::sync::mpsc::{channel, Receiver};
use tokio::sync::Notify;

use crate::hub::Claimed;
use crate::limits::Limits;
use crate::output::ConnId;
use crate::ratelimit::Bucket;
use crate::stats::Stats;
use crate::tls::IDLE_TIMEOUT;
use crate::work::Returned;

/// What the writer thread hands a connection.
#[derive(Debug)]
pub enum Outbound {
    /// Encode one message as a frame and write it on the stream.
    Message(ServerMessage),
    /// Finish the stream, give the peer up to 2 s to read what is queued, then close with this
    /// reason.
    Close(String),
}

/// What a connection (or a room's worker) tells the hub.
#[derive(Debug)]
pub enum HubEvent {
    /// A connection opened its stream, from this address (an IPv4-mapped address as IPv4).
    Connected(ConnId, IpAddr),
    /// A message and when its frame was read (the start of the server's time for it).
    Message(ConnId, ClientMessage, Instant),
    /// A connection ended, however it ended; nothing more comes from it. The instant is when
    /// its peer was last heard from: the end itself for an orderly close, the idle timeout
    /// earlier for a peer that fell silent (a killed process, a vanished network).
    Disconnected(ConnId, Instant),
    /// A room back from running a message on a worker thread.
    Returned(Returned),
    /// A room whose work on a worker thread failed (panicked): it does not come back.
    Failed(RoomCode),
    /// The store's answer to a claim for a connection's seat token.
    Claimed(ConnId, SeatToken, Claimed),
    /// The server is stopping: the hub thread ends once the rooms' work already queued is done.
    Shutdown,
}

/// The hub's inbox, counting what waits in it.
#[derive(Clone)]
pub struct HubSender {
    tx: Sender<HubEvent>,
    stats: Arc<Stats>,
}

impl HubSender {
    /// Wraps the hub's channel; what waits in it is counted in `stats.hub_queue` and its peak.
    pub fn new(tx: Sender<HubEvent>, stats: Arc<Stats>) -> HubSender {
        HubSender { tx, stats }
    }

    /// Queues `event` for the hub thread; fails only once that thread has stopped.
    pub fn send(&self, event: HubEvent) -> Result<(), SendError<HubEvent>> {
        let queued = self.stats.hub_queue.fetch_add(1, Ordering::Relaxed) + 1;
        self.stats
            .hub_queue_peak
            .fetch_max(queued, Ordering::Relaxed);
        self.tx.send(event).inspect_err(|_| {
            self.stats.hub_queue.fetch_sub(1, Ordering::Relaxed);
        })
    }
}

/// The writer thread's end of a connection's outgoing queue.
pub struct Outlet {
    /// The connection's bounded queue (`outbound_queue` messages); a full one gets it closed.
    pub tx: tokio::sync::mpsc::Sender<Outbound>,
    /// Wakes the connection to close it (its queue is full, so a message cannot say so).
    pub kill: Arc<Notify>,
}

/// A bounded outgoing queue: the writer's end, the connection's end, and the kill switch.
pub fn outlet(capacity: usize) -> (Outlet, Receiver<Outbound>, Arc<Notify>) {
    let (tx, rx) = channel(capacity.max(1));
    let kill = Arc::new(Notify::new());
    (
        Outlet {
            tx,
            kill: kill.clone(),
        },
        rx,
        kill,
    )
}

/// Application close code for an orderly end: the server shutting down, or a close the hub
/// asked for.
pub const CLOSE_NORMAL: u32 = 0;
/// Application close code for a client that broke the protocol: a malformed or late frame, too
/// many messages, no stream opened, or not reading what it is sent.
pub const CLOSE_PROTOCOL: u32 = 1;

/// How long queued bytes get to reach the peer before a close.
const FLUSH_TIMEOUT: Duration = Duration::from_secs(2);

/// Runs one connection to its end. The hub has been told `Connected(id)` once the stream is
/// open, and is told `Disconnected(id)` at the end.
pub async fn serve(
    id: ConnId,
    conn: quinn::Connection,
    hub: HubSender,
    mut outbound: Receiver<Outbound>,
    kill: Arc<Notify>,
    limits: &Limits,
) {
    let Ok(Ok((mut send, mut recv))) =
        tokio::time::timeout(limits.open_timeout, conn.accept_bi()).await
    else {
        conn.close(CLOSE_PROTOCOL.into(), b"no stream opened");
        return;
    };
    if hub
        .send(HubEvent::Connected(
            id,
            conn.remote_address().ip().to_canonical(),
        ))
        .is_err()
    {
        return;
    }
    let reader = {
        let hub = hub.clone();
        let conn = conn.clone();
        let frame_timeout = limits.frame_timeout;
        let per_second = limits.messages_per_second.max(1);
        async move {
            let mut rate = Bucket::new(
                per_second,
                Duration::from_secs(1) / per_second,
                Instant::now(),
            );
            loop {
                let why = match read_message(&mut recv, frame_timeout).await {
                    Ok(msg) if rate.take(Instant::now()) => {
                        if hub
                            .send(HubEvent::Message(id, msg, Instant::now()))
                            .is_err()
                        {
                            break;
                        }
                        continue;
                    }
                    Ok(_) => {
                        hub.stats.flooding.fetch_add(1, Ordering::Relaxed);
                        "too many messages".to_string()
                    }
                    Err(ReadEnd::Closed) => break,
                    Err(ReadEnd::Malformed(why)) => why,
                };
                tracing::info!(conn = id, %why, "closing connection");
                conn.close(CLOSE_PROTOCOL.into(), why.as_bytes());
                break;
            }
        }
    };
    let writer = async {
        while let Some(out) = outbound.recv().await {
            match out {
                Outbound::Message(msg) => {
                    let frame = match encode_frame(&msg) {
                        Ok(f) => f,
                        Err(e) => {
                            tracing::error!(conn = id, error = %e, "cannot encode a message");
                            continue;
                        }
                    };
                    if send.write_all(&frame).await.is_err() {
                        break;
                    }
                }
                Outbound::Close(reason) => {
                    let _ = send.finish();
                    let _ = tokio::time::timeout(FLUSH_TIMEOUT, send.stopped()).await;
                    conn.close(CLOSE_NORMAL.into(), reason.as_bytes());
                    break;
                }
            }
        }
    };
    // Either side ending ends the connection; so does a full outgoing queue (the writer may
    // be stuck on a peer that grants no more flow-control credit).
    tokio::select! {
        _ = reader => {}
        _ = writer => {}
        _ = kill.notified() => {
            conn.close(CLOSE_PROTOCOL.into(), b"not reading: outgoing queue full");
        }
    }
    let last_heard = last_heard(&conn, Instant::now());
    conn.close(CLOSE_NORMAL.into(), b"bye");
    let _ = hub.send(HubEvent::Disconnected(id, last_heard));
}

/// When the peer of a connection that ended at `now` was last heard from: a connection that
/// timed out had heard nothing for the idle timeout (its peer's keep-alives stopped then);
/// any other end is seen as it happens.
fn last_heard(conn: &quinn::Connection, now: Instant) -> Instant {
    match conn.close_reason() {
        Some(quinn::ConnectionError::TimedOut) => now.checked_sub(IDLE_TIMEOUT).unwrap_or(now),
        _ => now,
    }
}

enum ReadEnd {
    Closed,
    Malformed(String),
}

/// Reads one message. Waiting for a frame to start is unlimited (a player may think), but
/// once its first byte has arrived the rest must follow within `frame_timeout`.
async fn read_message(
    recv: &mut quinn::RecvStream,
    frame_timeout: Duration,
) -> Result<ClientMessage, ReadEnd> {
    let mut header = [0u8; HEADER_LEN];
    recv.read_exact(&mut header[..1])
        .await
        .map_err(|_| ReadEnd::Closed)?;
    let rest = async {
        recv.read_exact(&mut header[1..])
            .await
            .map_err(|_| ReadEnd::Malformed("truncated frame".into()))?;
        let len = payload_len(header).map_err(|e| ReadEnd::Malformed(e.to_string()))?;
        let mut payload = vec![0u8; len];
        recv.read_exact(&mut payload)
            .await
            .map_err(|_| ReadEnd::Malformed("truncated frame".into()))?;
        Ok(payload)
    };
    let payload = tokio::time::timeout(frame_timeout, rest)
        .await
        .map_err(|_| ReadEnd::Malformed("a frame took too long to arrive".into()))??;
    decode_payload(&payload).map_err(|e| ReadEnd::Malformed(e.to_string()))
}
