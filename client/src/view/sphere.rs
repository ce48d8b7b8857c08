//! A ball as a shaded sphere seen from above, computed without a window: a fan of rings over
//! the disc, each point coloured by what of the ball (number spot, stripe, plain) faces the
//! viewer there for the ball's orientation, and lit from the upper left. A ball's own frame
//! has its number spots on ±z and its stripe around the x axis (across the screen when unturned).

use glam::{DQuat, DVec3};

use super::palette::{self, BallLook, Rgb};

/// Rings of the fan: with [`SECTORS`], fine enough that a spot's edge stays smooth on a big
/// window.
pub(crate) const RINGS: usize = 14;
/// Points on each ring.
pub(crate) const SECTORS: usize = 48;
/// Angular radius of a number spot: cos of the half-angle it covers.
const SPOT_COS: f64 = 0.9;
/// Half-width of a stripe, as the sine of the latitude it reaches.
const STRIPE_HALF: f64 = 0.55;
/// Angular size of the cue ball's marker dots (cos).
const DOT_COS: f64 = 0.985;
/// Where the light comes from, in screen terms (right, down, towards the viewer).
const LIGHT: [f64; 3] = [-0.4, -0.55, 0.73];
const AMBIENT: f64 = 0.38;

/// How scene directions lie on the screen: the pixel directions of the scene's x and y axes
/// (unit length). Top-down, the scene's z points at the viewer.
#[derive(Clone, Copy, Debug)]
pub struct ScreenAxes {
    /// The scene's x axis on the screen.
    pub x: [f64; 2],
    /// The scene's y axis on the screen.
    pub y: [f64; 2],
}

impl ScreenAxes {
    /// The scene direction under a screen offset (u right, v down) on a unit sphere facing the
    /// viewer, with `w` towards the viewer.
    fn to_scene(self, u: f64, v: f64, w: f64) -> DVec3 {
        // Solve u,v = a·x + b·y for a, b.
        let det = self.x[0] * self.y[1] - self.y[0] * self.x[1];
        let a = (u * self.y[1] - v * self.y[0]) / det;
        let b = (self.x[0] * v - self.x[1] * u) / det;
        DVec3::new(a, b, w)
    }

    /// A scene direction as a screen offset.
    pub fn to_screen(self, d: DVec3) -> [f64; 2] {
        [
            d.x * self.x[0] + d.y * self.y[0],
            d.x * self.x[1] + d.y * self.y[1],
        ]
    }
}

/// One point of the fan: offset from the centre in ball radii, and colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Offset from the ball's centre (right, down) in ball radii.
    pub at: [f32; 2],
    /// Colour, lit.
    pub rgba: [u8; 4],
}

/// The fan: points (the centre first, then ring by ring) and triangles as index triples.
pub struct Fan {
    /// The centre, then ring by ring from the inside out.
    pub points: Vec<Point>,
    /// Triangles as indices into `points`.
    pub triangles: Vec<[u16; 3]>,
}

/// What the ball's surface is at `body` (a unit vector in the ball's own frame).
pub fn surface(look: &BallLook, body: DVec3) -> Rgb {
    if look.number.is_some() && body.z.abs() > SPOT_COS {
        return palette::BALL_WHITE;
    }
    if look.stripe {
        return if body.x.abs() < STRIPE_HALF {
            look.color
        } else {
            palette::BALL_WHITE
        };
    }
    if look.number.is_none() && is_cue_marker(body) {
        return palette::CUE_MARKER;
    }
    look.color
}

/// The cue ball carries six small dots (on its axes) so its spin shows.
fn is_cue_marker(b: DVec3) -> bool {
    b.x.abs() > DOT_COS || b.y.abs() > DOT_COS || b.z.abs() > DOT_COS
}

/// How bright a point whose normal is `n` (screen terms) is.
fn light(n: [f64; 3]) -> f64 {
    let l = DVec3::from(LIGHT).normalize();
    AMBIENT + (1.0 - AMBIENT) * DVec3::from(n).dot(l).max(0.0)
}

