//! A game as a screen shows it. Events from a [`GameLink`](super::link::GameLink) are applied
//! to a local copy of the game; a shot is simulated here with the same engine and shown as it
//! plays, its hash checked against the verdict's, and the table the rules leave (balls
//! spotted, re-racks) appears when it ends.

use breakshot_shared::physics::{simulate, BallState, MotionState, Strike};
use breakshot_shared::protocol::AimAid;
use breakshot_shared::rules::{rack, Command, Game, InHand, Phase, Seat, Variant};
use glam::DVec2;

use super::link::{GameEvent, Judgement};
use crate::view::hud::Connection;
use crate::view::playback::Playback;

/// What the player here may do now.
#[derive(Clone, Debug, PartialEq)]
pub enum Turn {
    /// Nothing: a shot is playing, it is the opponent's turn, or the game is over.
    Wait,
    /// Shoot (placing the cue ball first if `in_hand`); `call` says a pocket must be called.
    Shoot {
        seat: Seat,
        in_hand: Option<InHand>,
        call: bool,
    },
    /// Pick one of the rules' options.
    Decide {
        seat: Seat,
        options: Vec<breakshot_shared::rules::Choice>,
    },
}

pub struct GameFlow {
    game: Option<Game>,
    shot: Option<Playback>,
    pub last_verdict: Option<Judgement>,
    /// The hash of the last shot as simulated here, until its judgement arrives.
    predicted: Option<u64>,
    pub message: String,
    pub connection: Connection,
    /// Shots whose hash here differed from the verdict's.
    pub desyncs: u32,
    pub shots: u32,
    /// The pocket called for the next shot.
    pub call: Option<u8>,
    /// Seconds left on the shot clock, counting down.
    pub shot_clock: Option<f64>,
    /// The aiming aids the room allows.
    pub aim_aid: AimAid,
}

impl GameFlow {
    pub fn new(connection: Connection) -> GameFlow {
        GameFlow {
            game: None,
            shot: None,
            last_verdict: None,
            predicted: None,
            message: String::new(),
            connection,
            desyncs: 0,
            shots: 0,
            call: None,
            shot_clock: None,
            aim_aid: AimAid::Full,
        }
    }

    pub fn game(&self) -> Option<&Game> {
        self.game.as_ref()
    }

    pub fn shot(&self) -> Option<&Playback> {
        self.shot.as_ref()
    }

    /// Applies one event from the link.
    pub fn handle(&mut self, event: GameEvent) {
        match event {
            GameEvent::Started(game) => {
                self.game = Some(*game);
                self.shot = None;
                self.last_verdict = None;
                self.call = None;
                self.message = "New game".into();
            }
            GameEvent::Accepted { seat, command } => self.accepted(seat, &command),
            GameEvent::Judged(j) => self.judged(j),
            GameEvent::Refused(why) => self.message = format!("Refused: {why}"),
            GameEvent::Connection(c) => self.connection = c,
            GameEvent::ShotClock(s) => self.shot_clock = s.filter(|s| s.is_finite()),
            GameEvent::AimAid(policy) => self.aim_aid = policy,
        }
    }

    /// Applies an accepted command to the copy here; a shot starts playing at once.
    fn accepted(&mut self, seat: Seat, command: &Command) {
        let Some(game) = &mut self.game else { return };
        self.shot = None;
        self.predicted = None;
        if let Command::Shot { strike, .. } = command {
            if let Ok(outcome) = simulate(&game.shot_for(strike)) {
                self.predicted = Some(outcome.hash());
                self.shot = Some(Playback::new(outcome));
            }
            self.shots += 1;
            self.call = None;
        }
        if game.apply(seat, command).is_err() {
            // The copy here disagrees with the side that decides.
            self.desyncs += 1;
        }
        self.message = String::new();
    }

    /// The judgement of the last command; a shot's hash must match the one computed here.
    fn judged(&mut self, j: Judgement) {
        if let Some(hash) = j.hash {
            if self.predicted.take() != Some(hash) {
                self.desyncs += 1;
            }
        }
        self.last_verdict = Some(j);
    }

