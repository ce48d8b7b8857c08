//! The client's one copy of the game. Every accepted command is applied here once, with the
//! same rules and physics as the side that decides; a shot's verdict carries its trajectory,
//! which is played back as it is, so a shot is simulated once per client. The deciding
//! side's hash then confirms the shot bit for bit, or counts a desync. The window, the bot,
//! the replay viewer's checks and the tests all read this copy.
//!
//! A load run's bots stand for players on machines of their own, so a copy may check only
//! one shot in N ([`Replica::checking_every`]): the others are not simulated here, and the
//! game the deciding side sends with its judgement (`ShotResolved`) is taken as it is.

use breakshot_shared::physics::BallState;
use breakshot_shared::protocol::ServerMessage;
use breakshot_shared::rules::snooker::table::LAST_RED;
use breakshot_shared::rules::{
    is_off_table, Command, Game, Phase, RuleError, Seat, TurnId, Verdict,
};

use super::event::{game_events, GameEvent};
use crate::view::Playback;

/// What the replica learned from an event.
#[derive(Clone, Debug, PartialEq)]
pub enum Check {
    /// A shot was simulated here; its hash is `hash`.
    Predicted {
        /// The turn the shot was played on.
        turn: TurnId,
        /// The hash of the table at rest, as computed here.
        hash: u64,
    },
    /// The deciding side's hash equals the one computed here.
    Confirmed {
        /// The turn the shot was played on.
        turn: TurnId,
    },
    /// The deciding side's result differs from the one here (or the rules here refused a
    /// command it accepted).
    Desync {
        /// The turn of the command.
        turn: TurnId,
        /// The hash computed here, if the command was a shot the rules here played.
        local: Option<u64>,
        /// The deciding side's hash (0 for a refused command).
        server: u64,
    },
}

/// See the module documentation.
#[derive(Clone, Debug, Default)]
pub struct Replica {
    game: Option<Game>,
    /// The last shot, as it is being shown.
    playback: Option<Playback>,
    /// The turn and hash of the last shot played here, until the deciding side's hash.
    predicted: Option<(TurnId, Option<u64>)>,
    confirmed: u32,
    desyncs: u32,
    shots: u32,
    /// Shots left unchecked between two checked ones (0: every shot is checked).
    unchecked_between: u32,
    /// A shot was not simulated here: the deciding side's judgement brings the game after
    /// it.
    awaiting: bool,
    /// Shots not simulated here.
    unchecked: u32,
}

impl Replica {
    /// The game as the rules left it after the last accepted command.
    pub fn game(&self) -> Option<&Game> {
        self.game.as_ref()
    }

    /// The shot being shown, if one is.
    pub fn playback(&self) -> Option<&Playback> {
        self.playback.as_ref()
    }

    /// Shots whose hash was confirmed.
    pub fn confirmed(&self) -> u32 {
        self.confirmed
    }

    /// Shots (or commands) on which this copy and the deciding side disagreed.
    pub fn desyncs(&self) -> u32 {
        self.desyncs
    }

    /// Shots applied here since the replica was made.
    pub fn shots(&self) -> u32 {
        self.shots
    }

    /// This copy simulates and checks the first shot and then one in `n` (every shot for
    /// 0 or 1); the game after each other shot is the one the deciding side sends with its
    /// result (the judgement, [`Replica::judge`]). Until it comes the copy has no game.
    pub fn checking_every(mut self, n: u32) -> Replica {
        self.unchecked_between = n.saturating_sub(1);
        self
    }

    /// Shots taken on the deciding side's word, not simulated here.
    pub fn unchecked(&self) -> u32 {
        self.unchecked
    }

    /// Whether the game waits for `seat`.
    pub fn waits_for(&self, seat: Seat) -> bool {
        self.game
            .as_ref()
            .is_some_and(|g| g.to_move() == seat && !matches!(g.phase(), Phase::Over { .. }))
    }

