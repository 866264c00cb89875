//! A motor on a free DOF: rapier's force-based joint motor (`JointMotor`,
//! `MotorModel::ForceBased`) as a term of the KJOINT2 law.
//!
//! # The law
//! The motor drives its DOF towards a target position `q*` and rate `q̇*` with the force
//!
//! ```text
//! τ = clamp(τ_ff + k_p·(q* − q) + k_d·(q̇* − q̇), −F_max, F_max)
//! ```
//!
//! on body 2 (and `−τ` on body 1), rapier's `set_motor(axis, target_pos, target_vel,
//! stiffness, damping)` with `set_motor_max_force`, plus a constant force `τ_ff` (a
//! feed-forward term, as a robot's joint controller adds a model's gravity torque to its
//! servo; alone, an effort command: MuJoCo's `<motor>` actuator, ROS's effort interface),
//! which rapier's motors do not have. In the law's internal-force convention
//! (tension positive, [`super::kjoint2`]) its force is `F_m = −τ`. Below the cap its tangents,
//! which the implicit update uses, are `∂F_m/∂q = k_p` and `∂F_m/∂q̇ = k_d`, so a stiff
//! servo is as stable as a stiff spring; at the cap the force is constant and both are 0.
//!
//! `q` is the DOF as the joint measures it ([`crate::JointState::q`]): from the pose at
//! insertion, in the joint's working frame (`θx` of a hinge is its angle about its axis).
//!
//! # Energy
//! A motor is a source, not a store: the work the bodies did against it,
//! `∫F_m·dq` (trapezoidal, as the law's internal energy), is booked as
//! [`super::JointEnergy::motor`]; negative while the motor drives the bodies, positive while
//! they drive it back (a servo braking a load). The energy balance counts `−motor` as work
//! done on the model.

use super::per_dof::PerDof;
use super::property::Dof;
use serde::{Deserialize, Serialize};

/// A motor on one free DOF of a joint (rapier's force-based `JointMotor`, with a constant
/// force added): the drive force `τ = clamp(τ_ff + k_p·(q* − q) + k_d·(q̇* − q̇), ±F_max)`
/// (module docs, [`super::motor`]).
///
/// Units are those of the DOF: m, m/s, N/m, N·s/m, N on a translation; rad, rad/s,
/// N·m/rad, N·m·s/rad, N·m on a rotation.
///
/// A hinge driven to 0.5 rad by a servo of 200 N·m/rad, damped at 20 N·m·s/rad, that
/// gives at most 50 N·m:
///
/// ```
/// use rapier_kjoint::KjointMotor;
/// let m = KjointMotor::position(0.5, 200.0, 20.0).max_force(50.0);
/// assert_eq!(m.drive_force(0.0, 0.0), 50.0);          // 200·0.5 = 100, capped at 50
/// assert!((m.drive_force(0.45, 0.0) - 10.0).abs() < 1e-9); // 200·0.05: below the cap
/// assert!((m.drive_force(0.5, 1.0) + 20.0).abs() < 1e-12); // on target, damped: −20 N·m
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct KjointMotor {
    /// Target position `q*` [m or rad], measured as the DOF is (from the pose at insertion).
    pub target_pos: f64,
    /// Target rate `q̇*` [m/s or rad/s].
    pub target_vel: f64,
    /// Stiffness `k_p` [N/m or N·m/rad] pulling towards `target_pos`; 0: no position term.
    pub stiffness: f64,
    /// Damping `k_d` [N·s/m or N·m·s/rad] pulling towards `target_vel`; 0: no rate term.
    pub damping: f64,
    /// The largest force the motor gives [N or N·m]; `f64::INFINITY` (the default): no cap;
    /// 0: the motor gives nothing. Saved as nothing (`null`) for no cap: JSON has no
    /// infinity, and read as no cap where it is missing (TOML writes nothing for
    /// nothing).
    #[serde(with = "cap", default = "no_cap")]
    pub max_force: f64,
    /// A constant force `τ_ff` added to the drive [N or N·m] (feed-forward, or an effort
    /// command alone: [`Self::force`]); 0: none.
    #[serde(default)]
    pub force: f64,
}

