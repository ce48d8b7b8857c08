//! What the window shows of a snooker game, computed without a window: the markings on the cloth (baulk line, the D, the six spots), the scores and the words of
//! the HUD (the break, the points remaining, "snookers required"), and the nominations: a
//! ball clicked on the cloth, or a colour's button.

use ::glam::DVec2;
use breakshot_shared::rules::snooker::frame::{BallOn, Snooker};
use breakshot_shared::rules::snooker::table::{self, colour_name, COLOURS};
use breakshot_shared::rules::{Choice, Command, Game, Phase, Seat};

use super::palette::{snooker_ball_colour, Rgb};

/// The markings chalked on the cloth.
pub const MARKING: Rgb = [226, 232, 224];

/// The lines chalked on a snooker table, in scene coordinates (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Markings {
    /// The baulk line, from cushion to cushion.
    pub baulk: (DVec2, DVec2),
    /// The D's semicircle behind the baulk line, as a polyline from the green's spot to the
    /// yellow's.
    pub d_arc: Vec<DVec2>,
    /// The six spots, yellow to black.
    pub spots: [DVec2; 6],
}

/// Segments of the D's semicircle.
const ARC_STEPS: usize = 32;
/// Radius a spot is drawn with (m): small, as a real spot is, but seen at a glance.
pub const SPOT_RADIUS: f64 = 0.008;

/// The markings of the snooker table (WPBSA section 1, as the rules place them).
pub fn markings() -> Markings {
    let centre = table::d_centre();
    let width = 2.0 * centre.x;
    let d_arc = (0..=ARC_STEPS)
        .map(|k| {
            // From the green (x < centre) round the baulk side (y < baulk line) to the yellow.
            let a = core::f64::consts::PI * (1.0 + k as f64 / ARC_STEPS as f64);
            centre + table::D_RADIUS * DVec2::new(libm::cos(a), libm::sin(a))
        })
        .collect();
    Markings {
        baulk: (
            DVec2::new(0.0, table::BAULK_LINE),
            DVec2::new(width, table::BAULK_LINE),
        ),
        d_arc,
        spots: COLOURS.map(table::spot),
    }
}

/// A small circle about `centre` as a polyline, closed (for a spot drawn through any view).
pub fn circle(centre: DVec2, r: f64, steps: usize) -> Vec<DVec2> {
    (0..=steps)
        .map(|k| {
            let a = core::f64::consts::TAU * k as f64 / steps as f64;
            centre + r * DVec2::new(libm::cos(a), libm::sin(a))
        })
        .collect()
}

/// The seat's part of its HUD line: the frame's score, and the frames won in a longer match
/// (": 34" or ": 34, frames 1 of 2").
pub fn score_text(m: &Snooker, seat: Seat) -> String {
    let points = m.scores[seat.index()];
    if m.best_of > 1 {
        format!(
            ": {points}, frames {} of {}",
            m.frames[seat.index()],
            m.frames_to_win()
        )
    } else {
        format!(": {points}")
    }
}

/// The words for the ball on: "a red", "the blue (nominated)", "a colour (nominate one)".
pub fn ball_on_text(m: &Snooker, game: &Game) -> String {
    if m.free_ball {
        return match m.nominated {
            Some(b) => format!("free ball: {} nominated", table::ball_name(b)),
            None => "free ball: nominate a ball".into(),
        };
    }
    match m.ball_on(game.balls()) {
        BallOn::Red => "on: a red".into(),
        BallOn::Colour(Some(c)) => format!("on: the {} (nominated)", colour_name(c)),
        BallOn::Colour(None) => "on: a colour (nominate one)".into(),
        BallOn::Sequence(c) => format!("on: the {}", colour_name(c)),
    }
}

/// The snooker part of the status line: the ball on, the break, the points remaining and
/// who needs snookers ("on: a red | break 9 | 51 remaining | Player B needs snookers").
pub fn status(game: &Game) -> Option<String> {
    let m = game.snooker()?;
    let mut parts = Vec::new();
    if matches!(game.phase(), Phase::Shooting { .. }) {
        parts.push(ball_on_text(m, game));
    }
    if m.break_points > 0 {
        parts.push(format!("break {}", m.break_points));
    }
    parts.push(format!("{} remaining", m.points_remaining(game.balls())));
    for seat in [Seat::A, Seat::B] {
        if m.snookers_required(seat, game.balls()) {
            parts.push(format!("{seat} needs snookers"));
        }
    }
    if m.respotted_black {
        parts.push("re-spotted black".into());
    }
    Some(parts.join("  |  "))
}

/// The balls the options let the striker nominate.
pub fn nominable(options: &[Choice]) -> Vec<u8> {
    options
        .iter()
        .filter_map(|c| match c {
            Choice::Nominate(b) => Some(*b),
            _ => None,
        })
        .collect()
}

