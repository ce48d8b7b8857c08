//! The invite panel a host sees while the other seat is empty: the invite to send and, when
//! the web client is served, the link a friend opens in a browser, each with a button that
//! copies it to the clipboard, and a note when the invite's address cannot be dialled.

use breakshot_client::net::{names_wildcard, router_hint, ADDRESS_NOTE};
use breakshot_client::view::Rect;
use breakshot_shared::protocol::Invite;
use macroquad::prelude::*;

use super::draw;

const TEXT: f32 = 20.0;
const NOTE: f32 = 17.0;

/// What a copy button copies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Copied {
    Invite,
    Link,
}

/// Where the panel and its buttons go: over the middle of `area` (the table), so that it
/// stays clear of the panel beside the table and of the bar at the top. The link's row is
/// there only when there is a link.
fn panel(area: Rect, link: bool) -> (Rect, Rect, Option<Rect>) {
    let pw = (0.96 * area.w).min(1000.0);
    let ph = if link { 300.0f32 } else { 200.0 }.min(0.9 * area.h);
    let p = Rect::new(
        area.x + 0.5 * (area.w - pw),
        area.y + 0.5 * (area.h - ph),
        pw,
        ph,
    );
    let bw = 220.0f32.min(pw - 24.0);
    let button = |y: f32| Rect::new(p.x + 0.5 * (pw - bw), p.y + y, bw, 38.0);
    (p, button(96.0), link.then(|| button(244.0)))
}

/// Which copy button of the panel over `area` a click at `mouse` hits.
pub fn copy_clicked(area: Rect, link: bool, mouse: [f32; 2]) -> Option<Copied> {
    let (_, invite, link) = panel(area, link);
    if invite.contains(mouse) {
        Some(Copied::Invite)
    } else {
        link.filter(|b| b.contains(mouse)).map(|_| Copied::Link)
    }
}

/// Puts `text` on the system clipboard.
pub fn copy(text: &str) {
    macroquad::miniquad::window::clipboard_set(text);
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

/// The panel over `area` (the table), every line shrunk to fit it; `copied`: the button
/// pressed last.
pub fn draw_panel(area: Rect, invite: &Invite, link: Option<&str>, copied: Option<Copied>) {
    let (p, invite_button, link_button) = panel(area, link.is_some());
    let wildcard = names_wildcard(invite);
    let note = if wildcard {
        wrap(&format!("Note: {ADDRESS_NOTE}."), p.w - 32.0, NOTE)
    } else {
        wrap(
            &format!("{}.", router_hint(invite.first().port, link.is_some())),
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
    // A 64-digit fingerprint or key makes the line long: shrink it to fit the panel.
    let long_line = |text: &str, y: f32| {
        let size = (TEXT * (p.w - 24.0) / draw::text_width(text, TEXT).max(1.0)).min(TEXT);
        centred(text, y, size, YELLOW);
    };
    let button = |r: Rect, what: Copied, label: &str| {
        let done = copied == Some(what);
        let fill = if done {
            Color::from_rgba(40, 130, 90, 255)
        } else {
            Color::from_rgba(30, 60, 120, 255)
        };
        draw_rectangle(r.x, r.y, r.w, r.h, fill);
        draw_rectangle_lines(r.x, r.y, r.w, r.h, 2.0, WHITE);
        let label = if done { "Copied" } else { label };
        draw::label_in(label, r, TEXT, draw::Align::Centre, WHITE);
    };
    centred(
        "Waiting for the opponent. Send them this invite:",
        p.y + 32.0,
        TEXT,
        WHITE,
    );
    long_line(&invite.to_string(), p.y + 70.0);
    button(invite_button, Copied::Invite, "Copy invite");
    centred(
        "They run:  breakshot join '<invite>'",
        p.y + 170.0,
        NOTE,
        LIGHTGRAY,
    );
    if let (Some(link), Some(r)) = (link, link_button) {
        centred(
            "Or they open this link in a browser:",
            p.y + 204.0,
            NOTE,
            WHITE,
        );
        long_line(link, p.y + 228.0);
        button(r, Copied::Link, "Copy link");
    }
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
