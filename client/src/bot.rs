//! The load run: plays whole games between pairs of headless players through a server
//! (each a [`SeatPlayer`](crate::net) with a [`Chooser`]: ghost-ball aim or the computer
//! player at a level), every shot checked against the local prediction, and reports what
//! was measured.

use std::time::{Duration, Instant};

use breakshot_shared::ai::Level;
use breakshot_shared::protocol::{AimAid, ClientMessage, Invite, RoomCode};
use breakshot_shared::rules::{EightBallRules, Settings, TurnId, Variant};
use tokio::sync::oneshot;

pub use crate::net::RETRY_FOR;
use crate::net::{stalled, Entrance, PlayerResult, Progress, SeatPlayer, Seen, Tally};
use crate::play::Chooser;

#[derive(Clone, Debug)]
/// What the bots play, and against which server.
pub struct BotConfig {
    /// The server the bots connect to.
    pub server: Invite,
    /// Games played at once (two bots each).
    pub games: usize,
    /// Seeds the bots' aim and pauses.
    pub seed: u64,
    /// The game the rooms are created for.
    pub variant: Variant,
    /// The room's settings (called shots, shot clock, table).
    pub settings: Settings,
    /// How long a bot keeps trying to take its seat back after a drop.
    pub retry_for: Duration,
    /// Pause before each move, as a player would think (on average; each pause is drawn
    /// between half and one and a half times this).
    pub think: Duration,
    /// How the bot that opens each room and the one that joins it choose their moves: None
    /// for ghost-ball aim, else the computer player at that level.
    pub levels: [Option<Level>; 2],
    /// Games start evenly spread over this time rather than all at once, as players arrive
    /// at a server over time (thousands of handshakes in the same second are a load of
    /// their own).
    pub ramp: Duration,
    /// Each pair meets through quick match instead of a room's code (the server must allow
    /// pairs from one address: `Limits::match_one_address`).
    pub quick_match: bool,
    /// The run stops after this long; the games not finished by then are reported, each
    /// player with what it waits for and its last messages ([`Report::unfinished`]).
    pub timeout: Option<Duration>,
    /// Every this long, the players that have neither received nor sent anything for this
    /// long are printed on standard error (what each waits for, its last messages).
    pub watch: Option<Duration>,
    /// Each bot simulates and checks its first shot and then one in this many, taking the
    /// server's game after the others (1: every shot). A real client is one per machine:
    /// with thousands of bots in one process their simulations would be a load the server's
    /// players never put on its machine.
    pub check_every: u32,
    /// How many bot connections share one QUIC endpoint (one UDP socket and its driver);
    /// 1: an endpoint of each connection's own, as a client has. A real client is one
    /// connection per machine; a load run's thousands of bots on thousands of endpoints
    /// would cost the generator more than the server it measures.
    pub per_endpoint: usize,
}

impl BotConfig {
    /// `games` 8-ball games (WPA rules, no shot clock) on `server`, without pauses.
    pub fn new(server: Invite, games: usize) -> BotConfig {
        BotConfig {
            server,
            games,
            seed: 1,
            variant: Variant::EightBall(EightBallRules::Wpa),
            settings: Settings::offline(),
            retry_for: RETRY_FOR,
            think: Duration::ZERO,
            levels: [None, None],
            ramp: Duration::ZERO,
            quick_match: false,
            timeout: None,
            watch: None,
            check_every: 1,
            per_endpoint: PER_ENDPOINT,
        }
    }
}

/// How many bot connections share one endpoint unless told otherwise.
pub const PER_ENDPOINT: usize = 200;

/// The endpoints a run's bots connect through: a new one for every `per` connections.
struct Endpoints {
    per: usize,
    current: Option<(quinn::Endpoint, usize)>,
    made: usize,
}

impl Endpoints {
    fn new(per: usize) -> Endpoints {
        Endpoints {
            per,
            current: None,
            made: 0,
        }
    }

    /// The endpoint for the next connection: None for one of its own (`per` of 1, or a
    /// shared one could not be made, which its own will then report).
    fn next(&mut self) -> Option<quinn::Endpoint> {
        if self.per <= 1 {
            return None;
        }
        if let Some((endpoint, used)) = &mut self.current {
            if *used < self.per {
                *used += 1;
                return Some(endpoint.clone());
            }
        }
        match crate::net::shared_endpoint() {
            Ok(endpoint) => {
                self.made += 1;
                self.current = Some((endpoint.clone(), 1));
                Some(endpoint)
            }
            Err(e) => {
                tracing::warn!(error = %e, "cannot open a shared endpoint");
                self.current = None;
                None
            }
        }
    }
}

