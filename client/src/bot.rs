//! A headless player for load tests and integration tests: plays whole games against
//! another bot through a server, choosing its moves with ghost-ball aim at a pocket (with
//! some randomness) or as the computer player at a level, checks every shot against its
//! local prediction, and rejoins with its seat token when the server goes away.

use std::time::{Duration, Instant};

use breakshot_shared::ai::{self, Level, Rng};
use breakshot_shared::protocol::{
    AimAid, ClientMessage, ErrorCode, Invite, Role, RoomCode, ServerMessage,
};
use breakshot_shared::rules::{EightBallRules, Game, Phase, Seat, Settings, TurnId, Variant};
use tokio::sync::oneshot;

use crate::net::{command_message, Client, ClientEvent, NetError, Reconnect};
use crate::play::Replica;

/// How long a bot keeps trying to reach a server that went away.
pub const RETRY_FOR: Duration = Duration::from_secs(120);
/// A bot refused this many times in a row concedes (its aim logic is stuck).
const MAX_REFUSALS: u32 = 30;
/// A bot that has shot this many times in one game concedes (keeps tests bounded).
const MAX_SHOTS: u32 = 300;

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

#[derive(Clone, Debug, Default)]
/// What a run of bots measured.
pub struct Report {
    /// Games both bots saw to the end.
    pub games_completed: u32,
    /// Shots the bots took.
    pub shots: u32,
    /// Shots whose local prediction matched the server's hash (counted by each player).
    pub confirmed: u32,
    /// Shots (or commands) whose local result differed from the server's.
    pub desyncs: u32,
    /// Times a bot took its seat back after a drop.
    pub rejoins: u32,
    /// Each shot's round trip, from sending it to its result (ms).
    pub round_trips_ms: Vec<f64>,
    /// Each game, as the bots saw it.
    pub games: Vec<GameSummary>,
    /// What went wrong, one line per bot that failed.
    pub errors: Vec<String>,
}

