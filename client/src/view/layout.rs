//! Where everything goes on the screen. The renderer and the window test both use this, so a
//! ball the test looks for is where the renderer drew it.
//!
//! The table lies with its long side across the screen: scene `y` (along the table) runs to
//! the right and scene `x` (across) runs down. With the screen's `y` pointing down this is a
//! rotation, not a mirror image, so a shot looks on the screen as it is on the table. A
//! window taller than wide turns the table a quarter more, its length down the screen
//! (`tall`).

use breakshot_shared::physics::{BallState, MotionState, Table, TableKind};
use glam::DVec2;

mod tall;

/// Width of the rails drawn around the cloth (cushion and wood), in metres. Drawing only.
pub const RAIL_WIDTH: f64 = 0.12;
/// Width of the cushion rubber drawn behind the nose line (m).
pub const CUSHION_WIDTH: f64 = 0.045;
/// Margin around an open table's balls, in metres.
const OPEN_MARGIN: f64 = 0.3;

/// An axis-aligned rectangle in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left edge (pixels).
    pub x: f32,
    /// Top edge (pixels).
    pub y: f32,
    /// Width (pixels).
    pub w: f32,
    /// Height (pixels).
    pub h: f32,
}

impl Rect {
    /// A rectangle from its top-left corner and size.
    pub fn new(x: f32, y: f32, w: f32, h: f32) -> Rect {
        Rect { x, y, w, h }
    }

    /// Whether `p` is inside.
    pub fn contains(&self, p: [f32; 2]) -> bool {
        p[0] >= self.x && p[0] <= self.x + self.w && p[1] >= self.y && p[1] <= self.y + self.h
    }

    /// The part of the segment from `a` to `b` inside the rectangle, if any (Liang and
    /// Barsky's clipping).
    pub fn clip_segment(&self, a: [f32; 2], b: [f32; 2]) -> Option<([f32; 2], [f32; 2])> {
        let d = [b[0] - a[0], b[1] - a[1]];
        let (mut t0, mut t1) = (0.0f32, 1.0f32);
        let edges = [
            (-d[0], a[0] - self.x),
            (d[0], self.x + self.w - a[0]),
            (-d[1], a[1] - self.y),
            (d[1], self.y + self.h - a[1]),
        ];
        for (p, q) in edges {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
                continue;
            }
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
        (t0 <= t1).then(|| {
            let at = |t: f32| [a[0] + t * d[0], a[1] + t * d[1]];
            (at(t0), at(t1))
        })
    }

    /// Whether the two rectangles share any area (touching edges do not count).
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x < other.x + other.w
            && other.x < self.x + self.w
            && self.y < other.y + other.h
            && other.y < self.y + self.h
    }

    /// Whether `inner` lies wholly inside.
    pub fn holds(&self, inner: &Rect) -> bool {
        inner.x >= self.x
            && inner.y >= self.y
            && inner.x + inner.w <= self.x + self.w
            && inner.y + inner.h <= self.y + self.h
    }

    /// The centre.
    pub fn center(&self) -> [f32; 2] {
        [self.x + 0.5 * self.w, self.y + 0.5 * self.h]
    }
}

/// The part of the scene plane shown as the cloth: the playing surface of a real table, or a
/// box around the balls on the open (unbounded) table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Scene coordinates of the cloth's corner.
    pub min: DVec2,
    /// Width (across, scene x) and length (along, scene y) in metres.
    pub size: DVec2,
    /// Whether the table has rails and pockets.
    pub rails: bool,
}

impl Frame {
    /// The frame for a table; the open table gets a box around `balls`.
    pub fn new(kind: TableKind, balls: &[BallState]) -> Frame {
        match kind.size() {
            Some((w, l)) => Frame {
                min: DVec2::ZERO,
                size: DVec2::new(w, l),
                rails: true,
            },
            None => Frame::around(balls),
        }
    }

    /// A box around the balls on the table, at least a nine-foot table in size.
    fn around(balls: &[BallState]) -> Frame {
        let on_table = balls.iter().filter(|b| b.motion != MotionState::Pocketed);
        let (lo, hi) = on_table.fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), b| (lo.min(b.pos), hi.max(b.pos)),
        );
        let (lo, hi) = if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (DVec2::ZERO, DVec2::ZERO)
        };
        let centre = 0.5 * (lo + hi);
        let size = (hi - lo + DVec2::splat(2.0 * OPEN_MARGIN)).max(DVec2::new(1.27, 2.54));
        Frame {
            min: centre - 0.5 * size,
            size,
            rails: false,
        }
    }
}

/// The screen layout for one window size and one table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// The window size (pixels).
    pub screen: [f32; 2],
    /// The part of the table shown.
    pub frame: Frame,
    /// Pixels per metre.
    pub scale: f64,
    /// Pixel position of the cloth's top-left corner: the frame's corner `frame.min`, or in
    /// a turned layout the corner at the frame's far end (`frame.min.y + frame.size.y`).
    origin: DVec2,
    /// The table turned for a tall window: scene `x` to the right, scene `y` up the screen.
    turned: bool,
    /// The bar at the top with the players, the turn and the last verdict.
    pub hud: Rect,
    /// The cloth (the playing surface).
    pub cloth: Rect,
    /// The cloth with the rails around it.
    pub outer: Rect,
    /// The strip below the table where pocketed balls are shown.
    pub tray: Rect,
    /// The cue-ball face where the tip offset is set: centre and radius in pixels.
    pub tip_center: [f32; 2],
    /// The radius of the cue-ball face (pixels).
    pub tip_radius: f32,
    /// The side view of the cue over the cue ball, where the cue elevation is shown and set.
    pub elevation_view: Rect,
    /// The cue ball's centre in the side view (pixels).
    pub elevation_ball: [f32; 2],
    /// The cue ball's radius in the side view (pixels).
    pub elevation_ball_radius: f32,
    /// The power bar (power grows upwards).
    pub power_bar: Rect,
    /// The players' lines in the bar at the top: one each, side by side in a wide window and
    /// one over the other in a narrow one.
    pub players: [Rect; 2],
    /// The right-hand part of the bar at the top: the game, the shot clock, the connection.
    pub game_info: Rect,
    /// The line saying what the game waits for, between the bar and the table.
    pub status: Rect,
    /// The column beside the table with the tip face, the side view and the power bar.
    pub panel: Rect,
    /// The tip face's title.
    pub tip_title: Rect,
    /// The side view's title (the elevation).
    pub elevation_title: Rect,
    /// The power bar's title (the speed).
    pub power_title: Rect,
    /// The last verdict's lines, under the trays.
    pub verdict: Rect,
    /// The hint bar along the bottom of the window (keys, or the latest message).
    pub footer: Rect,
    /// How many rows of text the hint bar holds: two in a narrow window, so the keys stay
    /// readable.
    pub footer_rows: usize,
    /// The players' names on the trays: at the tray's left end for the first player and at
    /// its right end for the second, the balls of each beside them.
    pub tray_names: [Rect; 2],
    /// One line between the trays and the verdict for what the game asks or says now (the
    /// pocket to call, the computer thinking, a replay's warnings): off the cloth, where it
    /// covers no ball.
    pub notice: Rect,
    /// The chat: the last lines said and the line being typed, beside the notice and the
    /// verdict, off the table.
    pub chat: Rect,
    /// The end of a finished game (who won, why, what next), in the notice's and the
    /// verdict's place: once the game is over, they have nothing else to say, and the balls
    /// as they lie stay in view.
    pub banner: Rect,
}

