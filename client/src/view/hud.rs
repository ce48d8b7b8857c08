//! The words of the heads-up display: players, groups, whose turn, what the game waits for,
//! the last verdict, the shot clock and the connection. Built from a rules [`Game`], the same
//! for a replay and for a game played over the network.

use breakshot_shared::physics::MotionState;
use breakshot_shared::rules::{is_off_table, Choice, Game, InHand, Phase, Seat, Variant, Verdict};

/// One player's line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlayerLine {
    /// The seat the line is about.
    pub seat: Seat,
    /// The words shown.
    pub text: String,
    /// This seat shoots or decides next.
    pub to_move: bool,
}

/// The state of the link to the server, as the window shows it.
#[derive(Clone, Debug, PartialEq)]
pub enum Connection {
    /// No server: practice or a replay.
    Offline,
    /// Connecting to the server.
    Connecting,
    /// In a room whose other seat nobody has taken yet.
    WaitingForOpponent,
    /// Both players are there.
    Connected,
    /// Our connection dropped; taking the seat back.
    Reconnecting,
    /// The opponent's connection dropped; the game is forfeited after `seconds_left`.
    OpponentLeft {
        /// Seconds before the game is forfeited.
        seconds_left: f64,
    },
    /// The connection ended, with the reason.
    Closed(String),
}

impl Connection {
    /// The kind of state, without what it carries: a name that stays put while a countdown
    /// runs (for the page's report of how the game stands).
    pub fn kind(&self) -> &'static str {
        match self {
            Connection::Offline => "Offline",
            Connection::Connecting => "Connecting",
            Connection::WaitingForOpponent => "WaitingForOpponent",
            Connection::Connected => "Connected",
            Connection::Reconnecting => "Reconnecting",
            Connection::OpponentLeft { .. } => "OpponentLeft",
            Connection::Closed(_) => "Closed",
        }
    }
}

/// The readable name of a game.
pub fn variant_name(v: Variant) -> &'static str {
    match v {
        Variant::EightBall(breakshot_shared::rules::EightBallRules::Wpa) => "8-ball (WPA rules)",
        Variant::EightBall(breakshot_shared::rules::EightBallRules::Bar) => "8-ball (bar rules)",
        Variant::NineBall => "9-ball",
        Variant::Practice => "practice",
        Variant::ThreeCushion { .. } => "three-cushion",
        Variant::Snooker { .. } => "snooker",
    }
}

/// Both players' lines, by name once known (with the seat's letter), with their groups
/// once the table is closed, and their ratings once a rated game has ended; `me` is marked
/// "(you)".
pub fn players(
    game: &Game,
    me: Option<Seat>,
    names: &[Option<String>; 2],
    ratings: &[Option<i32>; 2],
) -> [PlayerLine; 2] {
    let line = |seat: Seat| {
        let k = usize::from(seat == Seat::B);
        let mut text = match &names[k] {
            Some(name) => format!("{name} ({})", if seat == Seat::A { "A" } else { "B" }),
            None => seat.to_string(),
        };
        if let Some(rating) = ratings[k] {
            text.push_str(&format!(" {rating}"));
        }
        if me == Some(seat) {
            text.push_str(" (you)");
        }
        match (game.variant(), game.group_of(seat)) {
            (Variant::EightBall(_), Some(g)) => {
                text.push_str(match g {
                    breakshot_shared::rules::Group::Solids => ": solids",
                    breakshot_shared::rules::Group::Stripes => ": stripes",
                });
                text.push_str(&balls_left(
                    g.balls().filter(|&n| on_table(game, n)).count(),
                ));
            }
            (Variant::EightBall(_), None) => text.push_str(": open table"),
            (Variant::NineBall, _) if game.consecutive_fouls(seat) > 0 => text.push_str(&format!(
                ": {} foul(s) in a row",
                game.consecutive_fouls(seat)
            )),
            (Variant::ThreeCushion { .. }, _) => {
                if let Some(m) = game.carom() {
                    let ball = match seat {
                        Seat::A => "white",
                        Seat::B => "yellow",
                    };
                    let points = m.scores()[usize::from(seat == Seat::B)];
                    text.push_str(&format!(": {ball}, {points} of {}", m.race()));
                }
            }
            (Variant::Snooker { .. }, _) => {
                if let Some(m) = game.snooker() {
                    text.push_str(&super::snooker::score_text(m, seat));
                }
            }
            _ => {}
        }
        let to_move = !matches!(game.phase(), Phase::Over { .. }) && game.to_move() == seat;
        PlayerLine {
            seat,
            text,
            to_move,
        }
    };
    [line(Seat::A), line(Seat::B)]
}

