//! Outputs of a run: time histories, summaries and recordings, fed by the run loop.

use crate::dynamics::{KjointEvent, KjointSet};
use crate::rapier::pipeline::PhysicsWorld;
use std::path::PathBuf;

/// Error of an output writer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A recording could not be written.
    #[error("recording: {0}")]
    Recording(String),
    /// A picture could not be drawn or written.
    #[error("{path}: {message}")]
    Picture {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// Something that watches a run: called after every logged step (frame or substep).
pub trait Observer {
    /// Records the state at simulation time `time` \[s\]; `events` are the sensor events
    /// since the previous call.
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError>;
    /// The work done on the model from outside since the start of the run \[J\]: the
    /// applied loads' and the prescribed motions' so far
    /// ([`crate::scene::RunStats::external_work`] at the end). The run loop gives it before
    /// every [`Self::record`]; ignored by default.
    fn external_work(&mut self, _work: f64) {}
    /// After every substep of a scene's run, with the events the substep raised (which
    /// reach [`Self::record`] too): for what must see every substep whatever the logging
    /// rate (the summary's peaks). Ignored by default.
    fn substep(
        &mut self,
        _world: &PhysicsWorld,
        _joints: &KjointSet,
        _events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        Ok(())
    }
    /// When the run fails, before [`Self::finish`]: the events no [`Self::record`] carried,
    /// those of the failing substep included (a warning it raised, or one of the frame's
    /// earlier substeps, is often the cause of the failure: a body at rapier's spin cap, a
    /// joint separating). No state is recorded with them: the failing substep's poses are
    /// what diverged. Ignored by default.
    fn failed(&mut self, _events: &[KjointEvent]) -> Result<(), OutputError> {
        Ok(())
    }
    /// Flushes and closes at the end of the run.
    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(())
    }
}

pub mod history;
#[cfg(feature = "plot")]
pub mod plot;
#[cfg(feature = "rerun")]
pub mod rerun_log;
pub mod summary;
