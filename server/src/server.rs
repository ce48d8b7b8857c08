//! The driver: binds the QUIC endpoint, runs the hub on its own thread, rooms' messages on a
//! pool of worker threads and the store on a writer thread, and moves bytes between them and
//! the connections.
//!
//! ```text
//! connections --HubEvent--> hub thread --Vec<Output>-------------------> writer thread --Outbound--> connections
//!                              |   ^                                     (stores, then sends)
//!                    Run(room) v   | Returned(room)                        ^
//!                            room workers --Vec<RoomOutput>---------------+
//! ```
//!
//! The hub thread only routes, checks and counts; a message for a room goes out with the
//! room to a worker (the shot's simulation runs there), which hands the room's outputs to the
//! writer and then the room back to the hub. One room is on at most one worker at a time, and
//! the hub holds its next events until it is back, so a room's events keep their order while
//! a long simulation in one room delays no other room and no handshake.
//!
//! The writer thread takes whatever batches are waiting, commits all their store operations
//! in one transaction, and only then hands their messages to the connections: results are
//! never shown before they are durable, and concurrent games share one disk flush.

use std::collections::BTreeMap;
use std::future::Future;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use breakshot_shared::protocol::{
    reference_hash, Fingerprint, Invite, RoomCode, SeatToken, WebLink,
};
use breakshot_shared::rules::Variant;
use thiserror::Error;
use tokio::net::TcpListener;
use tokio::sync::mpsc::error::TrySendError;
use tokio::sync::{watch, Notify};

use crate::admission::{Answer, Gate, Refusal, Ticket};
use crate::conn::{self, HubEvent, Outbound, Outlet};
use crate::endings::Ending;
use crate::hub::{Claimed, Hub, HubConfig, Output, Restored};
use crate::limits::Limits;
use crate::output::{ConnId, RoomMeta, RoomOutput, StoreOp};
use crate::pool::{self, Pool};
use crate::records;
use crate::secret::{Entropy, OsEntropy, TestEntropy, TokenDigest};
use crate::source::source_key;
use crate::stats::Stats;
use crate::store::{Claim, EndedGame, Location, Store, StoreError, StoredGame};
use crate::tls::{Identity, TlsError};
use crate::web::key::NoiseKey;
use crate::web::Web;
use crate::webcert::{ClockRef, WebCerts};
use crate::writer::{Attach, WriterMsg};

/// How to start a server; [`Config::new`] gives the defaults that the binary's flags change.
#[derive(Clone, Debug)]
pub struct Config {
    /// The UDP address to listen on (port 0: any free port, see [`Server::local_addr`]).
    pub bind: SocketAddr,
    /// The certificate's directory, and the SQLite store's unless `store` says otherwise.
    pub data: PathBuf,
    /// Where the games are kept: SQLite in `data` by default.
    pub store: Location,
    /// The server's resources and defences (docs/operations.md, *Limits*).
    pub limits: Limits,
    /// Tests only: draw room codes, seat tokens and game seeds from this seed instead of the
    /// operating system, so a test's games are the same on every run. Never set in service:
    /// predictable tokens let anyone take a seat.
    pub predictable_seed: Option<u64>,
    /// Threads that run rooms' messages (shots are simulated there); by default one per
    /// core and at least two.
    pub room_threads: usize,
    /// Tests only: called on the worker thread before each message a room runs, so a test
    /// can make one room as slow as it likes and watch the others. `None` in service.
    pub before_room_work: Option<RoomHook>,
    /// How long a drain ([`Stats::start_drain`]) waits for the games in play to end before
    /// the server stops anyway (their games stay in the store, for this server's next start
    /// or, on a shared PostgreSQL store, for another instance to take over at once).
    pub drain_timeout: Duration,
    /// The wall clock the browsers' short certificates are made and replaced by
    /// ([`crate::webcert`]): the system's in service, a hand-moved one in tests.
    pub clock: ClockRef,
    /// How often the server looks whether the browsers' certificate is due for replacement
    /// (a minute; tests make it shorter).
    pub web_cert_check: Duration,
    /// Serve the web client from this directory, and the game over a WebSocket, on TCP at
    /// the same address and port number as the UDP socket (docs/web.md). `None`: no TCP
    /// listener at all.
    pub web_dir: Option<PathBuf>,
}

/// The default [`Config::drain_timeout`]: long enough for most games to end.
pub const DEFAULT_DRAIN_TIMEOUT: Duration = Duration::from_secs(15 * 60);

/// See [`Config::before_room_work`].
#[derive(Clone)]
pub struct RoomHook(pub Arc<dyn Fn(&RoomCode) + Send + Sync>);

impl std::fmt::Debug for RoomHook {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RoomHook")
    }
}

