//! The scene's `[[motors]]`: time schedules of the motor targets of the robots' rapier
//! joints.

use super::checks::{finite, listed};
use super::time::{time_function, TimeFn};
use super::Assembly;
use crate::rapier::dynamics::{ImpulseJointHandle, JointAxis};
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source};

/// A time schedule of a rapier joint's motor target, in SI (scene `[[motors]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Motor {
    /// The joint's (URDF) name.
    pub joint_name: String,
    /// The rapier impulse joint.
    pub joint: ImpulseJointHandle,
    /// Its motorised axis.
    pub axis: JointAxis,
    /// The target \[m or rad\].
    pub target: f64,
    /// Its time function.
    pub function: TimeFn,
}

impl Motor {
    /// The target at time `t` \[s\] [m or rad].
    pub fn at(&self, t: f64) -> f64 {
        self.target * self.function.value(t)
    }
}

impl Assembly {
    /// The scene's motors: each on a rapier joint of a robot that has a motor, one per
    /// joint. URDF robots are SI, so are the targets.
    pub(super) fn motors(&self, scene: &Scene, src: &Source) -> Result<Vec<Motor>, SceneError> {
        let mut out: Vec<Motor> = Vec::new();
        for (i, m) in scene.motors.iter().enumerate() {
            let p = FieldPath::root("motors").index(i);
            let joint = self.rapier_joint(src, &p.key("joint"), &m.joint)?;
            let Some(data) = self.world.impulse_joints.get(joint).map(|j| &j.data) else {
                return Err(src.error(&p.key("joint"), "the rapier joint is not in the world"));
            };
            let Some(axis) = [JointAxis::LinX, JointAxis::AngX]
                .into_iter()
                .find(|a| data.motor(*a).is_some())
            else {
                return Err(src.error(
                    &p.key("joint"),
                    format!(
                        "joint `{}` has no motor: give it one in the robot's options \
                         (options.joints.{}.motor = {{ stiffness, damping, max_force }})",
                        m.joint, m.joint
                    ),
                ));
            };
            if out.iter().any(|o| o.joint == joint) {
                return Err(src.error(
                    &p.key("joint"),
                    format!(
                        "joint `{}` has a motor schedule already: one per joint",
                        m.joint
                    ),
                ));
            }
            let target = finite(src, &p.key("target"), m.target)?;
            // rapier joints come from URDF robots, which need an SI scene: times in seconds
            let function = time_function(src, &p.key("function"), &m.function, 1.0)?;
            out.push(Motor {
                joint_name: m.joint.clone(),
                joint,
                axis,
                target,
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
        let why = if self.joint_names.contains_key(name) {
            format!(
                "joint `{name}` is a KJOINT2 joint: motors drive rapier joints (engine = \
                 \"rapier\" in the robot's options.joints)"
            )
        } else {
            let known: Vec<&str> = self.rapier_joints.keys().map(|s| s.as_str()).collect();
            format!(
                "no rapier joint named `{name}` (rapier joints: {})",
                listed(known)
            )
        };
        Err(src.error(path, why))
    }
}
