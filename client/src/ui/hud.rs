//! Drawing the heads-up display of a rules game (replays, games at one computer and online):
//! both players, whose turn, groups, what the game waits for, the last verdict and the
//! connection, in the words `view::hud` chooses.

use breakshot_client::view::hud::{self, Connection};
use breakshot_client::view::Layout;
use breakshot_shared::rules::{Game, Seat, Verdict};
use macroquad::prelude::*;

use super::draw;

pub struct HudInfo<'a> {
    pub game: &'a Game,
    pub me: Option<Seat>,
    pub verdict: Option<&'a Verdict>,
    pub shot_clock: Option<f64>,
    pub connection: &'a Connection,
    /// The players' names, by seat, when known.
    pub names: &'a [Option<String>; 2],
}

pub fn game_hud(layout: &Layout, info: &HudInfo) {
    let bar = layout.hud;
    draw_rectangle(bar.x, bar.y, bar.w, bar.h, Color::new(0.0, 0.0, 0.0, 0.5));
    let y = 0.5 * bar.h + 6.0;
    // Right to left: the connection, the shot clock (red as it runs out), the game.
    let mut at = bar.w - 10.0;
    let mut right = |text: &str, c: Color| {
        at -= draw::text_width(text, 18.0);
        draw::label(text, at, y, 18.0, c);
    };
    right(&hud::connection(info.connection), LIGHTGRAY);
    if let Some(clock) = hud::shot_clock(info.shot_clock) {
        right("  |  ", LIGHTGRAY);
        let warn = info.shot_clock.is_some_and(hud::clock_running_out);
        right(&clock, if warn { RED } else { LIGHTGRAY });
    }
    right("  |  ", LIGHTGRAY);
    right(hud::variant_name(info.game.variant()), LIGHTGRAY);
    let right_w = bar.w - 10.0 - at;

    let lines: Vec<(String, Color)> = hud::players(info.game, info.me, info.names)
        .into_iter()
        .map(|p| {
            let (marker, c) = if p.to_move {
                ("> ", YELLOW)
            } else {
                ("  ", LIGHTGRAY)
            };
            (format!("{marker}{}", p.text), c)
        })
        .collect();
    // The players' lines shrink, if they must, to stay clear of the right-hand words.
    let room = bar.w - right_w - 40.0;
    let wide: f32 = lines
        .iter()
        .map(|(t, _)| draw::text_width(t, 20.0) + 30.0)
        .sum();
    let size = (20.0 * (room / wide).min(1.0)).max(11.0);
    let mut x = 10.0;
    for (text, c) in &lines {
        draw::label(text, x, y, size, *c);
        x += draw::text_width(text, size) + 30.0 * size / 20.0;
    }

    // What the game waits for, over the table; the last verdict's reasons, one a line, in
    // the tray's free right-hand part.
    let status = hud::status(info.game, info.names);
    // Unscaled: it sits in the margin between the bar and the table.
    draw_text(&status, layout.outer.x, layout.outer.y - 4.0, 18.0, WHITE);
    if let Some(v) = info.verdict {
        let c = if v.foul {
            Color::from_rgba(255, 120, 100, 255)
        } else {
            WHITE
        };
        let tray = layout.tray;
        let size = (tray.h / 3.4).clamp(12.0, 20.0);
        for (k, line) in hud::verdict_lines(v, info.names).iter().take(3).enumerate() {
            let w = measure_text(line, None, size as u16, 1.0).width;
            let y = tray.y + size * (k as f32 + 1.0);
            draw_text(line, tray.x + tray.w - w - 8.0, y, size, c);
        }
    }
}
