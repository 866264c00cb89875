//! The readouts of the planar friction and flex joint laws ([`super::ConnectorReport`]).

use crate::law::{FlexPhase, FrictionStatus};
use serde::Serialize;

/// Readout of the planar friction law after an evaluation (joint frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct PlanarFrictionReport {
    /// Normal force `F_N` \[N\].
    pub normal_force: f64,
    /// Normal moment `M_N` \[N·m\].
    pub normal_moment: f64,
    /// In-plane friction force `(f2, f3)` \[N\] (internal-force sign, without the stick damping).
    pub friction_force: [f64; 2],
    /// Friction moment about the normal `m1` \[N·m\] (without the stick damping).
    pub friction_moment: f64,
    /// Stick/slip of the in-plane mechanism.
    pub sliding: FrictionStatus,
    /// Stick/slip of the rotation about the normal.
    pub twist: FrictionStatus,
    /// In-plane slip of this evaluation `Δλ` \[m\].
    pub slip: f64,
    /// Accumulated in-plane slip distance `Σ Δλ` \[m\].
    pub slip_total: f64,
    /// Twist slip of this evaluation `Δλr` \[rad\].
    pub twist_slip: f64,
    /// Accumulated twist slip `Σ Δλr` \[rad\].
    pub twist_slip_total: f64,
    /// Stick stiffnesses used `(Kf [N/m], Kr [N·m/rad])` (automatic ones resolved).
    pub stick_stiffness: [f64; 2],
    /// Elastic energy of the two stick springs \[J\].
    pub stored: f64,
    /// Energy dissipated by friction since the start \[J\].
    pub dissipated: f64,
}

/// Readout of the flex joint law after an evaluation (joint frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct FlexJointReport {
    /// Bending angle `β` \[rad\]: the angle between the two bodies' axes (`√(θy² + θz²)` of
    /// the swing-twist measure).
    pub bending_angle: f64,
    /// Unit bending axis `(e_y, e_z)`.
    pub bending_axis: [f64; 2],
    /// Bending plane: unit direction `(t_y, t_z)` towards which the riser axis tilts.
    pub tilt_direction: [f64; 2],
    /// Bending moment vector `(My, Mz)` \[N·m\].
    pub bending_moment: [f64; 2],
    /// Torsion angle `θx` \[rad\].
    pub torsion_angle: f64,
    /// Torsion moment `Mx`, damping included \[N·m\].
    pub torsion_moment: f64,
    /// Phase of the bending law.
    pub phase: FlexPhase,
    /// Time of the quasi-static → dynamic switch \[s\], once it happened.
    pub switched_at: Option<f64>,
    /// The hysteretic law yields in this evaluation.
    pub yielding: bool,
    /// Plastic angle variation `φp` \[rad\].
    pub plastic_variation: [f64; 2],
    /// Back moment `α` \[N·m\].
    pub back_moment: [f64; 2],
    /// Energy dissipated by the hysteretic bending law since the start \[J\].
    pub dissipated_hysteresis: f64,
    /// Energy dissipated by the torsion damping since the start \[J\].
    pub dissipated_damping: f64,
    /// Elastic energy stored in the flex joint \[J\].
    pub stored: f64,
}
