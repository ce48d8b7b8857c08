//! A seat in an online room played by a [`Chooser`]: the async driver ([`Client`]) and its
//! core enter the room and keep the seat, a [`Replica`] follows the game, and the chooser
//! picks each move. The load bot plays two of these per game; [`SeatedComputer`] is one
//! with the computer player's chooser.
//!
//! [`SeatedComputer`]: super::SeatedComputer

use std::time::{Duration, Instant};

use breakshot_shared::ai::Rng;
use breakshot_shared::protocol::{ClientMessage, ErrorCode, Invite, RoomCode, ServerMessage};
use breakshot_shared::rules::{Phase, Seat, TurnId};
use tokio::sync::oneshot;

use super::client::{Client, ClientEvent};
use super::error::NetError;
use super::player::{Entry, Reconnect};
use super::progress::{Progress, Standing, Waiting};
use crate::play::{Chooser, Replica};

/// How long a seat player keeps trying to reach a server that went away.
pub const RETRY_FOR: Duration = Duration::from_secs(120);
/// A player refused this many times in a row concedes (its aim logic is stuck).
const MAX_REFUSALS: u32 = 30;
/// A player that has shot this many times in one game concedes (keeps tests bounded).
const MAX_SHOTS: u32 = 300;

/// How a seat player enters its room.
pub(crate) enum Entrance {
    /// Opens it (a `CreateRoom`), and tells another player its code.
    Create(ClientMessage, oneshot::Sender<RoomCode>),
    /// Joins the room whose code arrives.
    Join(oneshot::Receiver<RoomCode>),
    /// Waits for a quick match (a `QuickMatch`) and plays the room it opens.
    QuickMatch(ClientMessage),
}

/// What seat players count of their shots: one player's, or a whole run's added up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Shots taken.
    pub shots: u32,
    /// Shots whose local prediction matched the server's hash.
    pub confirmed: u32,
    /// Shots taken on the server's word, not simulated (a bot checking one shot in N).
    pub unchecked: u32,
    /// Shots (or commands) whose local result differed from the server's.
    pub desyncs: u32,
    /// Times a seat was taken back after a drop.
    pub rejoins: u32,
    /// Each shot's times.
    pub times: ShotTimes,
}

impl Tally {
    /// Adds `other`'s counts to these.
    pub fn add(&mut self, other: Tally) {
        self.shots += other.shots;
        self.confirmed += other.confirmed;
        self.unchecked += other.unchecked;
        self.desyncs += other.desyncs;
        self.rejoins += other.rejoins;
        let times = other.times;
        self.times.round_trip.extend(times.round_trip);
        self.times.accepted.extend(times.accepted);
        self.times.received.extend(times.received);
        self.times.sent.extend(times.sent);
        self.times.replica.extend(times.replica);
    }
}

/// Each shot's stages as a player measured them (ms), each in the order the shots came.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShotTimes {
    /// From sending the shot to its result.
    pub round_trip: Vec<f64>,
    /// From sending the shot to the server's `ShotAccepted`: the first part of the round
    /// trip; the rest is the server simulating and storing it, and the result's way back.
    pub accepted: Vec<f64>,
    /// The last part of the round trip that is the player's own: from the result's bytes
    /// read off the connection to the player handling it (its process busy meanwhile).
    pub received: Vec<f64>,
    /// The player's own share: how long its replica took over each shot it was told of
    /// (simulating it to check the server's hash). It runs on the player's runtime, so
    /// every other connection of a load run's process waits behind it.
    pub replica: Vec<f64>,
    /// The first part that is the player's own: from the shot's time (its thinking over) to
    /// its frame written on the connection. A busy process wakes late for it.
    pub sent: Vec<f64>,
}

/// What one bot saw and did.
#[derive(Debug, Default)]
pub(crate) struct PlayerResult {
    pub(crate) room: Option<RoomCode>,
    /// When both seats were taken, and when the game ended.
    pub(crate) began: Option<Instant>,
    pub(crate) ended: Option<Instant>,
    pub(crate) over: Option<String>,
    pub(crate) tally: Tally,
    pub(crate) resolved: Vec<(TurnId, u64)>,
    /// Commands the server refused.
    pub(crate) refused: u32,
    pub(crate) error: Option<String>,
}

impl PlayerResult {
    pub(crate) fn failed(e: String) -> PlayerResult {
        PlayerResult {
            error: Some(e),
            ..PlayerResult::default()
        }
    }
}

