//! Event times as the first contact of a polynomial distance function.
//!
//! Every contact the engine detects (ball–ball, ball–rail, ball–jaw, ball–pocket) is the
//! first time a polynomial `f(τ)` of degree ≤ 4 reaches zero *while decreasing*: `f` is a
//! squared distance minus the squared contact distance (or a signed distance to a rail), so
//! `f ≤ 0` means touching and `f' < 0` means approaching.
//!
//! The quartic is never solved in closed form (Ferrari's formulas lose all precision near
//! double roots, the grazing hits that matter most). For objects apart at the start the
//! contact is the first root of `f`: the interval `[0, τ_max]` is split at the roots of the
//! quadratic `f''` (closed form, cancellation-free), so that `f` is convex or concave on each
//! stretch, and on either Newton's steps approach the first root from the side they cannot
//! pass (`first_root`); a quadratic (a rail, or two balls with equal accelerations) has its
//! first root in closed form. For objects touching at the start the interval is split at the
//! critical points of `f` (the roots of the cubic `f'`, found the same way from the roots of
//! `f''`), so that `f` is monotone on each piece; the pieces are walked in time order, the
//! first decreasing piece on which `f` reaches zero holds the event, and a bracketed Newton
//! iteration (which falls back to bisection whenever Newton leaves the bracket or stalls)
//! finds it. A double root (a graze) is found by either search.
//!
//! Touching at `τ = 0` counts only when approaching: two frozen balls moving apart give no
//! phantom collision, and two balls that have just collided (now separating) do not collide
//! again.

/// A polynomial `c[0] + c[1]·τ + … + c[4]·τ⁴`.
pub type Poly = [f64; 5];

use glam::DVec2;

/// The value of the polynomial `c` at `t` (Horner's scheme).
#[inline]
pub fn eval(c: &Poly, t: f64) -> f64 {
    (((c[4] * t + c[3]) * t + c[2]) * t + c[1]) * t + c[0]
}

#[inline]
fn eval_d(c: &Poly, t: f64) -> f64 {
    ((4.0 * c[4] * t + 3.0 * c[3]) * t + 2.0 * c[2]) * t + c[1]
}

#[inline]
fn eval_dd(c: &Poly, t: f64) -> f64 {
    (12.0 * c[4] * t + 6.0 * c[3]) * t + 2.0 * c[2]
}

/// Up to two sorted real roots of `a·t² + b·t + c` inside the open interval (lo, hi).
fn quadratic_roots_in(a: f64, b: f64, c: f64, lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
    let mut n = 0;
    let mut push = |r: f64, n: &mut usize| {
        if r > lo && r < hi {
            out[*n] = r;
            *n += 1;
        }
    };
    if a == 0.0 {
        if b != 0.0 {
            push(-c / b, &mut n);
        }
        return n;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        // No real roots, or a double root within rounding: either way the derivative does
        // not change sign there, so the function stays monotone across it.
        return 0;
    }
    let sq = disc.sqrt();
    let q = if b >= 0.0 {
        -0.5 * (b + sq)
    } else {
        -0.5 * (b - sq)
    };
    let (mut r1, mut r2) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    if r1 > r2 {
        std::mem::swap(&mut r1, &mut r2);
    }
    push(r1, &mut n);
    if r2 != r1 {
        push(r2, &mut n);
    }
    n
}

/// How far short of contact (m) the bounds below place themselves: far above the rounding
/// of any contact polynomial the solver evaluates over a table's distances (some 1e-12 m),
/// far below any distance that matters.
const BOUND_MARGIN: f64 = 1e-6;

/// The margin for a motion that may cover up to `travel` metres (an upper bound on the
/// terms of its polynomial) before `t_max`: the polynomial's rounding grows with their
/// squares (about 1e-16 of them, over a contact distance), so the margin does too, by far
/// more. Infinite for an unbounded `t_max`, which leaves the answer to the solver.
fn margin(travel: f64) -> f64 {
    BOUND_MARGIN + 1e-12 * travel * travel
}

