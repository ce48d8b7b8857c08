//! The table in 3-D through the library's [`Camera`]: meshes built here each frame for the
//! cloth, cushions, jaws, wood, pockets and diamonds, lit spheres for the balls (their spots
//! and stripes from the same `sphere::surface` as the top-down view), the cue stick, and the
//! aids as lines on the cloth. Numbers are printed in 2-D over the projected spots.

use ::glam::{DQuat, DVec2, DVec3};
use breakshot_client::play::Aim;
use breakshot_client::view::aids::{drawn_pieces, AidToggles, PathPoint, Prediction};
use breakshot_client::view::palette::{self, ball_look, Rgb};
use breakshot_client::view::{sphere, Camera, Layout, TrailPoint, CUSHION_WIDTH, RAIL_WIDTH};
use breakshot_shared::physics::{Params, Table, TableKind};
use macroquad::models::Vertex;
use macroquad::prelude::*;

use super::draw::{self, BallsShown, Pen, Surface};

/// Where the light comes from (towards it): above the table, a little towards its foot.
const LIGHT: [f64; 3] = [-0.25, -0.35, 1.0];
const AMBIENT: f64 = 0.42;
/// Sphere tessellation: stacks from pole to pole and slices around.
const STACKS: usize = 14;
const SLICES: usize = 24;
/// Lines drawn on the cloth are lifted this much so the cloth does not hide them (m).
const ON_CLOTH: f64 = 0.0015;
/// How far the wood reaches below the cloth (m), so low views see the table's sides.
const SKIRT: f64 = 0.2;
/// The longest batch of vertices and indices sent at once (macroquad's default draw call
/// holds 10000 vertices and 5000 indices).
const BATCH: (usize, usize) = (4000, 4500);

/// The library's camera as macroquad draws with it.
struct Gl(Mat4);

impl macroquad::camera::Camera for Gl {
    fn matrix(&self) -> Mat4 {
        self.0
    }
    fn depth_enabled(&self) -> bool {
        true
    }
    fn render_pass(&self) -> Option<macroquad::texture::RenderPass> {
        None
    }
    fn viewport(&self) -> Option<(i32, i32, i32, i32)> {
        None
    }
}

/// Draws `paint` in the 3-D world of `camera`, then goes back to the window's pixels.
fn in_world(camera: &Camera, paint: impl FnOnce()) {
    let m = camera.matrix().to_cols_array().map(|x| x as f32);
    set_camera(&Gl(Mat4::from_cols_array(&m)));
    paint();
    set_default_camera();
}

fn v3(p: DVec3) -> Vec3 {
    vec3(p.x as f32, p.y as f32, p.z as f32)
}

/// How bright a surface facing `n` is.
fn lit(n: DVec3) -> f64 {
    AMBIENT
        + (1.0 - AMBIENT)
            * n.normalize_or_zero()
                .dot(DVec3::from(LIGHT).normalize())
                .max(0.0)
}

fn shade(c: Rgb, k: f64, alpha: u8) -> [u8; 4] {
    let s = |x: u8| (x as f64 * k).round().clamp(0.0, 255.0) as u8;
    [s(c[0]), s(c[1]), s(c[2]), alpha]
}

/// Triangles gathered and sent to the GPU in batches macroquad can take.
#[derive(Default)]
struct Meshes {
    vertices: Vec<Vertex>,
    indices: Vec<u16>,
}

impl Meshes {
    fn room(&mut self, vertices: usize, indices: usize) -> u16 {
        if self.vertices.len() + vertices > BATCH.0 || self.indices.len() + indices > BATCH.1 {
            self.flush();
        }
        self.vertices.len() as u16
    }

    fn vertex(&mut self, p: DVec3, c: [u8; 4]) {
        self.vertices.push(Vertex {
            position: v3(p),
            uv: Vec2::ZERO,
            color: c,
            normal: Vec4::ZERO,
        });
    }

    /// A flat polygon (convex, corners in order), lit by its own normal.
    fn polygon(&mut self, corners: &[DVec3], c: Rgb, alpha: u8) {
        if corners.len() < 3 {
            return;
        }
        let n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let colour = shade(c, lit(if n.z < 0.0 { -n } else { n }), alpha);
        let base = self.room(corners.len(), 3 * corners.len());
        for &p in corners {
            self.vertex(p, colour);
        }
        for k in 1..corners.len() as u16 - 1 {
            self.indices.extend([base, base + k, base + k + 1]);
        }
    }

