//! [`measure_rotation`](super::measure_rotation) of four joints at once, one per lane of
//! [`F4`], for the joints whose rotation is measured by [`RotationMeasure::TwistX`] (the
//! revolute, cylindrical and planar joints).
//!
//! A joint's twist-swing measure ([`super::twist_x`]) is a chain of dependent square roots
//! and divisions (the swing's norm, its half, the half twist) around one `atan2`: the
//! processor runs one joint's chain at a time, waiting on each root. In the lanes of one
//! vector four joints' roots and divisions take the time of one joint's, and their `atan2`
//! too (`super::atan2`, no library call). Every lane runs the scalar code's
//! operations in the same order (nalgebra's quaternion product and rotation matrix as
//! nalgebra forms them), so each joint gets the bits [`super::twist_x`] gives it (test
//! `four_twists_equal_the_scalar_measure_bit_for_bit`).
//!
//! The lanes take the common path only: the two x axes not antiparallel, and a swing that
//! is exactly zero (bodies turning in the plane of the hinge) or small enough for the
//! series of [`angle_over_sine`](super::angle_over_sine) (a blocked swing, far below
//! 1e-3 rad). A twist unwrapped past half a turn (a wheel that has turned) is in it: its
//! half turns are applied lane by lane, as [`with_half_turns`](super::with_half_turns)
//! does. When a lane leaves the common path, the four joints are measured one by one by
//! the scalar code instead (`false`), which takes every path.

use super::{with_half_turns, wrap_pi, JointFrames, MeasureState, Measured, RotationMeasure};
use crate::lanes::F4;
use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;

/// A quaternion in lanes, by nalgebra's coordinates: `[i, j, k, w]`.
type Q4 = [F4; 4];

/// The lanes of four unit quaternions.
#[cfg_attr(not(debug_assertions), inline(always))]
fn lanes(q: [&UnitQuaternion<f64>; 4]) -> Q4 {
    let c = [&q[0].coords, &q[1].coords, &q[2].coords, &q[3].coords];
    [
        F4([c[0][0], c[1][0], c[2][0], c[3][0]]),
        F4([c[0][1], c[1][1], c[2][1], c[3][1]]),
        F4([c[0][2], c[1][2], c[2][2], c[3][2]]),
        F4([c[0][3], c[1][3], c[2][3], c[3][3]]),
    ]
}

/// `a·b` as nalgebra's `Quaternion * Quaternion` forms it (coordinates `[i, j, k, w]`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn mul(a: &Q4, b: &Q4) -> Q4 {
    [
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
        a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
        a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
    ]
}

/// The rotation matrix of a unit quaternion as nalgebra's `to_rotation_matrix` forms it,
/// by rows.
#[cfg_attr(not(debug_assertions), inline(always))]
fn rotation_rows(q: &Q4) -> [[F4; 3]; 3] {
    let (i, j, k, w) = (q[0], q[1], q[2], q[3]);
    let two = F4::splat(2.0);
    let (ww, ii, jj, kk) = (w * w, i * i, j * j, k * k);
    let (ij, wk, wj) = (i * j * two, w * k * two, w * j * two);
    let (ik, jk, wi) = (i * k * two, j * k * two, w * i * two);
    [
        [ww + ii - jj - kk, ij - wk, wj + ik],
        [wk + ij, ww - ii + jj - kk, jk - wi],
        [ik - wj, wi + jk, ww - ii - jj + kk],
    ]
}

/// [`with_half_turns`] of each lane: `(a, b)` turned by the half turns of `twist − raw`.
/// Out of line and cold: inlined, its reads of single lanes made the compiler split the
/// lanes' arithmetic around it into scalar operations (300 more instructions an
/// island-substep in the contact scene, where no hinge has turned past half a turn).
#[cold]
#[inline(never)]
fn turned(a: F4, b: F4, twist: &[f64; 4], raw: &[f64; 4]) -> (F4, F4) {
    let t = |l: usize| with_half_turns(a.0[l], b.0[l], twist[l] - raw[l]);
    let (t0, t1, t2, t3) = (t(0), t(1), t(2), t(3));
    (F4([t0.0, t1.0, t2.0, t3.0]), F4([t0.1, t1.1, t2.1, t3.1]))
}