impl Config {
    /// A server on `bind` with everything in `data`: the SQLite store, default limits, the
    /// system's randomness and one room thread per core (at least two).
    pub fn new(bind: SocketAddr, data: PathBuf) -> Config {
        Config {
            bind,
            store: Location::Sqlite(data.clone()),
            data,
            limits: Limits::default(),
            predictable_seed: None,
            room_threads: pool::default_threads(),
            before_room_work: None,
            drain_timeout: DEFAULT_DRAIN_TIMEOUT,
            clock: ClockRef::default(),
            web_cert_check: WEB_CERT_CHECK,
            web_dir: None,
        }
    }
}

/// Why a server could not start, or stopped.
#[derive(Debug, Error)]
pub enum ServerError {
    /// The data directory cannot be created.
    #[error("data directory {path}: {source}")]
    DataDir {
        /// The directory, as given.
        path: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// The identity (certificate, key, reset secret) cannot be loaded, made or used.
    #[error("{0}")]
    Tls(#[from] TlsError),
    /// The store cannot be opened, migrated or read back at start.
    #[error("store: {0}")]
    Store(#[from] StoreError),
    // The io error is the source: printing it here too would say it twice in a chain.
    /// The UDP socket cannot be bound (the address is in use, or not this machine's).
    #[error("binding {addr}")]
    Bind {
        /// The address asked for.
        addr: SocketAddr,
        /// The system's error.
        source: std::io::Error,
    },
    /// The web directory is missing or not a directory.
    #[error("web directory {path}: {source}")]
    WebDir {
        /// The directory, as given.
        path: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// Not one thread to run rooms on could be started.
    #[error("cannot start the room worker threads: {0}")]
    Threads(std::io::Error),
    /// This build cannot simulate its reference shot, so it cannot check clients' physics.
    #[error("the reference shot does not simulate: {0}")]
    Physics(String),
    /// A store write failed, so the server stopped without sending the unstored results; fix the
    /// store and start it again (the games are kept as last committed).
    #[error("a storage write failed, so the server stopped: {0}")]
    StorageFailed(String),
}

/// A bound server, ready to run.
pub struct Server {
    endpoint: quinn::Endpoint,
    fingerprint: Fingerprint,
    web_certs: WebCerts,
    web_cert_check: Duration,
    hub: Hub,
    store: Store,
    restored: usize,
    limits: Limits,
    room_threads: usize,
    before_room_work: Option<RoomHook>,
    drain_timeout: Duration,
    stats: Arc<Stats>,
    noise: NoiseKey,
    web: Option<(TcpListener, Arc<Web>)>,
}

impl Server {
    /// Opens the data directory (certificate and store), reloads unfinished games, and binds.
    /// Must be called inside a tokio runtime.
    pub fn bind(config: &Config) -> Result<Server, ServerError> {
        std::fs::create_dir_all(&config.data).map_err(|source| ServerError::DataDir {
            path: config.data.display().to_string(),
            source,
        })?;
        let identity = Identity::load_or_create(&config.data)?;
        let web_certs = WebCerts::load_or_create(&config.data, config.clock.clone())?;
        let noise = NoiseKey::load_or_create(&config.data)?;
        let physics = reference_hash().map_err(|e| ServerError::Physics(e.to_string()))?;
        let mut hub = Hub::new(
            HubConfig {
                limits: config.limits.clone(),
                physics,
                shared_store: matches!(config.store, Location::Postgres(_)),
            },
            match config.predictable_seed {
                Some(seed) => Box::new(TestEntropy::new(seed)),
                None => Box::new(OsEntropy),
            },
        );
        // The PostgreSQL driver blocks on a runtime of its own, which cannot start inside the
        // server's: the store is opened and read back on a plain thread (the writer thread,
        // where it is used from then on, is one too).
        let (store, restored) = std::thread::scope(|s| {
            s.spawn(|| -> Result<_, ServerError> {
                let mut store = Store::at(&config.store)?;
                let restored = restore(&mut store, &mut hub)?;
                Ok((store, restored))
            })
            .join()
        })
        .map_err(|_| {
            ServerError::StorageFailed("the thread opening the store panicked".into())
        })??;
        let reset_key = crate::tls::reset_key(&config.data)?;
        let endpoint = endpoint(
            identity.server_config(Arc::new(web_certs.clone()))?,
            reset_key,
            config.bind,
        )
        .map_err(|source| ServerError::Bind {
            addr: config.bind,
            source,
        })?;
        let web = match &config.web_dir {
            Some(dir) => {
                let root = web_root(dir)?;
                // The port the UDP socket got, so a port 0 gives one number for both.
                let port = endpoint
                    .local_addr()
                    .map_or(config.bind.port(), |a| a.port());
                let addr = SocketAddr::new(config.bind.ip(), port);
                let listener =
                    tcp_listener(addr).map_err(|source| ServerError::Bind { addr, source })?;
                Some((
                    listener,
                    Arc::new(Web {
                        root,
                        key: noise.clone(),
                        certs: web_certs.clone(),
                    }),
                ))
            }
            None => None,
        };
        Ok(Server {
            endpoint,
            noise,
            web,
            fingerprint: identity.fingerprint(),
            web_certs,
            web_cert_check: config.web_cert_check,
            hub,
            store,
            restored,
            limits: config.limits.clone(),
            room_threads: config.room_threads,
            before_room_work: config.before_room_work.clone(),
            drain_timeout: config.drain_timeout,
            stats: Arc::new(Stats::default()),
        })
    }

    /// Live counters (connections, queues, refusals), shared with the running server.
    pub fn stats(&self) -> Arc<Stats> {
        self.stats.clone()
    }

    /// The address bound, with the port the system chose if `bind` asked for port 0.
    pub fn local_addr(&self) -> SocketAddr {
        // The endpoint was bound to a real socket in `bind`.
        self.endpoint
            .local_addr()
            .unwrap_or_else(|_| SocketAddr::from(([0, 0, 0, 0], 0)))
    }

    /// SHA-256 of the server's certificate, as every invite carries it.
    pub fn fingerprint(&self) -> Fingerprint {
        self.fingerprint
    }

    /// SHA-256 of the short certificates a browser may be shown over WebTransport, newest
    /// first: what a page passes as `serverCertificateHashes` (see [`crate::webcert`]).
    pub fn web_cert_hashes(&self) -> Vec<Fingerprint> {
        self.web_certs.hashes()
    }

    /// The short certificates themselves, shared with the running server: their hashes stay
    /// current through every replacement (for whoever publishes them), and a test can
    /// [`WebCerts::refresh`] them after moving its clock.
    pub fn web_certs(&self) -> WebCerts {
        self.web_certs.clone()
    }

    /// The server's Noise static public key (X25519), which web links carry (`key=`); the
    /// same whether or not the server serves the web.
    pub fn web_key(&self) -> [u8; 32] {
        self.noise.public
    }

    /// The TCP address of the web listener, when the server serves the web.
    pub fn web_addr(&self) -> Option<SocketAddr> {
        self.web.as_ref().and_then(|(l, _)| l.local_addr().ok())
    }

    /// The web link to this server (and `room`), or `None` when it does not serve the web:
    /// `http://HOST:P/?room=ROOM&key=KEY&cert=HASH[,HASH]`, with the `h3` certificates'
    /// hashes as they are now (a page on the server asks `/certificate.sha256` too, for a
    /// link older than a rotation).
    pub fn web_link(&self, room: Option<RoomCode>) -> Option<WebLink> {
        let addr = self.web_addr()?;
        let mut link = WebLink::new(self.web_key());
        link.page = Some(WebLink::page_url(&host_of(addr), addr.port()));
        link.room = room;
        link.cert = self.web_cert_hashes();
        Some(link)
    }

    /// Games brought back from the store at start.
    pub fn restored(&self) -> usize {
        self.restored
    }

    /// The server's invite (no room): `breakshot://HOST:PORT#FINGERPRINT`.
    pub fn invite(&self) -> Invite {
        let addr = self.local_addr();
        Invite::new(host_of(addr), addr.port(), self.fingerprint)
    }

    /// Serves until `shutdown` resolves (or a storage write fails), then closes every
    /// connection, finishes pending writes and returns.
    pub async fn run(self, shutdown: impl Future<Output = ()>) -> Result<(), ServerError> {
        let Server {
            endpoint,
            hub,
            store,
            limits,
            room_threads,
            before_room_work,
            drain_timeout,
            stats,
            web_certs,
            web_cert_check,
            web,
            ..
        } = self;
        let (web_listener, web) = match web {
            Some((l, w)) => (Some(l), Some(w)),
            None => (None, None),
        };
        let (stop_tx, stop_rx) = watch::channel(false);
        let (hub_tx, hub_rx) = mpsc::channel::<HubEvent>();
        let (writer_tx, writer_rx) = mpsc::channel::<WriterMsg>();
        let failed = Arc::new(Notify::new());
        let hub_tx = conn::HubSender::new(hub_tx, stats.clone());
        let hub_thread = spawn_hub(
            hub,
            hub_rx,
            hub_tx.clone(),
            writer_tx.clone(),
            Workers {
                pool: Pool::new(room_threads).map_err(ServerError::Threads)?,
                hook: before_room_work,
            },
            stats.clone(),
        );
        let writer_thread = spawn_writer(
            store,
            writer_rx,
            hub_tx.clone(),
            failed.clone(),
            stats.clone(),
        );

        let gate = Gate::new(stats.clone());
        let mut next_id: ConnId = 0;
        let mut connections = tokio::task::JoinSet::new();
        tokio::pin!(shutdown);
        let mut drain_check = tokio::time::interval(DRAIN_CHECK);
        let mut drain_started: Option<Instant> = None;
        let mut cert_check = tokio::time::interval(web_cert_check.max(Duration::from_millis(10)));
        let outcome = loop {
            tokio::select! {
                _ = &mut shutdown => break Ok(()),
                _ = failed.notified() => break Err(()),
                // Always polled: a drain starts from another task (a signal, the admin
                // address), and a disabled branch would not notice it until the next event.
                _ = drain_check.tick() => {
                    if !stats.is_draining() {
                        continue;
                    }
                    let started = *drain_started.get_or_insert_with(|| {
                        tracing::info!("draining: no new games; stopping when the games in play end");
                        Instant::now()
                    });
                    // The census is taken after the drain began, so a game started just
                    // before it is counted.
                    let settled = started.elapsed() > CENSUS_PERIOD * 2;
                    if settled && Stats::get(&stats.rooms_playing) == 0 {
                        tracing::info!("drained: no game in play");
                        break Ok(());
                    }
                    if started.elapsed() >= drain_timeout {
                        tracing::warn!(playing = Stats::get(&stats.rooms_playing), "drain time is up; stopping with games in play (they stay stored)");
                        break Ok(());
                    }
                }
                _ = cert_check.tick() => {
                    // Rare and small (a new key and certificate every eleven days): done in
                    // place rather than on a thread.
                    if let Err(e) = web_certs.refresh() {
                        tracing::error!(error = %e, "cannot keep the new certificate for browsers");
                    }
                }
                accepted = accept_tcp(web_listener.as_ref()) => {
                    let (Ok((stream, peer)), Some(web)) = (accepted, &web) else {
                        // Out of file descriptors or the like: wait a little rather than spin.
                        tokio::time::sleep(Duration::from_millis(50)).await;
                        continue;
                    };
                    while connections.try_join_next().is_some() {}
                    let source = source_key(peer.ip());
                    // A TCP handshake has proven the address already: no retry.
                    let ticket = match gate.admit(&limits, source, true) {
                        Answer::Admitted(ticket) => ticket,
                        Answer::Retry => continue,
                        Answer::Refused(why) => {
                            let counter = match why {
                                Refusal::Full => &stats.refused,
                                Refusal::AddressShare => &stats.refused_address,
                            };
                            counter.fetch_add(1, Ordering::Relaxed);
                            continue;
                        }
                    };
                    next_id += 1;
                    let visit = crate::web::Visit {
                        web: web.clone(),
                        limits: limits.clone(),
                        stats: stats.clone(),
                        stop: stop_rx.clone(),
                        attach: Attach::new(
                            next_id,
                            hub_tx.clone(),
                            writer_tx.clone(),
                            limits.clone(),
                        ),
                    };
                    connections.spawn(crate::web::serve(stream, peer, ticket, visit));
                }
                incoming = endpoint.accept() => {
                    let Some(incoming) = incoming else { break Ok(()) };
                    // Finished tasks are reaped here so the set holds only live ones.
                    while connections.try_join_next().is_some() {}
                    let Some((incoming, mut ticket)) = admit(incoming, &gate, &limits, &stats) else { continue };
                    next_id += 1;
                    let id = next_id;
                    let (outlet, wiring) = conn::wire(id, hub_tx.clone(), limits.outbound_queue);
                    if writer_tx.send(WriterMsg::Register(id, outlet)).is_err() {
                        break Err(());
                    }
                    let writer_tx = writer_tx.clone();
                    let limits = limits.clone();
                    let stats = stats.clone();
                    connections.spawn(async move {
                        // Dropping an unfinished handshake abandons it.
                        let handshake = tokio::time::timeout(limits.handshake_timeout, incoming).await;
                        ticket.handshake_over();
                        match handshake {
                            Ok(Ok(connection)) => {
                                tracing::debug!(conn = id, peer = %connection.remote_address(), "connected");
                                // One connection either way: the same gate, limits and hub.
                                if crate::webtransport::is_web(&connection) {
                                    crate::webtransport::serve(wiring, connection, &limits, &stats).await;
                                } else {
                                    crate::tls::native_streams(&connection);
                                    crate::quic::serve(wiring, connection, &limits).await;
                                }
                            }
                            Ok(Err(e)) => tracing::debug!(conn = id, error = %e, "handshake failed"),
                            Err(_) => tracing::debug!(conn = id, "handshake took too long"),
                        }
                        drop(ticket);
                        let _ = writer_tx.send(WriterMsg::Unregister(id));
                    });
                }
            }
        };
        tracing::info!("shutting down");
        endpoint.close(conn::CLOSE_NORMAL.into(), b"server shutting down");
        drop(web_listener);
        let _ = stop_tx.send(true);
        // Closing the endpoint ends every connection task; wait for them so that nothing
        // of this server is left running when `run` returns.
        let _ = tokio::time::timeout(Duration::from_secs(5), async {
            while connections.join_next().await.is_some() {}
        })
        .await;
        let _ = hub_tx.send(HubEvent::Shutdown);
        drop(writer_tx);
        let joined = tokio::task::spawn_blocking(move || {
            let _ = hub_thread.join();
            writer_thread.join()
        })
        .await;
        let _ = tokio::time::timeout(Duration::from_secs(3), endpoint.wait_idle()).await;
        report_command_time(&stats);
        match (outcome, joined) {
            (Ok(()), Ok(Ok(Ok(())))) => Ok(()),
            (_, Ok(Ok(Err(e)))) => Err(ServerError::StorageFailed(e)),
            _ => Err(ServerError::StorageFailed(
                "the writer thread stopped".into(),
            )),
        }
    }
}

/// The next connection on the web listener; never, without one.
async fn accept_tcp(
    listener: Option<&TcpListener>,
) -> std::io::Result<(tokio::net::TcpStream, SocketAddr)> {
    match listener {
        Some(l) => l.accept().await,
        None => std::future::pending().await,
    }
}

/// The web directory, canonical (so no path served can leave it), or why not.
fn web_root(dir: &std::path::Path) -> Result<PathBuf, ServerError> {
    let err = |source| ServerError::WebDir {
        path: dir.display().to_string(),
        source,
    };
    let root = dir.canonicalize().map_err(err)?;
    if !root.is_dir() {
        return Err(err(std::io::Error::other("not a directory")));
    }
    Ok(root)
}

/// The TCP listener of the web side (address reuse as for any server socket, so a restart
/// does not wait for old connections' TIME_WAIT).
fn tcp_listener(addr: SocketAddr) -> std::io::Result<TcpListener> {
    let socket = match addr {
        SocketAddr::V4(_) => tokio::net::TcpSocket::new_v4()?,
        SocketAddr::V6(_) => tokio::net::TcpSocket::new_v6()?,
    };
    socket.set_reuseaddr(true)?;
    socket.bind(addr)?;
    socket.listen(1024)
}

/// An address's host as links write it (an IPv6 address in brackets).
fn host_of(addr: SocketAddr) -> String {
    match addr.ip() {
        std::net::IpAddr::V6(ip) => format!("[{ip}]"),
        ip => ip.to_string(),
    }
}

/// Logs the server's own time per command over the run (see [`crate::timing`]).
fn report_command_time(stats: &Stats) {
    let h = &stats.command_time;
    let ms = |q| h.quantile(q).map_or(0.0, |d| d.as_secs_f64() * 1e3);
    if h.count() > 0 {
        tracing::info!(
            commands = h.count(),
            p50_ms = format!("{:.2}", ms(0.5)),
            p99_ms = format!("{:.2}", ms(0.99)),
            max_ms = format!("{:.2}", ms(1.0)),
            "server time per command (read, queue, rules and simulation, durable write)"
        );
    }
}

/// Socket buffer the server asks for (the kernel may cap it, e.g. at `net.core.rmem_max`).
const SOCKET_BUFFER: usize = 4 * 1024 * 1024;

/// The QUIC endpoint on one UDP socket for every client. The socket's buffers are enlarged:
/// with hundreds of connections a burst overflows the default receive buffer, and each
/// dropped datagram costs a QUIC loss-recovery delay.
fn endpoint(
    config: quinn::ServerConfig,
    reset_key: [u8; 32],
    addr: SocketAddr,
) -> std::io::Result<quinn::Endpoint> {
    let socket = std::net::UdpSocket::bind(addr)?;
    let state = quinn::udp::UdpSocketState::new((&socket).into())?;
    for (what, result) in [
        (
            "receive",
            state.set_recv_buffer_size((&socket).into(), SOCKET_BUFFER),
        ),
        (
            "send",
            state.set_send_buffer_size((&socket).into(), SOCKET_BUFFER),
        ),
    ] {
        if let Err(e) = result {
            tracing::warn!(error = %e, "cannot enlarge the UDP {what} buffer");
        }
    }
    let reset = ring::hmac::Key::new(ring::hmac::HMAC_SHA256, &reset_key);
    let mut endpoint_config = quinn::EndpointConfig::new(Arc::new(reset));
    endpoint_config.cid_generator(|| Box::new(RandomCids));
    quinn::Endpoint::new(
        endpoint_config,
        Some(config),
        socket,
        Arc::new(quinn::TokioRuntime),
    )
}

/// Decides whether a connection attempt gets a handshake (see [`crate::admission`]):
/// refused beyond the connection limit or its address's share; sent a retry (which a real
/// client answers at once and a spoofed one never does) when many handshakes are already
/// under way and its address is not yet proven.
fn admit(
    incoming: quinn::Incoming,
    gate: &Gate,
    limits: &Limits,
    stats: &Stats,
) -> Option<(quinn::Incoming, Ticket)> {
    let source = source_key(incoming.remote_address().ip());
    match gate.admit(limits, source, incoming.remote_address_validated()) {
        Answer::Admitted(ticket) => Some((incoming, ticket)),
        Answer::Retry => {
            stats.retried.fetch_add(1, Ordering::Relaxed);
            if let Err(e) = incoming.retry() {
                e.into_incoming().ignore();
            }
            None
        }
        Answer::Refused(why) => {
            let counter = match why {
                Refusal::Full => &stats.refused,
                Refusal::AddressShare => &stats.refused_address,
            };
            counter.fetch_add(1, Ordering::Relaxed);
            incoming.refuse();
            None
        }
    }
}

/// Connection IDs drawn at random, all accepted as well-formed. quinn's default generator
/// marks its IDs with a per-process key and silently drops packets for IDs it did not make,
/// so after a restart the clients of the previous run would get no stateless reset and
/// would wait for their idle timeout before reconnecting.
struct RandomCids;

const CID_LEN: usize = 8;

impl quinn::ConnectionIdGenerator for RandomCids {
    fn generate_cid(&mut self) -> quinn::ConnectionId {
        let mut bytes = [0u8; CID_LEN];
        OsEntropy.fill(&mut bytes);
        quinn::ConnectionId::new(&bytes)
    }

    fn cid_len(&self) -> usize {
        CID_LEN
    }

    fn cid_lifetime(&self) -> Option<Duration> {
        None
    }
}

/// Binds and serves until `shutdown` resolves.
pub async fn run(config: Config, shutdown: impl Future<Output = ()>) -> Result<(), ServerError> {
    Server::bind(&config)?.run(shutdown).await
}

/// Replays every unfinished game, checking each stored hash, and hands it to the hub (a
/// game stored in an older record format is written again in the current one first).
fn restore(store: &mut Store, hub: &mut Hub) -> Result<usize, ServerError> {
    let now = Instant::now();
    hub.load_ratings(store.ratings()?);
    let mut restored = 0;
    for stored in store.unfinished()? {
        store.upgrade(&stored)?;
        if let Some(r) = replayed(stored) {
            hub.restore(now, r);
            restored += 1;
        }
    }
    // Games that ended recently: their players may still come back to learn the result.
    let retention = hub.config().limits.finished_retention.as_secs();
    let today = crate::store::unix_now();
    for ended in store.ended_since(today.saturating_sub(retention))? {
        let (meta, ending, age) = ending_of(ended);
        hub.restore_ending(now, &meta, ending, age);
    }
    Ok(restored)
}

/// A stored game's end as the hub keeps it, with how long ago it was.
fn ending_of(ended: EndedGame) -> (RoomMeta, Ending, Duration) {
    let ending = Ending {
        room: ended.meta.code.clone(),
        game: ended.number,
        winner: ended.winner,
        reason: ended.reason,
    };
    let age = crate::store::unix_now().saturating_sub(ended.at);
    (ended.meta, ending, Duration::from_secs(age))
}

/// A stored game replayed with every hash checked, or `None` (and why, in the log).
fn replayed(stored: StoredGame) -> Option<Restored> {
    let room = stored.meta.code.clone();
    let record = match stored.record {
        Ok(r) => r,
        Err(e) => {
            tracing::error!(%room, game = stored.number, error = %e, "stored record unreadable; not restored");
            return None;
        }
    };
    match record.replay() {
        Ok(game) => {
            tracing::info!(%room, game = stored.number, commands = record.entries.len(), "game restored");
            Some(Restored {
                meta: stored.meta,
                number: stored.number,
                record,
                game,
                clock: stored.clock.map(|c| c.left_at(crate::store::unix_millis())),
                rated: stored.rated,
                listed: stored.listed,
            })
        }
        Err(e) => {
            tracing::error!(%room, game = stored.number, error = %e, "stored game does not replay; not restored");
            None
        }
    }
}

/// Asks the store for the room of a seat no room here knows (see [`Store::claim`]). A room
/// taken over is replayed here, on the writer thread, holding up other writes for that long:
/// a takeover is rare, and a game's replay is bounded by its length limit.
fn claim(store: &mut Store, token: &SeatToken) -> Claimed {
    match store.claim(&TokenDigest::of(token)) {
        Ok(Claim::Taken(stored)) => match store.upgrade(&stored).ok().and(replayed(*stored)) {
            Some(r) => {
                tracing::info!(room = %r.meta.code, "room taken over from a stopped instance");
                Claimed::Taken(Box::new(r))
            }
            None => Claimed::NotFound,
        },
        Ok(Claim::Ended(ended)) => {
            let (meta, ending, age) = ending_of(*ended);
            Claimed::Ended {
                meta: Box::new(meta),
                ending,
                age,
            }
        }
        Ok(Claim::Elsewhere) => Claimed::Elsewhere,
        Ok(Claim::NotFound) => Claimed::NotFound,
        Err(e) => {
            tracing::error!(error = %e, "the store could not say who owns a room");
            Claimed::Elsewhere
        }
    }
}

/// The threads that run rooms' messages, with the tests' hook.
struct Workers {
    pool: Pool,
    hook: Option<RoomHook>,
}

/// The default [`Config::web_cert_check`].
const WEB_CERT_CHECK: Duration = Duration::from_secs(60);

/// How often a draining server looks whether its games have ended.
const DRAIN_CHECK: Duration = Duration::from_millis(250);

/// How often the hub counts its rooms by state for the metrics (and so how stale they may be).
const CENSUS_PERIOD: Duration = Duration::from_secs(1);

/// The games the quick-match queues are counted by on `/metrics`.
const QUEUE_LABELS: [&str; 4] = ["eight_ball", "nine_ball", "three_cushion", "snooker"];

/// The `/metrics` label of a queue's game.
fn queue_label(variant: Variant) -> &'static str {
    match variant {
        Variant::EightBall(_) | Variant::Practice => QUEUE_LABELS[0],
        Variant::NineBall => QUEUE_LABELS[1],
        Variant::ThreeCushion { .. } => QUEUE_LABELS[2],
        Variant::Snooker { .. } => QUEUE_LABELS[3],
    }
}

fn spawn_hub(
    mut hub: Hub,
    events: Receiver<HubEvent>,
    back: conn::HubSender,
    writer: Sender<WriterMsg>,
    workers: Workers,
    stats: Arc<Stats>,
) -> JoinHandle<()> {
    // The pool moves into the thread: when the hub stops, dropping it finishes the rooms'
    // work already queued (so every accepted command is stored) before the writer stops.
    let mut last_census: Option<Instant> = None;
    std::thread::spawn(move || loop {
        stats.rooms.store(hub.room_count(), Ordering::Relaxed);
        if stats.is_draining() {
            // The first time: every player is told, and the queues are emptied.
            let told = hub.drain();
            if !told.is_empty() && writer.send(WriterMsg::batch(told, None)).is_err() {
                return;
            }
        }
        if last_census.is_none_or(|t| t.elapsed() >= CENSUS_PERIOD) {
            let census = hub.census();
            stats.rooms_waiting.store(census.waiting, Ordering::Relaxed);
            stats.rooms_playing.store(census.playing, Ordering::Relaxed);
            stats.rooms_over.store(census.over, Ordering::Relaxed);
            stats
                .refused_draining
                .store(hub.drain_refusals(), Ordering::Relaxed);
            stats.rooms_listed.store(hub.listed(), Ordering::Relaxed);
            stats
                .desyncs_reported
                .store(hub.desyncs(), Ordering::Relaxed);
            let mut queued: Vec<(&'static str, usize)> =
                QUEUE_LABELS.iter().map(|l| (*l, 0)).collect();
            for (variant, _, n) in hub.queue_lengths() {
                if let Some(q) = queued.iter_mut().find(|(l, _)| *l == queue_label(variant)) {
                    q.1 += n;
                }
            }
            if let Ok(mut q) = stats.queued.lock() {
                *q = queued;
            }
            last_census = Some(Instant::now());
        }
        // The hub wakes at least once a census period, so the metrics stay current while
        // nothing happens.
        let now = Instant::now();
        let wait = hub
            .next_deadline()
            .map_or(CENSUS_PERIOD, |d| d.saturating_duration_since(now))
            .min(CENSUS_PERIOD);
        let event = events.recv_timeout(wait);
        let now = Instant::now();
        if event.is_ok() {
            stats.hub_queue.fetch_sub(1, Ordering::Relaxed);
        }
        let read = match &event {
            Ok(HubEvent::Message(_, _, at)) => Some(*at),
            _ => None,
        };
        if let Some(read) = read {
            stats.hub_wait.record(now.saturating_duration_since(read));
        }
        let out = match event {
            Ok(HubEvent::Connected(id, addr)) => {
                hub.connected(now, id, addr);
                Vec::new()
            }
            Ok(HubEvent::Message(id, msg, read)) => hub.handle_read(now, read, id, msg),
            Ok(HubEvent::Disconnected(id, last_heard)) => hub.disconnected(now, last_heard, id),
            Ok(HubEvent::Returned(room)) => hub.returned(now, room),
            Ok(HubEvent::Failed(code)) => hub.failed(&code),
            Ok(HubEvent::Claimed(id, token, claimed)) => hub.claimed(now, id, token, claimed),
            Ok(HubEvent::Shutdown) | Err(RecvTimeoutError::Disconnected) => return,
            Err(RecvTimeoutError::Timeout) => hub.tick(now),
        };
        // Deadlines that passed while handling messages are handled too.
        let mut out = out;
        if hub.next_deadline().is_some_and(|d| d <= now) {
            out.extend(hub.tick(now));
        }
        if read.is_some() {
            stats.hub_time.record(now.elapsed());
        }
        let (work, out): (Vec<_>, Vec<_>) =
            out.into_iter().partition(|o| matches!(o, Output::Run(_)));
        // What the hub said goes to the writer before any room it lent out can answer.
        if !out.is_empty() && writer.send(WriterMsg::batch(out, read)).is_err() {
            return;
        }
        for o in work {
            let Output::Run(work) = o else { continue };
            let writer = writer.clone();
            let back = back.clone();
            let hook = workers.hook.clone();
            let stats = stats.clone();
            let lent = Instant::now();
            workers.pool.run(move || {
                let started = Instant::now();
                stats
                    .worker_wait
                    .record(started.saturating_duration_since(lent));
                let code = work.room().clone();
                let read = work.read;
                // A panic here is a bug in a room; it must cost that room only, not the
                // worker thread and not the rooms behind it.
                let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    if let Some(RoomHook(hook)) = hook {
                        hook(work.room());
                    }
                    work.run(Instant::now())
                }));
                stats.worker_time.record(started.elapsed());
                match ran {
                    Ok((out, room)) => {
                        // The room's results reach the writer before the room is back at
                        // the hub, so its next results always come after these.
                        let out = out.into_iter().map(Output::Room).collect();
                        let _ = writer.send(WriterMsg::batch(out, Some(read)));
                        let _ = back.send(HubEvent::Returned(room));
                    }
                    Err(_) => {
                        tracing::error!(room = %code, "a room's work panicked; the room is closed");
                        let _ = back.send(HubEvent::Failed(code));
                    }
                }
            });
        }
    })
}

fn spawn_writer(
    mut store: Store,
    inbox: Receiver<WriterMsg>,
    hub: conn::HubSender,
    failed: Arc<Notify>,
    stats: Arc<Stats>,
) -> JoinHandle<Result<(), String>> {
    std::thread::spawn(move || {
        let mut conns: BTreeMap<ConnId, Outlet> = BTreeMap::new();
        while let Ok(first) = inbox.recv() {
            // Group commit: everything already waiting goes into one transaction.
            let taken = Instant::now();
            let mut msgs = vec![first];
            msgs.extend(inbox.try_iter());
            let ops: Vec<_> = msgs
                .iter()
                .filter_map(|m| match m {
                    WriterMsg::Batch { out, .. } => Some(out.iter().filter_map(|o| match o {
                        Output::Room(RoomOutput::Store(op)) => Some(op),
                        _ => None,
                    })),
                    _ => None,
                })
                .flatten()
                .collect();
            if !ops.is_empty() {
                let started = Instant::now();
                let applied = store.apply(&ops);
                stats.store_write_time.record(started.elapsed());
                if let Err(e) = applied {
                    tracing::error!(error = %e, "storage write failed; stopping without showing the unstored results");
                    failed.notify_one();
                    return Err(e.to_string());
                }
            }
            for msg in msgs {
                match msg {
                    WriterMsg::Register(id, tx) => {
                        conns.insert(id, tx);
                    }
                    WriterMsg::Unregister(id) => {
                        conns.remove(&id);
                    }
                    WriterMsg::Batch { out, read, handed } => {
                        stats
                            .writer_wait
                            .record(taken.saturating_duration_since(handed));
                        let command = out.iter().any(|o| {
                            matches!(o, Output::Room(RoomOutput::Store(StoreOp::Command { .. })))
                        });
                        for o in out {
                            let (to, what) = match o {
                                Output::Room(RoomOutput::Send { to, msg }) => {
                                    (to, Outbound::Message(msg, Instant::now()))
                                }
                                Output::Room(RoomOutput::Close { conn, reason }) => {
                                    (conn, Outbound::Close(reason))
                                }
                                // The hub thread hands every `Run` to the workers.
                                Output::Room(RoomOutput::Store(_)) | Output::Run(_) => continue,
                                // Read after every earlier write is committed, as records are.
                                Output::Claim { conn, token } => {
                                    let claimed = claim(&mut store, &token);
                                    let _ = hub.send(HubEvent::Claimed(conn, token, claimed));
                                    continue;
                                }
                                Output::SendRecord { to, room, game } => {
                                    let answer = records::answer(&store, &room, game);
                                    (to, Outbound::Message(answer, Instant::now()))
                                }
                            };
                            let Some(outlet) = conns.get(&to) else {
                                continue;
                            };
                            if let Err(TrySendError::Full(_)) = outlet.tx.try_send(what) {
                                // The client is not reading: drop it rather than hold an
                                // unbounded backlog for it.
                                tracing::info!(
                                    conn = to,
                                    "closing connection: it does not read what it is sent"
                                );
                                stats.too_slow.fetch_add(1, Ordering::Relaxed);
                                outlet.kill.notify_one();
                                conns.remove(&to);
                            }
                        }
                        if let (true, Some(read)) = (command, read) {
                            stats.command_time.record(read.elapsed());
                        }
                    }
                }
            }
        }
        Ok(())
    })
}
