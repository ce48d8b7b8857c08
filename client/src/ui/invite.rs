//! The invite panel a host sees while the other seat is empty: the invite to send, a button
//! that copies it to the clipboard, and a note when the invite's address cannot be dialled.

use breakshot_client::net::{names_wildcard, router_hint, ADDRESS_NOTE};
use breakshot_client::view::Rect;
use breakshot_shared::protocol::Invite;
use macroquad::prelude::*;

use super::draw;

const TEXT: f32 = 20.0;
const NOTE: f32 = 17.0;

/// Where the panel and its button go: over the middle of `area` (the table), so that it
/// stays clear of the panel beside the table and of the bar at the top.
fn panel(area: Rect) -> (Rect, Rect) {
    let pw = (0.96 * area.w).min(1000.0);
    let ph = 200.0f32.min(0.9 * area.h);
    let p = Rect::new(
        area.x + 0.5 * (area.w - pw),
        area.y + 0.5 * (area.h - ph),
        pw,
        ph,
    );
    let bw = 220.0f32.min(pw - 24.0);
    let button = Rect::new(p.x + 0.5 * (pw - bw), p.y + 96.0, bw, 38.0);
    (p, button)
}

/// Whether a click at `mouse` hits the copy button of the panel over `area`.
pub fn copy_clicked(area: Rect, mouse: [f32; 2]) -> bool {
    panel(area).1.contains(mouse)
}

/// Puts the invite on the system clipboard.
pub fn copy(invite: &Invite) {
    macroquad::miniquad::window::clipboard_set(&invite.to_string());
}

/// The note, cut into lines that fit `width` pixels.
pub fn wrap(text: &str, width: f32, size: f32) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let last = lines.last_mut().map_or(String::new(), |l| l.clone());
        let candidate = if last.is_empty() {
            word.to_string()
        } else {
            format!("{last} {word}")
        };
        if draw::text_width(&candidate, size) > width && !last.is_empty() {
            lines.push(word.to_string());
        } else if let Some(l) = lines.last_mut() {
            *l = candidate;
        }
    }
    lines
}

/// The panel over `area` (the table), every line shrunk to fit it.
pub fn draw_panel(area: Rect, invite: &Invite, copied: bool) {
    let (p, button) = panel(area);
    let wildcard = names_wildcard(invite);
    let note = if wildcard {
        wrap(&format!("Note: {ADDRESS_NOTE}."), p.w - 32.0, NOTE)
    } else {
        wrap(
            &format!("{}.", router_hint(invite.first().port)),
            p.w - 32.0,
            NOTE,
        )
    };
    let height = p.h + NOTE * 1.3 * note.len() as f32;
    draw_rectangle(p.x, p.y, p.w, height, Color::new(0.0, 0.0, 0.0, 0.82));
    draw_rectangle_lines(p.x, p.y, p.w, height, 2.0, WHITE);
    let centred = |text: &str, y: f32, size: f32, c: Color| {
        let size = draw::fitted_size(text, p.w - 24.0, size * draw::text_scale(), size);
        let w = draw::text_width(text, size);
        draw::label(text, p.x + 0.5 * (p.w - w), y, size, c);
    };
    centred(
        "Waiting for the opponent. Send them this invite:",
        p.y + 32.0,
        TEXT,
        WHITE,
    );
    // A 64-digit fingerprint makes the invite long: shrink it to fit the panel.
    let text = invite.to_string();
    let size = (TEXT * (p.w - 24.0) / draw::text_width(&text, TEXT).max(1.0)).min(TEXT);
    centred(&text, p.y + 70.0, size, YELLOW);
    let fill = if copied {
        Color::from_rgba(40, 130, 90, 255)
    } else {
        Color::from_rgba(30, 60, 120, 255)
    };
    draw_rectangle(button.x, button.y, button.w, button.h, fill);
    draw_rectangle_lines(button.x, button.y, button.w, button.h, 2.0, WHITE);
    let label = if copied {
        "Copied"
    } else {
        "Copy to clipboard"
    };
    draw::label_in(label, button, TEXT, draw::Align::Centre, WHITE);
    centred(
        "They run:  breakshot join '<invite>'",
        p.y + 170.0,
        NOTE,
        LIGHTGRAY,
    );
    for (k, line) in note.iter().enumerate() {
        draw::label(
            line,
            p.x + 16.0,
            p.y + p.h + NOTE * 1.3 * k as f32,
            NOTE,
            Color::from_rgba(255, 200, 120, 255),
        );
    }
}
