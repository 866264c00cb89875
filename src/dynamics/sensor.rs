//! Sensors: conditions that switch on once and stay on (spec §4.5). A joint whose
//! property names an active sensor locks all its DOFs.
//!
//! A sensor watching a joint's DOF or force cannot fire once that joint leaves the set (it
//! broke, a body of it was removed, or it was removed): the set then reports a warning,
//! [`super::KjointEventKind::SensorJointRemoved`], naming the sensor and the joint, and the
//! sensor stays off unless triggered. The spec is silent; Radioss ties a sensor to the
//! element it reads, and an analyst whose lock never engages would want to know why.

use super::joint_set::KjointHandle;
use crate::law::Dof;

/// Identifier of a sensor (Radioss `sens_ID`).
pub type SensorId = u32;

/// When a sensor activates.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub enum SensorCondition {
    /// At simulation time `t` \[s\] (Radioss `/SENSOR/TIME` with `Tdelay = t`).
    Time(f64),
    /// When DOF `dof` of `joint` passes `value` (m or rad), from either side.
    DofPasses {
        /// The watched joint.
        joint: KjointHandle,
        /// The watched DOF.
        dof: Dof,
        /// The threshold.
        value: f64,
    },
    /// When the magnitude of the force/moment that DOF `dof` of `joint` transmitted to its
    /// bodies over a substep reaches `value` (`|F| ≥ value`, N or N·m;
    /// [`crate::JointState::applied`], not the law's `K·q`, which on a DOF stiffer than the
    /// substep resolves is not what the joint carries). Checked at the start of each substep
    /// on the previous substep's force.
    ForceReaches {
        /// The watched joint.
        joint: KjointHandle,
        /// The watched DOF.
        dof: Dof,
        /// The threshold (> 0).
        value: f64,
    },
    /// Only when [`crate::KjointSet::trigger_sensor`] is called.
    Manual,
}

impl SensorCondition {
    /// The joint whose DOF the condition watches, if any.
    pub fn joint(&self) -> Option<KjointHandle> {
        match self {
            SensorCondition::DofPasses { joint, .. }
            | SensorCondition::ForceReaches { joint, .. } => Some(*joint),
            SensorCondition::Time(_) | SensorCondition::Manual => None,
        }
    }
}

/// A sensor and its state.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Sensor {
    /// The condition.
    pub condition: SensorCondition,
    /// Simulation time at which it activated.
    pub activated_at: Option<f64>,
    /// Side of the threshold at the first check (for [`SensorCondition::DofPasses`]).
    pub(crate) initial_side: Option<bool>,
}
