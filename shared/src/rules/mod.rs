//! The game rules: 8-ball (World Standardized Rules, or the `bar` variant), 9-ball,
//! three-cushion billiards and practice.
//!
//! A [`Game`] takes [`Command`]s from the two seats. [`Game::check`] says whether a command
//! is acceptable now without changing anything; [`Game::apply`] is the only place the game
//! changes: it simulates shots with the physics engine, judges them from the events, and
//! returns a [`Verdict`] whose reasons a player can read. Like the physics, the rules are
//! pure and deterministic: the same seed and commands give the same game, bit for bit.
//!
//! Three-cushion is judged by [`three_cushion::Match`] and played as a `Game` by `carom.rs`;
//! its balls are 0 = white (seat A's), 1 = yellow (seat B's), 2 = red, and the ball struck is
//! the shooter's ([`Game::cue_ball`]).
//!
//! Ball index = ball number (0 = cue ball, 1..=15, or 1..=9 in 9-ball); balls off the table
//! stay in the list with `motion: Pocketed` (and `pocket: None` if they left the table other
//! than by a pocket).
//!
//! Choices made where the rule books leave room or the game needs a definite answer:
//! - A break is any shot taken while [`Game::is_break`]; the cue ball is in hand behind the
//!   head string for it. [`Choice::Rerack`] always means "re-rack, and the player choosing
//!   breaks"; [`Choice::OpponentRebreaks`] gives the break back to the offender.
//! - 8-ball under bar rules: the 8 on the break wins, unless the breaker scratches, which
//!   loses (a scratch on the 8).
//! - Called shots: a call names a pocket, not a ball. With `call_every_shot`, the turn goes
//!   on only if a ball of the shooter's group (on an open table, any group ball, which then
//!   assigns the group) falls in the called pocket; other balls that fall stay down, no foul.
//!   In 9-ball with calls, a 9 in another pocket is spotted and the turn passes.
//! - The shot clock runs outside (the server sends [`Command::TimeExpired`]). Out of time on
//!   a shot is a foul (ball in hand for the opponent; before the break, the opponent breaks
//!   instead). Out of time on a choice takes the first option offered, without a foul.
//! - 9-ball: illegal breaks (no ball down and fewer than four object balls to a cushion) are
//!   fouls; a push-out that scratches is a foul and gives no choice. The warning before a
//!   third foul is a reason in the verdict of the second.
//! - A ball's position (behind the head string or not) is its centre's; a ball touches
//!   ("is frozen to") a cushion when its centre is within 1 µm of the contact distance. The
//!   game has no referee to declare a ball frozen, so geometry decides.
//! - The 8 driven off the table on the break (8-ball 3.3 makes it a foul; the 8-ball rule on
//!   spotting balls spots it or re-racks) is judged as the 8 pocketed with a foul: the
//!   opponent spots it and takes the cue ball in hand behind the head string, or re-racks.
//!   Under bar rules it loses.
//! - WPA 6.11 (play from behind the head string) is not judged on the break, where every
//!   object ball is racked beyond the head string. Of legal balls equally near the head
//!   string, the lowest-numbered is the one spotted on request.
//!
//! What the rules implement, clause by clause (WPA World Standardized Rules, Rules of Play;
//! numbers as in the 2008 text):
//! - 1.4 Spotting balls: on the long string as near the foot spot as possible, behind it,
//!   else in front of it ([`rack::spot`]; if the string were ever full, the free place nearest
//!   the foot spot, so spotting never fails).
//! - 1.5 Cue ball in hand behind the head string: placed with its centre behind the line; if
//!   every legal ball lies behind the head string too, the shooter may have the one nearest it
//!   spotted ([`Choice::SpotNearestBall`]).
//! - 6.1 to 6.3, 6.5: scratch or cue ball off the table, wrong ball first, no rail after
//!   contact, object ball driven off the table (all fouls).
//! - 6.11 Bad play from behind the head string: from the kitchen, hitting first a ball behind
//!   the head string before the cue ball has crossed it is a foul.
//! - 8.4 Driven to a rail: a ball not touching a rail that then touches it; a ball frozen to a
//!   rail and pressed into it is not driven to it unless it leaves and comes back; a ball
//!   pocketed or driven off the table counts. This feeds both the no-rail foul and the
//!   break's four balls to a rail.
//! - 8.5 Driven off the table: the physics reports it through [`facts::departures`] ("ball X
//!   left the table at time t": a ball in flight that comes down beyond the rails, see
//!   `shared/tests/airborne.rs`); the clauses are tested with departures handed to
//!   [`ShotFacts::read`] (`rules/tests/wpa.rs`).
//! - 8-ball: 3.3 break (legal break, the three options after an illegal one, the 8 on the
//!   break, an object ball off the table on the break: a foul, the incoming player accepts
//!   the table in position or takes the cue ball behind the head string); a scratch on a
//!   legal break (cue ball in hand behind the head string); open table and groups; the 8
//!   called, lost if pocketed early, on a foul, in another pocket or driven off the table;
//!   jumped balls other than the 8 stay off (spotting balls).
//! - 9-ball: 2.3 legal break (the 1 first, a ball down or four to a rail, else a foul); 2.4
//!   push-out on the shot after a break without a foul only; the 9 spotted when it falls on a
//!   foul or a push-out or leaves the table, other jumped balls stay off; three consecutive
//!   fouls lose.

