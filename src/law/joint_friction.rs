//! Load-dependent Coulomb friction of the revolute, cylindrical and translational joints (a
//! pin in its bushing, a slider in its guide; docs/joint_friction.md).
//!
//! The friction limit is μ times a normal force built from the joint's own blocked
//! reactions (docs/joint_friction.md §2, [`JointFriction::normal_force`]):
//!
//! ```text
//! revolute, cylindrical:  F_N = | F_r + M_b/L + F_pre |
//! translational:          F_N = | F_r + √(M_b² + M_t²)/L + F_pre |
//! ```
//!
//! with `F_r = √(f_y² + f_z²)` the radial reaction, `M_b = √(m_y² + m_z²)` the bending
//! moment, `M_t = m_x` the torsion moment and `L` the bearing length (the `/L` term is 0 when
//! `L = 0`). The bounds (docs/joint_friction.md §3, [`JointFriction::cap`]):
//!
//! ```text
//! revolute:       |m| ≤ μ·(R_pin·F_N + R_thrust·|f_x|)     friction moment about x [N·m]
//! translational:  |f| ≤ μ·F_N                              friction force along x [N]
//! cylindrical:    |(f, m/R_pin)| ≤ μ·F_N                   one resultant surface traction
//! ```
//!
//! # One mechanism in surface coordinates
//!
//! All three are one elasto-plastic friction spring on a 2-vector `s` (the planar friction's
//! radial return, [`super::planar_friction`]), written in generalised coordinates
//! `u = (w_x·δx, w_θ·θx)` with weights `w`, so that the friction force and moment are
//! `f = w_x·s_1`, `m = w_θ·s_2`:
//!
//! | type | `(w_x, w_θ)` | stiffness `k` of `s` | cap |
//! |---|---|---|---|
//! | revolute | `(0, 1)` | `Kr` | `μ·(R_pin·F_N + R_thrust·|f_x|)` |
//! | translational | `(1, 0)` | `Kf` | `μ·F_N` |
//! | cylindrical | `(1, R_pin)` | `Kf` | `μ·F_N` |
//!
//! A zero weight leaves its component at 0 for ever (its increment is 0), so the 2-D return
//! is the 1-D one of the two single-DOF joints. The tangent in `(δx, θx)` is
//! `diag(w)·K_s·diag(w)` with `K_s` the consistent tangent of the radial return (`k·I`
//! sticking, `k·(c/|s*|)·(I − n nᵀ)` sliding): symmetric, the cap frozen over a substep.
//! The cylindrical's turning stick stiffness is therefore `Kf·R_pin²`.
//!
//! Energy (docs/joint_friction.md §5): stored `|s|²/(2k)`, dissipated the plastic work of the
//! return (`cap·Δλ` plus the spring energy a falling cap releases).

use super::planar_friction::{friction_spring_2d, spring_energy};
use super::JointType;
use crate::error::{finite, PropertyError};
use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};

/// Largest magnitude of `mu`, the lengths and the preload (a scene's range: the bound
/// `μ·(R·F_N + R_t·|f_x|)` stays finite).
const MAX_FACTOR: f64 = 1e12;

/// Smallest bearing length `L` \[m\] other than 0 (the bending term `M/L` of `F_N`).
const MIN_LENGTH: f64 = 1e-9;

