//! The KJOINT2 force law as pure functions of the joint kinematics and state
//! (docs/kjoint2.md §4, §5), and the connector laws (docs/planar_friction.md,
//! docs/joint_friction.md, docs/flex_joint.md).
//!
//! Nothing here knows about rapier: the inputs are relative displacements, rotations and
//! their rates in the joint's working frame, the outputs forces, tangent stiffness and
//! damping, and energies. They are tested against hand-computed numbers.

pub mod breaking;
pub mod connector;
pub mod curve;
pub mod flex_joint;
pub mod joint_friction;
pub mod kjoint2;
pub mod motor;
pub mod per_dof;
pub mod planar_friction;
pub mod property;
pub(crate) mod slip_prediction;
pub mod stiffness;
pub(crate) mod stop_prediction;
pub(crate) mod stored_energy;

pub use breaking::{BreakCause, BreakCriterion};
pub(crate) use connector::{Connector, ConnectorInput};
pub use connector::{
    ConnectorError, ConnectorEvent, ConnectorEventKind, ConnectorLaw, ConnectorReport,
    FlexJointConnector, FlexJointReport, FlexJointSwitchCause, JointFrictionReport,
    PlanarFrictionReport,
};
pub use curve::{Curve, CurveData};
pub use flex_joint::{FlexJointLaw, FlexPhase, FlexProAdd};
pub use joint_friction::JointFriction;
pub(crate) use kjoint2::evaluate_into;
pub use kjoint2::{
    evaluate, BlockedStiffness, DofStatus, ForceParts, FrictionStatus, JointEnergy, LawOutput,
    LawParams, LawState, SensorLock, StopContact,
};
pub(crate) use motor::MotorDrive;
pub use motor::{KjointMotor, MotorError};
pub use per_dof::PerDof;
pub use planar_friction::PlanarFriction;
pub(crate) use property::PropertyShape;
pub use property::{AutomaticStiffness, Dof, DofLaw, JointType, KjointProperty, ZERO_LIMIT};
pub(crate) use slip_prediction::predict_slips;
pub(crate) use stop_prediction::{
    predicted_coupled_stops, predicted_stops, StopInput, StopPredictionState,
};
