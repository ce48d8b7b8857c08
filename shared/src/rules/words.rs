//! The rules' words: how balls, pockets, seats and choices are named in verdicts.

use std::fmt;

use crate::physics::{Table, TableKind};

use super::{facts, snooker, Choice, Seat};

impl fmt::Display for Seat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Seat::A => f.write_str("Player A"),
            Seat::B => f.write_str("Player B"),
        }
    }
}

impl fmt::Display for Choice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Choice::Nominate(ball) = self {
            return write!(f, "nominate {}", snooker::table::ball_name(*ball));
        }
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
            Choice::OffenderPlaysAgain => "make the offender play again",
            Choice::ReplaceBalls => "have the balls replaced and the offender play again",
            Choice::Nominate(_) => "nominate a ball",
        })
    }
}

/// "the 8", "the cue ball".
pub(super) fn ball_name(ball: u8) -> String {
    if ball == facts::CUE {
        "the cue ball".into()
    } else {
        format!("the {ball}")
    }
}

/// `s` with its first letter in upper case ("The 8").
pub(super) fn capitalise(s: &str) -> String {
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
