//! The embedded server (the `host` feature): the same server as `breakshot-server`, run on
//! its own thread inside this process, and the hosted game this computer plays in through
//! the same network path as the other player.

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use breakshot_server::{Config, Server};
use breakshot_shared::protocol::{ClientMessage, Invite};
use breakshot_shared::rules::{Command, Game, Seat};
use tokio::sync::oneshot;

use super::host::{host_text, invite_host, loopback_for, names_wildcard, HostError, HostOptions};
use super::link::NetLink;
use super::session::Session;
use crate::play::link::{GameEvent, GameLink};
use crate::view::hud::Connection;

/// How long hosting waits for its own server to seat it. The server is in this process and
/// answers in milliseconds; this only turns a hang into an error.
const SEATING: Duration = Duration::from_secs(20);

/// The game server running on a thread of its own (with its own tokio runtime), stopped
/// cleanly when dropped.
pub struct EmbeddedServer {
    addr: SocketAddr,
    invite: Invite,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl EmbeddedServer {
    /// Opens the data directory, binds and starts serving; returns once the socket is bound
    /// (or with the reason it could not be).
    pub fn start(config: Config) -> Result<EmbeddedServer, HostError> {
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let (stop, stopped) = oneshot::channel::<()>();
        let thread = std::thread::Builder::new()
            .name("breakshot-server".into())
            .spawn(move || {
                let runtime = match tokio::runtime::Builder::new_multi_thread()
                    .worker_threads(2)
                    .enable_all()
                    .build()
                {
                    Ok(r) => r,
                    Err(e) => {
                        let _ = ready_tx.send(Err(HostError::Runtime(e.to_string())));
                        return;
                    }
                };
                runtime.block_on(async move {
                    // The endpoint must be made inside the runtime.
                    let server = match Server::bind(&config) {
                        Ok(s) => s,
                        Err(e) => {
                            let _ = ready_tx.send(Err(HostError::Server(e)));
                            return;
                        }
                    };
                    let _ = ready_tx.send(Ok((server.local_addr(), server.invite())));
                    let result = server
                        .run(async {
                            let _ = stopped.await;
                        })
                        .await;
                    if let Err(e) = result {
                        tracing::error!(error = %e, "the embedded game server stopped");
                    }
                });
            })
            .map_err(|e| HostError::Runtime(e.to_string()))?;
        match ready_rx.recv() {
            Ok(Ok((addr, invite))) => Ok(EmbeddedServer {
                addr,
                invite,
                stop: Some(stop),
                thread: Some(thread),
            }),
            Ok(Err(e)) => {
                let _ = thread.join();
                Err(e)
            }
            Err(_) => {
                let _ = thread.join();
                Err(HostError::Runtime("the server thread ended".into()))
            }
        }
    }

    /// The address the server is bound to.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// The server's own invite (no room), naming the bound address.
    pub fn invite(&self) -> Invite {
        self.invite.clone()
    }

    /// The server's invite as this computer dials it (loopback for a wildcard bind).
    pub fn loopback_invite(&self) -> Invite {
        let at = loopback_for(self.addr);
        Invite {
            host: host_text(at.ip()),
            port: at.port(),
            ..self.invite.clone()
        }
    }
}

impl Drop for EmbeddedServer {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// A hosted game: the embedded server, and this computer's seat (A) in a new room on it,
/// played through a [`NetLink`] like any other network game.
pub struct Host {
    link: NetLink,
    /// Events the link gave while the room was being opened, handed to the screen first.
    pending: VecDeque<GameEvent>,
    invite: Invite,
    data: PathBuf,
    /// Declared after the link so the session closes before the server stops.
    server: EmbeddedServer,
}

impl Host {
    /// Starts the server, connects to it over loopback, opens a room and returns once this
    /// computer holds seat A, with the invite for the other player.
    pub fn start(options: &HostOptions) -> Result<Host, HostError> {
        let address = options.address.as_deref().map(invite_host).transpose()?;
        let server = EmbeddedServer::start(Config::new(options.bind, options.data.clone()))?;
        let session = Session::connect(server.loopback_invite());
        session.send(ClientMessage::CreateRoom {
            variant: options.variant,
            mode: options.settings,
            aim_aid: options.aim_aid,
            name: "host".into(),
        });
        let mut link = NetLink::new(session);
        let mut pending = VecDeque::new();
        let since = Instant::now();
        let room = loop {
            while let Some(event) = link.poll() {
                match &event {
                    GameEvent::Connection(Connection::Closed(why)) => {
                        return Err(HostError::Room(why.clone()))
                    }
                    GameEvent::Refused(why) => return Err(HostError::Room(why.clone())),
                    _ => pending.push_back(event),
                }
            }
            if let Some(room) = link.session().room().cloned() {
                break room;
            }
            if since.elapsed() > SEATING {
                return Err(HostError::Room("the server did not answer".into()));
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        let mut invite = server.invite().with_room(room);
        if let Some(address) = address {
            invite.host = address;
        }
        Ok(Host {
            link,
            pending,
            invite,
            data: options.data.clone(),
            server,
        })
    }

    /// The invite for the other player: `breakshot://HOST:PORT/ROOM#FINGERPRINT`.
    pub fn invite(&self) -> &Invite {
        &self.invite
    }

    /// True when the invite names a wildcard address (see [`names_wildcard`]).
    pub fn needs_address(&self) -> bool {
        names_wildcard(&self.invite)
    }

    /// The server's data directory.
    pub fn data(&self) -> &std::path::Path {
        &self.data
    }

    /// The embedded server.
    pub fn server(&self) -> &EmbeddedServer {
        &self.server
    }

    /// The link this computer plays through.
    pub fn link(&self) -> &NetLink {
        &self.link
    }
}

impl GameLink for Host {
    fn seat(&self) -> Option<Seat> {
        self.link.seat()
    }

    fn send(&mut self, game: &Game, seat: Seat, command: Command) {
        self.link.send(game, seat, command)
    }

    fn poll(&mut self) -> Option<GameEvent> {
        self.pending.pop_front().or_else(|| self.link.poll())
    }

    fn rematch(&mut self) {
        self.link.rematch()
    }

    fn invite(&self) -> Option<&Invite> {
        Some(&self.invite)
    }
}
