//! The embedded server (the `host` feature): the same server as `breakshot-server`, run on
//! its own thread inside this process, and the hosted game this computer plays in through
//! the same network path as the other player.

use super::background::BackgroundThread;
use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use breakshot_server::{Config, Server, Stats};
use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{ClientMessage, Invite, WebLink};
use breakshot_shared::rules::{Command, Game, Seat, Settings, TurnId};

use super::host::{
    host_text, interface_addresses, invite_host, lan_address, loopback_for, names_wildcard,
    HostError, HostOptions,
};
use super::net_link::NetLink;
use super::player::Entry;
use super::seated_computer::SeatedComputer;
use super::seats::SeatStore;
use super::session::Session;
use crate::play::{GameEvent, GameLink};
use crate::view::hud::Connection;

/// How long hosting waits for its own server to seat it. The server is in this process and
/// answers in milliseconds; this only turns a hang into an error.
const SEATING: Duration = Duration::from_secs(20);

/// The game server running on a thread of its own (with its own tokio runtime), stopped
/// cleanly when dropped.
pub struct EmbeddedServer {
    addr: SocketAddr,
    invite: Invite,
    /// The page's link, when the server serves the web client.
    web_link: Option<WebLink>,
    /// The server's key and certificate hashes, for a link to a page published elsewhere.
    web_trust: WebLink,
    /// What the server counts, and its drain switch.
    stats: Arc<Stats>,
    /// The server's thread, stopped when this is dropped.
    _thread: BackgroundThread,
}

