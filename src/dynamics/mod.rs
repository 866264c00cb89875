//! The rapier hook: KJOINT2 joints between rapier bodies, stepped at every substep.
//!
//! The data flow of one frame is one way: [`KjointSet::step`] splits the frame into
//! substeps; at each one it measures every joint on the current poses and velocities,
//! evaluates the pure law ([`crate::law`]), solves for the penalty impulses with the
//! linearised implicit update of `solve`, applies them to the bodies, and advances rapier
//! by one substep.

mod convert;
pub mod energy;
mod event;
pub(crate) mod health;
mod isa;
mod joint;
mod joint_set;
mod prefetch;
mod sensor;
mod sleep;
mod snapshot;
pub(crate) mod solve;
mod substep;
mod tiles;

#[cfg(feature = "f64")]
pub(crate) use convert::from_f32;
pub(crate) use convert::{from_quat, from_vec3, to_quat, to_vec3};
pub use event::{
    DofStiffness, EventSource, FlexJointSwitchCause, HealthRemedy, KjointEvent, KjointEventKind,
    SensorCause, Severity, StopRemedy,
};
/// The thresholds of the health checks (warnings and the unstable-run error, README
/// "Health of a run").
pub use health::{
    OnUnstable, CONTACT_CREDIT_SUBSTEPS, CONTACT_CREDIT_TIME, FAR_FROM_ORIGIN, GAP_ERROR,
    GAP_FLOOR, GAP_WARNING, MIN_SIZE, ROTATION_ERROR, ROTATION_JUMP, ROTATION_WARNING,
    STOP_WARNING, UNEXPLAINED, WARNING_GROWTH,
};
pub use joint::{JointState, Kjoint, KjointBuilder, KjointDescription};
pub(crate) use joint_set::contact_filter_joint;
pub use joint_set::{
    is_contact_filter, KjointHandle, KjointSet, SubstepPhase, SubstepSettings,
    CONTACT_FILTER_USER_DATA, MAX_RAPIER_ITERATIONS, MAX_SUBSTEP,
};
pub use sensor::{SensorCondition, SensorId};
pub use snapshot::Snapshot;
pub(crate) use substep::pose_is_finite;
pub use substep::RESOLVE_TOLERANCE;
