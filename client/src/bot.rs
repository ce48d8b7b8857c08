//! A headless player for load tests and integration tests: plays whole games against
//! another bot through a server, aiming at legal balls (ghost-ball aim at a pocket, with
//! some randomness), checks every shot against its local prediction, and rejoins with its
//! seat token when the server goes away.

use std::time::{Duration, Instant};

use breakshot_shared::physics::{BallState, MotionState, Strike, Table};
use breakshot_shared::protocol::{
    AimAid, ClientMessage, ErrorCode, Invite, RoomCode, ServerMessage,
};
use breakshot_shared::rules::{
    Choice, EightBallRules, Game, InHand, Phase, Settings, TurnId, Variant,
};
use glam::DVec2;
use tokio::sync::oneshot;

use crate::net::{endpoint, Connection, Mirror, NetError};

/// How long a bot keeps trying to reach a server that went away.
pub const RETRY_FOR: Duration = Duration::from_secs(120);
/// Pause between reconnection attempts.
const RETRY_PAUSE: Duration = Duration::from_millis(250);
/// A bot refused this many times in a row concedes (its aim logic is stuck).
const MAX_REFUSALS: u32 = 30;
/// A bot that has shot this many times in one game concedes (keeps tests bounded).
const MAX_SHOTS: u32 = 300;

#[derive(Clone, Debug)]
pub struct BotConfig {
    pub server: Invite,
    pub games: usize,
    pub seed: u64,
    pub variant: Variant,
    pub retry_for: Duration,
    /// Pause before each move, as a player would think (on average; each pause is drawn
    /// between half and one and a half times this).
    pub think: Duration,
}

impl BotConfig {
    pub fn new(server: Invite, games: usize) -> BotConfig {
        BotConfig {
            server,
            games,
            seed: 1,
            variant: Variant::EightBall(EightBallRules::Wpa),
            retry_for: RETRY_FOR,
            think: Duration::ZERO,
        }
    }
}

/// One game as the bots saw it.
#[derive(Clone, Debug, Default)]
pub struct GameSummary {
    pub room: Option<RoomCode>,
    pub completed: bool,
    pub reason: String,
    /// Every shot result the host saw: (turn, server hash).
    pub resolved: Vec<(TurnId, u64)>,
}

#[derive(Clone, Debug, Default)]
pub struct Report {
    pub games_completed: u32,
    pub shots: u32,
    /// Shots whose local prediction matched the server's hash (counted by each player).
    pub confirmed: u32,
    pub desyncs: u32,
    pub rejoins: u32,
    pub round_trips_ms: Vec<f64>,
    pub games: Vec<GameSummary>,
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