/// Settings of the joint friction law. In a scene file `mu` is required, and `pin_radius` on
/// a revolute joint; the other fields default to 0 (no bending term, no thrust, no preload,
/// automatic stick stiffnesses). Units: m, N, N/m, N·m/rad (docs/joint_friction.md §1).
///
/// A pin of radius 1 cm, 5 cm long, carrying a radial load of 1000 N and a bending moment of
/// 10 N·m, `μ = 0.2`: `F_N = 1000 + 10/0.05 = 1200 N`, friction moment bound
/// `0.2·0.01·1200 = 2.4 N·m`.
///
/// ```
/// use rapier_kjoint::law::joint_friction::{JointFrictionInput, JointFrictionState};
/// use rapier_kjoint::law::{JointFriction, JointType};
/// let law = JointFriction { mu: 0.2, pin_radius: 0.01, length: 0.05, stick_rotational_stiffness: 100.0,
///                           ..Default::default() };
/// law.validate_for(JointType::Revolute).unwrap();
/// // reactions (f_x, f_y, f_z, m_x, m_y, m_z): radial 1000 N, bending 10 N·m
/// let reactions = [0.0, 600.0, 800.0, 0.0, 0.0, 10.0];
/// assert!((law.normal_force(JointType::Revolute, &reactions) - 1200.0).abs() < 1e-9);
/// let mut st = JointFrictionState::default();
/// let turn = |st: &mut JointFrictionState, dtheta: f64| {
///     law.evaluate(JointType::Revolute, st, &JointFrictionInput { reactions, dx: 0.0, dtheta })
/// };
/// let stick = turn(&mut st, 0.01);             // Kr·Δθ = 1 N·m < 2.4 N·m
/// assert!(!stick.sliding && (stick.moment - 1.0).abs() < 1e-12);
/// let slip = turn(&mut st, 0.02);              // trial 3 N·m: slips at the bound
/// assert!(slip.sliding && (slip.moment - 2.4).abs() < 1e-12);
/// assert!((slip.dissipated - 2.4 * 0.006).abs() < 1e-12); // cap · (3 − 2.4)/Kr
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFriction {
    /// Friction coefficient `μ` (≥ 0, dimensionless; 0 = no friction).
    pub mu: f64,
    /// Pin radius `R_pin` \[m\] (≥ 0): the friction moment's arm on a revolute joint (> 0
    /// there); on a cylindrical joint the radius that couples turning to sliding (0 = no
    /// friction on the rotation). Refused nonzero on a translational joint.
    #[serde(default)]
    pub pin_radius: f64,
    /// Bearing (or guide) length `L` \[m\] (≥ 0): the bending (and, translational, torsion)
    /// moments enter `F_N` divided by it. 0 = moments ignored.
    #[serde(default)]
    pub length: f64,
    /// Thrust friction arm `R_thrust` \[m\] of the axial reaction, revolute only (≥ 0; 0 = no
    /// thrust friction).
    #[serde(default)]
    pub thrust_radius: f64,
    /// Preload `F_pre` \[N\] added to the normal force (any sign; 0 = none).
    #[serde(default)]
    pub preload: f64,
    /// Stick stiffness `Kf` \[N/m\] of the sliding friction spring (cylindrical,
    /// translational; ≥ 0, 0 = automatic: the joint's automatic `KX` of the substep).
    #[serde(default)]
    pub stick_stiffness: f64,
    /// Stick stiffness `Kr` \[N·m/rad\] of the turning friction spring (revolute; ≥ 0, 0 =
    /// automatic: the joint's automatic `KR` of the substep).
    #[serde(default)]
    pub stick_rotational_stiffness: f64,
}

/// Stored state of the friction spring (one per joint, kept between evaluations).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct JointFrictionState {
    /// Stored friction traction `s` in generalised coordinates (module docs) \[N, or N·m on a
    /// revolute joint\].
    pub traction: Vector2<f64>,
    /// Cap of the last evaluation (to tell a falling cap).
    pub cap: f64,
    /// Total energy dissipated by friction since the start \[J\].
    pub dissipated: f64,
}

/// Input of one evaluation (joint frame).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct JointFrictionInput {
    /// KJOINT2 totals of the evaluation `(f_x, f_y, f_z, m_x, m_y, m_z)` \[N, N·m\]: only the
    /// blocked DOFs' values are read.
    pub reactions: [f64; 6],
    /// Increment of `δx` since the last evaluation \[m\] (ignored on a revolute joint).
    pub dx: f64,
    /// Increment of `θx` \[rad\] (ignored on a translational joint).
    pub dtheta: f64,
}

