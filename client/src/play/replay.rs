//! Watching a recorded game: the record's commands are applied one by one to a [`Replica`]
//! of the game, which shows each shot from the trajectory the rules computed (one
//! simulation per shot) while its hash is checked against the recorded one. Pause, step shot
//! by shot (both ways) and speed.

use breakshot_shared::physics::BallState;
use breakshot_shared::replay::{GameRecord, RecordError, RECORD_VERSION};
use breakshot_shared::rules::{Command, Game, Verdict};

use super::replica::Replica;
use crate::view::{Playback, MAX_SPEED, MIN_SPEED};

/// Pause between two entries at normal speed (s), so a viewer can follow.
const HOLD: f64 = 0.8;

/// Why a record cannot be watched.
#[derive(Debug, thiserror::Error)]
pub enum ReplayOpenError {
    /// The bytes are not a game record (the record's own error says why, once).
    #[error(transparent)]
    Record(#[from] RecordError),
    /// A record of another version.
    #[error("game record version {0} cannot be shown (this build reads {RECORD_VERSION})")]
    Version(u32),
}

/// A record being watched.
#[derive(Clone, Debug)]
pub struct ReplayViewer {
    record: GameRecord,
    /// The game, with entry `next` applied while its shot is shown.
    replica: Replica,
    /// The next entry to apply.
    next: usize,
    /// The verdict of entry `next`, shown once its shot has played.
    pending: Option<Verdict>,
    /// Time left before the next entry starts (s of real time at speed 1).
    hold: f64,
    /// Playback is paused.
    pub paused: bool,
    /// Playback speed (times real speed).
    pub speed: f64,
    /// The verdict of the last entry shown.
    pub last_verdict: Option<Verdict>,
    /// Entries whose replayed hash differs from the recorded one.
    pub mismatches: Vec<usize>,
    /// Why playback stopped early: an entry the rules refused.
    pub stopped: Option<String>,
    /// For each ball, when it last fell (a counter of falls), for the tray's order.
    fell: Vec<u64>,
    falls: u64,
}

impl ReplayViewer {
    /// The players' names by seat, as the record keeps them (records before format 3 have
    /// none).
    pub fn players(&self) -> &[Option<String>; 2] {
        &self.record.players
    }

    /// Opens an encoded record.
    pub fn decode(bytes: &[u8]) -> Result<ReplayViewer, ReplayOpenError> {
        let record = GameRecord::decode(bytes)?;
        ReplayViewer::new(record)
    }

    /// Opens a record, at its start.
    pub fn new(record: GameRecord) -> Result<ReplayViewer, ReplayOpenError> {
        if record.version != RECORD_VERSION {
            return Err(ReplayOpenError::Version(record.version));
        }
        let game = Game::new(record.variant, record.settings, record.seed);
        let balls = game.balls().len();
        let mut replica = Replica::default();
        replica.start(game);
        Ok(ReplayViewer {
            record,
            replica,
            next: 0,
            pending: None,
            hold: HOLD,
            paused: false,
            speed: 1.0,
            last_verdict: None,
            mismatches: Vec::new(),
            stopped: None,
            fell: vec![0; balls],
            falls: 0,
        })
    }

    /// The game as the rules leave it (with the shot being shown applied).
    pub fn game(&self) -> &Game {
        // The replica holds a game from the start.
        self.replica.game().unwrap_or_else(|| unreachable!())
    }

    /// The record watched.
    pub fn record(&self) -> &GameRecord {
        &self.record
    }

    /// Entries applied so far, and in all.
    pub fn position(&self) -> (usize, usize) {
        (self.next, self.record.entries.len())
    }

    /// No entry is left to show.
    pub fn at_end(&self) -> bool {
        self.next >= self.record.entries.len() || self.stopped.is_some()
    }

    /// The shot being shown, if any.
    pub fn shot(&self) -> Option<&Playback> {
        self.replica.playback()
    }

    /// The balls as shown now.
    pub fn balls(&self) -> Vec<BallState> {
        self.replica.balls()
    }

    /// Balls off the table now, in the order they fell.
    pub fn tray(&self) -> Vec<usize> {
        let mut off = self.replica.tray();
        let live = self.shot().map(|p| p.pocketed_so_far()).unwrap_or_default();
        let order = |b: usize| match live.iter().position(|&x| x == b) {
            Some(k) => self.falls + 1 + k as u64,
            None => self.fell.get(b).copied().unwrap_or(0),
        };
        off.sort_by_key(|&b| order(b));
        off
    }

