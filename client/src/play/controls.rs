//! Mouse and keys to commands, without a window. The window reads its devices into an
//! [`InputFrame`] once per frame; [`Controls::update`] turns it into changes of the set-up
//! ([`Aim`]) and into [`Intent`]s, the commands a screen carries out or sends.

use breakshot_shared::physics::Strike;
use glam::DVec2;

use super::aim::{Aim, MAX_SHOT_SPEED};
use crate::view::aids::Aid;
use crate::view::Layout;

/// How much finer the aim turns while Shift is held.
pub(crate) const FINE_FACTOR: f64 = 0.1;
/// Arrow-key aim rate (radians per second), and with Shift.
pub(crate) const KEY_AIM_RATE: f64 = 0.35;
/// Arrow-key power rate while held (full scale per second).
pub(crate) const KEY_POWER_RATE: f64 = 0.5;
/// Cue speed one press of Up or Down adds or takes (m/s; a tenth with Shift): soft to a
/// break in about ten presses.
pub(crate) const KEY_SPEED_STEP: f64 = 1.0;
/// Cue elevation rate while its key is held (degrees per second; a tenth with Shift).
pub(crate) const KEY_ELEVATION_RATE: f64 = 30.0;
/// Power change per mouse-wheel notch.
pub(crate) const WHEEL_POWER_STEP: f64 = 0.02;
/// Pull-back distance (in ball radii) that gives full power.
pub(crate) const FULL_PULL_RADII: f64 = 14.0;
/// A pull-back weaker than this is a click, not a shot.
pub(crate) const MIN_PULL_POWER: f64 = 0.03;
/// How far (pixels) the pointer may move between press and release and still be a tap,
/// which aims at where it was: a finger moves no pointer before it lands.
const TAP_SLOP: f32 = 6.0;

/// Keys that do one thing when pressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// Take the shot (or skip the one playing).
    Shoot,
    /// Toggle the aim line.
    AimLine,
    /// Toggle the ghost ball.
    GhostBall,
    /// Toggle the predicted paths.
    Paths,
    /// Toggle the debug overlay.
    Debug,
    /// Pick the cue ball up (practice).
    BallInHand,
    /// Rack again.
    Rerack,
    /// Back to the menu.
    Back,
    /// Replays: next shot, previous shot, faster, slower.
    Next,
    /// Replays: the previous shot.
    Previous,
    /// Replays: faster.
    Faster,
    /// Replays: slower.
    Slower,
    /// Give up an online game (when asked whether to leave).
    Concede,
    /// Open the chat line (online games).
    Chat,
    /// Remove the last character typed.
    Erase,
    /// Send what was typed (Enter).
    Send,
    /// Power up one step (Up pressed).
    PowerUp,
    /// Power down one step (Down pressed).
    PowerDown,
    /// Keep the spin from shot to shot, or not.
    KeepSpin,
    /// Switch between the top-down and the 3-D view.
    View,
    /// Show or hide the cue ball's trail after a shot.
    Trail,
    /// Sound off or on again.
    Mute,
    /// Sound quieter.
    VolumeDown,
    /// Sound louder.
    VolumeUp,
    /// One of the tools of practice and games against the computer.
    Tool(Tool),
    /// Paste the clipboard into the line being typed (Ctrl+V).
    Paste,
}

impl Key {
    /// True for the keys a line being typed uses itself (every other key types a character
    /// into it, or nothing).
    pub fn edits_text(self) -> bool {
        matches!(self, Key::Erase | Key::Send | Key::Back | Key::Paste)
    }
}

