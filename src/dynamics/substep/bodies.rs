//! The bodies' side of a substep: a rapier body's pose and velocities in f64, its solver
//! view (inverse mass, world inertia at its current rotation, external velocity change,
//! gyroscopic term) and reduced masses.

use crate::dynamics::convert::{from_quat, from_vec3};
use crate::dynamics::solve::{MassBlocks, SolverBody};
use crate::kinematics::BodyPose;
use crate::rapier::dynamics::{RigidBody, RigidBodyType};
use crate::rapier::math::{Pose, Real, Vector};
use nalgebra::{Matrix3, Vector3, Vector6};

/// The smallest velocity component \[m/s or rad/s\] the apply stage writes into a rapier
/// body ([`flush_velocity`]): below it, 0.
///
/// The solve's f64 round-off leaves components of order 1e-19 where the motion has none (a
/// hinge swinging in its plane: its rod's velocity out of the plane). In single precision
/// rapier's integrator multiplies two of them (its quaternion update `(1, h·ω/2)·q`) into
/// numbers below `f32::MIN_POSITIVE` (1.2e-38), subnormal ones, which the processor
/// handles far slower than normal ones: the 1000 pendulums of the solver bench stepped
/// 16 % faster with them flushed, 10 000 21 % faster (2026-12-05); the scenes whose
/// components the round-off leaves larger (the chain, the trees, the contact scene) as
/// before. A body at 1e-15 m/s moves a micrometre in 30 years: far below what its f32
/// pose resolves (an ulp of 1 m is 1.2e-7 m).
pub(crate) const VELOCITY_FLOOR: Real = 1e-15;

/// `v` with every component whose magnitude is below [`VELOCITY_FLOOR`] set to 0 (a NaN
/// kept: the health checks name it).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn flush_velocity(v: Vector) -> Vector {
    Vector::select(
        v.abs().cmplt(Vector::splat(VELOCITY_FLOOR)),
        Vector::ZERO,
        v,
    )
}

#[cfg(test)]
#[test]
fn velocities_below_the_floor_are_flushed_and_the_rest_kept_bit_for_bit() {
    let v = Vector::new(3e-16, -2.5, -9e-16);
    assert_eq!(flush_velocity(v), Vector::new(0.0, -2.5, 0.0));
    let kept = Vector::new(1e-15, -1.0000001e-15, 7.0);
    assert_eq!(flush_velocity(kept), kept);
    let nan = flush_velocity(Vector::new(Real::NAN, 1e-20, Real::INFINITY));
    assert!(nan.x.is_nan() && nan.y == 0.0 && nan.z == Real::INFINITY);
}

/// Pose and velocity of a rapier body in the law's f64.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn body_pose(b: &RigidBody) -> BodyPose {
    BodyPose {
        translation: from_vec3(b.translation()),
        rotation: from_quat(*b.rotation()),
        com: from_vec3(b.center_of_mass()),
        linvel: from_vec3(b.linvel()),
        angvel: from_vec3(b.angvel()),
    }
}

/// [`body_pose`] of a watched body (fixed, kinematic, asleep or disabled) over the substep
/// `h` \[s\]: a kinematic body moved by its next position (`KinematicPositionBased`,
/// `set_next_kinematic_position`) gets the velocity rapier gives it in the substep, the way
/// from its pose to that one in `h` (`RigidBodyPosition::interpolate_velocity`, rapier's
/// sums), not the one of its last step, which rapier keeps until it steps: a body the user
/// stopped still moved in the joints' view, and one sent on its way after a substep at
/// rest did not move in it (a pendulum hung from a base shaken at 5 Hz opened 4.5 mm).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn watched_pose(b: &RigidBody, h: f64) -> BodyPose {
    let mut pose = body_pose(b);
    if b.body_type() == RigidBodyType::KinematicPositionBased {
        let p = *b.position();
        let shift = Pose::from_translation(p * b.mass_properties().local_mprops.local_com);
        let d = shift.inverse() * *b.next_position() * p.inverse() * shift;
        let inv_h = 1.0 / h as Real;
        pose.linvel = from_vec3(d.translation * inv_h);
        pose.angvel = from_vec3(d.rotation.to_scaled_axis() * inv_h);
    }
    pose
}