    /// Doubles the speed.
    pub fn faster(&mut self) {
        self.speed = (self.speed * 2.0).min(MAX_SPEED);
    }

    /// Halves the speed.
    pub fn slower(&mut self) {
        self.speed = (self.speed * 0.5).max(MIN_SPEED);
    }

    /// Moves the replay on by `wall_dt` seconds of real time.
    pub fn tick(&mut self, wall_dt: f64) {
        if self.paused || !wall_dt.is_finite() || wall_dt <= 0.0 {
            return;
        }
        if self.shot().is_some() {
            self.replica.tick(wall_dt, self.speed);
            if self.shot().is_none() {
                self.commit();
            }
            return;
        }
        if self.at_end() {
            return;
        }
        self.hold -= wall_dt * self.speed;
        if self.hold <= 0.0 {
            self.begin();
        }
    }

    /// Shows the next shot to its end at once (finishing the one under way first), applying
    /// any commands before it.
    pub fn step(&mut self) {
        if self.shot().is_some() {
            self.finish_shot();
            return;
        }
        while !self.at_end() {
            let is_shot = matches!(self.record.entries[self.next].command, Command::Shot { .. });
            self.begin();
            if is_shot {
                self.finish_shot();
                return;
            }
        }
    }

    /// Goes back to just before the shot being shown, or when none is, the last one shown.
    pub fn step_back(&mut self) {
        let target = if self.shot().is_some() {
            self.next
        } else {
            (0..self.next.min(self.record.entries.len()))
                .rev()
                .find(|&i| matches!(self.record.entries[i].command, Command::Shot { .. }))
                .unwrap_or(0)
        };
        self.seek(target);
    }

    /// Plays every entry before `entry` instantly; the replay then waits there.
    pub fn seek(&mut self, entry: usize) {
        let Ok(mut fresh) = ReplayViewer::new(self.record.clone()) else {
            return;
        };
        fresh.speed = self.speed;
        fresh.paused = self.paused;
        while fresh.next < entry.min(fresh.record.entries.len()) && fresh.stopped.is_none() {
            fresh.begin();
            fresh.finish_shot();
        }
        *self = fresh;
    }

    fn finish_shot(&mut self) {
        if self.shot().is_some() {
            self.replica.skip();
            self.commit();
        }
    }

    /// Starts entry `next`: it is applied, and a shot is shown as it plays; any other
    /// command is done at once.
    fn begin(&mut self) {
        let Some(entry) = self.record.entries.get(self.next) else {
            return;
        };
        self.hold = HOLD;
        let turn = self.game().turn();
        match self.replica.accept(turn, entry.seat, &entry.command) {
            Ok(Some(verdict)) => {
                if verdict.shot.as_ref().map(|s| s.hash) != entry.hash {
                    self.mismatches.push(self.next);
                }
                self.pending = Some(verdict);
                if self.shot().is_none() {
                    self.commit();
                }
            }
            Ok(None) => self.stopped = Some(format!("entry {} is out of turn", self.next)),
            Err(e) => self.stopped = Some(format!("entry {} refused: {e}", self.next)),
        }
    }

