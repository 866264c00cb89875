//! Checks of single scene values, each error naming its field: finite numbers within
//! [`MAX_VALUE`](super::MAX_VALUE), positive and non-negative numbers, rotations; and the
//! conversion of checked values into rapier's vectors.

use super::MAX_VALUE;
use crate::rapier::prelude::{Rotation, Vector};
use crate::scene::schema::RotationSpec;
use crate::scene::{FieldPath, SceneError, Source};

/// `v` if it is finite and `|v| <= MAX_VALUE`.
pub(super) fn finite(src: &Source, path: &FieldPath, v: f64) -> Result<f64, SceneError> {
    if !v.is_finite() {
        Err(src.error(
            path,
            format!("{v} is not a finite number (NaN and infinity are refused)"),
        ))
    } else if v.abs() > MAX_VALUE {
        Err(src.error(
            path,
            format!(
                "{} is out of range: expected |value| <= {MAX_VALUE:e}",
                crate::error::compact_number(v.to_string())
            ),
        ))
    } else {
        Ok(v)
    }
}

/// `v` if each of its values is [`finite`] (an error names the value's index).
pub(super) fn finite_array<const N: usize>(
    src: &Source,
    path: &FieldPath,
    v: [f64; N],
) -> Result<[f64; N], SceneError> {
    for (i, x) in v.iter().enumerate() {
        finite(src, &path.index(i), *x)?;
    }
    Ok(v)
}

/// `v` if it is [`finite`] and `> 0`.
pub(super) fn positive(src: &Source, path: &FieldPath, v: f64) -> Result<f64, SceneError> {
    finite(src, path, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(src.error(path, format!("{v}: expected a value > 0")))
    }
}

/// `v` if it is [`finite`] and `>= 0` (times, frequencies).
pub(super) fn non_negative(src: &Source, path: &FieldPath, v: f64) -> Result<f64, SceneError> {
    let v = finite(src, path, v)?;
    if v < 0.0 {
        return Err(src.error(path, format!("{v}: expected >= 0")));
    }
    Ok(v)
}

/// A scene rotation: `axis` and `angle` \[rad\], or a unit `quaternion` `[x, y, z, w]`.
pub(super) fn rotation(
    src: &Source,
    path: &FieldPath,
    r: &RotationSpec,
) -> Result<Rotation, SceneError> {
    match (&r.axis, &r.angle, &r.quaternion) {
        (Some(axis), Some(angle), None) => {
            let axis = finite_array(src, &path.key("axis"), *axis)?;
            let angle = finite(src, &path.key("angle"), *angle)?;
            let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            if n < 1e-12 {
                return Err(src.error(&path.key("axis"), "the rotation axis is zero"));
            }
            let q = nalgebra::UnitQuaternion::from_axis_angle(
                &nalgebra::Unit::new_normalize(nalgebra::Vector3::from(axis)),
                angle,
            );
            Ok(crate::dynamics::to_quat(&q))
        }
        (None, None, Some(q)) => {
            let q = finite_array(src, &path.key("quaternion"), *q)?;
            let n = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
            if (n - 1.0).abs() > 1e-3 {
                return Err(src.error(
                    &path.key("quaternion"),
                    format!("norm {n}: expected a unit quaternion [x, y, z, w]"),
                ));
            }
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q[3], q[0], q[1], q[2],
            ));
            Ok(crate::dynamics::to_quat(&q))
        }
        _ => Err(src.error(
            path,
            "expected either `axis` and `angle` [rad], or `quaternion` = [x, y, z, w]",
        )),
    }
}

/// A checked vector times the factor `f` of its unit, as rapier's vector.
pub(super) fn vec3(v: [f64; 3], f: f64) -> Vector {
    Vector::new((v[0] * f) as _, (v[1] * f) as _, (v[2] * f) as _)
}

/// `items` joined by commas, or `none` (for messages listing what exists).
pub(super) fn listed<T: AsRef<str>>(items: Vec<T>) -> String {
    if items.is_empty() {
        "none".into()
    } else {
        items
            .iter()
            .map(|i| i.as_ref())
            .collect::<Vec<_>>()
            .join(", ")
    }
}