/// One player's connection and its copy of the game.
pub(crate) struct SeatPlayer {
    server: Invite,
    name: String,
    chooser: Chooser,
    policy: Reconnect,
    think: Duration,
    pause_rng: Rng,
    replica: Replica,
    result: PlayerResult,
    /// The turn this bot last answered, while its answer is pending.
    acted: Option<TurnId>,
    /// Shots sent and not yet resolved, with when they were sent, oldest first: a bot that
    /// keeps the table moves on its replica's prediction, before the server's result of its
    /// last shot has arrived.
    sent_shots: Vec<(TurnId, Instant)>,
    /// The move chosen, and when to send it (after the pause to think, and once the last
    /// shot has been seen to its end by a pacing player).
    due: Option<(Instant, ClientMessage)>,
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
    /// Both seats are taken: a room still waiting for its opponent refuses every move, and a
    /// bot that opened a room for a person (or a page) waits for them to arrive.
    full: bool,
    /// What it last saw and did, for a load run to tell a stalled game by.
    progress: Progress,
    /// The endpoint its connections go through, shared with other players (a load run's);
    /// None: one of its own, as a client's.
    endpoint: Option<quinn::Endpoint>,
}

/// Returns at `at`, or never.
async fn until(at: Option<Instant>) {
    match at {
        Some(at) => tokio::time::sleep_until(at.into()).await,
        None => std::future::pending().await,
    }
}

/// Milliseconds since `at`.
fn ms_since(at: Instant) -> f64 {
    at.elapsed().as_secs_f64() * 1000.0
}

/// How long a pacing player looks at the table after the balls stop, before its move.
pub(crate) const LOOK: Duration = Duration::from_millis(800);

impl SeatPlayer {
    /// A bot that plays in `server`'s rooms with `chooser`, without pauses, keeping its seat
    /// through drops for `retry_for`.
    pub(crate) fn seated(
        server: Invite,
        name: String,
        chooser: Chooser,
        retry_for: Duration,
    ) -> SeatPlayer {
        let name_for_progress = name.clone();
        SeatPlayer {
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
            result: PlayerResult::default(),
            acted: None,
            sent_shots: Vec::new(),
            due: None,
            refusals: 0,
            game_shots: 0,
            stays: false,
            paced: None,
            pacing: false,
            full: false,
            progress: Progress::new(name_for_progress),
            endpoint: None,
        }
    }

    /// The player connects through `endpoint`, which other players' connections share (a
    /// load run's thousands of bots on a few UDP sockets rather than one each: the load
    /// generator's own cost, not the server's).
    pub(crate) fn on_endpoint(mut self, endpoint: Option<quinn::Endpoint>) -> SeatPlayer {
        self.endpoint = endpoint;
        self
    }

    /// The bot moves only when the last shot has finished playing for the players (and
    /// [`LOOK`] more).
    pub(crate) fn pacing(mut self) -> SeatPlayer {
        self.pacing = true;
        self
    }

    /// The player simulates and checks only its first shot and then one in `n` (every
    /// shot for 0 or 1), taking the server's game after the others: a load run's bots
    /// stand for players on machines of their own, whose simulations are not the server's
    /// machine's work.
    pub(crate) fn checking_every(mut self, n: u32) -> SeatPlayer {
        self.replica = std::mem::take(&mut self.replica).checking_every(n);
        self
    }

    /// The player plays on after each game: asks for a rematch and plays it, until dropped.
    pub(crate) fn staying(mut self) -> SeatPlayer {
        self.stays = true;
        self
    }

    /// Before each move the player thinks for about `think` (between half and one and a
    /// half times it, drawn from `seed`).
    pub(crate) fn thinking(mut self, think: Duration, seed: u64) -> SeatPlayer {
        self.think = think;
        self.pause_rng = Rng::new(seed);
        self
    }

    /// The player's name.
    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    /// What the player last saw and did, and what it waits for, as it plays.
    pub(crate) fn progress(&self) -> Progress {
        self.progress.clone()
    }

    /// Enters the room as `start` says and plays until the game ends (or, for a bot that
    /// stays, until the connection is lost for good).
    pub(crate) async fn play(self, entrance: Entrance) -> PlayerResult {
        let progress = self.progress.clone();
        progress.begin();
        let result = self.play_inner(entrance).await;
        progress.ended(match (&result.error, &result.over) {
            (Some(e), _) => e.clone(),
            (None, Some(over)) => format!("game over: {over}"),
            (None, None) => "left".into(),
        });
        result
    }

