//! Load-dependent Coulomb friction of the planar joint (Abaqus PLANAR connector law,
//! docs/planar_friction.md).
//!
//! The law applies to the KJOINT2 planar joint (type 4). Its DOFs match the Abaqus PLANAR
//! connector:
//!
//! | DOF | role | symbol |
//! |---|---|---|
//! | translation along local x (direction 1) | blocked | constraint force `f1` |
//! | rotations about local y, z (2, 3) | blocked | constraint moments `m2`, `m3` |
//! | translations along local y, z (2, 3) | free, with friction | slip `u2`, `u3`; friction force `f = (f2, f3)` |
//! | rotation about local x (1) | free, with friction | twist `ur1`; friction moment `m1` |
//!
//! The friction **limit** depends on the forces the joint itself carries on its blocked
//! DOFs (the penalty forces of the current substep), not on a given friction force as
//! KJOINT2's own friction (docs/kjoint2.md §4.4).
//!
//! # Equations
//!
//! The normal force `F_N` of the in-plane mechanism and the normal moment `M_N` of the
//! twist mechanism are specified in docs/planar_friction.md §2 and §3, and computed by
//! [`PlanarFriction::normal_force`] and [`PlanarFriction::normal_moment`] (`R` = puck
//! radius, `F_int`, `M_int` = internal contact force and moment).
//!
//! Each mechanism is an **elasto-plastic friction spring**, as KJOINT2's friction: a stored
//! friction force (2-vector) `s` with stick stiffness `Kf` \[N/m\], and a stored friction
//! moment `m` with stick stiffness `Kr` \[N·m/rad\]. [`PlanarFriction::evaluate`] applies
//! the return mapping of docs/planar_friction.md §2 (in-plane: trial `s*`, cap `c = μ·F_N`,
//! radial return, slip `Δλ`) and §3 (twist), and books the dissipation of §6: the plastic
//! work `c·Δλ` plus the spring energy `e_c²/(2·Kf)` released when the cap falls from its
//! previous value `c_prev` below the stored force, so that the energy balance closes
//! whenever the normal load falls.
//!
//! In-plane sliding is **isotropic**: the return mapping acts on the force vector (a circle
//! in the (f2, f3) plane), not on the two components separately, so a diagonal pull slides
//! along the pull with `|s| = μ F_N`.
//!
//! # Sign convention
//!
//! Like KJOINT2's `F = K·δ`, the friction force is the **internal force** of the friction
//! spring: it has the sign of the displacement that loaded it (`s = Kf·Δu` while sticking).
//! The joint applies `+s` to body 1 and `−s` to body 2 (docs/kjoint2.md §4.7), which resists the
//! relative motion. The tangent stiffness below is `∂s/∂Δu` with this sign (positive
//! semi-definite).
//!
//! # Tangent while sliding
//!
//! The in-plane tangent is the **consistent (algorithmic) tangent of the radial return**,
//! holding the cap `c` fixed (its dependence on `f1`, `m2`, `m3` belongs to other DOFs and
//! is not linearised):
//!
//! ```text
//! stick:  K_t = Kf·I
//! slide:  K_t = Kf·(c/|s*|)·(I − n·nᵀ)
//! ```
//!
//! i.e. zero along the slip direction `n` and `Kf·c/|s*|` across it (a sliding puck resists
//! a sideways change of direction with the stiffness of a string of tension c and length
//! |s*|/Kf). The twist tangent is `Kr` while sticking and `0` while slipping.

use super::kjoint2::return_work;
use crate::error::{finite, PropertyError};
use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};