impl Default for KjointMotor {
    /// A motor that does nothing: no stiffness, no damping, no cap.
    fn default() -> Self {
        KjointMotor {
            target_pos: 0.0,
            target_vel: 0.0,
            stiffness: 0.0,
            damping: 0.0,
            max_force: f64::INFINITY,
            force: 0.0,
        }
    }
}

impl KjointMotor {
    /// A position motor (rapier's `set_motor_position(axis, target_pos, stiffness,
    /// damping)`): towards `target_pos` with `stiffness`, damped towards rest with `damping`.
    pub fn position(target_pos: f64, stiffness: f64, damping: f64) -> Self {
        KjointMotor {
            target_pos,
            stiffness,
            damping,
            ..KjointMotor::default()
        }
    }

    /// A velocity motor (rapier's `set_motor_velocity(axis, target_vel, factor)`): towards
    /// the rate `target_vel` with the damping `factor`.
    pub fn velocity(target_vel: f64, factor: f64) -> Self {
        KjointMotor {
            target_vel,
            damping: factor,
            ..KjointMotor::default()
        }
    }

    /// A motor with both targets (rapier's `set_motor(axis, target_pos, target_vel,
    /// stiffness, damping)`).
    pub fn new(target_pos: f64, target_vel: f64, stiffness: f64, damping: f64) -> Self {
        KjointMotor {
            target_pos,
            target_vel,
            stiffness,
            damping,
            ..KjointMotor::default()
        }
    }

    /// An effort command: the constant force (torque on a rotation) `force` on body 2 and
    /// its opposite on body 1, with no stiffness or damping (MuJoCo's `<motor>` actuator).
    /// ```
    /// use rapier_kjoint::KjointMotor;
    /// let m = KjointMotor::force(4.905);                 // 1 kg at 0.5 m held level
    /// assert_eq!(m.drive_force(0.3, -2.0), 4.905);       // whatever the DOF does
    /// let servo = KjointMotor::position(0.0, 10.0, 1.0).with_force(4.905);
    /// assert!((servo.drive_force(0.1, 0.0) - 3.905).abs() < 1e-12); // feed-forward + k_p·e
    /// ```
    pub fn force(force: f64) -> Self {
        KjointMotor {
            force,
            ..KjointMotor::default()
        }
    }

    /// The same motor with the constant force `force` added to its drive (a feed-forward
    /// term: the gravity torque a model predicts, say).
    #[must_use]
    pub fn with_force(mut self, force: f64) -> Self {
        self.force = force;
        self
    }

    /// The same motor capped at `max_force` (rapier's `set_motor_max_force`).
    #[must_use]
    pub fn max_force(mut self, max_force: f64) -> Self {
        self.max_force = max_force;
        self
    }

    /// The drive force `τ` [N or N·m] on body 2 at the DOF's value `q` and rate `q̇`
    /// (module docs): `clamp(τ_ff + k_p·(q* − q) + k_d·(q̇* − q̇), ±F_max)`.
    pub fn drive_force(&self, q: f64, rate: f64) -> f64 {
        -self.internal(q, rate).0
    }