mod carom;
mod eight;
pub mod facts;
mod kitchen;
mod nine;
mod practice;
pub mod rack;
#[cfg(test)]
mod tests;
pub mod three_cushion;

use std::fmt;

use glam::DVec2;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::{
    simulate, BallState, Event, MotionState, Outcome, Params, Shot, Strike, Table, TableKind,
};
pub use facts::ShotFacts;
pub use practice::layout_from_scene;

/// Which game is played.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Variant {
    /// 8-ball under one of its two rule sets.
    EightBall(EightBallRules),
    /// 9-ball (WPA): the lowest-numbered ball first, the 9 wins.
    NineBall,
    /// A sandbox: no turns, no fouls, any ball placed anywhere free.
    Practice,
    /// Three-cushion billiards on the carom table, a race to `race` points
    /// ([`three_cushion::DEFAULT_RACE`] unless agreed otherwise; 1 to
    /// [`three_cushion::MAX_RACE`]).
    ThreeCushion {
        /// The points a player needs to win the match.
        race: u32,
    },
}

impl Variant {
    /// Three-cushion to the default race.
    pub fn three_cushion() -> Variant {
        Variant::ThreeCushion {
            race: three_cushion::DEFAULT_RACE,
        }
    }

    /// The table this game is played on when the settings name `table`: three-cushion is
    /// only ever played on the carom table.
    pub fn table(self, table: TableKind) -> TableKind {
        match self {
            Variant::ThreeCushion { .. } => TableKind::Carom,
            _ => table,
        }
    }
}

/// The two 8-ball rule sets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum EightBallRules {
    /// World Standardized Rules (WPA).
    #[default]
    Wpa,
    /// Bar rules: a scratch while shooting at the 8 loses; the 8 on the break wins.
    Bar,
}

/// Settings fixed for a whole game.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Settings {
    /// Every shot (not only the 8) must name the pocket a ball of the shooter's is meant for;
    /// the turn continues only if one goes there.
    pub call_every_shot: bool,
    /// Seconds per shot; `None` = no shot clock. The clock itself runs outside the rules
    /// (the server sends [`Command::TimeExpired`]); running out is a foul.
    pub shot_clock: Option<u32>,
    /// The table played on.
    pub table: TableKind,
}

/// The online default shot clock (s).
pub const ONLINE_SHOT_CLOCK: u32 = 60;

impl Settings {
    /// Online play: 60 s shot clock.
    pub fn online() -> Settings {
        Settings {
            shot_clock: Some(ONLINE_SHOT_CLOCK),
            ..Settings::offline()
        }
    }

    /// Offline play: no shot clock.
    pub fn offline() -> Settings {
        Settings {
            call_every_shot: false,
            shot_clock: None,
            table: TableKind::NineFoot,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings::offline()
    }
}

/// A player's seat. Seat A breaks the first rack.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Seat {
    /// Breaks the first rack; online, the player who created the room.
    A,
    /// The other player; online, the one who joined the room.
    B,
}

impl Seat {
    /// The opponent's seat.
    pub fn other(self) -> Seat {
        match self {
            Seat::A => Seat::B,
            Seat::B => Seat::A,
        }
    }

    /// Where the seat sits in two-seat arrays (`[A, B]`): 0 for A, 1 for B.
    pub fn index(self) -> usize {
        match self {
            Seat::A => 0,
            Seat::B => 1,
        }
    }
}

impl fmt::Display for Seat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Seat::A => f.write_str("Player A"),
            Seat::B => f.write_str("Player B"),
        }
    }
}

/// Counts the commands applied to a game: it changes whenever the game does.
pub type TurnId = u32;

/// What a player asks for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Strike the cue ball. `call` is the pocket (index into the table's pockets) the
    /// shooter calls: required for the 8, and for every shot with `call_every_shot`.
    Shot {
        /// The strike on the shooter's cue ball ([`Game::cue_ball`]).
        strike: Strike,
        /// The called pocket, 0..6; `None` when nothing is called.
        call: Option<u8>,
    },
    /// Put the cue ball at `pos` (scene coordinates) while it is in hand.
    PlaceCueBall {
        /// The cue ball's centre (m, scene coordinates), inside the area in hand allows.
        pos: [f64; 2],
    },
    /// Answer a choice the rules offered.
    Decide(Choice),
    /// The shot clock ran out (sent by the server on behalf of the seat to move).
    TimeExpired,
    /// Give up the game.
    Concede,
    /// Offer a stalemate; when both players have offered, the balls are re-racked and the
    /// same player breaks.
    ProposeStalemate,
    /// Practice only: put any ball at `pos`, or take it off the table with `None`.
    PlaceBall {
        /// The ball's number (0 = cue ball).
        ball: u8,
        /// Its centre (m, scene coordinates); `None` takes it off the table.
        pos: Option<[f64; 2]>,
    },
    /// Practice only: lay out the table, one entry per ball number (`None` = off the table).
    /// [`layout_from_scene`] builds one from a scene file.
    LoadLayout {
        /// Centres (m, scene coordinates), indexed by ball number.
        balls: Vec<Option<[f64; 2]>>,
    },
    /// The seat's player left and did not come back within the reconnect window (sent by
    /// the server on their behalf): they lose, as by conceding, but the reason says so.
    Forfeit,
}

