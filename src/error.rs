//! Typed errors of the crate.
//!
//! Every error says which input was wrong (the field, and for files the file and line)
//! and what was expected, so that a user can fix the input without reading the code.

use crate::figure::fmt_num;
use thiserror::Error;

use crate::rapier::dynamics::RigidBodyHandle;

/// A body handle as a user finds it again: its raw parts, or `RigidBodyHandle::invalid()`.
fn handle_text(h: RigidBodyHandle) -> String {
    if h.is_invalid() {
        return "RigidBodyHandle::invalid()".into();
    }
    let (index, generation) = h.into_raw_parts();
    format!("RigidBodyHandle index {index}, generation {generation}")
}

/// An invalid value in a joint property, a curve, or an API call.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum PropertyError {
    /// A field holds a value outside its allowed range (or NaN / infinity).
    #[error("invalid {field} = {value}: expected {expected}")]
    InvalidField {
        /// Name of the field, e.g. `critical_damping (Cr)` or `rx.stop_min (SA-)`.
        field: String,
        /// The value that was given, as text.
        value: String,
        /// What the field accepts.
        expected: String,
    },
    /// The joint type number is not one of 1..=9.
    #[error("unknown joint type {0}: expected 1 (spherical) .. 9 (free)")]
    UnknownJointType(i64),
    /// A piecewise-linear curve is malformed.
    #[error("invalid curve: {0}")]
    InvalidCurve(String),
}

impl PropertyError {
    pub(crate) fn field(
        field: impl Into<String>,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> Self {
        PropertyError::InvalidField {
            field: field.into(),
            value: compact_number(value.to_string()),
            expected: expected.into(),
        }
    }
}

/// A number's text, in exponent form when Rust's `Display` would spell out its zeros
/// (`1e308` prints 309 characters otherwise); any other text unchanged.
pub(crate) fn compact_number(text: String) -> String {
    match text.parse::<f64>() {
        Ok(v) if text.len() > 12 => fmt_num(v),
        _ => text,
    }
}

/// Checks that `v` is finite, else an [`PropertyError::InvalidField`] naming `field`.
pub(crate) fn finite(field: &str, v: f64) -> Result<f64, PropertyError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(PropertyError::field(field, v, "a finite number"))
    }
}

/// Errors of the rapier hook: building joints and stepping the world.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SimError {
    /// A joint's property is invalid.
    #[error("joint `{joint}`: {source}")]
    Property {
        /// The joint's name.
        joint: String,
        /// What is wrong with its property.
        #[source]
        source: PropertyError,
    },
    /// A connector law (planar friction, flex joint) does not fit the joint.
    #[error("joint `{joint}`: {source}")]
    Connector {
        /// The joint's name.
        joint: String,
        /// What is wrong.
        #[source]
        source: crate::law::ConnectorError,
    },
    /// A body handle does not exist in the rapier body set (removed, of another world, or
    /// `RigidBodyHandle::invalid()`): "joint `arm`: body 2 (RigidBodyHandle index 5,
    /// generation 0) is not in the rigid-body set".
    #[error(
        "joint `{joint}`: body {which} ({}) is not in the rigid-body set",
        handle_text(*.body)
    )]
    MissingBody {
        /// The joint's name.
        joint: String,
        /// `1` or `2`.
        which: u8,
        /// The handle that was not found.
        body: RigidBodyHandle,
    },
    /// Both bodies of a joint are fixed (or the same body).
    #[error("joint `{joint}`: {reason}")]
    InvalidJoint {
        /// The joint's name.
        joint: String,
        /// Why the joint cannot be built.
        reason: String,
    },
    /// A joint's property names a sensor (`sens_ID`) that was never added to the set.
    #[error(
        "joint `{joint}`: property.sensor = {sensor}: no sensor with that id in the joint set \
         (add it with KjointSet::add_sensor)"
    )]
    UnknownSensor {
        /// The joint's name.
        joint: String,
        /// The sensor id its property names.
        sensor: u32,
    },
    /// An API argument is invalid (NaN, infinite, out of range).
    #[error("invalid argument {field} = {value}: expected {expected}")]
    InvalidArgument {
        /// The argument.
        field: String,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// A motor cannot be set on a joint ([`crate::KjointMotor`]): "joint `elbow`: motor on
    /// rx: motor.stiffness = -1: expected a finite number ≥ 0".
    #[error("joint `{joint}`: motor on {}: {source}", .dof.name())]
    Motor {
        /// The joint's name.
        joint: String,
        /// The DOF the motor was for.
        dof: crate::law::Dof,
        /// What is wrong.
        #[source]
        source: crate::law::MotorError,
    },
    /// The simulation produced non-finite values or diverged.
    #[error("simulation unstable at t = {time} s: {reason}")]
    Unstable {
        /// Simulation time of the failed substep.
        time: f64,
        /// What went wrong (which joint or body).
        reason: String,
    },
}