/// One frame of input, read from the devices by the window.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputFrame {
    /// Mouse position (pixels).
    pub mouse: [f32; 2],
    /// The left button went down this frame.
    pub left_pressed: bool,
    /// The left button is held.
    pub left_down: bool,
    /// The left button went up this frame.
    pub left_released: bool,
    /// The right button is held: moving the mouse turns the 3-D camera.
    pub right_down: bool,
    /// Held camera keys, each −1, 0 or 1: turn about the cue ball (Q/E), rise or sink
    /// (Home/End), come nearer or go back (Z/X).
    pub camera: [f32; 3],
    /// Wheel notches this frame (up is positive).
    pub wheel: f32,
    /// Two fingers on a touch screen this frame, if any: they turn and pinch the 3-D camera.
    pub fingers: Option<super::Gesture>,
    /// Shift is held (fine aim).
    pub shift: bool,
    /// The left arrow is held.
    pub left_key: bool,
    /// The right arrow is held.
    pub right_key: bool,
    /// The up arrow is held.
    pub up_key: bool,
    /// The down arrow is held.
    pub down_key: bool,
    /// The key that raises the cue's butt (more elevation) is held.
    pub raise_key: bool,
    /// The key that lowers the cue towards level is held.
    pub lower_key: bool,
    /// Keys pressed this frame.
    pub pressed: Vec<Key>,
    /// Printable characters typed this frame, for the chat line.
    pub typed: Vec<char>,
    /// The contents of files dropped on the window this frame.
    pub dropped: Vec<Vec<u8>>,
    /// Seconds since the last frame.
    pub dt: f64,
}

impl InputFrame {
    /// The frame as the window hands it on while a line of text is being typed: the line
    /// takes the keys, so only the characters and the line's own keys are left.
    pub fn while_typing(mut self) -> InputFrame {
        self.pressed.retain(|k| k.edits_text());
        self
    }
}

/// What the controls may do with the cue ball now (a [`Prompt`](super::Prompt) as the mouse
/// sees it, or practice's own placing mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CueMode {
    /// Balls are moving or it is not our turn: only toggles.
    Watching,
    /// The cue ball can be struck.
    Aiming,
    /// The cue ball can be struck or moved.
    InHand,
}

/// What the controls need to know about the table.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    /// Where things are on the screen.
    pub layout: &'a Layout,
    /// The cue ball's centre (scene coordinates).
    pub cue: DVec2,
    /// The ball radius (m).
    pub radius: f64,
    /// What the controls may do with the cue ball now.
    pub cue_mode: CueMode,
}

/// A command from the player.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Intent {
    /// Take this shot.
    Shoot(Strike),
    /// Put the cue ball here.
    PlaceCueBall([f64; 2]),
    /// Toggle an aiming aid.
    Toggle(Aid),
    /// Toggle the debug overlay.
    ToggleDebug,
    /// Pick the cue ball up.
    TakeBallInHand,
    /// Rack again.
    Rerack,
    /// Back to the menu.
    Back,
    /// Use a tool of practice or of a game against the computer.
    Tool(Tool),
}

/// What practice and games against the computer offer beside the shot: a key each, and the
/// same command whether the key or a button asked for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Take the last shot back.
    Undo,
    /// Play again a shot taken back.
    Redo,
    /// Set up the last shot again: its position and its cue.
    Again,
    /// Ask the computer which shot it would play here.
    Advice,
    /// Set the cue to the shot advised.
    PlayAdvice,
    /// Keep the position: a scene file and a code (practice).
    SavePosition,
    /// Start or stop setting up the position: drag any ball, take balls off and put them
    /// back (practice).
    Arrange,
}

/// What the left button is doing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drag {
    /// Nothing.
    None,
    /// Setting the tip on the cue-ball face.
    Tip,
    /// Setting the power on the bar.
    Power,
    /// Pulling the cue back from where the button went down (pixels).
    PullBack {
        /// Where the button went down (pixels).
        from: [f32; 2],
    },
    /// Moving the cue ball in hand; `at` is where it would go.
    CueBall {
        /// Where the ball would go (m).
        at: DVec2,
    },
    /// Setting the cue elevation in the side view.
    Elevation,
}