    /// A disc of radius `r` about `centre`, level.
    fn disc(&mut self, centre: DVec3, r: f64, c: Rgb, alpha: u8) {
        let ring: Vec<DVec3> = (0..32)
            .map(|k| {
                let a = k as f64 / 32.0 * std::f64::consts::TAU;
                centre + DVec3::new(r * libm::cos(a), r * libm::sin(a), 0.0)
            })
            .collect();
        self.polygon(&ring, c, alpha);
    }

    fn flush(&mut self) {
        if !self.vertices.is_empty() {
            draw_mesh(&Mesh {
                vertices: std::mem::take(&mut self.vertices),
                indices: std::mem::take(&mut self.indices),
                texture: None,
            });
        }
    }
}

/// The cloth, cushions, jaws, pockets, wood and diamonds.
pub fn table(camera: &Camera, layout: &Layout, kind: TableKind) {
    in_world(camera, || {
        let mut m = Meshes::default();
        let f = layout.frame;
        let corner = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        if !f.rails {
            let (lo, hi) = (f.min, f.min + f.size);
            m.polygon(
                &[
                    corner(lo.x, lo.y, 0.0),
                    corner(hi.x, lo.y, 0.0),
                    corner(hi.x, hi.y, 0.0),
                    corner(lo.x, hi.y, 0.0),
                ],
                palette::CLOTH,
                255,
            );
            m.flush();
            return;
        }
        let t = Table::new(kind);
        let h = Params::default().cushion_height;
        let (w, l) = (f.size.x, f.size.y);
        let rect = |grow: f64, z: f64| {
            [
                corner(-grow, -grow, z),
                corner(w + grow, -grow, z),
                corner(w + grow, l + grow, z),
                corner(-grow, l + grow, z),
            ]
        };
        m.polygon(&rect(CUSHION_WIDTH, 0.0), palette::CLOTH, 255);
        // A pocket reaches into the wood but stops short of its outer edge.
        let mouth = |c: DVec2, radius: f64| {
            let to_edge = (c.x + RAIL_WIDTH)
                .min(w + RAIL_WIDTH - c.x)
                .min(c.y + RAIL_WIDTH)
                .min(l + RAIL_WIDTH - c.y);
            radius.min(to_edge - 0.01)
        };
        for pocket in &t.pockets {
            let c = t.to_scene(pocket.center);
            let r = mouth(c, pocket.radius);
            m.disc(c.extend(ON_CLOTH * 0.5), r, palette::POCKET, 255);
        }
        // The wood: its top between the cushions' backs and its outer edge, and its sides.
        let (inner, outer) = (rect(CUSHION_WIDTH, h), rect(RAIL_WIDTH, h));
        let outer_low = rect(RAIL_WIDTH, -SKIRT);
        for k in 0..4 {
            let j = (k + 1) % 4;
            m.polygon(
                &[inner[k], outer[k], outer[j], inner[j]],
                palette::RAIL_WOOD,
                255,
            );
            m.polygon(
                &[outer[k], outer_low[k], outer_low[j], outer[j]],
                palette::RAIL_WOOD,
                255,
            );
        }
        for rail in &t.rails {
            let (a, b) = (t.to_scene(rail.a), t.to_scene(rail.b));
            let back = -rail.normal * CUSHION_WIDTH;
            let at = |p: DVec2, z: f64| p.extend(z);
            // The nose face and the top of the cushion.
            m.polygon(
                &[at(a, 0.0), at(b, 0.0), at(b, h), at(a, h)],
                palette::CUSHION,
                255,
            );
            m.polygon(
                &[at(a, h), at(b, h), at(b + back, h), at(a + back, h)],
                palette::CUSHION,
                255,
            );
        }
        for jaw in &t.jaws {
            let c = t.to_scene(jaw.center);
            let ring = |k: usize| {
                let a = k as f64 / 16.0 * std::f64::consts::TAU;
                c + jaw.radius * DVec2::new(libm::cos(a), libm::sin(a))
            };
            for k in 0..16 {
                let (p, q) = (ring(k), ring(k + 1));
                m.polygon(
                    &[p.extend(0.0), q.extend(0.0), q.extend(h), p.extend(h)],
                    palette::CUSHION,
                    255,
                );
            }
            m.disc(c.extend(h), jaw.radius, palette::CUSHION, 255);
        }
        // The pockets' mouths cut through the wood.
        for pocket in &t.pockets {
            let c = t.to_scene(pocket.center);
            let r = mouth(c, pocket.radius);
            m.disc(c.extend(h + 0.0005), r, palette::POCKET, 255);
        }
        for s in layout.sights(kind) {
            let d = 0.012;
            let z = h + 0.001;
            m.polygon(
                &[
                    DVec3::new(s.x - d, s.y, z),
                    DVec3::new(s.x, s.y - d, z),
                    DVec3::new(s.x + d, s.y, z),
                    DVec3::new(s.x, s.y + d, z),
                ],
                palette::DIAMOND,
                255,
            );
        }
        m.flush();
    });
}