    /// Moves the shot being shown on, and the clocks down.
    pub fn tick(&mut self, wall_dt: f64) {
        let dt = if wall_dt.is_finite() {
            wall_dt.max(0.0)
        } else {
            0.0
        };
        if let Some(s) = &mut self.shot_clock {
            *s = (*s - dt).max(0.0);
        }
        if let Connection::OpponentLeft { seconds_left } = &mut self.connection {
            *seconds_left = (*seconds_left - dt).max(0.0);
        }
        if let Some(p) = &mut self.shot {
            p.advance(wall_dt, 1.0);
            if p.finished() {
                self.shot = None;
            }
        }
    }

    pub fn skip(&mut self) {
        self.shot = None;
    }

    /// The balls as shown now.
    pub fn balls(&self) -> Vec<BallState> {
        match (&self.shot, &self.game) {
            (Some(p), _) => p.balls(),
            (None, Some(g)) => g.balls().to_vec(),
            (None, None) => Vec::new(),
        }
    }

    /// Balls off the table now.
    pub fn tray(&self) -> Vec<usize> {
        let balls = self.balls();
        (1..balls.len())
            .filter(|&b| balls[b].motion == MotionState::Pocketed)
            .collect()
    }

    /// What `me` (None: whoever is to move) may do now.
    pub fn turn(&self, me: Option<Seat>) -> Turn {
        let Some(game) = &self.game else {
            return Turn::Wait;
        };
        if self.shot.is_some() {
            return Turn::Wait;
        }
        let seat = game.to_move();
        if me.is_some_and(|m| m != seat) {
            return Turn::Wait;
        }
        match game.phase() {
            Phase::Shooting { in_hand, .. } => Turn::Shoot {
                seat,
                in_hand: *in_hand,
                call: needs_call(game),
            },
            Phase::Deciding { options } => Turn::Decide {
                seat,
                options: options.clone(),
            },
            Phase::Over { .. } => Turn::Wait,
        }
    }

    /// The shot command for `strike`, with the called pocket; None (and a message) if a
    /// call is needed and missing.
    pub fn shot_command(&mut self, strike: Strike) -> Option<Command> {
        let game = self.game.as_ref()?;
        if needs_call(game) && self.call.is_none() {
            self.message = "Call a pocket first: click the pocket".into();
            return None;
        }
        Some(Command::Shot {
            strike,
            call: self.call,
        })
    }
}

/// Whether the shot must name a pocket: 8-ball when shooting at the 8, or every shot when the
/// game is played with called shots. Never on the break.
pub fn needs_call(game: &Game) -> bool {
    if game.is_break() || !matches!(game.variant(), Variant::EightBall(_)) {
        return false;
    }
    game.settings().call_every_shot || game.legal_first_balls() == [8]
}