/// The heights of the banner's lines, one to another: the headline, the reason, what next.
const BANNER_LINES: [f32; 3] = [40.0, 22.0, 20.0];

/// The share of the band under the trays the notice and the verdict keep; the chat has the
/// rest.
const NOTICE_SHARE: f32 = 0.6;
/// The least height of one of the chat's rows (pixels).
const CHAT_ROW: f32 = 20.0;

/// The table, its cloth `cloth_m` metres across and down the screen with `rail` metres of
/// rail round it, fitted and centred in `area`: the scale (px/m), the outer box, the cloth.
fn fit_table(area: Rect, cloth_m: DVec2, rail: f64) -> (f64, Rect, Rect) {
    let outer_m = cloth_m + DVec2::splat(2.0 * rail);
    let scale = (area.w as f64 / outer_m.x).min(area.h as f64 / outer_m.y);
    let outer_px = outer_m * scale;
    let outer = Rect::new(
        area.x + 0.5 * (area.w - outer_px.x as f32),
        area.y + 0.5 * (area.h - outer_px.y as f32),
        outer_px.x as f32,
        outer_px.y as f32,
    );
    let rail_px = (rail * scale) as f32;
    let cloth = Rect::new(
        outer.x + rail_px,
        outer.y + rail_px,
        (cloth_m.x * scale) as f32,
        (cloth_m.y * scale) as f32,
    );
    (scale, outer, cloth)
}

/// The banner of a finished game: the notice and the verdict under it, as one box.
fn banner(notice: Rect, verdict: Rect) -> Rect {
    Rect::new(
        notice.x,
        notice.y,
        notice.w.max(verdict.w),
        verdict.y + verdict.h - notice.y,
    )
}

/// The two players' names at the ends of `tray`, each `share` of its width (180 px at most),
/// the balls between them.
fn tray_names(tray: Rect, margin: f32, share: f32) -> [Rect; 2] {
    let name_w = (share * tray.w).min(180.0);
    [
        Rect::new(tray.x + 0.5 * margin, tray.y, name_w, tray.h),
        Rect::new(
            tray.x + tray.w - name_w - 0.5 * margin,
            tray.y,
            name_w,
            tray.h,
        ),
    ]
}