/// The ball `look` turned by `turn`, seen from above.
pub fn fan(look: &BallLook, turn: DQuat, axes: ScreenAxes) -> Fan {
    let back = turn.inverse();
    let point = |u: f64, v: f64| {
        let w = (1.0 - u * u - v * v).max(0.0).sqrt();
        let body = back * axes.to_scene(u, v, w).normalize();
        let c = surface(look, body);
        let k = light([u, v, w]);
        let shade = |x: u8| (x as f64 * k).round().clamp(0.0, 255.0) as u8;
        Point {
            at: [u as f32, v as f32],
            rgba: [shade(c[0]), shade(c[1]), shade(c[2]), 255],
        }
    };
    let mut points = vec![point(0.0, 0.0)];
    for ring in 1..=RINGS {
        // Rings closer together at the rim, where the sphere turns away fastest.
        let s = libm::sin(ring as f64 / RINGS as f64 * std::f64::consts::FRAC_PI_2);
        for k in 0..SECTORS {
            let a = k as f64 / SECTORS as f64 * std::f64::consts::TAU;
            points.push(point(s * libm::cos(a), s * libm::sin(a)));
        }
    }
    let idx = |ring: usize, k: usize| (1 + (ring - 1) * SECTORS + k % SECTORS) as u16;
    let mut triangles = Vec::with_capacity(SECTORS * (2 * RINGS - 1));
    for k in 0..SECTORS {
        triangles.push([0, idx(1, k), idx(1, k + 1)]);
        for ring in 2..=RINGS {
            let (a, b) = (idx(ring - 1, k), idx(ring - 1, k + 1));
            let (c, d) = (idx(ring, k), idx(ring, k + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    Fan { points, triangles }
}

/// Where the centre of the number spot on +z (and the one on −z) of the ball lies on the
/// screen, in ball radii, with how squarely it faces the viewer (1: straight at, ≤0: hidden).
pub fn spots(turn: DQuat, axes: ScreenAxes) -> [([f64; 2], f64); 2] {
    let up = turn * DVec3::Z;
    [(axes.to_screen(up), up.z), (axes.to_screen(-up), -up.z)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::palette::ball_look;

    /// The layout's mapping: scene x goes down the screen, scene y to the right.
    const AXES: ScreenAxes = ScreenAxes {
        x: [0.0, 1.0],
        y: [1.0, 0.0],
    };

    fn centre_colour(look: &BallLook, turn: DQuat) -> Rgb {
        let body = turn.inverse() * DVec3::Z;
        surface(look, body)
    }

    #[test]
    fn an_unturned_ball_shows_its_number_on_top() {
        let seven = ball_look("7");
        assert_eq!(centre_colour(&seven, DQuat::IDENTITY), palette::BALL_WHITE);
        let [(at, facing), (_, back)] = spots(DQuat::IDENTITY, AXES);
        assert!(at[0].abs() < 1e-12 && at[1].abs() < 1e-12 && facing == 1.0 && back == -1.0);
    }

    #[test]
    fn a_quarter_roll_moves_the_spot_to_the_rim_in_the_direction_of_travel() {
        // Rolling along +y (to the right on screen) turns the ball about −x.
        let turn = DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        let [(at, facing), _] = spots(turn, AXES);
        assert!(facing.abs() < 1e-9);
        // The top of the ball went towards +y: the right of the screen.
        assert!((at[0] - 1.0).abs() < 1e-9 && at[1].abs() < 1e-9, "{at:?}");
        let seven = ball_look("7");
        assert_eq!(centre_colour(&seven, turn), seven.color);
    }

    #[test]
    fn a_stripe_shows_as_a_band_and_white_caps() {
        let eleven = ball_look("11");
        assert!(eleven.stripe);
        let f = fan(&eleven, DQuat::IDENTITY, AXES);
        // Along the stripe axis (scene x: screen down) the rim is white; across it, coloured.
        let colour_at = |u: f32, v: f32| {
            f.points
                .iter()
                .min_by(|a, b| {
                    let da = (a.at[0] - u).powi(2) + (a.at[1] - v).powi(2);
                    let db = (b.at[0] - u).powi(2) + (b.at[1] - v).powi(2);
                    da.total_cmp(&db)
                })
                .map(|p| p.rgba)
                .unwrap_or_default()
        };
        let white = colour_at(0.0, 0.95);
        let band = colour_at(0.95, 0.0);
        assert!(white[0] > band[0] || white[1] > band[1] || white[2] > band[2]);
        assert!(
            white[0].abs_diff(white[1]) < 40,
            "a cap is white: {white:?}"
        );
    }

    #[test]
    fn the_fan_is_whole_and_lit_from_the_upper_left() {
        let f = fan(&ball_look("cue"), DQuat::IDENTITY, AXES);
        assert_eq!(f.points.len(), 1 + RINGS * SECTORS);
        assert!(f
            .triangles
            .iter()
            .flatten()
            .all(|&i| (i as usize) < f.points.len()));
        let lum = |p: &Point| p.rgba[0] as u32 + p.rgba[1] as u32 + p.rgba[2] as u32;
        let upper_left = f.points.iter().filter(|p| p.at[0] < -0.5 && p.at[1] < -0.5);
        let lower_right = f.points.iter().filter(|p| p.at[0] > 0.5 && p.at[1] > 0.5);
        let ul = upper_left.map(lum).max().unwrap_or(0);
        let lr = lower_right.map(lum).max().unwrap_or(0);
        assert!(ul > lr, "{ul} vs {lr}");
    }
}