    /// The report as one JSON object with exactly the documented keys.
    pub fn to_json(&self) -> String {
        serde_json::json!({
            "games_completed": self.games_completed,
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
        tasks.push(tokio::spawn(
            async move { play_game(&config, g as u64).await },
        ));
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
    let host = Bot::new(config, format!("bot{g}a"), config.seed ^ (g * 2 + 1));
    let guest = Bot::new(config, format!("bot{g}b"), config.seed ^ (g * 2 + 2));
    let create = ClientMessage::CreateRoom {
        variant: config.variant,
        mode: Settings::offline(),
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
    };
    (summary, host, guest)
}

enum Start {
    Create(ClientMessage, oneshot::Sender<RoomCode>),
    Join(oneshot::Receiver<RoomCode>),
}

#[derive(Debug, Default)]
struct PlayerResult {
    room: Option<RoomCode>,
    over: Option<String>,
    shots: u32,
    confirmed: u32,
    desyncs: u32,
    rejoins: u32,
    round_trips_ms: Vec<f64>,
    resolved: Vec<(TurnId, u64)>,
    error: Option<String>,
}

impl PlayerResult {
    fn failed(e: String) -> PlayerResult {
        PlayerResult {
            error: Some(e),
            ..PlayerResult::default()
        }
    }
}

struct Bot {
    server: Invite,
    name: String,
    chooser: Chooser,
    retry_for: Duration,
    think: Duration,
    pause_rng: Rng,
    mirror: Mirror,
    result: PlayerResult,
    /// The turn this bot last answered, while its answer is pending.
    acted: Option<TurnId>,
    sent_shot: Option<(TurnId, Instant)>,
    refusals: u32,
}

impl Bot {
    fn new(config: &BotConfig, name: String, seed: u64) -> Bot {
        Bot {
            server: config.server.clone(),
            name,
            chooser: Chooser::new(seed),
            retry_for: config.retry_for,
            think: config.think,
            pause_rng: Rng(!seed),
            mirror: Mirror::default(),
            result: PlayerResult::default(),
            acted: None,
            sent_shot: None,
            refusals: 0,
        }
    }

    async fn play(mut self, start: Start) -> PlayerResult {
        let endpoint = match endpoint() {
            Ok(e) => e,
            Err(e) => return PlayerResult::failed(e.to_string()),
        };
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
        let mut conn = match Connection::open(&endpoint, &self.server).await {
            Ok(c) => c,
            Err(e) => return PlayerResult::failed(e.to_string()),
        };
        let mut hello = first;
        loop {
            match self.session(&mut conn, hello, &mut room_tx).await {
                Ok(()) => break,
                Err(e) => {
                    // The server went away: reconnect and take the seat back.
                    let Some(token) = self.mirror.token() else {
                        self.result.error = Some(e.to_string());
                        break;
                    };
                    match self.reconnect(&endpoint).await {
                        Ok(c) => {
                            conn = c;
                            hello = ClientMessage::Rejoin { token };
                            self.result.rejoins += 1;
                            self.acted = None;
                            self.sent_shot = None;
                        }
                        Err(e) => {
                            self.result.error = Some(e.to_string());
                            break;
                        }
                    }
                }
            }
        }
        conn.quic().close(0u32.into(), b"done");
        self.result.confirmed = self.mirror.confirmed();
        self.result.desyncs = self.mirror.desyncs();
        self.result
    }

    async fn reconnect(&self, endpoint: &quinn::Endpoint) -> Result<Connection, NetError> {
        let since = Instant::now();
        loop {
            match Connection::open(endpoint, &self.server).await {
                Ok(c) => return Ok(c),
                Err(e) if since.elapsed() > self.retry_for => return Err(e),
                Err(_) => tokio::time::sleep(RETRY_PAUSE).await,
            }
        }
    }

    /// Plays on one connection until the game ends (`Ok`) or the connection is lost.
    async fn session(
        &mut self,
        conn: &mut Connection,
        first: ClientMessage,
        room_tx: &mut Option<oneshot::Sender<RoomCode>>,
    ) -> Result<(), NetError> {
        conn.send(&first).await?;
        loop {
            let msg = conn.recv().await?;
            self.mirror.observe(&msg);
            match &msg {
                ServerMessage::Joined { snapshot, .. } => {
                    self.result.room = Some(snapshot.room.clone());
                    if let Some(tx) = room_tx.take() {
                        let _ = tx.send(snapshot.room.clone());
                    }
                    if let Phase::Over { reason, .. } = snapshot.game.phase() {
                        self.result.over = Some(reason.clone());
                        return Ok(());
                    }
                }
                ServerMessage::ShotAccepted { seat, .. } if Some(*seat) == self.mirror.seat() => {
                    self.result.shots += 1;
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
                ServerMessage::GameOver { reason, .. }
                | ServerMessage::GameFinished { reason, .. } => {
                    // `GameFinished`: the game ended while this bot was away.
                    self.result.over = Some(reason.clone());
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
                ServerMessage::Error { code, message } => {
                    self.refusals += 1;
                    self.acted = None;
                    if self.refusals > MAX_REFUSALS {
                        conn.send(&ClientMessage::Concede).await?;
                    }
                    tracing::debug!(bot = %self.name, ?code, %message, "refused");
                }
                ServerMessage::TurnChanged { .. } | ServerMessage::Applied { .. } => {
                    self.refusals = 0;
                }
                _ => {}
            }
            if let Some(cmd) = self.next_move() {
                if !self.think.is_zero() {
                    // Players do not all shoot in step: think between half and one and a
                    // half times the configured time.
                    let factor = self.pause_rng.range(0.5, 1.5);
                    tokio::time::sleep(self.think.mul_f64(factor)).await;
                }
                if matches!(cmd, ClientMessage::Shot { .. }) {
                    self.sent_shot = self.acted.map(|t| (t, Instant::now()));
                }
                conn.send(&cmd).await?;
            }
        }
    }

    /// What to send now, if it is this bot's move and it has not answered it yet.
    fn next_move(&mut self) -> Option<ClientMessage> {
        if !self.mirror.my_move() {
            return None;
        }
        let game = self.mirror.game()?;
        let turn = game.turn();
        if self.acted == Some(turn) {
            return None;
        }
        self.acted = Some(turn);
        if self.result.shots >= MAX_SHOTS {
            return Some(ClientMessage::Concede);
        }
        self.chooser.choose(game)
    }
}

/// Picks a move for whoever is to move: a decision, a cue-ball placement or a shot.
pub struct Chooser {
    rng: Rng,
}

impl Chooser {
    pub fn new(seed: u64) -> Chooser {
        Chooser { rng: Rng(seed) }
    }

    /// The move for the seat to move, `None` if the game is over.
    pub fn choose(&mut self, game: &Game) -> Option<ClientMessage> {
        let turn = game.turn();
        let msg = match game.phase() {
            Phase::Deciding { options } => {
                let choice = if options.contains(&Choice::AcceptTable) {
                    Choice::AcceptTable
                } else {
                    *options.first()?
                };
                ClientMessage::Decide { turn, choice }
            }
            Phase::Shooting {
                in_hand: Some(area),
                ..
            } if off_table(&game.balls()[0]) => ClientMessage::PlaceCueBall {
                turn,
                pos: self.placement(game, *area)?,
            },
            Phase::Shooting { .. } => {
                let (strike, call) = self.aim(game);
                ClientMessage::Shot { turn, strike, call }
            }
            Phase::Over { .. } => return None,
        };
        Some(msg)
    }

    fn placement(&mut self, game: &Game, area: InHand) -> Option<[f64; 2]> {
        let (w, l) = game.table().size()?;
        let r = breakshot_shared::physics::Params::default().ball_radius;
        let max_y = match area {
            InHand::Kitchen => l / 4.0 - r,
            InHand::Anywhere => l - 2.0 * r,
        };
        (0..200)
            .map(|_| {
                [
                    self.rng.range(2.0 * r, w - 2.0 * r),
                    self.rng.range(2.0 * r, max_y),
                ]
            })
            .find(|p| game.legal_cue_placement(*p).is_ok())
    }

    /// Ghost-ball aim at a legal ball into a pocket, with a little noise.
    fn aim(&mut self, game: &Game) -> (Strike, Option<u8>) {
        let balls = game.balls();
        let cue = balls[0].pos;
        let r = breakshot_shared::physics::Params::default().ball_radius;
        let table = Table::new(game.table());
        let pockets: Vec<DVec2> = table
            .pockets
            .iter()
            .map(|p| table.to_scene(p.center))
            .collect();
        let legal: Vec<u8> = game.legal_first_balls();
        let targets: Vec<(u8, DVec2)> = balls
            .iter()
            .enumerate()
            .skip(1)
            .filter(|(i, b)| !off_table(b) && (legal.is_empty() || legal.contains(&(*i as u8))))
            .map(|(i, b)| (i as u8, b.pos))
            .collect();
        if game.is_break() || targets.is_empty() {
            let at = targets
                .iter()
                .map(|t| t.1)
                .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
                .unwrap_or(cue + DVec2::Y);
            let dir = rotate(
                (at - cue).normalize_or(DVec2::Y),
                self.rng.range(-0.01, 0.01),
            );
            let strike = Strike {
                speed: self.rng.range(8.0, 10.0),
                dir,
                tip: DVec2::ZERO,
            };
            return (strike, None);
        }
        let mut options: Vec<(f64, DVec2, u8)> = Vec::new();
        for (_, t) in &targets {
            for (k, p) in pockets.iter().enumerate() {
                let to_pocket = (*p - *t).normalize_or_zero();
                let ghost = *t - to_pocket * (2.0 * r);
                let aim = (ghost - cue).normalize_or_zero();
                let straightness = aim.dot(to_pocket);
                if straightness > 0.3 {
                    let dist = ghost.distance(cue) + p.distance(*t);
                    options.push((straightness - 0.1 * dist, aim, k as u8));
                }
            }
        }
        options.sort_by(|a, b| b.0.total_cmp(&a.0));
        let pick = options.get(self.rng.below(options.len().min(3))).copied();
        let (aim, call) = match pick {
            Some((_, aim, pocket)) => (aim, Some(pocket)),
            None => {
                let (_, t) = targets[self.rng.below(targets.len())];
                let nearest = (0..pockets.len())
                    .min_by(|a, b| pockets[*a].distance(t).total_cmp(&pockets[*b].distance(t)))
                    .map(|k| k as u8);
                ((t - cue).normalize_or(DVec2::Y), nearest)
            }
        };
        let strike = Strike {
            speed: self.rng.range(2.5, 5.0),
            dir: rotate(aim, self.rng.range(-0.008, 0.008)),
            tip: DVec2::new(0.0, self.rng.range(-0.2, 0.3)),
        };
        (strike, call)
    }
}

fn off_table(b: &BallState) -> bool {
    b.pocket.is_some() || b.motion == MotionState::Pocketed
}

/// Rotates `v` by `angle` radians (small angles: aim noise).
fn rotate(v: DVec2, angle: f64) -> DVec2 {
    let (s, c) = angle.sin_cos();
    DVec2::new(v.x * c - v.y * s, v.x * s + v.y * c)
}

/// SplitMix64: small, seedable, good enough for aim noise.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}