/// What is left of a player's group: how many balls, or the 8 once they are all down.
fn balls_left(left: usize) -> String {
    match left {
        0 => ", on the 8".to_string(),
        1 => ", 1 ball left".to_string(),
        n => format!(", {n} balls left"),
    }
}

/// Whether ball number `n` is still on the table (not pocketed, not jumped off).
fn on_table(game: &Game, n: u8) -> bool {
    game.balls()
        .get(usize::from(n))
        .is_some_and(|b| b.motion != MotionState::Pocketed && !is_off_table(b))
}

/// `text` with each seat the rules name ("Player A", "Player B") called by the player's name
/// where it is known (a name the player chose, or the computer's "Computer (level 3)").
pub fn named(text: &str, names: &[Option<String>; 2]) -> String {
    let seats = [Seat::A, Seat::B].map(|s| s.to_string());
    // One pass over the text, so a name that reads like a seat is not named again.
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some((at, k)) = seats
        .iter()
        .enumerate()
        .filter_map(|(k, seat)| rest.find(seat.as_str()).map(|at| (at, k)))
        .min()
    {
        out.push_str(&rest[..at]);
        out.push_str(names[k].as_deref().unwrap_or(&seats[k]));
        rest = &rest[at + seats[k].len()..];
    }
    out.push_str(rest);
    out
}

/// The line under a finished game's banner: what the player can do next. `asked`: this
/// player asked for a rematch the other has not answered yet (online).
pub fn after_the_game(
    watching: bool,
    asked: bool,
    me: Option<Seat>,
    names: &[Option<String>; 2],
) -> String {
    if watching {
        "Esc: menu".to_owned()
    } else if asked {
        let other = me.map(Seat::other).map_or_else(
            || "the other player".to_owned(),
            |s| named(&s.to_string(), names),
        );
        format!("Rematch asked: waiting for {other} to accept  -  Esc: menu")
    } else {
        "R: rematch, Esc: menu".to_owned()
    }
}

/// The banner of a game that is over, for the player in `me`'s seat: "You won" or "You
/// lost"; for someone watching (or two players at one computer), who won, by name.
pub fn game_over_banner(
    game: &Game,
    me: Option<Seat>,
    names: &[Option<String>; 2],
) -> Option<String> {
    let Phase::Over { winner, .. } = game.phase() else {
        return None;
    };
    Some(match (winner, me) {
        (Some(w), Some(me)) if *w == me => "You won".to_owned(),
        (Some(_), Some(_)) => "You lost".to_owned(),
        (Some(w), None) => named(&format!("{w} won"), names),
        (None, _) => "Game over".to_owned(),
    })
}

/// What the game waits for, in words, the seats by name; in 9-ball, with the ball on.
pub fn status(game: &Game, names: &[Option<String>; 2]) -> String {
    named(&status_of_seats(game), names)
}

fn status_of_seats(game: &Game) -> String {
    let text = waiting_for(game);
    let legal = game.legal_first_balls();
    match (game.variant(), game.phase(), &legal[..]) {
        (Variant::NineBall, Phase::Shooting { .. }, [on]) => format!("{text} - the {on} is on"),
        (Variant::Snooker { .. }, _, _) => match super::snooker::status(game) {
            Some(more) => format!("{text}  |  {more}"),
            None => text,
        },
        _ => text,
    }
}

fn waiting_for(game: &Game) -> String {
    let who = game.to_move();
    match game.phase() {
        Phase::Over { reason, .. } => format!("Game over: {reason}"),
        Phase::Deciding { options } => {
            format!("{who} to choose: {}", choices(options))
        }
        Phase::Shooting { in_hand, .. } => {
            let act = if game.is_break() { "break" } else { "shoot" };
            match in_hand {
                Some(InHand::Kitchen) => {
                    format!("{who} to {act}, cue ball in hand behind the head string")
                }
                Some(InHand::Anywhere) => format!("{who} to {act}, cue ball in hand"),
                Some(InHand::D) => format!("{who} to {act}, cue ball in hand in the D"),
                None => format!("{who} to {act}"),
            }
        }
    }
}

fn choices(options: &[Choice]) -> String {
    options
        .iter()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(" or ")
}

