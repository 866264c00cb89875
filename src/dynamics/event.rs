//! Events of a joint set: sensor activations and connector-law events (the flex joint's
//! quasi-static → dynamic switch), reported once each by [`super::KjointSet::drain_events`].

use super::joint_set::KjointHandle;
use super::sensor::SensorId;
use serde::Serialize;
use std::fmt;

/// What an event comes from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub enum EventSource {
    /// A sensor activated (Radioss `sens_ID`).
    Sensor(SensorId),
    /// The connector law of a joint (e.g. a flex joint switching phase).
    Joint {
        /// The joint.
        handle: KjointHandle,
        /// Its name.
        name: String,
    },
}

impl fmt::Display for EventSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventSource::Sensor(id) => write!(f, "sensor {id}"),
            EventSource::Joint { name, .. } => write!(f, "joint {name}"),
        }
    }
}

/// How much an event matters to the user.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum Severity {
    /// Something that happened as modelled (a sensor fired, a phase switched).
    #[default]
    Info,
    /// Worth knowing about the model (a DOF the substep cannot resolve).
    Notice,
    /// The run may be wrong (anchors separating, a stop overrun): the text names the joint
    /// and a remedy.
    Warning,
}

/// An event of the joint set, reported once.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KjointEvent {
    /// What it comes from.
    pub source: EventSource,
    /// How much it matters.
    pub severity: Severity,
    /// When it happened \[s\].
    pub time: f64,
    /// What happened.
    pub reason: String,
}

impl KjointEvent {
    /// The sensor of a sensor activation, `None` for another event.
    pub fn sensor(&self) -> Option<SensorId> {
        match self.source {
            EventSource::Sensor(id) => Some(id),
            EventSource::Joint { .. } => None,
        }
    }
}

impl fmt::Display for KjointEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let tag = match self.severity {
            Severity::Info => "",
            Severity::Notice => "notice: ",
            Severity::Warning => "warning: ",
        };
        write!(
            f,
            "{tag}{} at t = {:.6} s: {}",
            self.source, self.time, self.reason
        )
    }
}