/// Whether [`body_pose`] of `b` is finite ([`BodyPose::is_finite`]), from rapier's numbers
/// without converting them: every one finite, and the rotation's squared norm (in f64, as
/// the conversion normalises it) positive. The conversion's normalisation is a square root
/// and a division per body, which the check after each step paid for nothing.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn pose_is_finite(b: &RigidBody) -> bool {
    let q = b.rotation();
    let (x, y, z, w) = (q.x as f64, q.y as f64, q.z as f64, q.w as f64);
    let n2 = (x * x + y * y) + (z * z + w * w);
    let mut all = [
        x, y, z, w, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    ];
    for (k, v) in [b.translation(), b.center_of_mass(), b.linvel(), b.angvel()]
        .iter()
        .enumerate()
    {
        all[4 + 3 * k..7 + 3 * k].copy_from_slice(&[v.x as f64, v.y as f64, v.z as f64]);
    }
    let sum = crate::kinematics::zero_unless_not_finite(&all);
    sum == 0.0 && n2 > 0.0 && n2.is_finite()
}

/// What the gather stage derives from a body's mass properties (reciprocals, the principal
/// frame in f64, the mean inertia), kept from one substep to the next while the rapier values
/// it was derived from compare equal: 12 divisions and 4 conversions a body a substep that
/// gave the same bits every time (rapier changes the mass properties only when a collider,
/// a lock or an additional mass changes).
#[derive(Debug, Clone, Copy)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct MassCache {
    /// The rapier values the rest was derived from (`None`: nothing derived yet).
    key: Option<MassKey>,
    /// Inverse masses along the world axes (rapier's `effective_inv_mass`) \[1/kg\].
    im: Vector3<f64>,
    /// `1/im` where every inverse mass is positive (`None`: a translation is locked or a
    /// mass is zero).
    mass: Option<Vector3<f64>>,
    /// 1 along the axes whose translation is free (inverse mass > 0), else 0.
    free: Vector3<f64>,
    /// The principal frame in the body's local frame.
    principal: nalgebra::UnitQuaternion<f64>,
    /// Whether [`Self::principal`] is the identity (every body whose colliders are
    /// symmetric about its local axes: a capsule, a box, a ball), whose world principal
    /// frame is then its rotation without a product.
    principal_is_identity: bool,
    /// Inverse principal inertias \[1/(kg·m²)\].
    inv_p: Vector3<f64>,
    /// Principal inertias `1/inv_p` (0 where `inv_p` is not positive) \[kg·m²\].
    p: Vector3<f64>,
    /// [`mean_inertia`] \[kg·m²\].
    pub(crate) mean_inertia: f64,
}

/// The rapier mass properties a [`MassCache`] is derived from.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
struct MassKey {
    inv_mass: crate::rapier::math::Vector,
    inv_principal: crate::rapier::math::Vector,
    frame: crate::rapier::math::Rotation,
}

impl MassCache {
    /// Nothing derived yet.
    pub(crate) const EMPTY: MassCache = MassCache {
        key: None,
        im: Vector3::new(0.0, 0.0, 0.0),
        mass: None,
        free: Vector3::new(0.0, 0.0, 0.0),
        principal: nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
            1.0, 0.0, 0.0, 0.0,
        )),
        principal_is_identity: true,
        inv_p: Vector3::new(0.0, 0.0, 0.0),
        p: Vector3::new(0.0, 0.0, 0.0),
        mean_inertia: 0.0,
    };

    /// Derives again from `b` unless its mass properties compare equal to the last ones (a
    /// NaN never does: derived again every time, as before the cache). `==` treats ±0 as
    /// equal, which derives nothing different: a zero inverse mass or inertia is mapped to
    /// 0 or excluded below whatever its sign. `true` where it derived again (the first
    /// time after an analysis, or the body's mass properties changed: what the set's mass
    /// check reads, `KjointSet::check_masses`).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn update(&mut self, b: &RigidBody) -> bool {
        let mp = b.mass_properties();
        let key = MassKey {
            inv_mass: mp.effective_inv_mass,
            inv_principal: mp.local_mprops.inv_principal_inertia,
            frame: mp.local_mprops.principal_inertia_local_frame,
        };
        if self.key == Some(key) {
            return false;
        }
        let im = from_vec3(key.inv_mass);
        let inv_p = from_vec3(key.inv_principal);
        let principal = from_quat(key.frame);
        *self = MassCache {
            key: Some(key),
            im,
            mass: im.iter().all(|x| *x > 0.0).then(|| im.map(|x| 1.0 / x)),
            free: im.map(|x| if x > 0.0 { 1.0 } else { 0.0 }),
            principal,
            principal_is_identity: principal == nalgebra::UnitQuaternion::identity(),
            inv_p,
            p: inv_p.map(|x| if x > 0.0 { 1.0 / x } else { 0.0 }),
            mean_inertia: mean_inertia(b),
        };
        true
    }
}

