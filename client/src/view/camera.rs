//! The 3-D view's camera, computed without a window: a perspective camera that follows the
//! aim from behind the cue ball, orbits and zooms, and rises to look straight down, where it
//! draws the table exactly as the top-down view does ([`Layout`]). The renderer draws with
//! [`Camera::matrix`] and the window tests and the mouse use the same camera, so a ball the
//! test looks for, or the spot the mouse points at, is where the renderer put it.
//!
//! Coordinates are the scene's: x across the table, y along it, z up, in metres.

use glam::{DMat4, DVec2, DVec3, DVec4};

use super::layout::{Layout, Rect};

/// Vertical field of view (radians).
pub(crate) const FOV_Y: f64 = 0.70;
/// The lowest the camera goes: this angle above the cloth (radians) as it looks at the cue ball.
pub(crate) const MIN_PITCH: f64 = 0.10;
/// Straight down.
pub(crate) const TOP_PITCH: f64 = std::f64::consts::FRAC_PI_2;
/// The camera's height angle when the 3-D view opens (radians).
pub(crate) const DEFAULT_PITCH: f64 = 0.32;
/// Distance from the cue ball when the 3-D view opens (m).
pub(crate) const DEFAULT_DISTANCE: f64 = 1.1;
/// The nearest and farthest the camera may be from the cue ball (m).
pub(crate) const DISTANCE_RANGE: (f64, f64) = (0.35, 3.5);
/// Where the cue ball sits in the 3-D area, as a fraction of its height from the top: low,
/// so the table ahead of the shot fills the view.
const CUE_AT: f64 = 0.68;
const NEAR: f64 = 0.02;
const FAR: f64 = 30.0;

