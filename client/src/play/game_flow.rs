//! A game as a screen shows it: the events a [`GameLink`](super::link::GameLink) gives go to
//! the [`Replica`] (the one copy of the game, which applies each accepted command once and
//! plays its shot back), and around it this keeps what the screen shows besides the table:
//! the message line, the pocket called, the shot clock, the players' names, the
//! opponent's live aim, the chat and how a game that ended while away came out.

use breakshot_shared::physics::{BallState, Strike};
use breakshot_shared::protocol::AimAid;
use breakshot_shared::rules::{Choice, Command, Game, InHand, Phase, Seat, TurnId, Verdict};

use super::chat::Chat;
use super::controls::CueMode;
use super::event::{AwayResult, GameEvent};
use super::link::Shown;
use super::replica::{Check, Replica};
use crate::view::hud::Connection;
use crate::view::Playback;

/// What the screen asks of the player here now, read from the rules' [`Phase`] for one seat:
/// wait, shoot or decide. (The rules' `Phase` is what the game waits for, whoever moves;
/// [`CueMode`] is what the mouse may do with the cue ball.)
#[derive(Clone, Debug, PartialEq)]
pub enum Prompt {
    /// Nothing: a shot is playing, it is the opponent's turn, or the game is over.
    Wait,
    /// Shoot (placing the cue ball first if `in_hand`); `call` says a pocket must be called.
    Shoot {
        /// The seat to shoot.
        seat: Seat,
        /// Where the cue ball may be placed first, if it is in hand.
        in_hand: Option<InHand>,
        /// The shot must name a pocket.
        call: bool,
    },
    /// Pick one of the rules' options.
    Decide {
        /// The seat to choose.
        seat: Seat,
        /// The options offered.
        options: Vec<Choice>,
    },
}

impl Prompt {
    /// What the controls may do on this turn: move the cue ball, strike, or only watch.
    pub fn cue_mode(&self) -> CueMode {
        match self {
            Prompt::Shoot {
                in_hand: Some(_), ..
            } => CueMode::InHand,
            Prompt::Shoot { .. } => CueMode::Aiming,
            Prompt::Wait | Prompt::Decide { .. } => CueMode::Watching,
        }
    }
}

/// A game screen's state: the [`Replica`] of the game, and what the screen shows around it.
pub struct GameFlow {
    replica: Replica,
    /// What the rules said of the last command, once the side that decides has judged it.
    pub last_verdict: Option<Verdict>,
    /// The verdict of the command accepted last, until the deciding side's judgement
    /// arrives.
    pending_verdict: Option<Verdict>,
    /// The line of text under the table.
    pub message: String,
    /// The connection state shown.
    pub connection: Connection,
    /// The pocket called for the next shot.
    pub call: Option<u8>,
    /// Seconds left on the shot clock, counting down.
    pub shot_clock: Option<f64>,
    /// The aiming aids the room allows.
    pub aim_aid: AimAid,
    /// The game as it stood when the shot being shown was struck: what the players see
    /// until the balls stop, so the result does not show before the shot does.
    before_shot: Option<Game>,
    /// The game asked back had ended while this player was away: its result.
    pub ended_away: Option<AwayResult>,
    /// The players' names, by seat, once the server has said them.
    pub names: [Option<String>; 2],
    /// The players' ratings, by seat, in a rated room (told on entering, and after the game).
    pub ratings: [Option<i32>; 2],
    /// The room's chat.
    pub chat: Chat,
    /// The last aim the shooter showed: (turn, seat, strike).
    opponent_aim: Option<(TurnId, Seat, Strike)>,
    /// A shot the deciding side's hash did not confirm here, not yet reported: (its turn,
    /// the deciding side's hash).
    desync: Option<(TurnId, u64)>,
}

impl Shown for GameFlow {
    fn shown_game(&self) -> Option<&Game> {
        self.game()
    }

    fn waits_for(&self, seat: Seat) -> bool {
        matches!(
            self.prompt(Some(seat)),
            Prompt::Shoot { .. } | Prompt::Decide { .. }
        )
    }
}

impl GameFlow {
    /// A screen with no game yet.
    pub fn new(connection: Connection) -> GameFlow {
        GameFlow {
            replica: Replica::default(),
            last_verdict: None,
            pending_verdict: None,
            message: String::new(),
            connection,
            call: None,
            shot_clock: None,
            aim_aid: AimAid::Full,
            before_shot: None,
            ended_away: None,
            names: [None, None],
            ratings: [None, None],
            chat: Chat::default(),
            opponent_aim: None,
            desync: None,
        }
    }

