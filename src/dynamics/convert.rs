//! Conversions between rapier's glam math (f32, or f64 with the `f64` feature) and the
//! law's nalgebra f64, and (with `f64`) from the f32 glam of the robot loaders to the world's
//! f64 glam. The one place where the crate changes precision.

use crate::rapier::math::{Rotation, Vector};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// glam vector → nalgebra f64.
pub fn from_vec3(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// nalgebra f64 → glam vector.
pub fn to_vec3(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x as _, v.y as _, v.z as _)
}

/// glam quaternion → nalgebra f64 unit quaternion.
pub fn from_quat(q: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(
        q.w as f64, q.x as f64, q.y as f64, q.z as f64,
    ))
}

/// nalgebra f64 unit quaternion → glam quaternion.
pub fn to_quat(q: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(q.i as _, q.j as _, q.k as _, q.w as _).normalize()
}

/// The robot loaders' glam (rapier3d, f32) → the world's (rapier3d-f64): exact, f32 → f64.
#[cfg(feature = "f64")]
pub(crate) mod from_f32 {
    use crate::rapier::math::{Pose, Rotation, Vector};

    /// f32 vector → f64 vector.
    pub(crate) fn vec3(v: rapier3d::math::Vector) -> Vector {
        v.as_dvec3()
    }

    /// f32 quaternion → f64 quaternion (not renormalised: the f32 values, exactly).
    pub(crate) fn quat(q: rapier3d::math::Rotation) -> Rotation {
        q.as_dquat()
    }

    /// f32 pose → f64 pose.
    pub(crate) fn pose(p: &rapier3d::math::Pose) -> Pose {
        Pose::from_parts(vec3(p.translation), quat(p.rotation))
    }
}
