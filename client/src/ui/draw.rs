//! Drawing the table and the balls. Positions come from the library's [`Layout`]; physics
//! values become f32 only here, at the last moment. What lies on the table is drawn through
//! one interface, [`Surface`]: flat from above here ([`TopDown`]), or in 3-D through the
//! view's camera (`table3d.rs`). A [`Pen`] picks which, once ([`Pen::surface`]). The panel
//! and the trays are in `panel.rs` and `trays.rs`.

use ::glam::{DQuat, DVec2};
use breakshot_client::play::Aim;
use breakshot_client::view::aids::{self, AidToggles, PathPoint, Prediction};
use breakshot_client::view::palette::{self, ball_look, Rgb};
use breakshot_client::view::snooker::{self, Markings};
use breakshot_client::view::sphere::{self, ScreenAxes};
use breakshot_client::view::{
    flight, Camera, Flight, Layout, Orientations, Playback, PocketDrop, Rect, Stroke, TrailPoint,
    CUSHION_WIDTH,
};
use breakshot_shared::physics::{BallState, Table, TableKind};
use macroquad::models::Vertex;
use macroquad::prelude::*;

/// The balls to draw: their names and states, their radius, one left out (the cue ball
/// while it is dragged) and how each is turned.
pub struct BallsShown<'a> {
    pub ids: &'a [String],
    pub states: &'a [BallState],
    pub radius: f64,
    pub skip: Option<usize>,
    pub turns: &'a Orientations,
}

/// How the table and what lies on it are drawn this frame.
pub struct Pen<'a> {
    /// The window's layout: the top-down view, and the panel, tray and HUD in both views.
    pub layout: &'a Layout,
    /// The 3-D view's camera, when it is shown.
    pub camera: Option<Camera>,
    /// Balls seen falling into pockets (the 3-D view shows them).
    pub drops: Vec<PocketDrop>,
    /// The cue ball's trail to draw on the cloth (empty when hidden).
    pub trail: Vec<TrailPoint>,
    /// The cue going through the cue ball as a shot starts.
    pub stroke: Option<Stroke>,
}

impl Pen<'_> {
    /// How what lies on the table is drawn this frame: through the 3-D view's camera when
    /// it is shown, else from above.
    pub fn surface(&self) -> &dyn Surface {
        match &self.camera {
            Some(camera) => camera,
            None => &TopDown,
        }
    }
}

/// What lies on the table, drawn one way or another: the one interface of the top-down and
/// the 3-D views.
pub trait Surface {
    /// The cloth, rails, cushions, diamonds and pockets, and the cue ball's trail.
    fn table(&self, pen: &Pen, kind: TableKind);
    /// The balls still on the table (and, in 3-D, those falling into pockets).
    fn balls(&self, pen: &Pen, shown: &BallsShown);
    /// Aim line, ghost ball and predicted paths, as toggled.
    fn aids(&self, pen: &Pen, p: &Prediction, toggles: AidToggles, radius: f64, object_id: &str);
    /// A ball at `pos`, unturned.
    fn ball_at(&self, pen: &Pen, id: &str, pos: DVec2, radius: f64);
    /// A circle just outside `radius` metres about `centre` (a pocket to call).
    fn mark(&self, pen: &Pen, centre: DVec2, radius: f64, width: f32, c: Color);
    /// A ring around the ball at `pos`.
    fn ring(&self, pen: &Pen, pos: DVec2, radius: f64, c: Color);
    /// A straight line on the table.
    fn segment(&self, pen: &Pen, a: DVec2, b: DVec2, width: f32, c: Color);
    /// The cue set up as `aim` says, its tip `back` metres behind the ball at `cue`.
    fn cue_at(&self, pen: &Pen, cue: DVec2, aim: &Aim, back: f64, radius: f64);
    /// The area where the cue ball may be put (pixels of the layout), and the ball dragged.
    fn in_hand(&self, pen: &Pen, area: Rect, dragged: Option<(DVec2, bool)>, radius: f64);
}

/// The table seen from straight above, as the layout maps it.
pub struct TopDown;

/// How far the cue's tip goes past where it met the ball at the end of its stroke (m).
const FOLLOW_THROUGH: f64 = 0.08;

