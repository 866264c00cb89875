//! What a program using the crate needs, in one import, as `rapier3d::prelude`:
//!
//! ```
//! use rapier_kjoint::prelude::*;
//! use rapier_kjoint::rapier::prelude::*; // rapier's own, at the crate's precision
//!
//! let mut world = PhysicsWorld::default();
//! let ground = world.insert_body(RigidBodyBuilder::fixed());
//! let (rod, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.1));
//! let hinge = KjointBuilder::new(
//!     KjointProperty::new(JointType::Revolute)
//!         .with_dof(Dof::Rx, DofLaw::spring(10.0).with_viscosity(0.5)),
//! )
//! .name("hinge")
//! .build();
//! let mut joints = KjointSet::new();
//! let h: KjointHandle = joints.insert(hinge, ground, rod, &world.bodies).unwrap();
//! joints.step(&mut world, 1.0 / 60.0).unwrap();
//! let state: &JointState = joints.get(h).unwrap().state().unwrap();
//! assert_eq!(state.status[Dof::Rx].friction, FrictionStatus::None);
//! for event in joints.drain_events() {
//!     let _: KjointEventKind = event.kind;
//! }
//! ```
//!
//! The names do not collide with rapier's prelude. The deck and robot readers
//! ([`RadiossDeck`], [`RiserDeck`], [`UrdfRobot`], [`MjcfRobot`]) are here too; the law
//! layer's pure functions, the scene files and the output observers stay in their modules
//! ([`crate::law`], [`crate::scene`], [`crate::output`]).

pub use crate::dynamics::{
    EventSource, JointState, Kjoint, KjointBuilder, KjointDescription, KjointEvent,
    KjointEventKind, KjointHandle, KjointSet, OnUnstable, SensorCause, SensorCondition, SensorId,
    Severity, Snapshot, SubstepPhase, SubstepSettings,
};
pub use crate::error::{PropertyError, SimError};
pub use crate::io::mjcf::MjcfRobot;
pub use crate::io::radioss::RadiossDeck;
pub use crate::io::riser::RiserDeck;
pub use crate::io::urdf::{UrdfOptions, UrdfRobot, UrdfRobotHandles};
pub use crate::law::{
    AutomaticStiffness, BreakCause, BreakCriterion, ConnectorLaw, Curve, Dof, DofLaw, DofStatus,
    FlexJointLaw, FlexProAdd, ForceParts, FrictionStatus, JointEnergy, JointFriction, JointType,
    KjointMotor, KjointProperty, PerDof, PlanarFriction, StopContact,
};
