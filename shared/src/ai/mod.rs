//! The computer player: given a [`Game`] and a [`Level`], the next command for the seat to
//! move — a strike with its called pocket, a cue-ball placement, or a choice the rules offer.
//!
//! It plays the way the strong programs of the computational pool tournaments did: generate
//! candidate shots (ghost-ball pots aimed through the real engine, banks, combinations,
//! kicks, safeties, a few speeds and spins each), play every candidate several times under
//! the player's own execution noise with the real engine and the real rules, score each
//! result by the rules' verdict and the position left, look one shot further for the
//! finalists, and take the best. The levels differ in execution noise and in how many
//! simulations the search may spend, so a decision is pure and deterministic: the same
//! game, level and seed give the same command on every machine, with no clock involved.
//!
//! [`decide`] is the whole interface a caller needs; [`Thinking::decide`] is the same search
//! in steps of a bounded number of simulations, for a front end that cannot wait for it:
//! ```
//! use breakshot_shared::ai::{decide, Level};
//! use breakshot_shared::rules::{Game, Settings, Variant};
//! let mut game = Game::new(Variant::NineBall, Settings::offline(), 7);
//! let seat = game.to_move();
//! let command = decide(&game, Level::new(1), 42).expect("the game is not over");
//!
//! // The same decision, a few simulations per frame.
//! use breakshot_shared::ai::Thinking;
//! let mut thinking = Thinking::decide(&game, Level::new(1), 42);
//! let stepped = loop {
//!     if let std::task::Poll::Ready(answer) = thinking.step(50) {
//!         break answer.clone();
//!     }
//!     let _bar = thinking.fraction(); // shown while the computer thinks
//! };
//! assert_eq!(stepped, Some(command.clone()));
//! game.apply(seat, &command).expect("the computer only makes legal moves");
//! ```

mod candidates;
mod caroms;
mod estimate;
mod game_judge;
mod geometry;
mod ghost;
mod lab;
mod noise;
mod placement;
mod scene_judge;
mod search;
mod snooker;
mod thinking;
mod value;

use crate::physics::simulate;
use crate::physics::MotionState;
use crate::physics::Strike;
use crate::rules::snooker::{frame as snooker_frame, table as snooker_table};
use crate::rules::{Choice, Command, Game, InHand, Phase, ShotFacts, Variant};

pub use candidates::{Breadth, Kind};
pub use ghost::ghost_move;
pub use noise::{Noise, Rng, AIM_SIGMA_DEG, ELEVATION_SIGMA_DEG, SPEED_SIGMA, TIP_SIGMA_M};
pub use scene_judge::Suggestion;
pub use search::Schedule;
pub use thinking::{Progress, Thinking};

use candidates::{Candidate, View};
use game_judge::GameJudge;
use geometry::Layout;
use lab::Lab;
use noise::mix;
use search::Judge;
use thinking::Meter;

/// How strong the computer plays: 1 (beginner) to 5 (strong).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Level(u8);

impl Level {
    /// The weakest level, a beginner.
    pub const MIN: u8 = 1;
    /// The strongest level.
    pub const MAX: u8 = 5;

    /// `n` clamped into 1..=5.
    pub fn new(n: u8) -> Level {
        Level(n.clamp(Self::MIN, Self::MAX))
    }

    /// The level as a number, 1 to 5.
    pub fn number(self) -> u8 {
        self.0
    }

    /// The execution noise: the tournament model's deviations times a factor per level.
    pub fn noise(self) -> Noise {
        let factor = match self.0 {
            1 => 4.0,
            2 => 2.5,
            3 => 1.6,
            4 => 1.0,
            _ => 0.4,
        };
        Noise { factor }
    }

    /// Which shots the level considers.
    pub fn breadth(self) -> Breadth {
        let n = self.0;
        Breadth {
            pots: [3, 4, 6, 8, 12][usize::from(n - 1)],
            speeds: [1, 2, 2, 3, 3][usize::from(n - 1)],
            side: n >= 3,
            banks: n >= 4,
            combinations: n >= 3,
            kicks: n >= 4,
            safeties: true,
            corrections: [1, 2, 2, 3, 3][usize::from(n - 1)],
        }
    }

    /// How many trials the search spends on each candidate.
    pub fn schedule(self) -> Schedule {
        let n = self.0;
        Schedule {
            samples: [[1, 3, 6], [2, 5, 10], [2, 8, 16], [3, 10, 16], [5, 16, 32]]
                [usize::from(n - 1)],
            keep: [[6, 2], [8, 3], [10, 4], [12, 3], [20, 5]][usize::from(n - 1)],
            look_ahead: n >= 4,
        }
    }