/// Settings of the load-dependent planar friction law. In a scene file only `mu` is
/// required; the other fields default to 0 (no radius, no internal force or moment,
/// automatic stick stiffnesses).
///
/// Units: forces in N, moments in N·m, lengths in m, stiffnesses in N/m and N·m/rad
/// (docs/planar_friction.md §1).
///
/// A puck pressed on its plate by 100 N (`f1`), `μ = 0.3`: it sticks while the in-plane
/// friction force is below `μ·F_N = 30 N`, then slides with the friction force at the cap,
/// along the pull.
///
/// ```
/// use nalgebra::Vector2;
/// use rapier_kjoint::law::planar_friction::{PlanarFrictionInput, PlanarFrictionState};
/// use rapier_kjoint::law::PlanarFriction;
/// // μ, R [m], F_int [N], M_int [N·m], Kf [N/m], Kr [N·m/rad]
/// let law = PlanarFriction::new(0.3, 0.0, 0.0, 0.0, 1e4, 100.0).unwrap();
/// let mut state = PlanarFrictionState::default();
/// let mut slip = |du: Vector2<f64>| {
///     let input = PlanarFrictionInput { f1: 100.0, du, ..Default::default() };
///     law.evaluate(&mut state, &input)
/// };
/// let stick = slip(Vector2::new(1e-3, 0.0));            // Kf·Δu = 10 N < 30 N
/// assert!(!stick.sliding && (stick.force.x - 10.0).abs() < 1e-9);
/// assert!((stick.normal_force - 100.0).abs() < 1e-12);
/// let slide = slip(Vector2::new(0.0, 1e-2));            // trial (10, 100) N: beyond the cap
/// assert!(slide.sliding);
/// assert!((slide.force.norm() - 30.0).abs() < 1e-9);    // |f| = μ·F_N, a circle in the plane
/// assert!(slide.dissipated > 0.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanarFriction {
    /// Friction coefficient `μ` (≥ 0, dimensionless).
    pub mu: f64,
    /// Characteristic radius `R` of the sliding puck \[m\] (≥ 0; 0 ignores the bending
    /// contribution to `F_N` and the `(2/3)·R·|f1|` term of `M_N`).
    #[serde(default)]
    pub radius: f64,
    /// Internal (preload) contact force `F_int` \[N\], added to the normal force.
    #[serde(default)]
    pub internal_force: f64,
    /// Internal contact moment `M_int` \[N·m\], added to the normal moment.
    #[serde(default)]
    pub internal_moment: f64,
    /// Stick stiffness `Kf` of the in-plane friction spring \[N/m\] (≥ 0; 0 = automatic:
    /// the joint's automatic penalty `KX` of the substep (docs/kjoint2.md §5), resolved by
    /// `super::connector::Connector::apply`; [`PlanarFriction::evaluate`] needs it > 0).
    #[serde(default)]
    pub stick_stiffness: f64,
    /// Stick stiffness `Kr` of the twist friction spring \[N·m/rad\] (≥ 0; 0 = automatic:
    /// the automatic rotational penalty `KR` of the substep).
    #[serde(default)]
    pub stick_rotational_stiffness: f64,
}

/// Stored state of the two friction springs (one per joint, kept between evaluations).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct PlanarFrictionState {
    /// Stored in-plane friction force `s = (f2, f3)` \[N\].
    pub force: Vector2<f64>,
    /// Stored friction moment about x `m1` \[N·m\].
    pub moment: f64,
    /// Total energy dissipated by in-plane sliding since the start \[J\].
    pub dissipated_sliding: f64,
    /// Total energy dissipated by twist slipping since the start \[J\].
    pub dissipated_twist: f64,
    /// Caps `μ·F_N` \[N\] and `μ·M_N` \[N·m\] of the last evaluation (to tell a falling cap).
    pub caps: [f64; 2],
}

/// Input of one evaluation: blocked-DOF constraint forces of this substep and the
/// increments of the free components since the last evaluation (joint frame).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct PlanarFrictionInput {
    /// Constraint force on the blocked translation along x, `f1` \[N\] (sign irrelevant).
    pub f1: f64,
    /// Constraint moment on the blocked rotation about y, `m2` \[N·m\].
    pub m2: f64,
    /// Constraint moment on the blocked rotation about z, `m3` \[N·m\].
    pub m3: f64,
    /// Increment of the in-plane slip `Δu = (Δu2, Δu3)` \[m\].
    pub du: Vector2<f64>,
    /// Increment of the twist about x `Δur1` \[rad\].
    pub dur1: f64,
}