/// A lower bound on the first τ ≥ 0 at which `d(τ) = dr + dv·τ + ½·da·τ²` comes within
/// `distance` (as the root solver finds it on the squared-distance polynomial of the same
/// `dr`, `dv`, `da`), or `None` when it never does. Along `n = dr/|dr|` the length is at
/// least `n·d(τ) = |dr| + u·τ + ½·w·τ²` (`u = n·dv`, `w = n·da`), so contact needs the
/// closing `−u·τ − ½·w·τ²` to reach the gap `|dr| − distance`. The closing rates are raised
/// by a billionth of `|dv|` and `|da|` and the gap lowered by a margin (`margin`), far above
/// their rounding, so the bound is never above a contact the solver can find in
/// `[0, t_max]`.
pub fn contact_bound(dr: DVec2, dv: DVec2, da: DVec2, distance: f64, t_max: f64) -> Option<f64> {
    let (dist, gap) = gap_less_margin(dr, dv, da, distance, t_max);
    if gap <= 0.0 {
        return Some(0.0);
    }
    let (speed, acc) = closing_rates(dr, dist, dv, da);
    closing_time(gap * dist, speed, acc)
}

/// `|dr|`, and the gap to `distance` along it lowered by the margin for the motion over
/// `[0, t_max]` (see [`contact_bound`]).
#[inline(always)]
fn gap_less_margin(dr: DVec2, dv: DVec2, da: DVec2, distance: f64, t_max: f64) -> (f64, f64) {
    let dist = dr.length();
    let l1 = |v: DVec2| v.x.abs() + v.y.abs();
    let travel = l1(dr) + distance + (l1(dv) + l1(da) * t_max) * t_max;
    (dist, dist - distance - margin(travel))
}

/// The closing speed and acceleration along `n = dr/|dr|` (from one object to the other),
/// each raised by a billionth of its vector's size (see [`contact_bound`]), both times
/// `dist = |dr|`: the closing reaches a gap when the scaled closing reaches the gap times
/// `dist`, at the same times, and no division by `dist` stands in the way of the square
/// root and the division that find them.
#[inline(always)]
fn closing_rates(dr: DVec2, dist: f64, dv: DVec2, da: DVec2) -> (f64, f64) {
    let speed = -dr.dot(dv) + 1e-9 * (dv.x.abs() + dv.y.abs()) * dist;
    let acc = -dr.dot(da) + 1e-9 * (da.x.abs() + da.y.abs()) * dist;
    (speed, acc)
}

/// [`contact_bound`], and for objects already within reach of contact (where that gives
/// zero) but surely moving apart, a bound on their *next* contact: most of these are two
/// balls that have just collided, whose solve would find nothing.
///
/// Along `n` the closing `speed·τ + ½·acc·τ²` (the rates raised as in [`contact_bound`]) is
/// below the gap (here at most zero), so no contact can be found, between the two roots
/// `τ_out < τ_back` of `½·acc·τ² + speed·τ = gap` (there only when `speed < 0`, and
/// `τ_back` infinite unless `acc > 0`). Before `τ_out` the squared distance
/// `f(τ) = c₀ + c₁·τ + c₂·τ² + c₃·τ³ + c₄·τ⁴` may be at or below zero, but it rises: on
/// `[0, τ₁]`, `τ₁ = 2·τ_out + 1e-12`, its derivative is at least
/// `c₁ − 2|c₂|·τ₁ − 3|c₃|·τ₁² − 4|c₄|·τ₁³`, asked to exceed a billionth of the terms (far
/// above their rounding) and the speed at which touching counts as approaching
/// ([`Touch::squared`]). Then the solver (on the same `dr`, `dv`, `da`) finds no contact at
/// the start, no critical point before `τ₁` less its tolerance, so none on `[0, τ_out]`,
/// and `f` above zero after it until `τ_back`: its first contact, if any, is at `τ_back` or
/// later, and there is none when `τ_back` is past `t_max`. When any of this fails the answer
/// is zero, as from [`contact_bound`].
#[inline]
pub fn pair_bound(dr: DVec2, dv: DVec2, da: DVec2, distance: f64, t_max: f64) -> Option<f64> {
    let (dist, gap) = gap_less_margin(dr, dv, da, distance, t_max);
    if gap <= 0.0 {
        return separating_time(dr, dist, dv, da, distance, t_max, gap).unwrap_or(Some(0.0));
    }
    let (speed, acc) = closing_rates(dr, dist, dv, da);
    closing_time(gap * dist, speed, acc)
}

