//! One player against the computer at this computer. The rules here decide, as for two
//! players taking turns ([`LocalLink`]); the computer's seat asks [`ai::decide`] when the game
//! waits for it, on a thread of its own so the window keeps drawing (in a browser, which has
//! no threads, the same search advances a few simulations each frame: [`ai::Thinking`]), and
//! its command goes through the same link a player's does.

#[cfg(not(target_arch = "wasm32"))]
use std::sync::mpsc::{self, Receiver, TryRecvError};

use breakshot_shared::ai::{self, Level};
use breakshot_shared::rules::{Command, Game, Seat, Settings, Variant};

use super::event::GameEvent;
use super::link::{GameLink, LocalLink, Shown};

/// The least time (of frames, in seconds) the computer is shown thinking, so the player
/// sees it take its turn even when it decides at once.
pub(crate) const SHOWN_THINKING: f64 = 0.8;

/// A seat the computer plays.
pub struct Computer {
    seat: Seat,
    level: Level,
    seed: u64,
    thinking: Option<Thinking>,
}

/// The computer thinking about one table.
struct Thinking {
    /// The game as it stood when the thinking started: an answer to any other is stale.
    game: Game,
    /// Frame time the thinking has been shown.
    shown: f64,
    answer: Answer,
    /// The command decided, once the thread has answered.
    decided: Option<Command>,
    /// The command was handed over.
    sent: bool,
}

/// Where the computer's answer comes from.
enum Answer {
    /// A thread running [`ai::decide`].
    #[cfg(not(target_arch = "wasm32"))]
    Thread(Receiver<Option<Command>>),
    /// The search itself, stepped once a frame.
    #[cfg(target_arch = "wasm32")]
    Steps(ai::Thinking<Option<Command>>),
}

/// The part of a frame (seconds) the stepped search may take: the page keeps drawing at
/// its pace while the computer thinks.
#[cfg(target_arch = "wasm32")]
const THINKING_PER_FRAME: f64 = 0.008;
/// Simulations between looks at the clock (one takes well under a millisecond).
#[cfg(target_arch = "wasm32")]
const SIMULATIONS_PER_STEP: usize = 2;

impl Answer {
    /// The answer, once there is one: `Err` when the search ended without one.
    fn try_take(&mut self) -> Option<Result<Option<Command>, &'static str>> {
        match self {
            #[cfg(not(target_arch = "wasm32"))]
            Answer::Thread(rx) => match rx.try_recv() {
                Ok(answer) => Some(Ok(answer)),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => {
                    Some(Err("the computer's thread ended without an answer"))
                }
            },
            #[cfg(target_arch = "wasm32")]
            Answer::Steps(search) => {
                let now = macroquad::miniquad::date::now;
                let until = now() + THINKING_PER_FRAME;
                loop {
                    if let std::task::Poll::Ready(answer) = search.step(SIMULATIONS_PER_STEP) {
                        return Some(Ok(answer.clone()));
                    }
                    if now() >= until {
                        return None;
                    }
                }
            }
        }
    }
}

impl Thinking {
    /// Starts deciding `game`: on a thread of its own, or stepped in a browser.
    #[cfg(target_arch = "wasm32")]
    fn start(game: Game, level: Level, seed: u64) -> Thinking {
        let answer = Answer::Steps(ai::Thinking::decide(&game, level, seed));
        Thinking {
            game,
            shown: 0.0,
            answer,
            decided: None,
            sent: false,
        }
    }

    /// Starts deciding `game` on a thread of its own.
    #[cfg(not(target_arch = "wasm32"))]
    fn start(game: Game, level: Level, seed: u64) -> Thinking {
        let (tx, answer) = mpsc::channel();
        let table = game.clone();
        let spawned = std::thread::Builder::new()
            .name("computer".into())
            .spawn(move || {
                // The receiver is gone when the game moved on: nothing to do then.
                let _ = tx.send(ai::decide(&table, level, seed));
            });
        if let Err(e) = spawned {
            // The sender was dropped with the closure: the answer reads as a failure.
            tracing::error!(error = %e, "cannot start the computer's thread");
        }
        Thinking {
            game,
            shown: 0.0,
            answer: Answer::Thread(answer),
            decided: None,
            sent: false,
        }
    }
}

impl Computer {
    /// The computer in `seat`, at `level`; `seed` varies its decisions from game to game.
    pub fn new(seat: Seat, level: Level, seed: u64) -> Computer {
        Computer {
            seat,
            level,
            seed,
            thinking: None,
        }
    }

    /// The seat the computer plays.
    pub fn seat(&self) -> Seat {
        self.seat
    }

    /// How strong it plays.
    pub fn level(&self) -> Level {
        self.level
    }