/// The wide layout's mapping of scene directions: x down the screen, y to the right
/// ([`Layout::dir_to_screen`]); for balls drawn off the table, whose turn is none.
const SCREEN_AXES: ScreenAxes = ScreenAxes {
    x: [0.0, 1.0],
    y: [1.0, 0.0],
};

/// The scene's axes on the screen as `layout` draws the table (turned in a tall window).
fn screen_axes(layout: &Layout) -> ScreenAxes {
    let axis = |d: DVec2| layout.dir_to_screen(d).map(f64::from);
    ScreenAxes {
        x: axis(DVec2::X),
        y: axis(DVec2::Y),
    }
}

/// Sides of the polygon a ball is drawn as.
const BALL_SIDES: u8 = 48;

pub fn color(c: Rgb) -> Color {
    Color::from_rgba(c[0], c[1], c[2], 255)
}

pub fn with_alpha(c: Rgb, a: f32) -> Color {
    Color::new(
        c[0] as f32 / 255.0,
        c[1] as f32 / 255.0,
        c[2] as f32 / 255.0,
        a,
    )
}

fn v(p: [f32; 2]) -> Vec2 {
    vec2(p[0], p[1])
}

pub fn fill_rect(r: Rect, c: Color) {
    draw_rectangle(r.x, r.y, r.w, r.h, c);
}

/// The cloth, rails, cushions, diamonds and pockets, and the cue ball's trail on the cloth.
pub fn table(pen: &Pen, kind: TableKind) {
    pen.surface().table(pen, kind);
    if kind == TableKind::Snooker {
        snooker_markings(pen);
    }
}

/// Chalk lines are drawn this wide (pixels, top-down view).
const CHALK_WIDTH: f32 = 1.5;

/// A snooker table's baulk line, D and spots (`view::snooker`'s geometry), on the cloth
/// under the balls, in either view.
fn snooker_markings(pen: &Pen) {
    let Markings {
        baulk,
        d_arc,
        spots,
    } = snooker::markings();
    let c = with_alpha(snooker::MARKING, 0.55);
    let surface = pen.surface();
    surface.segment(pen, baulk.0, baulk.1, CHALK_WIDTH, c);
    for w in d_arc.windows(2) {
        surface.segment(pen, w[0], w[1], CHALK_WIDTH, c);
    }
    for s in spots {
        let ring = snooker::circle(s, snooker::SPOT_RADIUS, 12);
        for w in ring.windows(2) {
            surface.segment(pen, w[0], w[1], 2.0, c);
        }
    }
}

/// The colour of a stretch of the cue ball's trail drawn with `strength`.
pub fn trail_colour(strength: f32) -> Color {
    Color::new(1.0, 0.92, 0.55, 0.85 * strength)
}

/// The table's rails, cushions, pockets and diamonds around the cloth.
fn rails(layout: &Layout, kind: TableKind) {
    let t = Table::new(kind);
    fill_rect(layout.outer, color(palette::RAIL_WOOD));
    let cushion = layout.px(CUSHION_WIDTH);
    // Under the cushions: pocket-black where the rails leave gaps for pockets, cushion all
    // round on a table without pockets (carom), whose cushions meet in the corners.
    let under = if t.pockets.is_empty() {
        palette::CUSHION
    } else {
        palette::POCKET
    };
    fill_rect(
        Rect::new(
            layout.cloth.x - cushion,
            layout.cloth.y - cushion,
            layout.cloth.w + 2.0 * cushion,
            layout.cloth.h + 2.0 * cushion,
        ),
        color(under),
    );
    fill_rect(layout.cloth, color(palette::CLOTH));
    let scene = |p: DVec2| v(layout.to_screen(t.to_scene(p)));
    for rail in &t.rails {
        let out = -rail.normal * CUSHION_WIDTH;
        let (a, b) = (scene(rail.a), scene(rail.b));
        let (a2, b2) = (scene(rail.a + out), scene(rail.b + out));
        draw_triangle(a, b, b2, color(palette::CUSHION));
        draw_triangle(a, b2, a2, color(palette::CUSHION));
    }
    let disc = |centre: DVec2, radius: f64, sides: u8, fill: Rgb| {
        let c = scene(centre);
        draw_poly(c.x, c.y, sides, layout.px(radius), 0.0, color(fill));
    };
    for jaw in &t.jaws {
        disc(jaw.center, jaw.radius, 24, palette::CUSHION);
    }
    for pocket in &t.pockets {
        disc(pocket.center, pocket.radius, 40, palette::POCKET);
    }
    diamonds(layout, kind);
}