/// The principal axes of a body in the world at its current `rotation` (columns).
#[cfg_attr(not(debug_assertions), inline(always))]
fn world_axes(rotation: &nalgebra::UnitQuaternion<f64>, cache: &MassCache) -> Matrix3<f64> {
    // (`q·1` is `q` bit for bit: each component is one product by 1 and three by 0)
    let world_principal = if cache.principal_is_identity {
        *rotation
    } else {
        rotation * cache.principal
    };
    world_principal.to_rotation_matrix().into_inner()
}

/// The solver's view of a body, written into `out`, but for the gyroscopic term
/// ([`add_gyroscopic_change`], which the gather stage adds in a loop of its own): rapier
/// applies gravity and user forces itself during its step, the set applies this one with the
/// joint impulses. The angular part of `out.dv_ext` is `I⁻¹·τ·h` when the body has a user
/// torque `τ` (then `true` is returned), zero otherwise. `rotation` is the body's rotation as
/// [`body_pose`] read it; `cache` what was derived from its mass properties (brought up to
/// date here; `rederived` set where it was derived again, [`MassCache::update`]). `axes`:
/// the body's principal axes in the world at `rotation`, written here.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn solver_body(
    b: &RigidBody,
    rotation: &nalgebra::UnitQuaternion<f64>,
    g: &Vector3<f64>,
    h: f64,
    cache: &mut MassCache,
    out: &mut SolverBody,
    rederived: &mut bool,
    axes: &mut Matrix3<f64>,
) -> bool {
    *rederived |= cache.update(b);
    let im = cache.im;
    // the principal axes in the world at the current rotation
    *axes = world_axes(rotation, cache);
    let axes = &*axes;
    let inv_p = cache.inv_p;
    let (inv_i, inertia) = world_inertia(b, axes, &inv_p, &cache.p);
    out.inv_mass = MassBlocks {
        linear: im,
        angular: inv_i,
    };
    // gravity and user forces/torques over the substep
    let f = from_vec3(b.user_force());
    let tau = from_vec3(b.user_torque());
    let gs = b.gravity_scale() as f64;
    let dv = (g * gs).component_mul(&cache.free) * h + f.component_mul(&im) * h;
    // (no user torque, the commonest case: `I⁻¹·0·h + gyro` is `gyro`, the product skipped)
    let torque = tau != Vector3::zeros();
    let dw = if torque {
        inv_i * tau * h
    } else {
        Vector3::zeros()
    };
    out.dv_ext = Vector6::new(dv.x, dv.y, dv.z, dw.x, dw.y, dw.z);
    out.mass = match (inertia, cache.mass) {
        (Some(i), Some(m)) => Some(MassBlocks {
            linear: m,
            angular: i,
        }),
        _ => None,
    };
    torque
}

/// How the set integrates a body's gyroscopic term ([`gyroscopic_change`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) enum Gyroscopic {
    /// rapier integrates it (the body's gyroscopic forces were off before the set took it).
    Off,
    /// The body turns freely: the term keeps `|L|` by the part of `L` across `ω` and the part
    /// along it.
    Free,
    /// A joint with one free rotation holds the body to a fixed body (a rotor on its axle):
    /// the term keeps `|L|` by the part of `L` across `ω` alone. (Not to a kinematic body,
    /// which may turn: `ω` then leaves the joint's axis.)
    OneAxis,
}

/// Adds to `out.dv_ext` ([`solver_body`], `torque` what it returned) the gyroscopic velocity
/// change `Δω` \[rad/s\] over the substep when the set integrates it (`gyroscopic`; zero
/// for [`Gyroscopic::Off`]), and returns it: `Δω_ext = I⁻¹·τ·h + Δω_gyro`, or `Δω_gyro` alone without a
/// user torque (the same sums as when [`solver_body`] made both). `pose` is the body's pose
/// as [`body_pose`] read it, `axes` and `cache` its principal axes in the world and its
/// [`MassCache`] as [`solver_body`] left them.
///
/// A loop of its own in the gather stage: [`gyroscopic_change`] is a chain of a division and
/// a square root (about 80 cycles) that the processor overlaps between bodies only when
/// little else sits between them (5 % of the joint set's time in the contact scene, most
/// of it waiting, when it ran inside [`solver_body`]).
#[cfg_attr(not(debug_assertions), inline(always))]
#[allow(clippy::too_many_arguments)]
pub(super) fn add_gyroscopic_change(
    pose: &BodyPose,
    axes: &Matrix3<f64>,
    cache: &MassCache,
    h: f64,
    gyroscopic: Gyroscopic,
    torque: bool,
    out: &mut SolverBody,
) -> Vector3<f64> {
    let gyro = if gyroscopic == Gyroscopic::Off {
        Vector3::zeros()
    } else {
        let one_axis = gyroscopic == Gyroscopic::OneAxis;
        gyroscopic_change(pose.angvel, axes, &cache.inv_p, &cache.p, h, one_axis)
    };
    // the whole `dv_ext` made in registers and stored once: the caller copies it at once,
    // and a load of 48 bytes from a store of 24 waits for the store to retire (no
    // forwarding), which chained one body's division and root to the next one's
    let dv = out.dv_ext;
    let dw = if torque {
        Vector3::new(dv[3], dv[4], dv[5]) + gyro
    } else {
        gyro
    };
    out.dv_ext = Vector6::new(dv[0], dv[1], dv[2], dw.x, dw.y, dw.z);
    gyro
}