    async fn play_inner(mut self, entrance: Entrance) -> PlayerResult {
        let (entry, mut room_tx) = match entrance {
            Entrance::Create(msg, tx) => (Entry::Create(msg), Some(tx)),
            Entrance::QuickMatch(msg) => (Entry::QuickMatch(msg), None),
            Entrance::Join(rx) => match rx.await {
                Ok(room) => (
                    Entry::Join {
                        room,
                        name: self.name.clone(),
                        watch_if_full: false,
                    },
                    None,
                ),
                Err(_) => return PlayerResult::failed("the host never created a room".into()),
            },
        };
        self.progress.waits(Waiting::Connection);
        let connecting = Client::connect_on(self.endpoint.take(), self.server.clone(), self.policy);
        let mut client = match connecting.await {
            Ok(c) => c,
            Err(e) => return PlayerResult::failed(e.to_string()),
        };
        if let Err(e) = self.run(&mut client, entry, &mut room_tx).await {
            self.result.error = Some(e.to_string());
        }
        client.close(Duration::ZERO).await;
        self.result.tally.confirmed = self.replica.confirmed();
        self.result.tally.unchecked = self.replica.unchecked();
        self.result.tally.desyncs = self.replica.desyncs();
        self.result
    }

    /// Plays until the game ends (`Ok`) or the connection is lost for good.
    async fn run(
        &mut self,
        client: &mut Client,
        entry: Entry,
        room_tx: &mut Option<oneshot::Sender<RoomCode>>,
    ) -> Result<(), NetError> {
        client.enter(entry).await;
        loop {
            self.progress.waits(self.waiting(client));
            // A chosen move waits for its time while the messages go on being read, so the
            // result of the last shot is seen when it comes, not after the pause.
            let due_at = self.due.as_ref().map(|(at, _)| *at);
            let event = tokio::select! {
                event = client.recv() => event?,
                () = until(due_at) => {
                    if let Some((at, cmd)) = self.due.take() {
                        self.send_move(client, cmd, at).await;
                    }
                    continue;
                }
            };
            let msg = match event {
                ClientEvent::Message(msg) => msg,
                ClientEvent::SeatGone => continue,
                ClientEvent::Reconnecting(why) => {
                    tracing::debug!(player = %self.name, %why, "reconnecting");
                    self.progress.waits(Waiting::Reconnecting);
                    continue;
                }
                ClientEvent::Reconnected => {
                    self.result.tally.rejoins += 1;
                    self.acted = None;
                    self.due = None;
                    self.sent_shots.clear();
                    continue;
                }
            };
            self.progress.received(&msg);
            let me = client.seating().seat();
            self.progress.seated(client.room(), me);
            let (desyncs, unchecked) = (self.replica.desyncs(), self.replica.unchecked());
            let observing = Instant::now();
            self.replica.observe(&msg, me);
            // The replica's time over a shot it simulated (not one taken unchecked).
            if matches!(msg, ServerMessage::ShotAccepted { .. })
                && self.replica.unchecked() == unchecked
            {
                self.result.tally.times.replica.push(ms_since(observing));
            }
            if self.replica.desyncs() > desyncs {
                // The operator counts these (`breakshot_desyncs_reported_total`).
                if let ServerMessage::ShotResolved { turn, hash, .. } = &msg {
                    let report = ClientMessage::ReportDesync {
                        turn: *turn,
                        hash: *hash,
                    };
                    self.send(client, &report).await?;
                }
            }
            match &msg {
                ServerMessage::Joined { snapshot, .. } => {
                    self.full = snapshot.seats.iter().all(Option::is_some);
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
                        self.send(client, &ClientMessage::Rematch).await?;
                    }
                }
                ServerMessage::ShotAccepted { turn, seat, .. } => {
                    if Some(*seat) == me {
                        self.result.tally.shots += 1;
                        self.game_shots += 1;
                    }
                    if let Some((_, at)) = self.sent_shots.iter().find(|(t, _)| t == turn) {
                        self.result.tally.times.accepted.push(ms_since(*at));
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
                    self.full = true;
                    self.result.began.get_or_insert_with(Instant::now);
                }
                ServerMessage::GameStarted { .. } => {
                    self.acted = None;
                    self.game_shots = 0;
                }
                ServerMessage::ShotResolved { turn, hash, .. } => {
                    self.result.resolved.push((*turn, *hash));
                    if let Some((_, at)) = self.sent_shots.iter().find(|(t, _)| t == turn) {
                        self.result.tally.times.round_trip.push(ms_since(*at));
                        let read = client.read_at().map_or(0.0, ms_since);
                        self.result.tally.times.received.push(read);
                    }
                    // This one is done, and an older one still here was refused.
                    self.sent_shots.retain(|(t, _)| t > turn);
                }
                ServerMessage::GameOver { reason, .. } if self.stays => {
                    self.result.over = Some(reason.clone());
                    self.result.ended.get_or_insert_with(Instant::now);
                    self.send(client, &ClientMessage::Rematch).await?;
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
                } if me.is_none() => {
                    self.result.error = Some(format!("no seat: {message}"));
                    return Ok(());
                }
                ServerMessage::Error { code, message } => {
                    self.refusals += 1;
                    self.result.refused += 1;
                    self.acted = None;
                    if self.refusals > MAX_REFUSALS {
                        self.send(client, &ClientMessage::Concede).await?;
                    }
                    tracing::debug!(player = %self.name, ?code, %message, "refused");
                }
                ServerMessage::TurnChanged { .. } | ServerMessage::Applied { .. } => {
                    self.refusals = 0;
                }
                _ => {}
            }
            if let Some(cmd) = self.next_move(me).await {
                let mut at = Instant::now();
                if !self.think.is_zero() {
                    // Players do not all shoot in step: think between half and one and a
                    // half times the configured time.
                    let factor = self.pause_rng.range(0.5, 1.5);
                    at += self.think.mul_f64(factor);
                }
                if let Some(paced) = self.paced.take() {
                    at = at.max(paced);
                }
                self.due = Some((at, cmd));
            }
        }
    }