impl Layout {
    /// Fits the table into a window of `width` × `height` pixels, with every box of text
    /// beside it: the bar at the top, the status line, the panel, the trays, the verdict, the
    /// chat and the hint bar, none over another.
    pub fn new(width: f32, height: f32, frame: Frame) -> Layout {
        let (w, h) = (width.max(64.0), height.max(64.0));
        let margin = (0.015 * w.min(h)).max(6.0);
        // A narrow window puts the players' lines one over the other, so they stay readable.
        let stacked = w < 1000.0;
        let hud_h = if stacked {
            (0.09 * h).clamp(36.0, 56.0)
        } else {
            (0.05 * h).clamp(28.0, 48.0)
        };
        let status_h = (0.04 * h).clamp(18.0, 30.0);
        let panel_w = (0.14 * w).clamp(110.0, 260.0);
        let row_h = (0.035 * h).clamp(18.0, 28.0);
        // The keys are one long line: a narrow window gives them two rows, unless it is taller
        // than wide, where the height goes to the turned table (and a phone has no keys).
        let footer_rows = if stacked && h <= w { 2 } else { 1 };
        let footer_h = footer_rows as f32 * row_h;
        // The notice line takes its room from the trays and the verdict, which had more than
        // they need, so the table keeps its size.
        let notice_h = row_h;
        let shared = notice_h + 0.5 * margin;
        let tray_h = ((0.09 * h).clamp(34.0, 90.0) - 0.6 * shared).max(30.0);
        let verdict_h = ((0.08 * h).clamp(48.0, 90.0) - 0.4 * shared).max(36.0);
        let rail = if frame.rails { RAIL_WIDTH } else { 0.0 };

        let hud = Rect::new(0.0, 0.0, w, hud_h);
        let info_w = 0.38 * w;
        let players_w = w - info_w - 2.0 * margin;
        let players = if stacked {
            let row = 0.5 * hud_h;
            [
                Rect::new(margin, 0.0, players_w, row),
                Rect::new(margin, row, players_w, row),
            ]
        } else {
            let half = 0.5 * (players_w - margin);
            [
                Rect::new(margin, 0.0, half, hud_h),
                Rect::new(2.0 * margin + half, 0.0, half, hud_h),
            ]
        };
        let game_info = Rect::new(w - info_w, 0.0, info_w - margin, hud_h);
        let footer = Rect::new(margin, h - footer_h, w - 2.0 * margin, footer_h);
        if h > w {
            let edges = tall::Edges {
                margin,
                hud,
                players,
                game_info,
                footer,
                footer_rows,
                row_h,
            };
            return tall::layout(w, h, frame, edges);
        }

        let panel_x = w - panel_w - margin;
        let status = Rect::new(
            margin,
            hud_h + 0.5 * margin,
            (panel_x - 2.0 * margin).max(10.0),
            status_h,
        );
        // The area left for the table and its rails, between the status line and the trays.
        let top = status.y + status_h + 0.5 * margin;
        let below = tray_h + notice_h + verdict_h + footer_h + 3.0 * margin;
        let area = Rect::new(
            margin,
            top,
            (panel_x - 2.0 * margin).max(10.0),
            (h - top - below).max(10.0),
        );
        // The table's length along the screen.
        let (scale, outer, cloth) = fit_table(area, DVec2::new(frame.size.y, frame.size.x), rail);
        let origin = DVec2::new(cloth.x as f64, cloth.y as f64);
        let tray = Rect::new(outer.x, outer.y + outer.h + margin, outer.w, tray_h);
        let tray_names = tray_names(tray, margin, 0.28);
        // Under the trays, the notice over the verdict on the left and the chat on the
        // right, as far as the panel's right edge: the panel ends at the trays.
        let text_w = NOTICE_SHARE * area.w;
        let notice = Rect::new(area.x, tray.y + tray_h + 0.5 * margin, text_w, notice_h);
        let verdict_y = notice.y + notice_h + 0.5 * margin;
        let band_bottom = footer.y - 0.5 * margin;
        let verdict = Rect::new(
            area.x,
            verdict_y,
            text_w,
            (band_bottom - verdict_y).max(10.0),
        );
        let chat_x = area.x + text_w + margin;
        let chat = Rect::new(
            chat_x,
            notice.y,
            panel_x + panel_w - chat_x,
            (band_bottom - notice.y).max(10.0),
        );

        // The panel, top to bottom: a title over each of the tip face, the side view and
        // the power bar.
        let panel = Rect::new(
            panel_x,
            hud_h + 0.5 * margin,
            panel_w,
            notice.y - margin - (hud_h + 0.5 * margin),
        );
        let title_h = (0.035 * h).clamp(16.0, 26.0);
        let tip_title = Rect::new(panel_x, panel.y, panel_w, title_h);
        let tip_radius = (0.38 * panel_w).min(0.12 * panel.h);
        let tip_center = [
            panel_x + 0.5 * panel_w,
            tip_title.y + title_h + margin + tip_radius,
        ];
        let elevation_title = Rect::new(
            panel_x,
            tip_center[1] + tip_radius + margin,
            panel_w,
            title_h,
        );
        let elevation_view = Rect::new(
            panel_x,
            elevation_title.y + title_h + 0.5 * margin,
            panel_w,
            (0.55 * panel_w).min(0.15 * panel.h),
        );
        let elevation_ball_radius = (0.15 * panel_w).min(0.3 * elevation_view.h);
        let elevation_ball = [
            elevation_view.x + elevation_view.w - 1.6 * elevation_ball_radius,
            elevation_view.y + elevation_view.h - elevation_ball_radius - 3.0,
        ];
        let power_title = Rect::new(
            panel_x,
            elevation_view.y + elevation_view.h + margin,
            panel_w,
            title_h,
        );
        let bar_top = power_title.y + title_h + 0.5 * margin;
        let bar_w = (0.25 * panel_w).max(18.0);
        let power_bar = Rect::new(
            panel_x + 0.5 * (panel_w - bar_w),
            bar_top,
            bar_w,
            (panel.y + panel.h - bar_top).max(20.0),
        );
        Layout {
            screen: [w, h],
            frame,
            scale,
            origin,
            turned: false,
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
            banner: banner(notice, verdict),
        }
    }