/// The gyroscopic velocity change `Δω` [rad/s] over `h`: rapier's own momentum-preserving
/// explicit correction (`RigidBody::angvel_with_gyroscopic_forces`, as Jolt does), in f64
/// from the principal frame `R` (`axes`), the inverse principal inertias `inv_p` and the
/// principal inertias `p` (0 where `inv_p` is not positive). With `ω_p = Rᵀ·ω` and `L =
/// I_p·ω_p` in principal axes:
///
/// ```text
/// L' = L − h·ω_p × L,      L'' = L'·|L|/|L'|,      Δω = R·(I_p⁻¹·L'') − ω
/// ```
///
/// (the explicit term, rescaled so that it turns the angular momentum without changing its
/// magnitude). The rescaling shortens `L` along `ω` by `½·h²·|ω × L|²/|L|²·(L·ω̂)` a
/// substep, which keeps a free body's energy to second order in `h` (its share along `ω`
/// takes back most of what the explicit step gives, `½·ΔL·I⁻¹·ΔL`). A body that a joint holds to one axis (`one_axis`:
/// [`Gyroscopic::OneAxis`], a rotor on its axle) turns about that axis, and the joint cannot
/// give back what is taken along it (it blocks the other rotations, not the axis): its spin
/// decayed at first order in `h` with no joint doing work (a disc tilted 0.1 rad on a
/// revolute joint at 50 rad/s lost 20 % of its energy in 10 s at 4 substeps). Such a body
/// keeps `|L|` with the part of `L` across `ω`, `L⊥ = L − (L·ω̂)·ω̂`, alone:
///
/// ```text
/// L'' = L − h·ω_p × L − α·L⊥,      α = 1 − √(1 − h²·|ω|²)
/// ```
///
/// (`ω × L` is orthogonal to `L` and to `ω`, so to `L⊥`, and `|L''| = |L|`): `L'' − L` has no
/// part along `ω`, and what the step gives across it is what the joint takes. (For a free
/// body that form gains energy, `½·ΔL·I⁻¹·ΔL` a substep, 0.6 % in 2 s of a body tumbling
/// about its intermediate axis; hence the two.) Where `h·|ω| ≥ 1` (beyond what rapier
/// integrates anyway) the first form.
#[cfg_attr(not(debug_assertions), inline(always))]
fn gyroscopic_change(
    w: Vector3<f64>,
    r: &Matrix3<f64>,
    inv_p: &Vector3<f64>,
    p: &Vector3<f64>,
    h: f64,
    one_axis: bool,
) -> Vector3<f64> {
    let wp = r.transpose() * w;
    let l = p.component_mul(&wp);
    let l1 = l - h * wp.cross(&l);
    if one_axis {
        let w2 = wp.norm_squared();
        let hw2 = h * h * w2;
        if hw2 < 1.0 && w2 > 0.0 {
            let l_across = l - wp * (l.dot(&wp) / w2);
            let alpha = 1.0 - (1.0 - hw2).sqrt();
            return r * inv_p.component_mul(&(l1 - l_across * alpha)) - w;
        }
    }
    let n1 = l1.norm_squared();
    if !(n1 > 0.0) {
        return Vector3::zeros();
    }
    let l2 = l1 * (l.norm_squared() / n1).sqrt();
    r * inv_p.component_mul(&l2) - w
}