/// The part of the cloth where the cue ball may go in hand, as scene-coordinate corners
/// (min, max) of a rectangle.
pub fn in_hand_area(game: &Game, area: InHand) -> (DVec2, DVec2) {
    let (w, l) = rack::table_size(game.table());
    match area {
        InHand::Kitchen => (DVec2::ZERO, DVec2::new(w, rack::head_string(game.table()))),
        InHand::Anywhere => (DVec2::ZERO, DVec2::new(w, l)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::link::{GameLink, LocalLink};
    use breakshot_shared::rules::{EightBallRules, Settings};

    fn drain(link: &mut LocalLink, flow: &mut GameFlow) {
        while let Some(e) = link.poll() {
            flow.handle(e);
        }
    }

    fn local() -> (LocalLink, GameFlow) {
        let mut link = LocalLink::new(
            Variant::EightBall(EightBallRules::Wpa),
            Settings::offline(),
            21,
        );
        let mut flow = GameFlow::new(Connection::Offline);
        drain(&mut link, &mut flow);
        (link, flow)
    }

    #[test]
    fn a_shot_is_shown_then_the_rules_table_appears() {
        let (mut link, mut flow) = local();
        let Turn::Shoot {
            seat,
            in_hand,
            call,
        } = flow.turn(None)
        else {
            panic!("the breaker shoots first")
        };
        assert_eq!((seat, call), (Seat::A, false));
        assert_eq!(in_hand, Some(InHand::Kitchen));
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let cmd = flow.shot_command(strike).expect("no call on the break");
        link.send(seat, cmd);
        drain(&mut link, &mut flow);
        assert!(flow.shot().is_some());
        assert_eq!(flow.turn(None), Turn::Wait, "nobody moves while balls roll");
        assert_eq!(flow.desyncs, 0);
        let rack = flow.balls();
        flow.tick(0.01);
        assert_ne!(flow.balls()[0].pos, rack[0].pos, "the cue ball is moving");
        flow.tick(1e9);
        assert!(flow.shot().is_none());
        assert_eq!(flow.game().expect("game").balls(), flow.balls().as_slice());
        assert!(flow.last_verdict.is_some());
    }

    #[test]
    fn a_seat_waits_for_the_other_seats_turn() {
        let (_, flow) = local();
        assert_eq!(flow.turn(Some(Seat::B)), Turn::Wait);
        assert!(matches!(flow.turn(Some(Seat::A)), Turn::Shoot { .. }));
    }

    #[test]
    fn refusals_change_nothing_and_are_shown() {
        let (mut link, mut flow) = local();
        let before = flow.game().cloned();
        link.send(Seat::B, Command::PlaceCueBall { pos: [0.5, 0.3] });
        drain(&mut link, &mut flow);
        assert_eq!(flow.game().cloned(), before);
        assert!(flow.message.starts_with("Refused"), "{}", flow.message);
    }

    #[test]
    fn a_judgement_with_another_hash_counts_a_desync() {
        let (_, mut flow) = local();
        let mut other = flow.game().expect("game").clone();
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let command = Command::Shot { strike, call: None };
        let verdict = other.apply(Seat::A, &command).expect("legal");
        let mut judgement = Judgement::of(&verdict);
        flow.handle(GameEvent::Accepted {
            seat: Seat::A,
            command: command.clone(),
        });
        flow.handle(GameEvent::Judged(judgement.clone()));
        assert_eq!(flow.desyncs, 0, "the same engine gives the same hash");
        assert_eq!(flow.game(), Some(&other));

        let (_, mut flow) = local();
        judgement.hash = judgement.hash.map(|h| h ^ 1);
        flow.handle(GameEvent::Accepted {
            seat: Seat::A,
            command,
        });
        flow.handle(GameEvent::Judged(judgement));
        assert_eq!(flow.desyncs, 1);
    }

    #[test]
    fn kitchen_is_the_head_quarter_of_the_table() {
        let (_, flow) = local();
        let g = flow.game().expect("game");
        let (lo, hi) = in_hand_area(g, InHand::Kitchen);
        assert_eq!(lo, DVec2::ZERO);
        assert!((hi.y - 2.54 / 4.0).abs() < 1e-12 && (hi.x - 1.27).abs() < 1e-12);
        assert!(!needs_call(g), "no call on the break");
    }

    #[test]
    fn clocks_count_down_and_stop_at_zero() {
        let (_, mut flow) = local();
        flow.handle(GameEvent::ShotClock(Some(30.0)));
        flow.handle(GameEvent::Connection(Connection::OpponentLeft {
            seconds_left: 10.0,
        }));
        flow.tick(4.0);
        assert_eq!(flow.shot_clock, Some(26.0));
        assert_eq!(
            flow.connection,
            Connection::OpponentLeft { seconds_left: 6.0 }
        );
        flow.tick(100.0);
        assert_eq!(flow.shot_clock, Some(0.0));
        flow.handle(GameEvent::ShotClock(None));
        assert_eq!(flow.shot_clock, None);
    }

    #[test]
    fn rematch_starts_a_new_game() {
        let (mut link, mut flow) = local();
        link.send(Seat::A, Command::Concede);
        drain(&mut link, &mut flow);
        assert_eq!(flow.turn(None), Turn::Wait);
        link.rematch();
        drain(&mut link, &mut flow);
        assert!(matches!(flow.turn(None), Turn::Shoot { .. }));
    }
}