    /// Every box the window writes text in, named, for checking that none overlaps another.
    pub fn text_boxes(&self) -> [(&'static str, Rect); 13] {
        [
            ("first player", self.players[0]),
            ("second player", self.players[1]),
            ("game info", self.game_info),
            ("status", self.status),
            ("tip title", self.tip_title),
            ("elevation title", self.elevation_title),
            ("power title", self.power_title),
            ("first tray name", self.tray_names[0]),
            ("second tray name", self.tray_names[1]),
            ("notice", self.notice),
            ("verdict", self.verdict),
            ("hint bar", self.footer),
            ("chat", self.chat),
        ]
    }

    /// The boxes of text once the game is over: the banner in the notice's and the
    /// verdict's place, the others as in [`Layout::text_boxes`].
    pub fn game_over_text_boxes(&self) -> Vec<(&'static str, Rect)> {
        let mut boxes: Vec<_> = self
            .text_boxes()
            .into_iter()
            .filter(|(name, _)| !matches!(*name, "notice" | "verdict"))
            .collect();
        boxes.push(("game over banner", self.banner));
        boxes
    }

    /// The banner's lines, top to bottom: the headline, the reason, what next, each as
    /// high as its size calls for.
    pub fn banner_rows(&self) -> [Rect; 3] {
        let b = self.banner;
        let total: f32 = BANNER_LINES.iter().sum();
        let mut y = b.y;
        BANNER_LINES.map(|size| {
            let h = b.h * size / total;
            y += h;
            Rect::new(b.x, y - h, b.w, h)
        })
    }

    /// The rows of the game-info box: two when the bar is high enough for two lines of
    /// text, else one.
    pub fn game_info_rows(&self) -> Vec<Rect> {
        let g = self.game_info;
        if g.h >= 36.0 {
            let half = 0.5 * g.h;
            vec![
                Rect::new(g.x, g.y, g.w, half),
                Rect::new(g.x, g.y + half, g.w, half),
            ]
        } else {
            vec![g]
        }
    }

    /// The chat's rows, top to bottom: as many as its box holds at `CHAT_ROW` pixels or
    /// more each (three in a 640 x 480 window), the last for the line being typed.
    pub fn chat_rows(&self) -> Vec<Rect> {
        let c = self.chat;
        let n = (c.h / CHAT_ROW).floor().max(1.0) as usize;
        let row = c.h / n as f32;
        (0..n)
            .map(|k| Rect::new(c.x, c.y + k as f32 * row, c.w, row))
            .collect()
    }

    /// The cue elevation (degrees) the side view shows for a mouse at `px`: the angle of the
    /// line from the ball's centre back to the mouse above the cloth, 0 level to 90 straight
    /// down (a mouse below the centre or in front of the ball is held at the nearest end).
    pub fn elevation_at(&self, px: [f32; 2]) -> f64 {
        let [bx, by] = self.elevation_ball;
        let back = (bx - px[0]) as f64;
        let up = (by - px[1]) as f64;
        let degrees = libm::atan2(up, back).to_degrees();
        if degrees < -90.0 {
            // Below and in front: nearer to straight down than to level.
            90.0
        } else {
            degrees.clamp(0.0, 90.0)
        }
    }

    /// The cue in the side view at `elevation_deg`: its tip, just off the ball, and its
    /// butt at the view's edge (pixels).
    pub fn elevation_cue(&self, elevation_deg: f64) -> ([f32; 2], [f32; 2]) {
        let rad = elevation_deg.to_radians();
        let back = [-(libm::cos(rad) as f32), -(libm::sin(rad) as f32)];
        let [bx, by] = self.elevation_ball;
        let r = self.elevation_ball_radius;
        let along = |d: f32| [bx + back[0] * d, by + back[1] * d];
        // As far back as the view goes: to its left edge or its top, whichever comes first.
        let v = self.elevation_view;
        let to_left = (bx - v.x - 2.0) / (-back[0]).max(1e-6);
        let to_top = (by - v.y - 2.0) / (-back[1]).max(1e-6);
        (along(1.15 * r), along(to_left.min(to_top)))
    }

    /// The sights on the wood of a `kind` table, halfway across it (scene coordinates):
    /// every eighth of the length, every quarter of the width; a pool table has its side
    /// pockets where a carom table has its middle sights.
    pub fn sights(&self, kind: TableKind) -> Vec<DVec2> {
        // A snooker table has no sights.
        if kind == TableKind::Snooker {
            return Vec::new();
        }
        let (w, l) = (self.frame.size.x, self.frame.size.y);
        let back = CUSHION_WIDTH + 0.5 * (RAIL_WIDTH - CUSHION_WIDTH);
        let mut spots = Vec::new();
        for k in (1..8).filter(|&k| k != 4 || !kind.has_pockets()) {
            let y = l * k as f64 / 8.0;
            spots.push(DVec2::new(-back, y));
            spots.push(DVec2::new(w + back, y));
        }
        for k in 1..4 {
            let x = w * k as f64 / 4.0;
            spots.push(DVec2::new(x, -back));
            spots.push(DVec2::new(x, l + back));
        }
        spots
    }

    /// Whether the table is turned for a tall window (its length down the screen).
    pub fn turned(&self) -> bool {
        self.turned
    }

    /// Scene coordinates (metres) to pixels.
    pub fn to_screen(&self, p: DVec2) -> [f32; 2] {
        let d = p - self.frame.min;
        let (right, down) = if self.turned {
            // The cloth's top edge is the frame's far end.
            (d.x, self.frame.size.y - d.y)
        } else {
            (d.y, d.x)
        };
        [
            (self.origin.x + right * self.scale) as f32,
            (self.origin.y + down * self.scale) as f32,
        ]
    }

    /// Pixels to scene coordinates (metres).
    pub fn to_scene(&self, px: [f32; 2]) -> DVec2 {
        let sx = (px[0] as f64 - self.origin.x) / self.scale;
        let sy = (px[1] as f64 - self.origin.y) / self.scale;
        self.frame.min
            + if self.turned {
                DVec2::new(sx, self.frame.size.y - sy)
            } else {
                DVec2::new(sy, sx)
            }
    }

    /// A scene direction as a pixel direction (same rotation as [`Layout::to_screen`]).
    pub fn dir_to_screen(&self, d: DVec2) -> [f32; 2] {
        if self.turned {
            [d.x as f32, -d.y as f32]
        } else {
            [d.y as f32, d.x as f32]
        }
    }

    /// A length in metres as pixels.
    pub fn px(&self, metres: f64) -> f32 {
        (metres * self.scale) as f32
    }

    /// The pocket of `table` under the pixel `px`, if any (a little generous, for clicking).
    pub fn pocket_at(&self, table: &Table, px: [f32; 2]) -> Option<u8> {
        let p = self.to_scene(px);
        table
            .pockets
            .iter()
            .position(|pk| (table.to_scene(pk.center) - p).length() <= 1.5 * pk.radius)
            .map(|i| i as u8)
    }

    /// Centre of tray slot `k` (the k-th ball pocketed), for balls of `radius` metres.
    pub fn tray_slot(&self, k: usize, radius: f64) -> [f32; 2] {
        let r = self.px(radius).max(3.0);
        let pitch = 2.6 * r;
        [
            self.tray.x + 1.5 * r + k as f32 * pitch,
            self.tray.y + 0.5 * self.tray.h,
        ]
    }
}

/// The menu's `n` buttons in a `w` x `h` window: one column under the title, as tall as
/// 44 pixels but shorter when the window is low, so that every button is inside it.
pub fn menu_buttons(w: f32, h: f32, n: usize) -> Vec<Rect> {
    let bw = 360.0f32.min(0.85 * w);
    let top = 0.24 * h;
    let gap = 10.0;
    let room = 0.97 * h - top;
    let bh = (room / n.max(1) as f32 - gap).clamp(18.0, 44.0);
    (0..n)
        .map(|k| Rect::new(0.5 * (w - bw), top + k as f32 * (bh + gap), bw, bh))
        .collect()
}

/// How many buttons the lobby's bottom bar holds: quick match (or cancel), refresh, the
/// previous and next pages, back.
pub const LOBBY_BAR: usize = 5;

/// The height of one of the lobby's rows in a window `h` high.
pub fn lobby_row(h: f32) -> f32 {
    (0.05 * h).clamp(24.0, 44.0)
}

/// The top of the lobby's first row (its headings sit a row above it) in a window `h` high.
pub fn lobby_top(h: f32) -> f32 {
    0.2 * h
}

/// Where the buttons beside the lobby's lists stand across a window `w` wide, and their
/// width (at least a word's, in a narrow window).
fn lobby_button_column(w: f32) -> (f32, f32) {
    let button_w = (0.14 * w).max(90.0);
    (w - 0.06 * w - button_w, button_w)
}

/// The box of a lobby's line of text at height `y` in a `w` x `h` window: from the left
/// margin to just short of the buttons beside it.
pub fn lobby_line(w: f32, h: f32, y: f32) -> Rect {
    let left = 0.06 * w;
    let (buttons, _) = lobby_button_column(w);
    Rect::new(left, y, buttons - left - 0.01 * w, lobby_row(h) * 0.9)
}

/// The buttons beside the lobby's lists in a `w` x `h` window: one for each of `waiting`
/// rooms (join), then, after a row's gap, one for each of `playing` games (watch).
pub fn lobby_rows(w: f32, h: f32, waiting: usize, playing: usize) -> (Vec<Rect>, Vec<Rect>) {
    let row_h = lobby_row(h);
    let (x, button_w) = lobby_button_column(w);
    let column = |first: f32, rows: usize| -> Vec<Rect> {
        (0..rows)
            .map(|i| Rect::new(x, first + i as f32 * row_h, button_w, row_h * 0.9))
            .collect()
    };
    let top = lobby_top(h);
    let join = column(top, waiting);
    let watch = column(top + (waiting + 1) as f32 * row_h, playing);
    (join, watch)
}

/// The lobby's bottom bar in a `w` x `h` window: its buttons from left to right, evenly
/// spread along the bottom.
pub fn lobby_bar(w: f32, h: f32) -> [Rect; LOBBY_BAR] {
    let row_h = lobby_row(h);
    let n = LOBBY_BAR as f32;
    let bw = w / (n + 1.0);
    std::array::from_fn(|k| {
        let k = k as f32;
        Rect::new(
            0.5 * bw / n * (k + 1.0) + k * bw,
            h - 1.6 * row_h,
            bw,
            row_h * 1.2,
        )
    })
}

/// The boxes of the menu's page for watching a game again, in a `w` x `h` window.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayPageBoxes {
    /// The line the game's invite (its server and room) is typed on.
    pub field: Rect,
    /// The button that asks the server for the room's games.
    pub list: Rect,
    /// The button back to the menu.
    pub back: Rect,
    /// One button a game, in rows of four: as many of the room's games as fit.
    pub games: Vec<Rect>,
}