impl Report {
    /// The `q` quantile (0..=1) of the shot round trips, in milliseconds (nearest rank).
    pub fn percentile_ms(&self, q: f64) -> f64 {
        let mut v = self.round_trips_ms.clone();
        if v.is_empty() {
            return 0.0;
        }
        v.sort_by(f64::total_cmp);
        let rank = (q * v.len() as f64).ceil() as usize;
        v[rank.clamp(1, v.len()) - 1]
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

    /// The report as one JSON object with exactly the documented keys.
    pub fn to_json(&self) -> String {
        serde_json::json!({
            "games_completed": self.games_completed,
            "peak_games": self.peak_games(),
            "shots": self.shots,
            "desyncs": self.desyncs,
            "p50_ms": round3(self.percentile_ms(0.5)),
            "p99_ms": round3(self.percentile_ms(0.99)),
        })
        .to_string()
    }

    fn add(&mut self, p: PlayerResult) {
        self.shots += p.shots;
        self.confirmed += p.confirmed;
        self.desyncs += p.desyncs;
        self.rejoins += p.rejoins;
        self.round_trips_ms.extend(p.round_trips_ms);
        if let Some(e) = p.error {
            self.errors.push(e);
        }
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Plays `config.games` games at once (two connections each) and reports.
pub async fn run(config: &BotConfig) -> Report {
    let mut tasks = Vec::new();
    for g in 0..config.games {
        let config = config.clone();
        let start = config.ramp.mul_f64(g as f64 / config.games as f64);
        tasks.push(tokio::spawn(async move {
            tokio::time::sleep(start).await;
            play_game(&config, g as u64).await
        }));
    }
    let mut report = Report::default();
    for t in tasks {
        match t.await {
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
    report
}

async fn play_game(config: &BotConfig, g: u64) -> (GameSummary, PlayerResult, PlayerResult) {
    let (room_tx, room_rx) = oneshot::channel();
    let host = Bot::new(config, 0, format!("bot{g}a"), config.seed ^ (g * 2 + 1));
    let guest = Bot::new(config, 1, format!("bot{g}b"), config.seed ^ (g * 2 + 2));
    let create = ClientMessage::CreateRoom {
        variant: config.variant,
        mode: config.settings,
        aim_aid: AimAid::Full,
        name: host.name.clone(),
    };
    let host_task = tokio::spawn(host.play(Start::Create(create, room_tx)));
    let guest_task = tokio::spawn(guest.play(Start::Join(room_rx)));
    let host = host_task
        .await
        .unwrap_or_else(|e| PlayerResult::failed(e.to_string()));
    let guest = guest_task
        .await
        .unwrap_or_else(|e| PlayerResult::failed(e.to_string()));
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

/// How a bot enters its room.
pub(crate) enum Start {
    /// Opens it, and tells the other bot its code.
    Create(ClientMessage, oneshot::Sender<RoomCode>),
    /// Joins the room whose code arrives.
    Join(oneshot::Receiver<RoomCode>),
}

/// What one bot saw and did.
#[derive(Debug, Default)]
pub(crate) struct PlayerResult {
    room: Option<RoomCode>,
    /// When both seats were taken, and when the game ended.
    began: Option<Instant>,
    ended: Option<Instant>,
    over: Option<String>,
    shots: u32,
    confirmed: u32,
    desyncs: u32,
    rejoins: u32,
    round_trips_ms: Vec<f64>,
    resolved: Vec<(TurnId, u64)>,
    /// Commands the server refused.
    refused: u32,
    pub(crate) error: Option<String>,
}

impl PlayerResult {
    fn failed(e: String) -> PlayerResult {
        PlayerResult {
            error: Some(e),
            ..PlayerResult::default()
        }
    }
}

/// One player's connection and its copy of the game.
pub(crate) struct Bot {
    server: Invite,
    name: String,
    chooser: Chooser,
    policy: Reconnect,
    think: Duration,
    pause_rng: Rng,
    replica: Replica,
    seat: Option<Seat>,
    result: PlayerResult,
    /// The turn this bot last answered, while its answer is pending.
    acted: Option<TurnId>,
    sent_shot: Option<(TurnId, Instant)>,
    refusals: u32,
    /// Shots taken in the game being played.
    game_shots: u32,
    /// Plays on after a game ends: asks for a rematch and plays it (a seat kept in a room
    /// rather than one game).
    stays: bool,
    /// Moves only once the last shot has finished playing on the players' screens, and
    /// [`LOOK`] later, as a player at the table would: a move that arrived sooner would cut
    /// the shot's animation short. None: moves as soon as it has chosen.
    paced: Option<Instant>,
    /// Whether this bot paces its moves.
    pacing: bool,
}

/// How long a pacing bot looks at the table after the balls stop, before its move.
pub const LOOK: Duration = Duration::from_millis(800);

impl Bot {
    /// The bot `k` of a game (0 opens the room, 1 joins it) as `config` says.
    fn new(config: &BotConfig, k: usize, name: String, seed: u64) -> Bot {
        let chooser = match config.levels[k] {
            Some(level) => Chooser::computer(level, seed),
            None => Chooser::new(seed),
        };
        let mut bot = Bot::seated(config.server.clone(), name, chooser, config.retry_for);
        bot.think = config.think;
        bot.pause_rng = Rng::new(!seed);
        bot
    }

    /// A bot that plays in `server`'s rooms with `chooser`, without pauses, keeping its seat
    /// through drops for `retry_for`.
    pub(crate) fn seated(
        server: Invite,
        name: String,
        chooser: Chooser,
        retry_for: Duration,
    ) -> Bot {
        Bot {
            server,
            name,
            chooser,
            policy: Reconnect {
                rejoin_for: retry_for,
                ..Reconnect::default()
            },
            think: Duration::ZERO,
            pause_rng: Rng::new(0),
            replica: Replica::default(),
            seat: None,
            result: PlayerResult::default(),
            acted: None,
            sent_shot: None,
            refusals: 0,
            game_shots: 0,
            stays: false,
            paced: None,
            pacing: false,
        }
    }

    /// The bot moves only when the last shot has finished playing for the players (and
    /// [`LOOK`] more).
    pub(crate) fn pacing(mut self) -> Bot {
        self.pacing = true;
        self
    }

    /// The bot plays on after each game: asks for a rematch and plays it, until dropped.
    pub(crate) fn staying(mut self) -> Bot {
        self.stays = true;
        self
    }

    /// Enters the room as `start` says and plays until the game ends (or, for a bot that
    /// stays, until the connection is lost for good).
    pub(crate) async fn play(mut self, start: Start) -> PlayerResult {
        let (first, mut room_tx) = match start {
            Start::Create(msg, tx) => (msg, Some(tx)),
            Start::Join(rx) => match rx.await {
                Ok(room) => (
                    ClientMessage::Join {
                        room,
                        name: self.name.clone(),
                    },
                    None,
                ),
                Err(_) => return PlayerResult::failed("the host never created a room".into()),
            },
        };
        let mut client = match Client::connect(self.server.clone(), self.policy).await {
            Ok(c) => c,
            Err(e) => return PlayerResult::failed(e.to_string()),
        };
        if let Err(e) = self.run(&mut client, &first, &mut room_tx).await {
            self.result.error = Some(e.to_string());
        }
        client.close(Duration::ZERO).await;
        self.result.confirmed = self.replica.confirmed();
        self.result.desyncs = self.replica.desyncs();
        self.result
    }

    /// Plays until the game ends (`Ok`) or the connection is lost for good.
    async fn run(
        &mut self,
        client: &mut Client,
        first: &ClientMessage,
        room_tx: &mut Option<oneshot::Sender<RoomCode>>,
    ) -> Result<(), NetError> {
        client.send(first).await?;
        loop {
            let msg = match client.recv().await? {
                ClientEvent::Message(msg) => msg,
                ClientEvent::Reconnecting(why) => {
                    tracing::debug!(bot = %self.name, %why, "reconnecting");
                    continue;
                }
                ClientEvent::Reconnected => {
                    self.result.rejoins += 1;
                    self.acted = None;
                    self.sent_shot = None;
                    continue;
                }
            };
            if let ServerMessage::Joined { role, .. } = &msg {
                self.seat = match role {
                    Role::Player(seat) => Some(*seat),
                    Role::Spectator => None,
                };
            }
            self.replica.observe(&msg, self.seat);
            match &msg {
                ServerMessage::Joined { snapshot, .. } => {
                    self.result.room = Some(snapshot.room.clone());
                    if let Some(tx) = room_tx.take() {
                        let _ = tx.send(snapshot.room.clone());
                    }
                    self.game_shots = 0;
                    if let Phase::Over { reason, .. } = snapshot.game.phase() {
                        self.result.over = Some(reason.clone());
                        self.result.ended.get_or_insert_with(Instant::now);
                        if !self.stays {
                            return Ok(());
                        }
                        client.send(&ClientMessage::Rematch).await?;
                    }
                }
                ServerMessage::ShotAccepted { seat, .. } => {
                    if Some(*seat) == self.seat {
                        self.result.shots += 1;
                        self.game_shots += 1;
                    }
                    if self.pacing {
                        let shown = self
                            .replica
                            .playback()
                            .map_or(0.0, |p| p.outcome().duration);
                        let shown = Duration::try_from_secs_f64(shown).unwrap_or_default();
                        self.paced = Some(Instant::now() + shown + LOOK);
                    }
                }
                ServerMessage::PlayerJoined { .. } => {
                    self.result.began.get_or_insert_with(Instant::now);
                }
                ServerMessage::GameStarted { .. } => {
                    self.acted = None;
                    self.game_shots = 0;
                }
                ServerMessage::ShotResolved { turn, hash, .. } => {
                    self.result.resolved.push((*turn, *hash));
                    if let Some((t, at)) = self.sent_shot {
                        if t == *turn {
                            self.result
                                .round_trips_ms
                                .push(at.elapsed().as_secs_f64() * 1000.0);
                            self.sent_shot = None;
                        }
                    }
                }
                ServerMessage::GameOver { reason, .. } if self.stays => {
                    self.result.over = Some(reason.clone());
                    self.result.ended.get_or_insert_with(Instant::now);
                    client.send(&ClientMessage::Rematch).await?;
                }
                ServerMessage::GameOver { reason, .. }
                | ServerMessage::GameFinished { reason, .. } => {
                    // `GameFinished`: the game ended while this bot was away.
                    self.result.over = Some(reason.clone());
                    self.result.ended.get_or_insert_with(Instant::now);
                    return Ok(());
                }
                ServerMessage::Error {
                    code: ErrorCode::BadToken,
                    message,
                } => {
                    // The seat is gone (a server that no longer knows the game): waiting
                    // would wait forever.
                    self.result.error = Some(format!("rejoin refused: {message}"));
                    return Ok(());
                }
                ServerMessage::Error {
                    code: ErrorCode::RoomFull | ErrorCode::NoSuchRoom,
                    message,
                } if self.seat.is_none() => {
                    self.result.error = Some(format!("no seat: {message}"));
                    return Ok(());
                }
                ServerMessage::Error { code, message } => {
                    self.refusals += 1;
                    self.result.refused += 1;
                    self.acted = None;
                    if self.refusals > MAX_REFUSALS {
                        client.send(&ClientMessage::Concede).await?;
                    }
                    tracing::debug!(bot = %self.name, ?code, %message, "refused");
                }
                ServerMessage::TurnChanged { .. } | ServerMessage::Applied { .. } => {
                    self.refusals = 0;
                }
                _ => {}
            }
            if let Some(cmd) = self.next_move().await {
                if !self.think.is_zero() {
                    // Players do not all shoot in step: think between half and one and a
                    // half times the configured time.
                    let factor = self.pause_rng.range(0.5, 1.5);
                    tokio::time::sleep(self.think.mul_f64(factor)).await;
                }
                if let Some(at) = self.paced.take() {
                    tokio::time::sleep_until(at.into()).await;
                }
                if matches!(cmd, ClientMessage::Shot { .. }) {
                    self.sent_shot = self.acted.map(|t| (t, Instant::now()));
                }
                // A message lost with the connection is answered again after the rejoin.
                if client.send(&cmd).await.is_err() {
                    self.acted = None;
                }
            }
        }
    }

    /// What to send now, if it is this bot's move and it has not answered it yet. The
    /// computer player thinks on the runtime's blocking threads: a decision can take a
    /// second, and the connection must be kept alive meanwhile.
    async fn next_move(&mut self) -> Option<ClientMessage> {
        if !self.seat.is_some_and(|s| self.replica.waits_for(s)) {
            return None;
        }
        let game = self.replica.game()?;
        let turn = game.turn();
        if self.acted == Some(turn) {
            return None;
        }
        self.acted = Some(turn);
        if self.game_shots >= MAX_SHOTS {
            return Some(ClientMessage::Concede);
        }
        if self.chooser.level.is_none() {
            return self.chooser.choose(game);
        }
        let (game, mut chooser) = (game.clone(), self.chooser.clone());
        let thought = tokio::task::spawn_blocking(move || (chooser.choose(&game), chooser)).await;
        match thought {
            Ok((msg, chooser)) => {
                self.chooser = chooser;
                msg
            }
            Err(e) => {
                tracing::error!(bot = %self.name, error = %e, "the computer player failed");
                Some(ClientMessage::Concede)
            }
        }
    }
}

/// Picks a move for whoever is to move: a decision, a cue-ball placement or a shot.
#[derive(Clone, Debug)]
pub struct Chooser {
    rng: Rng,
    /// None: ghost-ball aim; else the computer player at this level.
    level: Option<Level>,
}

impl Chooser {
    /// A chooser aiming ghost-ball pots, whose randomness starts from `seed`.
    pub fn new(seed: u64) -> Chooser {
        Chooser {
            rng: Rng::new(seed),
            level: None,
        }
    }

    /// A chooser that plays as the computer player at `level` (`shared::ai`), with
    /// decisions seeded from `seed`.
    pub fn computer(level: Level, seed: u64) -> Chooser {
        Chooser {
            rng: Rng::new(seed),
            level: Some(level),
        }
    }

    /// The computer player's level, None for ghost-ball aim.
    pub fn level(&self) -> Option<Level> {
        self.level
    }

    /// The move for the seat to move, `None` if the game is over. The computer player may
    /// think for up to a second.
    pub fn choose(&mut self, game: &Game) -> Option<ClientMessage> {
        let command = match self.level {
            Some(level) => ai::decide(game, level, self.rng.next_u64())?,
            None => ai::ghost_move(game, &mut self.rng)?,
        };
        command_message(game.turn(), command)
    }
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
}
