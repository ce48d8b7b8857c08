//! Drawing what a snooker game adds to the screen while it is played: the nominated ball
//! ringed, and the nomination buttons in the balls' own colours. The words are
//! `view::snooker`'s; the markings on the cloth are drawn with the table ([`draw::table`]).

use breakshot_client::view::snooker;
use breakshot_shared::physics::BallState;
use breakshot_shared::rules::{Choice, Game, Phase};
use macroquad::prelude::*;

use super::draw::{self, Pen};

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