/// The replay page's boxes for a room of `games` games (only as many buttons as fit the
/// window: the screen shows the latest ones).
pub fn replay_page(w: f32, h: f32, games: usize) -> ReplayPageBoxes {
    let bw = 560.0f32.min(0.9 * w);
    let x0 = 0.5 * (w - bw);
    let gap = 10.0;
    let bh = (0.06 * h).clamp(22.0, 40.0);
    let field = Rect::new(x0, 0.24 * h, bw, bh);
    let row = field.y + bh + gap;
    let list_w = 0.6 * bw;
    let list = Rect::new(x0, row, list_w, bh);
    let back = Rect::new(x0 + list_w + gap, row, bw - list_w - gap, bh);
    const COLUMNS: usize = 4;
    let top = row + bh + 2.0 * gap;
    let rows = ((0.92 * h - top) / (bh + gap)).floor().max(0.0) as usize;
    let gw = (bw - (COLUMNS - 1) as f32 * gap) / COLUMNS as f32;
    let games = (0..games.min(rows * COLUMNS))
        .map(|k| {
            let (r, c) = (k / COLUMNS, k % COLUMNS);
            Rect::new(
                x0 + c as f32 * (gw + gap),
                top + r as f32 * (bh + gap),
                gw,
                bh,
            )
        })
        .collect();
    ReplayPageBoxes {
        field,
        list,
        back,
        games,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nine_foot(w: f32, h: f32) -> Layout {
        Layout::new(w, h, Frame::new(TableKind::NineFoot, &[]))
    }

    #[test]
    fn screen_and_scene_coordinates_round_trip() {
        let l = nine_foot(1280.0, 720.0);
        for p in [DVec2::ZERO, DVec2::new(1.27, 2.54), DVec2::new(0.3, 1.9)] {
            let back = l.to_scene(l.to_screen(p));
            assert!((back - p).length() < 1e-4, "{p} -> {back}");
        }
    }

    /// Phone-shaped windows held upright.
    const TALL_SIZES: [(f32, f32); 2] = [(390.0, 844.0), (720.0, 1280.0)];

    #[test]
    fn a_tall_window_turns_the_table_and_pixels_map_back_to_the_same_spot() {
        for (w, h) in TALL_SIZES {
            let l = nine_foot(w, h);
            assert!(l.turned(), "{w}x{h}");
            for p in [DVec2::ZERO, DVec2::new(1.27, 2.54), DVec2::new(0.3, 1.9)] {
                let back = l.to_scene(l.to_screen(p));
                assert!((back - p).length() < 1e-4, "{w}x{h}: {p} -> {back}");
            }
            for px in [[l.cloth.x, l.cloth.y], l.cloth.center(), [30.0, 700.0]] {
                let back = l.to_screen(l.to_scene(px));
                assert!((back[0] - px[0]).abs() < 1e-2 && (back[1] - px[1]).abs() < 1e-2);
            }
            // The length runs up the screen: the near end (y = 0) at the cloth's bottom
            // left, the far corner at its top right.
            let near = l.to_screen(DVec2::ZERO);
            assert!((near[0] - l.cloth.x).abs() < 1e-2);
            assert!((near[1] - (l.cloth.y + l.cloth.h)).abs() < 1e-2);
            let far = l.to_screen(DVec2::new(1.27, 2.54));
            assert!((far[0] - (l.cloth.x + l.cloth.w)).abs() < 1e-2);
            assert!((far[1] - l.cloth.y).abs() < 1e-2);
            assert!((l.cloth.h / l.cloth.w - 2.0).abs() < 1e-3);
            // Directions turn with the points.
            let step = l.to_screen(DVec2::new(0.3, 1.0));
            let base = l.to_screen(DVec2::new(0.2, 0.8));
            let dir = l.dir_to_screen(DVec2::new(0.1, 0.2));
            let moved = [step[0] - base[0], step[1] - base[1]];
            let s = l.scale as f32;
            assert!((moved[0] - s * dir[0]).abs() < 1e-2 && (moved[1] - s * dir[1]).abs() < 1e-2);
            // A quarter turn of the wide picture, not its mirror image: scene x then y make
            // the same turn on the screen in both.
            let wide = nine_foot(h, w);
            let turn = |l: &Layout| {
                let [ax, ay] = l.dir_to_screen(DVec2::X);
                let [bx, by] = l.dir_to_screen(DVec2::Y);
                ax * by - ay * bx
            };
            assert_eq!(turn(&l), turn(&wide));
            // The table fills the width: most of it cloth, the rails nearly all of it.
            assert!(l.cloth.w > 0.55 * w, "{w}x{h}: cloth {:?}", l.cloth);
            assert!(l.outer.w > 0.65 * w, "{w}x{h}: table {:?}", l.outer);
        }
        assert!(!nine_foot(844.0, 390.0).turned());
        assert!(!nine_foot(800.0, 800.0).turned());
    }

    #[test]
    fn table_lies_along_the_screen_and_keeps_its_proportions() {
        let l = nine_foot(1280.0, 720.0);
        let corner = l.to_screen(DVec2::ZERO);
        assert!((corner[0] - l.cloth.x).abs() < 1e-3 && (corner[1] - l.cloth.y).abs() < 1e-3);
        let far = l.to_screen(DVec2::new(1.27, 2.54));
        assert!((far[0] - (l.cloth.x + l.cloth.w)).abs() < 1e-2);
        assert!((far[1] - (l.cloth.y + l.cloth.h)).abs() < 1e-2);
        assert!((l.cloth.w / l.cloth.h - 2.0).abs() < 1e-3);
    }

    #[test]
    fn everything_fits_on_screen_at_common_sizes() {
        let sizes = [
            (1280.0, 720.0),
            (1920.0, 1080.0),
            (1280.0, 800.0),
            (800.0, 600.0),
            (700.0, 900.0),
            (2560.0, 700.0),
            (640.0, 480.0),
            (720.0, 1280.0),
        ];
        for (kind, (w, h)) in [TableKind::NineFoot, TableKind::Carom]
            .into_iter()
            .flat_map(|k| sizes.map(|s| (k, s)))
        {
            let l = Layout::new(w, h, Frame::new(kind, &[]));
            let screen = Rect::new(0.0, 0.0, w, h);
            for r in [l.outer, l.tray, l.power_bar, l.elevation_view] {
                assert!(screen.contains([r.x, r.y]) && screen.contains([r.x + r.w, r.y + r.h]));
            }
            if h > w {
                // A tall window: the panel is below the table, its widgets side by side.
                assert!(l.turned(), "{w}x{h}");
                let below = l.tray.y + l.tray.h;
                assert!(l.power_bar.y > below && l.elevation_view.y > below);
                assert!(l.tip_center[1] - l.tip_radius > below);
                assert!(l.elevation_view.x > l.tip_center[0] + l.tip_radius);
                assert!(l.power_bar.x > l.elevation_view.x + l.elevation_view.w);
            } else {
                // Nothing overlaps the table: the panel is to its right, the tray below.
                assert!(!l.turned(), "{w}x{h}");
                assert!(l.power_bar.x > l.outer.x + l.outer.w);
                assert!(l.tip_center[0] - l.tip_radius > l.outer.x + l.outer.w);
                assert!(l.elevation_view.x > l.outer.x + l.outer.w);
                // The panel's widgets are stacked: tip face, side view, power bar.
                assert!(l.elevation_view.y > l.tip_center[1] + l.tip_radius);
                assert!(l.power_bar.y > l.elevation_view.y + l.elevation_view.h);
            }
            let [bx, by] = l.elevation_ball;
            let br = l.elevation_ball_radius;
            assert!(l.elevation_view.contains([bx - br, by - br]));
            assert!(l.elevation_view.contains([bx + br, by + br]));
            // The cue stays in the view at every elevation.
            for deg in [0.0, 30.0, 60.0, 90.0] {
                let (tip, butt) = l.elevation_cue(deg);
                assert!(l.elevation_view.contains(tip) && l.elevation_view.contains(butt));
            }
            assert!(l.tray.y > l.outer.y + l.outer.h);
            assert!(l.outer.y > l.hud.h);
        }
    }

    /// The window sizes the text boxes are checked at: small, common, tall.
    const TEXT_SIZES: [(f32, f32); 5] = [
        (640.0, 480.0),
        (1280.0, 720.0),
        (720.0, 1280.0),
        (1920.0, 1080.0),
        (800.0, 600.0),
    ];

    #[test]
    fn pool_and_carom_rails_carry_sights_and_the_snooker_table_s_none() {
        let count = |kind| {
            Layout::new(1280.0, 720.0, Frame::new(kind, &[]))
                .sights(kind)
                .len()
        };
        // Seven along each long rail (six beside the side pockets), three along each end.
        assert_eq!(count(TableKind::NineFoot), 2 * 6 + 2 * 3);
        assert_eq!(count(TableKind::Carom), 2 * 7 + 2 * 3);
        assert_eq!(count(TableKind::Snooker), 0);
    }

    #[test]
    fn no_box_of_text_overlaps_another_or_leaves_the_window() {
        for kind in [TableKind::NineFoot, TableKind::Carom] {
            for (w, h) in TEXT_SIZES {
                let l = Layout::new(w, h, Frame::new(kind, &[]));
                let screen = Rect::new(0.0, 0.0, w, h);
                for boxes in [l.text_boxes().to_vec(), l.game_over_text_boxes()] {
                    for (i, (name, r)) in boxes.iter().enumerate() {
                        assert!(screen.holds(r), "{w}x{h}: {name} {r:?} leaves the window");
                        assert!(
                            r.w >= 10.0 && r.h >= 14.0,
                            "{w}x{h}: {name} {r:?} too small"
                        );
                        for (other, q) in &boxes[i + 1..] {
                            assert!(
                                !r.overlaps(q),
                                "{w}x{h}: {name} {r:?} overlaps {other} {q:?}"
                            );
                        }
                        // No text over the table, the panel's widgets or (but the panel's
                        // titles) the panel.
                        assert!(!r.overlaps(&l.outer), "{w}x{h}: {name} over the table");
                        assert!(
                            !r.overlaps(&l.power_bar),
                            "{w}x{h}: {name} over the power bar"
                        );
                        assert!(
                            !r.overlaps(&l.elevation_view),
                            "{w}x{h}: {name} over the side view"
                        );
                        let tip = l.tip_radius;
                        let [cx, cy] = l.tip_center;
                        let face = Rect::new(cx - tip, cy - tip, 2.0 * tip, 2.0 * tip);
                        assert!(!r.overlaps(&face), "{w}x{h}: {name} over the tip face");
                        if !name.ends_with("title") {
                            assert!(!r.overlaps(&l.panel), "{w}x{h}: {name} over the panel");
                        }
                    }
                }
                for title in [l.tip_title, l.elevation_title, l.power_title] {
                    assert!(
                        l.panel.holds(&title),
                        "{w}x{h}: {title:?} outside the panel"
                    );
                }
                assert!(l.panel.holds(&l.power_bar) && l.panel.holds(&l.elevation_view));
                assert!(l.hud.holds(&l.players[0]) && l.hud.holds(&l.game_info));
            }
        }
    }

    /// Where a ball can lie, the cloth is free of text: no box of text meets the cloth,
    /// grown by a ball's radius (a ball frozen to a cushion reaches over its nose). The
    /// players' names on the trays leave the balls of a whole rack room between them.
    #[test]
    fn no_box_of_text_meets_the_cloth_where_balls_lie_nor_the_tray_s_balls() {
        let radius = breakshot_shared::physics::Params::default().ball_radius;
        for kind in [TableKind::NineFoot, TableKind::Carom] {
            for (w, h) in [(640.0, 480.0), (1280.0, 720.0), (720.0, 1280.0)] {
                let l = Layout::new(w, h, Frame::new(kind, &[]));
                let r = l.px(radius);
                let c = l.cloth;
                let balls = Rect::new(c.x - r, c.y - r, c.w + 2.0 * r, c.h + 2.0 * r);
                let shown = l.text_boxes().into_iter().chain(l.game_over_text_boxes());
                for (name, b) in shown {
                    assert!(
                        !b.overlaps(&balls),
                        "{w}x{h} {kind:?}: {name} {b:?} on the cloth"
                    );
                }
                let [a, b] = l.tray_names;
                assert!(
                    l.tray.holds(&a) && l.tray.holds(&b),
                    "{w}x{h}: names off the tray"
                );
                let room = b.x - (a.x + a.w);
                let rack = 15.0 * 2.6 * r.max(3.0);
                assert!(
                    room >= rack,
                    "{w}x{h}: {room} px between the names for {rack}"
                );
                assert!(
                    l.footer.h / l.footer_rows as f32 >= 18.0,
                    "{w}x{h}: hint rows"
                );
            }
        }
    }

    #[test]
    fn the_chat_shows_a_few_lines_in_rows_of_its_own_box() {
        for kind in [TableKind::NineFoot, TableKind::Carom] {
            for (w, h) in TEXT_SIZES {
                let l = Layout::new(w, h, Frame::new(kind, &[]));
                let rows = l.chat_rows();
                // Two lines said and the one being typed, even in the smallest window.
                assert!(rows.len() >= 3, "{w}x{h}: {} chat rows", rows.len());
                for (k, r) in rows.iter().enumerate() {
                    assert!(l.chat.holds(r), "{w}x{h}: row {k} {r:?} out of the chat");
                    assert!(r.h >= CHAT_ROW && r.w >= 0.2 * w, "{w}x{h}: row {k} {r:?}");
                }
                assert!(rows.windows(2).all(|p| p[0].y + p[0].h <= p[1].y + 1e-3));
            }
        }
    }

    #[test]
    fn the_game_over_banner_stacks_its_lines_in_its_box_the_headline_biggest() {
        for kind in [TableKind::NineFoot, TableKind::Carom] {
            for (w, h) in TEXT_SIZES {
                let l = Layout::new(w, h, Frame::new(kind, &[]));
                let [head, reason, next] = l.banner_rows();
                for r in [head, reason, next] {
                    assert!(l.banner.holds(&r), "{w}x{h}: {r:?} out of the banner");
                    assert!(r.h >= 14.0 && r.w >= 0.3 * w, "{w}x{h}: {r:?} too small");
                }
                assert!(head.y + head.h <= reason.y + 1e-3 && reason.y + reason.h <= next.y + 1e-3);
                assert!(head.h > reason.h && reason.h >= next.h);
                // It takes the notice's and the verdict's place, not another box's.
                assert!(l.banner.holds(&l.notice) && l.banner.holds(&l.verdict));
            }
        }
    }

    /// The smallest font, in pixels, a line of the bar at the top is readable at (the
    /// built-in font is drawn from 13-pixel glyphs).
    const READABLE_PX: f32 = 12.0;

    #[test]
    fn the_game_info_is_readable_in_its_box_whatever_the_connection_says() {
        use crate::view::hud::{game_info, Connection};
        use crate::view::text;
        use breakshot_shared::rules::{EightBallRules, Variant};
        let states = [
            Connection::Offline,
            Connection::Connecting,
            Connection::WaitingForOpponent,
            Connection::Connected,
            Connection::Reconnecting,
            Connection::OpponentLeft {
                seconds_left: 119.5,
            },
        ];
        let games = [
            Variant::EightBall(EightBallRules::Wpa),
            Variant::NineBall,
            Variant::ThreeCushion { race: 15 },
        ];
        for (w, h) in [(640.0, 480.0), (1280.0, 720.0), (720.0, 1280.0)] {
            let l = nine_foot(w, h);
            let rows = l.game_info_rows();
            let scale = text::scale(h);
            for (state, game) in states.iter().flat_map(|s| games.map(|g| (s, g))) {
                let lines = game_info(game, Some(65.0), state, rows.len());
                assert_eq!(lines.len(), rows.len());
                for (pieces, r) in lines.iter().zip(&rows) {
                    assert!(l.game_info.holds(r), "{w}x{h}: {r:?}");
                    let line: String = pieces.iter().map(|(t, _)| t.as_str()).collect();
                    // The size it is drawn at: 18 at most, as high as the row and no wider.
                    let chars = line.chars().count() as f32;
                    let px = (18.0 * scale).min(r.h).min(r.w / (chars * text::ADVANCE));
                    assert!(px >= READABLE_PX, "{w}x{h}: {line:?} at {px} px in {r:?}");
                    assert!(
                        text::width(&line, px / scale, h) <= r.w,
                        "{w}x{h}: {line:?} wider than {r:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_narrow_window_puts_the_players_one_over_the_other_and_a_wide_one_side_by_side() {
        let narrow = nine_foot(640.0, 480.0);
        assert!(narrow.players[1].y >= narrow.players[0].y + narrow.players[0].h);
        let wide = nine_foot(1280.0, 720.0);
        assert_eq!(wide.players[0].y, wide.players[1].y);
        assert!(wide.players[1].x >= wide.players[0].x + wide.players[0].w);
    }

    #[test]
    fn the_side_view_reads_the_elevation_the_cue_is_drawn_at() {
        let l = nine_foot(1280.0, 720.0);
        for deg in [0.0, 15.0, 45.0, 80.0, 90.0] {
            let (_, butt) = l.elevation_cue(deg);
            assert!((l.elevation_at(butt) - deg).abs() < 0.5, "{deg}");
        }
        let [bx, by] = l.elevation_ball;
        // Below the cloth behind the ball: level; in front of the ball: straight down.
        assert_eq!(l.elevation_at([bx - 40.0, by + 10.0]), 0.0);
        assert_eq!(l.elevation_at([bx + 40.0, by - 10.0]), 90.0);
    }

    #[test]
    fn the_carom_table_keeps_its_proportions_and_has_no_pockets_to_click() {
        let l = Layout::new(1280.0, 720.0, Frame::new(TableKind::Carom, &[]));
        assert!((l.cloth.w / l.cloth.h - 2.84 / 1.42).abs() < 1e-3);
        let far = l.to_screen(DVec2::new(1.42, 2.84));
        assert!((far[0] - (l.cloth.x + l.cloth.w)).abs() < 1e-2);
        assert!((far[1] - (l.cloth.y + l.cloth.h)).abs() < 1e-2);
        // The longer table is drawn at a smaller scale than a 9-foot one in the same window.
        assert!(l.scale < nine_foot(1280.0, 720.0).scale);
        let t = Table::new(TableKind::Carom);
        assert_eq!(l.pocket_at(&t, l.to_screen(DVec2::ZERO)), None);
    }

    #[test]
    fn bigger_window_draws_a_bigger_table() {
        let small = nine_foot(1280.0, 720.0);
        let big = nine_foot(1920.0, 1080.0);
        assert!(big.scale > 1.4 * small.scale);
    }

    #[test]
    fn clicking_a_pocket_names_it() {
        let l = nine_foot(1280.0, 720.0);
        let t = Table::new(TableKind::NineFoot);
        for (i, pk) in t.pockets.iter().enumerate() {
            assert_eq!(
                l.pocket_at(&t, l.to_screen(t.to_scene(pk.center))),
                Some(i as u8)
            );
        }
        assert_eq!(l.pocket_at(&t, l.to_screen(DVec2::new(0.6, 1.2))), None);
    }

    #[test]
    fn open_table_frames_its_balls() {
        let balls = [
            BallState::at_rest(DVec2::new(-3.0, 0.0)),
            BallState::at_rest(DVec2::new(1.0, 4.0)),
        ];
        let f = Frame::new(TableKind::Open, &balls);
        assert!(!f.rails);
        for b in &balls {
            let d = b.pos - f.min;
            assert!(d.x > 0.0 && d.y > 0.0 && d.x < f.size.x && d.y < f.size.y);
        }
    }

    #[test]
    fn every_menu_button_is_inside_the_window_at_every_size() {
        for (w, h) in [
            (1280.0, 720.0),
            (640.0, 480.0),
            (400.0, 300.0),
            (1920.0, 1200.0),
        ] {
            let buttons = menu_buttons(w, h, 8);
            assert_eq!(buttons.len(), 8);
            for b in &buttons {
                assert!(b.x >= 0.0 && b.x + b.w <= w, "{w}x{h}: {b:?}");
                assert!(b.y >= 0.0 && b.y + b.h <= h, "{w}x{h}: {b:?}");
            }
            assert!(buttons.windows(2).all(|p| p[0].y + p[0].h < p[1].y));
        }
    }

    #[test]
    fn the_lobby_s_buttons_are_inside_the_window_apart_and_clear_of_its_lines() {
        // A desktop, a small window and a phone held upright.
        for (w, h) in [(1280.0, 720.0), (640.0, 480.0), (390.0, 844.0)] {
            let screen = Rect::new(0.0, 0.0, w, h);
            let (join, watch) = lobby_rows(w, h, 2, 3);
            assert_eq!((join.len(), watch.len()), (2, 3));
            // The games to watch start a row (their heading's) after the rooms to join.
            let gap = watch[0].y - (join[1].y + join[1].h);
            assert!(gap > lobby_row(h), "{w}x{h}: {gap}");
            let mut all: Vec<Rect> = join.iter().chain(&watch).copied().collect();
            all.extend(lobby_bar(w, h));
            for (i, r) in all.iter().enumerate() {
                assert!(screen.holds(r), "{w}x{h}: {r:?}");
                assert!(
                    all[i + 1..].iter().all(|q| !q.overlaps(r)),
                    "{w}x{h}: {r:?}"
                );
            }
            for row in join.iter().chain(&watch) {
                let line = lobby_line(w, h, row.y);
                assert!(!line.overlaps(row), "{w}x{h}: {line:?} runs under {row:?}");
            }
        }
    }

    #[test]
    fn the_replay_page_s_buttons_are_inside_the_window_and_apart() {
        for (w, h) in [(1280.0, 720.0), (640.0, 480.0), (400.0, 300.0)] {
            let p = replay_page(w, h, 40);
            let screen = Rect::new(0.0, 0.0, w, h);
            let mut all = vec![p.field, p.list, p.back];
            all.extend(&p.games);
            assert!(p.games.len() >= 4, "{w}x{h}: {} games fit", p.games.len());
            for (i, r) in all.iter().enumerate() {
                assert!(screen.holds(r), "{w}x{h}: {r:?}");
                assert!(
                    all[i + 1..].iter().all(|q| !q.overlaps(r)),
                    "{w}x{h}: {r:?}"
                );
            }
        }
        assert_eq!(replay_page(1280.0, 720.0, 2).games.len(), 2);
    }

    #[test]
    fn a_segment_is_clipped_to_a_rectangle() {
        let r = Rect::new(0.0, 0.0, 10.0, 10.0);
        assert_eq!(
            r.clip_segment([5.0, 5.0], [15.0, 5.0]),
            Some(([5.0, 5.0], [10.0, 5.0]))
        );
        assert_eq!(
            r.clip_segment([-5.0, 5.0], [15.0, 5.0]),
            Some(([0.0, 5.0], [10.0, 5.0]))
        );
        assert_eq!(r.clip_segment([12.0, 0.0], [20.0, 20.0]), None);
        assert_eq!(
            r.clip_segment([2.0, 2.0], [3.0, 3.0]),
            Some(([2.0, 2.0], [3.0, 3.0]))
        );
    }
}