/// One ball as a lit sphere centred at `centre`, turned by `turn`, seen from `eye`.
fn sphere_mesh(m: &mut Meshes, id: &str, centre: DVec3, r: f64, turn: DQuat, eye: DVec3) {
    let look = ball_look(id);
    let back = turn.inverse();
    let light = DVec3::from(LIGHT).normalize();
    let base = m.room((STACKS + 1) * (SLICES + 1), 6 * STACKS * SLICES);
    for i in 0..=STACKS {
        let polar = i as f64 / STACKS as f64 * std::f64::consts::PI;
        for j in 0..=SLICES {
            let a = j as f64 / SLICES as f64 * std::f64::consts::TAU;
            let n = DVec3::new(
                libm::sin(polar) * libm::cos(a),
                libm::sin(polar) * libm::sin(a),
                libm::cos(polar),
            );
            let p = centre + r * n;
            let half = (light + (eye - p).normalize_or_zero()).normalize_or_zero();
            let glint = libm::pow(n.dot(half).max(0.0), 48.0) * 0.7;
            let c = sphere::surface(&look, back * n);
            let k = AMBIENT + (1.0 - AMBIENT) * n.dot(light).max(0.0);
            let s = |x: u8| (x as f64 * k + 255.0 * glint).round().clamp(0.0, 255.0) as u8;
            m.vertex(p, [s(c[0]), s(c[1]), s(c[2]), 255]);
        }
    }
    let row = (SLICES + 1) as u16;
    for i in 0..STACKS as u16 {
        for j in 0..SLICES as u16 {
            let (a, b) = (base + i * row + j, base + i * row + j + 1);
            let (c, d) = (a + row, b + row);
            m.indices.extend([a, c, d, a, d, b]);
        }
    }
}

/// A ball to draw: its id, its centre and how it is turned.
pub struct Ball<'a> {
    pub id: &'a str,
    pub centre: DVec3,
    pub turn: DQuat,
}

/// The balls on the table (and those falling into pockets), each with its shadow on the
/// cloth; then their numbers over the spots that face the camera.
pub fn balls(camera: &Camera, shown: &[Ball], radius: f64) {
    let light = DVec3::from(LIGHT).normalize();
    in_world(camera, || {
        let mut m = Meshes::default();
        for b in shown.iter().filter(|b| b.centre.z > -radius) {
            // The shadow falls on the cloth away from the light, fainter the higher the ball.
            let height = b.centre.z.max(0.0);
            let at = b.centre.truncate() - light.truncate() / light.z * height;
            let alpha = (90.0 / (1.0 + 0.5 * (height - radius).max(0.0) / radius)) as u8;
            m.disc(at.extend(ON_CLOTH * 0.7), 1.05 * radius, [0, 0, 0], alpha);
        }
        m.flush();
        for b in shown {
            sphere_mesh(&mut m, b.id, b.centre, radius, b.turn, camera.eye());
        }
        m.flush();
    });
    for b in shown {
        let Some(n) = ball_look(b.id).number else {
            continue;
        };
        for up in [b.turn * DVec3::Z, -(b.turn * DVec3::Z)] {
            let spot = b.centre + radius * up;
            let facing = up.dot((camera.eye() - spot).normalize_or_zero());
            let Some(px) = camera.project(spot).filter(|_| facing > 0.45) else {
                continue;
            };
            let r = camera.pixels_at(b.centre, radius);
            let text = n.to_string();
            let size = ((1.1 * r) as f64 * facing).max(6.0) as u16;
            let dims = measure_text(&text, None, size, 1.0);
            let alpha = ((facing - 0.45) / 0.35).min(1.0) as f32;
            draw_text(
                &text,
                px[0] - 0.5 * dims.width,
                px[1] + 0.5 * dims.offset_y - 0.5,
                size as f32,
                Color::new(0.0, 0.0, 0.0, alpha),
            );
        }
    }
}

/// The balls still on the table and those seen falling, as [`balls`] draws them.
fn on_table<'a>(shown: &BallsShown<'a>) -> Vec<Ball<'a>> {
    shown
        .ids
        .iter()
        .zip(shown.states)
        .enumerate()
        .filter(|&(i, (_, s))| !s.motion.is_gone() && Some(i) != shown.skip)
        .map(|(i, (id, s))| Ball {
            id,
            centre: s.pos.extend(shown.radius + s.lift),
            turn: shown.turns.get(i),
        })
        .collect()
}