/// The choices the rules offer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Choice {
    /// Play on from the table as it lies.
    AcceptTable,
    /// Re-rack, and the player choosing breaks.
    Rerack,
    /// Re-rack, and the player who broke illegally breaks again.
    OpponentRebreaks,
    /// After the 8 fell on the break: spot it and play on.
    SpotEightAndContinue,
    /// 9-ball, the shot after the break: declare this shot a push-out.
    PushOut,
    /// 9-ball, after the opponent's push-out: make the opponent shoot again.
    HandBack,
    /// 8-ball, after an object ball left the table on the break: take the cue ball in hand
    /// behind the head string instead of accepting the table in position.
    CueBallInKitchen,
    /// With the cue ball in hand behind the head string and every legal ball behind it too:
    /// have the legal ball nearest the head string spotted (WPA 1.5).
    SpotNearestBall,
    /// Three-cushion, with the shooter's ball against another: have the balls set up as at
    /// the start (UMB art. 27).
    Respot,
}

impl fmt::Display for Choice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Choice::AcceptTable => "accept the table",
            Choice::Rerack => "re-rack and break",
            Choice::OpponentRebreaks => "have the opponent break again",
            Choice::SpotEightAndContinue => "spot the 8 and continue",
            Choice::PushOut => "push out",
            Choice::HandBack => "hand the table back",
            Choice::CueBallInKitchen => "take the cue ball in hand behind the head string",
            Choice::SpotNearestBall => "have the ball nearest the head string spotted",
            Choice::Respot => "have the balls set up as at the start",
        })
    }
}

/// Where the cue ball may be put when it is in hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum InHand {
    /// Behind the head string (centre at `y < length/4`).
    Kitchen,
    /// Anywhere on the cloth, clear of the cushions, pockets and other balls.
    Anywhere,
}

/// The 8-ball groups.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Group {
    /// 1 to 7.
    Solids,
    /// 9 to 15.
    Stripes,
}

impl Group {
    /// The group a ball belongs to; `None` for the cue ball and the 8.
    pub fn of(ball: u8) -> Option<Group> {
        match ball {
            1..=7 => Some(Group::Solids),
            9..=15 => Some(Group::Stripes),
            _ => None,
        }
    }

    /// The group's ball numbers.
    pub fn balls(self) -> std::ops::RangeInclusive<u8> {
        match self {
            Group::Solids => 1..=7,
            Group::Stripes => 9..=15,
        }
    }

    /// The opponent's group once groups are assigned.
    pub fn other(self) -> Group {
        match self {
            Group::Solids => Group::Stripes,
            Group::Stripes => Group::Solids,
        }
    }

    /// "a solid" / "a stripe".
    pub fn one(self) -> &'static str {
        match self {
            Group::Solids => "a solid",
            Group::Stripes => "a stripe",
        }
    }
}

/// What the game waits for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Phase {
    /// `to_move()` shoots. `in_hand`: the cue ball may (or, if it is off the table, must) be
    /// placed first. `options`: declarations the shooter may make before shooting (the 9-ball
    /// push-out, the spot on request of WPA 1.5). `push_out`: this shot was declared a
    /// push-out.
    Shooting {
        /// Where the cue ball may be placed; `None` when it is not in hand.
        in_hand: Option<InHand>,
        /// Declarations the shooter may make first, with [`Command::Decide`].
        options: Vec<Choice>,
        /// Whether the coming shot is a declared push-out.
        push_out: bool,
    },
    /// `to_move()` must pick one of `options`.
    Deciding {
        /// The choices offered; running out of time takes the first.
        options: Vec<Choice>,
    },
    /// The game is over (`winner: None` when nobody won: practice was ended).
    Over {
        /// The winning seat, if any.
        winner: Option<Seat>,
        /// Why the game ended, readable by a person.
        reason: String,
    },
}

/// What a shot did, for the players.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShotReport {
    /// The physics state hash of the table at rest (before any ball is spotted).
    pub hash: u64,
    /// Every event of the shot, in time order.
    pub events: Vec<Event>,
    /// (ball, pocket) in the order they fell.
    pub pocketed: Vec<(u8, u8)>,
}

/// The result of an applied command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// Readable reasons, most important first ("Foul: wrong ball first — hit the 8 before a
    /// solid").
    pub reasons: Vec<String>,
    /// Whether the command was judged a foul.
    pub foul: bool,
    /// What the shot did; `None` for any command that is not a shot.
    pub shot: Option<ShotReport>,
    /// The seat to move next.
    pub next: Seat,
    /// The game ended: the winner (if any) and why.
    pub over: Option<(Option<Seat>, String)>,
    /// A shot's whole trajectory, so whoever shows it need not simulate it again. Not part
    /// of any encoding: it is rebuilt by applying the command.
    #[serde(skip)]
    pub outcome: Option<Outcome>,
}