fn diamonds(layout: &Layout, kind: TableKind) {
    let size = layout.px(0.012).max(2.0);
    for s in layout.sights(kind) {
        let p = layout.to_screen(s);
        draw_poly(p[0], p[1], 4, size, 0.0, color(palette::DIAMOND));
    }
}

/// One ball at pixel `at` with radius `r` pixels, unturned, on the cloth.
pub fn ball(id: &str, at: [f32; 2], r: f32) {
    ball_turned(id, at, r, DQuat::IDENTITY, flight(0.0, 1.0), SCREEN_AXES);
}

/// One ball turned by `turn` ([`Orientations`]) and at the height `air` says: a soft shadow
/// on the cloth, the shaded sphere with its spots and stripe where the turn puts them, the
/// numbers on the spots that face up, and a highlight. `r` is the radius on the cloth; a
/// ball in flight is drawn bigger, its shadow further off.
pub fn ball_turned(id: &str, at: [f32; 2], r: f32, turn: DQuat, air: Flight, axes: ScreenAxes) {
    let look = ball_look(id);
    let (x, y) = (at[0], at[1]);
    // The shadow falls down-right, away from the light; three layers make its edge soft.
    let (sx, sy) = (air.shadow[0] as f32 * r, air.shadow[1] as f32 * r);
    let dark = air.shadow_strength as f32;
    for (grow, alpha) in [(1.25, 0.10), (1.1, 0.14), (0.95, 0.18)] {
        draw_poly(
            x + sx,
            y + sy,
            BALL_SIDES,
            r * grow,
            0.0,
            Color::new(0.0, 0.0, 0.0, alpha * dark),
        );
    }
    let r = r * air.scale as f32;
    let f = sphere::fan(&look, turn, axes);
    let vertices = f
        .points
        .iter()
        .map(|p| Vertex {
            position: vec3(x + r * p.at[0], y + r * p.at[1], 0.0),
            uv: Vec2::ZERO,
            color: p.rgba,
            normal: Vec4::ZERO,
        })
        .collect();
    let indices = f.triangles.iter().flatten().copied().collect();
    draw_mesh(&Mesh {
        vertices,
        indices,
        texture: None,
    });
    if let Some(n) = look.number {
        for (spot, facing) in sphere::spots(turn, axes) {
            // The number fades and shrinks as its spot turns away.
            if facing < 0.45 {
                continue;
            }
            let text = n.to_string();
            let size = ((1.1 * r) as f64 * facing).max(6.0) as u16;
            let dims = measure_text(&text, None, size, 1.0);
            let (cx, cy) = (x + r * spot[0] as f32, y + r * spot[1] as f32);
            let alpha = ((facing - 0.45) / 0.35).min(1.0) as f32;
            draw_text(
                &text,
                cx - 0.5 * dims.width,
                cy + 0.5 * dims.offset_y - 0.5,
                size as f32,
                Color::new(0.0, 0.0, 0.0, alpha),
            );
        }
    }
    for (dx, grow, alpha) in [(0.36, 0.28, 0.25), (0.38, 0.14, 0.55)] {
        draw_poly(
            x - dx * r,
            y - 1.3 * dx * r,
            24,
            grow * r,
            0.0,
            Color::new(1.0, 1.0, 1.0, alpha),
        );
    }
}

/// The balls still on the table, each turned as `turns` says; balls in flight are drawn
/// after those on the cloth, so they pass over them.
pub fn balls(pen: &Pen, shown: &BallsShown) {
    pen.surface().balls(pen, shown);
    stroke(pen, shown.radius);
}

/// The cue going through where the cue ball was as the shot starts, level, slowing down.
fn stroke(pen: &Pen, radius: f64) {
    if let Some(s) = pen.stroke {
        let mut aim = Aim::default();
        aim.point_along(s.dir);
        let left = 1.0 - s.done;
        let eased = 1.0 - left * left;
        cue_at(pen, s.at, &aim, -FOLLOW_THROUGH * eased, radius);
    }
}