/// Output of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct JointFrictionOutput {
    /// Normal force `F_N` \[N\].
    pub normal_force: f64,
    /// Friction bound (cap) \[N, or N·m on a revolute joint\].
    pub cap: f64,
    /// Friction force along x `f` \[N\] (internal-force sign; 0 on a revolute joint).
    pub force: f64,
    /// Friction moment about x `m` \[N·m\] (0 on a translational joint).
    pub moment: f64,
    /// The friction spring slips in this evaluation.
    pub sliding: bool,
    /// Tangent `∂(f, m)/∂(δx, θx)` \[N/m, N, N·m/rad\].
    pub tangent: Matrix2<f64>,
    /// Slip increment `Δλ` \[m; rad on a revolute joint\] (0 when sticking).
    pub slip: f64,
    /// Energy dissipated in this evaluation \[J\].
    pub dissipated: f64,
    /// Elastic energy of the friction spring after the evaluation, `|s|²/(2k)` \[J\].
    pub stored: f64,
}

impl JointFriction {
    /// The joint types the law applies to.
    pub const JOINT_TYPES: [JointType; 3] = [
        JointType::Revolute,
        JointType::Cylindrical,
        JointType::Translational,
    ];

    /// Checks the settings for `joint`: every value finite, `mu`, `pin_radius`, `length`,
    /// `thrust_radius` and the stick stiffnesses `≥ 0`; `mu`, the lengths and `preload` of
    /// magnitude at most 1e12 (a scene's range), `length` 0 or at least 1e-9 m;
    /// `pin_radius > 0` on a revolute joint; no parameter the type does not use
    /// (docs/joint_friction.md §1). The joint type itself
    /// must be one of [`Self::JOINT_TYPES`] (checked by the connector).
    pub fn validate_for(&self, joint: JointType) -> Result<(), PropertyError> {
        let fields = [
            ("mu", self.mu),
            ("pin_radius", self.pin_radius),
            ("length", self.length),
            ("thrust_radius", self.thrust_radius),
            ("stick_stiffness", self.stick_stiffness),
            (
                "stick_rotational_stiffness",
                self.stick_rotational_stiffness,
            ),
        ];
        finite("preload", self.preload)?;
        for (name, v) in fields {
            finite(name, v)?;
            if v < 0.0 {
                return Err(PropertyError::field(name, v, "a value >= 0"));
            }
        }
        // the bound's factors within the scene's range, and a bearing length that does not
        // divide a moment into an infinite normal force (`length = 1e-308` filled the
        // histories with `inf`)
        for (name, v) in [
            ("mu", self.mu),
            ("pin_radius", self.pin_radius),
            ("length", self.length),
            ("thrust_radius", self.thrust_radius),
            ("preload", self.preload),
        ] {
            if v.abs() > MAX_FACTOR {
                return Err(PropertyError::field(
                    name,
                    v,
                    format!("a value of magnitude <= {MAX_FACTOR:e}"),
                ));
            }
        }
        if self.length > 0.0 && self.length < MIN_LENGTH {
            return Err(PropertyError::field(
                "length",
                self.length,
                format!("0 (no bending term) or a bearing length >= {MIN_LENGTH:e} m"),
            ));
        }
        let revolute = joint == JointType::Revolute;
        let unused = |name: &str, v: f64, what: &str| -> Result<(), PropertyError> {
            if v != 0.0 {
                let expected = format!("0 on a {} joint ({what})", joint.name());
                return Err(PropertyError::field(name, v, expected));
            }
            Ok(())
        };
        if revolute {
            if self.pin_radius == 0.0 {
                return Err(PropertyError::field(
                    "pin_radius",
                    0.0,
                    "a pin radius > 0 [m] on a revolute joint (the friction moment's arm)",
                ));
            }
            unused(
                "stick_stiffness",
                self.stick_stiffness,
                "it turns only: use stick_rotational_stiffness",
            )?;
        } else {
            unused(
                "thrust_radius",
                self.thrust_radius,
                "its axial translation is free",
            )?;
            unused(
                "stick_rotational_stiffness",
                self.stick_rotational_stiffness,
                "the turning stick stiffness is Kf·R_pin²",
            )?;
        }
        if joint == JointType::Translational {
            unused("pin_radius", self.pin_radius, "it does not turn")?;
        }
        Ok(())
    }

