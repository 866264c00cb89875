//! `atan2` without a library call, four lanes at a time ([`atan2_x4`]) or one ([`atan2`]),
//! the same bits either way: the twist angle of the rotation measure, `2·atan2(t_x, t_w)`
//! of every hinge at every substep. libm's `atan2` is a call of about a hundred
//! instructions, and around a call in the four-joint measure (`twist_x4`) every vector
//! register live across it was spilled: 4 % of the contact scene's joint work was libm's
//! `atan2`.
//!
//! The arctangent is Cephes' `atan` (S. L. Moshier; also Go's `math.Atan`) of `a = |y|/|x|`,
//! reduced to `|r| ≤ 0.66` without forming `a` (one division fewer on the chain):
//! `a > tan(3π/8)`: `π/2 + atan(−|x|/|y|)`; `a > 0.66`: `π/4 + atan((|y| − |x|)/(|y| + |x|))`;
//! else `atan(|y|/|x|)`; there `atan r = r + r·z·P(z)/Q(z)` with `z = r²`, a rational of
//! degrees 4/5, and the low bits of `π/2` and `π/4` added back (`MOREBITS`). Cephes gives
//! its peak relative error on IEEE doubles as 1.8e-16; the test below holds it within 2 ulp
//! of libm over every quadrant and twelve decades of `y/x`.
//!
//! The quadrants as IEEE's `atan2`: `x` of negative sign (−0 included) gives
//! `π − atan(|y|/|x|)`, and the sign is `y`'s; `y = ±0` gives `±0` (`x` positive) or `±π`
//! (`x` negative). Only finite arguments are meant (two infinities give NaN); a NaN gives
//! NaN.

use crate::lanes::{arr4, F4};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::ops::{Add, Div, Mul};

// The constants as Cephes prints them (each digit string rounds to the f64 it names).
/// `P(z)`, highest degree first.
#[allow(clippy::excessive_precision)]
const P: [f64; 5] = [
    -8.750608600031904122785e-01,
    -1.615753718733365076637e+01,
    -7.500855792314704667340e+01,
    -1.228866684490136173410e+02,
    -6.485021904942025371773e+01,
];
/// `Q(z) = z⁵ + …`, the coefficients after the leading 1, highest degree first.
#[allow(clippy::excessive_precision)]
const Q: [f64; 5] = [
    2.485846490142306297962e+01,
    1.650270098316988542046e+02,
    4.328810604912902668951e+02,
    4.853903996359136964868e+02,
    1.945506571482613964425e+02,
];
/// `tan(3π/8)`.
#[allow(clippy::excessive_precision)]
const TAN_3PI_8: f64 = 2.414_213_562_373_095_048_80;
/// The reduction's middle range starts here.
const MID: f64 = 0.66;
/// `π/2 − FRAC_PI_2`: the low bits of `π/2`.
#[allow(clippy::excessive_precision)]
const MOREBITS: f64 = 6.123_233_995_736_765_886_130e-17;

/// The reduction of `a = |y|/|x|` (the module's notes): `(num, den, base, more)`, with
/// `atan a = base + (atan(num/den) + more)`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn reduction(ay: f64, ax: f64) -> [f64; 4] {
    if ay > TAN_3PI_8 * ax {
        [-ax, ay, FRAC_PI_2, MOREBITS]
    } else if ay > MID * ax {
        [ay - ax, ay + ax, FRAC_PI_4, 0.5 * MOREBITS]
    } else {
        [ay, ax, 0.0, 0.0]
    }
}

/// `atan r = r + r·z·P(z)/Q(z)` with `r = num/den`, `z = r²`, in lanes or in one `f64`
/// (`s`: a constant in the type).
#[cfg_attr(not(debug_assertions), inline(always))]
fn reduced_atan<T>(num: T, den: T, s: impl Fn(f64) -> T) -> T
where
    T: Copy + Add<Output = T> + Mul<Output = T> + Div<Output = T>,
{
    let r = num / den;
    let z = r * r;
    let p = (((s(P[0]) * z + s(P[1])) * z + s(P[2])) * z + s(P[3])) * z + s(P[4]);
    let q = ((((z + s(Q[0])) * z + s(Q[1])) * z + s(Q[2])) * z + s(Q[3])) * z + s(Q[4]);
    let w = z * p / q;
    r * w + r
}