/// The bound of [`pair_bound`] for objects within reach (`gap ≤ 0`): `Some(None)` for no
/// contact in `[0, t_max]`, `Some(Some(τ_back))`, or `None` when moving apart is not sure.
#[inline(never)]
fn separating_time(
    dr: DVec2,
    dist: f64,
    dv: DVec2,
    da: DVec2,
    distance: f64,
    t_max: f64,
    gap: f64,
) -> Option<Option<f64>> {
    let (speed, acc) = closing_rates(dr, dist, dv, da);
    let (tau1, tau_back) = moving_out(gap * dist, speed, acc, t_max)?;
    // The squared-distance polynomial's coefficients, as `ball_ball::contact_poly` has them.
    let c1 = 2.0 * dr.dot(dv);
    let c2 = dv.dot(dv) + dr.dot(da);
    let c3 = dv.dot(da);
    let c4 = 0.25 * da.dot(da);
    let slow = ((4.0 * c4.abs() * tau1 + 3.0 * c3.abs()) * tau1 + 2.0 * c2.abs()) * tau1;
    let rising = c1 - slow > 1e-9 * (c1 + slow) + 2.0 * distance * TOUCH_SPEED;
    if !rising {
        return None;
    }
    Some((tau_back <= t_max).then_some(tau_back))
}

/// For a closing `speed·τ + ½·acc·τ²` below a gap `gap ≤ 0` between the two roots
/// `τ_out < τ_back` (see [`pair_bound`]): `τ₁ = 2·τ_out + 1e-12`, up to which the contact
/// function must be shown to rise, and `τ_back` (infinite when the closing never comes
/// back); `None` unless `speed < 0`, the roots are real and `τ₁ < τ_back`.
fn moving_out(gap: f64, speed: f64, acc: f64, t_max: f64) -> Option<(f64, f64)> {
    // Every test is written to fail on a NaN.
    if !(speed < 0.0 && t_max.is_finite()) {
        return None;
    }
    let disc = speed * speed + 2.0 * acc * gap;
    let real = disc >= 0.0;
    if !real {
        return None;
    }
    // The roots of ½·acc·τ² + speed·τ − gap, without cancellation (−speed > 0, gap ≤ 0).
    let out = disc.sqrt() - speed;
    let tau_out = -2.0 * gap / out;
    let tau_back = if acc > 0.0 { out / acc } else { f64::INFINITY };
    let tau1 = 2.0 * tau_out + 1e-12;
    let ordered = tau1 < tau_back;
    ordered.then_some((tau1, tau_back))
}

/// A lower bound on the first τ ≥ 0 at which the solver finds `c₀ + c₁·τ + c₂·τ²` (a signed
/// distance) at or below zero, or `None` when it never does: the same quadratic, solved in
/// closed form for a gap lowered by the margin (its evaluation's rounding is far smaller),
/// within `[0, t_max]`.
///
/// Within the margin of contact but surely moving away (most often just after a bounce off
/// the rail), the bound is that of the next contact, or none, as for a pair of balls
/// ([`pair_bound`]): `f = c₀ + c₁·τ + c₂·τ²` rises on `[0, τ₁]` when
/// `c₁ − 2|c₂|·τ₁` exceeds a billionth of its terms and the speed at which touching counts as
/// approaching ([`Touch::linear`]), and stays above the margin until `τ_back`.
pub fn line_bound(c0: f64, c1: f64, c2: f64, t_max: f64) -> Option<f64> {
    let travel = c0.abs() + (c1.abs() + c2.abs() * t_max) * t_max;
    let gap = c0 - margin(travel);
    if gap <= 0.0 {
        return line_moving_out(c1, c2, t_max, gap).unwrap_or(Some(0.0));
    }
    closing_time(gap, -c1, -2.0 * c2)
}

/// The bound of [`line_bound`] within the margin (`gap ≤ 0`): `Some(None)` for no contact in
/// `[0, t_max]`, `Some(Some(τ_back))`, or `None` when moving away is not sure.
#[inline(never)]
fn line_moving_out(c1: f64, c2: f64, t_max: f64, gap: f64) -> Option<Option<f64>> {
    let (tau1, tau_back) = moving_out(gap, -c1, -2.0 * c2, t_max)?;
    let slow = 2.0 * c2.abs() * tau1;
    let rising = c1 - slow > 1e-9 * (c1 + slow) + TOUCH_SPEED;
    if !rising {
        return None;
    }
    Some((tau_back <= t_max).then_some(tau_back))
}

/// The first root of `½·acc·τ² + speed·τ = gap` (`gap > 0`), written without cancellation;
/// `None` when the closing never reaches the gap.
fn closing_time(gap: f64, speed: f64, acc: f64) -> Option<f64> {
    let disc = speed * speed + 2.0 * acc * gap;
    if disc < 0.0 {
        return None;
    }
    let den = speed + disc.sqrt();
    if den <= 0.0 {
        return None;
    }
    let tau = 2.0 * gap / den;
    if tau.is_nan() {
        // Not from finite numbers; zero leaves the answer to the solver.
        return Some(0.0);
    }
    Some(tau)
}