fn line_on_cloth(a: DVec3, b: DVec3, c: Color) {
    draw_line_3d(v3(a), v3(b), c);
}

/// A path as a line on the cloth, risen where the ball flies; flying stretches dotted.
fn path(pts: &[PathPoint], radius: f64, c: Color) {
    let z = |p: &PathPoint| {
        if p.lift > 0.0 {
            p.lift + radius
        } else {
            ON_CLOTH
        }
    };
    for (p, q) in drawn_pieces(pts) {
        line_on_cloth(p.pos.extend(z(p)), q.pos.extend(z(q)), c);
    }
}

/// The cue ball's trail, on the cloth.
pub fn trail(camera: &Camera, points: &[TrailPoint]) {
    in_world(camera, || {
        for w in points.windows(2) {
            let c = draw::trail_colour(w[1].strength);
            line_on_cloth(w[0].pos.extend(ON_CLOTH), w[1].pos.extend(ON_CLOTH), c);
        }
    });
}

/// A circle of radius `r` about `centre`, level, as lines.
fn circle(centre: DVec3, r: f64, c: Color) {
    let at = |k: usize| {
        let a = k as f64 / 40.0 * std::f64::consts::TAU;
        centre + DVec3::new(r * libm::cos(a), r * libm::sin(a), 0.0)
    };
    for k in 0..40 {
        line_on_cloth(at(k), at(k + 1), c);
    }
}

/// Aim line, ghost ball and predicted paths, as toggled.
pub fn aids(camera: &Camera, p: &Prediction, toggles: AidToggles, radius: f64, object_id: &str) {
    in_world(camera, || {
        if toggles.paths {
            path(&p.cue_path, radius, Color::new(1.0, 1.0, 1.0, 0.6));
            path(
                &p.object_path,
                radius,
                draw::with_alpha(ball_look(object_id).color, 1.0),
            );
        }
        if toggles.aim_line {
            path(&p.aim_path, radius, Color::new(1.0, 1.0, 1.0, 0.9));
        }
        if toggles.ghost_ball {
            if let Some(g) = p.ghost {
                let white = Color::new(1.0, 1.0, 1.0, 0.85);
                circle(g.extend(ON_CLOTH), radius, white);
                circle(g.extend(radius), radius, white);
            }
        }
    });
}

/// A ring on the cloth around the ball at `pos`.
pub fn ring(camera: &Camera, pos: DVec2, radius: f64, c: Color) {
    mark(camera, pos, 1.35 * radius, c);
}

/// A circle of `radius` about `centre` on the cloth.
pub fn mark(camera: &Camera, centre: DVec2, radius: f64, c: Color) {
    in_world(camera, || circle(centre.extend(ON_CLOTH), radius, c));
}

/// A straight line on the cloth.
pub fn segment(camera: &Camera, a: DVec2, b: DVec2, c: Color) {
    in_world(camera, || {
        line_on_cloth(a.extend(ON_CLOTH), b.extend(ON_CLOTH), c)
    });
}

/// The cue stick behind the cue ball along the aim, raised by its elevation, its tip `back`
/// metres behind the spot it strikes (negative: through it).
pub fn cue_stick(camera: &Camera, cue: DVec2, aim: &Aim, back: f64, radius: f64) {
    let elevation = aim.elevation_deg.to_radians();
    let (s, c) = (libm::sin(elevation), libm::cos(elevation));
    let d = aim.dir();
    // The way the cue moves: along the aim and down by its elevation.
    let along = DVec3::new(d.x * c, d.y * c, -s);
    let side = DVec3::new(-d.y, d.x, 0.0);
    let up = side.cross(along);
    let contact = cue.extend(radius) + radius * (side * aim.tip.x + up * aim.tip.y)
        - along * radius * (1.0 - aim.tip.length_squared()).max(0.0).sqrt();
    let tip = contact - along * back;
    let butt = tip - along * 1.45;
    in_world(camera, || {
        let mut m = Meshes::default();
        let ferrule = tip - along * 0.02;
        rod(&mut m, tip, ferrule, 0.0065, 0.0066, palette::CUE_FERRULE);
        rod(&mut m, ferrule, butt, 0.0066, 0.014, palette::CUE_WOOD);
        m.flush();
    });
}

