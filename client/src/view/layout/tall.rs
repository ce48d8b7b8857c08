//! The layout of a window taller than wide (a phone held upright): the table turned a
//! quarter so that its length runs down the screen, with the tray, the verdict and the panel
//! (tip face, side view and power bar side by side) below it, the chat beside the notice
//! and the verdict.
//!
//! Turned, scene `x` (across the table) runs to the right and scene `y` (along it) runs up,
//! so the end the cue ball breaks from is at the bottom, nearest the player's thumb. Like the
//! wide layout's, this is a rotation, not a mirror image ([`Layout::to_screen`]).

use glam::DVec2;

use super::{Frame, Layout, Rect, RAIL_WIDTH};

/// What the tall layout takes from the wide one: the boxes along the top and the bottom.
pub(super) struct Edges {
    pub margin: f32,
    pub hud: Rect,
    pub players: [Rect; 2],
    pub game_info: Rect,
    pub footer: Rect,
    pub footer_rows: usize,
    /// The height of one line of text (the notice's).
    pub row_h: f32,
}

/// Fits the turned table into a `w` × `h` window (`h > w`) between `edges`.
pub(super) fn layout(w: f32, h: f32, frame: Frame, edges: Edges) -> Layout {
    let Edges {
        margin,
        hud,
        players,
        game_info,
        footer,
        footer_rows,
        row_h,
    } = edges;
    let status_h = (0.04 * h).clamp(18.0, 30.0);
    let title_h = (0.035 * h).clamp(16.0, 26.0);
    // Low boxes under the table: the height goes to the table, whose width the window caps.
    // The notice line under the tray takes its room from the verdict, down to two short
    // lines, and the rest from the panel, so the table keeps its size.
    let notice_room = row_h + 0.5 * margin;
    let wide_verdict = (0.05 * h).clamp(40.0, 64.0);
    let verdict_h = (wide_verdict - notice_room).max(30.0);
    let panel_h = (0.13 * h).clamp(100.0, 150.0) - (notice_room - (wide_verdict - verdict_h));
    let tray_h = (0.045 * h).clamp(30.0, 50.0);
    let rail = if frame.rails { RAIL_WIDTH } else { 0.0 };

    // Every box below runs the window's width, margin to margin.
    let row = |y: f32, h: f32| Rect::new(margin, y, (w - 2.0 * margin).max(10.0), h);
    let status = row(hud.h + 0.5 * margin, status_h);
    let panel = row(footer.y - 0.5 * margin - panel_h, panel_h);
    let verdict = row(panel.y - 0.5 * margin - verdict_h, verdict_h);
    let notice = row(verdict.y - 0.5 * margin - row_h, row_h);
    // The notice over the verdict on the left, the chat beside them on the right.
    let text_w = super::NOTICE_SHARE * notice.w;
    let chat_x = notice.x + text_w + margin;
    let chat = Rect::new(
        chat_x,
        notice.y,
        notice.x + notice.w - chat_x,
        verdict.y + verdict.h - notice.y,
    );
    let verdict = Rect::new(verdict.x, verdict.y, text_w, verdict.h);
    let notice = Rect::new(notice.x, notice.y, text_w, notice.h);
    let tray_y = notice.y - 0.5 * margin - tray_h;
    let top = status.y + status_h + 0.5 * margin;
    let area = row(top, (tray_y - 0.5 * margin - top).max(10.0));
    // Turned: the table's width across the screen, its length down it.
    let (scale, outer, cloth) = super::fit_table(area, frame.size, rail);
    // The tray runs the window's width (the turned table is narrower than the rack).
    let tray = row(tray_y, tray_h);
    let tray_names = super::tray_names(tray, margin, 0.2);

    // The panel, left to right: the tip face, the side view and the power bar, each under
    // its title.
    // Whole pixels, so the last column ends inside the panel.
    let column_w = ((panel.w - 2.0 * margin) / 3.0).floor();
    let column = |k: f32| panel.x + k * (column_w + margin);
    let widget_top = panel.y + title_h + 0.5 * margin;
    let widget_h = (panel.y + panel.h - widget_top).max(20.0);
    let tip_title = Rect::new(column(0.0), panel.y, column_w, title_h);
    let tip_radius = (0.4 * column_w).min(0.5 * widget_h - 2.0).max(4.0);
    let tip_center = [column(0.0) + 0.5 * column_w, widget_top + 0.5 * widget_h];
    let elevation_title = Rect::new(column(1.0), panel.y, column_w, title_h);
    let elevation_view = Rect::new(column(1.0), widget_top, column_w, widget_h);
    let elevation_ball_radius = (0.15 * column_w).min(0.3 * widget_h);
    let elevation_ball = [
        elevation_view.x + elevation_view.w - 1.6 * elevation_ball_radius,
        elevation_view.y + elevation_view.h - elevation_ball_radius - 3.0,
    ];
    let power_title = Rect::new(column(2.0), panel.y, column_w, title_h);
    let bar_w = (0.25 * column_w).max(18.0);
    let power_bar = Rect::new(
        column(2.0) + 0.5 * (column_w - bar_w),
        widget_top,
        bar_w,
        widget_h,
    );
    Layout {
        screen: [w, h],
        frame,
        scale,
        origin: DVec2::new(cloth.x as f64, cloth.y as f64),
        turned: true,
        hud,
        cloth,
        outer,
        tray,
        tip_center,
        tip_radius,
        elevation_view,
        elevation_ball,
        elevation_ball_radius,
        power_bar,
        players,
        game_info,
        status,
        panel,
        tip_title,
        elevation_title,
        power_title,
        verdict,
        footer,
        footer_rows,
        tray_names,
        notice,
        chat,
        banner: super::banner(notice, verdict),
    }
}
