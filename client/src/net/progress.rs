//! What a seat player last saw and did, and what it waits for, kept where a load run can
//! read it while the player plays: a game that makes no progress shows which side it waits
//! on (the server's answer to a move, the opponent, a move of its own never sent) instead
//! of a run that just never ends.

use std::fmt;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use breakshot_shared::protocol::{ClientMessage, RoomCode, ServerMessage};
use breakshot_shared::rules::{Seat, TurnId};

/// What a seat player waits for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Waiting {
    /// The code of the room to join (from the bot that opens it).
    #[default]
    RoomCode,
    /// The connection and its handshake.
    Connection,
    /// The server's answer to its entry (`Joined`).
    Seat,
    /// The second player.
    Opponent,
    /// Its move on `turn` is chosen and sent at `due`.
    OwnMove {
        /// The turn the move answers.
        turn: TurnId,
        /// When it is sent.
        due: Instant,
    },
    /// The result of its shot on `turn`.
    ShotResult {
        /// The turn the shot was taken on.
        turn: TurnId,
    },
    /// The server's answer (applied, refused) to its move on `turn`.
    Answer {
        /// The turn the move answered.
        turn: TurnId,
    },
    /// The table waits for this player on `turn`, and it has not chosen a move: never
    /// meant to last.
    Unanswered {
        /// The turn waited for.
        turn: TurnId,
    },
    /// The opponent's move on `turn`.
    OpponentMove {
        /// The turn waited for.
        turn: TurnId,
    },
    /// Its seat back after a dropped connection.
    Reconnecting,
    /// Nothing: its game is over.
    Done,
}

/// What a seated player knows, to tell what it waits for ([`Waiting::of`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Standing {
    /// Its seat, once the server gave it one.
    pub seat: Option<Seat>,
    /// Both seats are taken.
    pub full: bool,
    /// The move chosen and not yet sent: its turn and when it is due.
    pub due: Option<(TurnId, Instant)>,
    /// The newest shot sent whose result has not come.
    pub shot_sent: Option<TurnId>,
    /// The game's turn and the seat it waits for (None when over or not begun).
    pub turn: Option<(TurnId, Seat)>,
    /// The turn this player last answered.
    pub acted: Option<TurnId>,
}

impl Waiting {
    /// What a player standing as `s` waits for.
    pub fn of(s: &Standing) -> Waiting {
        let Some(seat) = s.seat else {
            return Waiting::Seat;
        };
        if !s.full {
            return Waiting::Opponent;
        }
        if let Some((turn, due)) = s.due {
            return Waiting::OwnMove { turn, due };
        }
        if let Some(turn) = s.shot_sent {
            return Waiting::ShotResult { turn };
        }
        match s.turn {
            Some((turn, to_move)) if to_move == seat && s.acted == Some(turn) => {
                Waiting::Answer { turn }
            }
            Some((turn, to_move)) if to_move == seat => Waiting::Unanswered { turn },
            Some((turn, _)) => Waiting::OpponentMove { turn },
            // A seat in a game not begun or over: the next game's start.
            None => Waiting::Opponent,
        }
    }

    /// The kind of wait, without its turn: to count players by what they wait for.
    pub fn kind(&self) -> &'static str {
        match self {
            Waiting::RoomCode => "the room's code",
            Waiting::Connection => "a connection",
            Waiting::Seat => "a seat",
            Waiting::Opponent => "an opponent",
            Waiting::OwnMove { .. } => "its own move's time",
            Waiting::ShotResult { .. } => "its shot's result",
            Waiting::Answer { .. } => "the answer to its move",
            Waiting::Unanswered { .. } => "itself (a move never chosen)",
            Waiting::OpponentMove { .. } => "the opponent's move",
            Waiting::Reconnecting => "its seat back",
            Waiting::Done => "nothing",
        }
    }
}

impl fmt::Display for Waiting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = self.kind();
        match self {
            Waiting::OwnMove { turn, due } => {
                let now = Instant::now();
                match due.checked_duration_since(now) {
                    Some(wait) if !wait.is_zero() => {
                        let wait = wait.as_secs_f64();
                        write!(f, "{kind} on turn {turn} (due in {wait:.1} s)")
                    }
                    _ => {
                        let late = now.saturating_duration_since(*due).as_secs_f64();
                        write!(f, "{kind} on turn {turn} (late by {late:.1} s)")
                    }
                }
            }
            Waiting::ShotResult { turn }
            | Waiting::Answer { turn }
            | Waiting::Unanswered { turn }
            | Waiting::OpponentMove { turn } => write!(f, "{kind} on turn {turn}"),
            _ => f.write_str(kind),
        }
    }
}