/// Aim line, ghost ball and predicted paths, as toggled.
pub fn aids(pen: &Pen, p: &Prediction, toggles: AidToggles, radius: f64, object_id: &str) {
    pen.surface().aids(pen, p, toggles, radius, object_id);
}

/// A ball on the table at `pos` (scene coordinates), unturned.
pub fn ball_at(pen: &Pen, id: &str, pos: DVec2, radius: f64) {
    pen.surface().ball_at(pen, id, pos, radius);
}

/// A circle just outside `radius` metres about `centre` on the table (a pocket to call).
pub fn mark(pen: &Pen, centre: DVec2, radius: f64, width: f32, c: Color) {
    pen.surface().mark(pen, centre, radius, width, c);
}

/// A ring around the ball at `pos`, to mark it.
pub fn ring(pen: &Pen, pos: DVec2, radius: f64, c: Color) {
    pen.surface().ring(pen, pos, radius, c);
}

/// A straight line on the table, from `a` to `b` (scene coordinates).
pub fn segment(pen: &Pen, a: DVec2, b: DVec2, width: f32, c: Color) {
    pen.surface().segment(pen, a, b, width, c);
}

/// The cue stick behind the cue ball, drawn back further the harder the shot. Seen from
/// above, an elevated cue is foreshortened: its length on the table shrinks with cos θ.
pub fn cue_stick(pen: &Pen, cue: DVec2, aim: &Aim, radius: f64) {
    cue_at(pen, cue, aim, radius * (0.3 + 8.0 * aim.power), radius);
}

/// The cue set up as `aim` says with its tip `back` metres behind the spot it strikes on the
/// ball at `cue` (negative: through it).
fn cue_at(pen: &Pen, cue: DVec2, aim: &Aim, back: f64, radius: f64) {
    pen.surface().cue_at(pen, cue, aim, back, radius);
}

/// The shaded area where the cue ball may be put (pixels of the layout), and the ball being
/// dragged.
pub fn in_hand(pen: &Pen, area: Rect, dragged: Option<(DVec2, bool)>, radius: f64) {
    pen.surface().in_hand(pen, area, dragged, radius);
}

/// How much text grows with the window, so it stays readable on large screens.
/// The F3 overlay's line for the shot being played: how far into it, and its events.
pub fn debug_shot_line(playback: &Playback) -> String {
    let o = playback.outcome();
    format!(
        "t {:.3} / {:.3} s, {} events",
        playback.time(),
        o.duration,
        o.events.len()
    )
}

/// The F3 overlay: `lines` in the tray under the table, where they cover no ball on the
/// cloth (two to a row, small enough to fit).
pub fn debug_lines(layout: &Layout, lines: &[String]) {
    let rows: Vec<String> = lines.chunks(2).map(|pair| pair.join("  |  ")).collect();
    let tray = layout.tray;
    let step = tray.h / rows.len().max(1) as f32;
    let widest = rows.iter().map(|r| text_width(r, 16.0)).fold(1.0, f32::max);
    let size = (16.0 * (0.8 * tray.w / widest).min(1.0))
        .min(0.8 * step / text_scale())
        .max(8.0);
    let width = rows.iter().map(|r| text_width(r, size)).fold(0.0, f32::max);
    let x = tray.x + 0.5 * (tray.w - width);
    draw_rectangle(
        x - 6.0,
        tray.y,
        width + 12.0,
        tray.h,
        Color::new(0.0, 0.0, 0.0, 0.75),
    );
    for (k, row) in rows.iter().enumerate() {
        let y = tray.y + step * (k as f32 + 0.5) + 0.35 * size * text_scale();
        label(row, x, y, size, YELLOW);
    }
}

pub fn text_scale() -> f32 {
    breakshot_client::view::text::scale(screen_height())
}

/// A line of text for the HUD and messages, `size` as at 720 pixels high.
pub fn label(text: &str, x: f32, y: f32, size: f32, c: Color) {
    draw_text(text, x, y, size * text_scale(), c);
}

/// A [`label`] centred across the window, its baseline at `y` (the pages' titles and notices).
pub fn centred(text: &str, y: f32, size: f32, c: Color) {
    label(
        text,
        0.5 * (screen_width() - text_width(text, size)),
        y,
        size,
        c,
    );
}

/// Width of a [`label`].
pub fn text_width(text: &str, size: f32) -> f32 {
    measure_text(text, None, (size * text_scale()) as u16, 1.0).width
}

