//! Contacts left out between the bodies of a joint ([`crate::KjointBuilder::contacts_enabled`]):
//! rapier's narrow phase skips the contacts of two bodies that one of its impulse joints
//! links with `contacts_enabled = false` (`ImpulseJointSet::joints_between`, read in rapier
//! 0.36's `pair_update`), whether that joint is enabled or not. The set puts such a joint in
//! the world for each of its joints whose contacts are off: switched off
//! (`JointEnabled::Disabled`), with no axis locked, it is seen by the narrow phase alone:
//! rapier's solver builds no constraint for it and its islands are not linked through it.

use super::KjointSet;
use crate::dynamics::joint::Kjoint;
use crate::rapier::dynamics::{
    GenericJoint, ImpulseJoint, ImpulseJointHandle, ImpulseJointSet, RigidBodySet,
};

/// The `user_data` of the rapier joints the set puts in the world to leave a joint's
/// bodies' contacts out ([`KjointSet::set_contacts_enabled`]): the bytes of
/// `"kjoint2 contacts"`, to tell them from the user's own joints when iterating the world's
/// `impulse_joints` ([`is_contact_filter`]).
pub const CONTACT_FILTER_USER_DATA: u128 = u128::from_be_bytes(*b"kjoint2 contacts");

/// Whether a rapier joint of the world is one the set put there to leave a joint's bodies'
/// contacts out ([`CONTACT_FILTER_USER_DATA`]), or a robot loader to leave two links apart
/// (an MJCF `<contact><exclude>`), not a joint of the user.
pub fn is_contact_filter(joint: &ImpulseJoint) -> bool {
    joint.data.user_data == CONTACT_FILTER_USER_DATA
        && !joint.data.contacts_enabled
        && !joint.data.is_enabled()
}

/// The set's rapier joints that leave contacts out, as it keeps them in the world.
#[derive(Debug, Clone, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct ContactFilters {
    /// A joint's contacts were switched, or a joint with them off inserted or removed,
    /// since the world was last brought in line.
    dirty: bool,
    /// The rapier joints of removed joints, to take out of the world.
    stale: Vec<ImpulseJointHandle>,
    /// How many rapier joints of the set are in the world (as of the last update).
    pub(crate) count: usize,
}

impl ContactFilters {
    /// A joint was inserted: with its contacts off, the world is to get its rapier joint.
    pub(crate) fn joint_inserted(&mut self, j: &Kjoint) {
        self.dirty |= !j.contacts_enabled;
    }

    /// A joint was removed: its rapier joint, if any, is to leave the world.
    pub(crate) fn joint_removed(&mut self, j: &Kjoint) {
        if let Some(h) = j.contact_filter {
            self.stale.push(h);
            self.dirty = true;
        }
    }
}

/// The rapier joint that leaves the contacts of its two bodies out and does nothing else
/// (also a robot's contact excludes', [`crate::io::robot::RobotDescription::contact_excludes`]).
pub(crate) fn contact_filter_joint() -> GenericJoint {
    let mut g = GenericJoint {
        contacts_enabled: false,
        user_data: CONTACT_FILTER_USER_DATA,
        ..GenericJoint::default()
    };
    g.set_enabled(false);
    g
}