/// `atan2(y, x)` from `at = atan(|y|/|x|)`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn quadrant(y: f64, x: f64, at: f64) -> f64 {
    // (y = ±0: at is NaN when x is too)
    let at = if y == 0.0 { 0.0 } else { at };
    let at = if x.is_sign_negative() {
        (PI - at) + 2.0 * MOREBITS
    } else {
        at
    };
    at.copysign(y)
}

/// `atan2(y, x)` in each lane (the module's notes).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn atan2_x4(y: F4, x: F4) -> F4 {
    let red = arr4(|l| reduction(y.0[l].abs(), x.0[l].abs()));
    let part = |k: usize| F4(arr4(|l| red[l][k]));
    let small = reduced_atan(part(0), part(1), F4::splat);
    let at = part(2) + (small + part(3));
    F4(arr4(|l| quadrant(y.0[l], x.0[l], at.0[l])))
}

/// [`atan2_x4`] of one pair: the same operations, the same bits.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    let [num, den, base, more] = reduction(y.abs(), x.abs());
    let at = base + (reduced_atan(num, den, |c| c) + more);
    quadrant(y, x, at)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite doubles of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        let key = |v: f64| {
            let i = v.to_bits() as i64;
            if i < 0 {
                i64::MIN - i
            } else {
                i
            }
        };
        key(a).abs_diff(key(b))
    }

    /// Against libm over every quadrant, twelve decades of `|y/x|` either way, the
    /// reduction's boundaries and the signed zeros: within 2 ulp (or 1e-300 absolute near
    /// zero), the lanes equal to the scalar form bit for bit.
    #[test]
    fn atan2_is_within_two_ulp_of_libm_and_the_lanes_equal_the_scalar() {
        let mut rand = crate::test_rand::xorshift(0x9e37_79b9_7f4a_7c15_u64);
        let mut pairs = vec![
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (1.0, 0.0),
            (1.0, -0.0),
            (-1.0, 0.0),
            (-1.0, -0.0),
            (1.0, 1.0),
            (-1.0, -1.0),
            (TAN_3PI_8, 1.0),
            (MID, 1.0),
            (1e-300, 1.0),
            (1.0, 1e-300),
        ];
        for _ in 0..400_000 {
            let m = 10f64.powf(12.0 * (2.0 * rand() - 1.0));
            let sy = if rand() < 0.5 { -1.0 } else { 1.0 };
            let sx = if rand() < 0.5 { -1.0 } else { 1.0 };
            let x = sx * (0.1 + rand());
            pairs.push((sy * m * x.abs(), x));
            // and near the reduction's boundaries
            let b = if rand() < 0.5 { TAN_3PI_8 } else { MID };
            pairs.push((sy * b * (1.0 + 1e-6 * (2.0 * rand() - 1.0)), sx));
        }
        let mut worst = 0;
        for four in pairs.chunks(4) {
            let get = |f: fn(&(f64, f64)) -> f64| F4(arr4(|l| four.get(l).map_or(1.0, f)));
            let lanes = atan2_x4(get(|p| p.0), get(|p| p.1));
            for (l, &(y, x)) in four.iter().enumerate() {
                let (ours, libm) = (atan2(y, x), y.atan2(x));
                assert_eq!(ours.to_bits(), lanes.0[l].to_bits(), "atan2({y:e}, {x:e})");
                assert_eq!(
                    ours.is_sign_negative(),
                    libm.is_sign_negative(),
                    "({y}, {x})"
                );
                let u = ulps(ours, libm);
                assert!(
                    u <= 2 || (ours - libm).abs() < 1e-300,
                    "atan2({y:e}, {x:e}) = {ours:e}, libm {libm:e}: {u} ulp"
                );
                worst = worst.max(u);
            }
        }
        assert!(atan2(f64::NAN, 1.0).is_nan() && atan2(1.0, f64::NAN).is_nan());
        println!("worst {worst} ulp over {} pairs", pairs.len());
    }
}
