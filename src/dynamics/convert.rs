//! Conversions between rapier's glam math (f32) and the law's nalgebra f64.

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