/// Where a line of text sits across its box.
#[derive(Clone, Copy)]
pub enum Align {
    Left,
    Centre,
}

/// The smallest size a fitted line is drawn at; a line still too wide there is cut short.
const SMALLEST_TEXT: f32 = 9.0;

/// The size (as for [`label`]) at which `text` fits `w` × `h` pixels, `max` at most.
pub fn fitted_size(text: &str, w: f32, h: f32, max: f32) -> f32 {
    let mut size = max.min(h / text_scale());
    // Font sizes are whole pixels, so the width is not quite proportional: shrink until it fits.
    for _ in 0..4 {
        let width = text_width(text, size);
        if width <= w {
            break;
        }
        size *= 0.98 * w / width.max(1.0);
    }
    size.max(SMALLEST_TEXT)
}

/// `text` cut, with "...", to fit `w` pixels at `size`.
fn cut_to_fit(text: &str, w: f32, size: f32) -> String {
    if text_width(text, size) <= w {
        return text.to_owned();
    }
    let chars: Vec<char> = text.chars().collect();
    (0..chars.len())
        .rev()
        .map(|n| format!("{}...", chars[..n].iter().collect::<String>()))
        .find(|t| text_width(t, size) <= w)
        .unwrap_or_default()
}

/// A menu button's face: its fill, lighter under the mouse (`hot`), and its outline.
pub fn button_face(r: Rect, hot: bool) {
    let fill = if hot {
        Color::from_rgba(40, 130, 90, 255)
    } else {
        Color::from_rgba(24, 104, 74, 255)
    };
    draw_rectangle(r.x, r.y, r.w, r.h, fill);
    draw_rectangle_lines(
        r.x,
        r.y,
        r.w,
        r.h,
        2.0,
        Color::from_rgba(200, 220, 200, 255),
    );
}

/// A line of text in the box `r`, shrunk (and if need be cut) to fit it, centred upright.
pub fn label_in(text: &str, r: Rect, max: f32, align: Align, c: Color) {
    let size = fitted_size(text, r.w, r.h, max);
    let text = cut_to_fit(text, r.w, size);
    let dims = measure_text(&text, None, (size * text_scale()) as u16, 1.0);
    let x = match align {
        Align::Left => r.x,
        Align::Centre => r.x + 0.5 * (r.w - dims.width),
    };
    let y = r.y + 0.5 * (r.h - dims.height) + dims.offset_y;
    label(&text, x, y, size, c);
}

impl Surface for TopDown {
    fn table(&self, pen: &Pen, kind: TableKind) {
        let layout = pen.layout;
        if layout.frame.rails {
            rails(layout, kind);
        } else {
            fill_rect(layout.cloth, color(palette::CLOTH));
        }
        for w in pen.trail.windows(2) {
            let (a, b) = (layout.to_screen(w[0].pos), layout.to_screen(w[1].pos));
            draw_line(a[0], a[1], b[0], b[1], 2.5, trail_colour(w[1].strength));
        }
    }

    fn balls(&self, pen: &Pen, shown: &BallsShown) {
        let BallsShown {
            ids,
            states,
            radius,
            skip,
            turns,
        } = *shown;
        let layout = pen.layout;
        let r = layout.px(radius);
        for in_air in [false, true] {
            for (i, (id, s)) in ids.iter().zip(states).enumerate() {
                if s.motion.is_gone() || Some(i) == skip || (s.lift > 0.0) != in_air {
                    continue;
                }
                let air = flight(s.lift, radius);
                let at = layout.to_screen(s.pos);
                ball_turned(id, at, r, turns.get(i), air, screen_axes(layout));
            }
        }
    }