    /// The force in the law's internal convention `F_m = −τ` and its tangents `∂F_m/∂q`,
    /// `∂F_m/∂q̇` (`k_p`, `k_d` below the cap, 0 at it).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn internal(&self, q: f64, rate: f64) -> (f64, f64, f64) {
        let f = self.stiffness * (q - self.target_pos) + self.damping * (rate - self.target_vel)
            - self.force;
        if f.abs() <= self.max_force {
            (f, self.stiffness, self.damping)
        } else {
            (f.signum() * self.max_force, 0.0, 0.0)
        }
    }

    /// Checks the settings: every field finite (`max_force` may be `+∞`), the stiffness,
    /// damping and cap not negative. The error names the field and what was expected.
    pub fn validate(&self) -> Result<(), MotorError> {
        let fields = [
            ("target_pos", self.target_pos, false, false),
            ("target_vel", self.target_vel, false, false),
            ("stiffness", self.stiffness, true, false),
            ("damping", self.damping, true, false),
            ("max_force", self.max_force, true, true),
            ("force", self.force, false, false),
        ];
        for (field, value, positive, infinite) in fields {
            let finite = value.is_finite() || (infinite && value == f64::INFINITY);
            if !finite || (positive && value < 0.0) {
                let expected = match (positive, infinite) {
                    (true, true) => "a number ≥ 0 or +inf (no cap)",
                    (true, false) => "a finite number ≥ 0",
                    _ => "a finite number",
                };
                return Err(MotorError::Field {
                    field,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }
}

/// Why a motor cannot be set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MotorError {
    /// A field is out of its range.
    #[error("motor.{field} = {value}: expected {expected}")]
    Field {
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// The DOF is blocked by the joint type (a motor drives a free DOF only).
    #[error(
        "a motor on {} of a {joint_type} joint: that DOF is blocked (free: {free})",
        .dof.name()
    )]
    BlockedDof {
        /// The DOF asked for.
        dof: Dof,
        /// The joint type's name.
        joint_type: &'static str,
        /// Its free DOFs.
        free: String,
    },
    /// The joint is a riser flex joint, whose bending and torsion laws own its free DOFs.
    #[error("a motor on a flex joint: its bending and torsion laws own its free DOFs")]
    FlexJoint,
}

/// Checks a motor for DOF `dof` of a joint of `joint_type` (a flex joint if `flex`): its
/// settings ([`KjointMotor::validate`]) and that the DOF is free.
pub(crate) fn check_motor(
    joint_type: super::JointType,
    flex: bool,
    dof: Dof,
    motor: &KjointMotor,
) -> Result<(), MotorError> {
    motor.validate()?;
    let free = joint_type.free_dofs();
    if !free[dof.index()] {
        let names: Vec<&str> = Dof::ALL
            .into_iter()
            .filter(|d| free[d.index()])
            .map(Dof::name)
            .collect();
        return Err(MotorError::BlockedDof {
            dof,
            joint_type: joint_type.name(),
            free: if names.is_empty() {
                "none".into()
            } else {
                names.join(", ")
            },
        });
    }
    if flex {
        return Err(MotorError::FlexJoint);
    }
    Ok(())
}

/// The motors of a joint and what their energy book carries from one evaluation to the next
/// (boxed in the joint record: 8 bytes there for a joint without one).
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct MotorDrive {
    /// The motor of each DOF, if any.
    pub motors: PerDof<Option<KjointMotor>>,
    /// Each DOF's motor force `F_m` at the previous evaluation (0 where it had none).
    pub prev_force: [f64; 6],
    /// Per DOF the motor's force `F_m` and its tangents `∂F_m/∂q`, `∂F_m/∂q̇` at the last
    /// substep whose readout was written (0 without one), from which
    /// `Kjoint::closed_energy` predicts the motors' share of that substep.
    pub outstanding: [[f64; 3]; 6],
}

impl MotorDrive {
    /// Whether any DOF has a motor.
    pub fn any(&self) -> bool {
        self.motors.0.iter().any(Option::is_some)
    }
}

/// No cap on a motor's force: [`KjointMotor::max_force`] where a file has none.
fn no_cap() -> f64 {
    f64::INFINITY
}

/// [`KjointMotor::max_force`] saved as a number, or as nothing for no cap (`f64::INFINITY`):
/// JSON has no infinity (`serde_json` wrote `null`, and refused it when read back).
mod cap {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if *x == f64::INFINITY {
            s.serialize_none()
        } else {
            s.serialize_some(x)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

#[cfg(test)]
mod tests {
    use super::KjointMotor;

    /// A motor saved to TOML and JSON reads back the same, with and without a cap: TOML
    /// writes nothing for no cap, and the field was then missing when read back.
    #[test]
    fn a_motor_reads_back_from_toml_and_json_with_and_without_a_cap() {
        for m in [
            KjointMotor::position(0.5, 200.0, 20.0),
            KjointMotor::position(0.5, 200.0, 20.0).max_force(50.0),
        ] {
            let t = toml::to_string(&m).unwrap();
            assert_eq!(toml::from_str::<KjointMotor>(&t).unwrap(), m, "{t}");
            let j = serde_json::to_string(&m).unwrap();
            assert_eq!(serde_json::from_str::<KjointMotor>(&j).unwrap(), m, "{j}");
        }
    }
}
