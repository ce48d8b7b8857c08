//! The panel beside the table: the cue-ball face with the tip's offset, the power bar and
//! the cue's elevation seen from the side.

use breakshot_client::play::Aim;
use breakshot_client::view::{palette, Layout};
use macroquad::prelude::*;

use super::draw::*;

/// The cue-ball face (tip offset) and the power bar, on the background (the 3-D view may
/// reach under the panel); `keep_spin`, when the player sets up shots here, says whether
/// the tip stays put after a shot (K).
pub fn panel(layout: &Layout, aim: &Aim, keep_spin: Option<bool>) {
    let p = layout.panel;
    draw_rectangle(
        p.x - 4.0,
        p.y,
        layout.screen[0] - p.x + 4.0,
        p.h,
        color(palette::BACKGROUND),
    );
    let [cx, cy] = layout.tip_center;
    let r = layout.tip_radius;
    let title = match keep_spin {
        Some(true) => "Tip (kept, K)",
        Some(false) => "Tip (resets, K)",
        None => "Tip",
    };
    label_in(title, layout.tip_title, 20.0, Align::Centre, LIGHTGRAY);
    draw_poly(cx, cy, 64, r, 0.0, color(palette::CUE_BALL));
    // The miscue limit: the tip stays inside this ring.
    draw_poly_lines(
        cx,
        cy,
        64,
        0.5 * r,
        0.0,
        1.0,
        Color::new(0.8, 0.2, 0.2, 0.6),
    );
    draw_line(cx - r, cy, cx + r, cy, 1.0, Color::new(0.0, 0.0, 0.0, 0.2));
    draw_line(cx, cy - r, cx, cy + r, 1.0, Color::new(0.0, 0.0, 0.0, 0.2));
    let tx = cx + aim.tip.x as f32 * r;
    let ty = cy - aim.tip.y as f32 * r;
    draw_poly(
        tx,
        ty,
        24,
        (0.12 * r).max(3.0),
        0.0,
        Color::from_rgba(30, 90, 200, 255),
    );

    elevation_view(layout, aim.elevation_deg);

    let bar = layout.power_bar;
    label_in(
        &format!("Power {:.1} m/s", aim.speed()),
        layout.power_title,
        18.0,
        Align::Centre,
        LIGHTGRAY,
    );
    fill_rect(bar, Color::new(0.0, 0.0, 0.0, 0.5));
    let filled = bar.h * aim.power as f32;
    let hot = aim.power as f32;
    draw_rectangle(
        bar.x,
        bar.y + bar.h - filled,
        bar.w,
        filled,
        Color::new(0.3 + 0.7 * hot, 0.8 - 0.6 * hot, 0.2, 1.0),
    );
    draw_rectangle_lines(bar.x, bar.y, bar.w, bar.h, 1.0, LIGHTGRAY);
}

/// The side view: the cue ball on the cloth and the cue over it at its elevation.
fn elevation_view(layout: &Layout, elevation_deg: f64) {
    let v = layout.elevation_view;
    label_in(
        &format!("Elevation {elevation_deg:.0} deg (W/S)"),
        layout.elevation_title,
        18.0,
        Align::Centre,
        LIGHTGRAY,
    );
    fill_rect(v, Color::new(0.0, 0.0, 0.0, 0.35));
    let [bx, by] = layout.elevation_ball;
    let r = layout.elevation_ball_radius;
    let cloth = by + r;
    draw_line(v.x, cloth, v.x + v.w, cloth, 2.0, color(palette::CLOTH));
    draw_poly(bx, by, 40, r, 0.0, color(palette::CUE_BALL));
    let (tip, butt) = layout.elevation_cue(elevation_deg);
    let w = (0.22 * r).max(3.0);
    draw_line(
        tip[0],
        tip[1],
        butt[0],
        butt[1],
        w,
        color(palette::CUE_WOOD),
    );
    // The white ferrule at the tip end.
    let ferrule = [
        tip[0] + 0.15 * (butt[0] - tip[0]),
        tip[1] + 0.15 * (butt[1] - tip[1]),
    ];
    draw_line(
        tip[0],
        tip[1],
        ferrule[0],
        ferrule[1],
        w,
        color(palette::CUE_FERRULE),
    );
    draw_rectangle_lines(v.x, v.y, v.w, v.h, 1.0, LIGHTGRAY);
}