    /// Sends a move whose time (`due`) has come.
    async fn send_move(&mut self, client: &mut Client, cmd: ClientMessage, due: Instant) {
        let shot = matches!(cmd, ClientMessage::Shot { .. });
        if let ClientMessage::Shot { turn, .. } = cmd {
            // A shot sent again on its turn (the first was refused) counts anew.
            self.sent_shots.retain(|(t, _)| *t != turn);
            self.sent_shots.push((turn, Instant::now()));
        }
        // A message lost with the connection is answered again after the rejoin.
        if self.send(client, &cmd).await.is_err() {
            self.acted = None;
        } else if shot {
            self.result.tally.times.sent.push(ms_since(due));
        }
    }

    /// Sends `msg`, and records that it did.
    async fn send(&mut self, client: &mut Client, msg: &ClientMessage) -> Result<(), NetError> {
        self.progress.sent(msg);
        client.send(msg).await
    }

    /// What the player waits for now.
    fn waiting(&self, client: &Client) -> Waiting {
        let due = self.due.as_ref().map(|(at, cmd)| {
            let turn = match cmd {
                ClientMessage::Shot { turn, .. }
                | ClientMessage::PlaceCueBall { turn, .. }
                | ClientMessage::Decide { turn, .. } => *turn,
                _ => self.replica.game().map_or(0, |g| g.turn()),
            };
            (turn, *at)
        });
        let turn = self
            .replica
            .game()
            .filter(|g| !matches!(g.phase(), Phase::Over { .. }))
            .map(|g| (g.turn(), g.to_move()));
        Waiting::of(&Standing {
            seat: client.seating().seat(),
            full: self.full,
            due,
            shot_sent: self.sent_shots.last().map(|(turn, _)| *turn),
            turn,
            acted: self.acted,
        })
    }

    /// What to send now, if it is this bot's move and it has not answered it yet. The
    /// computer player thinks on the runtime's blocking threads: a decision can take a
    /// second, and the connection must be kept alive meanwhile.
    async fn next_move(&mut self, seat: Option<Seat>) -> Option<ClientMessage> {
        if !self.full || !seat.is_some_and(|s| self.replica.waits_for(s)) {
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
        if self.chooser.level().is_none() {
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
                tracing::error!(player = %self.name, error = %e, "the computer player failed");
                Some(ClientMessage::Concede)
            }
        }
    }
}
