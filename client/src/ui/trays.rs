//! The trays under the table: the balls pocketed, in the order they fell, one tray per
//! player in a game with groups.

use breakshot_client::view::tray::Trays;
use breakshot_client::view::Layout;
use macroquad::prelude::*;

use super::draw::{ball, fill_rect, label_in, Align};

/// Pocketed balls in the tray, in the order they fell.
pub fn tray(layout: &Layout, ids: &[String], pocketed: &[usize], radius: f64) {
    fill_rect(layout.tray, Color::new(0.0, 0.0, 0.0, 0.35));
    let r = layout.px(radius).max(3.0);
    for (k, &b) in pocketed.iter().enumerate() {
        if let Some(id) = ids.get(b) {
            ball(id, layout.tray_slot(k, radius), r);
        }
    }
}

/// The pocketed balls of an 8-ball game in a tray per player, each named, the 8 and balls
/// down on an open table between them; a game without groups has the one tray of [`tray`].
pub fn player_trays(
    layout: &Layout,
    ids: &[String],
    trays: Option<Trays>,
    pocketed: &[usize],
    names: [String; 2],
    radius: f64,
) {
    let Some(t) = trays else {
        return tray(layout, ids, pocketed, radius);
    };
    let area = layout.tray;
    fill_rect(area, Color::new(0.0, 0.0, 0.0, 0.35));
    let r = layout.px(radius).max(3.0);
    let pitch = 2.6 * r;
    let y = area.y + 0.5 * area.h;
    let row = |balls: &[usize], x0: f32| {
        for (k, &b) in balls.iter().enumerate() {
            if let Some(id) = ids.get(b) {
                ball(id, [x0 + 1.5 * r + k as f32 * pitch, y], r);
            }
        }
    };
    let width = |n: usize| n as f32 * pitch + 0.5 * r;
    let [a, b] = names;
    let [a_box, b_box] = layout.tray_names;
    // [A's name][A's balls ... the 8 and the undecided ... B's balls][B's name]: each name in
    // its own box (shrunk to fit it), so no name runs under a ball.
    label_in(&a, a_box, 18.0, Align::Centre, LIGHTGRAY);
    row(&t.seats[0], a_box.x + a_box.w);
    label_in(&b, b_box, 18.0, Align::Centre, LIGHTGRAY);
    row(&t.seats[1], b_box.x - width(t.seats[1].len()));
    row(&t.between, area.x + 0.5 * (area.w - width(t.between.len())));
}
