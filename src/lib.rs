//! # rapier-kjoint
//!
//! Radioss KJOINT2 penalty joints for rapier.
#![warn(missing_docs)]

pub mod error;
/// Readers of input decks (riser flex joint keywords).
pub mod io;
pub mod law;

pub use error::{PropertyError, SimError};
pub use law::{Curve, Dof, DofLaw, JointType, Kjoint2Property};
