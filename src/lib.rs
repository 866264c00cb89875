//! # rapier-kjoint
//!
//! Radioss KJOINT2 penalty joints for the rapier physics engine.
//!
//! The behaviour is specified in the repository's `docs/` directory, the crate's reference:
//! `docs/kjoint2.md` (the joint: inputs and their defaults, types, kinematics, force law,
//! stiffness, outputs; the source cites its sections as "docs/kjoint2.md §4.4"),
//! `docs/planar_friction.md` (load-dependent friction on the planar joint),
//! `docs/joint_friction.md` (the same on the revolute, cylindrical and translational joints) and
//! `docs/flex_joint.md` (the riser flex joint). The README shows how to use the crate; its
//! Rust snippets are compiled as doctests.
//!
//! The data flow is one way: decks ([`io`]) → joint definitions ([`law::KjointProperty`])
//! → joint set ([`KjointSet`]) → substep loop → readout ([`JointState`]).
//!
//! - [`prelude`]: `use rapier_kjoint::prelude::*;` brings the set, the builder, the
//!   property, the readout, the events and the readers (beside `rapier::prelude::*`).
//! - [`law`]: the force laws as pure functions (no rapier types), tested against
//!   hand-computed numbers.
//! - [`kinematics`]: frames, displacements, rotation measure and rate Jacobians.
//! - [`dynamics`]: the rapier hook (joint set, implicit penalty update, sensors).
//! - [`io`]: readers for Radioss and riser decks, and the URDF robot loader.
//! - [`scene`]: scene files (TOML/JSON), their builder and run loop.
//! - [`output`]: observers of a run: CSV time histories, the summary, and rerun recordings
//!   (with the `rerun` feature).
//!
//! Where the crate differs from OpenRadioss on purpose (the implicit update, rotation
//! measures from the poses, friction per joint, refused inputs, ...) and why is listed in
//! `docs/radioss_differences.md` of the repository.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]
#![warn(missing_docs)]
// `!(x > 0.0)` is how the crate refuses a NaN together with the values out of range, in
// one test; `partial_cmp` spelled out would hide that, not show it
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// The rapier the crate is built on: `rapier3d` (f32), or `rapier3d_f64` with the `f64`
/// feature. The crate's API takes and returns its types (`PhysicsWorld`, `RigidBodyHandle`,
/// `Vector`, ...): write `use rapier_kjoint::rapier::prelude::*;` to get the matching ones
/// under either precision (as `bevy_rapier3d::rapier`); its parry (`parry3d` or
/// `parry3d_f64`) is `rapier_kjoint::rapier::parry`.
#[cfg(not(feature = "f64"))]
pub use rapier3d as rapier;
#[cfg(feature = "f64")]
pub use rapier3d_f64 as rapier;

pub mod dynamics;
pub mod error;
pub mod figure;
pub mod io;
pub mod kinematics;
mod lanes;
pub mod law;
pub mod output;
pub mod prelude;
pub mod scene;
#[cfg(test)]
mod test_rand;

pub use dynamics::{
    is_contact_filter, EventSource, JointState, Kjoint, KjointBuilder, KjointDescription,
    KjointEvent, KjointEventKind, KjointHandle, KjointSet, OnUnstable, SensorCause,
    SensorCondition, SensorId, Severity, Snapshot, SubstepPhase, SubstepSettings,
    MAX_RAPIER_ITERATIONS, MAX_SUBSTEP, RESOLVE_TOLERANCE,
};
pub use error::{PropertyError, SimError};
pub use law::{
    AutomaticStiffness, BreakCause, BreakCriterion, ConnectorLaw, Curve, Dof, DofLaw, DofStatus,
    FlexJointLaw, FlexProAdd, ForceParts, FrictionStatus, JointEnergy, JointFriction, JointType,
    KjointMotor, KjointProperty, MotorError, PerDof, PlanarFriction, StopContact, ZERO_LIMIT,
};

/// The README's Rust snippets, compiled and run as doctests (`cargo test --doc`), so that
/// the README cannot drift from the API.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
