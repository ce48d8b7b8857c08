//! Two fingers on a touch screen: dragging together turns the 3-D camera, pinching brings it
//! nearer or takes it back, and a tap of both (down and up without moving) switches between
//! the top-down and the 3-D view, as V does. One finger is the mouse (macroquad turns it into
//! one), so it aims, pulls back for power and taps the tip and the elevation view as the
//! mouse does.

/// How far (pixels) two fingers may move, in all, and still be a tap.
const TAP_TRAVEL: f32 = 12.0;
/// How much two fingers may pinch, in all (the logarithm's size), and still be a tap.
const TAP_PINCH: f32 = 0.1;

/// What two fingers did since the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Gesture {
    /// How far the point between the fingers moved (pixels).
    pub moved: [f32; 2],
    /// The logarithm of how much further apart the fingers are (0: no pinch; positive:
    /// spread, so nearer).
    pub spread: f32,
}

/// Follows two fingers from frame to frame.
#[derive(Debug, Default)]
pub struct TwoFingers {
    last: Option<([f32; 2], [f32; 2])>,
    /// How far the fingers have moved and pinched since they came down.
    travel: f32,
    pinch: f32,
    /// The fingers lifted this frame after a tap.
    tapped: bool,
}

impl TwoFingers {
    /// The fingers on the screen this frame; a gesture while exactly two stay down.
    pub fn update(&mut self, fingers: &[[f32; 2]]) -> Option<Gesture> {
        self.tapped = false;
        let [a, b] = fingers else {
            if self.last.take().is_some() {
                self.tapped = self.travel < TAP_TRAVEL && self.pinch < TAP_PINCH;
            }
            (self.travel, self.pinch) = (0.0, 0.0);
            return None;
        };
        let gesture = self.last.map(|(la, lb)| {
            let mid = |p: [f32; 2], q: [f32; 2]| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
            let apart = |p: [f32; 2], q: [f32; 2]| (p[0] - q[0]).hypot(p[1] - q[1]).max(1.0);
            let (m, lm) = (mid(*a, *b), mid(la, lb));
            Gesture {
                moved: [m[0] - lm[0], m[1] - lm[1]],
                spread: (apart(*a, *b) / apart(la, lb)).ln(),
            }
        });
        if let Some(g) = gesture {
            self.travel += g.moved[0].hypot(g.moved[1]);
            self.pinch += g.spread.abs();
        }
        self.last = Some((*a, *b));
        gesture
    }

    /// Whether two fingers were lifted this frame without moving: a two-finger tap.
    pub fn tapped(&self) -> bool {
        self.tapped
    }

    /// Whether two (or more) fingers are down: the table is being looked at, not aimed.
    pub fn active(&self) -> bool {
        self.last.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_fingers_dragged_together_move_without_pinching() {
        let mut f = TwoFingers::default();
        assert_eq!(f.update(&[[100.0, 100.0], [200.0, 100.0]]), None);
        let g = f.update(&[[110.0, 90.0], [210.0, 90.0]]).unwrap();
        assert_eq!(g.moved, [10.0, -10.0]);
        assert!(g.spread.abs() < 1e-6);
        assert!(f.active());
    }

    #[test]
    fn spreading_the_fingers_is_a_positive_pinch_and_closing_them_negative() {
        let mut f = TwoFingers::default();
        f.update(&[[100.0, 100.0], [200.0, 100.0]]);
        let spread = f.update(&[[50.0, 100.0], [250.0, 100.0]]).unwrap();
        assert!((spread.spread - 2f32.ln()).abs() < 1e-6);
        assert_eq!(spread.moved, [0.0, 0.0]);
        let closed = f.update(&[[100.0, 100.0], [200.0, 100.0]]).unwrap();
        assert!(closed.spread < 0.0);
    }

    #[test]
    fn one_finger_or_three_are_no_gesture_and_lifting_one_starts_afresh() {
        let mut f = TwoFingers::default();
        assert_eq!(f.update(&[[1.0, 1.0]]), None);
        f.update(&[[0.0, 0.0], [10.0, 0.0]]);
        assert_eq!(f.update(&[[0.0, 0.0]]), None);
        assert!(!f.active());
        // The next two-finger frame is a new start, not a jump from the old fingers.
        assert_eq!(f.update(&[[500.0, 500.0], [600.0, 500.0]]), None);
        assert_eq!(f.update(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), None);
    }

    #[test]
    fn two_fingers_lifted_where_they_came_down_are_a_tap_and_moved_ones_are_not() {
        let mut f = TwoFingers::default();
        f.update(&[[100.0, 100.0], [200.0, 100.0]]);
        f.update(&[[102.0, 101.0], [201.0, 100.0]]);
        assert!(!f.tapped(), "not while they are down");
        f.update(&[[102.0, 101.0]]);
        assert!(f.tapped());
        f.update(&[]);
        assert!(!f.tapped(), "one frame only");
        // Dragged, or pinched: a gesture, not a tap.
        for far in [
            [[160.0, 100.0], [260.0, 100.0]],
            [[90.0, 100.0], [210.0, 100.0]],
        ] {
            f.update(&[[100.0, 100.0], [200.0, 100.0]]);
            f.update(&far);
            f.update(&[]);
            assert!(!f.tapped(), "{far:?}");
        }
        // One finger is the mouse, never a two-finger tap.
        f.update(&[[5.0, 5.0]]);
        f.update(&[]);
        assert!(!f.tapped());
    }

    #[test]
    fn fingers_on_one_spot_do_not_divide_by_zero() {
        let mut f = TwoFingers::default();
        f.update(&[[5.0, 5.0], [5.0, 5.0]]);
        let g = f.update(&[[5.0, 5.0], [5.0, 5.0]]).unwrap();
        assert!(g.spread.is_finite());
    }
}