/// Whether every lane of `m` is set.
#[cfg_attr(not(debug_assertions), inline(always))]
fn all(m: [bool; 4]) -> bool {
    m[0] & m[1] & m[2] & m[3]
}

/// [`super::measure_rotation`] of four joints measured by [`RotationMeasure::TwistX`]
/// (`frames`, the bodies' rotations `r1` and `r2`, their measure states) written into `out`
/// (four entries), and `true`; or `false`, `out` untouched, when a lane leaves the common
/// path (module docs). Leaves the states alone: the caller records each result
/// ([`MeasureState::record`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn measure_twist_x4(
    frames: [&JointFrames; 4],
    r1: [&UnitQuaternion<f64>; 4],
    r2: [&UnitQuaternion<f64>; 4],
    states: [&MeasureState; 4],
    out: &mut [Measured],
) -> bool {
    debug_assert!(frames.iter().all(|f| f.measure == RotationMeasure::TwistX));
    let one = F4::splat(1.0);
    let two = F4::splat(2.0);
    let local1 = lanes([
        &frames[0].local_frame1,
        &frames[1].local_frame1,
        &frames[2].local_frame1,
        &frames[3].local_frame1,
    ]);
    let local2 = lanes([
        &frames[0].local_frame2,
        &frames[1].local_frame2,
        &frames[2].local_frame2,
        &frames[3].local_frame2,
    ]);
    let f1 = mul(&lanes(r1), &local1);
    let f2 = mul(&lanes(r2), &local2);
    // twist_x from here: q = F1⁻¹·F2 (the conjugate's vector negated, as nalgebra does)
    let q = mul(&[-f1[0], -f1[1], -f1[2], f1[3]], &f2);
    let (qw, qx, qy, qz) = (q[3], q[0], q[1], q[2]);
    let c = one - two * (qy * qy + qz * qz);
    let (ny, nz) = (
        F4::splat(-2.0) * (qx * qz - qw * qy),
        two * (qx * qy + qw * qz),
    );
    let opc = one + c;
    let sn2 = ny * ny + nz * nz;
    let ik = one / (opc * opc + sn2).sqrt();
    let sn = sn2.sqrt();
    // the common path: axes not antiparallel, a swing zero or within the series
    let common = |l: usize| {
        let (sn, c) = (sn.0[l], c.0[l]);
        opc.0[l] > 1e-12 && (sn == 0.0 || (c > 0.0 && sn < 1e-3 * c))
    };
    if !all([common(0), common(1), common(2), common(3)]) {
        return false;
    }
    // angle_over_sine's series, and 0 for no swing
    let x = sn / c;
    let x2 = x * x;
    let series = (one - x2 * (F4::splat(1.0 / 3.0) - x2 * F4::splat(0.2))) / c;
    let swung = |l: usize| if sn.0[l] > 0.0 { series.0[l] } else { 0.0 };
    let r = F4([swung(0), swung(1), swung(2), swung(3)]);
    let (sw, sy, sz, py, pz) = (opc * ik, ny * ik, nz * ik, ny * r, nz * r);
    let ikh = one / (two * (one + sw)).sqrt();
    let (hw, hy, hz) = ((one + sw) * ikh, sy * ikh, sz * ikh);
    let t_w = sw * qw + (sy * qy + sz * qz);
    let t_i = sw * qx - (sy * qz - sz * qy);
    let flip = |l: usize| t_w.0[l] < 0.0;
    let sign = |l: usize, v: &F4| if flip(l) { -v.0[l] } else { v.0[l] };
    let tw = F4([sign(0, &t_w), sign(1, &t_w), sign(2, &t_w), sign(3, &t_w)]);
    let ti = F4([sign(0, &t_i), sign(1, &t_i), sign(2, &t_i), sign(3, &t_i)]);
    // the raw twist in lanes (`atan2_x4`: the scalar measure's bits), its unwrapping lane
    // by lane
    let raw = (two * super::atan2::atan2_x4(ti, tw)).0;
    let mut twist = [0.0; 4];
    for l in 0..4 {
        let prev = states[l].prev_theta.map_or(raw[l], |p| p.x);
        twist[l] = prev + wrap_pi(raw[l] - prev);
    }
    // half_twist_parts within half a turn
    let n = (tw * tw + ti * ti).sqrt();
    let s = n + tw;
    let rh = one / (two * n * s).sqrt();
    let (a, b) = (s * rh, ti * rh);
    // the half turns of a twist unwrapped past ±π, lane by lane, where a lane has some
    // (with_half_turns leaves the others as they are)
    let within = |l: usize| (twist[l] - raw[l]).abs() < PI;
    let (a, b) = if all([within(0), within(1), within(2), within(3)]) {
        (a, b)
    } else {
        turned(a, b, &twist, &raw)
    };
    // E = F1·(S_l^{1/2}·(a + b·i)), nalgebra's Quaternion::new(w, i, j, k)
    let local = [b * hw, a * hy + b * hz, a * hz - b * hy, a * hw];
    let e = mul(&f1, &local);
    let m = rotation_rows(&e);
    let (cos_h, sin_h) = (a * a - b * b, two * a * b);
    let s_y = cos_h * py + sin_h * pz;
    let s_z = cos_h * pz - sin_h * py;
    // written in place (a returned array of four is 832 bytes copied)
    for (l, out) in out[..4].iter_mut().enumerate() {
        let e = UnitQuaternion::new_unchecked(Quaternion::new(
            e[3].0[l], e[0].0[l], e[1].0[l], e[2].0[l],
        ));
        let row = |r: usize| [m[r][0].0[l], m[r][1].0[l], m[r][2].0[l]];
        let (r0, r1, r2) = (row(0), row(1), row(2));
        let matrix = Matrix3::new(
            r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2],
        );
        *out = (
            Vector3::new(twist[l], s_y.0[l], s_z.0[l]),
            e,
            Rotation3::from_matrix_unchecked(matrix),
            None,
        );
    }
    true
}