/// True when `d(τ) = dr + dv·τ + ½·da·τ²` provably stays longer than `distance` for
/// τ in `[0, t_max]`: the straight-line part's closest approach, less the most the
/// acceleration can bend the path, is still out of reach. A cheap test that spares the root
/// isolation for nearly every pair of balls.
pub fn stays_apart(dr: DVec2, dv: DVec2, da: DVec2, t_max: f64, distance: f64) -> bool {
    let speed2 = dv.length_squared();
    let t_closest = if speed2 > 0.0 {
        (-dr.dot(dv) / speed2).clamp(0.0, t_max)
    } else {
        0.0
    };
    let closest = (dr + dv * t_closest).length();
    let bend = if t_max.is_finite() {
        0.5 * da.length() * t_max * t_max
    } else if da == DVec2::ZERO {
        0.0
    } else {
        f64::INFINITY
    };
    closest - bend > distance
}

/// Times closer than this (s) are not told apart: a ball at 50 m/s moves 5 pm in it.
pub const TIME_TOLERANCE: f64 = 1e-13;

/// Finds the zero of a function monotone on `[lo, hi]` whose ends have opposite signs, by
/// Newton steps kept inside the bracket (a step that would leave it, or not halve it, is
/// replaced by bisection), to within [`TIME_TOLERANCE`]. `f_lo` is `f(lo)`, which every
/// caller has already evaluated.
pub(super) fn bracketed_root(
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    f_lo: f64,
) -> f64 {
    bracketed_root_from(f, df, lo, hi, f_lo, 0.5 * (lo + hi))
}

/// [`bracketed_root`] with the first step taken from `start` (inside `[lo, hi]`) instead of
/// the middle.
fn bracketed_root_from(
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
    f_lo: f64,
    start: f64,
) -> f64 {
    let lo_positive = f_lo > 0.0;
    let mut x = start;
    let mut last_step = hi - lo;
    // 200 halvings exceed any f64 interval; Newton usually needs a handful of steps.
    for _ in 0..200 {
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if (fx > 0.0) == lo_positive {
            lo = x;
        } else {
            hi = x;
        }
        if hi - lo <= TIME_TOLERANCE {
            break;
        }
        let d = df(x);
        let newton = x - fx / d;
        let step = (newton - x).abs();
        if d != 0.0 && newton > lo && newton < hi && step < 0.5 * last_step {
            if step <= 0.5 * TIME_TOLERANCE {
                return newton;
            }
            last_step = step;
            x = newton;
        } else {
            last_step = hi - lo;
            x = 0.5 * (lo + hi);
        }
    }
    0.5 * (lo + hi)
}

/// The critical points of `c` (roots of its derivative) inside (lo, hi), in increasing
/// order, each found only when it is asked for: a search that stops at the first contact
/// never solves for the critical points after it.
struct CriticalPoints<'a> {
    c: &'a Poly,
    /// Where `f'` may change its monotony (the roots of `f''`), then `hi`; or, when `f'` is
    /// linear, its root itself.
    stops: [f64; 4],
    count: usize,
    /// Whether the stops are the critical points themselves (`f'` linear).
    solved: bool,
    /// The next stop, the start of its stretch and `f'` there.
    next: usize,
    a: f64,
    da: f64,
}

impl<'a> CriticalPoints<'a> {
    fn new(c: &'a Poly, lo: f64, hi: f64) -> Self {
        let mut stops = [0.0; 4];
        let solved = c[4] == 0.0 && c[3] == 0.0;
        let count = if solved {
            // f' is linear (or constant): at most one root.
            quadratic_roots_in(0.0, 2.0 * c[2], c[1], lo, hi, &mut stops)
        } else {
            // Roots of f'' split [lo, hi] into stretches on which f' is monotone.
            let ni = quadratic_roots_in(12.0 * c[4], 6.0 * c[3], 2.0 * c[2], lo, hi, &mut stops);
            stops[ni] = hi;
            ni + 1
        };
        CriticalPoints {
            c,
            stops,
            count,
            solved,
            next: 0,
            a: lo,
            da: if solved { 0.0 } else { eval_d(c, lo) },
        }
    }
}

impl Iterator for CriticalPoints<'_> {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        let c = self.c;
        while self.next < self.count {
            let k = self.next;
            let b = self.stops[k];
            self.next += 1;
            if self.solved {
                return Some(b);
            }
            let (a, da) = (self.a, self.da);
            let db = eval_d(c, b);
            self.a = b;
            self.da = db;
            if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                return Some(bracketed_root(
                    |t| eval_d(c, t),
                    |t| eval_dd(c, t),
                    a,
                    b,
                    da,
                ));
            } else if db == 0.0 && k + 1 < self.count {
                return Some(b);
            }
        }
        None
    }
}

