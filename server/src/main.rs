//! `breakshot-server`: serve games, or verify stored ones.

use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use breakshot_server::store::Location;
use breakshot_server::verify::{verify_dir, verify_store};
use breakshot_server::{admin, Config, Limits, Server, DEFAULT_DRAIN_TIMEOUT};
use breakshot_shared::protocol::{ServerAddress, WebLink};
use clap::{Parser, Subcommand};
use tokio::signal::unix::{signal, SignalKind};

#[derive(Parser)]
#[command(
    name = "breakshot-server",
    about = "Breakshot's authoritative game server"
)]
struct Cli {
    /// UDP address to listen on.
    #[arg(long, default_value = "127.0.0.1:4433")]
    bind: SocketAddr,
    /// Directory for the certificate and the game store.
    #[arg(long, default_value = "breakshot-data")]
    data: PathBuf,
    /// Keep the games in this PostgreSQL database (postgres://USER@HOST/DB) instead of
    /// SQLite in the data directory.
    #[arg(long, value_parser = parse_store)]
    store: Option<Location>,
    /// Host name or address players use to reach this server, for the invite (defaults to
    /// the bound address).
    #[arg(long)]
    host: Option<String>,
    /// Another instance's HOST:PORT for the invite, tried after this one (repeatable; the
    /// instances share one --store database and the same certificate and keys).
    #[arg(long, value_name = "HOST:PORT")]
    also: Vec<ServerAddress>,
    /// Connections open at once (including handshakes).
    #[arg(long)]
    max_connections: Option<usize>,
    /// Rooms on the server at once.
    #[arg(long)]
    max_rooms: Option<usize>,
    /// Open rooms one source address may create.
    #[arg(long)]
    rooms_per_address: Option<usize>,
    /// Room entries (create, join, rejoin, spectate) one address may attempt per minute.
    #[arg(long)]
    entries_per_minute: Option<u32>,
    /// Messages queued for a client that does not read before it is disconnected.
    #[arg(long)]
    outbound_queue: Option<usize>,
    /// Lift the per-address limits, for a load test from one machine. Never on a public
    /// server.
    #[arg(long)]
    load_test: bool,
    /// Serve the operator's view over HTTP on this TCP address: /metrics (Prometheus),
    /// /healthz, /readyz and POST /drain. Keep it private (loopback or an internal network).
    #[arg(long, value_name = "ADDR")]
    admin: Option<SocketAddr>,
    /// On SIGTERM or POST /drain, how long to wait for the games in play to end before
    /// stopping anyway (the games stay stored).
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_DRAIN_TIMEOUT.as_secs())]
    drain_timeout: u64,
    /// Serve the web client from this directory, and the game to browsers over a WebSocket,
    /// on TCP at the same address and port number as --bind (docs/web.md).
    #[arg(long, value_name = "DIR")]
    web: Option<PathBuf>,
    /// The address where the same web bundle is published (a static HTTPS site): the link
    /// printed opens that page and names this server with `server=HOST:PORT`, so browsers
    /// reach it over WebTransport (docs/web.md).
    #[arg(long, value_name = "URL", value_parser = WebLink::published_page)]
    web_page: Option<String>,
    /// Write the log as JSON lines (one object per event) instead of text.
    #[arg(long)]
    log_json: bool,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Re-simulate every stored game and check every recorded hash.
    Verify {
        #[arg(long, default_value = "breakshot-data")]
        data: PathBuf,
        /// Verify the games in this PostgreSQL database instead.
        #[arg(long, value_parser = parse_store)]
        store: Option<Location>,
    },
    /// Print the players' Glicko-2 ratings from the store, best first.
    Leaderboard {
        #[arg(long, default_value = "breakshot-data")]
        data: PathBuf,
        /// Read the ratings from this PostgreSQL database instead.
        #[arg(long, value_parser = parse_store)]
        store: Option<Location>,
        /// How many players to print.
        #[arg(long, default_value_t = 20)]
        top: usize,
    },
}