    /// Spots tried for a ball in hand.
    fn placements(self) -> usize {
        [2, 3, 4, 5, 6][usize::from(self.0 - 1)]
    }
}

/// A search's settings: a level, or a custom noise and budget (for studies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Player {
    /// How far the player's strikes stray from the ones it means.
    pub noise: Noise,
    /// Which candidates it looks at.
    pub breadth: Breadth,
    /// How many trials it gives them.
    pub schedule: Schedule,
    /// Spots tried for a ball in hand (0 counts as 1).
    pub placements: usize,
}

impl From<Level> for Player {
    fn from(level: Level) -> Player {
        Player {
            noise: level.noise(),
            breadth: level.breadth(),
            schedule: level.schedule(),
            placements: level.placements(),
        }
    }
}

/// What the search decided, before execution noise.
#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    /// The command the player means to make.
    pub command: Command,
    /// For a shot: the share of its trials that succeeded (kept the table or won).
    pub p_success: Option<f64>,
    /// For a shot: what kind of shot it is.
    pub kind: Option<Kind>,
    /// Simulations spent.
    pub simulations: usize,
}

/// The command the computer makes at `level` for the seat to move, execution noise included:
/// what it would actually play. `None` when the game is over. [`Thinking::decide`] in one
/// call.
pub fn decide(game: &Game, level: Level, seed: u64) -> Option<Command> {
    Thinking::decide(game, level, seed).finish()
}

impl Thinking<Option<Command>> {
    /// [`decide`] in steps: its answer is exactly the command [`decide`] returns for the same
    /// game, level and seed, however it is stepped.
    pub fn decide(game: &Game, level: Level, seed: u64) -> Thinking<Option<Command>> {
        let game = game.clone();
        let player = Player::from(level);
        Thinking::start(move |meter| async move {
            let decision = planned(&game, &player, seed, &meter).await?;
            Some(execute(decision.command, player.noise, seed))
        })
    }
}

impl Thinking<Option<Decision>> {
    /// [`plan`] in steps: its answer is exactly the decision [`plan`] returns for the same
    /// game, player and seed, however it is stepped.
    pub fn plan(game: &Game, player: &Player, seed: u64) -> Thinking<Option<Decision>> {
        let game = game.clone();
        let player = *player;
        Thinking::start(move |meter| async move { planned(&game, &player, seed, &meter).await })
    }
}

/// The command as the player's cue delivers it: a shot gets its execution noise.
pub fn execute(command: Command, noise: Noise, seed: u64) -> Command {
    match command {
        Command::Shot { strike, call } => Command::Shot {
            strike: noise.perturb(&strike, &mut Rng::new(mix(seed, 0xE0E0))),
            call,
        },
        other => other,
    }
}

/// The command `player` means to make for the seat to move (no execution noise), with what
/// the search found. `None` when the game is over. [`Thinking::plan`] in one call.
pub fn plan(game: &Game, player: &Player, seed: u64) -> Option<Decision> {
    Thinking::plan(game, player, seed).finish()
}

/// What [`plan`] returns, its simulations counted on `meter`.
async fn planned(game: &Game, player: &Player, seed: u64, meter: &Meter) -> Option<Decision> {
    match game.phase() {
        Phase::Over { .. } => None,
        Phase::Deciding { options } => {
            let me = game.to_move();
            let sigma = player.noise.aim_sigma();
            let best = options
                .iter()
                .filter_map(|&c| {
                    let mut g = game.clone();
                    g.apply(me, &Command::Decide(c)).ok()?;
                    Some((c, value::value(&g, me, sigma)))
                })
                .fold(None, |best: Option<(_, f64)>, (c, v)| match best {
                    Some((_, bv)) if bv >= v => best,
                    _ => Some((c, v)),
                })?;
            Some(Decision {
                command: Command::Decide(best.0),
                p_success: None,
                kind: None,
                simulations: 0,
            })
        }
        Phase::Shooting { in_hand, .. } => {
            let cue_off = game
                .balls()
                .first()
                .is_none_or(|b| b.motion == MotionState::Pocketed);
            // A break is played from where the rack left the cue ball, and practice from
            // the layout the player set up; otherwise a ball in hand is placed by search.
            let placing = match in_hand {
                _ if cue_off => true,
                Some(InHand::Kitchen) if game.is_break() => false,
                Some(_) => game.variant() != crate::rules::Variant::Practice,
                None => false,
            };
            if placing {
                let start = meter.done();
                let spot = placement::best_spot(game, player, *in_hand, meter).await;
                let sims = meter.done() - start;
                if let Some(spot) = spot {
                    let here = game.balls().first().map(|b| b.pos.to_array());
                    if cue_off || here != Some(spot) {
                        return Some(Decision {
                            command: Command::PlaceCueBall { pos: spot },
                            p_success: None,
                            kind: None,
                            simulations: sims,
                        });
                    }
                }
            }
            // A free ball offered is nominated before the stroke is chosen.
            if let Some(ball) = snooker::free_ball(game, player.noise.aim_sigma()) {
                return Some(Decision {
                    command: Command::Decide(Choice::Nominate(ball)),
                    p_success: None,
                    kind: None,
                    simulations: 0,
                });
            }
            let decision = shoot(game, player, seed, meter).await;
            match snooker_nomination(game, &decision.command) {
                Some(colour) => Some(Decision {
                    command: Command::Decide(Choice::Nominate(colour)),
                    ..decision
                }),
                None => Some(decision),
            }
        }
    }
}