    /// Applies what a server message says happened, as seen from `me`.
    pub fn observe(&mut self, msg: &ServerMessage, me: Option<Seat>) -> Vec<Check> {
        game_events(msg, me)
            .iter()
            .filter_map(|e| self.handle(e))
            .collect()
    }

    /// Applies one game event; events about anything but the game are ignored.
    pub fn handle(&mut self, event: &GameEvent) -> Option<Check> {
        match event {
            GameEvent::Started(game) => {
                self.start((**game).clone());
                None
            }
            GameEvent::Accepted {
                turn,
                seat,
                command,
            }
            | GameEvent::Decided {
                turn,
                seat,
                command,
            } => match self.accept(*turn, *seat, command) {
                Ok(_) => None,
                Err(_) => Some(Check::Desync {
                    turn: *turn,
                    local: None,
                    server: 0,
                }),
            },
            GameEvent::Judged { hash, game } => self.judge(*hash, game.as_deref()),
            _ => None,
        }
    }

    /// A new game from this state (first game, rematch, or back in after a reconnect).
    pub fn start(&mut self, game: Game) {
        self.game = Some(game);
        self.playback = None;
        self.predicted = None;
        self.awaiting = false;
    }

    /// Applies an accepted command once; a shot starts playing at once, from the
    /// trajectory the rules computed. Returns the verdict, or why the rules here refuse
    /// the command (counted as a desync: the deciding side accepted it). A command for
    /// another turn (one the snapshot already holds) is ignored.
    pub fn accept(
        &mut self,
        turn: TurnId,
        seat: Seat,
        command: &Command,
    ) -> Result<Option<Verdict>, RuleError> {
        let Some(game) = &mut self.game else {
            return Ok(None);
        };
        if game.turn() != turn {
            return Ok(None);
        }
        self.playback = None;
        self.predicted = None;
        let shot = matches!(command, Command::Shot { .. });
        if shot {
            self.shots += 1;
            if (self.shots - 1) % (self.unchecked_between + 1) != 0 {
                // Not simulated: the deciding side's result brings the game after it.
                self.unchecked += 1;
                self.game = None;
                self.awaiting = true;
                return Ok(None);
            }
        }
        // The ball struck, asked before the shot changes who is to move.
        let cue = game.cue_ball();
        match game.apply(seat, command) {
            Ok(mut verdict) => {
                if shot {
                    self.predicted = Some((turn, verdict.shot.as_ref().map(|s| s.hash)));
                }
                self.playback = verdict.outcome.take().map(|o| Playback::new(o, cue));
                Ok(Some(verdict))
            }
            Err(e) => {
                self.desyncs += 1;
                Err(e)
            }
        }
    }

    /// The deciding side's judgement of the last command: a shot's hash must match the
    /// one computed here. The copy goes on from `decided`, the deciding side's game after
    /// the shot, when it came with the judgement and the copy has no game of its own to
    /// trust: after a shot not simulated here, or after a difference (the desync is
    /// counted once, and the next commands are played on the table every other player
    /// sees).
    pub fn judge(&mut self, hash: Option<u64>, decided: Option<&Game>) -> Option<Check> {
        let server = hash?;
        if std::mem::take(&mut self.awaiting) {
            if let Some(game) = decided {
                self.start(game.clone());
            }
            return None;
        }
        let (turn, local) = self.predicted.take()?;
        if local == Some(server) {
            self.confirmed += 1;
            Some(Check::Confirmed { turn })
        } else {
            self.desyncs += 1;
            if let Some(game) = decided {
                self.game = Some(game.clone());
            }
            Some(Check::Desync {
                turn,
                local,
                server,
            })
        }
    }

    /// The last shot's prediction, while its judgement is awaited.
    pub fn prediction(&self) -> Option<Check> {
        match self.predicted {
            Some((turn, Some(hash))) => Some(Check::Predicted { turn, hash }),
            _ => None,
        }
    }

    /// Moves the shot being shown on by `wall_dt` seconds at `speed` times real speed; it
    /// is dropped when it has ended, and the rules' table shows.
    pub fn tick(&mut self, wall_dt: f64, speed: f64) {
        if let Some(p) = &mut self.playback {
            p.advance(wall_dt, speed);
            if p.finished() {
                self.playback = None;
            }
        }
    }

