//! The first contact of a polynomial of degree up to 8: a ball in flight against a pocket
//! jaw's nose, a horizontal circle (a torus's core), whose squared-distance condition is an
//! octic in time (see `airborne.rs`).
//!
//! The same procedure as `roots.rs`, one level deeper: `[0, τ_max]` is cut at the critical
//! points of `f` (the roots of `f'`, found the same way from the roots of `f''`, down to a
//! linear polynomial), so that `f` is monotone on each piece; the pieces are walked in time
//! order and the first decreasing piece on which `f` reaches zero holds the contact, found by
//! the bracketed Newton iteration of `roots.rs`. A bracket always holds the root, so none is
//! missed. This is slower than the quartic solver (a few dozen evaluations more), which is why
//! only the rare jaw contacts in flight use it.

use super::roots::{bracketed_root, contact_at_start, first_descent, Touch};

/// A polynomial `c[0] + c[1]·τ + … + c[8]·τ⁸`.
pub(super) type Octic = [f64; 9];

/// The value at `t` of `c` of degree `deg` (Horner's scheme).
fn eval(c: &Octic, deg: usize, t: f64) -> f64 {
    let mut v = c[deg];
    for k in (0..deg).rev() {
        v = v * t + c[k];
    }
    v
}

/// The derivative of `c` of degree `deg` (degree `deg − 1`).
fn derivative(c: &Octic, deg: usize) -> Octic {
    let mut d = [0.0; 9];
    for k in 1..=deg {
        d[k - 1] = k as f64 * c[k];
    }
    d
}

/// The degree of `c` once leading zeros are dropped.
fn degree(c: &Octic) -> usize {
    (1..9).rev().find(|&k| c[k] != 0.0).unwrap_or(0)
}

/// The roots of `c` (degree `deg`) in the open interval (lo, hi) at which it changes sign,
/// in increasing order, into `out`; how many.
fn sign_changes_in(c: &Octic, deg: usize, lo: f64, hi: f64, out: &mut [f64; 8]) -> usize {
    if deg == 0 {
        return 0;
    }
    if deg == 1 {
        let r = -c[0] / c[1];
        if r > lo && r < hi {
            out[0] = r;
            return 1;
        }
        return 0;
    }
    let d = derivative(c, deg);
    let mut stops = [0.0; 8];
    let count = sign_changes_in(&d, deg - 1, lo, hi, &mut stops);
    let mut n = 0;
    let mut a = lo;
    let mut fa = eval(c, deg, lo);
    for (k, b) in stops[..count].iter().copied().chain([hi]).enumerate() {
        let fb = eval(c, deg, b);
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            out[n] = bracketed_root(|t| eval(c, deg, t), |t| eval(&d, deg - 1, t), a, b, fa);
            n += 1;
        } else if fb == 0.0 && k < count {
            out[n] = b;
            n += 1;
        }
        a = b;
        fa = fb;
    }
    n
}

/// The first time in `[0, t_max]` at which `f` is at or below zero while decreasing, with
/// the touch rules of [`super::roots::first_contact`]. `None` if there is none.
pub(super) fn first_contact(c: &Octic, t_max: f64, touch: Touch) -> Option<f64> {
    if t_max.is_nan() || t_max <= 0.0 || c.iter().any(|x| !x.is_finite()) {
        return None;
    }
    if contact_at_start(c, touch) {
        return Some(0.0);
    }
    let deg = degree(c);
    if deg == 0 {
        return None;
    }
    let d = derivative(c, deg);
    let mut stops = [0.0; 8];
    let count = sign_changes_in(&d, deg - 1, 0.0, t_max, &mut stops);
    let ends = stops[..count].iter().copied().chain([t_max]);
    first_descent(c[0], ends, |t| eval(c, deg, t), |t| eval(&d, deg - 1, t))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOUCH: Touch = super::super::roots::TEST_TOUCH;

    fn from_roots(roots: &[f64]) -> Octic {
        super::super::roots::poly_from_roots(roots, 1.0)
    }

    #[test]
    fn finds_the_first_downward_crossing_of_an_octic() {
        let c = from_roots(&[0.15, 0.2, 0.45, 0.5, 0.9, 1.1, -1.0, -2.0]);
        assert!(eval(&c, 8, 0.0) > 0.0);
        let t = first_contact(&c, 2.0, TOUCH).expect("root");
        assert!((t - 0.15).abs() < 1e-13, "{t}");
        // Past the first pair of roots, from where f is positive again.
        let later = from_roots(&[-0.2, -0.1, 0.45, 0.5, 0.9, 1.1, -1.0, -2.0]);
        let t = first_contact(&later, 2.0, TOUCH).expect("root");
        assert!((t - 0.45).abs() < 1e-13, "{t}");
    }

    #[test]
    fn rising_or_out_of_reach_is_no_contact() {
        // Negative at zero and rising until a root past the horizon.
        let c = from_roots(&[-5.0, 3.0, 4.0, 5.0, -6.0, -7.0, -8.0, -9.0]);
        assert!(eval(&c, 8, 0.0) < 0.0);
        assert_eq!(first_contact(&c, 2.0, TOUCH), None);
        assert_eq!(first_contact(&from_roots(&[1.5, 2.5]), 1.0, TOUCH), None);
    }

    #[test]
    fn a_graze_is_found_and_a_near_miss_is_not() {
        let mut c = from_roots(&[0.7, 0.7, -1.0, -2.0, -3.0, -4.0, -5.0, -6.0]);
        c[0] -= 1e-9;
        let t = first_contact(&c, 2.0, TOUCH).expect("graze");
        assert!((t - 0.7).abs() < 1e-4 && eval(&c, 8, t) <= 0.0, "{t}");
        c[0] += 2e-9;
        assert_eq!(first_contact(&c, 2.0, TOUCH), None);
    }
}