/// `R·diag(d)·Rᵀ`, symmetric by construction: `S_ik = Σ_j (R_ij·d_j)·R_kj` for `i ≤ k`
/// (6 entries of 3 terms instead of two general 3×3 products).
#[cfg_attr(not(debug_assertions), inline(always))]
fn sandwich(r: &Matrix3<f64>, d: &Vector3<f64>) -> Matrix3<f64> {
    let a = Matrix3::from_fn(|i, j| r[(i, j)] * d[j]);
    let e =
        |i: usize, k: usize| a[(i, 0)] * r[(k, 0)] + a[(i, 1)] * r[(k, 1)] + a[(i, 2)] * r[(k, 2)];
    let (s00, s01, s02, s11, s12, s22) = (e(0, 0), e(0, 1), e(0, 2), e(1, 1), e(1, 2), e(2, 2));
    Matrix3::new(s00, s01, s02, s01, s11, s12, s02, s12, s22)
}

/// World inverse inertia at the body's **current** rotation (rapier's cached one lags a
/// substep behind, which matters for stiff rotational DOFs on slender bodies), with rapier's
/// rotation locks applied, and the world inertia itself when no rotation is locked and every
/// principal inertia is finite. `r`: the principal axes in the world; `inv_p`: the inverse
/// principal inertias; `p`: the principal inertias (`1/inv_p` where `inv_p > 0`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn world_inertia(
    b: &RigidBody,
    r: &Matrix3<f64>,
    inv_p: &Vector3<f64>,
    p: &Vector3<f64>,
) -> (Matrix3<f64>, Option<Matrix3<f64>>) {
    if !b.is_dynamic() {
        return (Matrix3::zeros(), None);
    }
    let mut inv = sandwich(r, inv_p);
    let locked = b.is_rotation_locked();
    if locked.iter().any(|l| *l) {
        for i in 0..3 {
            if locked[i] {
                for k in 0..3 {
                    inv[(i, k)] = 0.0;
                    inv[(k, i)] = 0.0;
                }
            }
        }
        return (inv, None);
    }
    let inertia = inv_p.iter().all(|x| *x > 0.0).then(|| sandwich(r, p));
    (inv, inertia)
}

/// Mean of the principal inertias \[kg·m²\].
pub(crate) fn mean_inertia(b: &RigidBody) -> f64 {
    let p = from_vec3(b.mass_properties().local_mprops.principal_inertia());
    (p.x + p.y + p.z) / 3.0
}

/// `m1·m2/(m1+m2)`, with a non-dynamic side (`None`) counting as infinite.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn reduced(m1: Option<f64>, m2: Option<f64>) -> f64 {
    match (m1, m2) {
        (Some(a), Some(b)) => {
            if a + b > 0.0 {
                a * b / (a + b)
            } else {
                0.0
            }
        }
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rapier::dynamics::RigidBodyBuilder;
    use crate::rapier::math::{Real, Rotation, Vector};

    /// The check without the conversion says what the converted pose says, on finite
    /// bodies, on every kind of number that is not, and on rotations whose norm vanishes
    /// or overflows in rapier's precision.
    #[test]
    fn the_raw_check_agrees_with_the_converted_pose() {
        let bad = [Real::NAN, Real::INFINITY, Real::NEG_INFINITY];
        let mut bodies = vec![RigidBodyBuilder::dynamic()
            .translation(Vector::new(1.0, -2.0, 3.0))
            .linvel(Vector::new(0.5, 0.0, -1.0))
            .angvel(Vector::new(0.0, 2.0, 0.0))
            .build()];
        for (i, v) in bad.iter().enumerate() {
            let mut b = bodies[0].clone();
            match i {
                0 => b.set_translation(Vector::new(*v, 0.0, 0.0), false),
                1 => b.set_linvel(Vector::new(0.0, *v, 0.0), false),
                _ => b.set_angvel(Vector::new(0.0, 0.0, *v), false),
            }
            bodies.push(b);
        }
        for q in [
            Rotation::from_xyzw(0.0, 0.0, 0.0, 0.0),
            Rotation::from_xyzw(1e-30, 0.0, 0.0, 0.0),
            Rotation::from_xyzw(Real::MAX, Real::MAX, 0.0, 0.0),
            Rotation::from_xyzw(Real::NAN, 0.0, 0.0, 1.0),
            Rotation::from_xyzw(0.0, 0.0, 0.6, 0.8),
        ] {
            let mut b = bodies[0].clone();
            b.set_rotation(q, false);
            bodies.push(b);
        }
        let mut finite = 0;
        for b in &bodies {
            let expected = body_pose(b).is_finite();
            assert_eq!(pose_is_finite(b), expected, "{:?}", b.rotation());
            finite += expected as usize;
        }
        // the plain body, the rotation of norm 1, and the tiny one, which the conversion
        // normalises in f64 (its squared norm, 1e-60, is zero in f32)
        assert_eq!(finite, 3);
    }
}