    /// Ends entry `next`: its verdict shows and the replay moves on.
    fn commit(&mut self) {
        let Some(verdict) = self.pending.take() else {
            return;
        };
        for &(b, _) in verdict.shot.iter().flat_map(|s| &s.pocketed) {
            self.falls += 1;
            if let Some(slot) = self.fell.get_mut(usize::from(b)) {
                *slot = self.falls;
            }
        }
        self.last_verdict = Some(verdict);
        self.next += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{MotionState, Strike};
    use breakshot_shared::rules::{EightBallRules, Phase, Seat, Settings, Variant};
    use glam::DVec2;

    /// A real game: each turn the shooter places the ball if in hand and shoots up the table.
    pub(crate) fn record(shots: usize) -> GameRecord {
        let variant = Variant::EightBall(EightBallRules::Wpa);
        let mut game = Game::new(variant, Settings::offline(), 11);
        let mut rec = GameRecord::new(variant, Settings::offline(), 11);
        for k in 0..shots {
            let seat = game.to_move();
            if let Phase::Shooting {
                in_hand: Some(_), ..
            } = game.phase()
            {
                let pos = [0.3 + 0.05 * k as f64, 0.3];
                let cmd = Command::PlaceCueBall { pos };
                if game.apply(seat, &cmd).is_ok() {
                    rec.push(seat, cmd, None);
                }
            }
            if let Phase::Deciding { options } = game.phase() {
                let cmd = Command::Decide(options[0]);
                game.apply(seat, &cmd).expect("offered choice");
                rec.push(seat, cmd, None);
                continue;
            }
            if let Phase::Over { .. } = game.phase() {
                break;
            }
            let speed = if k == 0 { 9.0 } else { 3.0 };
            let strike = Strike::at_angle(speed, 88.0 + 3.0 * k as f64, DVec2::ZERO);
            let cmd = Command::Shot { strike, call: None };
            let v = game.apply(seat, &cmd).expect("legal shot");
            rec.push(seat, cmd, v.shot.map(|s| s.hash));
        }
        rec
    }

    fn shots(rec: &GameRecord) -> Vec<usize> {
        (0..rec.entries.len())
            .filter(|&i| matches!(rec.entries[i].command, Command::Shot { .. }))
            .collect()
    }

    fn run_to_end(v: &mut ReplayViewer) {
        for _ in 0..100_000 {
            if v.at_end() && v.shot().is_none() {
                return;
            }
            v.tick(0.05);
        }
        panic!("replay did not end");
    }

    #[test]
    fn playing_a_record_ends_on_the_recorded_game() {
        let rec = record(6);
        let end = rec.replay().expect("record replays");
        let mut v = ReplayViewer::decode(&rec.encode()).expect("decodes");
        assert_eq!(v.position(), (0, rec.entries.len()));
        v.tick(0.5 * HOLD);
        assert!(v.shot().is_none(), "held before the first entry");
        run_to_end(&mut v);
        assert_eq!(v.game(), &end);
        assert!(v.mismatches.is_empty() && v.stopped.is_none());
        let off = end
            .balls()
            .iter()
            .skip(1)
            .filter(|b| b.motion == MotionState::Pocketed);
        assert_eq!(v.tray().len(), off.count());
    }

    #[test]
    fn pausing_stops_the_clock_and_stepping_goes_shot_by_shot() {
        let rec = record(4);
        let mut v = ReplayViewer::new(rec.clone()).expect("valid");
        v.paused = true;
        v.tick(10.0);
        assert_eq!(v.position().0, 0);
        v.step();
        // One step plays everything up to and including the break, and nothing is moving.
        let first = shots(&rec)[0];
        assert_eq!(v.position().0, first + 1);
        assert!(v.shot().is_none());
        let mut g = Game::new(rec.variant, rec.settings, rec.seed);
        for e in &rec.entries[..=first] {
            g.apply(e.seat, &e.command).expect("recorded command");
        }
        assert_eq!(v.game(), &g);
        v.step();
        assert_eq!(v.position().0, shots(&rec)[1] + 1);
        v.step_back();
        assert_eq!(
            v.position().0,
            shots(&rec)[1],
            "back to just before the second shot"
        );
        v.step_back();
        assert_eq!(v.position().0, first, "back to just before the break");
    }

    #[test]
    fn a_tampered_hash_is_reported_and_a_refused_entry_stops_the_replay() {
        let mut rec = record(3);
        let first = shots(&rec)[0];
        rec.entries[first].hash = Some(12345);
        rec.push(Seat::B, Command::PlaceCueBall { pos: [-1.0, -1.0] }, None);
        let mut v = ReplayViewer::new(rec).expect("valid");
        run_to_end(&mut v);
        assert_eq!(v.mismatches, vec![first]);
        assert!(
            v.stopped.as_deref().is_some_and(|s| s.contains("refused")),
            "{:?}",
            v.stopped
        );
    }

    #[test]
    fn garbage_and_other_versions_are_refused() {
        assert!(ReplayViewer::decode(b"not a record").is_err());
        let mut rec = record(1);
        rec.version = RECORD_VERSION + 1;
        assert!(matches!(
            ReplayViewer::new(rec),
            Err(ReplayOpenError::Version(_))
        ));
    }

    #[test]
    fn speed_stays_within_limits() {
        let mut v = ReplayViewer::new(record(1)).expect("valid");
        for _ in 0..10 {
            v.faster();
        }
        assert_eq!(v.speed, MAX_SPEED);
        for _ in 0..20 {
            v.slower();
        }
        assert_eq!(v.speed, MIN_SPEED);
    }
}