/// How fast `f` must fall at τ = 0 for objects already touching to count as approaching:
/// `speed` bounds `−f'(0)`, and `accel` bounds `−f''(0)` when `f'(0)` is about zero. Below
/// these (rounding noise after a collision, or a push slower than any effect on the result)
/// touching objects are left alone instead of colliding again and again at the same instant.
#[derive(Clone, Copy, Debug)]
pub struct Touch {
    /// Bound on `−f'(0)`, in `f`'s units per second.
    pub speed: f64,
    /// Bound on `−f''(0)`, in `f`'s units per second squared.
    pub accel: f64,
}

/// Approach speed (m/s) below which touching objects are not colliding: far below rounding
/// of any real speed, far above rounding noise of a zero one.
pub const TOUCH_SPEED: f64 = 1e-11;
/// Approach acceleration (m/s²) below which touching objects are not pushing into each other.
pub const TOUCH_ACCEL: f64 = 1e-11;

impl Touch {
    /// For `f` a squared distance minus `distance²`.
    pub fn squared(distance: f64) -> Touch {
        Touch {
            speed: 2.0 * distance * TOUCH_SPEED,
            accel: 2.0 * distance * TOUCH_ACCEL,
        }
    }

    /// For `f` a signed distance.
    pub fn linear() -> Touch {
        Touch {
            speed: TOUCH_SPEED,
            accel: TOUCH_ACCEL,
        }
    }
}

/// The first time in `[0, t_max]` at which `f` is at or below zero while decreasing: the
/// moment of contact. `None` if there is none (or `t_max` is not positive).
pub fn first_contact(c: &Poly, t_max: f64, touch: Touch) -> Option<f64> {
    if t_max.is_nan() || t_max <= 0.0 {
        return None;
    }
    if contact_at_start(c, touch) {
        return Some(0.0);
    }
    if c[0] > 0.0 && t_max.is_finite() {
        // Apart at the start (nearly every call): the contact is the first root.
        return if c[3] == 0.0 && c[4] == 0.0 {
            first_root_of_quadratic(c[0], c[1], c[2], t_max)
        } else {
            first_root(c, t_max)
        };
    }
    // Touching at the start without approaching (judged above), or an unbounded search: the
    // walk over the pieces on which `f` is monotone.
    let ends = CriticalPoints::new(c, 0.0, t_max).chain(std::iter::once(t_max));
    first_descent(c[0], ends, |t| eval(c, t), |t| eval_d(c, t))
}

/// The first root in `(0, t_max]` of `c₀ + c₁·τ + c₂·τ²` with `c₀ > 0`, in closed form: the
/// smaller root when `c₁ < 0` (written as `2c₀/(√disc − c₁)`, without cancellation), the
/// only positive one when `c₁ ≥ 0 > c₂`. A double root (a graze) is a root; a negative
/// discriminant is none.
fn first_root_of_quadratic(c0: f64, c1: f64, c2: f64, t_max: f64) -> Option<f64> {
    let disc = c1 * c1 - 4.0 * c2 * c0;
    // Every test is written to fail on a NaN.
    let real = disc >= 0.0;
    if !real {
        return None;
    }
    let root = if c1 < 0.0 {
        2.0 * c0 / (disc.sqrt() - c1)
    } else if c2 < 0.0 {
        -0.5 * (c1 + disc.sqrt()) / c2
    } else {
        return None;
    };
    (root <= t_max).then_some(root)
}

/// The first root in `(0, t_max]` of the polynomial `c` with `c[0] > 0` (finite `t_max`).
///
/// Between the roots of `f''` (a quadratic, in closed form) `f` is convex or concave, and on
/// either Newton's method converges to the first root from one side without passing it: on a
/// convex stretch from its start, where `f > 0` (the tangent lies below `f`, so its zero is
/// no later than the root; a tangent whose zero lies past the stretch, or that rises, shows
/// there is none on it); on a concave stretch from its end when `f ≤ 0` there (the tangent
/// lies above `f`; with `f > 0` at both ends a concave stretch holds no root). The stretches
/// are taken in time order, so the first root found is the first contact, and a graze (a
/// double root) is found as the limit of the convex side's steps.
fn first_root(c: &Poly, t_max: f64) -> Option<f64> {
    let mut ends = [0.0; 4];
    let inflections =
        quadratic_roots_in(12.0 * c[4], 6.0 * c[3], 2.0 * c[2], 0.0, t_max, &mut ends);
    ends[inflections] = t_max;
    let mut a = 0.0;
    let mut fa = c[0];
    for &b in &ends[..=inflections] {
        if fa <= 0.0 {
            // The stretch before ended at the root, within rounding.
            return Some(a);
        }
        if eval_dd(c, 0.5 * (a + b)) >= 0.0 {
            if let Some(t) = convex_root(c, a, fa, b) {
                return Some(t);
            }
            fa = eval(c, b);
        } else {
            let fb = eval(c, b);
            if fb <= 0.0 {
                return Some(concave_root(c, a, fa, b, fb));
            }
            fa = fb;
        }
        a = b;
    }
    None
}