/// What a click at `at` (scene coordinates) nominates while the options offer nominations:
/// the ball under it, if it is not nominated already and not the cue ball; `Err` with the
/// rules' reason when that ball cannot be nominated (a red when a colour is to be), so that
/// the click is answered rather than taken for aiming.
pub fn nomination_at(
    game: &Game,
    seat: Seat,
    options: &[Choice],
    at: DVec2,
) -> Option<Result<Choice, String>> {
    let offered = nominable(options);
    if offered.is_empty() {
        return None;
    }
    let r = game.params().ball_radius;
    let nominated = game.snooker().and_then(|m| m.nominated);
    let ball = (1..game.balls().len()).find(|&b| {
        let s = &game.balls()[b];
        !s.motion.is_gone() && (s.pos - at).length() <= r
    })?;
    let ball = u8::try_from(ball).ok().filter(|&b| Some(b) != nominated)?;
    if offered.contains(&ball) {
        return Some(Ok(Choice::Nominate(ball)));
    }
    match game.check(seat, &Command::Decide(Choice::Nominate(ball))) {
        Err(why) => Some(Err(why.to_string())),
        // The rules would take what the options do not offer: not for a click to decide.
        Ok(()) => None,
    }
}

/// The words on a choice's button: a colour's name for a nomination ("blue"), the rules'
/// words for the others, shortened to fit a button.
pub fn button_text(choice: Choice) -> String {
    match choice {
        Choice::Nominate(b) => colour_name(b).to_owned(),
        Choice::AcceptTable => "play on".into(),
        Choice::OffenderPlaysAgain => "make them play again".into(),
        Choice::ReplaceBalls => "replace the balls".into(),
        other => other.to_string(),
    }
}

/// The fill of a choice's button in a snooker game: the ball's own colour for a nomination.
pub fn button_colour(choice: Choice) -> Option<Rgb> {
    match choice {
        Choice::Nominate(b) => Some(snooker_ball_colour(b)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::rules::snooker::table::{BLACK, BLUE, GREEN, YELLOW};
    use breakshot_shared::rules::{Settings, Variant};

    fn six_reds() -> Game {
        Game::new(
            Variant::Snooker {
                reds: 6,
                best_of: 3,
            },
            Settings::offline(),
            1,
        )
    }

    #[test]
    fn the_d_is_behind_the_baulk_line_between_the_green_and_the_yellow() {
        let m = markings();
        let first = m.d_arc[0];
        let last = *m.d_arc.last().unwrap();
        assert!((first - table::spot(GREEN)).length() < 1e-9);
        assert!((last - table::spot(YELLOW)).length() < 1e-9);
        for p in &m.d_arc {
            assert!(p.y <= table::BAULK_LINE + 1e-9, "{p}");
            assert!(((*p - table::d_centre()).length() - table::D_RADIUS).abs() < 1e-9);
        }
        assert_eq!(m.baulk.0.y, table::BAULK_LINE);
        assert!((m.baulk.1.x - 1.778).abs() < 0.01);
        assert_eq!(m.spots[5], table::spot(BLACK));
    }

    #[test]
    fn the_hud_shows_scores_frames_and_the_points_remaining() {
        let game = six_reds();
        let m = game.snooker().unwrap();
        assert_eq!(score_text(m, Seat::A), ": 0, frames 0 of 2");
        let status = status(&game).unwrap();
        // Six reds with a black each and the colours: 6 * 8 + 27.
        assert!(status.contains("on: a red"), "{status}");
        assert!(status.contains("75 remaining"), "{status}");
        assert!(!status.contains("snookers"), "{status}");
    }

    #[test]
    fn a_click_on_a_nominable_ball_nominates_it_on_another_says_why_not_and_elsewhere_aims() {
        let game = six_reds();
        let seat = game.to_move();
        let options = [Choice::Nominate(BLUE), Choice::Nominate(BLACK)];
        let at = |ball: u8| game.balls()[usize::from(ball)].pos;
        assert_eq!(
            nomination_at(&game, seat, &options, at(BLUE) + DVec2::new(0.01, 0.0)),
            Some(Ok(Choice::Nominate(BLUE)))
        );
        assert_eq!(
            nomination_at(&game, seat, &options, at(BLUE) + DVec2::new(0.2, 0.0)),
            None
        );
        // The green is on the table but not offered: the rules say why.
        let Some(Err(why)) = nomination_at(&game, seat, &options, at(GREEN)) else {
            panic!("the green nominated");
        };
        assert!(why.contains("green"), "{why}");
        // The cue ball is never nominated, and with no nomination offered a click on a ball
        // is left to aim.
        assert_eq!(nomination_at(&game, seat, &options, at(0)), None);
        assert_eq!(nomination_at(&game, seat, &[], at(BLUE)), None);
        assert_eq!(button_text(Choice::Nominate(BLUE)), "blue");
        assert_eq!(
            button_colour(Choice::Nominate(BLUE)),
            Some(super::super::palette::SNOOKER_COLOURS[3])
        );
        assert_eq!(button_colour(Choice::AcceptTable), None);
    }
}