impl BotConfig {
    /// The settings a room is created with: these settings, on the table the game is
    /// played on (three-cushion's carom table, snooker's snooker table).
    fn room_settings(&self) -> Settings {
        Settings {
            table: self.variant.table(self.settings.table),
            ..self.settings
        }
    }
}

/// One game as the bots saw it.
#[derive(Clone, Debug, Default)]
pub struct GameSummary {
    /// The room the game was played in.
    pub room: Option<RoomCode>,
    /// Both bots saw the game end.
    pub completed: bool,
    /// Why the game ended, as the host saw it.
    pub reason: String,
    /// Every shot result the host saw: (turn, server hash).
    pub resolved: Vec<(TurnId, u64)>,
    /// Commands the server refused, of the bot that opened the room and of the one that
    /// joined it.
    pub refused: [u32; 2],
    /// When the game was in play, as the bot that opened the room saw it: from both seats
    /// taken to the end (None for a game that never started or never ended).
    pub played: Option<(Instant, Instant)>,
}

/// What a run of bots measured.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Games both bots saw to the end.
    pub games_completed: u32,
    /// The shots of every bot, added up (each player counts the shots it confirmed).
    pub tally: Tally,
    /// Each game, as the bots saw it.
    pub games: Vec<GameSummary>,
    /// What went wrong, one line per bot that failed.
    pub errors: Vec<String>,
    /// The players of the games not finished when the run's time-out came, one line each:
    /// what it waited for (or how it ended), and its last messages either way.
    pub unfinished: Vec<String>,
    /// The shared endpoints the bots connected through (0: each connection had its own).
    pub endpoints: usize,
}

impl Report {
    /// The `q` quantile (0..=1) of the shot round trips, in milliseconds (nearest rank).
    pub fn percentile_ms(&self, q: f64) -> f64 {
        quantile(&self.tally.times.round_trip, q)
    }

    /// The stages of a shot as the bots saw them, each as (name, p50, p99) in ms: the way to
    /// the server's acceptance, the whole round trip, the result's wait in the bot's own
    /// process once read off the connection, the bots' own replicas, and the shot's wait in
    /// the bot's own process before it was written on the connection.
    pub fn stages_ms(&self) -> [(&'static str, f64, f64); 5] {
        let stage = |name, v: &[f64]| (name, quantile(v, 0.5), quantile(v, 0.99));
        [
            stage("accepted", &self.tally.times.accepted),
            stage("round trip", &self.tally.times.round_trip),
            stage("received", &self.tally.times.received),
            stage("replica", &self.tally.times.replica),
            stage("sent", &self.tally.times.sent),
        ]
    }

    /// The most games in play at the same moment.
    pub fn peak_games(&self) -> usize {
        let mut changes: Vec<(Instant, i32)> = self
            .games
            .iter()
            .filter_map(|g| g.played)
            .flat_map(|(from, to)| [(from, 1), (to, -1)])
            .collect();
        // An end and a start at the same instant: the end first.
        changes.sort();
        let mut now = 0i32;
        let mut peak = 0;
        for (_, change) in changes {
            now += change;
            peak = peak.max(now);
        }
        peak as usize
    }

    /// The report's figures as one JSON object (games completed, peak games, shots,
    /// desyncs, the round trips' p50 and p99 as `p50_ms` and `p99_ms`, the other stages' as
    /// `accepted_p50_ms` and so on), for `breakshot-bot --json` to add its own to.
    pub fn json(&self) -> serde_json::Value {
        let mut json = serde_json::json!({
            "games_completed": self.games_completed,
            "peak_games": self.peak_games(),
            "shots": self.tally.shots,
            "confirmed": self.tally.confirmed,
            "unchecked": self.tally.unchecked,
            "desyncs": self.tally.desyncs,
            "endpoints": self.endpoints,
        });
        for (stage, p50, p99) in self.stages_ms() {
            let prefix = match stage {
                "round trip" => String::new(),
                other => format!("{other}_"),
            };
            json[format!("{prefix}p50_ms")] = round3(p50).into();
            json[format!("{prefix}p99_ms")] = round3(p99).into();
        }
        json
    }

    fn add(&mut self, p: PlayerResult) {
        self.tally.add(p.tally);
        if let Some(e) = p.error {
            self.errors.push(e);
        }
    }
}

/// The processor time this process has used so far, all its threads, user and system: what
/// a load run costs the machine it runs on. `None` where the system does not say (read from
/// `/proc/self/stat` on Linux, whose ticks are 1/100 s for every process).
pub fn process_cpu() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command's name, which is in parentheses and may hold spaces:
    // the state first, then the user and system times as the 12th and 13th.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k)?.parse::<u64>().ok();
    const TICKS_PER_SECOND: u64 = 100;
    Some(Duration::from_millis(
        (ticks(11)? + ticks(12)?) * 1000 / TICKS_PER_SECOND,
    ))
}