    /// Normal force `F_N` \[N\] of docs/joint_friction.md §2 from the KJOINT2 totals
    /// `(f_x, f_y, f_z, m_x, m_y, m_z)` of the evaluation.
    pub fn normal_force(&self, joint: JointType, r: &[f64; 6]) -> f64 {
        let radial = r[1].hypot(r[2]);
        let mut moment = r[4].hypot(r[5]);
        if joint == JointType::Translational {
            moment = moment.hypot(r[3]);
        }
        let bend = if self.length > 0.0 {
            moment / self.length
        } else {
            0.0
        };
        (radial + bend + self.preload).abs()
    }

    /// Friction bound of docs/joint_friction.md §3 for a normal force `normal_force` and the
    /// axial reaction `f_x`: `μ·(R_pin·F_N + R_thrust·|f_x|)` \[N·m\] on a revolute joint,
    /// `μ·F_N` \[N\] otherwise.
    pub fn cap(&self, joint: JointType, normal_force: f64, f_x: f64) -> f64 {
        if joint == JointType::Revolute {
            self.mu * (self.pin_radius * normal_force + self.thrust_radius * f_x.abs())
        } else {
            self.mu * normal_force
        }
    }

    /// Weights `(w_x, w_θ)` of the generalised coordinates and the stiffness of the spring
    /// (module docs). The stick stiffnesses must be resolved.
    fn weights(&self, joint: JointType) -> ([f64; 2], f64) {
        match joint {
            JointType::Revolute => ([0.0, 1.0], self.stick_rotational_stiffness),
            JointType::Cylindrical => ([1.0, self.pin_radius], self.stick_stiffness),
            _ => ([1.0, 0.0], self.stick_stiffness),
        }
    }

    /// Stick stiffnesses `(on δx [N/m], on θx [N·m/rad])` the spring has on the two DOFs
    /// (`Kf·R_pin²` on the cylindrical's rotation, 0 on a DOF it does not act on).
    pub fn dof_stiffness(&self, joint: JointType) -> [f64; 2] {
        let (w, k) = self.weights(joint);
        [w[0] * w[0] * k, w[1] * w[1] * k]
    }

    /// One evaluation: updates `state` and returns the friction force and moment, the
    /// stick/slip flag, the tangent and the energies (module documentation). The stick
    /// stiffnesses must be resolved (> 0); with a zero one the spring never loads.
    pub fn evaluate(
        &self,
        joint: JointType,
        state: &mut JointFrictionState,
        input: &JointFrictionInput,
    ) -> JointFrictionOutput {
        let (w, k) = self.weights(joint);
        let normal_force = self.normal_force(joint, &input.reactions);
        let cap = self.cap(joint, normal_force, input.reactions[0]);
        let du = Vector2::new(w[0] * input.dx, w[1] * input.dtheta);
        let ret = friction_spring_2d(state.traction, du, cap, state.cap, k);
        let wm = Matrix2::from_diagonal(&Vector2::new(w[0], w[1]));
        state.traction = ret.force;
        state.cap = cap;
        state.dissipated += ret.dissipated;
        JointFrictionOutput {
            normal_force,
            cap,
            force: w[0] * ret.force.x,
            moment: w[1] * ret.force.y,
            sliding: ret.sliding,
            tangent: wm * ret.tangent * wm,
            slip: ret.slip,
            dissipated: ret.dissipated,
            stored: spring_energy(ret.force.norm_squared(), k),
        }
    }
}

#[cfg(test)]
mod tests;