    /// True while it is thinking (its answer not yet handed over).
    pub fn thinking(&self) -> bool {
        self.thinking.as_ref().is_some_and(|t| !t.sent)
    }

    /// Once a frame, `dt` seconds after the last: starts thinking when the game shown waits
    /// for the computer's seat (no shot playing), and returns its command once decided and
    /// shown thinking for [`SHOWN_THINKING`]. The command is one the rules accept on that
    /// table; a computer that cannot move concedes.
    pub fn update(&mut self, shown: &dyn Shown, dt: f64) -> Option<Command> {
        let waits = shown.waits_for(self.seat);
        let game = shown.shown_game().filter(|_| waits);
        let Some(game) = game else {
            self.thinking = None;
            return None;
        };
        if self.thinking.as_ref().is_none_or(|t| t.game != *game) {
            let seed = self.seed ^ u64::from(game.turn()).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            self.thinking = Some(Thinking::start(game.clone(), self.level, seed));
        }
        let t = self.thinking.as_mut()?;
        if t.sent {
            return None;
        }
        if dt.is_finite() {
            t.shown += dt.max(0.0);
        }
        if t.decided.is_none() {
            t.decided = match t.answer.try_take() {
                Some(Ok(Some(command))) if game.check(self.seat, &command).is_ok() => Some(command),
                Some(Ok(command)) => {
                    tracing::error!(?command, "the computer chose no legal move");
                    Some(Command::Concede)
                }
                None => None,
                Some(Err(why)) => {
                    tracing::error!("{why}");
                    Some(Command::Concede)
                }
            };
        }
        if t.shown < SHOWN_THINKING {
            return None;
        }
        let command = t.decided.take()?;
        t.sent = true;
        Some(command)
    }
}

/// A game against the computer at this computer: the player here plays one seat, the
/// computer the other. The first game's breaker is chosen; rematches alternate the break.
pub struct ComputerLink {
    local: LocalLink,
    computer: Computer,
}

impl ComputerLink {
    /// A new game of `variant` against the computer at `level`; seat A breaks, and the
    /// computer plays it when `computer_breaks`.
    pub fn new(
        variant: Variant,
        settings: Settings,
        seed: u64,
        level: Level,
        computer_breaks: bool,
    ) -> ComputerLink {
        let seat = if computer_breaks { Seat::A } else { Seat::B };
        ComputerLink {
            local: LocalLink::new(variant, settings, seed),
            computer: Computer::new(seat, level, seed.rotate_left(17)),
        }
    }

    /// The computer's seat.
    pub fn computer(&self) -> &Computer {
        &self.computer
    }
}

impl GameLink for ComputerLink {
    fn seat(&self) -> Option<Seat> {
        Some(self.computer.seat.other())
    }

    fn send(&mut self, game: &Game, seat: Seat, command: Command) {
        self.local.send(game, seat, command)
    }

    fn poll(&mut self) -> Option<GameEvent> {
        self.local.poll()
    }

    fn rematch(&mut self) {
        // Seat A breaks every game: the players change seats so the break alternates.
        self.computer.seat = self.computer.seat.other();
        self.local.rematch()
    }

    fn update(&mut self, shown: &dyn Shown, dt: f64) {
        if let (Some(command), Some(game)) = (self.computer.update(shown, dt), shown.shown_game()) {
            self.local.send(game, self.computer.seat, command);
        }
    }

    fn thinking(&self) -> bool {
        self.computer.thinking()
    }

    fn takes_back(&self) -> bool {
        true
    }
}

/// Any link whose own seat the computer plays (a page opened with `computer=LEVEL`: the
/// page's computer takes the seat the server gives it and plays it through the link, as a
/// player would).
pub struct PlayedByComputer<L: GameLink> {
    inner: L,
    level: Level,
    seed: u64,
    computer: Option<Computer>,
}

impl<L: GameLink> PlayedByComputer<L> {
    /// `inner`'s seat, played by the computer at `level`.
    pub fn new(inner: L, level: Level, seed: u64) -> PlayedByComputer<L> {
        PlayedByComputer {
            inner,
            level,
            seed,
            computer: None,
        }
    }
}

impl<L: GameLink> GameLink for PlayedByComputer<L> {
    fn seat(&self) -> Option<Seat> {
        self.inner.seat()
    }

    fn send(&mut self, game: &Game, seat: Seat, command: Command) {
        self.inner.send(game, seat, command)
    }

    fn poll(&mut self) -> Option<GameEvent> {
        self.inner.poll()
    }

    fn rematch(&mut self) {
        self.inner.rematch()
    }

    fn chats(&self) -> bool {
        self.inner.chats()
    }