/// The root of `f` on the convex stretch `[a, b]` with `f(a) = fa > 0`, if any: Newton's
/// steps from `a`, each no later than the root, until a step is under half
/// [`TIME_TOLERANCE`] (or lands on `f ≤ 0`, the root within rounding).
fn convex_root(c: &Poly, a: f64, fa: f64, b: f64) -> Option<f64> {
    let (mut x, mut fx) = (a, fa);
    // Near a root of multiplicity m (at most 4) each step closes at least 1/m of the distance
    // left, so 200 steps are far more than any interval needs.
    for _ in 0..200 {
        let d = eval_d(c, x);
        let falling = d < 0.0;
        if !falling {
            // Rising from here to the end of the stretch (or not a number).
            return None;
        }
        let next = x - fx / d;
        let within = next <= b;
        if !within {
            return None;
        }
        if next - x <= 0.5 * TIME_TOLERANCE {
            return Some(next);
        }
        x = next;
        fx = eval(c, x);
        if fx <= 0.0 {
            return Some(x);
        }
    }
    Some(x)
}

/// The root of `f` on the concave stretch `[a, b]` with `f(a) = fa > 0 ≥ f(b) = fb`: Newton's
/// steps from `b`, each no earlier than the root, kept inside the bracket (the bracketed
/// search from `b`).
fn concave_root(c: &Poly, a: f64, fa: f64, b: f64, fb: f64) -> f64 {
    if fb == 0.0 {
        return b;
    }
    bracketed_root_from(|t| eval(c, t), |t| eval_d(c, t), a, b, fa, b)
}

/// Whether `f` (coefficients lowest power first) touches at `t = 0` and is already
/// approaching: its value is at or below zero and its speed or acceleration inward is beyond
/// `touch`'s rounding.
pub(super) fn contact_at_start(c: &[f64], touch: Touch) -> bool {
    let d0 = c[1];
    c[0] <= 0.0 && (d0 < -touch.speed || (d0 <= touch.speed && 2.0 * c[2] < -touch.accel))
}

/// The first time at which `f` is at or below zero while decreasing, given `f(0) = f0` and
/// the `ends` of the pieces of `[0, t_max]` on which `f` is monotone (the last one `t_max`),
/// once [`contact_at_start`] said no. One walk serves every degree of polynomial.
pub(super) fn first_descent(
    f0: f64,
    ends: impl Iterator<Item = f64>,
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
) -> Option<f64> {
    let mut a = 0.0;
    let mut fa = f0;
    for b in ends {
        let fb = f(b);
        // On [a, b] f is monotone; it decreases when f' < 0 inside.
        // (The values first: they often settle it without the derivative.)
        let decreasing = fb < fa || df(0.5 * (a + b)) < 0.0;
        if decreasing {
            if fa <= 0.0 {
                if a == 0.0 {
                    // Touching at the start without approaching (judged by
                    // `contact_at_start`): a contact only if `f` rises above zero and falls
                    // back, on a later piece.
                    a = b;
                    fa = fb;
                    continue;
                }
                return Some(a);
            }
            if fb <= 0.0 {
                return Some(bracketed_root(&f, &df, a, b, fa));
            }
        }
        a = b;
        fa = fb;
    }
    None
}

/// The coefficients (lowest power first) of scale·Π(t − r) over `roots`: the polynomials
/// the root finders' tests know the roots of.
#[cfg(test)]
pub(crate) fn poly_from_roots<const N: usize>(roots: &[f64], scale: f64) -> [f64; N] {
    let mut c = [0.0; N];
    c[0] = scale;
    for &r in roots {
        let mut next = [0.0; N];
        for i in 0..N {
            if i + 1 < N {
                next[i + 1] += c[i];
            }
            next[i] -= r * c[i];
        }
        c = next;
    }
    c
}