/// The set-up and the state of a drag, kept across frames.
#[derive(Clone, Debug)]
pub struct Controls {
    /// The shot being set up.
    pub aim: Aim,
    /// What the left button is doing.
    pub drag: Drag,
    /// Keep the tip offset from shot to shot (K toggles); by default it goes back to the
    /// centre after each shot, as a player's stroke does.
    pub keep_spin: bool,
    last_mouse: Option<[f32; 2]>,
}

impl Controls {
    /// Controls starting from `aim`.
    pub fn new(aim: Aim) -> Controls {
        Controls {
            aim,
            drag: Drag::None,
            keep_spin: false,
            last_mouse: None,
        }
    }

    /// A shot was played from this set-up: the tip goes back to the centre unless the spin
    /// is kept.
    pub fn shot_played(&mut self) {
        if !self.keep_spin {
            self.aim.set_tip(DVec2::ZERO);
        }
    }

    /// Applies one frame of input. `legal` says whether the cue ball may be put at a spot.
    pub fn update(
        &mut self,
        input: &InputFrame,
        ctx: &Context,
        legal: &dyn Fn(DVec2) -> bool,
    ) -> Vec<Intent> {
        let mut out = Vec::new();
        for key in &input.pressed {
            match key {
                Key::AimLine => out.push(Intent::Toggle(Aid::AimLine)),
                Key::GhostBall => out.push(Intent::Toggle(Aid::GhostBall)),
                Key::Paths => out.push(Intent::Toggle(Aid::Paths)),
                Key::Debug => out.push(Intent::ToggleDebug),
                Key::BallInHand => out.push(Intent::TakeBallInHand),
                Key::Rerack => out.push(Intent::Rerack),
                Key::Back => out.push(Intent::Back),
                Key::Tool(tool) => out.push(Intent::Tool(*tool)),
                Key::KeepSpin => self.keep_spin = !self.keep_spin,
                Key::Shoot
                | Key::Next
                | Key::Previous
                | Key::Faster
                | Key::Slower
                | Key::Concede
                | Key::Chat
                | Key::Erase
                | Key::Send
                | Key::Paste
                | Key::PowerUp
                | Key::PowerDown
                | Key::View
                | Key::Trail
                | Key::Mute
                | Key::VolumeDown
                | Key::VolumeUp => {}
            }
        }
        if ctx.cue_mode == CueMode::Watching {
            self.drag = Drag::None;
            self.last_mouse = Some(input.mouse);
            return out;
        }
        self.keys(input);
        self.mouse(input, ctx, legal, &mut out);
        if input.pressed.contains(&Key::Shoot) && self.drag == Drag::None && self.aim.power > 0.0 {
            out.push(Intent::Shoot(self.aim.strike()));
        }
        self.last_mouse = Some(input.mouse);
        out
    }

    fn keys(&mut self, input: &InputFrame) {
        let dt = if input.dt.is_finite() {
            input.dt.clamp(0.0, 0.25)
        } else {
            0.0
        };
        let rate = KEY_AIM_RATE * if input.shift { FINE_FACTOR } else { 1.0 };
        let turn = (input.right_key as i32 - input.left_key as i32) as f64;
        self.aim.rotate(turn * rate * dt);
        let push = (input.up_key as i32 - input.down_key as i32) as f64;
        let fine = if input.shift { FINE_FACTOR } else { 1.0 };
        let steps = input
            .pressed
            .iter()
            .map(|k| match k {
                Key::PowerUp => 1.0,
                Key::PowerDown => -1.0,
                _ => 0.0,
            })
            .sum::<f64>();
        let step = steps * KEY_SPEED_STEP * fine / MAX_SHOT_SPEED;
        let mut power = self.aim.power + step + push * KEY_POWER_RATE * dt;
        if input.wheel.is_finite() {
            power += input.wheel as f64 * WHEEL_POWER_STEP;
        }
        self.aim.set_power(power);
        let lift = (input.raise_key as i32 - input.lower_key as i32) as f64;
        self.aim
            .set_elevation(self.aim.elevation_deg + lift * KEY_ELEVATION_RATE * fine * dt);
    }