/// The last verdict as lines: each reason, then the end of the game if it is not among them;
/// the seats by name.
pub fn verdict_lines(v: &Verdict, names: &[Option<String>; 2]) -> Vec<String> {
    let mut lines = v.reasons.clone();
    if let Some((_, reason)) = &v.over {
        if !lines.contains(reason) {
            lines.push(reason.clone());
        }
    }
    lines.iter().map(|l| named(l, names)).collect()
}

/// The shot clock: whole seconds left, or nothing when the game has none.
pub fn shot_clock(seconds_left: Option<f64>) -> Option<String> {
    let s = seconds_left?;
    let s = if s.is_finite() {
        s.max(0.0).ceil() as u64
    } else {
        0
    };
    Some(format!("shot clock {}:{:02}", s / 60, s % 60))
}

/// Seconds left under which the shot clock is shown as a warning.
pub(crate) const CLOCK_WARNING_SECS: f64 = 10.0;

/// Whether the shot clock is running out: the HUD shows it in red.
pub fn clock_running_out(seconds_left: f64) -> bool {
    seconds_left <= CLOCK_WARNING_SECS
}

/// What to tell the shooter who must call a pocket: the 8 when the rules say it is the
/// only ball on in 8-ball, else the shot.
pub fn call_prompt(game: &Game) -> &'static str {
    let on_the_eight =
        matches!(game.variant(), Variant::EightBall(_)) && game.legal_first_balls() == [8];
    if on_the_eight {
        "Click a pocket to call the 8"
    } else {
        "Click a pocket to call your shot"
    }
}

/// The words for a connection state.
pub fn connection(c: &Connection) -> String {
    match c {
        Connection::Offline => "offline".into(),
        Connection::Connecting => "connecting...".into(),
        Connection::WaitingForOpponent => "waiting for the opponent".into(),
        Connection::Connected => "connected".into(),
        Connection::Reconnecting => "connection lost, reconnecting...".into(),
        Connection::OpponentLeft { seconds_left } => {
            // Short, so that it stays readable in the game-info box of a small window.
            format!(
                "opponent left: forfeits in {:.0} s unless back",
                seconds_left.ceil()
            )
        }
        Connection::Closed(why) => format!("disconnected: {why}"),
    }
}

/// One piece of the game-info text, and whether it warns (the shot clock running out).
pub type InfoPiece = (String, bool);

/// The game-info box's text in `rows` rows (one or two), each row's pieces in order: the
/// game, the shot clock and the connection. With two rows the connection has the second to
/// itself, so that a long state ("opponent left: ...") is drawn at a readable size.
pub fn game_info(
    variant: Variant,
    shot_clock_secs: Option<f64>,
    connection_state: &Connection,
    rows: usize,
) -> Vec<Vec<InfoPiece>> {
    let gap = || (HINT_SEPARATOR.to_owned(), false);
    let mut first = vec![(variant_name(variant).to_owned(), false)];
    if let Some(clock) = shot_clock(shot_clock_secs) {
        first.push(gap());
        let warn = shot_clock_secs.is_some_and(clock_running_out);
        first.push((clock, warn));
    }
    let state = (connection(connection_state), false);
    if rows >= 2 {
        vec![first, vec![state]]
    } else {
        first.push(gap());
        first.push(state);
        vec![first]
    }
}

/// The pieces the hint bar's keys are written in, between which it may break a row.
pub const HINT_SEPARATOR: &str = "  |  ";

