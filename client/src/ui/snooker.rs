//! Drawing what a snooker game adds to the table and the screen: the markings on the cloth
//! (baulk line, the D, the six spots, in both views through the one [`Surface`]), the
//! nominated ball ringed, and the nomination buttons in the balls' own colours. The words
//! and the geometry are `view::snooker`'s.

use breakshot_client::view::snooker::{self, Markings};
use breakshot_shared::physics::BallState;
use breakshot_shared::rules::{Choice, Game, Phase};
use macroquad::prelude::*;

use super::draw::{self, Pen};

/// Chalk lines are drawn this wide (pixels, top-down view).
const LINE_WIDTH: f32 = 1.5;

/// The baulk line, the D and the spots, on the cloth under the balls.
pub fn markings(pen: &Pen) {
    let Markings {
        baulk,
        d_arc,
        spots,
    } = snooker::markings();
    let c = draw::with_alpha(snooker::MARKING, 0.55);
    let surface = pen.surface();
    surface.segment(pen, baulk.0, baulk.1, LINE_WIDTH, c);
    for w in d_arc.windows(2) {
        surface.segment(pen, w[0], w[1], LINE_WIDTH, c);
    }
    for s in spots {
        let ring = snooker::circle(s, snooker::SPOT_RADIUS, 12);
        for w in ring.windows(2) {
            surface.segment(pen, w[0], w[1], 2.0, c);
        }
    }
}

/// The nominated ball (or free ball) ringed while the striker aims.
pub fn nominated_ring(pen: &Pen, game: &Game, balls: &[BallState], radius: f64) {
    let nominated = game.snooker().and_then(|m| m.nominated);
    if let (Some(b), Phase::Shooting { .. }) = (nominated, game.phase()) {
        if let Some(s) = balls.get(usize::from(b)).filter(|s| !s.motion.is_gone()) {
            pen.surface().ring(pen, s.pos, radius, YELLOW);
        }
    }
}

/// A choice's button in a snooker game: its words, its fill and the colour of its words (a
/// nomination in the ball's own colour).
pub fn button(choice: Choice) -> (String, Color, Color) {
    let fill = snooker::button_colour(choice);
    let text = snooker::button_text(choice);
    match fill {
        Some(rgb) => {
            let light = u32::from(rgb[0]) + u32::from(rgb[1]) + u32::from(rgb[2]) > 380;
            (text, draw::color(rgb), if light { BLACK } else { WHITE })
        }
        None => (text, Color::from_rgba(30, 60, 120, 220), WHITE),
    }
}