/// One player's progress as last recorded.
#[derive(Clone, Debug)]
pub struct Seen {
    /// The player's name.
    pub player: String,
    /// The room it plays in, once known.
    pub room: Option<RoomCode>,
    /// Its seat, once given.
    pub seat: Option<Seat>,
    /// When it began (its game's start, for a run that spreads them).
    pub since: Instant,
    /// The last message received: when, and what.
    pub received: Option<(Instant, String)>,
    /// The last message sent: when, and what.
    pub sent: Option<(Instant, String)>,
    /// What it waits for.
    pub waiting: Waiting,
    /// How it ended, once done: the game's end, or what went wrong.
    pub end: Option<String>,
}

impl Seen {
    /// A player that has done nothing yet.
    pub fn new(player: String, since: Instant) -> Seen {
        Seen {
            player,
            room: None,
            seat: None,
            since,
            received: None,
            sent: None,
            waiting: Waiting::default(),
            end: None,
        }
    }

    /// The last thing that happened to it: a message either way, or its start.
    pub fn last_progress(&self) -> Instant {
        let at = |m: &Option<(Instant, String)>| m.as_ref().map(|(at, _)| *at);
        [at(&self.received), at(&self.sent)]
            .into_iter()
            .flatten()
            .fold(self.since, Instant::max)
    }

    /// Whether it has waited at least `quiet` since its last progress, at `now`, and is
    /// not done.
    pub fn stalled(&self, now: Instant, quiet: Duration) -> bool {
        self.waiting != Waiting::Done
            && now.saturating_duration_since(self.last_progress()) >= quiet
    }

    /// One line for a person: who, where, what it waits for, and its last messages.
    pub fn line(&self, now: Instant) -> String {
        let ago = |at: Instant| now.saturating_duration_since(at).as_secs_f64();
        let msg = |m: &Option<(Instant, String)>| match m {
            Some((at, what)) => format!("{what} {:.1} s ago", ago(*at)),
            None => "nothing".into(),
        };
        let room = self.room.as_ref().map_or("-".into(), RoomCode::to_string);
        let seat = match self.seat {
            Some(Seat::A) => "A",
            Some(Seat::B) => "B",
            None => "-",
        };
        let state = match (&self.waiting, &self.end) {
            (Waiting::Done, Some(end)) => format!("ended ({end})"),
            (waiting, _) => format!("waits for {waiting}"),
        };
        format!(
            "{} room {room} seat {seat}: {state}; quiet {:.1} s; last received {}; last sent {}",
            self.player,
            ago(self.last_progress()),
            msg(&self.received),
            msg(&self.sent),
        )
    }
}