    fn aids(&self, pen: &Pen, p: &Prediction, toggles: AidToggles, radius: f64, object_id: &str) {
        let layout = pen.layout;
        let line = |pts: &[PathPoint], width: f32, c: Color| {
            for (p, q) in aids::drawn_pieces(pts) {
                let (a, b) = (layout.to_screen(p.pos), layout.to_screen(q.pos));
                draw_line(a[0], a[1], b[0], b[1], width, c);
            }
        };
        let mark_landings = |pts: &[PathPoint], c: Color| {
            for at in aids::landings(pts) {
                let q = layout.to_screen(at);
                draw_poly_lines(q[0], q[1], 16, layout.px(0.4 * radius), 0.0, 1.5, c);
            }
        };
        if toggles.paths {
            line(&p.cue_path, 1.5, Color::new(1.0, 1.0, 1.0, 0.5));
            mark_landings(&p.cue_path, Color::new(1.0, 1.0, 1.0, 0.7));
            // The object ball's path in its own colour, on a pale halo so dark balls show too.
            line(&p.object_path, 4.0, Color::new(1.0, 1.0, 1.0, 0.35));
            line(
                &p.object_path,
                2.0,
                with_alpha(ball_look(object_id).color, 1.0),
            );
        }
        if toggles.aim_line {
            line(&p.aim_path, 1.5, Color::new(1.0, 1.0, 1.0, 0.85));
            mark_landings(&p.aim_path, Color::new(1.0, 1.0, 1.0, 0.85));
        }
        if toggles.ghost_ball {
            if let Some(g) = p.ghost {
                let c = layout.to_screen(g);
                draw_poly_lines(
                    c[0],
                    c[1],
                    BALL_SIDES,
                    layout.px(radius),
                    0.0,
                    1.5,
                    Color::new(1.0, 1.0, 1.0, 0.8),
                );
            }
        }
    }

    fn ball_at(&self, pen: &Pen, id: &str, pos: DVec2, radius: f64) {
        let layout = pen.layout;
        ball(id, layout.to_screen(pos), layout.px(radius));
    }

    fn mark(&self, pen: &Pen, centre: DVec2, radius: f64, width: f32, c: Color) {
        let layout = pen.layout;
        let p = layout.to_screen(centre);
        draw_poly_lines(p[0], p[1], 32, layout.px(radius) + 3.0, 0.0, width, c);
    }

    fn ring(&self, pen: &Pen, pos: DVec2, radius: f64, c: Color) {
        let layout = pen.layout;
        let p = layout.to_screen(pos);
        draw_poly_lines(p[0], p[1], BALL_SIDES, layout.px(radius) + 4.0, 0.0, 2.5, c);
    }

    fn segment(&self, pen: &Pen, a: DVec2, b: DVec2, width: f32, c: Color) {
        let layout = pen.layout;
        let (a, b) = (layout.to_screen(a), layout.to_screen(b));
        draw_line(a[0], a[1], b[0], b[1], width, c);
    }

    fn cue_at(&self, pen: &Pen, cue: DVec2, aim: &Aim, back: f64, radius: f64) {
        let layout = pen.layout;
        let dir = aim.dir();
        let slant = libm::cos(aim.elevation_deg.to_radians()).max(0.05);
        let gap = (radius + back) * slant;
        let tip = cue - dir * gap;
        let butt = tip - dir * (1.3 * slant);
        let w = layout.px(0.012).max(3.0);
        // Only the part over the table is drawn: the cue never covers the panel beside it.
        let over_table = |from: DVec2, to: DVec2, c: Rgb| {
            let (a, b) = (layout.to_screen(from), layout.to_screen(to));
            if let Some((a, b)) = layout.outer.clip_segment(a, b) {
                draw_line(a[0], a[1], b[0], b[1], w, color(c));
            }
        };
        over_table(tip, butt, palette::CUE_WOOD);
        over_table(tip, tip - dir * 0.02, palette::CUE_FERRULE);
    }

    fn in_hand(&self, pen: &Pen, area: Rect, dragged: Option<(DVec2, bool)>, radius: f64) {
        let layout = pen.layout;
        fill_rect(area, Color::new(1.0, 1.0, 1.0, 0.08));
        draw_rectangle_lines(
            area.x,
            area.y,
            area.w,
            area.h,
            2.0,
            Color::new(1.0, 1.0, 1.0, 0.5),
        );
        if let Some((at, legal)) = dragged {
            let p = layout.to_screen(at);
            let r = layout.px(radius);
            ball("cue", p, r);
            let ring = if legal {
                Color::new(0.2, 0.9, 0.3, 1.0)
            } else {
                Color::new(0.95, 0.15, 0.15, 1.0)
            };
            draw_poly_lines(p[0], p[1], BALL_SIDES, r + 2.0, 0.0, 2.0, ring);
        }
    }
}
