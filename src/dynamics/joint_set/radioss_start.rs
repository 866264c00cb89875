//! The Radioss-compatible start of the time integration
//! ([`super::SubstepSettings::radioss_start`]): the first substep's half kick.

use super::KjointSet;
use crate::rapier::dynamics::{RigidBody, RigidBodyHandle, RigidBodySet};
use std::collections::HashMap;

impl KjointSet {
    /// The Radioss-compatible start ([`super::SubstepSettings::radioss_start`]): on the first
    /// substep of the simulation (while [`Self::time`] is 0), removes half of the substep's
    /// velocity change from every dynamic body, so that the substep is a half kick
    /// `v(h/2) = v(0) + ½·a(0)·h` as the central difference scheme of Radioss starts. A
    /// no-op when the setting is off or after the first substep.
    ///
    /// Call it once per substep **after** [`Self::apply_substep`] and **before** rapier's
    /// `world.step()` (the stepping loops of [`Self::step`] and `scene::run` do; so must a
    /// loop of your own). It removes half of the joint impulses just applied (`P = −h·F_a`
    /// of each joint's `applied` force, through the same Jacobians and inverse masses) and
    /// half of what rapier is about to add (gravity, the bodies' user forces and torques).
    /// The gyroscopic correction, quadratic in ω, keeps its full first step, and contacts
    /// are solved by rapier as usual.
    ///
    /// A substep `h` \[s\] that is not finite and > 0 is refused
    /// ([`crate::SimError::InvalidArgument`]) and nothing changed.
    pub fn radioss_start_kick(
        &mut self,
        bodies: &mut RigidBodySet,
        gravity: crate::rapier::math::Vector,
        h: f64,
    ) -> Result<(), crate::SimError> {
        // (self-contained, fully qualified: the substep pipeline around it is being rewritten)
        use crate::dynamics::convert::{from_vec3, to_vec3};
        use nalgebra::Vector6;
        super::check_substep(h)?;
        super::check_gravity(gravity)?;
        if !self.settings.radioss_start || self.time != 0.0 {
            return Ok(());
        }
        // it reads the substep's transmitted forces (`Kjoint::last_applied`)
        self.fold_stored_results();
        // the bodies end this substep with half its velocity change: its work stays booked
        // with the full one, as before the book was corrected to the bodies' end rates
        for data in std::iter::once(&mut self.data).chain(&mut self.tiles) {
            data.book_pending = false;
            // (the kick is no contact's)
            data.contact_pred = crate::dynamics::substep::ContactPrediction::None;
        }
        let g = from_vec3(gravity);
        // the joint impulses of this substep, P = −h·applied, as velocity changes M⁻¹·Jᵀ·P
        let mut dv: HashMap<RigidBodyHandle, Vector6<f64>> = HashMap::new();
        for j in &self.joints {
            // (every joint was prepared: the substep ran)
            let (Some(p1), Some(p2)) = (
                crate::dynamics::joint::body_pose(bodies, j.body1),
                crate::dynamics::joint::body_pose(bodies, j.body2),
            ) else {
                continue;
            };
            let p = Vector6::from_iterator(j.last_applied.iter().map(|f| -h * f));
            let kin = crate::kinematics::measure(&j.frames, &p1, &p2, &mut j.measure.clone());
            for (hb, jac) in [(j.body1, &kin.jac1), (j.body2, &kin.jac2)] {
                let b = &bodies[hb];
                if b.is_dynamic() {
                    *dv.entry(hb).or_default() += start_inv_mass(b) * (jac.transpose() * p);
                }
            }
        }
        for (hb, b) in bodies.iter_mut().filter(|(_, b)| b.is_dynamic()) {
            // what rapier adds during the step: gravity and the user force and torque
            let m = start_inv_mass(b);
            let im = m.diagonal().fixed_rows::<3>(0).into_owned();
            let free = im.map(|x| if x > 0.0 { 1.0 } else { 0.0 });
            let lin = (g * b.gravity_scale() as f64).component_mul(&free) * h
                + from_vec3(b.user_force()).component_mul(&im) * h;
            let ang = m.fixed_view::<3, 3>(3, 3) * from_vec3(b.user_torque()) * h;
            let mut total = Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z);
            if let Some(d) = dv.get(&hb) {
                total += d;
            }
            let v = b.linvel() - to_vec3(&(0.5 * total.fixed_rows::<3>(0).into_owned()));
            let w = b.angvel() - to_vec3(&(0.5 * total.fixed_rows::<3>(3).into_owned()));
            b.set_linvel(v, true);
            b.set_angvel(w, true);
        }
        Ok(())
    }
}

/// Generalised inverse mass of a dynamic body, `(M⁻¹, I⁻¹_world)` with rapier's locks, the
/// world inverse inertia at the body's current rotation (as the joint solve uses them).
fn start_inv_mass(b: &RigidBody) -> nalgebra::Matrix6<f64> {
    use crate::dynamics::convert::{from_quat, from_vec3};
    let mp = b.mass_properties();
    let im = from_vec3(mp.effective_inv_mass);
    let r = (from_quat(*b.rotation()) * from_quat(mp.local_mprops.principal_inertia_local_frame))
        .to_rotation_matrix();
    let inv_p = nalgebra::Matrix3::from_diagonal(&from_vec3(mp.local_mprops.inv_principal_inertia));
    let mut inv_i = r.matrix() * inv_p * r.matrix().transpose();
    for (i, locked) in b.is_rotation_locked().into_iter().enumerate() {
        if locked {
            inv_i.row_mut(i).fill(0.0);
            inv_i.column_mut(i).fill(0.0);
        }
    }
    let mut m = nalgebra::Matrix6::zeros();
    m[(0, 0)] = im.x;
    m[(1, 1)] = im.y;
    m[(2, 2)] = im.z;
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&inv_i);
    m
}