    /// The copy of the game shown (its desync count is the one the overlay shows).
    pub fn replica(&self) -> &Replica {
        &self.replica
    }

    /// The game as the rules left it.
    pub fn game(&self) -> Option<&Game> {
        self.replica.game()
    }

    /// The shot being shown.
    pub fn shot(&self) -> Option<&Playback> {
        self.replica.playback()
    }

    /// The game as the players see it: while a shot is shown, the game as it was when the
    /// shot was struck (whose turn, groups, score), else the game as the rules left it.
    pub fn shown_game(&self) -> Option<&Game> {
        match (self.shot(), &self.before_shot) {
            (Some(_), Some(before)) => Some(before),
            _ => self.game(),
        }
    }

    /// Seconds left on the shot clock as shown: never more than the room's limit (the server
    /// gives the next turn its limit plus the time the last shot takes to play out, so the
    /// clock stands full while the balls roll and runs from when they stop), none when the
    /// game is over.
    pub fn shown_shot_clock(&self) -> Option<f64> {
        let game = self.game()?;
        if matches!(game.phase(), Phase::Over { .. }) {
            return None;
        }
        let left = self.shot_clock?;
        Some(match game.settings().shot_clock {
            Some(limit) => left.min(f64::from(limit)),
            None => left,
        })
    }

    /// Where the other player is aiming, to draw their cue: only while the table waits for
    /// their shot on the turn they aimed on (not ours: `me`), and no shot is playing.
    pub fn opponent_aim(&self, me: Option<Seat>) -> Option<Strike> {
        let (turn, seat, strike) = self.opponent_aim?;
        let game = self.game()?;
        let waiting = game.turn() == turn && game.to_move() == seat && self.shot().is_none();
        (waiting && me != Some(seat)).then_some(strike)
    }

    /// The judgement to show: none while a shot is shown (fouls, turn changes and pockets
    /// appear when the balls stop, or at once when the shot is skipped).
    pub fn shown_verdict(&self) -> Option<&Verdict> {
        match self.shot() {
            Some(_) => None,
            None => self.last_verdict.as_ref(),
        }
    }

    /// Applies one event from the link.
    pub fn handle(&mut self, event: GameEvent) {
        match &event {
            GameEvent::Started(game) => {
                self.last_verdict = None;
                self.pending_verdict = None;
                self.call = None;
                // A game that already has commands is one coming back (a rejoin, a restarted
                // host); a new one needs no words: the hint bar shows what to do.
                self.message = if game.turn() > 0 {
                    "Game resumed".into()
                } else {
                    String::new()
                };
            }
            GameEvent::Accepted {
                turn,
                seat,
                command,
            } => {
                self.pending_verdict = self.accepted(*turn, *seat, command);
                return;
            }
            GameEvent::Decided {
                turn,
                seat,
                command,
            } => {
                // The rules here decide: their verdict is the judgement.
                if let Some(v) = self.accepted(*turn, *seat, command) {
                    self.last_verdict = Some(v);
                }
                return;
            }
            GameEvent::Judged { .. } => {
                self.last_verdict = self.pending_verdict.take();
                if let Some(Check::Desync { turn, server, .. }) = self.replica.handle(&event) {
                    self.desync = Some((turn, server));
                }
                return;
            }
            GameEvent::Refused(why) => self.message = format!("Refused: {why}"),
            GameEvent::Connection(c) => self.connection = c.clone(),
            GameEvent::ShotClock(s) => self.shot_clock = s.filter(|s| s.is_finite()),
            GameEvent::AimAid(policy) => self.aim_aid = *policy,
            GameEvent::EndedAway(result) => self.ended_away = Some(result.clone()),
            GameEvent::Seated { seat, name } => {
                self.names[usize::from(*seat == Seat::B)] = Some(name.clone());
            }
            GameEvent::Chat(line) => self.chat.heard(&line.from, &line.text),
            GameEvent::Rated {
                seat,
                before,
                after,
            } => {
                self.ratings[usize::from(*seat == Seat::B)] = Some(*after);
                let who = crate::view::hud::named(&seat.to_string(), &self.names);
                self.chat.heard(
                    "",
                    &format!("{who}'s rating: {before} -> {after} ({:+})", after - before),
                );
            }
            GameEvent::Ratings(ratings) => self.ratings = ratings.map(Some),
            GameEvent::Aim { turn, seat, strike } => {
                self.opponent_aim = Some((*turn, *seat, *strike));
            }
        }
        self.replica.handle(&event);
    }