/// In snooker, on a colour with none nominated: the colour the chosen stroke hits first (the
/// search then runs again for that colour alone), or the lowest colour if it hits none.
fn snooker_nomination(game: &Game, command: &Command) -> Option<u8> {
    let m = game.snooker()?;
    if !m.on_colour || m.nominated.is_some() {
        return None;
    }
    let Command::Shot { strike, .. } = command else {
        return None;
    };
    let first = simulate(&game.shot_for(strike))
        .ok()
        .and_then(|o| ShotFacts::from_outcome(&o, game.table()).first_contact)
        .filter(|&b| snooker_table::is_colour(b));
    first.or_else(|| snooker_frame::lowest_colour(game.balls()))
}

/// The best strike from the table as it lies.
async fn shoot(game: &Game, player: &Player, seed: u64, meter: &Meter) -> Decision {
    let start = meter.done();
    let found = search_shot(game, player, seed, meter).await;
    let sims = meter.done() - start;
    match found {
        Some(choice) => Decision {
            command: Command::Shot {
                strike: choice.candidate.strike,
                call: choice.candidate.call,
            },
            p_success: Some(choice.p_success),
            kind: Some(choice.candidate.kind),
            simulations: sims,
        },
        None => Decision {
            command: Command::Shot {
                strike: fallback(game),
                call: Some(0),
            },
            p_success: Some(0.0),
            kind: None,
            simulations: sims,
        },
    }
}

/// Candidates for the table as it lies, and the search among them.
async fn search_shot(
    game: &Game,
    player: &Player,
    seed: u64,
    meter: &Meter,
) -> Option<search::Choice> {
    let layout = Layout::new(game.table(), game.balls());
    let snooker = matches!(game.variant(), Variant::Snooker { .. });
    let targets = if snooker {
        snooker::targets(game)
    } else {
        game.legal_first_balls()
    };
    let pottable = value::pottable(game);
    let mut judge = GameJudge::new(game, player, meter);
    let candidates: Vec<Candidate>;
    if matches!(game.variant(), Variant::ThreeCushion { .. }) {
        meter.expect(estimate::caroms(&player.breadth, &player.schedule));
        candidates = caroms::caroms(game, &player.breadth, meter).await;
    } else if game.is_break() {
        candidates = candidates::breaks(&layout, &targets);
    } else {
        let look_ahead = judge.look_ahead_guess();
        meter.expect(estimate::shot(
            &player.breadth,
            &player.schedule,
            look_ahead,
        ));
        let mut lab = Lab::new(game.shot_for(&fallback(game)), meter);
        let view = View {
            layout: &layout,
            targets: &targets,
            pottable: &pottable,
            aim_sigma: player.noise.aim_sigma(),
        };
        let mut found = candidates::generate(&mut lab, &view, &player.breadth).await;
        if snooker && player.breadth.safeties {
            found.extend(snooker::safeties(&view));
        }
        candidates = found;
    }
    search::choose(
        &mut judge,
        &candidates,
        player.noise,
        &player.schedule,
        mix(seed, 0x5EA7),
    )
    .await
}

/// A plain strike at the nearest ball: used only when no candidate could be made.
fn fallback(game: &Game) -> Strike {
    let balls = game.balls();
    let shooter = game.cue_ball();
    let cue = balls.get(shooter).map(|b| b.pos).unwrap_or_default();
    let dir = balls
        .iter()
        .enumerate()
        .filter(|&(i, b)| i != shooter && b.motion != MotionState::Pocketed)
        .map(|(_, b)| b)
        .map(|b| b.pos - cue)
        .min_by(|a, b| a.length().total_cmp(&b.length()))
        .and_then(|d| d.try_normalize())
        .unwrap_or(glam::DVec2::Y);
    Strike {
        speed: 2.0,
        dir,
        tip: glam::DVec2::ZERO,
        elevation_deg: 0.0,
    }
}