/// The players of `all` quiet for at least `quiet` at `now`, the longest quiet first, and
/// how many of them wait for each kind of thing (most first).
pub fn stalled(
    all: &[Seen],
    now: Instant,
    quiet: Duration,
) -> (Vec<&Seen>, Vec<(&'static str, usize)>) {
    let mut stalled: Vec<&Seen> = all.iter().filter(|s| s.stalled(now, quiet)).collect();
    stalled.sort_by_key(|s| s.last_progress());
    let mut kinds: Vec<(&'static str, usize)> = Vec::new();
    for s in &stalled {
        match kinds.iter_mut().find(|(k, _)| *k == s.waiting.kind()) {
            Some((_, n)) => *n += 1,
            None => kinds.push((s.waiting.kind(), 1)),
        }
    }
    kinds.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    (stalled, kinds)
}

/// A shared handle on one player's [`Seen`]: the player writes it, a watcher reads it.
#[derive(Clone, Debug)]
pub struct Progress(Arc<Mutex<Seen>>);

impl Progress {
    /// A player named `player`, starting now.
    pub fn new(player: String) -> Progress {
        Progress(Arc::new(Mutex::new(Seen::new(player, Instant::now()))))
    }

    fn lock(&self) -> MutexGuard<'_, Seen> {
        // A panic elsewhere leaves the record as it was: still worth reading.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A copy of what it recorded.
    pub fn seen(&self) -> Seen {
        self.lock().clone()
    }

    /// It began now (its start was put off).
    pub(crate) fn begin(&self) {
        self.lock().since = Instant::now();
    }

    /// It begins at `at`: until then it is not quiet, only not started (a run that spreads
    /// its games' starts).
    pub(crate) fn begins_at(&self, at: Instant) {
        self.lock().since = at;
    }

    /// It received `msg`.
    pub(crate) fn received(&self, msg: &ServerMessage) {
        self.lock().received = Some((Instant::now(), received_label(msg)));
    }

    /// It sent `msg`.
    pub(crate) fn sent(&self, msg: &ClientMessage) {
        self.lock().sent = Some((Instant::now(), sent_label(msg)));
    }

    /// Where it sits now.
    pub(crate) fn seated(&self, room: Option<&RoomCode>, seat: Option<Seat>) {
        let mut seen = self.lock();
        if seen.room.as_ref() != room {
            seen.room = room.cloned();
        }
        seen.seat = seat;
    }

    /// It waits for `waiting` now.
    pub(crate) fn waits(&self, waiting: Waiting) {
        self.lock().waiting = waiting;
    }

    /// It is done, as `end` says.
    pub(crate) fn ended(&self, end: String) {
        let mut seen = self.lock();
        seen.waiting = Waiting::Done;
        seen.end = Some(end);
    }
}

fn seat_letter(seat: Seat) -> &'static str {
    match seat {
        Seat::A => "A",
        Seat::B => "B",
    }
}

/// A message from the server in a few words: its kind, and its turn and seat if it has them.
pub(crate) fn received_label(msg: &ServerMessage) -> String {
    use ServerMessage as M;
    match msg {
        M::Joined { snapshot, .. } => format!("Joined (turn {})", snapshot.game.turn()),
        M::GameStarted { .. } => "GameStarted".into(),
        M::PlayerJoined { seat, .. } => format!("PlayerJoined {}", seat_letter(*seat)),
        M::ShotAccepted { turn, seat, .. } => {
            format!("ShotAccepted turn {turn} by {}", seat_letter(*seat))
        }
        M::ShotResolved { turn, .. } => format!("ShotResolved turn {turn}"),
        M::Applied { turn, seat, .. } => format!("Applied turn {turn} for {}", seat_letter(*seat)),
        M::TurnChanged { turn, to_move, .. } => {
            format!("TurnChanged turn {turn} to {}", seat_letter(*to_move))
        }
        M::PlayerLeft { seat, .. } => format!("PlayerLeft {}", seat_letter(*seat)),
        M::PlayerBack { seat } => format!("PlayerBack {}", seat_letter(*seat)),
        M::GameOver { .. } => "GameOver".into(),
        M::Error { code, message } => format!("Error {code:?} ({message})"),
        other => {
            // The variant's name: what its debug form starts with.
            let debug = format!("{other:?}");
            let end = debug.find([' ', '{', '(']).unwrap_or(debug.len());
            debug[..end].to_owned()
        }
    }
}

/// A message to the server in a few words: its kind, and its turn if it has one.
pub(crate) fn sent_label(msg: &ClientMessage) -> String {
    use ClientMessage as C;
    match msg {
        C::Shot { turn, .. } => format!("Shot turn {turn}"),
        C::PlaceCueBall { turn, .. } => format!("PlaceCueBall turn {turn}"),
        C::Decide { turn, .. } => format!("Decide turn {turn}"),
        other => {
            let debug = format!("{other:?}");
            let end = debug.find([' ', '{', '(']).unwrap_or(debug.len());
            debug[..end].to_owned()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn standing() -> Standing {
        Standing {
            seat: Some(Seat::A),
            full: true,
            ..Standing::default()
        }
    }

    #[test]
    fn a_player_waits_for_the_first_thing_missing() {
        let now = Instant::now();
        assert_eq!(Waiting::of(&Standing::default()), Waiting::Seat);
        let alone = Standing {
            full: false,
            ..standing()
        };
        assert_eq!(Waiting::of(&alone), Waiting::Opponent);
        // A move due goes before a shot in flight: it is the next thing it does.
        let due = Standing {
            due: Some((7, now)),
            shot_sent: Some(6),
            turn: Some((7, Seat::A)),
            ..standing()
        };
        assert_eq!(Waiting::of(&due), Waiting::OwnMove { turn: 7, due: now });
        let in_flight = Standing {
            shot_sent: Some(6),
            turn: Some((7, Seat::B)),
            ..standing()
        };
        assert_eq!(Waiting::of(&in_flight), Waiting::ShotResult { turn: 6 });
        let answered = Standing {
            turn: Some((8, Seat::A)),
            acted: Some(8),
            ..standing()
        };
        assert_eq!(Waiting::of(&answered), Waiting::Answer { turn: 8 });
        let forgotten = Standing {
            turn: Some((8, Seat::A)),
            acted: Some(7),
            ..standing()
        };
        assert_eq!(Waiting::of(&forgotten), Waiting::Unanswered { turn: 8 });
        let theirs = Standing {
            turn: Some((9, Seat::B)),
            ..standing()
        };
        assert_eq!(Waiting::of(&theirs), Waiting::OpponentMove { turn: 9 });
    }

    #[test]
    fn a_player_is_stalled_when_quiet_for_long_enough_and_not_done() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let mut seen = Seen::new("bot3a".into(), t0);
        assert!(!seen.stalled(at(9), Duration::from_secs(10)));
        assert!(seen.stalled(at(10), Duration::from_secs(10)));
        seen.received = Some((at(5), "TurnChanged turn 4 to B".into()));
        seen.sent = Some((at(3), "Shot turn 3".into()));
        assert_eq!(seen.last_progress(), at(5));
        assert!(!seen.stalled(at(14), Duration::from_secs(10)));
        assert!(seen.stalled(at(15), Duration::from_secs(10)));
        seen.waiting = Waiting::Done;
        assert!(!seen.stalled(at(100), Duration::from_secs(10)));
        // Not started yet: not quiet either.
        let later = Seen::new("bot9a".into(), at(50));
        assert!(!later.stalled(at(40), Duration::from_secs(10)));
    }

    #[test]
    fn the_stalled_come_longest_quiet_first_and_are_counted_by_what_they_wait_for() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let player = |name: &str, last: u64, waiting| {
            let mut seen = Seen::new(name.into(), t0);
            seen.received = Some((at(last), "TurnChanged turn 1 to A".into()));
            seen.waiting = waiting;
            seen
        };
        let all = [
            player("a", 20, Waiting::OpponentMove { turn: 1 }),
            player("b", 5, Waiting::ShotResult { turn: 3 }),
            player("c", 8, Waiting::OpponentMove { turn: 2 }),
            player("d", 1, Waiting::Done),
            player("e", 2, Waiting::OpponentMove { turn: 5 }),
        ];
        let (stalled, kinds) = stalled(&all, at(30), Duration::from_secs(20));
        let names: Vec<&str> = stalled.iter().map(|s| s.player.as_str()).collect();
        assert_eq!(names, ["e", "b", "c"]);
        assert_eq!(
            kinds,
            [("the opponent's move", 2), ("its shot's result", 1)]
        );
    }

    #[test]
    fn a_line_says_who_what_it_waits_for_and_its_last_messages() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let mut seen = Seen::new("bot12b".into(), t0);
        seen.room = Some(RoomCode::parse("K7QX2M4B").expect("a room code"));
        seen.seat = Some(Seat::B);
        seen.received = Some((
            at(2),
            received_label(&ServerMessage::TurnChanged {
                turn: 17,
                to_move: Seat::B,
                shot_clock_ms: None,
            }),
        ));
        seen.sent = Some((at(1), sent_label(&ClientMessage::Concede)));
        seen.waiting = Waiting::Answer { turn: 17 };
        assert_eq!(
            seen.line(at(12)),
            "bot12b room K7QX2M4B seat B: waits for the answer to its move on turn 17; \
             quiet 10.0 s; last received TurnChanged turn 17 to B 10.0 s ago; \
             last sent Concede 11.0 s ago"
        );
        seen.waiting = Waiting::Done;
        seen.end = Some("cannot reach the game".into());
        assert!(
            seen.line(at(12))
                .starts_with("bot12b room K7QX2M4B seat B: ended (cannot reach the game); quiet"),
            "{}",
            seen.line(at(12))
        );
        assert_eq!(
            Seen::new("x".into(), t0).line(at(3)),
            "x room - seat -: waits for the room's code; quiet 3.0 s; \
             last received nothing; last sent nothing"
        );
    }

    #[test]
    fn a_move_waiting_for_its_time_says_whether_it_is_due_or_late() {
        let now = Instant::now();
        let soon = Waiting::OwnMove {
            turn: 4,
            due: now + Duration::from_secs(60),
        };
        assert!(
            soon.to_string()
                .starts_with("its own move's time on turn 4 (due in "),
            "{soon}"
        );
        let Some(past) = now.checked_sub(Duration::from_secs(5)) else {
            return;
        };
        let late = Waiting::OwnMove { turn: 4, due: past };
        assert!(
            late.to_string()
                .starts_with("its own move's time on turn 4 (late by "),
            "{late}"
        );
    }

    #[test]
    fn labels_name_the_message_and_its_turn() {
        let ready = ServerMessage::Draining {
            message: "bye".into(),
        };
        assert_eq!(received_label(&ready), "Draining");
        let welcome = ServerMessage::Welcome { protocol: 3 };
        assert_eq!(received_label(&welcome), "Welcome");
        assert_eq!(sent_label(&ClientMessage::Rematch), "Rematch");
    }
}