/// The `q` quantile (0..=1) of `values` (nearest rank); 0 for none.
fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = (q * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Plays `config.games` games at once (two connections each) and reports.
pub async fn run(config: &BotConfig) -> Report {
    let started = Instant::now();
    let deadline = config.timeout.map(|t| tokio::time::Instant::now() + t);
    let mut tasks = Vec::new();
    let mut watched = Vec::new();
    let mut endpoints = Endpoints::new(config.per_endpoint);
    for g in 0..config.games {
        let config = config.clone();
        let start = config.ramp.mul_f64(g as f64 / config.games as f64);
        let (host, guest) = players(&config, g as u64);
        let (host, guest) = (
            host.on_endpoint(endpoints.next()),
            guest.on_endpoint(endpoints.next()),
        );
        let progress = [host.progress(), guest.progress()];
        for p in &progress {
            p.begins_at(started + start);
        }
        watched.push(progress.clone());
        tasks.push(tokio::spawn(async move {
            tokio::time::sleep(start).await;
            play_game(&config, host, guest).await
        }));
    }
    let watcher = config.watch.map(|every| {
        let watched = watched.clone();
        tokio::spawn(async move {
            loop {
                tokio::time::sleep(every).await;
                let seen: Vec<Seen> = watched.iter().flatten().map(Progress::seen).collect();
                eprint!("{}", stall_report(&seen, Instant::now(), every, started));
            }
        })
    });
    let mut report = Report {
        endpoints: endpoints.made,
        ..Report::default()
    };
    drop(endpoints);
    for (g, mut t) in tasks.into_iter().enumerate() {
        let joined = match deadline {
            Some(at) => match tokio::time::timeout_at(at, &mut t).await {
                Ok(joined) => joined,
                Err(_) => {
                    t.abort();
                    let now = Instant::now();
                    // Both players: the one still waiting, and how its opponent ended.
                    report.unfinished.extend(
                        watched[g]
                            .iter()
                            .map(|p| format!("game {g}: {}", p.seen().line(now))),
                    );
                    report.games.push(GameSummary::default());
                    continue;
                }
            },
            None => t.await,
        };
        match joined {
            Ok((summary, host, guest)) => {
                report.add(host);
                report.add(guest);
                if summary.completed {
                    report.games_completed += 1;
                }
                report.games.push(summary);
            }
            Err(e) => report.errors.push(e.to_string()),
        }
    }
    if let Some(w) = watcher {
        w.abort();
    }
    report
}

/// What a watcher prints every `quiet`: the time since the run `started`, how many players
/// are done, and the players quiet for at least `quiet` (counted by what they wait for, the
/// longest quiet [`STALLED_SHOWN`] one line each). Nothing when no player is quiet.
pub fn stall_report(seen: &[Seen], now: Instant, quiet: Duration, started: Instant) -> String {
    let (quiet_ones, kinds) = stalled(seen, now, quiet);
    if quiet_ones.is_empty() {
        return String::new();
    }
    let done = seen
        .iter()
        .filter(|s| s.waiting == crate::net::Waiting::Done)
        .count();
    let kinds: Vec<String> = kinds.iter().map(|(k, n)| format!("{n} {k}")).collect();
    let mut out = format!(
        "at {:.0} s: {done} of {} players done; {} quiet for {:.0} s or more, waiting for: {}\n",
        now.saturating_duration_since(started).as_secs_f64(),
        seen.len(),
        quiet_ones.len(),
        quiet.as_secs_f64(),
        kinds.join(", "),
    );
    for s in quiet_ones.iter().take(STALLED_SHOWN) {
        out += &format!("  {}\n", s.line(now));
    }
    out
}

/// How many quiet players a watcher's report names, the longest quiet first.
pub const STALLED_SHOWN: usize = 20;

/// Opens one room as the bot that opens rooms (`config.levels[0]`), tells `opened` its code,
/// and plays one game against whoever joins it: a person at a window, a page. The report is
/// this bot's side only (`games_completed` is 1 when it saw the game end).
pub async fn open_room(config: &BotConfig, opened: oneshot::Sender<RoomCode>) -> Report {
    let host = player(config, 0, "Bot".to_owned(), config.seed);
    let create = ClientMessage::CreateRoom {
        variant: config.variant,
        mode: config.room_settings(),
        aim_aid: AimAid::Full,
        name: host.name().to_owned(),
    };
    let result = host.play(Entrance::Create(create, opened)).await;
    let mut report = Report::default();
    if let Some(e) = &result.error {
        report.errors.push(e.clone());
    }
    if result.over.is_some() {
        report.games_completed = 1;
    }
    report.games.push(GameSummary {
        room: result.room.clone(),
        completed: result.over.is_some(),
        reason: result.over.clone().unwrap_or_default(),
        resolved: result.resolved.clone(),
        refused: [result.refused, 0],
        played: result.began.zip(result.ended),
    });
    report.add(result);
    report
}

/// The two players of game `g`: the one that opens the room, and the one that joins it.
fn players(config: &BotConfig, g: u64) -> (SeatPlayer, SeatPlayer) {
    (
        player(config, 0, format!("bot{g}a"), config.seed ^ (g * 2 + 1)),
        player(config, 1, format!("bot{g}b"), config.seed ^ (g * 2 + 2)),
    )
}

async fn play_game(
    config: &BotConfig,
    host: SeatPlayer,
    guest: SeatPlayer,
) -> (GameSummary, PlayerResult, PlayerResult) {
    let (room_tx, room_rx) = oneshot::channel();
    let create = ClientMessage::CreateRoom {
        variant: config.variant,
        mode: config.room_settings(),
        aim_aid: AimAid::Full,
        name: host.name().to_owned(),
    };
    let host_progress = host.progress();
    let (host_task, guest_task) = if config.quick_match {
        // No invite to a room: both wait in the queue and are paired by the server.
        let queue = |name: &str| {
            Entrance::QuickMatch(ClientMessage::QuickMatch {
                variant: config.variant,
                mode: config.settings,
                name: name.to_owned(),
            })
        };
        let (h, g) = (queue(host.name()), queue(guest.name()));
        drop((room_tx, room_rx));
        (tokio::spawn(host.play(h)), tokio::spawn(guest.play(g)))
    } else {
        (
            tokio::spawn(host.play(Entrance::Create(create, room_tx))),
            tokio::spawn(guest.play(Entrance::Join(room_rx))),
        )
    };
    let guest = guest_task
        .await
        .unwrap_or_else(|e| PlayerResult::failed(e.to_string()));
    // A room waits for its second player as long as its first stays: when the bot meant to
    // join it never took its seat (it could not connect, or was refused), the one that
    // opened it would wait for ever, and the run with it. (Quick match pairs whoever waits,
    // and its queue gives up by itself.)
    if !config.quick_match && guest.room.is_none() && !host_task.is_finished() {
        host_task.abort();
    }
    let host = match host_task.await {
        Ok(host) => host,
        Err(e) if e.is_cancelled() => {
            let why = format!(
                "the opponent never took its seat ({})",
                guest.error.as_deref().unwrap_or("it left")
            );
            host_progress.ended(why.clone());
            PlayerResult::failed(why)
        }
        Err(e) => PlayerResult::failed(e.to_string()),
    };
    let summary = GameSummary {
        room: host.room.clone(),
        completed: host.over.is_some() && guest.over.is_some(),
        reason: host.over.clone().unwrap_or_default(),
        resolved: host.resolved.clone(),
        refused: [host.refused, guest.refused],
        played: host.began.zip(host.ended),
    };
    (summary, host, guest)
}

/// The player `k` of a game (0 opens the room, 1 joins it) as `config` says.
fn player(config: &BotConfig, k: usize, name: String, seed: u64) -> SeatPlayer {
    let chooser = match config.levels[k] {
        Some(level) => Chooser::computer(level, seed),
        None => Chooser::new(seed),
    };
    SeatPlayer::seated(config.server.clone(), name, chooser, config.retry_for)
        .thinking(config.think, !seed)
        .checking_every(config.check_every)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peak_counts_games_in_play_at_one_moment() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let game = |played| GameSummary {
            played,
            ..GameSummary::default()
        };
        let report = Report {
            games: vec![
                game(Some((at(0), at(10)))),
                game(Some((at(5), at(15)))),
                // Starts as the first ends: never three at once.
                game(Some((at(10), at(20)))),
                game(Some((at(12), at(13)))),
                game(None),
            ],
            ..Report::default()
        };
        assert_eq!(report.peak_games(), 3);
        assert_eq!(Report::default().peak_games(), 0);
    }

    #[test]
    fn each_stage_is_reported_by_its_nearest_rank_quantiles() {
        let mut report = Report::default();
        report.tally.times.round_trip = (1..=100).map(f64::from).collect();
        report.tally.times.accepted = vec![3.0, 1.0, 2.0];
        report.tally.times.received = vec![0.5];
        report.tally.times.sent = vec![0.25, 4.0];
        let [accepted, round_trip, received, replica, sent] = report.stages_ms();
        assert_eq!(received, ("received", 0.5, 0.5));
        assert_eq!(sent, ("sent", 0.25, 4.0));
        assert_eq!(accepted, ("accepted", 2.0, 3.0));
        assert_eq!(round_trip, ("round trip", 50.0, 99.0));
        // No shot seen: nothing to rank.
        assert_eq!(replica, ("replica", 0.0, 0.0));
        let json = report.json();
        assert_eq!(json["accepted_p99_ms"], 3.0);
        assert_eq!(json["p50_ms"], 50.0);
        assert_eq!(json["replica_p50_ms"], 0.0);
        assert_eq!(json["sent_p99_ms"], 4.0);
    }

    #[test]
    fn a_watcher_names_the_quiet_players_and_counts_them_by_what_they_wait_for() {
        use crate::net::Waiting;
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let player = |name: &str, waiting| {
            let mut seen = Seen::new(name.into(), t0);
            seen.waiting = waiting;
            seen
        };
        let mut busy = player("bot1a", Waiting::OpponentMove { turn: 3 });
        busy.received = Some((at(55), "TurnChanged turn 3 to B".into()));
        let mut seen = vec![
            player("bot0a", Waiting::Opponent),
            player("bot0b", Waiting::Done),
            busy,
            player("bot1b", Waiting::Opponent),
        ];
        let report = stall_report(&seen, at(60), Duration::from_secs(30), t0);
        let lines: Vec<&str> = report.lines().collect();
        assert_eq!(
            lines[0],
            "at 60 s: 1 of 4 players done; 2 quiet for 30 s or more, waiting for: 2 an opponent"
        );
        assert_eq!(lines.len(), 3);
        assert!(lines[1].starts_with("  bot0a room - seat -: waits for an opponent; quiet 60.0 s"));
        assert!(lines[2].starts_with("  bot1b "));
        // Nothing quiet: nothing to say.
        seen.retain(|s| s.player == "bot1a");
        assert_eq!(stall_report(&seen, at(60), Duration::from_secs(30), t0), "");
    }

    #[test]
    fn connections_share_an_endpoint_as_configured() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        runtime.block_on(async {
            let sockets = |per: usize, connections: usize| {
                let mut endpoints = Endpoints::new(per);
                let addrs: Vec<_> = (0..connections)
                    .map(|_| endpoints.next().map(|e| e.local_addr().expect("bound")))
                    .collect();
                (addrs, endpoints.made)
            };
            // Three to an endpoint: seven connections on three sockets, in turn.
            let (addrs, made) = sockets(3, 7);
            assert_eq!(made, 3);
            let addrs: Vec<_> = addrs.into_iter().map(|a| a.expect("shared")).collect();
            assert!(addrs[..3].iter().all(|a| *a == addrs[0]));
            assert!(addrs[3..6].iter().all(|a| *a == addrs[3]));
            assert_ne!(addrs[0], addrs[3]);
            assert_ne!(addrs[3], addrs[6]);
            assert_ne!(addrs[0], addrs[6]);
            // One to an endpoint: each connection makes its own, as a client does.
            assert_eq!(sockets(1, 4), (vec![None; 4], 0));
        });
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn the_process_s_processor_time_grows_with_the_work_done() {
        let before = process_cpu().expect("Linux says a process's processor time");
        // Busy for about half a second of processor time (a tick is 10 ms).
        let start = Instant::now();
        let mut x = 0u64;
        while start.elapsed() < Duration::from_millis(500) {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
        }
        let spent = process_cpu().expect("still") - before;
        assert!(
            spent >= Duration::from_millis(100) && spent <= start.elapsed() * 4,
            "{spent:?} for {:?} of busy work",
            start.elapsed()
        );
    }
}