/// Output of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct PlanarFrictionOutput {
    /// Friction-producing normal force `F_N` \[N\] ([`PlanarFriction::normal_force`]).
    pub normal_force: f64,
    /// Friction-producing normal moment `M_N` \[N·m\] ([`PlanarFriction::normal_moment`]).
    pub normal_moment: f64,
    /// In-plane friction force `(f2, f3)` \[N\] after the return mapping (internal-force sign).
    pub force: Vector2<f64>,
    /// Friction moment about x `m1` \[N·m\] after the return mapping.
    pub moment: f64,
    /// `true` when the in-plane mechanism slides in this evaluation (`|s*| > μ F_N`).
    pub sliding: bool,
    /// `true` when the twist mechanism slips in this evaluation (`|m*| > μ M_N`).
    pub twist_sliding: bool,
    /// In-plane consistent tangent `∂s/∂Δu` \[N/m\]: `Kf·I` sticking,
    /// `Kf·(c/|s*|)·(I − n nᵀ)` sliding.
    pub tangent: Matrix2<f64>,
    /// Twist tangent `∂m1/∂Δur1` \[N·m/rad\]: `Kr` sticking, 0 slipping.
    pub rotational_tangent: f64,
    /// In-plane slip increment `Δλ = (|s*| − μ F_N)/Kf` \[m\] (0 when sticking).
    pub slip: f64,
    /// Twist slip increment `Δλr = (|m*| − μ M_N)/Kr` \[rad\] (0 when sticking).
    pub twist_slip: f64,
    /// Energy dissipated in this evaluation, `μ F_N·Δλ + μ M_N·Δλr` plus the spring energy
    /// released by a cap that fell below the stored force (module docs) \[J\].
    pub dissipated: f64,
    /// Elastic energy stored in the two friction springs after the evaluation,
    /// `|s|²/(2 Kf) + m1²/(2 Kr)` \[J\].
    pub stored: f64,
}

/// Radial return of an elasto-plastic friction spring in any dimension: returns
/// (new force, slip increment, sliding?).
fn radial_return(trial_norm: f64, cap: f64, k: f64) -> (f64, f64, bool) {
    if trial_norm > cap {
        let slip = if k > 0.0 { (trial_norm - cap) / k } else { 0.0 };
        (cap / trial_norm, slip, true)
    } else {
        (1.0, 0.0, false)
    }
}

/// `f²/(2k)`, 0 for a non-positive `k`.
pub(crate) fn spring_energy(f2: f64, k: f64) -> f64 {
    if k > 0.0 {
        f2 / (2.0 * k)
    } else {
        0.0
    }
}

/// One evaluation of a 2-D elasto-plastic friction spring (docs/planar_friction.md §2):
/// the isotropic radial return of the trial force `s* = s + k·Δu` onto the circle of radius
/// `cap`, and the plastic work of the return (§6, [`return_work`]). Shared by the planar
/// friction and the joint friction (docs/joint_friction.md) laws.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct SpringReturn<V, T> {
    /// Force after the return.
    pub force: V,
    /// Consistent tangent `∂s/∂Δu`.
    pub tangent: T,
    /// Slip increment `Δλ = (|s*| − cap)/k` (0 when sticking).
    pub slip: f64,
    /// The spring slips in this evaluation (`|s*| > cap`).
    pub sliding: bool,
    /// Plastic work of the return \[J\].
    pub dissipated: f64,
}

/// 2-D return (see [`SpringReturn`]): `prev` the stored force, `du` the increment, `cap`
/// and `cap_prev` the caps of this and of the last evaluation, `k` the stick stiffness.
/// Tangent `k·I` sticking, `k·(c/|s*|)·(I − n·nᵀ)` sliding.
pub(crate) fn friction_spring_2d(
    prev: Vector2<f64>,
    du: Vector2<f64>,
    cap: f64,
    cap_prev: f64,
    k: f64,
) -> SpringReturn<Vector2<f64>, Matrix2<f64>> {
    let trial = prev + du * k;
    let trial_norm = trial.norm();
    let (scale, slip, sliding) = radial_return(trial_norm, cap, k);
    let (tangent, dissipated) = if sliding {
        let n = trial / trial_norm;
        (
            (Matrix2::identity() - n * n.transpose()) * (k * scale),
            return_work(trial_norm, prev.dot(&n), cap_prev, cap, k),
        )
    } else {
        (Matrix2::identity() * k, 0.0)
    };
    SpringReturn {
        force: trial * scale,
        tangent,
        slip,
        sliding,
        dissipated,
    }
}