/// Why a command was refused. Nothing changed.
#[derive(Clone, Debug, PartialEq, Eq, Error, Serialize, Deserialize)]
pub enum RuleError {
    /// The command came from the seat not to move.
    #[error("it is not your turn")]
    NotYourTurn,
    /// The game is over; nothing more can be applied.
    #[error("the game is over")]
    GameOver,
    /// The command does not fit the phase (a shot while a choice is due, ...); says why.
    #[error("not now: {0}")]
    WrongPhase(String),
    /// A ball would not lie where it may: outside the area in hand allows, against a cushion,
    /// in a pocket or on another ball (in practice, any ball placed).
    #[error("illegal cue ball placement: {0}")]
    IllegalPlacement(String),
    /// The strike is refused, the call names no pocket, or a required call is missing.
    #[error("invalid shot: {0}")]
    InvalidShot(String),
    /// The choice is not among the options offered.
    #[error("invalid choice: {0}")]
    InvalidChoice(String),
    /// The command has no place in this variant or these settings (a stalemate in
    /// practice, a shot clock running out where there is none, ...).
    #[error("not in this game: {0}")]
    NotAllowed(String),
}

/// A choice the rules are waiting for, and what it is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
enum Pending {
    /// 8-ball: the break was illegal (`offender` broke; `scratched` with it).
    IllegalBreak { offender: Seat, scratched: bool },
    /// 8-ball: the 8 fell or left the table on the break (`foul`: the breaker fouled too,
    /// and the opponent chooses).
    EightOnBreak { foul: bool },
    /// 8-ball: an object ball left the table on an otherwise legal break.
    JumpedOnBreak,
    /// 9-ball: `pusher` pushed out.
    PushOut { pusher: Seat },
}

/// What a judged shot leads to.
#[derive(Clone, Debug, PartialEq)]
enum Next {
    Shoot {
        seat: Seat,
        in_hand: Option<InHand>,
        options: Vec<Choice>,
    },
    Decide {
        seat: Seat,
        options: Vec<Choice>,
        pending: Pending,
    },
    Over {
        winner: Option<Seat>,
        reason: String,
    },
    Rerack {
        breaker: Seat,
    },
}

/// The judgement of one shot by a variant's rules.
#[derive(Clone, Debug, PartialEq)]
struct Ruling {
    reasons: Vec<String>,
    foul: bool,
    next: Next,
}

/// A game in progress.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Game {
    variant: Variant,
    settings: Settings,
    seed: u64,
    /// Racks played before the current one (re-racks included).
    racks: u32,
    balls: Vec<BallState>,
    turn: TurnId,
    to_move: Seat,
    breaker: Seat,
    phase: Phase,
    /// The next shot is a break.
    breaking: bool,
    /// 8-ball: seat A's group once assigned.
    group_a: Option<Group>,
    /// 9-ball: consecutive fouls of each seat.
    fouls: [u8; 2],
    pending: Option<Pending>,
    /// Stalemate offers since the last shot.
    stalemate: [bool; 2],
    /// Three-cushion: the match (its scores, innings and balls).
    carom: Option<three_cushion::Match>,
}

impl Game {
    /// A new game: the first rack, seat A to break.
    pub fn new(variant: Variant, settings: Settings, seed: u64) -> Game {
        let settings = Settings {
            table: variant.table(settings.table),
            ..settings
        };
        let mut game = Game {
            variant,
            settings,
            seed,
            racks: 0,
            balls: Vec::new(),
            turn: 0,
            to_move: Seat::A,
            breaker: Seat::A,
            phase: Phase::Deciding {
                options: Vec::new(),
            },
            breaking: false,
            group_a: None,
            fouls: [0; 2],
            pending: None,
            stalemate: [false; 2],
            carom: None,
        };
        game.rack(Seat::A);
        game
    }

    /// The game played, fixed for the whole game.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// The settings, with the table the variant plays on.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// The seed every rack's random layout derives from.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The table played on (the carom table for three-cushion, whatever was asked).
    pub fn table(&self) -> TableKind {
        self.settings.table
    }

    /// The balls, index = ball number (0 = cue ball), in scene coordinates.
    pub fn balls(&self) -> &[BallState] {
        &self.balls
    }

    /// The number of commands applied so far: a command must answer this turn.
    pub fn turn(&self) -> TurnId {
        self.turn
    }

    /// The seat that shoots or decides next.
    pub fn to_move(&self) -> Seat {
        self.to_move
    }

    /// What the game waits for now.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// How many racks came before the current one (re-racks included; 0 for the opening).
    pub fn rack_number(&self) -> u32 {
        self.racks
    }

    /// The seat that broke (or breaks) the current rack.
    pub fn breaker(&self) -> Seat {
        self.breaker
    }

    /// The next shot is a break.
    pub fn is_break(&self) -> bool {
        self.breaking
    }

    /// 8-ball: the group of `seat`, once the table is no longer open.
    pub fn group_of(&self, seat: Seat) -> Option<Group> {
        match seat {
            Seat::A => self.group_a,
            Seat::B => self.group_a.map(Group::other),
        }
    }

