//! `breakshot-bot --server URL --games N [--level L [--vs-ghost]] [--json]`: plays N complete
//! games against a server (two bot connections per game) and reports shots, desyncs and shot
//! round trips. The bots aim ghost-ball pots, or play as the computer player at level L.
//! With `--open-room` one bot opens a room, prints `room CODE` and plays whoever joins it.

use std::process::ExitCode;

use anyhow::Context;
use breakshot_client::bot::{open_room, process_cpu, run, BotConfig, PER_ENDPOINT};
use breakshot_shared::ai::Level;
use breakshot_shared::protocol::Invite;
use clap::Parser;

#[derive(Parser)]
#[command(
    name = "breakshot-bot",
    about = "Play complete games against a Breakshot server"
)]
struct Cli {
    /// The server's invite: breakshot://HOST:PORT#FINGERPRINT
    #[arg(long)]
    server: String,
    /// Games to play at once.
    #[arg(long, default_value_t = 1)]
    games: usize,
    /// Seed for the bots' aim noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Pause before each move (milliseconds), as a player would think.
    #[arg(long, default_value_t = 0)]
    think_ms: u64,
    /// Start the games evenly spread over this many milliseconds instead of all at once.
    #[arg(long, default_value_t = 0)]
    ramp_ms: u64,
    /// The bots play as the computer player at this level (1 to 5) instead of aiming
    /// ghost-ball pots.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=5))]
    level: Option<u8>,
    /// With --level: the bot that joins each room aims ghost-ball pots, so each game is the
    /// computer player against the ghost-ball bot.
    #[arg(long, requires = "level")]
    vs_ghost: bool,
    /// Open one room, print `room CODE` on a line of its own, and play one game against
    /// whoever joins it (a person, a page) instead of playing --games games bot against bot.
    #[arg(long, conflicts_with_all = ["games", "vs_ghost", "ramp_ms"])]
    open_room: bool,
    /// Stop after this many seconds; each player of a game not finished by then is printed
    /// on standard error with what it waits for and its last messages either way.
    #[arg(long)]
    timeout_s: Option<u64>,
    /// Every this many seconds, print on standard error the players that have neither
    /// received nor sent anything for that long (counted by what they wait for, the longest
    /// quiet named).
    #[arg(long)]
    watch_s: Option<u64>,
    /// Each bot simulates and checks its first shot and then one in N, and takes the
    /// server's game after the others (a real client is one per machine: thousands of bots
    /// simulating every shot would load this machine as no real players do).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    check_every: u32,
    /// How many bot connections share one QUIC endpoint (one UDP socket and its driver
    /// task); 1 gives each connection an endpoint of its own, as a client has. Thousands of
    /// endpoints cost the load generator more processor time and memory than the server
    /// it measures.
    #[arg(long, default_value_t = PER_ENDPOINT as u32, value_parser = clap::value_parser!(u32).range(1..))]
    per_endpoint: u32,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    match main_inner() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("breakshot-bot: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn main_inner() -> anyhow::Result<bool> {
    let cli = Cli::parse();
    let invite: Invite = cli.server.parse().context("--server")?;
    let mut config = BotConfig::new(invite, cli.games);
    config.seed = cli.seed;
    config.check_every = cli.check_every;
    config.per_endpoint = cli.per_endpoint as usize;
    config.think = std::time::Duration::from_millis(cli.think_ms);
    config.ramp = std::time::Duration::from_millis(cli.ramp_ms);
    config.timeout = cli.timeout_s.map(std::time::Duration::from_secs);
    config.watch = cli
        .watch_s
        .filter(|s| *s > 0)
        .map(std::time::Duration::from_secs);
    let level = cli.level.map(Level::new);
    config.levels = [level, level.filter(|_| !cli.vs_ghost)];
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    // What the bots cost: a real client is one per machine, so a load run's own processor
    // time says how much of its round trips may be the bots' rather than the server's.
    let (cpu_before, started) = (process_cpu(), std::time::Instant::now());
    let report = if cli.open_room {
        config.games = 1;
        runtime.block_on(async {
            let (opened, code) = tokio::sync::oneshot::channel();
            let printer = tokio::spawn(async move {
                if let Ok(room) = code.await {
                    use std::io::Write as _;
                    println!("room {room}");
                    let _ = std::io::stdout().flush();
                }
            });
            let report = open_room(&config, opened).await;
            let _ = printer.await;
            report
        })
    } else {
        runtime.block_on(run(&config))
    };
    let wall = started.elapsed().as_secs_f64();
    let cpu = process_cpu()
        .zip(cpu_before)
        .map(|(after, before)| (after - before).as_secs_f64());
    for e in &report.errors {
        eprintln!("breakshot-bot: {e}");
    }
    if !report.unfinished.is_empty() {
        eprintln!(
            "breakshot-bot: games not finished within the time-out ({}), both players of each:",
            report.unfinished.len() / 2
        );
        for line in &report.unfinished {
            eprintln!("  {line}");
        }
    }
    if cli.json {
        let mut json = report.json();
        json["wall_s"] = serde_json::json!(wall);
        json["cpu_s"] = serde_json::json!(cpu);
        json["unfinished_games"] = serde_json::json!(report.unfinished.len() / 2);
        println!("{json}");
    } else {
        println!(
            "games completed: {} of {}",
            report.games_completed, config.games
        );
        println!("peak games:      {}", report.peak_games());
        println!("shots:           {}", report.tally.shots);
        // Both players of a game see each shot: a check is one player's.
        println!(
            "checks:          {} confirmed, {} taken unchecked (--check-every)",
            report.tally.confirmed, report.tally.unchecked
        );
        println!("desyncs:         {}", report.tally.desyncs);
        println!("rejoins:         {}", report.tally.rejoins);
        match report.endpoints {
            0 => println!("endpoints:       one per connection (--per-endpoint 1)"),
            n => println!(
                "endpoints:       {n} shared (--per-endpoint {})",
                config.per_endpoint
            ),
        }
        for (stage, p50, p99) in report.stages_ms() {
            println!("shot {stage:<11} p50 {p50:.2} ms, p99 {p99:.2} ms");
        }
        match cpu {
            Some(cpu) => println!(
                "bot process CPU: {cpu:.1} s in {wall:.1} s ({:.0} % of one core)",
                100.0 * cpu / wall.max(1e-9)
            ),
            None => println!("bot process CPU: not measured on this system"),
        }
    }
    Ok(report.games_completed as usize == config.games && report.tally.desyncs == 0)
}
