//! The scene's `[[motors]]`: time schedules of the motor targets of the robots' joints with
//! a motor (rapier joints, and KJOINT2 joints given one in the robot's options), or of the
//! constant force of a KJOINT2 joint's motor.

use super::checks::{finite, listed};
use super::time::{time_function, TimeFn};
use super::Assembly;
use crate::dynamics::KjointHandle;
use crate::law::Dof;
use crate::rapier::dynamics::{ImpulseJointHandle, JointAxis};
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source};

/// The joint a [`Motor`] schedule drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MotorJoint {
    /// A rapier impulse joint (`engine = "rapier"`) and its motorised axis.
    Rapier {
        /// The rapier impulse joint.
        joint: ImpulseJointHandle,
        /// Its motorised axis.
        axis: JointAxis,
    },
    /// A KJOINT2 joint with a motor ([`crate::KjointMotor`]) on its axis DOF.
    Kjoint {
        /// The joint.
        joint: KjointHandle,
        /// Its axis DOF (`rx` or `dx`).
        dof: Dof,
        /// Its position at insertion `q0` [rad or m]: the motor drives `q − q0` to
        /// `target − q0`.
        q0: f64,
    },
}

/// A time schedule of a joint's motor target or force, in SI (scene `[[motors]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Motor {
    /// The joint's (URDF) name.
    pub joint_name: String,
    /// The joint and its axis.
    pub joint: MotorJoint,
    /// What the schedule sets: the target (`false`) or the constant force (`true`, a
    /// KJOINT2 joint's).
    pub force: bool,
    /// The target \[m or rad\], a position `q` as the robot's file counts it, or the force
    /// [N or N·m].
    pub target: f64,
    /// Its time function.
    pub function: TimeFn,
}

impl Motor {
    /// The target [m or rad] or force [N or N·m] at time `t` \[s\].
    pub fn at(&self, t: f64) -> f64 {
        self.target * self.function.value(t)
    }

    /// The unit of its target: `rad` or `m` (of its force: `N·m` or `N`).
    pub fn unit(&self) -> &'static str {
        match self.joint {
            MotorJoint::Kjoint { dof, .. } if self.force => {
                if dof.is_rotation() {
                    "N·m"
                } else {
                    "N"
                }
            }
            MotorJoint::Rapier {
                axis: JointAxis::AngX,
                ..
            } => "rad",
            MotorJoint::Rapier { .. } => "m",
            MotorJoint::Kjoint { dof, .. } => dof.unit(),
        }
    }
}

impl Assembly {
    /// The scene's motors: each on a rapier joint of a robot that has a motor, one per
    /// joint. URDF robots are SI, so are the targets.
    pub(super) fn motors(&self, scene: &Scene, src: &Source) -> Result<Vec<Motor>, SceneError> {
        let mut out: Vec<Motor> = Vec::new();
        for (i, m) in scene.motors.iter().enumerate() {
            let p = FieldPath::root("motors").index(i);
            let no_motor = || {
                src.error(
                    &p.key("joint"),
                    format!(
                        "joint `{}` has no motor: give it one in the robot's options \
                         (options.joints.{}.motor = {{ stiffness, damping, max_force }})",
                        m.joint, m.joint
                    ),
                )
            };
            let (value, force) = match (m.target, m.force) {
                (Some(t), None) => (finite(src, &p.key("target"), t)?, false),
                (None, Some(f)) => (finite(src, &p.key("force"), f)?, true),
                (t, _) => {
                    let key = if t.is_some() { "force" } else { "joint" };
                    return Err(src.error(
                        &p.key(key),
                        "expected one of `target` (a position [m or rad]) and `force` (a \
                         constant force [N or N·m] of a KJOINT2 joint's motor), not both, not \
                         neither",
                    ));
                }
            };
            let joint = if let Some(&h) = self.joint_names.get(&m.joint) {
                let j = self.joints.get(h).expect("a named joint is in the set");
                let axis = crate::io::urdf::axis_dof(j.property().joint_type);
                let Some(dof) = axis.filter(|d| force || j.motor(*d).is_some()) else {
                    if force {
                        return Err(src.error(
                            &p.key("joint"),
                            format!(
                                "joint `{}` is a {} joint: a `force` drives the one axis of \
                                 a revolute, continuous or prismatic joint",
                                m.joint,
                                j.property().joint_type.name()
                            ),
                        ));
                    }
                    return Err(no_motor());
                };
                let q0 = self.joint_q0.get(&m.joint).copied().unwrap_or(0.0);
                MotorJoint::Kjoint { joint: h, dof, q0 }
            } else if force {
                let known: Vec<&str> = self.joint_names.keys().map(|s| s.as_str()).collect();
                return Err(src.error(
                    &p.key("joint"),
                    format!(
                        "no KJOINT2 joint (of the scene or of a robot) named `{}` (a `force` drives a KJOINT2 \
                         joint's motor; rapier's motors have no constant force): {}",
                        m.joint,
                        listed(known)
                    ),
                ));
            } else {
                let joint = self.rapier_joint(src, &p.key("joint"), &m.joint)?;
                let Some(data) = self.world.impulse_joints.get(joint).map(|j| &j.data) else {
                    return Err(src.error(&p.key("joint"), "the rapier joint is not in the world"));
                };
                let Some(axis) = [JointAxis::LinX, JointAxis::AngX]
                    .into_iter()
                    .find(|a| data.motor(*a).is_some())
                else {
                    return Err(no_motor());
                };
                MotorJoint::Rapier { joint, axis }
            };
            if out.iter().any(|o| o.joint_name == m.joint) {
                return Err(src.error(
                    &p.key("joint"),
                    format!(
                        "joint `{}` has a motor schedule already: one per joint",
                        m.joint
                    ),
                ));
            }
            // rapier joints come from URDF robots, which need an SI scene: times in seconds
            let function = time_function(src, &p.key("function"), &m.function, 1.0)?;
            out.push(Motor {
                joint_name: m.joint.clone(),
                joint,
                force,
                target: value,
                function,
            });
        }
        Ok(out)
    }

    /// The rapier joint named `name` (at `path` in the scene).
    fn rapier_joint(
        &self,
        src: &Source,
        path: &FieldPath,
        name: &str,
    ) -> Result<ImpulseJointHandle, SceneError> {
        if let Some(&joint) = self.rapier_joints.get(name) {
            return Ok(joint);
        }
        let known: Vec<&str> = self.rapier_joints.keys().map(|s| s.as_str()).collect();
        let why = format!(
            "no robot joint named `{name}` (rapier joints: {}; or a KJOINT2 joint of a robot \
             with a motor in its options)",
            listed(known)
        );
        Err(src.error(path, why))
    }
}