    /// 9-ball: consecutive fouls of `seat` (three lose).
    pub fn consecutive_fouls(&self, seat: Seat) -> u8 {
        self.fouls[seat.index()]
    }

    /// Seats that have offered a stalemate since the last shot.
    pub fn stalemate_offered(&self, seat: Seat) -> bool {
        self.stalemate[seat.index()]
    }

    /// The balls the shooter may legally strike first now (empty in practice: anything goes).
    pub fn legal_first_balls(&self) -> Vec<u8> {
        match self.variant {
            Variant::EightBall(_) => eight::legal_first_balls(self, self.to_move),
            Variant::NineBall => nine::lowest_ball(&self.balls).into_iter().collect(),
            Variant::Practice => Vec::new(),
            Variant::ThreeCushion { .. } => self.carom_first_balls(),
        }
    }

    /// The ball the shooter strikes: the cue ball, or in three-cushion the shooter's own
    /// ball (the white for seat A, the yellow for seat B).
    pub fn cue_ball(&self) -> usize {
        match &self.carom {
            Some(m) => usize::from(three_cushion::cue_ball(m.to_move())),
            None => usize::from(facts::CUE),
        }
    }

    /// The physics shot that `strike` on the cue ball would be from the current table.
    pub fn shot_for(&self, strike: &Strike) -> Shot {
        Shot::new(self.table(), self.balls.clone()).struck(self.cue_ball(), *strike)
    }

    /// The physical parameters every shot of this game is simulated with.
    pub fn params(&self) -> Params {
        Shot::new(self.table(), Vec::new()).params
    }

    /// Must the next shot name a pocket? The same answer [`Game::check`] enforces: never on
    /// a break; in 8-ball when shooting at the 8; with `call_every_shot`, every shot.
    pub fn needs_call(&self) -> bool {
        self.missing_call().is_some()
    }