impl EmbeddedServer {
    /// Opens the data directory, binds and starts serving; returns once the socket is bound
    /// (or with the reason it could not be).
    pub fn start(config: Config) -> Result<EmbeddedServer, HostError> {
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let thread = BackgroundThread::spawn("breakshot-server", move |stopped| {
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
                let _ = ready_tx.send(Ok((
                    server.local_addr(),
                    server.invite(),
                    server.web_link(None),
                    WebLink {
                        cert: server.web_cert_hashes(),
                        ..WebLink::new(server.web_key())
                    },
                    server.stats(),
                )));
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
            Ok(Ok((addr, invite, web_link, web_trust, stats))) => Ok(EmbeddedServer {
                addr,
                invite,
                web_link,
                web_trust,
                stats,
                _thread: thread,
            }),
            // The thread has ended or is ending: dropping it waits for that.
            Ok(Err(e)) => Err(e),
            Err(_) => Err(HostError::Runtime("the server thread ended".into())),
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

    /// The page's link to the server (no room), when it serves the web client.
    pub fn web_link(&self) -> Option<&WebLink> {
        self.web_link.as_ref()
    }

    /// What the server counts; [`Stats::start_drain`] drains it as `SIGTERM` drains
    /// `breakshot-server` (no new game, the players told, the games in play finished).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The server's invite as this computer dials it (loopback for a wildcard bind).
    pub fn loopback_invite(&self) -> Invite {
        let at = loopback_for(self.addr);
        Invite::new(host_text(at.ip()), at.port(), self.invite.fingerprint)
    }
}

/// A hosted game: the embedded server, and this computer's seat (A) in a new room on it,
/// played through a [`NetLink`] like any other network game.
pub struct Host {
    link: NetLink<Session>,
    /// Events the link gave while the room was being opened, handed to the screen first.
    pending: VecDeque<GameEvent>,
    invite: Invite,
    /// The link a friend opens in a browser, when the web client is served.
    web_link: Option<String>,
    resumed: bool,
    data: PathBuf,
    /// The computer player in the other seat, when it plays it.
    computer: Option<SeatedComputer>,
    /// Declared after the link and the computer so their sessions close before the server
    /// stops.
    server: EmbeddedServer,
}

impl Host {
    /// Starts the server, connects to it over loopback and returns once this computer holds
    /// seat A, with the invite for the other player. The seat is the one this computer
    /// still holds in an unfinished game on this server (a host restarted with the same data
    /// directory goes back to its game: same room, same invite), unless
    /// [`HostOptions::resume`] is false or that game is over; else a new room.
    pub fn start(options: &HostOptions) -> Result<Host, HostError> {
        let address = options.address.as_deref().map(invite_host).transpose()?;
        let mut config = Config::new(options.bind, options.data.clone());
        config.web_dir = options.web.clone();
        let server = EmbeddedServer::start(config)?;
        let mut addressed = server.invite();
        // A server on every interface is dialled on this computer's LAN address.
        let lan = || {
            (options.bind.ip().is_unspecified())
                .then(|| lan_address(&interface_addresses()))
                .flatten()
                .map(host_text)
        };
        if let Some(address) = address.or_else(lan) {
            addressed = addressed.with_host(address);
        }
        let seats = SeatStore::new(&options.data);
        // The computer's seat is not kept when the host closes: its game cannot go on.
        let resuming = (options.resume && options.computer.is_none())
            .then(|| seats.on_server(&addressed.fingerprint))
            .flatten();
        let create = Entry::Create(ClientMessage::CreateRoom {
            variant: options.variant,
            mode: Settings {
                table: options.variant.table(options.settings.table),
                ..options.settings
            },
            aim_aid: options.aim_aid,
            name: options.name.clone(),
        });
        let session = Session::connect(server.loopback_invite());
        // The remembered game may be over (or was never stored): then a new room.
        session.enter(match &resuming {
            Some(seat) => Entry::Rejoin {
                token: seat.token,
                otherwise: Some(Box::new(create.clone())),
            },
            None => create.clone(),
        });
        let mut link = NetLink::new(session);
        if options.computer.is_none() {
            // Under the remembered seat's own invite, so a stale one is forgotten.
            let under = resuming.as_ref().map_or(&addressed, |r| &r.invite);
            link.remember(seats.clone(), under.clone());
        }
        let deadline = Instant::now() + SEATING;
        let mut pending = VecDeque::new();
        let seated = |link: &NetLink<Session>, event: Option<&GameEvent>| match event {
            Some(GameEvent::EndedAway(_)) => Some(None),
            _ => link.session().room().cloned().map(Some),
        };
        let room = match wait_for(&mut link, &mut pending, deadline, seated)? {
            Some(room) => room,
            None => {
                // The remembered game ended while this host was away: a new room.
                pending.clear();
                link.session().enter(create);
                wait_for(&mut link, &mut pending, deadline, |link, _| {
                    link.session().room().cloned()
                })?
            }
        };
        let resumed = resuming.is_some_and(|r| link.session().seating().token == Some(r.token));
        let computer = match options.computer {
            Some(level) => {
                // Each room's computer decides differently, the same way every time.
                let seed = room
                    .as_str()
                    .bytes()
                    .fold(0u64, |h, b| h.rotate_left(8) ^ u64::from(b));
                let invite = server.loopback_invite().with_room(room.clone());
                let computer = SeatedComputer::join(invite, level, seed, true)?;
                // Seated before anyone else is told the invite, so a friend who opens it
                // finds the room full and watches.
                wait_for(&mut link, &mut pending, deadline, |_, event| {
                    (event == Some(&GameEvent::Connection(Connection::Connected))).then_some(())
                })?;
                Some(computer)
            }
            None => None,
        };
        let at = addressed.first();
        let web_link = match &options.web_page {
            // The page comes from the published site; the game from this server's UDP port.
            Some(site) => Some(WebLink {
                page: Some(site.clone()),
                server: Some(at.clone()),
                ..server.web_trust.with_room(room.clone())
            }),
            // The page is served on the same port number, at the address the invite names.
            None => server.web_link().map(|link| WebLink {
                page: Some(WebLink::page_url(&at.host, at.port)),
                ..link.with_room(room.clone())
            }),
        }
        .map(|link| link.to_string());
        Ok(Host {
            link,
            pending,
            web_link,
            invite: addressed.with_room(room),
            resumed,
            data: options.data.clone(),
            computer,
            server,
        })
    }

    /// True when this host went back to its unfinished game rather than opening a room.
    pub fn resumed(&self) -> bool {
        self.resumed
    }

    /// The invite for the other player: `breakshot://HOST:PORT/ROOM#FINGERPRINT`.
    pub fn invite(&self) -> &Invite {
        &self.invite
    }

    /// The link a friend opens in a browser to join, when the web client is served.
    pub fn web_link(&self) -> Option<&str> {
        self.web_link.as_deref()
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

    /// The computer player's level, when it plays the other seat.
    pub fn computer(&self) -> Option<breakshot_shared::ai::Level> {
        self.computer.as_ref().map(|c| c.level())
    }

    /// The link this computer plays through.
    pub fn link(&self) -> &NetLink<Session> {
        &self.link
    }
}

/// Waits on `link` (keeping its events for the screen) until `done` says what was waited
/// for has come, given the link and each event; fails on a refusal, a closed connection or
/// `deadline`.
fn wait_for<T>(
    link: &mut NetLink<Session>,
    pending: &mut VecDeque<GameEvent>,
    deadline: Instant,
    done: impl Fn(&NetLink<Session>, Option<&GameEvent>) -> Option<T>,
) -> Result<T, HostError> {
    loop {
        if let Some(found) = done(link, None) {
            return Ok(found);
        }
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(HostError::Room("the server did not answer in time".into()));
        }
        let Some(event) = link.wait(left) else {
            continue;
        };
        match &event {
            GameEvent::Connection(Connection::Closed(why)) | GameEvent::Refused(why) => {
                return Err(HostError::Room(why.clone()))
            }
            _ => {}
        }
        let found = done(link, Some(&event));
        pending.push_back(event);
        if let Some(found) = found {
            return Ok(found);
        }
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

    fn chats(&self) -> bool {
        self.link.chats()
    }

    fn chat(&mut self, text: String) {
        self.link.chat(text)
    }

    fn aim(&mut self, turn: TurnId, strike: Strike) {
        self.link.aim(turn, strike)
    }

    fn report_desync(&mut self, turn: TurnId, hash: u64) {
        self.link.report_desync(turn, hash)
    }

    fn invite(&self) -> Option<&Invite> {
        Some(&self.invite)
    }

    fn web_link(&self) -> Option<String> {
        self.web_link.clone()
    }
}