/// The hint bar's `text` in at most `rows` rows, broken between its pieces (separated by
/// [`HINT_SEPARATOR`]) so the rows are about as long as each other.
pub fn hint_rows(text: &str, rows: usize) -> Vec<String> {
    let pieces: Vec<&str> = text.split(HINT_SEPARATOR).collect();
    if rows <= 1 || pieces.len() < 2 {
        return vec![text.to_owned()];
    }
    let total = text.chars().count();
    let target = total.div_ceil(rows);
    let mut out: Vec<String> = vec![String::new()];
    for piece in pieces {
        let full = out.len() == rows;
        let row = out.last_mut().expect("one row at least");
        let longer = row.chars().count() + HINT_SEPARATOR.len() + piece.chars().count();
        if row.is_empty() {
            row.push_str(piece);
        } else if longer <= target || full {
            row.push_str(HINT_SEPARATOR);
            row.push_str(piece);
        } else {
            out.push(piece.to_owned());
        }
    }
    out
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_hint_bar_breaks_its_keys_between_pieces_into_rows_of_about_one_length() {
        let keys = "Mouse: aim  |  Space: shoot  |  W/S: elevation  |  V: 3-D  |  Esc: leave";
        assert_eq!(hint_rows(keys, 1), vec![keys.to_owned()]);
        let two = hint_rows(keys, 2);
        assert_eq!(two.len(), 2);
        assert_eq!(two.join(HINT_SEPARATOR), keys);
        let (a, b) = (two[0].len() as i32, two[1].len() as i32);
        assert!((a - b).abs() < 20, "{two:?}");
        // A message has no pieces: one row.
        assert_eq!(
            hint_rows("Game resumed", 2),
            vec!["Game resumed".to_owned()]
        );
    }
    use super::*;

    #[test]
    fn after_a_game_the_line_names_whom_a_rematch_waits_for() {
        let names = [Some("ann".to_owned()), Some("ben".to_owned())];
        assert_eq!(
            after_the_game(false, true, Some(Seat::A), &names),
            "Rematch asked: waiting for ben to accept  -  Esc: menu"
        );
        assert!(after_the_game(false, true, Some(Seat::B), &names).contains("for ann to"));
        assert_eq!(
            after_the_game(false, false, Some(Seat::A), &names),
            "R: rematch, Esc: menu"
        );
        assert_eq!(after_the_game(true, true, None, &names), "Esc: menu");
    }
    use crate::test_games::eight_ball;
    use breakshot_shared::rules::{Command, EightBallRules, Settings};

    #[test]
    fn a_new_game_shows_the_breaker_and_an_open_table() {
        let g = eight_ball(3);
        let [a, b] = players(&g, Some(Seat::B), &[None, None], &[None, None]);
        assert!(a.to_move && !b.to_move);
        assert_eq!(a.text, "Player A: open table");
        assert_eq!(b.text, "Player B (you): open table");
        assert!(
            status(&g, &NO_NAMES).starts_with("Player A to break"),
            "{}",
            status(&g, &NO_NAMES)
        );
    }

    #[test]
    fn a_nine_ball_game_names_the_ball_on_and_a_group_its_balls_left() {
        let g = Game::new(Variant::NineBall, Settings::offline(), 3);
        assert!(
            status(&g, &NO_NAMES).starts_with("Player A to break")
                && status(&g, &NO_NAMES).ends_with(" - the 1 is on"),
            "{}",
            status(&g, &NO_NAMES)
        );
        assert_eq!(balls_left(7), ", 7 balls left");
        assert_eq!(balls_left(1), ", 1 ball left");
        assert_eq!(balls_left(0), ", on the 8");
        assert!(on_table(&g, 9) && !on_table(&g, 10));
    }

    #[test]
    fn players_are_named_once_the_server_says_their_names() {
        let g = eight_ball(3);
        let [a, b] = players(
            &g,
            Some(Seat::A),
            &[Some("ann".into()), None],
            &[None, None],
        );
        assert_eq!(a.text, "ann (A) (you): open table");
        assert_eq!(b.text, "Player B: open table");
    }

    #[test]
    fn a_rating_stands_beside_the_name_once_known() {
        let g = eight_ball(3);
        let names = [Some("ann".into()), Some("ben".into())];
        let [a, b] = players(&g, Some(Seat::B), &names, &[Some(1662), None]);
        assert_eq!(a.text, "ann (A) 1662: open table");
        assert_eq!(b.text, "ben (B) (you): open table");
    }

    #[test]
    fn three_cushion_shows_each_ball_and_score_against_the_race() {
        let mut g = Game::new(Variant::ThreeCushion { race: 10 }, Settings::offline(), 3);
        let [a, b] = players(&g, Some(Seat::A), &[None, None], &[None, None]);
        assert_eq!(a.text, "Player A (you): white, 0 of 10");
        assert_eq!(b.text, "Player B: yellow, 0 of 10");
        assert_eq!(status(&g, &NO_NAMES), "Player A to shoot");
        g.apply(Seat::A, &Command::TimeExpired)
            .expect_err("no shot clock offline");
        g.apply(Seat::A, &Command::Concede).expect("concede");
        assert_eq!(variant_name(g.variant()), "three-cushion");
    }

    #[test]
    fn a_conceded_game_is_over_for_everyone() {
        let mut g = eight_ball(3);
        let v = g
            .apply(Seat::A, &Command::Concede)
            .expect("concede is allowed");
        assert!(players(&g, None, &[None, None], &[None, None])
            .iter()
            .all(|p| !p.to_move));
        assert!(status(&g, &NO_NAMES).starts_with("Game over: "));
        let lines = verdict_lines(&v, &NO_NAMES);
        assert_eq!(
            lines.iter().filter(|l| l.contains("Player B wins")).count(),
            1
        );
    }

    const NO_NAMES: [Option<String>; 2] = [None, None];

    #[test]
    fn seats_are_called_by_their_names_in_turn_lines_verdicts_and_the_end() {
        let names = [
            Some("ann".to_owned()),
            Some("Computer (level 3)".to_owned()),
        ];
        let mut g = eight_ball(3);
        assert!(
            status(&g, &names).starts_with("ann to break"),
            "{}",
            status(&g, &names)
        );
        assert_eq!(game_over_banner(&g, Some(Seat::A), &names), None);
        let v = g.apply(Seat::A, &Command::Concede).expect("concede");
        let lines = verdict_lines(&v, &names);
        assert!(
            lines.iter().any(|l| l.contains("Computer (level 3) wins")),
            "{lines:?}"
        );
        assert!(lines.iter().all(|l| !l.contains("Player ")), "{lines:?}");
        assert!(status(&g, &names).starts_with("Game over: "));
        assert!(
            !status(&g, &names).contains("Player "),
            "{}",
            status(&g, &names)
        );
        assert_eq!(
            game_over_banner(&g, Some(Seat::A), &names).as_deref(),
            Some("You lost")
        );
        assert_eq!(
            game_over_banner(&g, Some(Seat::B), &names).as_deref(),
            Some("You won")
        );
        assert_eq!(
            game_over_banner(&g, None, &names).as_deref(),
            Some("Computer (level 3) won")
        );
        // A name that reads like a seat is not named again.
        let odd = [Some("Player B".to_owned()), Some("ben".to_owned())];
        assert_eq!(named("Player A beat Player B", &odd), "Player B beat ben");
        // A name not known yet leaves the seat's own words.
        assert!(named("Player A to shoot", &[None, Some("ben".into())]).starts_with("Player A"));
    }

    #[test]
    fn the_call_prompt_names_the_8_only_when_the_rules_say_it_is_on() {
        let called = Settings {
            call_every_shot: true,
            ..Settings::offline()
        };
        let nine = Game::new(Variant::NineBall, called, 3);
        assert_eq!(call_prompt(&nine), "Click a pocket to call your shot");
        let eight = Game::new(Variant::EightBall(EightBallRules::Wpa), called, 3);
        assert_eq!(call_prompt(&eight), "Click a pocket to call your shot");
    }

    #[test]
    fn shot_clock_and_connection_read_well() {
        assert_eq!(shot_clock(Some(61.2)).as_deref(), Some("shot clock 1:02"));
        assert_eq!(shot_clock(Some(-3.0)).as_deref(), Some("shot clock 0:00"));
        assert_eq!(shot_clock(None), None);
        assert!(clock_running_out(9.5) && !clock_running_out(10.5));
        assert!(connection(&Connection::OpponentLeft { seconds_left: 29.2 }).contains("30 s"));
    }

    #[test]
    fn the_game_info_keeps_the_game_and_the_clock_apart_from_a_long_connection_state() {
        let left = Connection::OpponentLeft { seconds_left: 41.5 };
        let two = game_info(Variant::NineBall, Some(8.0), &left, 2);
        let text = |row: &[InfoPiece]| row.iter().map(|(t, _)| t.as_str()).collect::<String>();
        assert_eq!(text(&two[0]), "9-ball  |  shot clock 0:08");
        assert_eq!(text(&two[1]), "opponent left: forfeits in 42 s unless back");
        // Only the clock warns, and only as it runs out.
        assert!(two[0]
            .iter()
            .any(|(t, warn)| *warn && t.starts_with("shot clock")));
        assert!(game_info(Variant::NineBall, Some(50.0), &left, 2)[0]
            .iter()
            .all(|(_, warn)| !warn));
        let one = game_info(Variant::NineBall, None, &Connection::Connected, 1);
        assert_eq!(one.len(), 1);
        assert_eq!(text(&one[0]), "9-ball  |  connected");
    }
}
