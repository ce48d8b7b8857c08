//! One client connection: reads frames into the hub, writes what the hub sends. It only
//! moves bytes; every decision is the hub's, except the defences that must act before a
//! message reaches the hub: the frame size, the time a frame may take, the message rate
//! (so no connection can fill the hub's queue) and the outgoing queue's length.

use std::future::Future;
use std::net::IpAddr;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{SendError, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::{
    claimed_version, decode_payload, encode_frame, payload_len, ClientMessage, RoomCode, SeatToken,
    ServerMessage, HEADER_LEN, PROTOCOL_VERSION,
};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::sync::mpsc::{channel, Receiver};
use tokio::sync::Notify;

use crate::hub::Claimed;
use crate::limits::Limits;
use crate::output::ConnId;
use crate::ratelimit::Bucket;
use crate::stats::Stats;
use crate::work::Returned;

/// What the writer thread hands a connection.
#[derive(Debug)]
pub enum Outbound {
    /// Encode one message as a frame and write it on the stream; handed to the connection
    /// at this instant.
    Message(ServerMessage, Instant),
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

/// What a connection is wired to: its id, the hub it tells what it reads, and its end of the
/// outgoing queue the writer thread fills, with the switch that wakes it to close.
pub struct Wiring {
    /// The connection's id in the hub.
    pub id: ConnId,
    /// Where what the connection reads goes.
    pub hub: HubSender,
    /// The messages the writer thread hands the connection to send.
    pub outbound: Receiver<Outbound>,
    /// Woken when the outgoing queue is full.
    pub kill: Arc<Notify>,
}

/// Wires connection `id` to `hub` with a bounded outgoing queue of `capacity` messages: the
/// writer thread's end of it, and the connection's.
pub fn wire(id: ConnId, hub: HubSender, capacity: usize) -> (Outlet, Wiring) {
    let (tx, outbound) = channel(capacity.max(1));
    let kill = Arc::new(Notify::new());
    let outlet = Outlet {
        tx,
        kill: kill.clone(),
    };
    (
        outlet,
        Wiring {
            id,
            hub,
            outbound,
            kill,
        },
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

/// What [`serve`] needs from a transport beyond its two byte streams: QUIC
/// ([`crate::quic::QuicLink`]), a Noise-encrypted WebSocket, WebTransport, or any other way
/// in. Everything else (frames, limits, rate, queue, the hub) is the same for all of them.
pub trait Transport: Send + Sync {
    /// The stream [`serve`] writes frames to.
    type Send: AsyncWrite + Unpin + Send;

    /// The peer's address, for the per-address limits (an IPv4-mapped address as IPv4).
    fn remote_ip(&self) -> IpAddr;

    /// Ends the connection at once with `code` ([`CLOSE_NORMAL`] or [`CLOSE_PROTOCOL`]) and a
    /// short reason for the peer. May be called more than once; only the first counts.
    fn close(&self, code: u32, reason: &str);

    /// When the peer of a connection that ended at `now` was last heard from: `now` for any
    /// end seen as it happens, earlier for a peer that fell silent and timed out.
    fn last_heard(&self, now: Instant) -> Instant;

    /// Ends the sending side (no more bytes follow) and resolves once the peer has received
    /// what was written, or gave up on it. [`serve`] bounds the wait, so this may wait for
    /// ever on a peer that never answers.
    fn finish<'a>(&'a self, send: &'a mut Self::Send) -> impl Future<Output = ()> + Send + 'a;
}

/// Runs one connection to its end over `recv` (the peer's bytes) and `send` (bytes for the
/// peer), with `link` for what is specific to its transport. Tells the hub `Connected(id)`
/// first and `Disconnected(id)` at the end; the caller has already registered the writer's end
/// of `wiring`'s queue with the writer thread ([`wire`]).
pub async fn serve<T: Transport>(
    wiring: Wiring,
    link: &T,
    mut recv: impl AsyncRead + Unpin + Send,
    mut send: T::Send,
    limits: &Limits,
) {
    let Wiring {
        id,
        hub,
        mut outbound,
        kill,
    } = wiring;
    if hub
        .send(HubEvent::Connected(id, link.remote_ip().to_canonical()))
        .is_err()
    {
        return;
    }
    let reader = {
        let hub = hub.clone();
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
                    Ok((msg, started)) if rate.take(Instant::now()) => {
                        hub.stats.read_time.record(started.elapsed());
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
                link.close(CLOSE_PROTOCOL, &why);
                break;
            }
        }
    };
    let writer = async {
        while let Some(out) = outbound.recv().await {
            match out {
                Outbound::Message(msg, handed) => {
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
                    hub.stats.send_wait.record(handed.elapsed());
                }
                Outbound::Close(reason) => {
                    let _ = tokio::time::timeout(FLUSH_TIMEOUT, link.finish(&mut send)).await;
                    link.close(CLOSE_NORMAL, &reason);
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
            link.close(CLOSE_PROTOCOL, "not reading: outgoing queue full");
        }
    }
    let last_heard = link.last_heard(Instant::now());
    link.close(CLOSE_NORMAL, "bye");
    let _ = hub.send(HubEvent::Disconnected(id, last_heard));
}

enum ReadEnd {
    Closed,
    Malformed(String),
}

/// Reads one message, with the time its first byte arrived. Waiting for a frame to start is
/// unlimited (a player may think), but once its first byte has arrived the rest must follow
/// within `frame_timeout`.
async fn read_message(
    recv: &mut (impl AsyncRead + Unpin),
    frame_timeout: Duration,
) -> Result<(ClientMessage, Instant), ReadEnd> {
    let mut header = [0u8; HEADER_LEN];
    recv.read_exact(&mut header[..1])
        .await
        .map_err(|_| ReadEnd::Closed)?;
    let started = Instant::now();
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
    let msg = decode_payload(&payload).or_else(|e| match claimed_version(&payload) {
        // A `Hello` of another version, whose shape may differ: the hub refuses it by its
        // version, with a reason the player can read.
        Some(protocol) if protocol != PROTOCOL_VERSION => Ok(ClientMessage::Hello {
            protocol,
            physics: 0,
            key: Vec::new(),
        }),
        _ => Err(ReadEnd::Malformed(e.to_string())),
    })?;
    Ok((msg, started))
}