    fn chat(&mut self, text: String) {
        self.inner.chat(text)
    }

    fn watching(&self) -> bool {
        self.inner.watching()
    }

    fn update(&mut self, shown: &dyn Shown, dt: f64) {
        self.inner.update(shown, dt);
        let Some(seat) = self.inner.seat() else {
            return;
        };
        let (level, seed) = (self.level, self.seed);
        let computer = self
            .computer
            .get_or_insert_with(|| Computer::new(seat, level, seed));
        if computer.seat != seat {
            *computer = Computer::new(seat, level, seed);
        }
        if let (Some(command), Some(game)) = (computer.update(shown, dt), shown.shown_game()) {
            self.inner.send(game, seat, command);
        }
    }

    fn thinking(&self) -> bool {
        self.computer.as_ref().is_some_and(Computer::thinking)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::{GameFlow, Prompt};
    use crate::view::hud::Connection;
    use breakshot_shared::rules::EightBallRules;
    use std::time::{Duration, Instant};

    /// Frames of `dt` seconds until `done` holds, at most `limit` of wall time.
    fn frames(
        link: &mut ComputerLink,
        flow: &mut GameFlow,
        dt: f64,
        limit: Duration,
        mut done: impl FnMut(&ComputerLink, &GameFlow) -> bool,
    ) -> bool {
        let since = Instant::now();
        while since.elapsed() < limit {
            while let Some(e) = link.poll() {
                flow.handle(e);
            }
            if done(link, flow) {
                return true;
            }
            flow.tick(dt);
            link.update(flow, dt);
            std::thread::sleep(Duration::from_millis(2));
        }
        false
    }

    fn eight_ball(computer_breaks: bool) -> (ComputerLink, GameFlow) {
        let variant = Variant::EightBall(EightBallRules::Wpa);
        let link = ComputerLink::new(
            variant,
            Settings::offline(),
            3,
            Level::new(1),
            computer_breaks,
        );
        (link, GameFlow::new(Connection::Offline))
    }

    #[test]
    fn the_computer_breaks_after_thinking_for_a_moment() {
        let (mut link, mut flow) = eight_ball(true);
        assert_eq!(
            link.seat(),
            Some(Seat::B),
            "the player here has the other seat"
        );
        // The game has started; the computer thinks, shown for at least SHOWN_THINKING.
        let mut shown = 0.0;
        let struck = frames(
            &mut link,
            &mut flow,
            0.05,
            Duration::from_secs(120),
            |l, f| {
                if l.thinking() {
                    shown += 0.05;
                }
                f.shot().is_some()
            },
        );
        assert!(struck, "the computer never broke");
        // Counted before each frame's update: the last frame of thinking is not seen here.
        assert!(
            shown + 0.05 >= SHOWN_THINKING - 1e-9,
            "thinking shown {shown} s"
        );
        assert!(!link.thinking());
        assert_eq!(flow.replica().shots(), 1);
        assert_eq!(flow.replica().desyncs(), 0);
    }

    #[test]
    fn the_computer_waits_for_the_players_turn_and_the_shot_to_be_shown() {
        let (mut link, mut flow) = eight_ball(false);
        let computer = link.computer().seat();
        let since = Instant::now();
        let mut player_moves = 0;
        loop {
            assert!(
                since.elapsed() < Duration::from_secs(120),
                "the computer never shot"
            );
            assert!(player_moves < 20, "the computer never had a turn");
            while let Some(e) = link.poll() {
                flow.handle(e);
            }
            if flow.shot().is_some() {
                assert!(!link.thinking(), "no thinking while the balls roll");
                let shooter = flow.shown_game().expect("a game").to_move();
                if shooter == computer {
                    break;
                }
                flow.skip();
            }
            if let Prompt::Shoot { seat, .. } | Prompt::Decide { seat, .. } =
                flow.prompt(link.seat())
            {
                assert!(!link.thinking(), "no thinking on the player's turn");
                // The player here moves as a level-1 computer would: legal moves.
                let game = flow.game().expect("a game").clone();
                let command = ai::decide(&game, Level::new(1), player_moves).expect("a move");
                link.send(&game, seat, command);
                player_moves += 1;
                continue;
            }
            flow.tick(0.05);
            link.update(&flow, 0.05);
            std::thread::sleep(Duration::from_millis(2));
        }
        assert_eq!(flow.replica().desyncs(), 0);
    }

    #[test]
    fn a_rematch_gives_the_break_to_the_other_player() {
        let (mut link, _) = eight_ball(false);
        assert_eq!(link.seat(), Some(Seat::A));
        link.rematch();
        assert_eq!(link.seat(), Some(Seat::B));
        assert_eq!(link.computer().seat(), Seat::A);
    }
}
