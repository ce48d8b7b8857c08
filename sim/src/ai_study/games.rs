//! Whole games between two players, with what each decision cost and what each shot did.

use std::time::Instant;

use breakshot_shared::ai::{self, Player, Rng};
use breakshot_shared::rules::{Command, Game, Seat, Settings, Variant};

/// A game stops as a draw after this many commands (keeps the study bounded).
const MAX_COMMANDS: usize = 400;

/// Who plays a seat.
#[derive(Clone, Copy, Debug)]
pub enum Contestant {
    Computer(Player),
    Ghost,
}

/// What happened in one game, per seat (index 0 = A).
#[derive(Clone, Debug, Default)]
pub struct GameRecord {
    pub winner: Option<Seat>,
    /// Shots that were not breaks.
    pub shots: [u32; 2],
    /// … of which kept the table or won.
    pub successes: [u32; 2],
    /// Decision times (s) of each seat's shots and placements: CPU time of the deciding
    /// thread where the system reports it (see [`cpu_seconds`]), wall time otherwise.
    pub times: [Vec<f64>; 2],
    /// Simulations per decision.
    pub sims: [Vec<usize>; 2],
    /// The breaker won without the opponent ever shooting.
    pub break_and_run: bool,
}

/// One move a contestant chose, with what it cost.
pub struct Move {
    /// The command.
    pub command: Command,
    /// Simulations the choice ran.
    pub simulations: usize,
    /// Processor seconds the choice took (wall seconds where the processor's are unknown).
    pub seconds: f64,
}

impl Move {
    /// Whether the move is a stroke (not a placement or an answer to a choice).
    pub fn is_shot(&self) -> bool {
        matches!(self.command, Command::Shot { .. })
    }

    /// Whether its time counts among the decision times: strokes and placements do,
    /// answers to the rules' choices do not.
    pub fn is_timed(&self) -> bool {
        !matches!(self.command, Command::Decide(_))
    }
}

impl Contestant {
    /// This contestant's move in `game` (None: it has none), timed; `ghost` is the ghost's
    /// own random stream.
    pub fn choose(self, game: &Game, ghost: &mut Rng, seed: u64) -> Option<Move> {
        let start = Instant::now();
        let cpu_start = cpu_seconds();
        let (command, simulations) = match self {
            Contestant::Computer(player) => {
                let d = ai::plan(game, &player, seed)?;
                (ai::execute(d.command, player.noise, seed), d.simulations)
            }
            Contestant::Ghost => (ai::ghost_move(game, ghost)?, 0),
        };
        let seconds = match (cpu_start, cpu_seconds()) {
            (Some(a), Some(b)) => b - a,
            _ => start.elapsed().as_secs_f64(),
        };
        Some(Move {
            command,
            simulations,
            seconds,
        })
    }
}

/// The two contestants of a game, each with its ghost's own random stream, and what their
/// decisions cost.
pub struct Seats {
    contestants: [Contestant; 2],
    ghosts: [Rng; 2],
    seed: u64,
    /// Each seat's decision times (s) and simulations, of its timed moves only
    /// ([`Move::is_timed`]).
    pub times: [Vec<f64>; 2],
    pub sims: [Vec<usize>; 2],
}

impl Seats {
    /// `a` in seat A, `b` in seat B, for the game played from `seed`.
    pub fn new(a: Contestant, b: Contestant, seed: u64) -> Seats {
        Seats {
            contestants: [a, b],
            ghosts: [Rng::new(seed ^ 0xA), Rng::new(seed ^ 0xB)],
            seed,
            times: Default::default(),
            sims: Default::default(),
        }
    }

    /// Who is to move in `game` and the move they chose as its `n`th command (None: they
    /// have none); a timed move's cost is kept in `times` and `sims`.
    pub fn choose(&mut self, game: &Game, n: usize) -> Option<(Seat, Move)> {
        let seat = game.to_move();
        let i = seat.index();
        let decision_seed = self.seed.wrapping_mul(1_000_003).wrapping_add(n as u64);
        let chosen = self.contestants[i].choose(game, &mut self.ghosts[i], decision_seed)?;
        if chosen.is_timed() {
            self.times[i].push(chosen.seconds);
            self.sims[i].push(chosen.simulations);
        }
        Some((seat, chosen))
    }
}

/// Plays game `k` of a pairing of `us` against `them`: seats alternate from one game to the
/// next, and each pair of games shares its seed. Returns what `play` made of it and our seat.
pub fn seated<R>(
    us: Contestant,
    them: Contestant,
    k: usize,
    salt: u64,
    play: impl Fn(Contestant, Contestant, u64) -> R,
) -> (R, Seat) {
    let seed = salt.wrapping_mul(7919).wrapping_add(k as u64 / 2);
    if k % 2 == 0 {
        (play(us, them, seed), Seat::A)
    } else {
        (play(them, us, seed), Seat::B)
    }
}

/// Plays one game of `variant` from `seed`: `a` sits in seat A (which breaks), `b` in B.
pub fn play(variant: Variant, a: Contestant, b: Contestant, seed: u64) -> GameRecord {
    let mut game = Game::new(variant, Settings::offline(), seed);
    let mut seats = Seats::new(a, b, seed);
    let mut record = GameRecord::default();
    let mut opponent_shot = false;
    let breaker = game.to_move();
    for n in 0..MAX_COMMANDS {
        let Some((seat, chosen)) = seats.choose(&game, n) else {
            break;
        };
        let i = seat.index();
        let is_shot = chosen.is_shot();
        let breaking = game.is_break();
        if is_shot && seat != breaker {
            opponent_shot = true;
        }
        let verdict = match game.apply(seat, &chosen.command) {
            Ok(v) => v,
            // A refused command would be a bug in a player: the other seat wins.
            Err(_) => {
                record.winner = Some(seat.other());
                break;
            }
        };
        if is_shot && !breaking {
            record.shots[i] += 1;
            let kept = match &verdict.over {
                Some((w, _)) => *w == Some(seat),
                None => !verdict.foul && verdict.next == seat,
            };
            record.successes[i] += u32::from(kept);
        }
        if let Some((winner, _)) = verdict.over {
            record.winner = winner;
            break;
        }
    }
    record.break_and_run = record.winner == Some(breaker) && !opponent_shot;
    record.times = seats.times;
    record.sims = seats.sims;
    record
}

/// CPU time (s) the calling thread has run, from Linux's `/proc/thread-self/schedstat` (its
/// first field, in nanoseconds): on a loaded machine it still measures one core's work,
/// where wall time would count the waits for a core.
pub fn cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}