    /// Why a shot without a call would be refused now, if it would.
    fn missing_call(&self) -> Option<&'static str> {
        if self.breaking {
            return None;
        }
        match self.variant {
            Variant::EightBall(_) if eight::on_eight(self, self.to_move) => {
                Some("call a pocket for the 8")
            }
            Variant::EightBall(_) | Variant::NineBall if self.settings.call_every_shot => {
                Some("this game requires a called pocket on every shot")
            }
            _ => None,
        }
    }

    /// The part of the cloth where the cue ball may go when in hand in `area`: the corners
    /// (min, max) of a rectangle in scene coordinates. The cue ball must also lie clear of
    /// the cushions and the other balls ([`Game::legal_cue_placement`]).
    pub fn in_hand_area(&self, area: InHand) -> (DVec2, DVec2) {
        let (w, l) = rack::table_size(self.table());
        match area {
            InHand::Kitchen => (DVec2::ZERO, DVec2::new(w, rack::head_string(self.table()))),
            InHand::Anywhere => (DVec2::ZERO, DVec2::new(w, l)),
        }
    }

    /// May the cue ball, in hand, go at `pos` (scene coordinates)?
    pub fn legal_cue_placement(&self, pos: [f64; 2]) -> Result<(), RuleError> {
        let area = match (&self.phase, self.variant) {
            (Phase::Over { .. }, _) => return Err(RuleError::GameOver),
            (_, Variant::Practice) => InHand::Anywhere,
            (
                Phase::Shooting {
                    in_hand: Some(area),
                    ..
                },
                _,
            ) => *area,
            _ => return Err(RuleError::WrongPhase("the cue ball is not in hand".into())),
        };
        self.placement_in(area, pos)
    }

    fn placement_in(&self, area: InHand, pos: [f64; 2]) -> Result<(), RuleError> {
        let p = DVec2::from_array(pos);
        if !p.is_finite() {
            return Err(RuleError::IllegalPlacement(
                "the position must be finite numbers".into(),
            ));
        }
        if area == InHand::Kitchen && p.y >= self.in_hand_area(area).1.y {
            return Err(RuleError::IllegalPlacement(
                "the cue ball must be behind the head string".into(),
            ));
        }
        if !rack::is_free(&self.balls, 0, p, self.table()) {
            return Err(RuleError::IllegalPlacement(
                "the cue ball must lie on the cloth, clear of the cushions, pockets and other balls"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Would `cmd` from `seat` be accepted now? Changes nothing.
    pub fn check(&self, seat: Seat, cmd: &Command) -> Result<(), RuleError> {
        if let Phase::Over { .. } = self.phase {
            return Err(RuleError::GameOver);
        }
        let practice = self.variant == Variant::Practice;
        match cmd {
            Command::Concede | Command::Forfeit => Ok(()),
            Command::ProposeStalemate => {
                if practice || self.carom.is_some() {
                    return Err(RuleError::NotAllowed(format!(
                        "there is no stalemate in {}",
                        if practice {
                            "practice"
                        } else {
                            "three-cushion"
                        }
                    )));
                }
                if self.stalemate[seat.index()] {
                    return Err(RuleError::WrongPhase(
                        "you have already offered a stalemate".into(),
                    ));
                }
                Ok(())
            }
            Command::TimeExpired => {
                if practice || self.settings.shot_clock.is_none() {
                    return Err(RuleError::NotAllowed("this game has no shot clock".into()));
                }
                self.check_seat(seat)
            }
            Command::PlaceBall { ball, pos } => {
                if !practice {
                    return Err(RuleError::NotAllowed(
                        "balls can be placed freely only in practice".into(),
                    ));
                }
                practice::check_place_ball(self, *ball, *pos)
            }
            Command::LoadLayout { balls } => {
                if !practice {
                    return Err(RuleError::NotAllowed(
                        "a layout can be loaded only in practice".into(),
                    ));
                }
                practice::check_layout(self, balls)
            }
            Command::PlaceCueBall { pos } => {
                if !practice {
                    self.check_seat(seat)?;
                }
                self.legal_cue_placement(*pos)
            }
            Command::Decide(choice) => {
                if practice {
                    return Err(RuleError::NotAllowed(
                        "there are no choices in practice".into(),
                    ));
                }
                self.check_seat(seat)?;
                let options = match &self.phase {
                    Phase::Deciding { options } | Phase::Shooting { options, .. } => options,
                    Phase::Over { .. } => return Err(RuleError::GameOver),
                };
                if options.contains(choice) {
                    Ok(())
                } else {
                    Err(RuleError::InvalidChoice(format!("you cannot {choice} now")))
                }
            }
            Command::Shot { strike, call } => {
                if !practice {
                    self.check_seat(seat)?;
                }
                self.check_shot(strike, *call)
            }
        }
    }

    fn check_seat(&self, seat: Seat) -> Result<(), RuleError> {
        if seat == self.to_move {
            Ok(())
        } else {
            Err(RuleError::NotYourTurn)
        }
    }

    fn check_shot(&self, strike: &Strike, call: Option<u8>) -> Result<(), RuleError> {
        strike
            .validated()
            .map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let in_hand = match &self.phase {
            Phase::Shooting { in_hand, .. } => *in_hand,
            Phase::Deciding { .. } => {
                return Err(RuleError::WrongPhase("a choice must be made first".into()))
            }
            Phase::Over { .. } => return Err(RuleError::GameOver),
        };
        let cue = match self.balls.get(self.cue_ball()) {
            Some(b) if !is_off_table(b) => *b,
            _ => return Err(RuleError::WrongPhase("place the cue ball first".into())),
        };
        if let (Some(area), false) = (in_hand, self.variant == Variant::Practice) {
            self.placement_in(area, cue.pos.to_array())?;
        }
        let pockets = Table::new(self.table()).pockets.len();
        if let Some(p) = call {
            if usize::from(p) >= pockets {
                return Err(RuleError::InvalidShot(format!(
                    "pocket {p} does not exist (the table has {pockets})"
                )));
            }
        }
        match (call, self.missing_call()) {
            (None, Some(why)) => Err(RuleError::InvalidShot(why.into())),
            _ => Ok(()),
        }
    }

    /// Applies `cmd` from `seat`: the only way a game changes. On error nothing changes.
    pub fn apply(&mut self, seat: Seat, cmd: &Command) -> Result<Verdict, RuleError> {
        self.check(seat, cmd)?;
        let verdict = match cmd {
            Command::Shot { strike, call } => self.shoot(seat, strike, *call)?,
            Command::PlaceCueBall { pos } => {
                if let Some(cue) = self.balls.first_mut() {
                    *cue = BallState::at_rest(DVec2::from_array(*pos));
                }
                if self.variant == Variant::Practice {
                    self.to_move = seat;
                }
                self.verdict(vec![format!("{seat} places the cue ball")])
            }
            Command::PlaceBall { ball, pos } => {
                practice::place_ball(self, *ball, *pos);
                self.to_move = seat;
                self.verdict(Vec::new())
            }
            Command::LoadLayout { balls } => {
                practice::load_layout(self, balls);
                self.to_move = seat;
                self.verdict(vec!["Layout loaded".into()])
            }
            Command::Decide(choice) => self.decide(seat, *choice),
            Command::TimeExpired => self.time_expired(seat),
            Command::Concede | Command::Forfeit => {
                let how = match cmd {
                    Command::Forfeit => "left and forfeited",
                    _ => "conceded",
                };
                let (winner, reason) = if self.variant == Variant::Practice {
                    (None, "Practice ended".to_string())
                } else {
                    (
                        Some(seat.other()),
                        format!("{seat} {how}; {} wins", seat.other()),
                    )
                };
                self.enact(
                    Next::Over {
                        winner,
                        reason: reason.clone(),
                    },
                    vec![reason],
                    false,
                    None,
                )
            }
            Command::ProposeStalemate => {
                self.stalemate[seat.index()] = true;
                if self.stalemate[seat.other().index()] {
                    let breaker = self.breaker;
                    let reasons = vec![format!(
                        "Stalemate agreed by both players: re-rack, {breaker} breaks again"
                    )];
                    self.enact(Next::Rerack { breaker }, reasons, false, None)
                } else {
                    self.verdict(vec![format!("{seat} offers a stalemate")])
                }
            }
        };
        self.turn = self.turn.wrapping_add(1);
        Ok(verdict)
    }

    /// A verdict for a command that leaves the turn where it is.
    fn verdict(&self, reasons: Vec<String>) -> Verdict {
        Verdict {
            reasons,
            foul: false,
            shot: None,
            next: self.to_move,
            over: None,
            outcome: None,
        }
    }

    fn shoot(
        &mut self,
        seat: Seat,
        strike: &Strike,
        call: Option<u8>,
    ) -> Result<Verdict, RuleError> {
        if self.carom.is_some() {
            return self.carom_shot(seat, strike);
        }
        let outcome =
            simulate(&self.shot_for(strike)).map_err(|e| RuleError::InvalidShot(e.to_string()))?;
        let facts = ShotFacts::from_outcome(&outcome, self.table());
        let report = ShotReport {
            hash: outcome.hash(),
            events: outcome.events.clone(),
            pocketed: facts.pocketed.clone(),
        };
        let mut verdict = self.judge_shot(seat, call, outcome.finals.clone(), &facts, report);
        verdict.outcome = Some(outcome);
        Ok(verdict)
    }

    /// Judges a shot that left the balls at `finals` with `facts`, and moves the game on.
    fn judge_shot(
        &mut self,
        seat: Seat,
        call: Option<u8>,
        finals: Vec<BallState>,
        facts: &ShotFacts,
        report: ShotReport,
    ) -> Verdict {
        let before = std::mem::replace(&mut self.balls, finals);
        for &b in &facts.off_table {
            if let Some(ball) = self.balls.get_mut(usize::from(b)) {
                *ball = off_table();
            }
        }
        self.stalemate = [false; 2];
        let push_out = matches!(self.phase, Phase::Shooting { push_out: true, .. });
        let ruling = match self.variant {
            Variant::EightBall(rules) => eight::judge(self, rules, seat, call, facts, &before),
            Variant::NineBall => nine::judge(self, seat, call, facts, &before, push_out),
            Variant::Practice => practice::judge(self, seat, facts),
            // Three-cushion shots are judged by the match (`carom_shot`), never here: the
            // turn stays as it is.
            Variant::ThreeCushion { .. } => Ruling {
                reasons: Vec::new(),
                foul: false,
                next: Next::Shoot {
                    seat: self.to_move,
                    in_hand: None,
                    options: Vec::new(),
                },
            },
        };
        self.breaking = false;
        self.enact(ruling.next, ruling.reasons, ruling.foul, Some(report))
    }

    fn decide(&mut self, seat: Seat, choice: Choice) -> Verdict {
        let mut reasons = vec![format!("{seat} chooses to {choice}")];
        if choice == Choice::SpotNearestBall {
            reasons.extend(self.spot_nearest_ball());
            return self.verdict(reasons);
        }
        if choice == Choice::Respot {
            return self.carom_respot(seat, reasons);
        }
        if choice == Choice::PushOut {
            if let Phase::Shooting { in_hand, .. } = self.phase {
                self.phase = Phase::Shooting {
                    in_hand,
                    options: Vec::new(),
                    push_out: true,
                };
            }
            return self.verdict(reasons);
        }
        let next = match (self.pending.take(), choice) {
            (Some(Pending::IllegalBreak { scratched, .. }), Choice::AcceptTable) => Next::Shoot {
                seat,
                in_hand: scratched.then_some(InHand::Kitchen),
                options: Vec::new(),
            },
            (Some(Pending::IllegalBreak { offender, .. }), Choice::OpponentRebreaks) => {
                Next::Rerack { breaker: offender }
            }
            (Some(Pending::EightOnBreak { foul }), Choice::SpotEightAndContinue) => {
                let kind = self.table();
                let spotted = rack::spot(&mut self.balls, 8, kind);
                reasons.push(format!("The 8 is spotted {}", spotted.describe()));
                Next::Shoot {
                    seat,
                    in_hand: foul.then_some(InHand::Kitchen),
                    options: Vec::new(),
                }
            }
            (Some(Pending::JumpedOnBreak), choice) => Next::Shoot {
                seat,
                in_hand: (choice == Choice::CueBallInKitchen).then_some(InHand::Kitchen),
                options: Vec::new(),
            },
            (Some(Pending::PushOut { .. }), Choice::AcceptTable) => Next::Shoot {
                seat,
                in_hand: None,
                options: Vec::new(),
            },
            (Some(Pending::PushOut { pusher }), Choice::HandBack) => Next::Shoot {
                seat: pusher,
                in_hand: None,
                options: Vec::new(),
            },
            // Re-rack (after an illegal break or the 8 on the break): the chooser breaks.
            _ => Next::Rerack { breaker: seat },
        };
        self.enact(next, reasons, false, None)
    }

    fn time_expired(&mut self, seat: Seat) -> Verdict {
        if let Phase::Deciding { options } = &self.phase {
            // Out of time on a choice: the first option offered is taken (no foul).
            let choice = options.first().copied().unwrap_or(Choice::AcceptTable);
            let mut verdict = self.decide(seat, choice);
            verdict.reasons.insert(
                0,
                format!("{seat} ran out of time; the first option is taken"),
            );
            return verdict;
        }
        if self.carom.is_some() {
            return self.carom_time_out(seat);
        }
        let mut reasons = vec![format!("Foul: {seat} ran out of time")];
        self.stalemate = [false; 2];
        let opponent = seat.other();
        let mut next = if self.breaking {
            // The break was never taken: the opponent breaks the same rack.
            self.breaker = opponent;
            reasons.push(format!("{opponent} breaks"));
            Next::Shoot {
                seat: opponent,
                in_hand: Some(InHand::Kitchen),
                options: Vec::new(),
            }
        } else {
            reasons.push(format!("{opponent} has ball in hand"));
            Next::Shoot {
                seat: opponent,
                in_hand: Some(InHand::Anywhere),
                options: Vec::new(),
            }
        };
        if self.variant == Variant::NineBall {
            if let Some(over) = nine::count_foul(self, seat, &mut reasons) {
                next = over;
            }
        }
        self.enact(next, reasons, true, None)
    }

    /// Moves the game to `next` and builds the verdict.
    fn enact(
        &mut self,
        next: Next,
        reasons: Vec<String>,
        foul: bool,
        shot: Option<ShotReport>,
    ) -> Verdict {
        let mut over = None;
        match next {
            Next::Shoot {
                seat,
                mut in_hand,
                options,
            } => {
                let cue_off = self.balls.first().is_none_or(is_off_table);
                if cue_off && in_hand.is_none() {
                    in_hand = Some(InHand::Anywhere);
                }
                self.to_move = seat;
                self.pending = None;
                self.phase = Phase::Shooting {
                    in_hand,
                    options,
                    push_out: false,
                };
                self.offer_spot_nearest_ball();
            }
            Next::Decide {
                seat,
                options,
                pending,
            } => {
                self.to_move = seat;
                self.pending = Some(pending);
                self.phase = Phase::Deciding { options };
            }
            Next::Over { winner, reason } => {
                self.pending = None;
                over = Some((winner, reason.clone()));
                self.phase = Phase::Over { winner, reason };
            }
            Next::Rerack { breaker } => {
                self.racks = self.racks.wrapping_add(1);
                self.rack(breaker);
            }
        }
        Verdict {
            reasons,
            foul,
            shot,
            next: self.to_move,
            over,
            outcome: None,
        }
    }

    /// Racks the balls for the current rack number; `breaker` breaks from the kitchen.
    fn rack(&mut self, breaker: Seat) {
        let seed = rack::rack_seed(self.seed, self.racks);
        self.carom = Game::start_carom(self.variant);
        self.balls = match (self.variant, &self.carom) {
            (Variant::NineBall, _) => rack::nine_ball(self.table(), seed),
            (Variant::EightBall(_) | Variant::Practice, _) => rack::eight_ball(self.table(), seed),
            // The match sets up its own start.
            (Variant::ThreeCushion { .. }, m) => {
                m.iter().flat_map(|m| m.balls()).copied().collect()
            }
        };
        self.breaker = breaker;
        self.to_move = breaker;
        self.group_a = None;
        self.fouls = [0; 2];
        self.pending = None;
        self.stalemate = [false; 2];
        let practice = self.variant == Variant::Practice;
        let carom = self.carom.is_some();
        self.breaking = !practice && !carom;
        // In practice the cue ball is always in hand: it can be put anywhere free. In
        // three-cushion no ball is ever in hand.
        self.phase = Phase::Shooting {
            in_hand: match (practice, carom) {
                (true, _) => Some(InHand::Anywhere),
                (false, true) => None,
                (false, false) => Some(InHand::Kitchen),
            },
            options: Vec::new(),
            push_out: false,
        };
    }
}

/// Is `ball` off the table (pocketed, or gone over a rail)? Balls off the table keep their
/// place in the list.
pub fn is_off_table(ball: &BallState) -> bool {
    ball.motion == MotionState::Pocketed
}

/// A ball that left the table (not through a pocket).
fn off_table() -> BallState {
    BallState {
        motion: MotionState::Pocketed,
        pocket: None,
        ..BallState::at_rest(DVec2::ZERO)
    }
}

/// "the 8", "the cue ball".
fn ball_name(ball: u8) -> String {
    if ball == facts::CUE {
        "the cue ball".into()
    } else {
        format!("the {ball}")
    }
}

/// `s` with its first letter in upper case ("The 8").
fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(first) => first.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}

/// A readable pocket name for `index` on `kind`.
pub fn pocket_name(kind: TableKind, index: u8) -> String {
    let table = Table::new(kind);
    let name = table.pockets.get(usize::from(index)).map(|p| p.name);
    match name {
        Some("lb") => "bottom-left corner".into(),
        Some("lc") => "left side pocket".into(),
        Some("lt") => "top-left corner".into(),
        Some("rb") => "bottom-right corner".into(),
        Some("rc") => "right side pocket".into(),
        Some("rt") => "top-right corner".into(),
        Some(other) => other.into(),
        None => format!("pocket {index}"),
    }
}