impl KjointSet {
    /// Whether rapier's contacts act between the colliders of joint `h`'s two bodies
    /// (`true` lets them collide, as any two bodies of a rapier world, the default; `false`
    /// leaves them apart, as rapier's `GenericJoint::set_contacts_enabled(false)` does for
    /// its own joints). Returns whether the handle found a joint.
    ///
    /// The set carries it out at its next step (or at [`Self::update_contact_filters`])
    /// with a rapier impulse joint of its own between the two bodies, which rapier's narrow
    /// phase reads: switched off (`JointEnabled::Disabled`) and with no axis locked, it
    /// adds no constraint to rapier's solve and does not link its islands. It is in the
    /// world's `impulse_joints`, its `user_data` [`CONTACT_FILTER_USER_DATA`]
    /// ([`is_contact_filter`] tells it from the user's); removing the KJOINT2 joint (or
    /// switching its contacts on) takes it out. As for rapier's own joints, a contact pair
    /// rapier recycles (two bodies resting against each other, barely moving) keeps its
    /// contacts until it is updated again.
    ///
    /// A hinge between two overlapping boxes whose contacts are left out carries the weight
    /// alone:
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let (arm, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 0.0, 0.0)),
    ///     ColliderBuilder::cuboid(0.6, 0.05, 0.05),
    /// );
    /// world.insert_collider(ColliderBuilder::cuboid(0.1, 0.1, 0.1), Some(ground));
    /// let mut joints = KjointSet::new();
    /// let hinge = KjointBuilder::new(KjointProperty::new(JointType::Revolute))
    ///     .world_axis(Vector::Z)
    ///     .local_anchor2(Vector::new(-0.5, 0.0, 0.0))
    ///     .contacts_enabled(false);
    /// let h = joints.insert(hinge, ground, arm, &world.bodies).unwrap();
    /// joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// assert!(!joints.get(h).unwrap().contacts_enabled());
    /// assert_eq!(world.impulse_joints.len(), 1);
    /// assert!(joints.set_contacts_enabled(h, true));
    /// joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// assert!(world.impulse_joints.is_empty());
    /// ```
    pub fn set_contacts_enabled(
        &mut self,
        h: crate::dynamics::KjointHandle,
        enabled: bool,
    ) -> bool {
        let Some(s) = self.slot(h) else {
            return false;
        };
        let j = &mut self.joints[s];
        if j.contacts_enabled != enabled {
            j.contacts_enabled = enabled;
            self.contact_filters.dirty = true;
            // contacts that come or go move the bodies: an island asleep is taken up by
            // the next analysis only
            if self.asleep.holds(j.body1) || self.asleep.holds(j.body2) {
                self.wake.extend([j.body1, j.body2]);
                self.data.valid = false;
            }
        }
        true
    }

    /// Brings the world's rapier joints that leave contacts out in line with the set's
    /// joints ([`Self::set_contacts_enabled`]): one for each joint whose contacts are off
    /// (put back if it left the world), none for the others or for removed joints. Every
    /// step does it when something changed; call it yourself before rapier's step when
    /// driving rapier with [`Self::apply_substep`]. A joint whose body left `bodies` gets
    /// none (the set removes the joint at its next analysis).
    pub fn update_contact_filters(
        &mut self,
        bodies: &RigidBodySet,
        impulse_joints: &mut ImpulseJointSet,
    ) {
        let filters = &mut self.contact_filters;
        for h in filters.stale.drain(..) {
            impulse_joints.remove(h, true);
        }
        let mut count = 0;
        for j in &mut self.joints {
            let present = j.contact_filter.filter(|h| impulse_joints.contains(*h));
            let bodies_in = bodies.contains(j.body1) && bodies.contains(j.body2);
            j.contact_filter = match (j.contacts_enabled || !bodies_in, present) {
                (true, Some(h)) => {
                    impulse_joints.remove(h, true);
                    None
                }
                (true, None) => None,
                (false, Some(h)) => Some(h),
                (false, None) => {
                    Some(impulse_joints.insert(j.body1, j.body2, contact_filter_joint(), true))
                }
            };
            count += j.contact_filter.is_some() as usize;
        }
        filters.count = count;
        filters.dirty = false;
    }

    /// [`Self::update_contact_filters`] where something changed since the last: a joint's
    /// contacts switched, a joint with them off inserted or removed, or the set's
    /// structure changed (a body removed from the world takes its rapier joints along).
    pub(in crate::dynamics) fn contact_filters_in_line(
        &mut self,
        bodies: &RigidBodySet,
        impulse_joints: &mut ImpulseJointSet,
    ) {
        let f = &self.contact_filters;
        if f.dirty || (f.count > 0 && !self.data.valid) {
            self.update_contact_filters(bodies, impulse_joints);
        }
    }
}
