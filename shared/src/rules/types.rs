//! The rules' vocabulary: the games, settings, seats, commands, choices, phases and the
//! verdicts and errors a command gets, and the rules' own record of what a shot leads to.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::{Event, Outcome, Strike, TableKind};

use super::three_cushion;

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
    /// Snooker (WPBSA rules) on the snooker table: frames of `reds` reds (15, or 10 or 6 for
    /// short games), a match of the best of `best_of` frames (1 to
    /// [`crate::rules::snooker::MAX_BEST_OF`], odd).
    Snooker {
        /// Reds racked each frame: 15, 10 or 6.
        reds: u8,
        /// Frames in the match; the first to win more than half wins.
        best_of: u8,
    },
}

impl Variant {
    /// Three-cushion to the default race.
    pub fn three_cushion() -> Variant {
        Variant::ThreeCushion {
            race: three_cushion::DEFAULT_RACE,
        }
    }

    /// A single frame of snooker with 15 reds.
    pub fn snooker() -> Variant {
        Variant::Snooker {
            reds: 15,
            best_of: 1,
        }
    }

    /// The table this game is played on when the settings name `table`: three-cushion is
    /// only ever played on the carom table, snooker on the snooker table.
    pub fn table(self, table: TableKind) -> TableKind {
        match self {
            Variant::ThreeCushion { .. } => TableKind::Carom,
            Variant::Snooker { .. } => TableKind::Snooker,
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

/// Counts the commands applied to a game: it changes whenever the game does.
pub type TurnId = u32;

/// What a player asks for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Strike the cue ball. `call` is the pocket (index into the table's pockets) the
    /// shooter calls: required for the 8, and for every shot with `call_every_shot`.
    Shot {
        /// The strike on the shooter's cue ball ([`Game::cue_ball`](super::Game::cue_ball)).
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
    /// [`crate::rules::layout_from_scene`] builds one from a scene file.
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
    /// Snooker, after a foul: have the offender play again from the table as it lies.
    OffenderPlaysAgain,
    /// Snooker, after a foul and a miss: have the balls put back where they were before the
    /// stroke, and the offender play again.
    ReplaceBalls,
    /// Snooker: nominate this ball (its index) for the coming stroke: a colour after a red,
    /// or any ball as the free ball.
    Nominate(u8),
}

/// Where the cue ball may be put when it is in hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum InHand {
    /// Behind the head string (centre at `y < length/4`).
    Kitchen,
    /// Anywhere on the cloth, clear of the cushions, pockets and other balls.
    Anywhere,
    /// Snooker: in the D (on or behind the baulk line, within the D's radius of its centre).
    D,
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

impl Verdict {
    /// Whether a shot `seat` played did what a shot is meant to: won the game, or kept the
    /// turn without a foul (what the computer's chance of success counts).
    pub fn succeeded_for(&self, seat: Seat) -> bool {
        match &self.over {
            Some((winner, _)) => *winner == Some(seat),
            None => !self.foul && self.next == seat,
        }
    }
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
pub(super) enum Pending {
    /// 8-ball: the break was illegal (`offender` broke; `scratched` with it).
    IllegalBreak { offender: Seat, scratched: bool },
    /// 8-ball: the 8 fell or left the table on the break (`foul`: the breaker fouled too,
    /// and the opponent chooses).
    EightOnBreak { foul: bool },
    /// 8-ball: an object ball left the table on an otherwise legal break.
    JumpedOnBreak,
    /// 9-ball: `pusher` pushed out.
    PushOut { pusher: Seat },
    /// Snooker: the choice after a foul (its details are the match's).
    SnookerFoul,
}

/// What a judged shot leads to.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Next {
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

/// What a pool variant's judge decided of one shot: its reasons, whether it was a foul and
/// what comes next (the wire's `protocol::Ruling` is a verdict's summary, another thing).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Judged {
    pub(super) reasons: Vec<String>,
    pub(super) foul: bool,
    pub(super) next: Next,
}

impl Judged {
    /// The shot ends in a choice: `seat` picks one of `options`, and `pending` says what the
    /// answer settles.
    pub(super) fn offer(
        reasons: Vec<String>,
        foul: bool,
        seat: Seat,
        options: Vec<Choice>,
        pending: Pending,
    ) -> Judged {
        Judged {
            reasons,
            foul,
            next: Next::Decide {
                seat,
                options,
                pending,
            },
        }
    }
}