/// 1-D return (see [`friction_spring_2d`]): tangent `k` sticking, 0 slipping.
pub(crate) fn friction_spring_1d(
    prev: f64,
    du: f64,
    cap: f64,
    cap_prev: f64,
    k: f64,
) -> SpringReturn<f64, f64> {
    let trial = prev + k * du;
    let (scale, slip, sliding) = radial_return(trial.abs(), cap, k);
    SpringReturn {
        force: trial * scale,
        tangent: if sliding { 0.0 } else { k },
        slip,
        sliding,
        dissipated: return_work(trial.abs(), prev * trial.signum(), cap_prev, cap, k),
    }
}

impl PlanarFriction {
    /// Builds and validates the settings (see [`PlanarFriction::validate`]).
    pub fn new(
        mu: f64,
        radius: f64,
        internal_force: f64,
        internal_moment: f64,
        stick_stiffness: f64,
        stick_rotational_stiffness: f64,
    ) -> Result<Self, PropertyError> {
        let law = PlanarFriction {
            mu,
            radius,
            internal_force,
            internal_moment,
            stick_stiffness,
            stick_rotational_stiffness,
        };
        law.validate()?;
        Ok(law)
    }

    /// Checks the settings: every value finite, `mu ≥ 0`, `radius ≥ 0`, both stick
    /// stiffnesses `≥ 0` (0 = automatic). `internal_force` and `internal_moment` may have any sign.
    pub fn validate(&self) -> Result<(), PropertyError> {
        finite("mu", self.mu)?;
        finite("radius (R)", self.radius)?;
        finite("internal_force (F_int)", self.internal_force)?;
        finite("internal_moment (M_int)", self.internal_moment)?;
        finite("stick_stiffness (Kf)", self.stick_stiffness)?;
        finite(
            "stick_rotational_stiffness (Kr)",
            self.stick_rotational_stiffness,
        )?;
        if self.mu < 0.0 {
            return Err(PropertyError::field("mu", self.mu, "a value >= 0"));
        }
        if self.radius < 0.0 {
            return Err(PropertyError::field(
                "radius (R)",
                self.radius,
                "a value >= 0",
            ));
        }
        if self.stick_stiffness < 0.0 {
            return Err(PropertyError::field(
                "stick_stiffness (Kf)",
                self.stick_stiffness,
                "a stiffness >= 0 [N/m] (0 = automatic)",
            ));
        }
        if self.stick_rotational_stiffness < 0.0 {
            return Err(PropertyError::field(
                "stick_rotational_stiffness (Kr)",
                self.stick_rotational_stiffness,
                "a stiffness >= 0 [N·m/rad] (0 = automatic)",
            ));
        }
        Ok(())
    }

    /// Normal force `F_N` \[N\] from the blocked-DOF constraint force `f1` \[N\] and moments
    /// `m2`, `m3` \[N·m\] (taken at the puck), as docs/planar_friction.md §2 states it.
    ///
    /// ```
    /// use rapier_kjoint::law::PlanarFriction;
    /// // μ = 0.3, R = 0.5 m, F_int = 20 N, M_int = 0, Kf = Kr = 0 (automatic)
    /// let law = PlanarFriction::new(0.3, 0.5, 20.0, 0.0, 0.0, 0.0).unwrap();
    /// // |f1| = 100 N, |(m2, m3)|/R = 50/0.5 = 100 N, plus the 20 N preload
    /// assert!((law.normal_force(-100.0, 30.0, 40.0) - 220.0).abs() < 1e-12);
    /// ```
    pub fn normal_force(&self, f1: f64, m2: f64, m3: f64) -> f64 {
        let bend = if self.radius > 0.0 {
            m2.hypot(m3) / self.radius
        } else {
            0.0
        };
        (f1.abs() + bend + self.internal_force).abs()
    }