    /// Applies an accepted command to the replica; a shot starts playing at once.
    fn accepted(&mut self, turn: TurnId, seat: Seat, command: &Command) -> Option<Verdict> {
        if matches!(command, Command::Shot { .. }) {
            self.call = None;
            self.before_shot = self.game().cloned();
        }
        self.message = String::new();
        self.replica.accept(turn, seat, command).ok().flatten()
    }

    /// A shot whose deciding side's hash this copy of the game did not reach, once: (its
    /// turn, the deciding side's hash), for the server's operator to count.
    pub fn take_desync(&mut self) -> Option<(TurnId, u64)> {
        self.desync.take()
    }

    /// Moves the shot being shown on, and the clocks down.
    pub fn tick(&mut self, wall_dt: f64) {
        let dt = if wall_dt.is_finite() {
            wall_dt.max(0.0)
        } else {
            0.0
        };
        // The server pauses the clock while a player is away and says when it runs again.
        let paused = matches!(
            self.connection,
            Connection::OpponentLeft { .. } | Connection::Reconnecting | Connection::Closed(_)
        );
        if let (Some(s), false) = (&mut self.shot_clock, paused) {
            *s = (*s - dt).max(0.0);
        }
        if let Connection::OpponentLeft { seconds_left } = &mut self.connection {
            *seconds_left = (*seconds_left - dt).max(0.0);
        }
        self.chat.tick(dt);
        self.replica.tick(wall_dt, 1.0);
    }

    /// Stops showing the shot.
    pub fn skip(&mut self) {
        self.replica.skip();
    }

    /// The balls as shown now.
    pub fn balls(&self) -> Vec<BallState> {
        self.replica.balls()
    }

    /// Balls off the table now.
    pub fn tray(&self) -> Vec<usize> {
        self.replica.tray()
    }

    /// What `me` (None: whoever is to move) may do now.
    pub fn prompt(&self, me: Option<Seat>) -> Prompt {
        let Some(game) = self.game() else {
            return Prompt::Wait;
        };
        if self.shot().is_some() {
            return Prompt::Wait;
        }
        let seat = game.to_move();
        if me.is_some_and(|m| m != seat) {
            return Prompt::Wait;
        }
        match game.phase() {
            Phase::Shooting { in_hand, .. } => Prompt::Shoot {
                seat,
                in_hand: *in_hand,
                call: game.needs_call(),
            },
            Phase::Deciding { options } => Prompt::Decide {
                seat,
                options: options.clone(),
            },
            Phase::Over { .. } => Prompt::Wait,
        }
    }

    /// What the player here may do: as [`GameFlow::prompt`], but nothing until the opponent is
    /// seated, and nothing for a spectator (`watching`).
    pub fn prompt_here(&self, me: Option<Seat>, watching: bool) -> Prompt {
        if self.connection == Connection::WaitingForOpponent || watching {
            Prompt::Wait
        } else {
            self.prompt(me)
        }
    }

