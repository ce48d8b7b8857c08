//! Colours: the cloth, the rails and the standard pool ball colours (1 yellow, 2 blue, 3 red,
//! 4 purple, 5 orange, 6 green, 7 maroon, 8 black; 9 to 15 are the same colours as stripes),
//! the three carom balls (white, yellow, red) and the snooker balls (the reds and the six
//! colours).

use breakshot_shared::rules::snooker::table;

/// An sRGB colour.
pub type Rgb = [u8; 3];

/// The cloth.
pub const CLOTH: Rgb = [24, 104, 74];
/// The cushions.
pub const CUSHION: Rgb = [18, 82, 56];
/// The rails.
pub const RAIL_WOOD: Rgb = [92, 52, 26];
/// The diamonds on the rails.
pub const DIAMOND: Rgb = [236, 226, 196];
/// Pocket openings.
pub const POCKET: Rgb = [8, 8, 8];
/// Around the table.
pub const BACKGROUND: Rgb = [26, 28, 34];
/// The cue ball.
pub const CUE_BALL: Rgb = [246, 244, 232];
/// The white of stripes and of the number disc.
pub const BALL_WHITE: Rgb = [244, 240, 226];
/// The dots on the cue ball that show its spin.
pub(crate) const CUE_MARKER: Rgb = [200, 40, 40];
/// A ball whose id is not a pool ball number.
pub(crate) const OTHER_BALL: Rgb = [200, 200, 200];
/// The cue stick's wood.
pub const CUE_WOOD: Rgb = [214, 180, 120];
/// The cue's ferrule, at its tip.
pub const CUE_FERRULE: Rgb = [240, 240, 240];
/// The yellow carom ball, seat B's (seat A's white is [`CUE_BALL`]).
pub(crate) const CAROM_YELLOW: Rgb = [246, 206, 40];
/// The red carom ball, the object ball of both.
pub(crate) const CAROM_RED: Rgb = [200, 24, 30];

const SOLIDS: [Rgb; 8] = [
    [250, 196, 20], // 1 yellow
    [24, 64, 196],  // 2 blue
    [214, 30, 36],  // 3 red
    [96, 40, 150],  // 4 purple
    [252, 112, 16], // 5 orange
    [10, 150, 44],  // 6 green
    [124, 22, 38],  // 7 maroon
    [16, 16, 16],   // 8 black
];

/// How a ball is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BallLook {
    /// The ball's colour.
    pub color: Rgb,
    /// A striped ball (white with a band).
    pub stripe: bool,
    /// The number printed on it.
    pub number: Option<u8>,
}

/// The look of the ball called `id` ("cue" or "0" for the cue ball, "1" to "15"; "white",
/// "yellow" and "red" for carom balls, plain and unnumbered).
pub fn ball_look(id: &str) -> BallLook {
    let plain = |color| BallLook {
        color,
        stripe: false,
        number: None,
    };
    match id {
        "cue" | "0" | "white" => return plain(CUE_BALL),
        "yellow" => return plain(CAROM_YELLOW),
        "red" => return plain(CAROM_RED),
        _ => {}
    }
    if let Some(look) = snooker_look(id) {
        return look;
    }
    match id.parse::<u8>() {
        Ok(n @ 1..=15) => BallLook {
            color: SOLIDS[((n - 1) % 8) as usize],
            stripe: n > 8,
            number: Some(n),
        },
        _ => plain(OTHER_BALL),
    }
}