    fn mouse(
        &mut self,
        input: &InputFrame,
        ctx: &Context,
        legal: &dyn Fn(DVec2) -> bool,
        out: &mut Vec<Intent>,
    ) {
        let layout = ctx.layout;
        let at = layout.to_scene(input.mouse);
        if input.left_pressed {
            self.drag = if dist(input.mouse, layout.tip_center) <= layout.tip_radius {
                Drag::Tip
            } else if layout.power_bar.contains(input.mouse) {
                Drag::Power
            } else if layout.elevation_view.contains(input.mouse) {
                Drag::Elevation
            } else if ctx.cue_mode == CueMode::InHand && (at - ctx.cue).length() <= 1.5 * ctx.radius
            {
                Drag::CueBall { at }
            } else if layout.outer.contains(input.mouse) {
                Drag::PullBack { from: input.mouse }
            } else {
                Drag::None
            };
        }
        match self.drag {
            // A click (pressed and released within one frame) counts as much as a drag.
            Drag::Tip if input.left_down || input.left_pressed => {
                let d = [
                    input.mouse[0] - layout.tip_center[0],
                    input.mouse[1] - layout.tip_center[1],
                ];
                // The widget is the ball's face as the shooter sees it: up is top spin.
                let r = layout.tip_radius as f64;
                self.aim
                    .set_tip(DVec2::new(d[0] as f64 / r, -(d[1] as f64) / r));
            }
            Drag::Elevation if input.left_down || input.left_pressed => {
                self.aim.set_elevation(layout.elevation_at(input.mouse));
            }
            Drag::Power if input.left_down || input.left_pressed => {
                let bar = layout.power_bar;
                let frac = (bar.y + bar.h - input.mouse[1]) / bar.h;
                self.aim.set_power(frac as f64);
            }
            Drag::CueBall { .. } if input.left_down => {
                self.drag = Drag::CueBall { at };
            }
            Drag::CueBall { .. } => {
                // Released: put the ball down if the spot is legal, otherwise refuse.
                if at.is_finite() && legal(at) {
                    out.push(Intent::PlaceCueBall([at.x, at.y]));
                }
                self.drag = Drag::None;
            }
            Drag::PullBack { from } => {
                let pulled = pull_power(layout, &self.aim, from, input.mouse, ctx.radius);
                self.aim.set_power(pulled.max(0.0));
                if !input.left_down {
                    self.drag = Drag::None;
                    if pulled >= MIN_PULL_POWER {
                        out.push(Intent::Shoot(self.aim.strike()));
                    } else if dist(from, input.mouse) <= TAP_SLOP
                        && !input.shift
                        && at.is_finite()
                        && (at - ctx.cue).length() > ctx.radius
                    {
                        // A tap (or a click) on the table aims at it; Shift's fine aim stays.
                        self.aim.point_along(at - ctx.cue);
                    }
                }
            }
            Drag::Tip | Drag::Power | Drag::Elevation => self.drag = Drag::None,
            Drag::None => self.follow_mouse(input, ctx, at),
        }
    }

    /// With no button held the cue points at the mouse; with Shift it turns a tenth as far.
    /// A mouse that has not moved leaves the aim alone, so the arrow keys can set it.
    fn follow_mouse(&mut self, input: &InputFrame, ctx: &Context, at: DVec2) {
        let Some(last) = self.last_mouse else { return };
        if last == input.mouse || !ctx.layout.outer.contains(input.mouse) || !at.is_finite() {
            return;
        }
        if input.shift {
            let before = ctx.layout.to_scene(last) - ctx.cue;
            let now = at - ctx.cue;
            let turned = libm::atan2(before.perp_dot(now), before.dot(now));
            if turned.is_finite() {
                self.aim.rotate(FINE_FACTOR * turned);
            }
        } else {
            self.aim.point_along(at - ctx.cue);
        }
    }
}