    /// The shot command for `strike`, with the called pocket; None (and a message) if a
    /// call is needed and missing.
    pub fn shot_command(&mut self, strike: Strike) -> Option<Command> {
        let game = self.game()?;
        if game.needs_call() && self.call.is_none() {
            self.message = "Call a pocket first: click the pocket".into();
            return None;
        }
        Some(Command::Shot {
            strike,
            call: self.call,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::{GameLink, LocalLink};
    use breakshot_shared::physics::simulations_on_this_thread;
    use breakshot_shared::rules::{EightBallRules, Settings, Variant};
    use glam::DVec2;

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

    fn send(link: &mut LocalLink, flow: &mut GameFlow, seat: Seat, command: Command) {
        let game = flow.game().expect("a game").clone();
        link.send(&game, seat, command);
        drain(link, flow);
    }

    #[test]
    fn a_rated_room_s_ratings_stand_beside_the_names_and_the_game_s_end_says_the_change() {
        let (_, mut flow) = local();
        flow.handle(GameEvent::Seated {
            seat: Seat::B,
            name: "ben".into(),
        });
        flow.handle(GameEvent::Ratings([1500, 1500]));
        assert_eq!(flow.ratings, [Some(1500), Some(1500)], "from the start");
        flow.handle(GameEvent::Rated {
            seat: Seat::B,
            before: 1500,
            after: 1338,
        });
        assert_eq!(flow.ratings, [Some(1500), Some(1338)]);
        let said: Vec<String> = flow.chat.lines().map(|l| l.text.clone()).collect();
        assert_eq!(said, ["ben's rating: 1500 -> 1338 (-162)"]);
    }

    #[test]
    fn nobody_here_moves_until_the_opponent_is_seated_and_a_spectator_never_does() {
        let (_, mut flow) = local();
        let shoot = flow.prompt_here(Some(Seat::A), false);
        assert!(matches!(
            shoot,
            Prompt::Shoot {
                seat: Seat::A,
                in_hand: Some(_),
                ..
            }
        ));
        assert_eq!(
            shoot.cue_mode(),
            CueMode::InHand,
            "the break: cue ball in hand"
        );
        assert_eq!(
            flow.prompt_here(Some(Seat::B), false),
            Prompt::Wait,
            "not B's turn"
        );
        assert_eq!(flow.prompt_here(None, true), Prompt::Wait, "a spectator");
        flow.connection = Connection::WaitingForOpponent;
        assert_eq!(flow.prompt_here(Some(Seat::A), false), Prompt::Wait);
        assert_eq!(Prompt::Wait.cue_mode(), CueMode::Watching);
    }

    #[test]
    fn a_shot_is_shown_then_the_rules_table_appears() {
        let (mut link, mut flow) = local();
        let Prompt::Shoot {
            seat,
            in_hand,
            call,
        } = flow.prompt(None)
        else {
            panic!("the breaker shoots first")
        };
        assert_eq!((seat, call), (Seat::A, false));
        assert_eq!(in_hand, Some(InHand::Kitchen));
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let cmd = flow.shot_command(strike).expect("no call on the break");
        send(&mut link, &mut flow, seat, cmd);
        assert!(flow.shot().is_some());
        assert_eq!(
            flow.prompt(None),
            Prompt::Wait,
            "nobody moves while balls roll"
        );
        assert_eq!(flow.replica().desyncs(), 0);
        let rack = flow.balls();
        flow.tick(0.01);
        assert_ne!(flow.balls()[0].pos, rack[0].pos, "the cue ball is moving");
        flow.tick(1e9);
        assert!(flow.shot().is_none());
        assert_eq!(flow.game().expect("game").balls(), flow.balls().as_slice());
        assert!(flow.last_verdict.is_some());
    }

    #[test]
    fn the_result_of_a_shot_shows_when_the_balls_stop_or_the_shot_is_skipped() {
        for skip in [false, true] {
            let (mut link, mut flow) = local();
            let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
            let cmd = flow.shot_command(strike).expect("no call on the break");
            let before = flow.game().expect("a game").clone();
            send(&mut link, &mut flow, Seat::A, cmd);
            assert!(flow.last_verdict.is_some(), "the rules here judged at once");
            flow.tick(0.05);
            assert!(flow.shot().is_some(), "the balls roll");
            assert_eq!(
                flow.shown_verdict(),
                None,
                "no verdict while the balls roll"
            );
            let shown = flow.shown_game().expect("a game");
            assert_eq!(shown.turn(), before.turn(), "the turn shown is the shot's");
            assert_eq!(shown.to_move(), before.to_move());
            if skip {
                flow.skip();
            } else {
                flow.tick(1e9);
            }
            assert!(flow.shot().is_none());
            assert_eq!(flow.shown_verdict(), flow.last_verdict.as_ref());
            assert!(flow.shown_verdict().is_some());
            assert_eq!(flow.shown_game(), flow.game());
        }
    }

    #[test]
    fn a_shot_is_simulated_once_by_a_screen() {
        for (name, deciding_elsewhere) in [("local", false), ("network", true)] {
            let (mut link, mut flow) = local();
            let game = flow.game().expect("game").clone();
            let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
            let command = Command::Shot { strike, call: None };
            let before = simulations_on_this_thread();
            if deciding_elsewhere {
                // As a network link gives it: accepted, then judged with the server's hash
                // (computed beforehand, outside the count).
                flow.handle(GameEvent::Accepted {
                    turn: game.turn(),
                    seat: Seat::A,
                    command,
                });
                flow.handle(GameEvent::Judged {
                    hash: None,
                    game: None,
                });
            } else {
                send(&mut link, &mut flow, Seat::A, command);
            }
            while flow.shot().is_some() {
                flow.tick(0.05);
            }
            assert_eq!(simulations_on_this_thread() - before, 1, "{name}");
        }
    }

    #[test]
    fn a_seat_waits_for_the_other_seats_turn() {
        let (_, flow) = local();
        assert_eq!(flow.prompt(Some(Seat::B)), Prompt::Wait);
        assert!(matches!(flow.prompt(Some(Seat::A)), Prompt::Shoot { .. }));
    }

    #[test]
    fn refusals_change_nothing_and_are_shown() {
        let (mut link, mut flow) = local();
        let before = flow.game().cloned();
        send(
            &mut link,
            &mut flow,
            Seat::B,
            Command::PlaceCueBall { pos: [0.5, 0.3] },
        );
        assert_eq!(flow.game().cloned(), before);
        assert!(flow.message.starts_with("Refused"), "{}", flow.message);
    }

    #[test]
    fn a_judgement_with_another_hash_counts_a_desync_and_goes_on_from_the_server_s_game() {
        let (_, mut flow) = local();
        let mut other = flow.game().expect("game").clone();
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let command = Command::Shot { strike, call: None };
        let verdict = other.apply(Seat::A, &command).expect("legal");
        let hash = verdict.shot.as_ref().map(|s| s.hash);
        flow.handle(GameEvent::Accepted {
            turn: 0,
            seat: Seat::A,
            command: command.clone(),
        });
        flow.handle(GameEvent::Judged {
            hash,
            game: Some(Box::new(other.clone())),
        });
        assert_eq!(
            flow.replica().desyncs(),
            0,
            "the same engine gives the same hash"
        );
        assert_eq!(flow.replica().confirmed(), 1);
        assert_eq!(flow.game(), Some(&other));

        let (_, mut flow) = local();
        flow.handle(GameEvent::Accepted {
            turn: 0,
            seat: Seat::A,
            command,
        });
        // The server's game after the shot differs too (here: it has heard a concession).
        let mut decided = other.clone();
        decided
            .apply(Seat::B, &Command::Concede)
            .expect("a concession");
        flow.handle(GameEvent::Judged {
            hash: hash.map(|h| h ^ 1),
            game: Some(Box::new(decided.clone())),
        });
        assert_eq!(flow.replica().desyncs(), 1);
        // Counted once, then the game goes on from the table every other player sees.
        assert_eq!(flow.game(), Some(&decided));
        assert_ne!(flow.game(), Some(&other));
    }

    #[test]
    fn a_nine_ball_game_with_called_shots_asks_for_a_pocket_after_the_break() {
        let settings = Settings {
            call_every_shot: true,
            ..Settings::offline()
        };
        let mut link = LocalLink::new(Variant::NineBall, settings, 5);
        let mut flow = GameFlow::new(Connection::Offline);
        drain(&mut link, &mut flow);
        let strike = Strike::at_angle(9.0, 90.0, DVec2::ZERO);
        let cmd = flow.shot_command(strike).expect("no call on the break");
        send(&mut link, &mut flow, Seat::A, cmd);
        flow.skip();
        let Prompt::Shoot { seat, call, .. } = flow.prompt(None) else {
            panic!("a shot is due after the break: {:?}", flow.prompt(None))
        };
        assert!(call, "every shot names a pocket");
        let gentle = Strike::at_angle(1.0, 90.0, DVec2::ZERO);
        assert_eq!(flow.shot_command(gentle), None, "refused without a call");
        flow.call = Some(0);
        let cmd = flow.shot_command(gentle).expect("called");
        let game = flow.game().expect("game").clone();
        assert_eq!(game.check(seat, &cmd), Ok(()), "the rules accept it");
    }

    #[test]
    fn no_call_is_asked_on_the_break() {
        let (_, flow) = local();
        assert!(!flow.game().expect("game").needs_call());
    }

    #[test]
    fn clocks_count_down_and_stop_at_zero() {
        let (_, mut flow) = local();
        flow.handle(GameEvent::ShotClock(Some(30.0)));
        flow.tick(4.0);
        assert_eq!(flow.shot_clock, Some(26.0));
        flow.tick(100.0);
        assert_eq!(flow.shot_clock, Some(0.0));
        flow.handle(GameEvent::Connection(Connection::OpponentLeft {
            seconds_left: 10.0,
        }));
        flow.tick(4.0);
        assert_eq!(
            flow.connection,
            Connection::OpponentLeft { seconds_left: 6.0 }
        );
        flow.tick(100.0);
        assert_eq!(
            flow.connection,
            Connection::OpponentLeft { seconds_left: 0.0 }
        );
        flow.handle(GameEvent::ShotClock(None));
        assert_eq!(flow.shot_clock, None);
    }

    #[test]
    fn rematch_starts_a_new_game() {
        let (mut link, mut flow) = local();
        send(&mut link, &mut flow, Seat::A, Command::Concede);
        assert_eq!(flow.prompt(None), Prompt::Wait);
        link.rematch();
        drain(&mut link, &mut flow);
        assert!(matches!(flow.prompt(None), Prompt::Shoot { .. }));
    }

    #[test]
    fn a_new_game_leaves_the_hint_bar_and_a_game_coming_back_says_it_is_resumed() {
        let (mut link, mut flow) = local();
        assert_eq!(
            flow.message, "",
            "a new game says nothing over the hint bar"
        );
        let game = flow.game().expect("a game").clone();
        let cue = game.balls()[0].pos;
        let strike = breakshot_shared::physics::Strike {
            speed: 3.0,
            dir: game.balls()[1].pos - cue,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        send(
            &mut link,
            &mut flow,
            Seat::A,
            Command::Shot { strike, call: None },
        );
        let played = flow.game().expect("a game").clone();
        assert!(played.turn() > 0);
        let mut back = GameFlow::new(Connection::Connecting);
        back.handle(GameEvent::Started(Box::new(played)));
        assert_eq!(back.message, "Game resumed");
    }

    #[test]
    fn a_game_that_ended_while_away_is_shown_as_won_or_lost_for_this_seat() {
        use crate::play::AwayResult;
        let mut flow = GameFlow::new(Connection::Connecting);
        let lost = AwayResult::for_seat(Seat::A, Some(Seat::B), "A conceded");
        flow.handle(GameEvent::EndedAway(lost.clone()));
        assert_eq!(flow.ended_away, Some(lost.clone()));
        assert_eq!(flow.prompt(Some(Seat::A)), Prompt::Wait);
        let [headline, why] = lost.lines();
        assert_eq!(headline, "You lost");
        assert!(why.ends_with("away: A conceded"), "{why}");
        let won = AwayResult::for_seat(Seat::B, Some(Seat::B), "A conceded");
        assert_eq!(won.lines()[0], "You won");
        assert_eq!(AwayResult::for_seat(Seat::B, None, "stalemate").won, None);
    }

    #[test]
    fn the_shot_clock_shown_never_passes_its_limit_stops_while_away_and_ends_with_the_game() {
        use breakshot_shared::rules::{EightBallRules, Settings, Variant};
        let settings = Settings::online();
        let limit = f64::from(settings.shot_clock.expect("online games have a clock"));
        let game = Game::new(Variant::EightBall(EightBallRules::Wpa), settings, 1);
        let mut flow = GameFlow::new(Connection::Connected);
        flow.handle(GameEvent::Started(Box::new(game.clone())));
        // The next turn's clock includes the last shot's animation: it stands full meanwhile.
        flow.handle(GameEvent::ShotClock(Some(limit + 8.0)));
        assert_eq!(flow.shown_shot_clock(), Some(limit));
        flow.tick(10.0);
        assert_eq!(flow.shown_shot_clock(), Some(limit - 2.0));
        // While the opponent is away the server holds the clock: so does the screen.
        flow.handle(GameEvent::Connection(Connection::OpponentLeft {
            seconds_left: 120.0,
        }));
        flow.tick(5.0);
        assert_eq!(flow.shown_shot_clock(), Some(limit - 2.0));
        // At game over there is no clock.
        let mut over = game;
        over.apply(over.to_move(), &Command::Concede)
            .expect("a concession");
        flow.handle(GameEvent::Started(Box::new(over)));
        assert_eq!(flow.shown_shot_clock(), None);
    }
}