/// A perspective camera over the whole window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    view_proj: DMat4,
    inverse: DMat4,
    eye: DVec3,
    screen: [f32; 2],
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` upwards on the screen, its field of
    /// view `fov_y` over the window's height, and `target` drawn at the pixel `centre` of a
    /// window of `screen` pixels.
    pub fn look(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y: f64,
        screen: [f32; 2],
        centre: [f32; 2],
    ) -> Camera {
        let (w, h) = (screen[0].max(1.0) as f64, screen[1].max(1.0) as f64);
        let view = DMat4::look_at_rh(eye, target, up);
        let proj = DMat4::perspective_rh_gl(fov_y, w / h, NEAR, FAR);
        // Moving the picture in normalised device coordinates puts the target off the
        // window's middle (an off-axis projection), beside the panel and under the HUD.
        let shift = DMat4::from_translation(DVec3::new(
            2.0 * centre[0] as f64 / w - 1.0,
            1.0 - 2.0 * centre[1] as f64 / h,
            0.0,
        ));
        let view_proj = shift * proj * view;
        Camera {
            view_proj,
            inverse: view_proj.inverse(),
            eye,
            screen,
        }
    }

    /// The top-down camera: the table at the layout's place and scale. Ball centres (a ball
    /// radius above the cloth) are drawn where [`Layout::to_screen`] puts them.
    pub fn top_down(layout: &Layout, radius: f64) -> Camera {
        let (target, height, centre) = top_down_frame(layout);
        let target = target.extend(radius);
        Camera::look(
            target + DVec3::Z * height,
            target,
            // The scene direction up the screen.
            if layout.turned() {
                DVec3::Y
            } else {
                DVec3::NEG_X
            },
            FOV_Y,
            layout.screen,
            centre,
        )
    }

    /// World to clip space, as the renderer draws.
    pub fn matrix(&self) -> DMat4 {
        self.view_proj
    }

    /// Where the camera is.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The pixel a point is drawn at, or None if it is behind the camera.
    pub fn project(&self, p: DVec3) -> Option<[f32; 2]> {
        let c = self.view_proj * p.extend(1.0);
        if c.w <= NEAR * 0.5 {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        Some([
            ((x + 1.0) * 0.5 * self.screen[0] as f64) as f32,
            ((1.0 - y) * 0.5 * self.screen[1] as f64) as f32,
        ])
    }

    /// How many pixels a length of `metres` at `p`, square to the view, is drawn as.
    pub fn pixels_at(&self, p: DVec3, metres: f64) -> f32 {
        let depth = (self.view_proj * p.extend(1.0)).w.max(NEAR);
        let f = 0.5 * self.screen[1] as f64 / libm::tan(0.5 * FOV_Y);
        (f * metres / depth) as f32
    }

    /// The point at height `z` under the pixel `px`, if the ray through it meets that plane in
    /// front of the camera.
    pub fn onto_plane(&self, px: [f32; 2], z: f64) -> Option<DVec2> {
        let x = 2.0 * px[0] as f64 / self.screen[0] as f64 - 1.0;
        let y = 1.0 - 2.0 * px[1] as f64 / self.screen[1] as f64;
        let unproject = |depth: f64| {
            let p: DVec4 = self.inverse * DVec4::new(x, y, depth, 1.0);
            p.truncate() / p.w
        };
        let (near, far) = (unproject(-1.0), unproject(1.0));
        let dir = far - near;
        if dir.z.abs() < 1e-12 {
            return None;
        }
        let s = (z - near.z) / dir.z;
        let hit = near + dir * s;
        (s >= 0.0 && hit.is_finite()).then(|| hit.truncate())
    }

    /// The pixel of the top-down layout that shows the spot on the table under `px` in this
    /// view (at the height of a ball's centre): the mouse in the 3-D view, given to controls
    /// that think in the layout's pixels. None where the pointer is not over the cloth plane.
    pub fn layout_pixel(&self, layout: &Layout, px: [f32; 2], radius: f64) -> Option<[f32; 2]> {
        self.onto_plane(px, radius).map(|p| layout.to_screen(p))
    }
}

/// The top-down view's look-at point on the cloth, its height above a ball's centre and the
/// pixel the look-at point is drawn at.
fn top_down_frame(layout: &Layout) -> (DVec2, f64, [f32; 2]) {
    let centre = layout.frame.min + 0.5 * layout.frame.size;
    let f = 0.5 * layout.screen[1] as f64 / libm::tan(0.5 * FOV_Y);
    (centre, f / layout.scale, layout.to_screen(centre))
}

/// The part of the window the 3-D view fills: the table's place, between the HUD and the
/// tray, left of the panel.
pub fn area(layout: &Layout) -> Rect {
    if layout.turned() {
        // A tall window: the panel is below the table, under the tray.
        return Rect::new(
            0.0,
            layout.hud.h,
            layout.screen[0],
            layout.tray.y - layout.hud.h,
        );
    }
    let right = (layout.elevation_view.x - 4.0).max(1.0);
    Rect::new(0.0, layout.hud.h, right, layout.tray.y - layout.hud.h)
}

/// The player's choice of where the camera is, relative to the shot: it turns with the aim.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Turned about the cue ball from straight behind the aim (radians, anticlockwise from
    /// above).
    pub around: f64,
    /// Height angle above the cloth (radians), `MIN_PITCH` to `TOP_PITCH`.
    pub pitch: f64,
    /// Distance from the cue ball (m).
    pub distance: f64,
}

impl Default for Orbit {
    fn default() -> Self {
        Orbit {
            around: 0.0,
            pitch: DEFAULT_PITCH,
            distance: DEFAULT_DISTANCE,
        }
    }
}

impl Orbit {
    /// Turns the camera about the cue ball by `around` and up by `up` (radians).
    pub fn turn(&mut self, around: f64, up: f64) {
        if around.is_finite() {
            self.around = (self.around + around).rem_euclid(std::f64::consts::TAU);
        }
        if up.is_finite() {
            self.pitch = (self.pitch + up).clamp(MIN_PITCH, TOP_PITCH);
        }
    }

    /// Moves the camera nearer (`factor` < 1) or farther.
    pub fn zoom(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(DISTANCE_RANGE.0, DISTANCE_RANGE.1);
        }
    }

    /// How far the camera has risen towards the top-down view: 0 low behind the cue ball,
    /// 1 straight down.
    pub fn rise(&self) -> f64 {
        let t = (self.pitch - MIN_PITCH) / (TOP_PITCH - MIN_PITCH);
        // The lower part of the climb keeps following the aim; the upper part swings round
        // to the table's own orientation, eased at both ends.
        let t = ((t - 0.4) / 0.6).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    /// The camera for a cue ball at `cue` (its centre on the cloth) aimed along `aim`. It
    /// always looks at the cue ball. Low, it looks along the aim (turned by `around`) with the
    /// cue ball low in the view; as it rises it turns to the layout's orientation and moves
    /// the cue ball to its place in the layout, which it reaches straight down: there it
    /// draws the table as [`Camera::top_down`] does (a plane seen square on is the same
    /// picture from any point above it, at the same scale).
    pub fn camera(&self, layout: &Layout, cue: DVec2, aim: DVec2, radius: f64) -> Camera {
        let s = self.rise();
        let a = area(layout);
        let low_centre = [a.x + 0.5 * a.w, a.y + CUE_AT as f32 * a.h];
        let (_, top_height, _) = top_down_frame(layout);
        let top_centre = layout.to_screen(cue);
        let aim = if aim.is_finite() && aim.length() > 1e-9 {
            aim.normalize()
        } else {
            DVec2::Y
        };
        let low_heading = libm::atan2(aim.y, aim.x) + self.around;
        // The top-down view looks along −x (up the screen).
        let top_heading = std::f64::consts::PI;
        let heading = low_heading + s * wrap(top_heading - low_heading);
        let target = cue.extend(radius);
        let distance = self.distance + s * (top_height - self.distance);
        let centre = [
            low_centre[0] + s as f32 * (top_centre[0] - low_centre[0]),
            low_centre[1] + s as f32 * (top_centre[1] - low_centre[1]),
        ];
        let ahead = DVec3::new(libm::cos(heading), libm::sin(heading), 0.0);
        let (sp, cp) = (libm::sin(self.pitch), libm::cos(self.pitch));
        let eye = target + distance * (DVec3::Z * sp - ahead * cp);
        let up = ahead * sp + DVec3::Z * cp;
        Camera::look(eye, target, up, FOV_Y, layout.screen, centre)
    }
}

/// An angle brought into −π..π.
fn wrap(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    (a + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI
}

/// Which view of the table the window shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ViewKind {
    /// Straight down, flat: the layout's view.
    #[default]
    TopDown,
    /// The perspective camera.
    ThreeD,
}

impl ViewKind {
    /// The name used on the command line and in the remembered file.
    pub fn name(self) -> &'static str {
        match self {
            ViewKind::TopDown => "top",
            ViewKind::ThreeD => "3d",
        }
    }

    /// The view called `name` ("top" or "3d").
    pub fn parse(name: &str) -> Option<ViewKind> {
        match name.trim() {
            "top" => Some(ViewKind::TopDown),
            "3d" => Some(ViewKind::ThreeD),
            _ => None,
        }
    }

    /// The other view.
    pub fn toggled(self) -> ViewKind {
        match self {
            ViewKind::TopDown => ViewKind::ThreeD,
            ViewKind::ThreeD => ViewKind::TopDown,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::{Aim, Context, Controls, CueMode, InputFrame};
    use crate::view::Frame;
    use breakshot_shared::physics::TableKind;

    const R: f64 = 0.028575;

    fn layout(w: f32, h: f32) -> Layout {
        Layout::new(w, h, Frame::new(TableKind::NineFoot, &[]))
    }

    fn spots() -> Vec<DVec2> {
        let mut v = Vec::new();
        for i in 0..=6 {
            for j in 0..=8 {
                v.push(DVec2::new(1.27 * i as f64 / 6.0, 2.54 * j as f64 / 8.0));
            }
        }
        v
    }

    #[test]
    fn the_top_down_camera_draws_ball_centres_where_the_layout_does() {
        for (w, h) in [
            (1280.0, 720.0),
            (1920.0, 1080.0),
            (800.0, 600.0),
            (390.0, 844.0),
        ] {
            let l = layout(w, h);
            let cam = Camera::top_down(&l, R);
            for p in spots() {
                let got = cam.project(p.extend(R)).expect("in front");
                let want = l.to_screen(p);
                let off = (got[0] - want[0]).hypot(got[1] - want[1]);
                assert!(off < 0.5, "{p} at {got:?}, layout {want:?} ({w}x{h})");
            }
            // A ball there is drawn the layout's size.
            let r = cam.pixels_at(DVec3::new(0.6, 1.2, R), R);
            assert!((r - l.px(R)).abs() < 0.05, "{r} vs {}", l.px(R));
        }
    }

    #[test]
    fn the_orbit_straight_down_is_the_top_down_camera() {
        let l = layout(1280.0, 720.0);
        let top = Orbit {
            around: 1.0,
            pitch: TOP_PITCH,
            distance: 0.5,
        };
        let cam = top.camera(&l, DVec2::new(0.3, 0.4), DVec2::new(1.0, 1.0), R);
        for p in spots() {
            let got = cam.project(p.extend(R)).expect("in front");
            let want = l.to_screen(p);
            assert!((got[0] - want[0]).hypot(got[1] - want[1]) < 1.0, "{p}");
        }
    }

    #[test]
    fn the_cue_ball_stays_in_view_however_the_camera_is_turned() {
        let l = layout(1280.0, 720.0);
        let a = area(&l);
        let aims = [DVec2::Y, DVec2::X, DVec2::new(-1.0, -0.3), DVec2::NEG_Y];
        for cue in spots() {
            for aim in aims {
                for k in 0..=10 {
                    for around in [0.0, 1.5, 3.0, 4.5] {
                        for distance in [DISTANCE_RANGE.0, 1.0, DISTANCE_RANGE.1] {
                            let orbit = Orbit {
                                around,
                                pitch: MIN_PITCH + (TOP_PITCH - MIN_PITCH) * k as f64 / 10.0,
                                distance,
                            };
                            let cam = orbit.camera(&l, cue, aim, R);
                            let p = cam.project(cue.extend(R)).expect("in front of the camera");
                            assert!(a.contains(p), "{cue} {aim} {orbit:?}: {p:?} outside {a:?}");
                            assert!(cam.eye().z > 2.0 * R, "the camera stays above the cloth");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn low_the_camera_looks_along_the_aim_from_behind_the_cue_ball() {
        let l = layout(1280.0, 720.0);
        let cue = DVec2::new(0.6, 0.8);
        let cam = Orbit::default().camera(&l, cue, DVec2::Y, R);
        assert!(cam.eye().y < cue.y, "behind: {}", cam.eye());
        assert!((cam.eye().x - cue.x).abs() < 1e-9);
        // Further along the aim is higher on the screen, and smaller.
        let near = cam.project(cue.extend(R)).expect("seen");
        let far = cam.project(DVec3::new(0.6, 1.8, R)).expect("seen");
        assert!(far[1] < near[1] && (far[0] - near[0]).abs() < 0.5);
        assert!(cam.pixels_at(DVec3::new(0.6, 1.8, R), R) < cam.pixels_at(cue.extend(R), R));
    }

    #[test]
    fn orbit_and_zoom_stay_in_their_ranges() {
        let mut o = Orbit::default();
        o.turn(0.0, 10.0);
        assert_eq!(o.pitch, TOP_PITCH);
        assert_eq!(o.rise(), 1.0);
        o.turn(-7.0, -10.0);
        assert_eq!(o.pitch, MIN_PITCH);
        assert_eq!(o.rise(), 0.0);
        assert!((0.0..std::f64::consts::TAU).contains(&o.around));
        o.zoom(100.0);
        assert_eq!(o.distance, DISTANCE_RANGE.1);
        o.zoom(0.0);
        o.zoom(f64::NAN);
        assert_eq!(o.distance, DISTANCE_RANGE.1);
        o.turn(f64::NAN, f64::INFINITY);
        assert_eq!(o.pitch, MIN_PITCH);
    }

    #[test]
    fn the_mouse_in_the_3d_view_finds_the_spot_it_points_at() {
        let l = layout(1280.0, 720.0);
        let orbit = Orbit {
            around: 0.4,
            ..Orbit::default()
        };
        let cam = orbit.camera(&l, DVec2::new(0.6, 0.8), DVec2::new(0.2, 1.0), R);
        for p in [
            DVec2::new(0.6, 1.5),
            DVec2::new(0.2, 2.2),
            DVec2::new(1.1, 1.0),
        ] {
            let px = cam.project(p.extend(R)).expect("seen");
            let back = cam.onto_plane(px, R).expect("on the plane");
            assert!((back - p).length() < 2e-3, "{p} -> {back}");
            let lp = cam.layout_pixel(&l, px, R).expect("on the plane");
            assert!((l.to_scene(lp) - p).length() < 2e-3);
        }
        // Above the horizon, the pointer is over no spot of the table.
        assert_eq!(cam.onto_plane([640.0, l.hud.h], R), None);
    }

    #[test]
    fn aiming_with_the_mouse_in_the_3d_view_points_the_cue_where_the_mouse_is() {
        let l = layout(1280.0, 720.0);
        let cue = DVec2::new(0.6, 0.8);
        let cam = Orbit::default().camera(&l, cue, DVec2::Y, R);
        let ctx = Context {
            layout: &l,
            cue,
            radius: R,
            cue_mode: CueMode::Aiming,
        };
        let target = DVec2::new(0.9, 1.9);
        let mut controls = Controls::new(Aim::default());
        for px in [[300.0, 300.0], cam.project(target.extend(R)).expect("seen")] {
            let input = InputFrame {
                mouse: cam.layout_pixel(&l, px, R).expect("over the table"),
                dt: 1.0 / 60.0,
                ..Default::default()
            };
            controls.update(&input, &ctx, &|_| true);
        }
        let want = (target - cue).normalize();
        assert!((controls.aim.dir() - want).length() < 2e-3);
    }

    #[test]
    fn view_names_read_back() {
        for v in [ViewKind::TopDown, ViewKind::ThreeD] {
            assert_eq!(ViewKind::parse(v.name()), Some(v));
            assert_eq!(v.toggled().toggled(), v);
        }
        assert_eq!(ViewKind::parse("side"), None);
    }
}
