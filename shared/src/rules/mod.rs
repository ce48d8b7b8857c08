//! The game rules: 8-ball (World Standardized Rules, or the `bar` variant), 9-ball,
//! three-cushion billiards, snooker and practice.
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
//! Snooker is played by `snooker.rs` (its module documentation lists the rules it judges);
//! its balls are 0 = cue ball, 1 to 15 = reds, 16 to 21 = yellow to black.
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
mod game;
mod kitchen;
mod nine;
mod practice;
pub mod rack;
pub mod snooker;
#[cfg(test)]
mod tests;
pub mod three_cushion;
mod types;
mod words;

pub use facts::ShotFacts;
pub use game::is_off_table;
use game::off_table;
pub use game::Game;
pub use practice::layout_from_scene;
pub use types::*;
pub use words::pocket_name;
use words::{ball_name, capitalise};