    /// Normal moment `M_N` \[N·m\] of the twist mechanism, as docs/planar_friction.md §3
    /// states it.
    pub fn normal_moment(&self, f1: f64, m2: f64, m3: f64) -> f64 {
        (2.0 / 3.0 * self.radius * f1.abs() + m2.hypot(m3) + self.internal_moment).abs()
    }

    /// One evaluation of both friction mechanisms: updates `state` (stored force, moment,
    /// cumulative dissipation) and returns the forces, stick/slip flags, tangents and the
    /// energy dissipated in this evaluation. See the module documentation for the
    /// equations. The stick stiffnesses must be resolved (> 0); with a zero one the spring never
    /// loads (no friction force) instead of dividing by zero.
    pub fn evaluate(
        &self,
        state: &mut PlanarFrictionState,
        input: &PlanarFrictionInput,
    ) -> PlanarFrictionOutput {
        let kf = self.stick_stiffness;
        let kr = self.stick_rotational_stiffness;
        let normal_force = self.normal_force(input.f1, input.m2, input.m3);
        let normal_moment = self.normal_moment(input.f1, input.m2, input.m3);

        // In-plane: one 2-D radial return on the force vector; twist: a 1-D return.
        let cap = self.mu * normal_force;
        let plane = friction_spring_2d(state.force, input.du, cap, state.caps[0], kf);
        let cap_r = self.mu * normal_moment;
        let twist = friction_spring_1d(state.moment, input.dur1, cap_r, state.caps[1], kr);
        let (force, moment) = (plane.force, twist.force);
        let (sliding, twist_sliding) = (plane.sliding, twist.sliding);
        let (tangent, rotational_tangent) = (plane.tangent, twist.tangent);
        let (slip, twist_slip) = (plane.slip, twist.slip);
        let (d_slide, d_twist) = (plane.dissipated, twist.dissipated);

        state.force = force;
        state.moment = moment;
        state.caps = [cap, cap_r];
        state.dissipated_sliding += d_slide;
        state.dissipated_twist += d_twist;

        PlanarFrictionOutput {
            normal_force,
            normal_moment,
            force,
            moment,
            sliding,
            twist_sliding,
            tangent,
            rotational_tangent,
            slip,
            twist_slip,
            dissipated: d_slide + d_twist,
            stored: spring_energy(force.norm_squared(), kf) + spring_energy(moment * moment, kr),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn law(mu: f64, r: f64) -> PlanarFriction {
        PlanarFriction::new(mu, r, 0.0, 0.0, 1.0e5, 1.0e4).unwrap()
    }

    /// Pulls along `dir` in small steps until it slides; returns the force magnitude at
    /// the first sliding evaluation.
    fn sliding_threshold(
        law: &PlanarFriction,
        input: PlanarFrictionInput,
        dir: Vector2<f64>,
    ) -> f64 {
        let mut st = PlanarFrictionState::default();
        let step = dir.normalize() * 1.0e-7;
        let mut last = 0.0;
        for _ in 0..1_000_000 {
            let out = law.evaluate(&mut st, &PlanarFrictionInput { du: step, ..input });
            if out.sliding {
                return out.force.norm();
            }
            last = out.force.norm();
        }
        panic!("never slid (last force {last})");
    }

    #[test]
    fn validation() {
        assert!(PlanarFriction::new(-0.1, 0.0, 0.0, 0.0, 1.0, 1.0).is_err());
        assert!(PlanarFriction::new(0.1, -1.0, 0.0, 0.0, 1.0, 1.0).is_err());
        assert!(PlanarFriction::new(0.1, 0.0, 0.0, 0.0, -1.0, 1.0).is_err());
        assert!(PlanarFriction::new(0.1, 0.0, 0.0, 0.0, 1.0, -1.0).is_err());
        // 0 = automatic (resolved by the connector).
        assert!(PlanarFriction::new(0.1, 0.0, 0.0, 0.0, 0.0, 0.0).is_ok());
        assert!(PlanarFriction::new(f64::NAN, 0.0, 0.0, 0.0, 1.0, 1.0).is_err());
        assert!(PlanarFriction::new(0.1, 0.0, f64::INFINITY, 0.0, 1.0, 1.0).is_err());
        assert!(PlanarFriction::new(0.1, 0.0, -5.0, -5.0, 1.0, 1.0).is_ok());
    }

    #[test]
    fn sliding_threshold_is_mu_times_normal_force() {
        let l = law(0.3, 0.0);
        for f1 in [10.0, 100.0, -250.0, 1000.0] {
            let input = PlanarFrictionInput {
                f1,
                ..Default::default()
            };
            let p = sliding_threshold(&l, input, Vector2::new(1.0, 0.0));
            let expected = 0.3 * f64::abs(f1);
            assert_relative_eq!(p, expected, max_relative = 0.01);
            assert_relative_eq!(l.normal_force(f1, 0.0, 0.0), f64::abs(f1));
        }
    }

    #[test]
    fn bending_moment_over_radius_adds_to_normal_force() {
        let l = PlanarFriction::new(0.2, 0.5, 20.0, 0.0, 1.0e5, 1.0e4).unwrap();
        // f1 = 100, m = (30, 40) -> |m| = 50, /R = 100; F_int = 20 -> F_N = 220.
        let input = PlanarFrictionInput {
            f1: 100.0,
            m2: 30.0,
            m3: 40.0,
            ..Default::default()
        };
        assert_relative_eq!(l.normal_force(100.0, 30.0, 40.0), 220.0, epsilon = 1e-12);
        let p = sliding_threshold(&l, input, Vector2::new(0.0, -1.0));
        assert_relative_eq!(p, 0.2 * 220.0, max_relative = 0.01);
        // R = 0: bending ignored.
        let l0 = PlanarFriction::new(0.2, 0.0, 20.0, 0.0, 1.0e5, 1.0e4).unwrap();
        assert_relative_eq!(l0.normal_force(100.0, 30.0, 40.0), 120.0, epsilon = 1e-12);
        // Negative internal force larger than the load: absolute value.
        let ln = PlanarFriction::new(0.2, 0.0, -150.0, 0.0, 1.0e5, 1.0e4).unwrap();
        assert_relative_eq!(ln.normal_force(100.0, 0.0, 0.0), 50.0, epsilon = 1e-12);
    }

    #[test]
    fn rotational_threshold_is_mu_times_normal_moment() {
        let l = PlanarFriction::new(0.25, 0.3, 0.0, 5.0, 1.0e5, 1.0e4).unwrap();
        // M_N = 2/3*0.3*600 + 50 + 5 = 120 + 55 = 175
        let (f1, m2, m3) = (-600.0, 30.0, 40.0);
        assert_relative_eq!(l.normal_moment(f1, m2, m3), 175.0, epsilon = 1e-9);
        let mut st = PlanarFrictionState::default();
        let mut threshold = None;
        for _ in 0..100_000 {
            let out = l.evaluate(
                &mut st,
                &PlanarFrictionInput {
                    f1,
                    m2,
                    m3,
                    dur1: -1.0e-6,
                    ..Default::default()
                },
            );
            assert!(!out.sliding);
            if out.twist_sliding {
                threshold = Some(out.moment);
                assert_eq!(out.rotational_tangent, 0.0);
                break;
            }
            assert_eq!(out.rotational_tangent, 1.0e4);
        }
        let m = threshold.expect("twist never slipped");
        assert_relative_eq!(m, -0.25 * 175.0, max_relative = 0.01);
    }

    #[test]
    fn diagonal_pull_slides_along_the_pull() {
        let l = law(0.5, 0.0);
        let mut st = PlanarFrictionState::default();
        let dir = Vector2::new(1.0, 1.0) / 2f64.sqrt();
        let input = PlanarFrictionInput {
            f1: 200.0,
            ..Default::default()
        };
        let mut out = None;
        for _ in 0..100 {
            out = Some(l.evaluate(
                &mut st,
                &PlanarFrictionInput {
                    du: dir * 1.0e-4,
                    ..input
                },
            ));
        }
        let out = out.unwrap();
        assert!(out.sliding);
        // |s| = mu F_N = 100, along the pull (internal force sign).
        assert_relative_eq!(out.force.norm(), 100.0, epsilon = 1e-9);
        assert_relative_eq!(out.force.x, 100.0 / 2f64.sqrt(), epsilon = 1e-9);
        assert_relative_eq!(out.force.y, 100.0 / 2f64.sqrt(), epsilon = 1e-9);
        // Two independent 1-D returns would give 100 per component.
        assert!(out.force.x < 99.0);
        // Consistent tangent: zero along the slip direction, positive across it.
        assert_relative_eq!((out.tangent * dir).norm(), 0.0, epsilon = 1e-9);
        let across = Vector2::new(1.0, -1.0) / 2f64.sqrt();
        assert!((out.tangent * across).dot(&across) > 0.0);
    }

    #[test]
    fn load_unload_reverse_by_hand() {
        // Kf = 1000 N/m, mu = 0.5, f1 = 100 -> cap 50 N.
        let l = PlanarFriction::new(0.5, 0.0, 0.0, 0.0, 1000.0, 10.0).unwrap();
        let mut st = PlanarFrictionState::default();
        let step = |st: &mut PlanarFrictionState, dx: f64| {
            l.evaluate(
                st,
                &PlanarFrictionInput {
                    f1: 100.0,
                    du: Vector2::new(dx, 0.0),
                    ..Default::default()
                },
            )
        };
        // Load 0.03 m: s* = 30 < 50, stick.
        let o = step(&mut st, 0.03);
        assert!(!o.sliding);
        assert_relative_eq!(o.force.x, 30.0);
        assert_eq!(o.tangent, Matrix2::identity() * 1000.0);
        assert_eq!(o.dissipated, 0.0);
        // Load 0.04 m more: s* = 70 > 50 -> s = 50, slip = 0.02 m, D = 1 J.
        let o = step(&mut st, 0.04);
        assert!(o.sliding);
        assert_relative_eq!(o.force.x, 50.0);
        assert_relative_eq!(o.slip, 0.02, epsilon = 1e-12);
        assert_relative_eq!(o.dissipated, 1.0, epsilon = 1e-12);
        // Unload 0.03 m: s* = 20, stick.
        let o = step(&mut st, -0.03);
        assert!(!o.sliding);
        assert_relative_eq!(o.force.x, 20.0, epsilon = 1e-12);
        // Reverse 0.1 m: s* = -80 -> s = -50, slip 0.03 m, D = 1.5 J.
        let o = step(&mut st, -0.1);
        assert!(o.sliding);
        assert_relative_eq!(o.force.x, -50.0, epsilon = 1e-12);
        assert_relative_eq!(o.slip, 0.03, epsilon = 1e-12);
        assert_relative_eq!(o.dissipated, 1.5, epsilon = 1e-12);
        assert_relative_eq!(st.dissipated_sliding, 2.5, epsilon = 1e-12);
        assert_relative_eq!(o.stored, 50.0 * 50.0 / 2000.0, epsilon = 1e-12);
        // Normal load drops to f1 = 40 (cap 20) without motion: the stored force is
        // returned onto the smaller cap.
        let o = l.evaluate(
            &mut st,
            &PlanarFrictionInput {
                f1: 40.0,
                ..Default::default()
            },
        );
        assert!(o.sliding);
        assert_relative_eq!(o.force.x, -20.0, epsilon = 1e-12);
        // It releases the spring energy (50² − 20²)/2000 = 1.05 J, all dissipated: the cap
        // times the slip (20·0.03 = 0.6 J) plus (|s*| − cap)²/(2Kf) = 30²/2000 = 0.45 J.
        assert_relative_eq!(o.slip, 0.03, epsilon = 1e-12);
        assert_relative_eq!(o.dissipated, 1.05, epsilon = 1e-12);
        assert_relative_eq!(o.stored, 20.0 * 20.0 / 2000.0, epsilon = 1e-12);
        // A reversal under the fallen cap slips at the cap only: s* = -20 + 1000·0.05 = 30,
        // cap 20, slip 0.01 m, D = 20·0.01 = 0.2 J (the old force pointed the other way).
        let o = l.evaluate(
            &mut st,
            &PlanarFrictionInput {
                f1: 40.0,
                du: Vector2::new(0.05, 0.0),
                ..Default::default()
            },
        );
        assert!(o.sliding);
        assert_relative_eq!(o.dissipated, 0.2, epsilon = 1e-12);
    }

    #[test]
    fn falling_twist_cap_releases_the_stored_moment() {
        // Kr = 10, mu = 0.5, R = 0, M_int = 10 -> cap 5 N·m; load to 4 N·m (stick), then
        // M_int = 2 -> cap 1: the moment returns to 1 at rest, dissipating (16 − 1)/20 = 0.75 J
        // (cap·slip = 1·0.3 = 0.3 J plus 3²/20 = 0.45 J).
        let mut l = PlanarFriction::new(0.5, 0.0, 0.0, 10.0, 1000.0, 10.0).unwrap();
        let mut st = PlanarFrictionState::default();
        let o = l.evaluate(
            &mut st,
            &PlanarFrictionInput {
                dur1: 0.4,
                ..Default::default()
            },
        );
        assert!(!o.twist_sliding);
        assert_relative_eq!(o.moment, 4.0, epsilon = 1e-12);
        l.internal_moment = 2.0;
        let o = l.evaluate(&mut st, &PlanarFrictionInput::default());
        assert!(o.twist_sliding);
        assert_relative_eq!(o.moment, 1.0, epsilon = 1e-12);
        assert_relative_eq!(o.dissipated, 0.75, epsilon = 1e-12);
    }

    #[test]
    fn dissipated_energy_is_cap_times_slip_distance() {
        let l = PlanarFriction::new(0.4, 0.0, 0.0, 0.0, 1.0e6, 1.0e3).unwrap();
        let f1 = 250.0; // cap = 100 N
        let mut st = PlanarFrictionState::default();
        let mut total = 0.0;
        let mut moved = 0.0;
        // A circular path of radius 0.05 m in 2000 steps, then a straight 0.2 m pull.
        let n = 2000;
        let mut prev = Vector2::new(0.0, 0.0);
        for i in 1..=n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let p = Vector2::new(0.05 * (1.0 - a.cos()), 0.05 * a.sin());
            let o = l.evaluate(
                &mut st,
                &PlanarFrictionInput {
                    f1,
                    du: p - prev,
                    ..Default::default()
                },
            );
            total += o.dissipated;
            moved += (p - prev).norm();
            prev = p;
        }
        for _ in 0..1000 {
            let du = Vector2::new(2.0e-4, 0.0);
            let o = l.evaluate(
                &mut st,
                &PlanarFrictionInput {
                    f1,
                    du,
                    ..Default::default()
                },
            );
            total += o.dissipated;
            moved += du.norm();
        }
        // Elastic travel is tiny (cap/Kf = 1e-4 m); the slip distance is the path length
        // minus the elastic travel (at most a few times 1e-4 m).
        assert_relative_eq!(total, 100.0 * moved, max_relative = 0.01);
        assert_relative_eq!(total, st.dissipated_sliding, epsilon = 1e-12);
        // Once sliding along a straight line, every step dissipates exactly cap × |Δu|.
        let du = Vector2::new(0.0, 3.0e-5);
        let mut st2 = PlanarFrictionState {
            force: Vector2::new(0.0, 100.0),
            ..Default::default()
        };
        for _ in 0..10 {
            let o = l.evaluate(
                &mut st2,
                &PlanarFrictionInput {
                    f1,
                    du,
                    ..Default::default()
                },
            );
            assert!(o.sliding);
            assert_relative_eq!(o.dissipated, 100.0 * 3.0e-5, max_relative = 1e-12);
        }
    }
}