fn parse_store(url: &str) -> Result<Location, String> {
    Location::parse(url).map_err(|e| e.to_string())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Some(Command::Verify { data, store }) => verify(data, store.as_ref()),
        Some(Command::Leaderboard { data, store, top }) => {
            leaderboard(data, store.as_ref(), *top).map(|()| true)
        }
        None => serve(&cli).map(|()| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("breakshot-server: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Prints the leaderboard: rank, rating ± deviation, games, the key's first characters and
/// the name last played under.
fn leaderboard(data: &std::path::Path, store: Option<&Location>, top: usize) -> anyhow::Result<()> {
    let location = store
        .cloned()
        .unwrap_or_else(|| Location::Sqlite(data.to_path_buf()));
    let store = breakshot_server::store::Store::at(&location).context("opening the store")?;
    let ratings = breakshot_server::ratings::Ratings::from_stored(store.ratings()?);
    let mut out = std::io::stdout().lock();
    writeln!(out, "rank  rating   ±dev  games  key       name")?;
    let mut page = 0;
    let mut printed = 0;
    while printed < top {
        let (pages, players) = ratings.leaderboard(page);
        for p in players.iter().take(top - printed) {
            writeln!(
                out,
                "{:>4}  {:>6}  {:>5}  {:>5}  {}  {}",
                p.rank, p.rating, p.deviation, p.games, p.key, p.name
            )?;
            printed += 1;
        }
        page += 1;
        if page >= pages {
            break;
        }
    }
    if printed == 0 {
        writeln!(out, "(no rated games yet)")?;
    }
    Ok(())
}

fn serve(cli: &Cli) -> anyhow::Result<()> {
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info"));
    let log = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr);
    if cli.log_json {
        log.json().init();
    } else {
        log.init();
    }
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    runtime.block_on(async {
        // Listen for Ctrl-C (and SIGTERM from service managers) before announcing the
        // server, so a signal sent right after the invite line still shuts down cleanly.
        let mut interrupt = signal(SignalKind::interrupt()).context("listening for Ctrl-C")?;
        let mut terminate = signal(SignalKind::terminate()).context("listening for SIGTERM")?;
        let mut config = Config::new(cli.bind, cli.data.clone());
        config.limits = limits(cli);
        config.drain_timeout = std::time::Duration::from_secs(cli.drain_timeout);
        config.web_dir = cli.web.clone();
        if let Some(store) = &cli.store {
            config.store = store.clone();
        }
        let server = Server::bind(&config)?;
        let stats = server.stats();
        let admin = match cli.admin {
            Some(addr) => {
                let listener = tokio::net::TcpListener::bind(addr)
                    .await
                    .with_context(|| format!("admin address {addr}"))?;
                let bound = listener.local_addr().context("admin address")?;
                tracing::info!(addr = %bound, "admin: /metrics /healthz /readyz POST /drain");
                Some(tokio::spawn(admin::serve(listener, stats.clone())))
            }
            None => None,
        };
        let mut invite = server.invite();
        if let Some(host) = &cli.host {
            invite = invite.with_host(host);
        }
        invite.servers.extend(cli.also.iter().cloned());
        let mut out = std::io::stdout().lock();
        writeln!(out, "{invite}")?;
        if let Some(site) = &cli.web_page {
            // The page comes from the site; the game from this server's UDP port.
            let mut link = WebLink::new(server.web_key());
            link.cert = server.web_cert_hashes();
            link.page = Some(site.clone());
            link.server = Some(invite.first().clone());
            writeln!(out, "{link}")?;
        } else if let Some(mut link) = server.web_link(None) {
            if let (Some(host), Some(addr)) = (&cli.host, server.web_addr()) {
                link.page = Some(WebLink::page_url(host, addr.port()));
            }
            writeln!(out, "{link}")?;
        }
        out.flush()?;
        drop(out);
        tracing::info!(addr = %server.local_addr(), restored = server.restored(), "serving");
        // Ctrl-C stops at once; SIGTERM (a service manager's stop) drains first, and a
        // second SIGTERM stops at once.
        server
            .run(async {
                tokio::select! {
                    _ = interrupt.recv() => {}
                    _ = async {
                        terminate.recv().await;
                        stats.start_drain();
                        terminate.recv().await;
                    } => {}
                }
            })
            .await?;
        if let Some(admin) = admin {
            admin.abort();
        }
        tracing::info!("stopped");
        Ok(())
    })
}

/// The default limits with the command line's changes.
fn limits(cli: &Cli) -> Limits {
    let mut limits = if cli.load_test {
        Limits::single_address_load()
    } else {
        Limits::default()
    };
    if let Some(n) = cli.max_connections {
        limits.max_connections = n;
    }
    if let Some(n) = cli.max_rooms {
        limits.max_rooms = n;
    }
    if let Some(n) = cli.rooms_per_address {
        limits.rooms_per_address = n;
    }
    if let Some(n) = cli.entries_per_minute {
        limits.entry_burst = n.max(1);
        limits.entry_refill = std::time::Duration::from_secs(60) / n.max(1);
    }
    if let Some(n) = cli.outbound_queue {
        limits.outbound_queue = n.max(1);
    }
    limits
}

fn verify(data: &std::path::Path, store: Option<&Location>) -> anyhow::Result<bool> {
    let checks = match store {
        Some(store) => verify_store(store).context("reading games in the PostgreSQL store")?,
        None => verify_dir(data).with_context(|| format!("reading games in {}", data.display()))?,
    };
    let mut failed = 0;
    for c in &checks {
        let state = if c.finished { "finished" } else { "unfinished" };
        match &c.result {
            Ok(()) => {
                println!(
                    "verified {} game {} ({} commands, {state})",
                    c.room, c.number, c.commands
                );
                if let Some(note) = &c.note {
                    println!("         {note}");
                }
            }
            Err(e) => {
                failed += 1;
                println!(
                    "FAILED   {} game {} ({} commands, {state}): {e}",
                    c.room, c.number, c.commands
                );
            }
        }
    }
    println!(
        "{} games: {} verified, {} failed",
        checks.len(),
        checks.len() - failed,
        failed
    );
    Ok(failed == 0)
}