    /// Stops showing the shot: the rules' table shows.
    pub fn skip(&mut self) {
        self.playback = None;
    }

    /// The balls as shown now: the shot playing, or the table the rules left.
    pub fn balls(&self) -> Vec<BallState> {
        match (&self.playback, &self.game) {
            (Some(p), _) => p.balls(),
            (None, Some(g)) => g.balls().to_vec(),
            (None, None) => Vec::new(),
        }
    }

    /// Object balls off the table as shown now: every ball but the one struck (and, in a
    /// short snooker frame, not the reds it never racked).
    pub fn tray(&self) -> Vec<usize> {
        let balls = self.balls();
        let cue = self.game.as_ref().map_or(0, Game::cue_ball);
        let unused = |b: usize| {
            let reds = self.game.as_ref().and_then(Game::snooker).map(|m| m.reds);
            reds.is_some_and(|reds| b > usize::from(reds) && b <= usize::from(LAST_RED))
        };
        (0..balls.len())
            .filter(|&b| b != cue && is_off_table(&balls[b]) && !unused(b))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::GameFlow;
    use crate::test_games::eight_ball;
    use crate::view::hud::Connection;
    use breakshot_shared::physics::{simulations_on_this_thread, Strike};
    use breakshot_shared::protocol::{command_of, Ruling};
    use glam::DVec2;

    /// A break, as a server announces it: accepted, then resolved with `hash` and the game
    /// after it.
    fn announced_break(game: &Game, hash: u64) -> [ServerMessage; 2] {
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let mut after = game.clone();
        after
            .apply(Seat::A, &Command::Shot { strike, call: None })
            .expect("legal break");
        let ruling = Ruling {
            foul: false,
            reasons: Vec::new(),
            pocketed: Vec::new(),
            next: Seat::A,
        };
        [
            ServerMessage::ShotAccepted {
                turn: game.turn(),
                seat: Seat::A,
                command: Command::Shot { strike, call: None },
            },
            ServerMessage::ShotResolved {
                turn: game.turn(),
                hash,
                game: Box::new(after),
                ruling,
            },
        ]
    }

    /// The hash the deciding side computes for the break.
    fn true_hash(game: &Game) -> u64 {
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let mut decider = game.clone();
        let verdict = decider
            .apply(Seat::A, &Command::Shot { strike, call: None })
            .expect("legal break");
        verdict.shot.expect("a shot").hash
    }

    #[test]
    fn a_shot_is_simulated_once_and_confirmed() {
        let game = eight_ball(4);
        let hash = true_hash(&game);
        let mut replica = Replica::default();
        replica.start(game.clone());
        let messages = announced_break(&game, hash);
        let before = simulations_on_this_thread();
        let mut checks = Vec::new();
        for msg in messages {
            checks.extend(replica.observe(&msg, Some(Seat::B)));
        }
        while replica.playback().is_some() {
            replica.tick(0.05, 1.0);
        }
        assert_eq!(simulations_on_this_thread() - before, 1);
        assert_eq!(checks, vec![Check::Confirmed { turn: 0 }]);
        assert_eq!((replica.confirmed(), replica.desyncs()), (1, 0));
    }

    #[test]
    fn the_screen_and_the_bot_count_desyncs_in_the_same_replica() {
        let game = eight_ball(4);
        let wrong = true_hash(&game) ^ 1;
        // The bot and the tests' player feed server messages to a replica...
        let mut bot = Replica::default();
        bot.start(game.clone());
        // ...and a screen hears the same messages as game events through its link.
        let mut screen = GameFlow::new(Connection::Connected);
        screen.handle(GameEvent::Started(Box::new(game.clone())));
        for msg in announced_break(&game, wrong) {
            bot.observe(&msg, Some(Seat::A));
            for event in game_events(&msg, Some(Seat::A)) {
                screen.handle(event);
            }
        }
        // The overlay prints `screen.replica().desyncs()`; the bot reports `desyncs()`.
        assert_eq!(bot.desyncs(), 1);
        assert_eq!(screen.replica().desyncs(), bot.desyncs());
        assert_eq!(screen.replica().game(), bot.game());
        // The screen reports it to the server once, with the server's hash.
        assert_eq!(screen.take_desync(), Some((game.turn(), wrong)));
        assert_eq!(screen.take_desync(), None);
    }

    #[test]
    fn a_confirmed_shot_leaves_nothing_to_report() {
        let game = eight_ball(4);
        let mut screen = GameFlow::new(Connection::Connected);
        screen.handle(GameEvent::Started(Box::new(game.clone())));
        for msg in announced_break(&game, true_hash(&game)) {
            for event in game_events(&msg, Some(Seat::A)) {
                screen.handle(event);
            }
        }
        assert_eq!(screen.replica().desyncs(), 0);
        assert_eq!(screen.take_desync(), None);
    }

    #[test]
    fn a_copy_checking_one_shot_in_three_simulates_those_and_takes_the_server_s_game_after_the_others(
    ) {
        // The deciding side: a game played shot after shot with its messages.
        let mut server = eight_ball(4);
        let mut replica = Replica::default().checking_every(3);
        replica.start(server.clone());
        let (mut simulated, mut confirmed) = (Vec::new(), 0);
        let mut chooser = crate::play::Chooser::new(1);
        while simulated.len() < 7 {
            let seat = server.to_move();
            let msg = chooser.choose(&server).expect("a move");
            let (_, command) = command_of(&msg, None).expect("a command");
            if !matches!(command, Command::Shot { .. }) {
                // Placing the cue ball, a decision: applied on both sides alike.
                let turn = server.turn();
                replica
                    .accept(turn, seat, &command)
                    .expect("the same rules");
                server.apply(seat, &command).expect("a legal move");
                continue;
            }
            let turn = server.turn();
            let before = simulations_on_this_thread();
            let verdict = server.apply(seat, &command).expect("a legal shot");
            let on_server = simulations_on_this_thread() - before;
            let accepted = ServerMessage::ShotAccepted {
                turn,
                seat,
                command: command.clone(),
            };
            let resolved = ServerMessage::ShotResolved {
                turn,
                hash: verdict.shot.expect("a shot").hash,
                game: Box::new(server.clone()),
                ruling: Ruling {
                    foul: verdict.foul,
                    reasons: verdict.reasons,
                    pocketed: Vec::new(),
                    next: verdict.next,
                },
            };
            let before = simulations_on_this_thread();
            for msg in [accepted, resolved] {
                if replica
                    .observe(&msg, Some(seat))
                    .contains(&Check::Confirmed { turn })
                {
                    confirmed += 1;
                }
            }
            simulated.push(simulations_on_this_thread() - before == on_server);
            // Whether it simulated the shot or not, the copy goes on from the same game.
            assert_eq!(
                replica.game(),
                Some(&server),
                "after shot {}",
                simulated.len()
            );
        }
        // Shots 1, 4 and 7 are simulated and confirmed; the other four are taken as sent.
        assert!(
            !matches!(server.phase(), Phase::Over { .. }),
            "seven shots in one game"
        );
        assert_eq!(
            simulated,
            [true, false, false, true, false, false, true],
            "which shots were simulated here"
        );
        assert_eq!(
            (confirmed, replica.confirmed(), replica.desyncs()),
            (3, 3, 0)
        );
        assert_eq!((replica.shots(), replica.unchecked()), (7, 4));
    }

    #[test]
    fn a_command_for_another_turn_is_ignored() {
        let game = eight_ball(4);
        let mut replica = Replica::default();
        replica.start(game.clone());
        let stale = replica.accept(game.turn() + 3, Seat::A, &Command::Concede);
        assert_eq!(stale, Ok(None));
        assert_eq!(replica.game(), Some(&game));
        assert_eq!(replica.desyncs(), 0);
    }
}