/// Contact tolerances tight enough that the tests' roots are found to rounding.
#[cfg(test)]
pub(crate) const TEST_TOUCH: Touch = Touch {
    speed: 1e-15,
    accel: 1e-12,
};

#[cfg(test)]
mod tests {
    use super::*;

    const TOUCH: Touch = TEST_TOUCH;

    fn first_contact(c: &Poly, t_max: f64) -> Option<f64> {
        super::first_contact(c, t_max, TOUCH)
    }

    fn from_roots(roots: &[f64], scale: f64) -> Poly {
        poly_from_roots(roots, scale)
    }

    #[test]
    fn finds_first_downward_crossing_of_quartic() {
        // Positive before 0.3, negative between 0.3 and 0.5, positive again, ...
        let c = from_roots(&[0.3, 0.5, 0.9, 1.4], 1.0);
        let t = first_contact(&c, 2.0).expect("root");
        assert!((t - 0.3).abs() < 1e-15, "{t}");
    }

    #[test]
    fn ignores_upward_crossing() {
        // Negative at 0 and rising: separating overlap, then it stays positive until 2.
        let c = from_roots(&[-0.3, 0.2, 2.0, 3.0], 1.0);
        assert!(eval(&c, 0.0) < 0.0 && eval_d(&c, 0.0) > 0.0);
        let t = first_contact(&c, 2.5).expect("root at 2");
        assert!((t - 2.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn touching_and_separating_is_not_contact() {
        // f(0) = 0 and increasing.
        let c = [0.0, 1.0, 1.0, 0.0, 0.0];
        assert_eq!(first_contact(&c, 10.0), None);
    }

    #[test]
    fn touching_and_approaching_is_contact_now() {
        let c = [0.0, -1.0, 1.0, 0.0, 0.0];
        assert_eq!(first_contact(&c, 10.0), Some(0.0));
    }

    #[test]
    fn double_root_graze_is_found() {
        // (t − 0.7)² · (t + 1)(t + 2), lowered by 1e-12: dips just below zero at 0.7.
        let mut c = from_roots(&[0.7, 0.7, -1.0, -2.0], 1.0);
        c[0] -= 1e-12;
        let t = first_contact(&c, 2.0).expect("graze");
        assert!((t - 0.7).abs() < 1e-5, "{t}");
        assert!(eval(&c, t) <= 0.0);
    }

    #[test]
    fn near_miss_is_not_contact() {
        let mut c = from_roots(&[0.7, 0.7, -1.0, -2.0], 1.0);
        c[0] += 1e-12;
        assert_eq!(first_contact(&c, 2.0), None);
    }

    #[test]
    fn respects_horizon() {
        let c = from_roots(&[1.5, 2.5], 1.0);
        assert_eq!(first_contact(&c, 1.0), None);
        assert!(first_contact(&c, 2.0).is_some());
    }

    /// `f(τ) = |d(τ)|² − distance²` for `d(τ) = dr + dv·τ + ½·da·τ²`.
    fn squared_distance_poly(dr: DVec2, dv: DVec2, da: DVec2, distance: f64) -> Poly {
        [
            dr.length_squared() - distance * distance,
            2.0 * dr.dot(dv),
            dv.dot(dv) + dr.dot(da),
            dv.dot(da),
            0.25 * da.dot(da),
        ]
    }

    /// How the bounds of a random walk came out against the solver, for the cases that start
    /// within a micrometre of contact: no contact at all, or one later than now.
    #[derive(Default)]
    struct BoundTally {
        none: usize,
        later: usize,
    }

    impl BoundTally {
        /// Fails unless `bound` is at most the solver's `exact` contact and says none only
        /// where it finds none (`case` describes the inputs); counts a case `near` contact
        /// whose bound is not zero.
        fn check(
            &mut self,
            bound: Option<f64>,
            exact: Option<f64>,
            near: bool,
            case: impl Fn() -> String,
        ) {
            match (bound, exact) {
                (None, Some(e)) => panic!("{}: none, solver {e}", case()),
                (Some(b), Some(e)) => assert!(b <= e, "{}: {b} > {e}", case()),
                _ => {}
            }
            match bound {
                _ if !near => {}
                None => self.none += 1,
                Some(b) if b != 0.0 => self.later += 1,
                Some(_) => {}
            }
        }
    }

    #[test]
    fn line_bound_is_below_every_contact_the_solver_finds() {
        // Signed distances starting within a micrometre of the line (most moving away, as
        // after a bounce) and some further: the bound is never above the solver's contact,
        // and says none only when the solver finds none.
        let mut rng = crate::ai::Rng::new(0x5851_f42d_4c95_7f2du64);
        let mut unit = || rng.unit();
        let mut tally = BoundTally::default();
        for k in 0..100_000 {
            let c0 = match k % 3 {
                0 => (unit() - 0.5) * 2e-6,
                1 => (unit() - 0.5) * 2e-15,
                _ => unit() * 0.01,
            };
            let c1 = (unit() - 0.2) * [1e-12, 1e-3, 0.1, 1.0, 10.0][k % 5];
            let c2 = (unit() - 0.8) * 2.0;
            let t_max = [1e-9, 1e-4, 0.01, 0.3, 2.0][(k / 5) % 5] * (0.5 + unit());
            let bound = line_bound(c0, c1, c2, t_max);
            let exact = super::first_contact(&[c0, c1, c2, 0.0, 0.0], t_max, Touch::linear());
            tally.check(bound, exact, c0.abs() < 1e-6, || {
                format!("{c0} {c1} {c2} {t_max}")
            });
        }
        let BoundTally { none, later } = tally;
        assert!(none > 1_000 && later > 1_000, "{none} {later}");
    }

    #[test]
    fn the_first_root_agrees_with_the_walk_over_monotone_pieces() {
        // The walk over the pieces between the critical points of `f` (what the solver does
        // for objects touching at the start) is an independent search of the same contact.
        let walk = |c: &Poly, t_max: f64| {
            if contact_at_start(c, Touch::linear()) {
                return Some(0.0);
            }
            let ends = CriticalPoints::new(c, 0.0, t_max).chain(std::iter::once(t_max));
            first_descent(c[0], ends, |t| eval(c, t), |t| eval_d(c, t))
        };
        let mut rng = crate::ai::Rng::new(0x2545_f491_4f6c_dd1du64);
        let mut unit = || rng.unit();
        let (mut found, mut differ) = (0, Vec::new());
        for k in 0..200_000 {
            let quartic = k % 2 == 1;
            let c0 = unit() - 0.1;
            let c1 = (unit() - 0.5) * 4.0;
            let c2 = (unit() - 0.5) * 2.0;
            let (c3, c4) = if quartic {
                ((unit() - 0.5) * 2.0, (unit() - 0.3) * 0.5)
            } else {
                (0.0, 0.0)
            };
            let c = [c0, c1, c2, c3, c4];
            let t_max = 0.01 + unit() * 3.0;
            let fast = super::first_contact(&c, t_max, Touch::linear());
            let slow = walk(&c, t_max);
            match (fast, slow) {
                (Some(a), Some(b)) if (a - b).abs() <= 1e-9 => found += 1,
                (None, None) => {}
                _ => differ.push((c, t_max, fast, slow)),
            }
        }
        assert!(
            differ.is_empty(),
            "{} differ: {:?}",
            differ.len(),
            &differ[..differ.len().min(5)]
        );
        assert!(found > 50_000, "{found}");
    }

    #[test]
    fn pair_bound_is_below_every_contact_the_solver_finds() {
        // Random relative motions starting within a micrometre of contact (most moving
        // apart, as after a collision) and some further away: the bound is never above the
        // solver's contact, and says none only when the solver finds none.
        let mut rng = crate::ai::Rng::new(0x5851_f42d_4c95_7f2du64);
        let mut unit = || rng.unit();
        let distance = 0.05715;
        let mut tally = BoundTally::default();
        for k in 0..50_000 {
            let n = DVec2::new(unit() - 0.5, unit() - 0.5).normalize_or(DVec2::X);
            let off = match k % 3 {
                0 => (unit() - 0.5) * 2e-6,
                1 => (unit() - 0.5) * 2e-15,
                _ => unit() * 0.01,
            };
            let dr = n * (distance + off);
            let scale = [1e-9, 1e-3, 0.1, 1.0, 10.0][k % 5];
            let mut v = || DVec2::new(unit() - 0.5, unit() - 0.5);
            let (dv, da) = (v() * scale, v() * 8.0);
            let t = [1e-9, 1e-4, 0.01, 0.3, 2.0][(k / 5) % 5] * (0.5 + unit());
            let bound = pair_bound(dr, dv, da, distance, t);
            let c = squared_distance_poly(dr, dv, da, distance);
            let exact = super::first_contact(&c, t, Touch::squared(distance));
            tally.check(bound, exact, off.abs() < 1e-6, || {
                format!("{dr} {dv} {da} {t}")
            });
        }
        let BoundTally { none: apart, later } = tally;
        assert!(apart > 1_000 && later > 100, "{apart} {later}");
    }
}
