//! Mechanical energy of the bodies, for energy-balance checks.

use super::convert::{from_quat, from_vec3};
use crate::rapier::dynamics::{RigidBody, RigidBodySet};
use crate::rapier::math::Vector;
use nalgebra::{Matrix3, Vector3};

/// Kinetic energy `½m|v|² + ½ωᵀIω` of a dynamic body \[J\], in f64.
pub fn kinetic_energy(body: &RigidBody) -> f64 {
    if !body.is_dynamic() {
        return 0.0;
    }
    let mp = body.mass_properties().local_mprops;
    let m = mp.mass() as f64;
    let v = from_vec3(body.linvel());
    let w = from_vec3(body.angvel());
    let rot = from_quat(*body.rotation()) * from_quat(mp.principal_inertia_local_frame);
    let pi = from_vec3(mp.principal_inertia());
    let r = rot.to_rotation_matrix();
    let inertia: Matrix3<f64> = r.matrix() * Matrix3::from_diagonal(&pi) * r.matrix().transpose();
    0.5 * m * v.norm_squared() + 0.5 * w.dot(&(inertia * w))
}

/// Gravitational potential energy `−m·g·x_com` of a dynamic body \[J\].
pub fn potential_energy(body: &RigidBody, gravity: Vector) -> f64 {
    if !body.is_dynamic() {
        return 0.0;
    }
    let m = body.mass() as f64;
    let g: Vector3<f64> = from_vec3(gravity) * body.gravity_scale() as f64;
    -m * g.dot(&from_vec3(body.center_of_mass()))
}

/// Kinetic plus gravitational potential energy of all dynamic bodies \[J\].
pub fn mechanical_energy(bodies: &RigidBodySet, gravity: Vector) -> f64 {
    bodies
        .iter()
        .map(|(_, b)| kinetic_energy(b) + potential_energy(b, gravity))
        .sum()
}
