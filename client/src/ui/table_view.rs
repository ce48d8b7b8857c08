//! Which view of the table a screen shows, and the 3-D camera's place: V switches between the
//! top-down and the 3-D view (the choice is remembered for the next run and the next screen),
//! Q/E turn the camera about the cue ball, Home/End raise and lower it, Z/X bring it nearer or
//! take it back, and moving the mouse with the right button held turns it too. L shows or
//! hides the cue ball's trail in both views.

use std::path::PathBuf;
use std::sync::Mutex;

use ::glam::DVec2;
use breakshot_client::memory;
use breakshot_client::play::{InputFrame, Key};
use breakshot_client::view::{area, Camera, Layout, Orbit, Playback, Trail, ViewKind};
use breakshot_shared::physics::{Table, TableKind};

use super::draw::Pen;

/// Camera keys' rates: turning (rad/s), rising (rad/s) and zooming (factor per second).
const TURN_RATE: f64 = 1.4;
const RISE_RATE: f64 = 0.8;
const ZOOM_RATE: f64 = 2.5;
/// Radians the camera turns per pixel the mouse moves with the right button held.
const DRAG_TURN: f64 = 0.006;
/// How quickly the camera catches up with a new aim or cue ball (s).
const FOLLOW_TIME: f64 = 0.12;

/// The view chosen, shared by every screen, and where it is remembered.
static CHOICE: Mutex<(ViewKind, Option<PathBuf>)> = Mutex::new((ViewKind::TopDown, None));

/// Starts the run on `view`, remembering later choices in the data directory `data`.
pub fn start(view: ViewKind, data: Option<PathBuf>) {
    if let Ok(mut c) = CHOICE.lock() {
        *c = (view, data);
    }
}

fn chosen() -> ViewKind {
    CHOICE.lock().map_or(ViewKind::TopDown, |c| c.0)
}

fn choose(view: ViewKind) {
    let Ok(mut c) = CHOICE.lock() else { return };
    c.0 = view;
    if let Some(data) = &c.1 {
        if let Err(e) = memory::remember_view(data, view) {
            tracing::warn!(error = %e, "cannot remember the view");
        }
    }
}

/// One screen's view of the table.
pub struct TableView {
    orbit: Orbit,
    /// The cue ball and the aim the camera follows, as it has caught up with them.
    followed: Option<(DVec2, DVec2)>,
    last_mouse: Option<[f32; 2]>,
    /// The mouse last frame and where it pointed, for [`TableView::pointer`].
    pointed: Option<([f32; 2], [f32; 2])>,
    trail: Trail,
    show_trail: bool,
}

impl TableView {
    pub fn new() -> TableView {
        TableView {
            orbit: Orbit::default(),
            followed: None,
            last_mouse: None,
            pointed: None,
            trail: Trail::new(),
            show_trail: false,
        }
    }

    /// Reads the view keys and the camera's keys and mouse; `aiming` says whether the player
    /// sets up a shot with the cue ball at `cue` along `aim`, which the camera then follows
    /// (it stays put while the balls move).
    pub fn update(&mut self, input: &InputFrame, cue: DVec2, aim: DVec2, aiming: bool) {
        if input.pressed.contains(&Key::View) {
            choose(chosen().toggled());
        }
        if input.pressed.contains(&Key::Trail) {
            self.show_trail = !self.show_trail;
        }
        let dt = if input.dt.is_finite() {
            input.dt.clamp(0.0, 0.25)
        } else {
            0.0
        };
        let [turn, rise, near] = input.camera.map(f64::from);
        self.orbit
            .turn(turn * TURN_RATE * dt, rise * RISE_RATE * dt);
        self.orbit.zoom(libm::pow(ZOOM_RATE, -near * dt));
        if let (true, Some(last)) = (input.right_down, self.last_mouse) {
            let (dx, dy) = (input.mouse[0] - last[0], input.mouse[1] - last[1]);
            self.orbit
                .turn(-DRAG_TURN * dx as f64, DRAG_TURN * dy as f64);
        }
        if let Some(g) = input.fingers {
            self.orbit
                .turn(-DRAG_TURN * g.moved[0] as f64, DRAG_TURN * g.moved[1] as f64);
            self.orbit.zoom(f64::from(-g.spread).exp());
        }
        self.last_mouse = Some(input.mouse);
        self.followed = match self.followed {
            None => Some((cue, aim)),
            Some((c, a)) if aiming => {
                let k = 1.0 - libm::exp(-dt / FOLLOW_TIME);
                let a = a.lerp(aim, k);
                Some((c.lerp(cue, k), if a.length() > 1e-6 { a } else { aim }))
            }
            kept => kept,
        };
    }

    /// The 3-D camera, when the 3-D view is shown.
    pub fn camera(&self, layout: &Layout, radius: f64) -> Option<Camera> {
        let (cue, aim) = self.followed?;
        (chosen() == ViewKind::ThreeD).then(|| self.orbit.camera(layout, cue, aim, radius))
    }

    /// How to draw the table this frame: `shot` is the shot shown, if any, on a table of
    /// `kind`; the trail kept is the ball it struck.
    pub fn pen<'a>(
        &mut self,
        layout: &'a Layout,
        radius: f64,
        shot: Option<&Playback>,
        kind: TableKind,
    ) -> Pen<'a> {
        let cue = shot.map_or(0, Playback::cue);
        self.trail.follow(shot, cue);
        Pen {
            layout,
            camera: self.camera(layout, radius),
            drops: shot
                .map(|p| p.dropping(&Table::new(kind), radius))
                .unwrap_or_default(),
            stroke: shot.and_then(|p| p.stroke(cue)),
            trail: if self.show_trail {
                self.trail.points()
            } else {
                Vec::new()
            },
        }
    }

    /// `input` as the controls read it: in the 3-D view a mouse over the table area is moved
    /// to the layout's pixel of the spot it points at (off the table when it points at none),
    /// so aiming, pulling back, placing the cue ball and calling a pocket work as top-down.
    /// Over the panel it is left alone. A mouse that has not moved (or turns the camera with
    /// the right button) points where it pointed before: the camera follows the aim, and the
    /// aim must not chase the camera.
    pub fn pointer(&mut self, input: &InputFrame, layout: &Layout, radius: f64) -> InputFrame {
        let mut out = input.clone();
        if let Some(camera) = self.camera(layout, radius) {
            let still = self.pointed.filter(|(raw, _)| {
                input.right_down
                    || (*raw == input.mouse && !input.left_pressed && !input.left_released)
            });
            if let Some((_, at)) = still {
                out.mouse = at;
            } else if area(layout).contains(input.mouse) {
                out.mouse = camera
                    .layout_pixel(layout, input.mouse, radius)
                    .unwrap_or([-1.0, -1.0]);
            }
        }
        self.pointed = Some((input.mouse, out.mouse));
        out
    }
}