/// The snooker reds.
pub const SNOOKER_RED: Rgb = [196, 22, 28];
/// The snooker colours, yellow to black, in the order of their values.
pub const SNOOKER_COLOURS: [Rgb; 6] = [
    [246, 206, 40],  // yellow (the carom yellow: the same id)
    [18, 128, 52],   // green
    [120, 70, 32],   // brown
    [30, 80, 200],   // blue
    [240, 130, 170], // pink
    [18, 18, 18],    // black
];
/// The look of a snooker ball by its scene id (`r1`..`r15`, `yellow`, ..., `black`), if `id`
/// names one (the yellow's id is the carom yellow's, and looks the same).
fn snooker_look(id: &str) -> Option<BallLook> {
    let color = match id {
        "green" => SNOOKER_COLOURS[1],
        "brown" => SNOOKER_COLOURS[2],
        "blue" => SNOOKER_COLOURS[3],
        "pink" => SNOOKER_COLOURS[4],
        "black" => SNOOKER_COLOURS[5],
        _ => {
            let n: u8 = id.strip_prefix('r')?.parse().ok()?;
            if !table::is_red(n) {
                return None;
            }
            SNOOKER_RED
        }
    };
    Some(BallLook {
        color,
        stripe: false,
        number: None,
    })
}

/// The colour a ball of the snooker list is drawn in (a red, a colour, the cue ball white).
pub fn snooker_ball_colour(ball: u8) -> Rgb {
    match ball {
        b if table::is_red(b) => SNOOKER_RED,
        b if table::is_colour(b) => SNOOKER_COLOURS[usize::from(b - table::YELLOW)],
        _ => CUE_BALL,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::rules::{Game, Variant};

    fn distance(a: Rgb, b: Rgb) -> i32 {
        a.iter()
            .zip(b)
            .map(|(&x, y)| (x as i32 - y as i32).abs())
            .sum()
    }

    #[test]
    fn standard_colours_and_stripes() {
        assert_eq!(ball_look("1").color, ball_look("9").color);
        assert!(!ball_look("8").stripe && ball_look("9").stripe && ball_look("15").stripe);
        assert_eq!(ball_look("cue").color, CUE_BALL);
        assert_eq!(ball_look("16").color, OTHER_BALL);
        assert_eq!(ball_look("12").number, Some(12));
    }

    #[test]
    fn carom_balls_are_plain_white_yellow_and_red() {
        let game = Game::new(Variant::three_cushion(), Default::default(), 1);
        let ids = game.ball_ids();
        assert_eq!(ids, ["white", "yellow", "red"]);
        let looks: Vec<BallLook> = ids.iter().map(|id| ball_look(id)).collect();
        assert_eq!(looks[0].color, CUE_BALL);
        assert!(looks.iter().all(|l| l.number.is_none() && !l.stripe));
        // Red reads red and yellow reads yellow.
        let [r, g, b] = looks[2].color;
        assert!(r > 150 && g < 60 && b < 60);
        let [r, g, b] = looks[1].color;
        assert!(r > 200 && g > 180 && b < 80);
        for (i, a) in looks.iter().enumerate() {
            assert!(distance(a.color, CLOTH) > 60);
            for c in &looks[i + 1..] {
                assert!(distance(a.color, c.color) > 60);
            }
        }
    }

    #[test]
    fn every_ball_stands_out_from_the_cloth_and_the_others() {
        let ids = ["cue", "1", "2", "3", "4", "5", "6", "7", "8"];
        for (i, a) in ids.iter().enumerate() {
            let ca = ball_look(a).color;
            assert!(distance(ca, CLOTH) > 60, "ball {a} looks like the cloth");
            for b in &ids[i + 1..] {
                assert!(
                    distance(ca, ball_look(b).color) > 60,
                    "{a} and {b} look alike"
                );
            }
        }
    }

    #[test]
    fn every_snooker_ball_has_its_own_colour_and_none_is_the_cloth() {
        let ids: Vec<String> = (0..22).map(table::scene_id).collect();
        for id in &ids[1..] {
            let look = ball_look(id);
            assert_ne!(look.color, OTHER_BALL, "{id}");
            assert!(look.number.is_none() && !look.stripe, "{id}");
        }
        assert_eq!(snooker_look("r7").map(|l| l.color), Some(SNOOKER_RED));
        assert_eq!(snooker_look("r16"), None);
        assert_eq!(snooker_look("x"), None);
        let mut seen = vec![SNOOKER_RED, CLOTH];
        for c in table::COLOURS {
            let rgb = snooker_ball_colour(c);
            assert!(!seen.contains(&rgb), "{c}");
            seen.push(rgb);
        }
    }
}
