//! # rapier-kjoint
//!
//! Radioss KJOINT2 penalty joints for rapier.
#![warn(missing_docs)]

pub mod error;
pub mod kinematics;
pub mod law;

pub use error::{PropertyError, SimError};
pub use law::{
    Curve, Dof, DofLaw, DofStatus, ForceParts, FrictionStatus, JointEnergy, JointType,
    Kjoint2Property, StopContact,
};
pub mod dynamics;

pub use dynamics::{
    JointState, Kjoint2, Kjoint2Builder, KjointHandle, KjointSet, SensorCondition, SubstepSettings,
};