#[cfg(test)]
mod tests {
    use super::super::{measure_rotation, JointFrames, MeasureState, RotationMeasure};
    use super::measure_twist_x4;
    use nalgebra::{UnitQuaternion, Vector3};

    fn frames(local1: UnitQuaternion<f64>, local2: UnitQuaternion<f64>) -> JointFrames {
        JointFrames {
            local_anchor1: Vector3::zeros(),
            local_anchor2: Vector3::zeros(),
            local_frame1: local1,
            local_frame2: local2,
            delta0: Vector3::zeros(),
            measure: RotationMeasure::TwistX,
            translation: super::super::TranslationMeasure::MidPoint,
        }
    }

    /// Four hinges at random poses, each body 2 turned about the hinge by an angle that
    /// wanders over several turns (so the twist is unwrapped from the previous one, past ±π
    /// with its half turns) and tilted off it by a blocked swing of 1e-9 to 1e-4 rad or none:
    /// the lanes give every number of [`measure_rotation`]'s result with its bits, over
    /// consecutive measures that carry the state; a swing of 0.01 rad (past the series) and
    /// antiparallel axes fall back (`false`).
    // (a swing of 3.14159 rad: axes close to antiparallel, deliberately not π)
    #[allow(clippy::approx_constant)]
    #[test]
    fn four_twists_equal_the_scalar_measure_bit_for_bit() {
        let mut rand = crate::test_rand::xorshift(0x2545_f491_4f6c_dd1du64);
        let unit = |rand: &mut dyn FnMut() -> f64| {
            let v = Vector3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5);
            UnitQuaternion::from_scaled_axis(v * 6.0)
        };
        let mut compared = 0;
        for round in 0..200 {
            let fr: Vec<JointFrames> = (0..4)
                .map(|_| frames(unit(&mut rand), unit(&mut rand)))
                .collect();
            let r1: Vec<UnitQuaternion<f64>> = (0..4).map(|_| unit(&mut rand)).collect();
            let mut scalar = [MeasureState::default(); 4];
            let mut lanes = [MeasureState::default(); 4];
            let mut angle: Vec<f64> = (0..4).map(|_| 30.0 * (rand() - 0.5)).collect();
            for step in 0..6 {
                // body 2 such that F2 = F1·R_x(angle)·(small tilt about y and z)
                let r2: Vec<UnitQuaternion<f64>> = (0..4)
                    .map(|l| {
                        // steps under half a turn, so that the unwrapping follows them
                        angle[l] += 2.5 * (rand() - 0.5);
                        // no swing at all in one round of three (a hinge turning in its
                        // plane), else a blocked one
                        let tilt = if round % 3 == 0 && l != 1 {
                            0.0
                        } else {
                            10f64.powf(-9.0 + 5.0 * rand())
                        };
                        let tilt = if round == 7 && step == 3 && l == 2 {
                            0.01
                        } else {
                            tilt
                        };
                        let rel = UnitQuaternion::from_scaled_axis(Vector3::x() * angle[l])
                            * UnitQuaternion::from_scaled_axis(Vector3::new(
                                0.0,
                                tilt * (rand() - 0.5),
                                tilt * (rand() - 0.5),
                            ));
                        r1[l] * fr[l].local_frame1 * rel * fr[l].local_frame2.inverse()
                    })
                    .collect();
                let expected: Vec<_> = (0..4)
                    .map(|l| measure_rotation(&fr[l], &r1[l], &r2[l], &mut scalar[l]))
                    .collect();
                let mut got = expected.clone();
                for m in &mut got {
                    *m = (
                        Vector3::zeros(),
                        UnitQuaternion::identity(),
                        Default::default(),
                        None,
                    );
                }
                let in_lanes = measure_twist_x4(
                    [&fr[0], &fr[1], &fr[2], &fr[3]],
                    [&r1[0], &r1[1], &r1[2], &r1[3]],
                    [&r2[0], &r2[1], &r2[2], &r2[3]],
                    [&lanes[0], &lanes[1], &lanes[2], &lanes[3]],
                    &mut got,
                );
                match in_lanes {
                    true => {
                        for l in 0..4 {
                            let (a, b) = (&got[l], &expected[l]);
                            let bits = |m: &super::Measured| {
                                let mut v: Vec<u64> = m.0.iter().map(|x| x.to_bits()).collect();
                                v.extend(m.1.coords.iter().map(|x| x.to_bits()));
                                v.extend(m.2.matrix().iter().map(|x| x.to_bits()));
                                v
                            };
                            assert_eq!(bits(a), bits(b), "round {round} step {step} lane {l}");
                            assert!(a.3.is_none() && b.3.is_none());
                            lanes[l].record(a);
                            compared += 1;
                        }
                    }
                    false => {
                        // the caller's fallback: the scalar measure, state recorded by it
                        for l in 0..4 {
                            lanes[l].record(&expected[l]);
                        }
                    }
                }
            }
        }
        // nearly every measure ran in the lanes
        assert!(
            compared > 4 * 200 * 6 * 9 / 10,
            "{compared} measured in lanes"
        );
        // past the series and antiparallel axes: the scalar path; a twist unwrapped past π,
        // and none at all: the lanes
        let fr = frames(UnitQuaternion::identity(), UnitQuaternion::identity());
        let id = UnitQuaternion::identity();
        let blocked = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 1e-6, 0.0));
        let past_pi = UnitQuaternion::from_scaled_axis(Vector3::new(-3.0, 1e-6, 0.0));
        let fresh = MeasureState::default();
        let at_3 = MeasureState {
            prev_theta: Some(Vector3::new(3.0, 0.0, 0.0)),
            jump: 0.0,
        };
        let x4 = |rel: &UnitQuaternion<f64>, s: &MeasureState| {
            measure_twist_x4(
                [&fr; 4],
                [&id; 4],
                [&blocked, &blocked, rel, &blocked],
                [&fresh, &fresh, s, &fresh],
                &mut [(Vector3::zeros(), id, Default::default(), None); 4],
            )
        };
        assert!(x4(&blocked, &fresh));
        assert!(x4(&past_pi, &fresh));
        assert!(x4(&past_pi, &at_3));
        let planar = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.0, 0.0));
        assert!(x4(&planar, &fresh));
        for (rel, s) in [
            (
                UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.01, 0.0)),
                &fresh,
            ),
            (
                UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 3.14159, 0.0)),
                &fresh,
            ),
        ] {
            assert!(!x4(&rel, s));
        }
    }
}