/// Power of a pull-back from `from` to `to` (pixels): how far the mouse moved back against
/// the aim, with full power at [`FULL_PULL_RADII`] ball radii.
pub(crate) fn pull_power(
    layout: &Layout,
    aim: &Aim,
    from: [f32; 2],
    to: [f32; 2],
    radius: f64,
) -> f64 {
    let back = layout.to_scene(from) - layout.to_scene(to);
    (back.dot(aim.dir()) / (FULL_PULL_RADII * radius)).min(1.0)
}

fn dist(a: [f32; 2], b: [f32; 2]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_being_typed_takes_the_keys_and_leaves_the_characters() {
        let typed = InputFrame {
            pressed: vec![
                Key::Mute,
                Key::VolumeDown,
                Key::VolumeUp,
                Key::Erase,
                Key::Send,
                Key::View,
                Key::Paste,
            ],
            typed: vec!['m', '[', ']'],
            ..InputFrame::default()
        }
        .while_typing();
        assert_eq!(typed.pressed, [Key::Erase, Key::Send, Key::Paste]);
        assert_eq!(typed.typed, ['m', '[', ']']);
    }
    use crate::view::Frame;
    use breakshot_shared::physics::TableKind;

    const R: f64 = 0.028575;

    fn layout() -> Layout {
        Layout::new(1280.0, 720.0, Frame::new(TableKind::NineFoot, &[]))
    }

    fn ctx(layout: &Layout, cue_mode: CueMode) -> Context<'_> {
        Context {
            layout,
            cue: DVec2::new(0.635, 0.6),
            radius: R,
            cue_mode,
        }
    }

    fn frame(mouse: [f32; 2]) -> InputFrame {
        InputFrame {
            mouse,
            dt: 1.0 / 60.0,
            ..Default::default()
        }
    }

    /// The frame in which the left button goes down at `mouse`.
    fn press(mouse: [f32; 2]) -> InputFrame {
        InputFrame {
            left_pressed: true,
            left_down: true,
            ..frame(mouse)
        }
    }

    /// The frame in which the left button comes up at `mouse`.
    fn release(mouse: [f32; 2]) -> InputFrame {
        InputFrame {
            left_released: true,
            ..frame(mouse)
        }
    }

    fn anywhere(_: DVec2) -> bool {
        true
    }

    #[test]
    fn the_cue_points_at_the_mouse() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        let target = DVec2::new(1.0, 1.5);
        // The first frame only learns where the mouse is; a mouse that stays put does not aim.
        c.update(
            &frame(l.to_screen(target)),
            &ctx(&l, CueMode::Aiming),
            &anywhere,
        );
        assert_eq!(c.aim, Aim::default());
        c.update(&frame([300.0, 300.0]), &ctx(&l, CueMode::Aiming), &anywhere);
        let out = c.update(
            &frame(l.to_screen(target)),
            &ctx(&l, CueMode::Aiming),
            &anywhere,
        );
        assert!(out.is_empty());
        let want = (target - DVec2::new(0.635, 0.6)).normalize();
        assert!((c.aim.dir() - want).length() < 1e-3, "{:?}", c.aim.dir());
    }

    #[test]
    fn shift_turns_the_aim_a_tenth_as_far() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let cue = cx.cue;
        let mut c = Controls::new(Aim::default());
        c.update(
            &frame(l.to_screen(cue + DVec2::new(0.0, 1.0))),
            &cx,
            &anywhere,
        );
        let before = c.aim.angle;
        let mut f = frame(l.to_screen(cue + DVec2::new(0.5, 0.5)));
        f.shift = true;
        c.update(&f, &cx, &anywhere);
        // The mouse swept 45 degrees about the cue ball; the aim turns 4.5.
        let turned = c.aim.angle - before;
        assert!(
            (turned + 0.1 * std::f64::consts::FRAC_PI_4).abs() < 2e-3,
            "{turned}"
        );
    }

    #[test]
    fn arrow_keys_turn_and_set_power_and_the_wheel_adds_power() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        let outside = [1.0, 1.0];
        let mut f = frame(outside);
        f.right_key = true;
        f.up_key = true;
        f.dt = 0.2;
        let (a0, p0) = (c.aim.angle, c.aim.power);
        c.update(&f, &ctx(&l, CueMode::Aiming), &anywhere);
        assert!((c.aim.angle - a0 - 0.2 * KEY_AIM_RATE).abs() < 1e-12);
        assert!((c.aim.power - p0 - 0.2 * KEY_POWER_RATE).abs() < 1e-12);
        let mut w = frame(outside);
        w.wheel = -2.0;
        let p1 = c.aim.power;
        c.update(&w, &ctx(&l, CueMode::Aiming), &anywhere);
        assert!((c.aim.power - (p1 - 2.0 * WHEEL_POWER_STEP)).abs() < 1e-6);
    }

    #[test]
    fn elevation_keys_raise_and_lower_the_cue_within_its_range() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let mut raise = frame([1.0, 1.0]);
        raise.raise_key = true;
        raise.dt = 0.2;
        c.update(&raise, &cx, &anywhere);
        assert!((c.aim.elevation_deg - 0.2 * KEY_ELEVATION_RATE).abs() < 1e-12);
        // Shift: a tenth as fast.
        raise.shift = true;
        c.update(&raise, &cx, &anywhere);
        let want = 0.2 * KEY_ELEVATION_RATE * (1.0 + FINE_FACTOR);
        assert!((c.aim.elevation_deg - want).abs() < 1e-12);
        // Held long enough, the cue stops straight down, then comes back to level.
        raise.shift = false;
        raise.dt = 0.25;
        for _ in 0..40 {
            c.update(&raise, &cx, &anywhere);
        }
        assert_eq!(c.aim.elevation_deg, 90.0);
        let mut lower = frame([1.0, 1.0]);
        lower.lower_key = true;
        lower.dt = 0.25;
        for _ in 0..40 {
            c.update(&lower, &cx, &anywhere);
        }
        assert_eq!(c.aim.elevation_deg, 0.0);
        // Not while watching.
        raise.dt = 0.2;
        c.update(&raise, &ctx(&l, CueMode::Watching), &anywhere);
        assert_eq!(c.aim.elevation_deg, 0.0);
    }

    #[test]
    fn dragging_in_the_side_view_sets_the_elevation_and_the_shot_carries_it() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let (_, butt) = l.elevation_cue(40.0);
        let down = press(butt);
        c.update(&down, &cx, &anywhere);
        assert_eq!(c.drag, Drag::Elevation);
        assert!(
            (c.aim.elevation_deg - 40.0).abs() < 0.5,
            "{}",
            c.aim.elevation_deg
        );
        // Dragging on outside the view keeps setting it (to straight down, in front).
        let [bx, by] = l.elevation_ball;
        let mut hold = frame([bx + 30.0, by - 30.0]);
        hold.left_down = true;
        c.update(&hold, &cx, &anywhere);
        assert_eq!(c.aim.elevation_deg, 90.0);
        let up = release([bx + 30.0, by - 30.0]);
        assert!(c.update(&up, &cx, &anywhere).is_empty());
        assert_eq!(c.drag, Drag::None);
        let mut f = frame([1.0, 1.0]);
        f.pressed = vec![Key::Shoot];
        let out = c.update(&f, &cx, &anywhere);
        let [Intent::Shoot(strike)] = out[..] else {
            panic!("{out:?}")
        };
        assert_eq!(strike.elevation_deg, 90.0);
    }

    #[test]
    fn space_shoots_the_set_up_only_when_allowed() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        let mut f = frame([1.0, 1.0]);
        f.pressed = vec![Key::Shoot];
        let out = c.update(&f, &ctx(&l, CueMode::Aiming), &anywhere);
        assert_eq!(out, vec![Intent::Shoot(c.aim.strike())]);
        assert!(c
            .update(&f, &ctx(&l, CueMode::Watching), &anywhere)
            .is_empty());
    }

    #[test]
    fn a_press_of_up_or_down_steps_the_speed_and_soft_to_break_takes_ten() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        assert_eq!(c.aim.speed(), 1.5);
        let mut f = frame([1.0, 1.0]);
        f.pressed = vec![Key::PowerUp];
        f.up_key = true;
        f.dt = 0.0;
        for _ in 0..10 {
            c.update(&f, &ctx(&l, CueMode::Aiming), &anywhere);
        }
        assert!((c.aim.speed() - 11.5).abs() < 1e-9, "{}", c.aim.speed());
        f.pressed = vec![Key::PowerDown];
        f.up_key = false;
        f.shift = true;
        c.update(&f, &ctx(&l, CueMode::Aiming), &anywhere);
        assert!((c.aim.speed() - 11.4).abs() < 1e-9, "{}", c.aim.speed());
    }

    #[test]
    fn the_spin_goes_back_to_the_centre_after_a_shot_unless_it_is_kept() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        c.aim.set_tip(DVec2::new(0.2, -0.3));
        c.shot_played();
        assert_eq!(c.aim.tip, DVec2::ZERO);
        let mut f = frame([1.0, 1.0]);
        f.pressed = vec![Key::KeepSpin];
        c.update(&f, &ctx(&l, CueMode::Watching), &anywhere);
        assert!(c.keep_spin);
        c.aim.set_tip(DVec2::new(0.2, -0.3));
        c.shot_played();
        assert_eq!(c.aim.tip, DVec2::new(0.2, -0.3));
    }

    #[test]
    fn a_click_on_the_power_bar_sets_the_power_even_if_released_at_once() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        let bar = l.power_bar;
        let mut f = frame([bar.x + 0.5 * bar.w, bar.y + 0.5 * bar.h]);
        f.left_pressed = true;
        f.left_released = true;
        c.update(&f, &ctx(&l, CueMode::Aiming), &anywhere);
        assert!((c.aim.speed() - 0.5 * MAX_SHOT_SPEED).abs() < 0.05);
        assert_eq!(c.drag, Drag::Power);
        c.update(&frame(f.mouse), &ctx(&l, CueMode::Aiming), &anywhere);
        assert_eq!(c.drag, Drag::None);
    }

    #[test]
    fn power_bar_and_tip_widget_set_power_and_tip() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let bar = l.power_bar;
        let f = press([bar.x + 0.5 * bar.w, bar.y + 0.25 * bar.h]);
        c.update(&f, &cx, &anywhere);
        assert!((c.aim.power - 0.75).abs() < 1e-3);

        // Top right of the face, far past the miscue limit: clamped onto it.
        let t = press([
            l.tip_center[0] + 0.6 * l.tip_radius,
            l.tip_center[1] - 0.6 * l.tip_radius,
        ]);
        c.update(&t, &cx, &anywhere);
        assert!((c.aim.tip.length() - 0.5).abs() < 1e-9);
        assert!(c.aim.tip.x > 0.0 && c.aim.tip.y > 0.0);
        let up = release(t.mouse);
        assert!(c.update(&up, &cx, &anywhere).is_empty());
        assert_eq!(c.drag, Drag::None);
    }

    #[test]
    fn pulling_back_and_releasing_shoots_along_the_locked_aim() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let ahead = cx.cue + DVec2::new(0.3, 0.5);
        c.update(&frame([300.0, 300.0]), &cx, &anywhere);
        c.update(&frame(l.to_screen(ahead)), &cx, &anywhere);
        assert!(c.aim.angle != Aim::default().angle);
        let dir = c.aim.dir();
        let down = press(l.to_screen(ahead));
        c.update(&down, &cx, &anywhere);
        // Pull back half of full power's distance (moving the mouse does not re-aim).
        let back = ahead - dir * 0.5 * FULL_PULL_RADII * R + dir.perp() * 0.2;
        let mut hold = frame(l.to_screen(back));
        hold.left_down = true;
        assert!(c.update(&hold, &cx, &anywhere).is_empty());
        assert!((c.aim.power - 0.5).abs() < 0.02, "{}", c.aim.power);
        let up = release(l.to_screen(back));
        let out = c.update(&up, &cx, &anywhere);
        assert_eq!(out.len(), 1);
        let Intent::Shoot(s) = out[0] else {
            panic!("{out:?}")
        };
        assert!((s.dir - dir).length() < 1e-12);
    }

    #[test]
    fn a_tap_on_the_table_aims_where_it_lands_in_a_wide_and_a_tall_window() {
        let tall = Layout::new(390.0, 844.0, Frame::new(TableKind::NineFoot, &[]));
        for l in [layout(), tall] {
            let cx = ctx(&l, CueMode::Aiming);
            let mut c = Controls::new(Aim::default());
            let target = cx.cue + DVec2::new(0.4, 0.9);
            // A finger lands there at once: no movement before the press.
            let down = press(l.to_screen(target));
            c.update(&down, &cx, &anywhere);
            let up = release(l.to_screen(target));
            assert!(c.update(&up, &cx, &anywhere).is_empty());
            let want = (target - cx.cue).normalize();
            assert!(
                (c.aim.dir() - want).length() < 1e-2,
                "{} {want}",
                c.aim.dir()
            );
        }
    }

    #[test]
    fn a_click_without_pulling_back_does_not_shoot() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let p = l.to_screen(cx.cue + DVec2::new(0.0, 0.5));
        let down = press(p);
        c.update(&down, &cx, &anywhere);
        let up = release(p);
        assert!(c.update(&up, &cx, &anywhere).is_empty());
    }

    #[test]
    fn cue_ball_in_hand_is_dragged_and_illegal_spots_are_refused() {
        let l = layout();
        let cx = ctx(&l, CueMode::InHand);
        let legal = |p: DVec2| p.y < 0.635;
        for (target, placed) in [(DVec2::new(0.4, 0.5), true), (DVec2::new(0.4, 1.5), false)] {
            let mut c = Controls::new(Aim::default());
            let down = press(l.to_screen(cx.cue));
            c.update(&down, &cx, &legal);
            let mut mv = frame(l.to_screen(target));
            mv.left_down = true;
            c.update(&mv, &cx, &legal);
            assert!(matches!(c.drag, Drag::CueBall { at } if (at - target).length() < 1e-2));
            let up = release(l.to_screen(target));
            let out = c.update(&up, &cx, &legal);
            match out.as_slice() {
                [Intent::PlaceCueBall(p)] => {
                    assert!(placed && (DVec2::from_array(*p) - target).length() < 1e-2)
                }
                [] => assert!(!placed),
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn the_cue_ball_cannot_be_dragged_unless_in_hand() {
        let l = layout();
        let cx = ctx(&l, CueMode::Aiming);
        let mut c = Controls::new(Aim::default());
        let down = press(l.to_screen(cx.cue));
        c.update(&down, &cx, &anywhere);
        assert!(matches!(c.drag, Drag::PullBack { .. }));
    }

    #[test]
    fn keys_map_to_toggles_whatever_the_cue_mode() {
        let l = layout();
        let mut c = Controls::new(Aim::default());
        let mut f = frame([0.0, 0.0]);
        f.pressed = vec![Key::AimLine, Key::Debug, Key::Back];
        let out = c.update(&f, &ctx(&l, CueMode::Watching), &anywhere);
        assert_eq!(
            out,
            vec![
                Intent::Toggle(Aid::AimLine),
                Intent::ToggleDebug,
                Intent::Back
            ]
        );
    }
}
