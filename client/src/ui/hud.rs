//! Drawing the heads-up display of a rules game (replays, games at one computer and online):
//! both players, whose turn, groups, what the game waits for, the last verdict and the
//! connection, in the words `view::hud` chooses.

use breakshot_client::view::hud::{self, Connection};
use breakshot_client::view::{Layout, Rect};
use breakshot_shared::rules::{Game, Seat, Verdict};
use macroquad::prelude::*;

use super::draw::{self, Align};

pub struct HudInfo<'a> {
    pub game: &'a Game,
    pub me: Option<Seat>,
    pub verdict: Option<&'a Verdict>,
    pub shot_clock: Option<f64>,
    pub connection: &'a Connection,
    /// The players' names, by seat, when known.
    pub names: &'a [Option<String>; 2],
    /// The players' ratings, by seat, when known.
    pub ratings: &'a [Option<i32>; 2],
}

pub fn game_hud(layout: &Layout, info: &HudInfo) {
    let bar = layout.hud;
    draw_rectangle(bar.x, bar.y, bar.w, bar.h, Color::new(0.0, 0.0, 0.0, 0.5));
    // In its box, right-aligned: the game and the shot clock (red as it runs out) over the
    // connection when the bar has room for two rows, all on one row otherwise.
    let rows = layout.game_info_rows();
    let text = hud::game_info(
        info.game.variant(),
        info.shot_clock,
        info.connection,
        rows.len(),
    );
    for (pieces, r) in text.into_iter().zip(rows) {
        let coloured: Vec<(String, Color)> = pieces
            .into_iter()
            .map(|(t, warn)| (t, if warn { RED } else { LIGHTGRAY }))
            .collect();
        right_aligned(&coloured, r);
    }

    // The players' lines, each in its own box.
    for (p, r) in hud::players(info.game, info.me, info.names, info.ratings)
        .into_iter()
        .zip(layout.players)
    {
        let (marker, c) = if p.to_move {
            ("> ", YELLOW)
        } else {
            ("  ", LIGHTGRAY)
        };
        draw::label_in(&format!("{marker}{}", p.text), r, 20.0, Align::Left, c);
    }

    // What the game waits for, in the line over the table; the last verdict's reasons, one a
    // line, under the trays.
    let status = hud::status(info.game, info.names);
    draw::label_in(&status, layout.status, 18.0, Align::Left, WHITE);
    if let Some(v) = info.verdict {
        let c = if v.foul {
            Color::from_rgba(255, 120, 100, 255)
        } else {
            WHITE
        };
        let lines = hud::verdict_lines(v, info.names);
        let shown = &lines[..lines.len().min(3)];
        let area = layout.verdict;
        let row = area.h / shown.len().max(1) as f32;
        for (k, line) in shown.iter().enumerate() {
            let r = Rect::new(area.x, area.y + k as f32 * row, area.w, row);
            draw::label_in(line, r, 20.0, Align::Left, c);
        }
    }
}

/// Coloured pieces of one line, at the one size that fits them all in `r`, ending at its
/// right edge.
fn right_aligned(pieces: &[(String, Color)], r: Rect) {
    let all: String = pieces.iter().map(|(t, _)| t.as_str()).collect();
    let size = draw::fitted_size(&all, r.w, r.h, 18.0);
    let mut right = r.x + r.w;
    for (text, c) in pieces.iter().rev() {
        let w = draw::text_width(text, size);
        right -= w;
        draw::label_in(
            text,
            Rect::new(right, r.y, w + 1.0, r.h),
            size,
            Align::Left,
            *c,
        );
    }
}

/// The hint bar along the bottom: `text` in as many rows as the layout gives it (two in a
/// narrow window), broken between its pieces, every row at one size.
pub fn hint_bar(layout: &Layout, text: &str, c: Color) {
    let rows = hud::hint_rows(text, layout.footer_rows);
    let f = layout.footer;
    let row_h = f.h / rows.len().max(1) as f32;
    let size = rows
        .iter()
        .map(|r| draw::fitted_size(r, f.w, row_h, 18.0))
        .fold(18.0f32, f32::min);
    for (k, line) in rows.iter().enumerate() {
        let r = Rect::new(f.x, f.y + k as f32 * row_h, f.w, row_h);
        draw::label_in(line, r, size, Align::Left, c);
    }
}