/// A tapered rod from `a` (radius `ra`) to `b` (radius `rb`).
fn rod(m: &mut Meshes, a: DVec3, b: DVec3, ra: f64, rb: f64, c: Rgb) {
    let axis = (b - a).normalize_or_zero();
    let (u, w) = axis.any_orthonormal_pair();
    const SIDES: usize = 12;
    let base = m.room(2 * SIDES, 6 * SIDES);
    for k in 0..SIDES {
        let ang = k as f64 / SIDES as f64 * std::f64::consts::TAU;
        let n = u * libm::cos(ang) + w * libm::sin(ang);
        let colour = shade(c, lit(n), 255);
        m.vertex(a + n * ra, colour);
        m.vertex(b + n * rb, colour);
    }
    for k in 0..SIDES as u16 {
        let j = (k + 1) % SIDES as u16;
        let (a0, b0, a1, b1) = (
            base + 2 * k,
            base + 2 * k + 1,
            base + 2 * j,
            base + 2 * j + 1,
        );
        m.indices.extend([a0, a1, b1, a0, b1, b0]);
    }
}

/// The shaded area where the cue ball may be put (scene corners `lo`, `hi`), and the ball
/// being dragged with a ring saying whether it may go there.
pub fn in_hand(camera: &Camera, area: (DVec2, DVec2), dragged: Option<(DVec2, bool)>, radius: f64) {
    let (lo, hi) = area;
    let z = ON_CLOTH;
    let corners = [
        DVec3::new(lo.x, lo.y, z),
        DVec3::new(hi.x, lo.y, z),
        DVec3::new(hi.x, hi.y, z),
        DVec3::new(lo.x, hi.y, z),
    ];
    in_world(camera, || {
        let mut m = Meshes::default();
        m.polygon(&corners, [255, 255, 255], 20);
        m.flush();
        for k in 0..4 {
            line_on_cloth(
                corners[k],
                corners[(k + 1) % 4],
                Color::new(1.0, 1.0, 1.0, 0.5),
            );
        }
    });
    if let Some((at, legal)) = dragged {
        let ball = Ball {
            id: "cue",
            centre: at.extend(radius),
            turn: DQuat::IDENTITY,
        };
        balls(camera, &[ball], radius);
        let c = if legal {
            Color::new(0.2, 0.9, 0.3, 1.0)
        } else {
            Color::new(0.95, 0.15, 0.15, 1.0)
        };
        ring(camera, at, radius, c);
    }
}

/// The 3-D view: what lies on the table, seen through the view's camera.
impl Surface for Camera {
    fn table(&self, pen: &Pen, kind: TableKind) {
        table(self, pen.layout, kind);
        trail(self, &pen.trail);
    }

    fn balls(&self, pen: &Pen, shown: &BallsShown) {
        let mut drawn = on_table(shown);
        drawn.extend(pen.drops.iter().filter_map(|d| {
            Some(Ball {
                id: shown.ids.get(d.ball)?,
                centre: d.centre,
                turn: shown.turns.get(d.ball),
            })
        }));
        balls(self, &drawn, shown.radius);
    }

    fn aids(&self, _pen: &Pen, p: &Prediction, toggles: AidToggles, radius: f64, object_id: &str) {
        aids(self, p, toggles, radius, object_id);
    }

    fn ball_at(&self, _pen: &Pen, id: &str, pos: DVec2, radius: f64) {
        let ball = Ball {
            id,
            centre: pos.extend(radius),
            turn: DQuat::IDENTITY,
        };
        balls(self, &[ball], radius);
    }

    fn mark(&self, _pen: &Pen, centre: DVec2, radius: f64, _width: f32, c: Color) {
        mark(self, centre, 1.1 * radius, c);
    }

    fn ring(&self, _pen: &Pen, pos: DVec2, radius: f64, c: Color) {
        ring(self, pos, radius, c);
    }

    fn segment(&self, _pen: &Pen, a: DVec2, b: DVec2, _width: f32, c: Color) {
        segment(self, a, b, c);
    }

    fn cue_at(&self, _pen: &Pen, cue: DVec2, aim: &Aim, back: f64, radius: f64) {
        cue_stick(self, cue, aim, back, radius);
    }

    fn in_hand(
        &self,
        pen: &Pen,
        area: breakshot_client::view::Rect,
        dragged: Option<(DVec2, bool)>,
        radius: f64,
    ) {
        let layout = pen.layout;
        let (a, b) = (
            layout.to_scene([area.x, area.y]),
            layout.to_scene([area.x + area.w, area.y + area.h]),
        );
        // Opposite corners, whichever way the layout turns the table.
        in_hand(self, (a.min(b), a.max(b)), dragged, radius);
    }
}
